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
//! The contact-force and energy norms are not measured: they are defined through the nodal
//! multiplier and the scene's mass and stiffness on the scene's nodes.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::time::Instant;

use serde::{Deserialize, Serialize};

use super::{Declared, RunRecord, VerifiedFile};
use crate::engine::fem::box_mesh::{BoxMesh, Elasticity};
use crate::harness::external::box_run::{
    displacement_array, first_non_finite, BoxScene, SeriesOptions, NODE_ROUNDINGS,
    STEP_TIME_TOLERANCE,
};
use crate::harness::external::error::ExternalError;
use crate::harness::external::format::Code;
use crate::harness::external::mesh::{
    check_domain, pair_errors_each, CellKind, ElementMesh, Quadrature, Topology, ALLOWED_CELLS,
};
use crate::harness::external::nodal_snapshot::NodalSnapshot;
use crate::harness::external::snapshot_series::SnapshotSeries;
use crate::harness::problem::{MassVariant, Scheme};
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

/// Why the contact-force and energy norms of such a series are not computed (after "the file
/// … has no").
pub const NOT_MEASURED: &str = "norm defined without the nodal multiplier and the scene's \
     matrices: not measured on a foreign mesh (the contact force is the sum of the nodal \
     multipliers, the energy uses the scene's mass and stiffness on its nodes)";

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
}

/// A series' file on its own mesh, its first snapshot read and checked.
pub struct OwnMeshRun {
    /// The file.
    pub path: PathBuf,
    /// The code and its version.
    pub code: Code,
    /// The series' label.
    pub label: String,
    /// The scheme, when declared.
    pub scheme: Option<Scheme>,
    /// The mass matrix, when declared.
    pub mass: Option<MassVariant>,
    /// How contact is enforced, when declared.
    pub contact: Option<String>,
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
    series: SnapshotSeries,
    displacement: String,
    first: NodalSnapshot,
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
        check_domain(&mesh, lengths, NODE_ROUNDINGS * first.point_epsilon).map_err(|why| {
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
        let (code, label) = options.code_and_label(path)?;
        let run = Self {
            path: path.to_path_buf(),
            code,
            label,
            scheme: options.scheme,
            mass: options.mass,
            contact: options.contact.clone(),
            cells: counted(&mesh),
            longest_edge: longest_edge(&mesh),
            mesh,
            time,
            steps,
            displacement: displacement_array(&first, options, d)?,
            series,
            first,
        };
        run.sample(0)?;
        Ok(run)
    }

    /// Sample `n`'s displacement, `d` per point of the mesh (its snapshot read now, its points
    /// and cells checked to be the first snapshot's).
    pub fn sample(&self, n: usize) -> Result<Vec<f64>, ExternalError> {
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
        let name = &self.displacement;
        let array = snapshot.array(name).filter(|a| a.components >= d);
        let array = array.ok_or_else(|| {
            ExternalError::invalid(
                &snapshot.path,
                "PointData",
                None,
                format!("no array {name:?} of at least {d} components"),
                "the displacement's point array (--displacement NAME)",
            )
        })?;
        first_non_finite(&snapshot, array, self.time[n])?;
        Ok((0..snapshot.points.len())
            .flat_map(|k| array.row(k)[..d].iter().copied())
            .collect())
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
        // The projection's and the quadrature's parts, in H and in V.
        let mut parts: [TimeSeriesNorm; 4] = Default::default();
        for (n, &k) in self.steps.iter().enumerate() {
            let t = self.time[n];
            if k >= projections.samples() {
                return Err(ExternalError::invalid(
                    &self.path,
                    "timestep",
                    Some(format!("sample {n}")),
                    t,
                    format!(
                        "a time the reference recorded on level {finest} ({} steps)",
                        projections.samples()
                    ),
                ));
            }
            let u = self.sample(n)?;
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
                            &self.path,
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
            series.push_partial(t, Some((p_h * p_h + r_h, p_v * p_v + r_v)), None, None);
            let values = [r_h, r_v].map(|r| 2f64.sqrt() * r.max(0.0).sqrt());
            let quadrature = [(p_h - q_h).abs(), (p_v - q_v).abs()].map(|x| 2.0 * x);
            for (part, value) in parts.iter_mut().zip(values.into_iter().chain(quadrature)) {
                part.push(t, value);
            }
        }
        let spacing = self.time.windows(2).map(|w| w[1] - w[0]);
        let dt_max = spacing.clone().fold(0.0, f64::max);
        let d = self.mesh.dim();
        let file = self.path.display().to_string();
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
        let lacks = [Norm::MultiplierL2, Norm::EnergyLinf, Norm::EnergyL2]
            .into_iter()
            .map(|norm| (norm, NOT_MEASURED.to_string()))
            .collect();
        let cells = self.mesh.cells().len();
        let samples = self.time.len();
        Ok(VerifiedFile {
            label: self.label.clone(),
            code: self.code.clone(),
            declared: Declared::of(self.scheme, self.mass, self.contact.as_deref()),
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
                multiplier_variation_ratio: None,
            },
            errors: series.errors(),
            lacks,
            notes: vec![note],
            reported_energy: None,
            step_differences: None,
        })
    }
}

/// The unknowns `unknowns` of `mesh` as nodal values, `d` per node (a clamped node's 0).
fn on_nodes(mesh: &BoxMesh, unknowns: &[f64]) -> Vec<f64> {
    let d = mesh.dim();
    (0..mesh.n_nodes())
        .flat_map(|node| (0..d).map(move |c| (node, c)))
        .map(|(node, c)| mesh.dof_of(node, c).map_or(0.0, |dof| unknowns[dof]))
        .collect()
}
