//! Another code's runs of a box scene verified against the scene's fine-mesh reference: each
//! file ([`crate::harness::external::box_run`]) is compared with the reference's projection on
//! its level at every step by the box study's own comparison ([`ReferenceComparison`]), so its
//! errors are those the study would measure for a run of the harness with the same states; the
//! files are grouped by label into series and fitted by the harness's fit; the note's findings
//! are judged on the series that declare their scheme and mass.
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
//! A reference that is not in the cache is computed only when its estimated work and memory fit
//! the request's limits (`--max-*`), as `signorini reference` checks them.

use std::collections::{BTreeMap, BTreeSet};
use std::fmt::Write as _;
use std::path::PathBuf;
use std::time::Instant;

use serde::{Deserialize, Serialize};

use super::findings::{findings_of_cases, Finding};
use super::report::findings_table;
use crate::harness::external::box_run::{BoxExternalRun, BoxScene, PvdOptions};
use crate::harness::external::report::{reported_energies, sampled_displacement, tables};
use crate::harness::external::verify::{
    into_series, Declared, ReportedEnergy, RunRecord, Series, VerifiedFile,
};
use crate::harness::external::{ExternalError, Verification};
use crate::harness::problem::{BoxProblem, MassVariant, Problem, Scheme, Settings};
use crate::harness::reference::fine_mesh::cache::ReferenceCache;
use crate::harness::reference::fine_mesh::comparison::ComparedSample;
use crate::harness::reference::fine_mesh::{
    obtain_reference, rate_bias_bound, Comparator, ElasticStudyConfig,
};
use crate::harness::run::nested_comparison::error_series::Quantity;
use crate::harness::run::norms::{Norm, TimeSeriesNorm};
use crate::harness::run::Timings;
use crate::harness::study::budget::Limits;
use crate::harness::study::error::Error;
use crate::harness::study::scene::Scene;
use crate::harness::study::{Case, CaseStudy, LevelRecord};

/// The verification of another code's box runs (`verify.json` for a box scene).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct BoxVerification {
    /// The series, as a bar scene's verification has them; `reference` names the fine-mesh
    /// reference.
    #[serde(flatten)]
    pub verification: Verification,
    /// The reference's rate-bias bound per norm key (`None`: no bound can be formed).
    pub rate_bias: BTreeMap<String, Option<f64>>,
    /// The note's findings judged on the series that declare a scheme and a mass (each
    /// `(scheme, mass)` once); empty when none do.
    pub findings: Vec<Finding>,
    /// The codes' own energies beside the harness's, file by file.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub reported_energy: Vec<ReportedEnergy>,
}

/// What `verify` takes for a box scene.
pub struct BoxVerifyRequest<'a> {
    /// The scene.
    pub scene: &'a Scene,
    /// The run files: `.pvd` collections or `.json` files of the box form.
    pub files: &'a [PathBuf],
    /// How a `.pvd`'s arrays are named, and what its runs are.
    pub options: &'a PvdOptions,
    /// Where the reference is read from (and saved to, when writable).
    pub cache: &'a ReferenceCache,
    /// The resource limits a reference computed for want of a cached one must fit.
    pub limits: &'a Limits,
}

/// Verifies the box runs of `request` against the scene's reference (read from the cache when
/// its key matches, computed otherwise; `note` hears why a cache was not used).
pub fn verify_box(
    request: &BoxVerifyRequest<'_>,
    note: &mut dyn FnMut(String),
) -> Result<BoxVerification, ExternalError> {
    let scene = request.scene;
    let Problem::Box(problem) = scene.problem() else {
        unreachable!("verify_box is called for a box scene");
    };
    let config = ElasticStudyConfig::from_scene(scene, None).map_err(Error::from)?;
    let finest = config.validate().map_err(Error::from)?;
    let box_scene = BoxScene {
        name: &scene.name,
        problem: &problem,
        levels: &config.levels,
        ratio: config.ratio,
    };
    let runs = request
        .files
        .iter()
        .map(|path| read_run(&box_scene, path, request.options))
        .collect::<Result<Vec<_>, _>>()?;
    let afford = || -> Result<(), Error> {
        let estimate = config.reference_estimate(&problem);
        estimate.check(request.limits).map_err(Error::from)
    };
    let reference = obtain_reference(&problem, &config, (request.cache, None), note, &afford)?;
    let comparator = Comparator::new(&problem, reference, finest)?;
    let norms: BTreeSet<Norm> = Norm::ALL.into_iter().collect();
    let mut verified = Vec::new();
    let mut reported_energy = Vec::new();
    for run in &runs {
        let (file, energy) = verify_file(run, &problem, &comparator, config.settings)?;
        reported_energy.extend(energy);
        verified.push(file);
    }
    let series = into_series(verified, &norms)?;
    let reference = &comparator.reference;
    let bias_of = |case: &CaseStudy, n: Norm| {
        rate_bias_bound(case, n, reference.histories.check.distance[n.key()])
    };
    let rate_bias_of = |case: &CaseStudy| -> BTreeMap<String, Option<f64>> {
        Norm::ALL
            .iter()
            .map(|&n| (n.key().to_string(), bias_of(case, n)))
            .collect()
    };
    let cases = declared_cases(&series);
    let mut rate_bias = BTreeMap::new();
    for case in &cases {
        for (key, bias) in rate_bias_of(case) {
            let worst: &mut Option<f64> = rate_bias.entry(key).or_insert(Some(0.0));
            *worst = worst.zip(bias).map(|(a, b)| a.max(b));
        }
    }
    let findings = if cases.is_empty() {
        Vec::new()
    } else {
        findings_of_cases(&cases, &bias_of)
    };
    let h = &reference.histories;
    Ok(BoxVerification {
        verification: Verification {
            signorini_version: env!("CARGO_PKG_VERSION").to_string(),
            scene: scene.name.clone(),
            reference: format!(
                "the fine-mesh reference: {} on {} elements along the axis ({} unknowns, {} \
                 steps){}",
                ElasticStudyConfig::reference_case().id(),
                config.reference_level,
                h.dofs,
                h.steps,
                if reference.from_cache {
                    ", read from the cache"
                } else {
                    ""
                }
            ),
            horizon: problem.horizon,
            norms: norms.into_iter().collect(),
            series,
        },
        rate_bias,
        findings,
        reported_energy,
    })
}

/// The cases of the series that declare a scheme and a mass the harness names (the first
/// series of each case), with their levels and rates: what the note's findings are judged on.
pub fn declared_cases(series: &[Series]) -> Vec<CaseStudy> {
    let mut cases: Vec<CaseStudy> = Vec::new();
    for s in series {
        let scheme = s
            .declared
            .scheme
            .as_deref()
            .and_then(|n| n.parse::<Scheme>().ok());
        let mass = s
            .declared
            .mass
            .as_deref()
            .and_then(|n| n.parse::<MassVariant>().ok());
        let Some((scheme, mass)) = scheme.zip(mass) else {
            continue;
        };
        let case = Case { scheme, mass };
        if cases.iter().all(|c| c.case != case) {
            cases.push(CaseStudy {
                case,
                levels: s.levels.clone(),
                rates: s.rates.clone(),
            });
        }
    }
    cases
}

/// Reads the run file `path` of `scene`: a `.pvd` collection (its arrays as `options` name
/// them) or the JSON format's box form, checked against the scene's mesh and time grid.
fn read_run(
    scene: &BoxScene<'_>,
    path: &std::path::Path,
    options: &PvdOptions,
) -> Result<BoxExternalRun, ExternalError> {
    let extension = path
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase());
    match extension.as_deref() {
        Some("pvd") => scene.read_pvd(path, options),
        Some("json") => scene.read_json(path),
        other => Err(ExternalError::invalid(
            path,
            "file name",
            None,
            format!("extension {:?}", other.unwrap_or("")),
            ".pvd (a ParaView collection) or .json (the format's box form) for a box scene",
        )),
    }
}

/// One file compared with the reference at every step of its level: its record, its errors
/// and what it lacks; the code's own energy beside, when it reports one.
fn verify_file(
    run: &BoxExternalRun,
    problem: &BoxProblem,
    comparator: &Comparator,
    settings: Settings,
) -> Result<(VerifiedFile, Option<ReportedEnergy>), ExternalError> {
    let clock = Instant::now();
    let mesh = &run.mesh;
    let d = mesh.dim();
    let model = run
        .mass
        .map(|mass| problem.discretise(run.level, mass, &settings))
        .transpose()
        .map_err(Error::from)?
        .map(|discretisation| discretisation.model);
    let dofs = |nodal: &[f64]| -> Vec<f64> {
        let mut u = vec![0.0; mesh.n_dofs()];
        for node in 0..mesh.n_nodes() {
            for c in 0..d {
                if let Some(dof) = mesh.dof_of(node, c) {
                    u[dof] = nodal[node * d + c];
                }
            }
        }
        u
    };
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
        let energy = match (&model, &u, &v) {
            (Some(model), Some(u), Some(v)) => Some(model.energy(u, v)),
            _ => None,
        };
        comparison.compare(ComparedSample {
            displacement: u.as_deref(),
            total_force: sample.total_force(),
            energy,
        });
        if let (Some(e), Some(&r)) = (sample.reported_energy, reference_energy.get(n * stride)) {
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
                "displacement fields at every step ({lacking} of {samples} steps have none: the \
                 error at the steps that have them is listed)"
            ),
            Quantity::Force => format!(
                "contact multipliers (or total force) at every step ({lacking} of {samples} \
                 steps have none)"
            ),
            Quantity::Energy if run.mass.is_none() => {
                "declared mass matrix (the energy is computed with the file's mass: --mass, or \
                 `mass` in the file)"
                    .to_string()
            }
            Quantity::Energy if without_velocity > 0 => format!(
                "velocity fields at every step ({without_velocity} of {samples} steps have none: \
                 the energy is computed from the displacement and the velocity)"
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
    let file = run.path.display().to_string();
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
    Ok((
        VerifiedFile {
            label: run.label.clone(),
            code: run.code.clone(),
            declared: Declared::of(run.scheme, run.mass, run.contact.as_deref()),
            record: RunRecord {
                file,
                nx: run.level,
                samples,
                dt_min: spacing.fold(f64::INFINITY, f64::min),
                dt_max,
                contact_displacement_error: None,
                displacement_at_samples,
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
        },
        reported_energy,
    ))
}

/// The markdown of a box scene's verification: the series' tables, the errors at the sampled
/// steps of files without fields at every step, the codes' own energies, the note's findings.
pub fn render(v: &BoxVerification) -> String {
    let mut out = String::new();
    let w = &v.verification;
    let _ = writeln!(
        out,
        "# Verification of external runs\n\nScene `{}` against {}, T = {}. Each cell: the \
         least-squares rate over the series' levels (`—` with fewer than two). The errors are \
         the box study's: the displacement in H and V against the reference's projection on \
         the file's level, the total contact force, and the energy the harness computes from the \
         file's fields with its own mass and stiffness matrices.\n",
        w.scene, w.reference, w.horizon
    );
    out.push_str(&tables(w));
    out.push_str(&sampled_displacement(w));
    let energies: Vec<&ReportedEnergy> = v.reported_energy.iter().collect();
    out.push_str(&reported_energies(&energies, "the reference's energy"));
    if !v.findings.is_empty() {
        let _ = writeln!(
            out,
            "\n## The note's findings, on the series that declare a scheme and a mass\n\n{}",
            findings_table(&v.findings)
        );
    }
    out
}
