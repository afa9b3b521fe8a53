//! Another code's run of a box scene (`bar2d`, `bar3d`), read from a ParaView collection
//! ([`super::pvd`]) or from the box form of the JSON format (`signorini-external/2` with a
//! `mesh` of `lengths` and `elements`), checked against the scene's structured Q1 mesh at the
//! file's level and handed over step by step in the harness's node order ([`BoxSample`]).
//!
//! The checks, each refused with the field and what is allowed: the scene's name (JSON), a mesh
//! that is the scene's at one of its study levels (every node matched to [`NODE_TOLERANCE`] of
//! the box's size, in any order; the first node that matches none is named), its cells, when the
//! file gives them, the scene's elements ([`check_cells`]: a cell the harness does not interpolate
//! is refused by its type, a triangle or tetrahedron by name; `verify` reads a series with one on
//! its own mesh instead, [`super::verify::own_mesh`]), one sample at
//! every step `t_n = n Δt` of that level's time grid from 0 to `T` (the first missing step is
//! named), the clamped face at rest.

use std::cell::Cell;
use std::collections::HashMap;
use std::fmt;
use std::path::{Path, PathBuf};

use serde::de::{self, SeqAccess, Visitor};
use serde::{Deserialize, Deserializer};

use super::error::ExternalError;
use super::format::{Code, CLAMPED_TOLERANCE, HORIZON_TOLERANCE, MAX_VALUES, RUN_FILE};
use super::mesh::{CellKind, Topology, ALLOWED_CELLS};
use super::nodal_snapshot::{NodalSnapshot, PointArray};
use super::snapshot_series::SnapshotSeries;
use super::verify::Declared;
use crate::engine::fem::box_mesh::BoxMesh;
use crate::engine::problem::{box_mesh, BoxProblem};
use crate::harness::files::input::{self, LARGEST_VALUE};
use crate::harness::problem::{MassVariant, Scheme};

/// The box form's format name, version 2 of the format (the 1D form reads `/1` and `/2`).
pub use super::format::FORMAT_2 as BOX_FORMAT;

/// How far a file's node may be from the scene's mesh node it matches, relative to the box's
/// largest length, for points of double precision.
pub const NODE_TOLERANCE: f64 = 1e-9;

/// How many units of their type's rounding a file's points may be from the scene's nodes, relative
/// to the box's largest length: a point rounded to single precision (GetFEM's exporter writes
/// `Float32` points) is within half of `f32::EPSILON` of its node, relative to its own size.
pub const NODE_ROUNDINGS: f64 = 4.0;

/// How far a sample's time may be from its step's `n Δt`, relative to `Δt`.
pub const STEP_TIME_TOLERANCE: f64 = 1e-9;

/// The node order of the box form's per-node arrays: `x₁` fastest, then `x₂`, then `x₃`.
pub const NODE_ORDER: &str = "x1-fastest";

/// What a code reports as its energy, when it does (one list for both forms of the format).
pub use super::format::EnergyDefinition;

/// How a `.pvd`'s point arrays are named and what its runs are: what the command line gives.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct SeriesOptions {
    /// The code and its version.
    pub code: Option<Code>,
    /// The series' label (default: the collection's file stem).
    pub label: Option<String>,
    /// The scheme the code ran (for the note's findings).
    pub scheme: Option<Scheme>,
    /// The mass matrix the code used: the energy is computed with it.
    pub mass: Option<MassVariant>,
    /// How the code enforces contact, in its words (shown, not interpreted).
    pub contact: Option<String>,
    /// The displacement's point array (default: the file's only 2- or 3-component array,
    /// else one named `displacement`).
    pub displacement: Option<String>,
    /// The velocity's point array, if any.
    pub velocity: Option<String>,
    /// The contact multipliers' point array (one component, `λ_i ≤ 0` on the contact nodes),
    /// if any.
    pub multiplier: Option<String>,
    /// Measure the series as fields on their own mesh ([`super::verify::own_mesh`]) even when
    /// its cells are the scene's Q1 elements (a series with a triangle or tetrahedron is always).
    pub own_mesh: bool,
}

/// A box run's file with who wrote it and what it declares: what a verification says of it,
/// whatever the mesh it is measured on.
#[derive(Debug, Clone)]
pub struct SeriesFile {
    /// The file (`.pvd`, `.xdmf` or `.json`).
    pub path: PathBuf,
    /// The code and its version.
    pub code: Code,
    /// The configuration: files with one label form one refinement series.
    pub label: String,
    /// The scheme, when declared.
    pub scheme: Option<Scheme>,
    /// The mass matrix, when declared.
    pub mass: Option<MassVariant>,
    /// How contact is enforced, when declared.
    pub contact: Option<String>,
}

impl SeriesFile {
    /// What it declares, as verify.json lists it.
    pub fn declared(&self) -> Declared {
        Declared::of(self.scheme, self.mass, self.contact.as_deref())
    }
}

impl SeriesOptions {
    /// The series file `path` as these options describe it: the code (required: a `.pvd` or
    /// `.xdmf` does not say which code wrote it), the series' label (default: the file's stem)
    /// and what it declares.
    pub(crate) fn file(&self, path: &Path) -> Result<SeriesFile, ExternalError> {
        let code = self.code.clone().ok_or_else(|| {
            ExternalError::invalid(
                path,
                "--code",
                None,
                "missing",
                "the code's name and version (--code NAME --code-version VERSION): a .pvd or .xdmf \
                 does not say which code wrote it",
            )
        })?;
        let label = self.label.clone().unwrap_or_else(|| {
            path.file_stem()
                .map_or("pvd".into(), |s| s.to_string_lossy().into_owned())
        });
        Ok(SeriesFile {
            path: path.to_path_buf(),
            code,
            label,
            scheme: self.scheme,
            mass: self.mass,
            contact: self.contact.clone(),
        })
    }
}

/// One step of a box run in the harness's order: what the file has of it.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct BoxSample {
    /// The nodal displacements (`d` per node, node by node).
    pub displacement: Option<Vec<f64>>,
    /// The nodal velocities, like `displacement`.
    pub velocity: Option<Vec<f64>>,
    /// The contact multipliers, one per contact node in the harness's order.
    pub multipliers: Option<Vec<f64>>,
    /// `Σ_i λ_i` when the file gives it without the multipliers.
    pub total_force: Option<f64>,
    /// The code's own energy ([`BoxExternalRun::energy_definition`]).
    pub reported_energy: Option<f64>,
}

impl BoxSample {
    /// `Σ_i λ_i`: the multipliers' sum (in the harness's order), else the file's total.
    pub fn total_force(&self) -> Option<f64> {
        match &self.multipliers {
            Some(m) => Some(m.iter().sum()),
            None => self.total_force,
        }
    }
}

/// Where the samples come from.
#[derive(Debug, Clone)]
#[allow(clippy::large_enum_variant)] // one per run file, never moved once read
enum Source {
    /// One snapshot per step (a `.pvd` or an `.xdmf`), read when its step is asked for.
    Snapshots {
        series: SnapshotSeries,
        names: ArrayNames,
        /// Per file node, the scene's node.
        order: Vec<usize>,
        /// The cells of the first snapshot: every snapshot's.
        topology: Option<Topology>,
    },
    /// Every sample, read.
    Json(Vec<BoxSample>),
}

/// The point arrays a collection's snapshots are read through.
#[derive(Debug, Clone)]
struct ArrayNames {
    displacement: String,
    velocity: Option<String>,
    multiplier: Option<String>,
}

/// Another code's run of a box scene, checked against the scene's mesh and time grid.
#[derive(Debug, Clone)]
pub struct BoxExternalRun {
    /// The file, its code and what it declares.
    pub file: SeriesFile,
    /// The level: elements along the axis.
    pub level: usize,
    /// The mesh of that level.
    pub mesh: BoxMesh,
    /// `t_n`, one per step of the level's grid.
    pub time: Vec<f64>,
    /// What the code's reported energy is, when it reports one.
    pub energy_definition: Option<EnergyDefinition>,
    /// The machine epsilon of the file's numbers: the largest of its displacement's, velocity's
    /// and multipliers' arrays (`f64::EPSILON` for the JSON form, whose numbers are doubles).
    pub value_epsilon: f64,
    source: Source,
}

impl BoxExternalRun {
    /// The samples, `N + 1`.
    pub fn samples(&self) -> usize {
        self.time.len()
    }

    /// Step `n`'s sample (a collection's snapshot is read now: one at a time is held).
    pub fn sample(&self, n: usize) -> Result<BoxSample, ExternalError> {
        match &self.source {
            Source::Json(samples) => Ok(samples[n].clone()),
            Source::Snapshots {
                series,
                names,
                order,
                topology,
            } => {
                let snapshot = series.snapshot(n)?;
                if snapshot.topology != *topology {
                    return Err(ExternalError::invalid(
                        &snapshot.path,
                        "Cells",
                        None,
                        "other cells",
                        "the cells of the collection's first snapshot: one mesh for every time",
                    ));
                }
                self.sample_of_snapshot(&snapshot, names, order, self.time[n])
            }
        }
    }

    /// The arrays of `snapshot` (at `time`) in the scene's node order (`order`: per file node,
    /// the scene's), its points first checked to be those of the collection's first snapshot,
    /// every value it reads finite and within [`LARGEST_VALUE`] ([`first_non_finite`]) and its
    /// multipliers on the contact face with the harness's sign ([`check_multipliers`]).
    fn sample_of_snapshot(
        &self,
        snapshot: &NodalSnapshot,
        names: &ArrayNames,
        order: &[usize],
        time: f64,
    ) -> Result<BoxSample, ExternalError> {
        let checked = node_order(&self.mesh, snapshot)?;
        if checked != order {
            return Err(ExternalError::invalid(
                &snapshot.path,
                "Points",
                None,
                "the nodes in another order",
                "the points of the collection's first snapshot, in its order",
            ));
        }
        let d = self.mesh.dim();
        let nodal = |name: &str| -> Result<Vec<f64>, ExternalError> {
            let array = snapshot.array(name).ok_or_else(|| {
                ExternalError::invalid(
                    &snapshot.path,
                    "PointData",
                    None,
                    format!("no array {name:?}"),
                    format!("the arrays {:?}", array_names(snapshot)),
                )
            })?;
            first_non_finite(snapshot, array, time)?;
            if array.components < d {
                return Err(ExternalError::invalid(
                    &snapshot.path,
                    format!("PointData {name:?}"),
                    None,
                    format!("{} component(s)", array.components),
                    format!("at least {d} (a vector of the {d}D box)"),
                ));
            }
            let mut values = vec![0.0; self.mesh.n_nodes() * d];
            for (file_node, &node) in order.iter().enumerate() {
                let row = &array.row(file_node)[..d];
                values[node * d..(node + 1) * d].copy_from_slice(row);
            }
            Ok(values)
        };
        let multipliers = names
            .multiplier
            .as_deref()
            .map(|name| {
                let on_face = |k: usize| self.mesh.on_contact_boundary(order[k]);
                let values = point_multipliers(snapshot, name, time, (d, on_face))?;
                let mut by_node = vec![0.0; self.mesh.n_nodes()];
                for (file_node, &node) in order.iter().enumerate() {
                    by_node[node] = values[file_node];
                }
                let contact = self.mesh.contact_nodes();
                Ok::<Vec<f64>, ExternalError>(contact.iter().map(|&n| by_node[n]).collect())
            })
            .transpose()?;
        let sample = BoxSample {
            displacement: Some(nodal(&names.displacement)?),
            velocity: names.velocity.as_deref().map(nodal).transpose()?,
            multipliers,
            total_force: None,
            reported_energy: None,
        };
        check_clamped(&self.mesh, &sample, &snapshot.path, None)?;
        Ok(sample)
    }
}

/// The one-component multiplier array `name` of `snapshot` (at `time`) of a `d`-dimensional
/// box, one value per point: every value finite ([`first_non_finite`]), 0 within
/// [`multiplier_scale`] at each point `on_face` says is off the contact face `x_d = 0`, and of
/// the harness's sign
/// ([`check_multipliers`]).
pub(crate) fn point_multipliers(
    snapshot: &NodalSnapshot,
    name: &str,
    time: f64,
    (d, on_face): (usize, impl Fn(usize) -> bool),
) -> Result<Vec<f64>, ExternalError> {
    let array = snapshot.array(name).filter(|a| a.components == 1);
    let array = array.ok_or_else(|| {
        ExternalError::invalid(
            &snapshot.path,
            "PointData",
            None,
            format!("no one-component array {name:?}"),
            format!("the arrays {:?}", array_names(snapshot)),
        )
    })?;
    first_non_finite(snapshot, array, time)?;
    let scale = multiplier_scale(&array.values);
    let off_face = (0..array.values.len()).find(|&k| !on_face(k) && array.values[k].abs() > scale);
    if let Some(k) = off_face {
        return Err(ExternalError::invalid(
            &snapshot.path,
            format!("PointData {name:?}"),
            Some(at_point(snapshot, k, time)),
            array.values[k],
            format!(
                "0 within {scale:e} off the contact face x{d} = 0: a multiplier acts on a \
                 contact node only"
            ),
        ));
    }
    check_multipliers(&array.values, &snapshot.path, |k| {
        at_point(snapshot, k, time)
    })?;
    Ok(array.values.clone())
}

/// Where point `k` of `snapshot` is, at `time`, as the errors say it.
fn at_point(snapshot: &NodalSnapshot, k: usize, time: f64) -> String {
    format!("point {k} {:?} at t = {time}", snapshot.points[k])
}

/// What a value of a box run must be ([`LARGEST_VALUE`]).
const IN_RANGE: &str = "finite numbers of magnitude at most 1e100 (a run that went non-finite or \
                        diverged is not verified)";

/// Whether `v` is finite and at most [`LARGEST_VALUE`] in magnitude.
fn in_range(v: f64) -> bool {
    v.is_finite() && v.abs() <= LARGEST_VALUE
}

/// Refuses `array` of `snapshot` (at `time`) at its first value that is not finite or is beyond
/// [`LARGEST_VALUE`], naming the point: a run that went NaN, infinite or that far is broken,
/// whatever the steps before it.
pub(crate) fn first_non_finite(
    snapshot: &NodalSnapshot,
    array: &PointArray,
    time: f64,
) -> Result<(), ExternalError> {
    let components = array.components.max(1);
    match array.values.iter().position(|v| !in_range(*v)) {
        None => Ok(()),
        Some(i) => Err(ExternalError::invalid(
            &snapshot.path,
            format!("PointData {:?}", array.name),
            Some(at_point(snapshot, i / components, time)),
            array.values[i],
            IN_RANGE,
        )),
    }
}

/// How far a multiplier may stray to the wrong side of 0 (or off the contact face), relative to
/// the largest multiplier of its sample or 1, whichever is larger: a contact solver's round-off
/// (GetFEM's Newton leaves about 1e-16 on a step without contact).
pub const MULTIPLIER_TOLERANCE: f64 = 1e-9;

/// [`MULTIPLIER_TOLERANCE`] for the multipliers `values` of one sample.
fn multiplier_scale(values: &[f64]) -> f64 {
    MULTIPLIER_TOLERANCE * values.iter().fold(1.0f64, |m, v| m.max(v.abs()))
}

/// Refuses contact multipliers of the wrong sign: the harness's convention is `λ_i ≤ 0` (the
/// obstacle pushes the body, the nodal force is `−λ_i e_d`), within [`multiplier_scale`];
/// `place` says where value `i` is.
fn check_multipliers(
    multipliers: &[f64],
    path: &Path,
    place: impl Fn(usize) -> String,
) -> Result<(), ExternalError> {
    let scale = multiplier_scale(multipliers);
    match multipliers.iter().position(|&l| l > scale) {
        None => Ok(()),
        Some(i) => Err(ExternalError::invalid(
            path,
            "multipliers",
            Some(place(i)),
            multipliers[i],
            format!(
                "λ ≤ 0 within {scale:e}: the obstacle pushes, so a contact force −λ e_d points \
                 into the body (a code whose multipliers are ≥ 0 uses the opposite sign: negate \
                 them)"
            ),
        )),
    }
}

fn array_names(snapshot: &NodalSnapshot) -> Vec<&str> {
    snapshot.arrays.iter().map(|a| a.name.as_str()).collect()
}

/// The scene's levels a file may be at (those the reference is projected on), with the
/// problem.
#[derive(Debug, Clone, Copy)]
pub struct BoxScene<'a> {
    /// The scene's name.
    pub name: &'a str,
    /// Its problem.
    pub problem: &'a BoxProblem,
    /// Its study levels.
    pub levels: &'a [usize],
    /// `Δx/Δt`.
    pub ratio: f64,
}

impl BoxScene<'_> {
    /// The level whose mesh has `nodes` nodes, if one has.
    fn level_with(&self, nodes: usize, path: &Path) -> Result<(usize, BoxMesh), ExternalError> {
        let mut sizes = Vec::new();
        for &level in self.levels {
            let mesh =
                box_mesh(self.problem, level).map_err(|e| ExternalError::Harness(e.into()))?;
            if mesh.n_nodes() == nodes {
                return Ok((level, mesh));
            }
            sizes.push(format!("{} at level {level}", mesh.n_nodes()));
        }
        Err(ExternalError::invalid(
            path,
            "Points",
            None,
            format!("{nodes} nodes"),
            format!(
                "the scene's Q1 mesh at one of its study levels: {}",
                sizes.join(", ")
            ),
        ))
    }

    /// `t_n = n Δt` of `level`, `n = 0..N`, as the harness's runs step.
    pub(crate) fn time_grid(&self, level: usize) -> Vec<f64> {
        let h = self.problem.lengths[self.problem.lengths.len() - 1] / level as f64;
        let (steps, dt) = crate::harness::run::time_grid(self.problem.horizon, h, self.ratio);
        (0..=steps).map(|n| n as f64 * dt).collect()
    }

    /// Checks the times `times` (a file's, in its order) against `level`'s grid: one per step.
    fn check_times(
        &self,
        level: usize,
        times: &[f64],
        path: &Path,
        field: &str,
    ) -> Result<Vec<f64>, ExternalError> {
        let grid = self.time_grid(level);
        let dt = grid.get(1).copied().unwrap_or(self.problem.horizon);
        for (n, &t) in grid.iter().enumerate() {
            match times.get(n) {
                Some(&given) if (given - t).abs() <= STEP_TIME_TOLERANCE * dt => {}
                given => {
                    return Err(ExternalError::invalid(
                        path,
                        field,
                        Some(format!("step {n}")),
                        given.map_or("missing".to_string(), |g| g.to_string()),
                        format!(
                            "one sample per step of level {level}: t_n = n Δt with Δt = {dt} \
                             ({} steps to T = {}), within {STEP_TIME_TOLERANCE:e} Δt; step {n} \
                             is at {t}",
                            grid.len() - 1,
                            self.problem.horizon
                        ),
                    ))
                }
            }
        }
        if times.len() > grid.len() {
            return Err(ExternalError::invalid(
                path,
                field,
                Some(format!("sample {}", grid.len())),
                times[grid.len()],
                format!(
                    "no sample after T = {} (within a relative {HORIZON_TOLERANCE:e})",
                    self.problem.horizon
                ),
            ));
        }
        Ok(grid)
    }

    /// Reads the series `series` of the file `path` (a `.pvd` or an `.xdmf`) as a run of this
    /// scene, its arrays named by `options`.
    pub fn read_series(
        &self,
        path: &Path,
        series: SnapshotSeries,
        options: &SeriesOptions,
    ) -> Result<BoxExternalRun, ExternalError> {
        let first = series.snapshot(0)?;
        let (level, mesh) = self.level_with(first.points.len(), &first.path)?;
        let order = node_order(&mesh, &first)?;
        check_cells(&mesh, &first, &order)?;
        let time = self.check_times(level, &series.times(), path, "timestep")?;
        let names = ArrayNames {
            displacement: displacement_array(&first, options, mesh.dim())?,
            velocity: options.velocity.clone(),
            multiplier: options.multiplier.clone(),
        };
        let value_epsilon = [
            Some(&names.displacement),
            names.velocity.as_ref(),
            names.multiplier.as_ref(),
        ]
        .into_iter()
        .flatten()
        .filter_map(|name| first.array(name))
        .fold(f64::EPSILON, |e, a| e.max(a.epsilon));
        let run = BoxExternalRun {
            file: options.file(path)?,
            level,
            mesh,
            time,
            energy_definition: None,
            value_epsilon,
            source: Source::Snapshots {
                series,
                names,
                order,
                topology: first.topology.clone(),
            },
        };
        run.sample(0)?;
        Ok(run)
    }

    /// Reads the box form of the JSON format `path` as a run of this scene, its numbers and
    /// samples counted as they are read ([`Room`]): a file of more is refused before they are
    /// held.
    pub fn read_json(&self, path: &Path) -> Result<BoxExternalRun, ExternalError> {
        let samples = self
            .levels
            .iter()
            .map(|&level| self.time_grid(level).len())
            .max()
            .unwrap_or(0);
        let file: BoxFile = Room::within(samples, || input::read_json(path, RUN_FILE))
            .map_err(|e| ExternalError::of_json(path, e))?;
        file.into_run(self, path)
    }
}

/// The displacement's array of `snapshot`: the one `options` names, else the only array of `d`
/// or 3 components, else one named `displacement`.
pub(crate) fn displacement_array(
    snapshot: &NodalSnapshot,
    options: &SeriesOptions,
    d: usize,
) -> Result<String, ExternalError> {
    if let Some(name) = &options.displacement {
        return Ok(name.clone());
    }
    let vectors: Vec<&str> = snapshot
        .arrays
        .iter()
        .filter(|a| a.components == d || a.components == 3)
        .map(|a| a.name.as_str())
        .collect();
    match vectors.as_slice() {
        [only] => Ok(only.to_string()),
        _ if snapshot.array("displacement").is_some() => Ok("displacement".into()),
        _ => Err(ExternalError::invalid(
            &snapshot.path,
            "--displacement",
            None,
            format!("not given, and the vector arrays are {vectors:?}"),
            "the name of the displacement's point array (--displacement NAME)",
        )),
    }
}

/// Per point of `snapshot`, the node of `mesh` it is (within [`NODE_TOLERANCE`] of the box's
/// largest length, or [`NODE_ROUNDINGS`] times its points' machine epsilon when that is larger;
/// coordinates past the mesh's dimension 0), every node once.
fn node_order(mesh: &BoxMesh, snapshot: &NodalSnapshot) -> Result<Vec<usize>, ExternalError> {
    let (points, path) = (&snapshot.points, snapshot.path.as_path());
    let d = mesh.dim();
    let scale = mesh.lengths().iter().fold(0.0f64, |a, &b| a.max(b));
    let relative = NODE_TOLERANCE.max(NODE_ROUNDINGS * snapshot.point_epsilon);
    let tolerance = relative * scale;
    let sizes = mesh.element_sizes();
    let counts = mesh.counts();
    let by_index: HashMap<[usize; 3], usize> = (0..mesh.n_nodes())
        .map(|node| (mesh.node_index(node), node))
        .collect();
    let mut seen = vec![false; mesh.n_nodes()];
    let mut order = Vec::with_capacity(points.len());
    for (k, p) in points.iter().enumerate() {
        let mut index = [0usize; 3];
        let mut matched = p[d..].iter().all(|x| x.abs() <= tolerance);
        for c in 0..d {
            let i = (p[c] / sizes[c]).round();
            matched &= i >= 0.0
                && i <= counts[c] as f64
                && (p[c] - i * sizes[c]).abs() <= tolerance
                && (i as usize != counts[c] || (p[c] - mesh.lengths()[c]).abs() <= tolerance);
            index[c] = i.max(0.0) as usize;
        }
        let node = by_index.get(&index).copied().filter(|_| matched);
        match node {
            Some(node) if !seen[node] => {
                seen[node] = true;
                order.push(node);
            }
            _ => {
                return Err(ExternalError::invalid(
                    path,
                    "Points",
                    Some(format!("point {k}")),
                    format!("{:?}", &p[..]),
                    format!(
                        "the nodes of the scene's Q1 mesh of {counts:?} elements on {:?}, each \
                         once, within {tolerance:e} ({relative:e} of the box's size){}",
                        mesh.lengths(),
                        if node.is_some() {
                            ": this node is listed twice"
                        } else {
                            ""
                        }
                    ),
                ))
            }
        }
    }
    Ok(order)
}

/// The cells of `snapshot` (whose point `k` is the scene's node `order[k]`), when its file gives
/// them, checked to be the scene's Q1 elements, each once: the only elements a box run is
/// measured on. A cell of a type the harness does not interpolate ([`ALLOWED_CELLS`]) is refused
/// by its type; a triangle or tetrahedron (on the scene's nodes, DOLFINx's default mesh: a P1
/// field, which measured as Q1 would be another function) by name; a quadrilateral or
/// hexahedron whose edges are not edges of the scene's mesh (a cell listed in another order
/// than VTK's), on nodes that are no element's, or on an element already listed, by its
/// points. A grid without cells is taken on the scene's elements, as its nodes are.
fn check_cells(
    mesh: &BoxMesh,
    snapshot: &NodalSnapshot,
    order: &[usize],
) -> Result<(), ExternalError> {
    let d = mesh.dim();
    let q1 = if d == 2 {
        CellKind::Quadrilateral
    } else {
        CellKind::Hexahedron
    };
    let path = snapshot.path.as_path();
    let scene_elements = || {
        format!(
            "the {} of the scene's mesh at this level ({:?} elements on {:?}), each once, \
             its vertices in VTK's order",
            q1.plural(),
            mesh.counts(),
            mesh.lengths()
        )
    };
    let only_q1 = |kind: CellKind, at: Option<String>, value: String| {
        if kind == q1 {
            return Ok(());
        }
        Err(ExternalError::invalid(
            path,
            "Cells",
            at,
            value,
            format!(
                "{}: a box run is measured against the reference on the scene's own elements \
                 only, so a mesh of {} is not verified (it is not read as {})",
                scene_elements(),
                kind.plural(),
                q1.plural()
            ),
        ))
    };
    let cells = match &snapshot.topology {
        None => return Ok(()),
        Some(Topology::Declared(name)) => {
            let kind = CellKind::of_xdmf(name).ok_or_else(|| {
                ExternalError::invalid(
                    path,
                    "Topology.TopologyType",
                    None,
                    format!("{name:?}"),
                    ALLOWED_CELLS,
                )
            })?;
            return only_q1(kind, None, format!("TopologyType {name:?}"));
        }
        Some(Topology::Cells(cells)) => cells,
    };
    let elements: HashMap<Vec<usize>, usize> = mesh
        .elements()
        .enumerate()
        .map(|(e, nodes)| {
            let mut nodes = nodes.to_vec();
            nodes.sort_unstable();
            (nodes, e)
        })
        .collect();
    let mut listed = vec![false; mesh.n_elements()];
    for (k, (vtk, points)) in cells.iter().enumerate() {
        let at = || Some(format!("cell {k}"));
        let kind = CellKind::of_vtk(vtk, points.len()).ok_or_else(|| {
            ExternalError::invalid(
                path,
                "Cells types",
                at(),
                format!("VTK cell type {vtk} of {} points", points.len()),
                ALLOWED_CELLS,
            )
        })?;
        only_q1(
            kind,
            at(),
            format!("a {} (VTK cell type {vtk})", kind.name()),
        )?;
        let nodes: Vec<usize> = points.iter().map(|&p| order[p]).collect();
        let on_edges = kind.edges().iter().all(|&[a, b]| {
            let (i, j) = (mesh.node_index(nodes[a]), mesh.node_index(nodes[b]));
            (0..d).map(|c| i[c].abs_diff(j[c])).sum::<usize>() == 1
        });
        let mut sorted = nodes.clone();
        sorted.sort_unstable();
        match elements.get(&sorted) {
            Some(&e) if on_edges && !listed[e] => listed[e] = true,
            _ => {
                return Err(ExternalError::invalid(
                    path,
                    "Cells connectivity",
                    at(),
                    format!(
                        "the points {points:?} at {:?}",
                        points
                            .iter()
                            .map(|&p| snapshot.points[p])
                            .collect::<Vec<_>>()
                    ),
                    scene_elements(),
                ))
            }
        }
    }
    match listed.iter().position(|l| !l) {
        None => Ok(()),
        Some(e) => Err(ExternalError::invalid(
            path,
            "Cells",
            None,
            format!(
                "{} cells, none on the scene's element {e} (nodes at {:?})",
                cells.len(),
                mesh.element(e)
                    .iter()
                    .map(|&n| mesh.node(n))
                    .collect::<Vec<_>>()
            ),
            scene_elements(),
        )),
    }
}

/// The clamped face `x_d = L_d` at rest in `sample`: its displacement and velocity within
/// [`CLAMPED_TOLERANCE`] of 0.
fn check_clamped(
    mesh: &BoxMesh,
    sample: &BoxSample,
    path: &Path,
    at: Option<String>,
) -> Result<(), ExternalError> {
    let d = mesh.dim();
    for (name, field) in [
        ("displacement", &sample.displacement),
        ("velocity", &sample.velocity),
    ] {
        let Some(values) = field else { continue };
        for node in (0..mesh.n_nodes()).filter(|&n| mesh.on_dirichlet_boundary(n)) {
            if let Some(v) = values[node * d..(node + 1) * d]
                .iter()
                .find(|v| v.abs() > CLAMPED_TOLERANCE)
            {
                return Err(ExternalError::invalid(
                    path,
                    name,
                    at.clone().or(Some(format!("node {node}"))),
                    v,
                    format!(
                        "0 within {CLAMPED_TOLERANCE:e} on the clamped face x{d} = {} (node \
                         {node} is on it)",
                        mesh.lengths()[d - 1]
                    ),
                ));
            }
        }
    }
    Ok(())
}

/// The box form of the JSON format (`signorini-external/2` with a box `mesh`), as a file holds
/// it: read by [`BoxScene::read_json`], written by converters of other codes' output
/// ([`crate::harness::getfem::anchor`]).
#[derive(Debug, Clone, PartialEq, Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields)]
pub struct BoxFile {
    /// [`BOX_FORMAT`].
    pub format: String,
    /// The scene's name.
    pub scene: String,
    /// The code and its version.
    pub code: Code,
    /// The series the file belongs to.
    pub label: String,
    /// The scheme, a preset name.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub scheme: Option<String>,
    /// The mass matrix.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mass: Option<MassVariant>,
    /// How contact is enforced, in the code's words.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub contact: Option<String>,
    /// The mesh.
    pub mesh: BoxFileMesh,
    /// What `energy` is, when the samples give it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub energy_definition: Option<EnergyDefinition>,
    /// One sample per step.
    #[serde(deserialize_with = "bounded_samples")]
    pub samples: Vec<BoxFileSample>,
}

/// The mesh of a box file: the box's lengths and the elements per direction, its nodes
/// numbered [`NODE_ORDER`].
#[derive(Debug, Clone, PartialEq, Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields)]
pub struct BoxFileMesh {
    /// The box's lengths, `x_d` (the axis) last.
    #[serde(deserialize_with = "bounded_list")]
    pub lengths: Vec<f64>,
    /// The elements per direction.
    #[serde(deserialize_with = "bounded_list")]
    pub elements: Vec<usize>,
    /// [`NODE_ORDER`].
    pub node_order: String,
}

/// One sample of a box file: any per-node array may be absent or `null`.
#[derive(Debug, Clone, PartialEq, Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields)]
pub struct BoxFileSample {
    /// `t_n`.
    pub time: f64,
    /// `d` numbers per node, nodes in [`NODE_ORDER`].
    #[serde(
        default,
        deserialize_with = "bounded_rows",
        skip_serializing_if = "Option::is_none"
    )]
    pub displacement: Option<Vec<Vec<f64>>>,
    /// Like `displacement`.
    #[serde(
        default,
        deserialize_with = "bounded_rows",
        skip_serializing_if = "Option::is_none"
    )]
    pub velocity: Option<Vec<Vec<f64>>>,
    /// `λ_i ≤ 0` per contact node (`x_d = 0`), in [`NODE_ORDER`].
    #[serde(
        default,
        deserialize_with = "bounded_numbers",
        skip_serializing_if = "Option::is_none"
    )]
    pub multipliers: Option<Vec<f64>>,
    /// `Σ_i λ_i`, for a code that reports only the resultant.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub total_force: Option<f64>,
    /// The code's own energy ([`BoxFile::energy_definition`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub energy: Option<f64>,
}

impl BoxFile {
    fn into_run(self, scene: &BoxScene<'_>, path: &Path) -> Result<BoxExternalRun, ExternalError> {
        let invalid = |field: &str, at: Option<String>, value: String, allowed: String| {
            ExternalError::invalid(path, field, at, value, allowed)
        };
        if self.format != BOX_FORMAT {
            return Err(invalid(
                "format",
                None,
                format!("{:?}", self.format),
                format!("{BOX_FORMAT:?} for a box scene's run"),
            ));
        }
        if self.scene != scene.name {
            return Err(invalid(
                "scene",
                None,
                format!("{:?}", self.scene),
                format!("{:?}, the scene given on the command line", scene.name),
            ));
        }
        for (field, value) in [
            ("code.name", &self.code.name),
            ("code.version", &self.code.version),
            ("label", &self.label),
        ] {
            if value.trim().is_empty() {
                return Err(invalid(
                    field,
                    None,
                    "\"\"".into(),
                    "a non-empty text".into(),
                ));
            }
        }
        let scheme = self
            .scheme
            .as_deref()
            .map(|name| {
                name.parse::<Scheme>()
                    .map_err(|e| invalid("scheme", None, format!("{name:?}"), e.to_string()))
            })
            .transpose()?;
        if self.mesh.node_order != NODE_ORDER {
            return Err(invalid(
                "mesh.node_order",
                None,
                format!("{:?}", self.mesh.node_order),
                format!("{NODE_ORDER:?}: node = i1 + (n1 + 1)·(i2 + (n2 + 1)·i3)"),
            ));
        }
        let lengths = &scene.problem.lengths;
        let same_box = self.mesh.lengths.len() == lengths.len()
            && self
                .mesh
                .lengths
                .iter()
                .zip(lengths)
                .all(|(a, b)| (a - b).abs() <= NODE_TOLERANCE * b);
        if !same_box {
            return Err(invalid(
                "mesh.lengths",
                None,
                format!("{:?}", self.mesh.lengths),
                format!("the scene's box {lengths:?}"),
            ));
        }
        let nodes: usize = self.mesh.elements.iter().map(|n| n + 1).product();
        let (level, mesh) = scene.level_with(nodes, path)?;
        if mesh.counts() != self.mesh.elements.as_slice() {
            return Err(invalid(
                "mesh.elements",
                None,
                format!("{:?}", self.mesh.elements),
                format!(
                    "the elements of the scene's mesh at level {level}: {:?}",
                    mesh.counts()
                ),
            ));
        }
        let times: Vec<f64> = self.samples.iter().map(|s| s.time).collect();
        let time = scene.check_times(level, &times, path, "time")?;
        let d = mesh.dim();
        let contact = mesh.contact_nodes().len();
        let mut samples = Vec::with_capacity(self.samples.len());
        for (k, s) in self.samples.into_iter().enumerate() {
            let at = || Some(format!("samples[{k}]"));
            let nodal = |name: &str, field: Option<Vec<Vec<f64>>>| {
                field
                    .map(|rows| {
                        if rows.len() != mesh.n_nodes() || rows.iter().any(|r| r.len() != d) {
                            return Err(invalid(
                                name,
                                at(),
                                format!("{} rows", rows.len()),
                                format!("{} rows of {d} numbers (one per node)", mesh.n_nodes()),
                            ));
                        }
                        Ok(rows.concat())
                    })
                    .transpose()
            };
            let multipliers = s.multipliers;
            if let Some(m) = &multipliers {
                if m.len() != contact {
                    return Err(invalid(
                        "multipliers",
                        at(),
                        format!("{} values", m.len()),
                        format!("one per contact node: {contact}"),
                    ));
                }
            }
            let sample = BoxSample {
                displacement: nodal("displacement", s.displacement)?,
                velocity: nodal("velocity", s.velocity)?,
                multipliers,
                total_force: s.total_force,
                reported_energy: s.energy,
            };
            let numbers = sample
                .displacement
                .iter()
                .chain(&sample.velocity)
                .chain(&sample.multipliers)
                .flatten()
                .chain(&sample.total_force)
                .chain(&sample.reported_energy);
            if let Some(bad) = numbers.clone().find(|v| !in_range(**v)) {
                return Err(invalid("samples", at(), bad.to_string(), IN_RANGE.into()));
            }
            if let Some(m) = &sample.multipliers {
                check_multipliers(m, path, |i| match at() {
                    Some(a) => format!("{a}, contact node {i}"),
                    None => format!("contact node {i}"),
                })?;
            }
            check_clamped(&mesh, &sample, path, at())?;
            samples.push(sample);
        }
        if samples.iter().any(|s| s.reported_energy.is_some()) && self.energy_definition.is_none() {
            return Err(invalid(
                "energy_definition",
                None,
                "missing".into(),
                format!(
                    "the definition of the samples' energy: {}",
                    EnergyDefinition::NAMES
                ),
            ));
        }
        Ok(BoxExternalRun {
            file: SeriesFile {
                path: path.to_path_buf(),
                code: self.code,
                label: self.label,
                scheme,
                mass: self.mass,
                contact: self.contact,
            },
            level,
            mesh,
            time,
            energy_definition: self.energy_definition,
            value_epsilon: f64::EPSILON,
            source: Source::Json(samples),
        })
    }
}

/// What a box file may still hold while [`BoxScene::read_json`] reads it: numbers of the mesh,
/// `displacement`, `velocity` and `multipliers` (at most [`MAX_VALUES`] in all, a node's row of
/// fewer than two counted as two) and samples (one per step of the scene's finest study level and
/// one at `t = 0`). Each is counted before it is kept, so a file of more is refused having held at
/// most these: 2²⁴ numbers in rows of two, each row its own array, took 585 MiB, whatever the
/// file's size.
#[derive(Debug, Clone, Copy)]
struct Room {
    /// Numbers left.
    numbers: usize,
    /// Samples left.
    samples: usize,
    /// The samples allowed in all.
    max_samples: usize,
}

thread_local! {
    /// The [`Room`] of the box file being read on this thread; `None` outside
    /// [`Room::within`], where nothing is counted.
    static ROOM: Cell<Option<Room>> = const { Cell::new(None) };
}

impl Room {
    /// `read` with the room of a box file of at most `samples` samples.
    fn within<T>(samples: usize, read: impl FnOnce() -> T) -> T {
        /// Empties [`ROOM`] when the read ends, even by a panic.
        struct Leave;
        impl Drop for Leave {
            fn drop(&mut self) {
                ROOM.with(|room| room.set(None));
            }
        }
        ROOM.with(|room| {
            room.set(Some(Room {
                numbers: MAX_VALUES,
                samples,
                max_samples: samples,
            }))
        });
        let _leave = Leave;
        read()
    }

    /// Takes `numbers` numbers and `samples` samples from [`ROOM`], or says which limit they pass.
    fn take<E: de::Error>(numbers: usize, samples: usize) -> Result<(), E> {
        ROOM.with(|room| {
            let Some(mut left) = room.get() else {
                return Ok(());
            };
            if numbers > left.numbers {
                return Err(E::custom(format_args!(
                    "more than {MAX_VALUES} numbers (a node's row of fewer than two counted as \
                     two), the most a run file may hold"
                )));
            }
            if samples > left.samples {
                return Err(E::custom(format_args!(
                    "more than {} samples, one per step of the scene's finest study level and \
                     one at t = 0",
                    left.max_samples
                )));
            }
            left.numbers -= numbers;
            left.samples -= samples;
            room.set(Some(left));
            Ok(())
        })
    }
}

/// An array of numbers, each counted in the [`Room`] before it is kept.
struct Numbers<T>(Vec<T>);

impl<'de, T: Deserialize<'de>> Deserialize<'de> for Numbers<T> {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        /// [`Numbers`]' visitor.
        struct Each<T>(std::marker::PhantomData<T>);
        impl<'de, T: Deserialize<'de>> Visitor<'de> for Each<T> {
            type Value = Numbers<T>;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("an array of numbers")
            }
            fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Numbers<T>, A::Error> {
                let mut values = Vec::new();
                while let Some(value) = seq.next_element::<T>()? {
                    Room::take(1, 0)?;
                    values.push(value);
                }
                Ok(Numbers(values))
            }
        }
        deserializer.deserialize_seq(Each(std::marker::PhantomData))
    }
}

/// An array of [`Numbers`] (one per node), a row of fewer than two counted as two (its place).
struct Rows(Vec<Vec<f64>>);

impl<'de> Deserialize<'de> for Rows {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        /// [`Rows`]' visitor.
        struct Each;
        impl<'de> Visitor<'de> for Each {
            type Value = Rows;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("an array of arrays of numbers")
            }
            fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Rows, A::Error> {
                let mut rows = Vec::new();
                while let Some(Numbers(row)) = seq.next_element()? {
                    Room::take(2usize.saturating_sub(row.len()), 0)?;
                    rows.push(row);
                }
                Ok(Rows(rows))
            }
        }
        deserializer.deserialize_seq(Each)
    }
}

/// `displacement` or `velocity`, its numbers counted in the [`Room`].
fn bounded_rows<'de, D: Deserializer<'de>>(
    deserializer: D,
) -> Result<Option<Vec<Vec<f64>>>, D::Error> {
    Ok(Option::<Rows>::deserialize(deserializer)?.map(|rows| rows.0))
}

/// `multipliers`, counted in the [`Room`].
fn bounded_numbers<'de, D: Deserializer<'de>>(
    deserializer: D,
) -> Result<Option<Vec<f64>>, D::Error> {
    Ok(Option::<Numbers<f64>>::deserialize(deserializer)?.map(|numbers| numbers.0))
}

/// `mesh.lengths` or `mesh.elements`, counted in the [`Room`].
fn bounded_list<'de, D: Deserializer<'de>, T: Deserialize<'de>>(
    deserializer: D,
) -> Result<Vec<T>, D::Error> {
    Ok(Numbers::<T>::deserialize(deserializer)?.0)
}

/// `samples`, each counted in the [`Room`].
fn bounded_samples<'de, D: Deserializer<'de>>(
    deserializer: D,
) -> Result<Vec<BoxFileSample>, D::Error> {
    /// The samples' visitor.
    struct Each;
    impl<'de> Visitor<'de> for Each {
        type Value = Vec<BoxFileSample>;
        fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
            f.write_str("an array of samples")
        }
        fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Self::Value, A::Error> {
            let mut samples = Vec::new();
            while let Some(sample) = seq.next_element()? {
                Room::take(0, 1)?;
                samples.push(sample);
            }
            Ok(samples)
        }
    }
    deserializer.deserialize_seq(Each)
}
