//! A box's run file measured against the scene's fine-mesh reference: each file
//! ([`crate::harness::external::box_run`]) is compared with the reference's projection on its
//! level at every step by the box study's own comparison
//! ([`crate::harness::reference::fine_mesh::comparison`]), so its errors are those the study
//! would measure for a run of the harness with the same states.
//!
//! What each norm takes from a file:
//! * the four displacement norms: the displacement at every step (a file with fields at some
//!   steps only gets its error at those steps instead);
//! * `lambda_L2`, the total contact force `Σ λ_i`: the multipliers (or the total) at every step;
//! * the energy norms: `E_h = ½ VᵀM V + ½ UᵀS U` computed by the harness from the file's
//!   displacement and velocity with its own `M` (of the mass the file declares) and `S`, at every
//!   step. An energy the code reports itself is never used for these norms: its distance to the
//!   reference is shown beside them, under its declared definition.
//!
//! A series that declares its scheme and mass is also run by the harness at its coarsest level,
//! from the file's first sample, and compared with the file at every step
//! ([`compare_with_harness`]): round-off differences say both codes solve the same discrete
//! problem.
//!
//! A series on its own mesh (triangles, tetrahedra, or `--own-mesh`) is measured against the
//! reference's projections on the finest study level by a quadrature on its elements
//! ([`super::own_mesh`]).
//!
//! Every file is read and checked before the reference is obtained; a reference that is not in
//! the cache is computed only when its estimated work and memory fit the limits (`--max-*`), as
//! `signorini reference` checks them.

use std::collections::BTreeMap;
use std::path::Path;
use std::time::Instant;

use super::own_mesh::{is_own_mesh, OwnMeshRun};
use super::{ReportedEnergy, RunRecord, VerifiedFile};
use crate::engine::fem::box_mesh::BoxMesh;
use crate::engine::problem::box_mesh;
use crate::engine::problem::Discretisation;
use crate::engine::schemes::Timed;
use crate::harness::external::box_run::{BoxExternalRun, BoxScene, SeriesOptions};
use crate::harness::external::error::ExternalError;
use crate::harness::external::rerun::{compare_with_harness, FileSample, StepDifferences};
use crate::harness::external::snapshot_series::{SnapshotSeries, SERIES_FILES};
use crate::harness::reference::declared::FineMeshDeclared;
use crate::harness::reference::fine_mesh::cache::ReferenceCache;
use crate::harness::reference::fine_mesh::comparison::ComparedSample;
use crate::harness::reference::fine_mesh::{obtain_reference, Comparator, ElasticStudyConfig};
use crate::harness::run::nested_comparison::error_series::Quantity;
use crate::harness::run::norms::{Norm, TimeSeriesNorm};
use crate::harness::run::Timings;
use crate::harness::study::budget::Limits;
use crate::harness::study::error::Error;
use crate::harness::study::LevelRecord;

/// A box scene's fine-mesh reference, obtained, with the scene's files read and checked.
pub struct AgainstFineMesh {
    /// The box, its study and finest level.
    declared: FineMeshDeclared,
    /// The reference and what compares a run with it.
    pub comparator: Comparator,
    /// The files, in the order given.
    runs: Vec<Run>,
    /// The finest study level's mesh (a run on its own mesh is measured on its elements).
    finest_mesh: BoxMesh,
}

/// One file: on the scene's mesh at one of its levels, or on its own mesh.
#[allow(clippy::large_enum_variant)] // one per run file, never moved once read
enum Run {
    /// On the scene's structured mesh.
    Scene(BoxExternalRun),
    /// On its own mesh.
    Own(OwnMeshRun),
}

/// Where a box scene's reference is read from, and the limits one computed for want of a
/// cached one must fit.
pub struct ReferenceSource<'a> {
    /// The cache it is read from (and saved to, when writable).
    pub cache: &'a ReferenceCache,
    /// The resource limits.
    pub limits: &'a Limits,
}

impl AgainstFineMesh {
    /// Reads every file of `files` (`.pvd` collections, their arrays as `options` name them, or
    /// `.json` files of the box form) against the scene `name`, then obtains its reference from
    /// `source` (`note` hears why a cache was not used).
    pub fn obtain(
        name: &str,
        declared: FineMeshDeclared,
        files: &[impl AsRef<Path>],
        options: &SeriesOptions,
        source: &ReferenceSource<'_>,
        note: &mut dyn FnMut(String),
    ) -> Result<Self, ExternalError> {
        let FineMeshDeclared {
            problem, config, ..
        } = &declared;
        let scene = BoxScene {
            name,
            problem,
            levels: &config.levels,
            ratio: config.ratio,
        };
        let runs = files
            .iter()
            .map(|path| read_run(&scene, declared.finest, path.as_ref(), options))
            .collect::<Result<Vec<_>, _>>()?;
        let finest_mesh = box_mesh(problem, declared.finest).map_err(Error::from)?;
        let afford = || -> Result<(), Error> {
            let estimate = config.reference_estimate(problem);
            estimate.check(source.limits).map_err(Error::from)
        };
        let reference = obtain_reference(problem, config, (source.cache, None), note, &afford)?;
        let comparator = Comparator::new(problem, reference, declared.finest)?;
        Ok(Self {
            declared,
            comparator,
            runs,
            finest_mesh,
        })
    }

    /// What the errors are measured against, as verify.json names it.
    pub fn description(&self) -> String {
        let reference = &self.comparator.reference;
        let h = &reference.histories;
        format!(
            "the fine-mesh reference: {} on {} elements along the axis ({} unknowns, {} steps){}",
            ElasticStudyConfig::reference_case().id(),
            self.declared.config.reference_level,
            h.dofs,
            h.steps,
            if reference.from_cache {
                ", read from the cache"
            } else {
                ""
            }
        )
    }

    /// The scene's horizon `T`.
    pub fn horizon(&self) -> f64 {
        self.declared.problem.horizon
    }

    /// The reference's check distance per norm key: what bounds a rate's bias.
    pub fn distance(&self) -> &BTreeMap<String, f64> {
        &self.comparator.reference.histories.check.distance
    }

    /// The `k`-th file compared with the reference at every step of its level: its record, its
    /// errors and what it lacks; the code's own energy beside, when it reports one.
    pub fn measure(&self, k: usize) -> Result<VerifiedFile, ExternalError> {
        let run = match &self.runs[k] {
            Run::Scene(run) => run,
            Run::Own(run) => {
                return run.measure(
                    &self.comparator.reference,
                    (self.declared.finest, &self.finest_mesh),
                    &self.declared.problem.elasticity,
                )
            }
        };
        let comparator = &self.comparator;
        let clock = Instant::now();
        let mesh = &run.mesh;
        let d = mesh.dim();
        let discretisation = run
            .file
            .mass
            .map(|mass| {
                let settings = &self.declared.config.settings;
                self.declared.problem.discretise(run.level, mass, settings)
            })
            .transpose()
            .map_err(Error::from)?;
        let model = discretisation.as_ref().map(|d| &d.model);
        let dofs = |nodal: &[f64]| on_unknowns(mesh, nodal);
        let mut comparison = comparator.comparison(run.level);
        let stride = comparator.finest / run.level;
        let reference_energy = &comparator.reference.histories.energy;
        let mut reported = TimeSeriesNorm::default();
        let mut reported_samples = 0usize;
        let mut without_velocity = 0usize;
        for n in 0..run.samples() {
            let sample = run.sample(n)?;
            let u = sample.displacement.as_deref().map(dofs);
            let v = sample.velocity.as_deref().map(dofs);
            if v.is_none() {
                without_velocity += 1;
            }
            let energy = match (model, &u, &v) {
                (Some(model), Some(u), Some(v)) => Some(model.energy(u, v)),
                _ => None,
            };
            comparison.compare(ComparedSample {
                displacement: u.as_deref(),
                total_force: sample.total_force(),
                energy,
            });
            if let (Some(e), Some(&r)) = (sample.reported_energy, reference_energy.get(n * stride))
            {
                reported.push(run.time[n], e - r);
                reported_samples += 1;
            }
        }
        let series = comparison.series();
        let samples = run.samples();
        let mut lacks = BTreeMap::new();
        for norm in Norm::ALL {
            let quantity = Quantity::of(norm);
            let lacking = series.lacking(quantity);
            if lacking == 0 {
                continue;
            }
            let what = match quantity {
                Quantity::Displacement => format!(
                    "displacement fields at every step ({lacking} of {samples} steps have none: \
                     the error at the steps that have them is listed)"
                ),
                Quantity::Force => format!(
                    "contact multipliers (or total force) at every step ({lacking} of {samples} \
                     steps have none)"
                ),
                Quantity::Energy if run.file.mass.is_none() => {
                    "declared mass matrix (the energy is computed with the file's mass: --mass, \
                     or `mass` in the file)"
                        .to_string()
                }
                Quantity::Energy if without_velocity > 0 => format!(
                    "velocity fields at every step ({without_velocity} of {samples} steps have \
                     none: the energy is computed from the displacement and the velocity)"
                ),
                Quantity::Energy => format!(
                    "displacement fields at every step ({lacking} of {samples} steps have none)"
                ),
            };
            lacks.insert(norm, what);
        }
        let displacement_at_samples = if series.lacking(Quantity::Displacement) > 0 {
            series.displacement_errors().to_vec()
        } else {
            Vec::new()
        };
        let spacing = run.time.windows(2).map(|w| w[1] - w[0]);
        let dt_max = spacing.clone().fold(0.0, f64::max);
        let h = mesh.lengths()[d - 1] / run.level as f64;
        let file = run.file.path.display().to_string();
        let rerun = self.rerun_declared(run, discretisation.as_ref(), &file);
        let notes = match &rerun {
            Some(Err(why)) => vec![format!(
                "{file}: not compared with the harness's run of its declared scheme and mass: \
                 {why}"
            )],
            _ => Vec::new(),
        };
        let reported_energy = run
            .energy_definition
            .filter(|_| reported_samples > 0)
            .map(|definition| ReportedEnergy {
                file: file.clone(),
                definition,
                linf: reported.linf(),
                l2: reported.l2(),
            })
            .filter(ReportedEnergy::is_finite);
        Ok(VerifiedFile {
            label: run.file.label.clone(),
            code: run.file.code.clone(),
            declared: run.file.declared(),
            record: RunRecord {
                file,
                nx: run.level,
                samples,
                dt_min: spacing.fold(f64::INFINITY, f64::min),
                dt_max,
                contact_displacement_error: None,
                displacement_at_samples,
                own_mesh: None,
            },
            level: LevelRecord {
                nx: run.level,
                h,
                dt: dt_max,
                steps: samples - 1,
                dofs: mesh.n_dofs(),
                timings: Timings {
                    observe: clock.elapsed().as_secs_f64(),
                    ..Timings::default()
                },
                multiplier_variation_ratio: comparison.variation_ratio(),
            },
            errors: comparison.errors(),
            lacks,
            notes,
            reported_energy,
            step_differences: rerun.and_then(Result::ok),
        })
    }

    /// The harness's run of the scheme and mass `run` declares (`discretised` at its level,
    /// when it declares a mass) compared with it at every step ([`compare_with_harness`]),
    /// when `run` is the coarsest level of its series and declares a scheme; `Err` says why it
    /// could not be compared.
    fn rerun_declared(
        &self,
        run: &BoxExternalRun,
        discretised: Option<&Discretisation<BoxMesh>>,
        file: &str,
    ) -> Option<Result<StepDifferences, String>> {
        let coarsest = self
            .runs
            .iter()
            .filter_map(|r| match r {
                Run::Scene(r) => Some(r),
                Run::Own(_) => None,
            })
            .filter(|r| r.file.label == run.file.label)
            .all(|r| r.level >= run.level);
        let (scheme, discretised) = run.file.scheme.zip(discretised).filter(|_| coarsest)?;
        let dofs = |nodal: &[f64]| on_unknowns(&run.mesh, nodal);
        let declared = (&discretised.model, scheme, &discretised.conventions);
        let file = (file, run.value_epsilon);
        Some(compare_with_harness(file, declared, &run.time, &mut |n| {
            let s = run.sample(n).map_err(|e| e.to_string())?;
            let displacement = s
                .displacement
                .as_deref()
                .map(dofs)
                .ok_or_else(|| "it has no displacement field at every sample".to_string())?;
            Ok(FileSample {
                displacement,
                velocity: s.velocity.as_deref().map(dofs),
                multipliers: s.multipliers.map(|value| Timed {
                    time: run.time[n],
                    value,
                }),
            })
        }))
    }
}

/// The nodal values `nodal` (d per node) on `mesh`'s unknowns: the clamped nodes' left out.
fn on_unknowns(mesh: &BoxMesh, nodal: &[f64]) -> Vec<f64> {
    let d = mesh.dim();
    let mut u = vec![0.0; mesh.n_dofs()];
    for node in 0..mesh.n_nodes() {
        for c in 0..d {
            if let Some(dof) = mesh.dof_of(node, c) {
                u[dof] = nodal[node * d + c];
            }
        }
    }
    u
}

/// Reads the run file `path` of `scene`: a `.pvd` collection or an `.xdmf` file (their arrays
/// as `options` name them), or the JSON format's box form, checked against the scene's mesh and
/// time grid; a series on its own mesh ([`is_own_mesh`]) against the box and the finest level
/// `finest`'s time grid.
fn read_run(
    scene: &BoxScene<'_>,
    finest: usize,
    path: &Path,
    options: &SeriesOptions,
) -> Result<Run, ExternalError> {
    if let Some(series) = SnapshotSeries::read(path) {
        let series = series?;
        if is_own_mesh(&series.snapshot(0)?, options) {
            return OwnMeshRun::read(scene, finest, path, series, options).map(Run::Own);
        }
        return scene.read_series(path, series, options).map(Run::Scene);
    }
    let extension = path
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase());
    match extension.as_deref() {
        Some("json") => scene.read_json(path).map(Run::Scene),
        other => Err(ExternalError::invalid(
            path,
            "file name",
            None,
            format!("extension {:?}", other.unwrap_or("")),
            SERIES_FILES,
        )),
    }
}
