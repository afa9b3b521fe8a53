//! A box run on the code's own mesh (issue 57): a `.pvd` or `.xdmf` series whose cells are not
//! the scene's structured Q1 elements (any triangle or tetrahedron, or any series with
//! `--own-mesh`), measured as the finite element function its cells define.
//!
//! **Against what.** The reference keeps no fine field: it records, at every step of each study
//! level, its projections `w_H` (in `M`) and `w_V` (in `M + S`) on that level and the squared
//! remainders `r_H = ‖u − P w_H‖²_M`, `r_V = ‖u − P w_V‖²_{M+S}`
//! ([`crate::harness::run::nested_comparison::projection`]). A series on its own mesh is
//! measured against the projections on the **finest** study level, at that level's steps (each
//! sample's time must be one of them, within [`STEP_TIME_TOLERANCE`] `Δt`; the first that is not
//! is refused by name), the first at 0 and the last at `T`. Per sample, with `p_H = ‖u_h − w_H‖_H` and `p_V = ‖u_h − w_V‖_V` by
//! [`pair_errors_each`] on the finest level's elements ([`QUADRATURE`]), the error is
//! ```text
//! e_H = (p_H² + r_H)^½,   e_V = (p_V² + r_V)^½,
//! ```
//! which is `‖u_h − u_ref‖` exactly when `u_h` is a field of the finest level's Q1 space or of a
//! coarser one (Pythagoras: `u − P w` is orthogonal to that space), so on the scene's own mesh it
//! equals the structured path to round-off. For any other `u_h` the cross term
//! `2 (u_h − P w, P w − u)` is not zero, and `‖u_h − u_ref‖` lies in `[|p − √r|, p + √r]`, whose
//! points are within `√2 √r` of `e`. The time norms are the structured path's (largest sample,
//! trapezoidal `L²(0, T)` over the samples).
//!
//! **The bound** stated beside each time norm ([`OwnMeshRecord::bound`]): the same time norm of
//! `√2 √r(t)` (the projection's part: the finest level's own distance to the reference) plus
//! that of `2 |p(t) − p'(t)|`, `p'` by the rule on halved subcells ([`HALVED`]; the
//! quadrature's part, [`super::super::mesh`]'s stated bound): how far each reported error may
//! be from the series' distance to the reference itself. The
//! reference's own distance to the exact solution is the fine-mesh reference's check distance,
//! shown with every box verification.
//!
//! **The contact quantities** ([`FaceComparison`], docs/src/external-runs.md), compared with the
//! reference's at the same steps, where the nodal multipliers of two meshes whose contact nodes
//! differ cannot be:
//! - the resultant `F = Σ_i λ_i` over the points of the contact face: its `L²(0, T)` distance
//!   is `lambda_L2`, as on the scene's mesh, and its total variation over the reference's is
//!   the oscillation indicator the findings read;
//! - the pressure at the face's centre (the reference's contact node nearest it), `p(x) = Σ_i
//!   (λ_i / a_i) φ_i(x)` with `a_i = ∫_{Γ_C} φ_i` ([`ContactFace`]), the reference's by the same
//!   definition on its mesh;
//! - the axial displacement at that point, `u_d(x)`, the reference's at its node.
//!
//!
//! **The energy** of a sample is [`cell_energy`] on the file's cells with the mass it declares
//! (the redistributed one as the cells without a vertex on the contact face), compared with the
//! reference's `E_h` at the same step: `energy_Linf`, `energy_L2`, as on the scene's mesh.

use std::collections::BTreeMap;
use std::path::Path;
use std::time::Instant;

use serde::{Deserialize, Serialize};

use super::{declared_series, own_mesh_bound, RunRecord, Series, VerifiedFile};
use crate::engine::fem::box_mesh::{BoxMesh, Elasticity};
use crate::harness::external::box_run::{
    displacement_array, first_non_finite, point_multipliers, BoxScene, SeriesFile, SeriesOptions,
    NODE_ROUNDINGS, STEP_TIME_TOLERANCE,
};
use crate::harness::external::error::ExternalError;
use crate::harness::external::mesh::{
    cell_energy, check_domain, pair_errors_each, CellKind, ContactFace, ElementMesh, MassCells,
    Quadrature, Topology, ALLOWED_CELLS,
};
use crate::harness::external::nodal_snapshot::NodalSnapshot;
use crate::harness::external::snapshot_series::SnapshotSeries;
use crate::harness::problem::MassVariant;
use crate::harness::reference::fine_mesh::fine_run::FineReference;
use crate::harness::run::nested_comparison::error_series::ErrorSeries;
use crate::harness::run::norms::{Norm, TimeSeriesNorm};
use crate::harness::run::Timings;
use crate::harness::study::LevelRecord;

/// The rule of the errors: 3 Gauss points per axis on 4 subcells per axis of each of the finest
/// level's elements.
pub const QUADRATURE: Quadrature = Quadrature {
    gauss: 3,
    subcells: 4,
};

/// The rule on halved subcells whose distance to [`QUADRATURE`], twice, bounds its error.
pub const HALVED: Quadrature = Quadrature {
    gauss: 3,
    subcells: 2,
};

/// Why the energy norms of such a series without a declared mass are not computed.
pub const NO_MASS: &str = "declared mass matrix (--mass: the energy is computed on the file's \
     cells with that mass)";

/// Why the energy norms of such a series with another declared mass are not computed.
pub const OTHER_MASS: &str = "a mass defined on a foreign mesh (--mass standard or \
     redistributed: the others are defined through the scene's structured nodes)";

/// Why the energy norms of such a series without velocities are not computed.
pub const NO_VELOCITY: &str = "velocity fields at every sample (--velocity NAME: the energy is \
     computed from the displacement and the velocity)";

/// Why `lambda_L2` of such a series without multipliers is not computed.
pub const NO_MULTIPLIER: &str = "contact multipliers (--multiplier NAME: their resultant over \
     the contact face is compared with the reference's)";

/// A series' contact quantities on its own mesh beside the reference's, per sample, and the
/// time norms of their differences (the module's definitions).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FaceComparison {
    /// The named point: the reference's contact node nearest the face's centre.
    pub point: Vec<f64>,
    /// The samples' times.
    pub time: Vec<f64>,
    /// `u_d` at the point, the file's.
    pub displacement: Vec<f64>,
    /// `u_d` at the point, the reference's.
    pub reference_displacement: Vec<f64>,
    /// The resultant `Σ_i λ_i` over the contact face, the file's (without multipliers: none).
    pub force: Option<Vec<f64>>,
    /// The reference's resultant.
    pub reference_force: Vec<f64>,
    /// The pressure at the point, the file's (without multipliers: none).
    pub pressure: Option<Vec<f64>>,
    /// The reference's pressure at the point.
    pub reference_pressure: Vec<f64>,
    /// `<quantity>_Linf`, `<quantity>_L2` (`quantity` one of `displacement`, `force`,
    /// `pressure`) → the time norm of the file's value minus the reference's, with
    /// `<quantity>_scale` the reference's largest magnitude.
    pub errors: BTreeMap<String, f64>,
}

impl FaceComparison {
    /// The time norms of the differences and the reference's scales.
    fn norms(&mut self) {
        let quantities = [
            (
                "displacement",
                Some(&self.displacement),
                &self.reference_displacement,
            ),
            ("force", self.force.as_ref(), &self.reference_force),
            ("pressure", self.pressure.as_ref(), &self.reference_pressure),
        ];
        for (name, file, reference) in quantities {
            let Some(file) = file else { continue };
            let mut norm = TimeSeriesNorm::default();
            for ((t, a), b) in self.time.iter().zip(file).zip(reference) {
                norm.push(*t, a - b);
            }
            let scale = reference.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            self.errors.insert(format!("{name}_Linf"), norm.linf());
            self.errors.insert(format!("{name}_L2"), norm.l2());
            self.errors.insert(format!("{name}_scale"), scale);
        }
    }

    /// `TV(F_h) / TV(F_ref)` over the samples: the oscillation indicator of the scene's mesh
    /// ([`crate::harness::reference::fine_mesh::comparison::ReferenceComparison::variation_ratio`]).
    fn variation_ratio(&self) -> Option<f64> {
        let variation = |v: &[f64]| v.windows(2).map(|w| (w[1] - w[0]).abs()).sum::<f64>();
        let force = self.force.as_ref()?;
        Some(variation(force) / variation(&self.reference_force))
    }

    /// One line for verify.md's notes.
    fn summary(&self, file: &str) -> String {
        let point: Vec<String> = self.point.iter().map(|x| format!("{x}")).collect();
        let parts: Vec<String> = ["displacement", "force", "pressure"]
            .into_iter()
            .filter_map(|q| {
                let linf = self.errors.get(&format!("{q}_Linf"))?;
                let scale = self.errors[&format!("{q}_scale")];
                Some(format!(
                    "{q} L∞ {linf:.3e} (the reference's largest {scale:.3e})"
                ))
            })
            .collect();
        format!(
            "{file}: at the face centre ({}), against the reference's: {}",
            point.join(", "),
            parts.join(", ")
        )
    }
}

/// What verify.json says of a file measured on its own mesh.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct OwnMeshRecord {
    /// Its cells, e.g. `own mesh: 400 triangles`.
    pub mesh: String,
    /// `h`: its longest edge.
    pub longest_edge: f64,
    /// The largest spacing of its sample times.
    pub dt: f64,
    /// What its errors are measured against.
    pub reference: String,
    /// The quadrature.
    pub quadrature: String,
    /// Norm key → the projection's part of the bound: the norm's time norm of `√2 √r`.
    pub projection: BTreeMap<String, f64>,
    /// Norm key → the quadrature's part: the time norm of twice the distance to halved
    /// subcells.
    pub quadrature_error: BTreeMap<String, f64>,
    /// Norm key → how far the reported error may be from the distance to the reference itself:
    /// the sum of the two parts.
    pub bound: BTreeMap<String, f64>,
    /// The contact quantities beside the reference's.
    pub contact: FaceComparison,
}

/// A series' file on its own mesh, its first snapshot read and checked.
pub struct OwnMeshRun {
    /// The file, its code and what it declares.
    pub file: SeriesFile,
    /// The mesh.
    pub mesh: ElementMesh,
    /// Its cells counted by kind, e.g. `400 triangles`.
    pub cells: String,
    /// Its longest edge.
    pub longest_edge: f64,
    /// The samples' times, as the file gives them.
    pub time: Vec<f64>,
    /// Per sample, the finest level's step it is at.
    pub steps: Vec<usize>,
    /// Its contact face.
    pub face: ContactFace,
    /// How far from `x_d = 0` a point is on the contact face.
    face_tolerance: f64,
    series: SnapshotSeries,
    displacement: String,
    velocity: Option<String>,
    multiplier: Option<String>,
    first: NodalSnapshot,
}

/// One sample of a series on its own mesh.
pub struct OwnSample {
    /// `d` values per point.
    pub displacement: Vec<f64>,
    /// `d` values per point, when the series names its velocity.
    pub velocity: Option<Vec<f64>>,
    /// One per point (0 off the contact face), when the series names its multipliers.
    pub multipliers: Option<Vec<f64>>,
}

/// Whether the series whose first snapshot is `first` is measured on its own mesh: `--own-mesh`,
/// or a cell of a simplex kind (the scene's mesh has none).
pub fn is_own_mesh(first: &NodalSnapshot, options: &SeriesOptions) -> bool {
    let simplex = |cells: &crate::harness::external::mesh::Cells| {
        cells.iter().any(|(vtk, points)| {
            CellKind::of_vtk(vtk, points.len()).is_some_and(CellKind::is_simplex)
        })
    };
    options.own_mesh || matches!(&first.topology, Some(Topology::Cells(cells)) if simplex(cells))
}

/// `mesh`'s cells counted by kind: `400 triangles`, `10 quadrilaterals and 4 triangles`.
fn counted(mesh: &ElementMesh) -> String {
    let mut by_kind: BTreeMap<&str, usize> = BTreeMap::new();
    for cell in mesh.cells() {
        *by_kind.entry(cell.kind.plural()).or_default() += 1;
    }
    let parts: Vec<String> = by_kind.iter().map(|(k, n)| format!("{n} {k}")).collect();
    parts.join(" and ")
}

/// The longest edge of `mesh`'s cells.
fn longest_edge(mesh: &ElementMesh) -> f64 {
    let p = mesh.points();
    mesh.cells()
        .iter()
        .flat_map(|cell| {
            cell.kind.edges().iter().map(|&[a, b]| {
                let (x, y) = (p[cell.vertices[a]], p[cell.vertices[b]]);
                (0..3).map(|c| (x[c] - y[c]).powi(2)).sum::<f64>().sqrt()
            })
        })
        .fold(0.0, f64::max)
}

impl OwnMeshRun {
    /// Reads the series `series` of `path` as a run of `scene` on its own mesh, measured against
    /// the projections on level `finest`: its cells (each of a type the harness interpolates),
    /// the box they cover ([`check_domain`]), its sample times (each a step of `finest`), its
    /// displacement array (as `options` names it) and its first sample.
    pub fn read(
        scene: &BoxScene<'_>,
        finest: usize,
        path: &Path,
        series: SnapshotSeries,
        options: &SeriesOptions,
    ) -> Result<Self, ExternalError> {
        let first = series.snapshot(0)?;
        let lengths = &scene.problem.lengths;
        let d = lengths.len();
        let Some(Topology::Cells(cells)) = &first.topology else {
            return Err(ExternalError::invalid(
                &first.path,
                "Cells",
                None,
                "a grid without its cells' connectivity",
                "the cells of the mesh: a field on its own mesh is the finite element function \
                 its cells define",
            ));
        };
        let mesh = ElementMesh::of_cells(d, first.points.clone(), cells).map_err(|why| {
            ExternalError::invalid(&first.path, "Cells", None, why, ALLOWED_CELLS)
        })?;
        let tolerance = NODE_ROUNDINGS * first.point_epsilon;
        check_domain(&mesh, lengths, tolerance).map_err(|why| {
            ExternalError::invalid(
                &first.path,
                "Cells",
                None,
                why,
                format!(
                    "a conforming mesh of the scene's box {lengths:?} (its contact face x{d} = \
                     0)"
                ),
            )
        })?;
        let grid = scene.time_grid(finest);
        let dt = grid.get(1).copied().unwrap_or(scene.problem.horizon);
        let time = series.times();
        let mut steps: Vec<usize> = Vec::with_capacity(time.len());
        for (n, &t) in time.iter().enumerate() {
            let k = (t / dt).round();
            let on_grid = k >= 0.0
                && (k as usize) < grid.len()
                && (t - grid[k as usize]).abs() <= STEP_TIME_TOLERANCE * dt
                && steps.last().is_none_or(|&last| (k as usize) > last);
            if !on_grid {
                return Err(ExternalError::invalid(
                    path,
                    "timestep",
                    Some(format!("sample {n}")),
                    t,
                    format!(
                        "a step t_k = k Δt of the finest study level {finest} (Δt = {dt}, {} \
                         steps to T = {}), within {STEP_TIME_TOLERANCE:e} Δt, after the \
                         previous sample's: a series on its own mesh is measured against the \
                         reference's projection on that level at its steps",
                        grid.len() - 1,
                        scene.problem.horizon
                    ),
                ));
            }
            steps.push(k as usize);
        }
        let last = grid.len() - 1;
        if steps.first() != Some(&0) || steps.last() != Some(&last) {
            return Err(ExternalError::invalid(
                path,
                "timestep",
                None,
                format!("samples from {} to {}", time[0], time[time.len() - 1]),
                format!(
                    "samples from 0 to T = {} (step {last} of level {finest}): the time norms \
                     are taken over (0, T)",
                    scene.problem.horizon
                ),
            ));
        }
        let file = options.file(path)?;
        let face_tolerance = tolerance * lengths.iter().fold(0.0f64, |a, &b| a.max(b));
        let run = Self {
            file,
            cells: counted(&mesh),
            longest_edge: longest_edge(&mesh),
            face: ContactFace::of(&mesh, face_tolerance),
            face_tolerance,
            mesh,
            time,
            steps,
            displacement: displacement_array(&first, options, d)?,
            velocity: options.velocity.clone(),
            multiplier: options.multiplier.clone(),
            series,
            first,
        };
        run.sample(0)?;
        Ok(run)
    }

    /// Sample `n`'s displacement and velocity, `d` per point of the mesh, and its multipliers
    /// (its snapshot read now, its points and cells checked to be the first snapshot's, every
    /// value finite, the multipliers by [`point_multipliers`] on this mesh's contact face).
    pub fn sample(&self, n: usize) -> Result<OwnSample, ExternalError> {
        let snapshot = if n == 0 {
            self.first.clone()
        } else {
            self.series.snapshot(n)?
        };
        if snapshot.points != self.first.points || snapshot.topology != self.first.topology {
            return Err(ExternalError::invalid(
                &snapshot.path,
                "Points",
                None,
                "other points or cells",
                "the points and cells of the series' first snapshot: one mesh for every time",
            ));
        }
        let d = self.mesh.dim();
        let vector = |name: &str, flag: &str| {
            let array = snapshot.array(name).filter(|a| a.components >= d);
            let array = array.ok_or_else(|| {
                ExternalError::invalid(
                    &snapshot.path,
                    "PointData",
                    None,
                    format!("no array {name:?} of at least {d} components"),
                    format!("the point array {flag} names"),
                )
            })?;
            first_non_finite(&snapshot, array, self.time[n])?;
            Ok::<Vec<f64>, ExternalError>(
                (0..snapshot.points.len())
                    .flat_map(|k| array.row(k)[..d].iter().copied())
                    .collect(),
            )
        };
        let on_face = (d, |k: usize| self.face.holds(k));
        let multipliers = self
            .multiplier
            .as_deref()
            .map(|name| point_multipliers(&snapshot, name, self.time[n], on_face))
            .transpose()?;
        Ok(OwnSample {
            displacement: vector(&self.displacement, "--displacement NAME")?,
            velocity: self
                .velocity
                .as_deref()
                .map(|name| vector(name, "--velocity NAME"))
                .transpose()?,
            multipliers,
        })
    }

    /// The file measured against `reference`'s projections on its finest level `finest` (whose
    /// mesh is `finest_mesh`, the box's elasticity `elasticity`): the module's errors and bound.
    pub fn measure(
        &self,
        reference: &FineReference,
        (finest, finest_mesh): (usize, &BoxMesh),
        elasticity: &Elasticity,
    ) -> Result<VerifiedFile, ExternalError> {
        let clock = Instant::now();
        let projections = reference
            .projections_on(finest)
            .expect("the reference is projected on every fitted level");
        let n_dofs = projections.dofs;
        let mut series = ErrorSeries::default();
        let mut contact = self.face_comparison(reference);
        // The projection's and the quadrature's parts, in H and in V.
        let mut parts: [TimeSeriesNorm; 4] = Default::default();
        for (n, &k) in self.steps.iter().enumerate() {
            let t = self.time[n];
            let recorded = projections.samples().min(reference.histories.time.len());
            if k >= recorded {
                return Err(ExternalError::invalid(
                    &self.file.path,
                    "timestep",
                    Some(format!("sample {n}")),
                    t,
                    format!("a time the reference recorded on level {finest} ({recorded} steps)"),
                ));
            }
            let OwnSample {
                displacement: u,
                velocity,
                multipliers,
            } = self.sample(n)?;
            let cells = self.file.mass.and_then(MassCells::of);
            let energy = cells.zip(velocity).map(|(mass, v)| {
                let e = cell_energy(&self.mesh, (&u, &v), elasticity, mass, self.face_tolerance);
                e - reference.histories.energy[k]
            });
            let force = self.compare_contact(&mut contact, reference, (k, t), (&u, multipliers))?;
            let nodal = |all: &[f64]| on_nodes(finest_mesh, &all[k * n_dofs..(k + 1) * n_dofs]);
            let (w_h, w_v) = (
                nodal(&projections.h_projection),
                nodal(&projections.v_projection),
            );
            let distances = |rule: Quadrature| {
                let fields = (finest_mesh, [w_h.as_slice(), w_v.as_slice()]);
                pair_errors_each(&self.mesh, &u, fields, elasticity, rule)
                    .map(|[h, v]| (h.h(), v.v()))
                    .map_err(|why| {
                        ExternalError::invalid(
                            &self.file.path,
                            "Cells",
                            Some(format!("t = {t}")),
                            why,
                            "a conforming mesh of the scene's box",
                        )
                    })
            };
            let (p_h, p_v) = distances(QUADRATURE)?;
            let (q_h, q_v) = distances(HALVED)?;
            let (r_h, r_v) = (projections.h_remainder[k], projections.v_remainder[k]);
            let squared = (p_h * p_h + r_h, p_v * p_v + r_v);
            series.push_partial(t, Some(squared), force, energy);
            let values = [r_h, r_v].map(|r| 2f64.sqrt() * r.max(0.0).sqrt());
            let quadrature = [(p_h - q_h).abs(), (p_v - q_v).abs()].map(|x| 2.0 * x);
            for (part, value) in parts.iter_mut().zip(values.into_iter().chain(quadrature)) {
                part.push(t, value);
            }
        }
        let spacing = self.time.windows(2).map(|w| w[1] - w[0]);
        let dt_max = spacing.clone().fold(0.0, f64::max);
        let d = self.mesh.dim();
        let file = self.file.path.display().to_string();
        let by_norm = |h: &TimeSeriesNorm, v: &TimeSeriesNorm| {
            BTreeMap::from([
                (Norm::DisplacementLinfH.key().to_string(), h.linf()),
                (Norm::DisplacementL2H.key().to_string(), h.l2()),
                (Norm::DisplacementLinfV.key().to_string(), v.linf()),
                (Norm::DisplacementL2V.key().to_string(), v.l2()),
            ])
        };
        let projection = by_norm(&parts[0], &parts[1]);
        let quadrature_error = by_norm(&parts[2], &parts[3]);
        let bound = projection
            .iter()
            .map(|(key, p)| (key.clone(), p + quadrature_error[key]))
            .collect();
        contact.norms();
        let record = OwnMeshRecord {
            mesh: format!("own mesh: {}", self.cells),
            longest_edge: self.longest_edge,
            dt: dt_max,
            reference: format!(
                "the reference's projections on the finest study level {finest} (w_H in M, w_V \
                 in M + S) at its steps, with their remainders"
            ),
            quadrature: format!(
                "{} Gauss points per axis on {}^{d} subcells of each of level {finest}'s \
                 elements; bound: twice the distance to {}^{d} subcells",
                QUADRATURE.gauss, QUADRATURE.subcells, HALVED.subcells
            ),
            projection,
            quadrature_error,
            bound,
            contact,
        };
        let bounds: Vec<String> = record
            .bound
            .iter()
            .map(|(key, b)| {
                let (p, q) = (record.projection[key], record.quadrature_error[key]);
                format!("{key} {b:.2e} (projection {p:.2e}, quadrature {q:.2e})")
            })
            .collect();
        let note = format!(
            "{file}: {}, h (longest edge) {:.4e}, Δt {dt_max:.4e}: measured against {}, by {}; \
             each error is within {} of the distance to the reference itself",
            record.mesh,
            self.longest_edge,
            record.reference,
            record.quadrature,
            bounds.join(", ")
        );
        let mut lacks: BTreeMap<Norm, String> = BTreeMap::new();
        let energy_lacks = match (self.file.mass, &self.velocity) {
            (None, _) => Some(NO_MASS),
            (Some(mass), _) if MassCells::of(mass).is_none() => Some(OTHER_MASS),
            (_, None) => Some(NO_VELOCITY),
            _ => None,
        };
        for norm in [Norm::EnergyLinf, Norm::EnergyL2] {
            if let Some(why) = energy_lacks {
                lacks.insert(norm, why.to_string());
            }
        }
        if record.contact.force.is_none() {
            lacks.insert(Norm::MultiplierL2, NO_MULTIPLIER.to_string());
        }
        let contact_note = record.contact.summary(&file);
        let variation_ratio = record.contact.variation_ratio();
        let cells = self.mesh.cells().len();
        let samples = self.time.len();
        Ok(VerifiedFile {
            label: self.file.label.clone(),
            code: self.file.code.clone(),
            declared: self.file.declared(),
            record: RunRecord {
                file,
                nx: cells,
                samples,
                dt_min: spacing.fold(f64::INFINITY, f64::min),
                dt_max,
                contact_displacement_error: None,
                displacement_at_samples: Vec::new(),
                own_mesh: Some(record),
            },
            level: LevelRecord {
                nx: cells,
                h: self.longest_edge,
                dt: dt_max,
                steps: samples - 1,
                dofs: self.mesh.points().len() * d,
                timings: Timings {
                    observe: clock.elapsed().as_secs_f64(),
                    ..Timings::default()
                },
                multiplier_variation_ratio: variation_ratio,
            },
            errors: series.errors(),
            lacks,
            notes: vec![note, contact_note],
            reported_energy: None,
            step_differences: None,
        })
    }
}

impl OwnMeshRun {
    /// An empty comparison at the reference's contact node nearest the face's centre.
    fn face_comparison(&self, reference: &FineReference) -> FaceComparison {
        let x = reference.mesh.node(reference.mesh.face_centre());
        let d = self.mesh.dim();
        FaceComparison {
            point: x[..d].to_vec(),
            time: Vec::new(),
            displacement: Vec::new(),
            reference_displacement: Vec::new(),
            force: self.multiplier.as_ref().map(|_| Vec::new()),
            reference_force: Vec::new(),
            pressure: self.multiplier.as_ref().map(|_| Vec::new()),
            reference_pressure: Vec::new(),
            errors: BTreeMap::new(),
        }
    }

    /// Adds the sample at time `t`, the finest level's step `k` (the reference's history
    /// sample `k`), of displacement `u` and multipliers `lambda` to `contact`; returns its
    /// resultant's distance to the reference's (`None` without multipliers).
    fn compare_contact(
        &self,
        contact: &mut FaceComparison,
        reference: &FineReference,
        (k, t): (usize, f64),
        (u, lambda): (&[f64], Option<Vec<f64>>),
    ) -> Result<Option<f64>, ExternalError> {
        let d = self.mesh.dim();
        let h = &reference.histories;
        let mut x = [0.0; 3];
        x[..d].copy_from_slice(&contact.point);
        let outside = || {
            ExternalError::invalid(
                &self.file.path,
                "Cells",
                Some(format!("t = {t}")),
                format!("no cell holds the face's centre {:?}", &contact.point),
                "a conforming mesh of the scene's box",
            )
        };
        let at = self.mesh.evaluate(u, x).ok_or_else(outside)?;
        let centre = reference.mesh.face_centre();
        contact.time.push(t);
        contact.displacement.push(at.value[d - 1]);
        contact
            .reference_displacement
            .push(h.centre_displacement[k]);
        contact.reference_force.push(h.total_force[k]);
        let share = reference.mesh.face_share(centre);
        contact
            .reference_pressure
            .push(h.centre_multiplier[k] / share);
        let (Some(lambda), Some(force), Some(pressure)) =
            (lambda, contact.force.as_mut(), contact.pressure.as_mut())
        else {
            return Ok(None);
        };
        let resultant = self.face.resultant(&lambda);
        force.push(resultant);
        let p = self.face.pressure_at(&self.mesh, &lambda, x);
        pressure.push(p.ok_or_else(outside)?);
        Ok(Some(resultant - h.total_force[k]))
    }
}

/// What the note's findings on the series `series` that are on their own mesh rest on (each
/// series that declares a case, [`declared_series`]), one sentence per kind naming the series
/// it concerns: the bound of their displacement errors, by which their rates' intervals are
/// widened; a redistributed mass that is the code's own; the energy computed on their cells, or
/// missing; the contact force as the resultant over the face, or missing.
pub fn own_mesh_caveats(series: &[Series]) -> Vec<String> {
    let mut own = Vec::new();
    let (mut redistributed, mut resultant, mut without) = (Vec::new(), Vec::new(), Vec::new());
    let (mut energy, mut no_energy) = (Vec::new(), Vec::new());
    let mut bound = 0.0f64;
    for (s, case) in declared_series(series) {
        let Some(finest) = s
            .runs
            .iter()
            .filter_map(|r| r.own_mesh.as_ref())
            .next_back()
        else {
            continue;
        };
        let cells = finest.mesh.trim_start_matches("own mesh: ");
        own.push(format!("`{}` ({cells} at its finest level)", s.label));
        bound = bound.max(own_mesh_bound(s, Norm::DisplacementLinfV));
        let label = format!("`{}`", s.label);
        if case.mass == MassVariant::Redistributed {
            redistributed.push(label.clone());
        }
        match s.not_computed(Norm::EnergyLinf) {
            None => energy.push(label.clone()),
            Some(_) => no_energy.push(label.clone()),
        }
        match s.not_computed(Norm::MultiplierL2) {
            None => resultant.push(label),
            Some(_) => without.push(label),
        }
    }
    if own.is_empty() {
        return Vec::new();
    }
    let mut caveats = vec![format!(
        "On their own mesh: {}. Their displacement errors are measured against the reference's \
         projections on the finest study level, each within its stated bound (u_Linf_V's up to \
         {bound:.1e}), by which each rate's interval is widened beside the reference's bias \
         bound.",
        own.join(", ")
    )];
    if !energy.is_empty() {
        caveats.push(format!(
            "The energy of {} is computed on its own cells with the mass it declares (the \
             redistributed one over the cells without a vertex on Γ_C) and compared with the \
             reference's at the same steps.",
            energy.join(", ")
        ));
    }
    if !no_energy.is_empty() {
        caveats.push(format!(
            "The energy of {} is not computed (its reason is listed with the norms), so the \
             findings that rest on it are undecided.",
            no_energy.join(", ")
        ));
    }
    if !redistributed.is_empty() {
        caveats.push(format!(
            "The redistributed mass of {} on its own cells is the code's construction: the note \
             defines it on the scene's Q1 elements (those that touch Γ_C removed), so the \
             findings judge the code's mass, not the note's.",
            redistributed.join(", ")
        ));
    }
    if !resultant.is_empty() {
        caveats.push(format!(
            "The contact force of {} is the resultant of its multipliers over its contact face, \
             compared with the reference's at its samples; the oscillation indicator is that \
             resultant's, as on the scene's mesh.",
            resultant.join(", ")
        ));
    }
    if !without.is_empty() {
        caveats.push(format!(
            "No multipliers were read for {} (--multiplier NAME), so the findings on the contact \
             force are undecided.",
            without.join(", ")
        ));
    }
    caveats
}

/// The unknowns `unknowns` of `mesh` as nodal values, `d` per node (a clamped node's 0).
fn on_nodes(mesh: &BoxMesh, unknowns: &[f64]) -> Vec<f64> {
    let d = mesh.dim();
    (0..mesh.n_nodes())
        .flat_map(|node| (0..d).map(move |c| (node, c)))
        .map(|(node, c)| mesh.dof_of(node, c).map_or(0.0, |dof| unknowns[dof]))
        .collect()
}
