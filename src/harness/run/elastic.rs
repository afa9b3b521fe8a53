//! Runs of the 2D/3D bars of the note (§3): a box of Q1 elements, its face `x_d = 0` on the
//! obstacle side, its face `x_d = L_d` held fixed, any scheme and mass variant, with the
//! energy (eq. 6), the contact history and VTK snapshots of displacement, velocity and von
//! Mises stress, with the obstacle and their collection for ParaView ([`paraview`]).
//!
//! Reading of the note's set-up (it writes `u(x₁, 1, t) = 0.2` for an undeformed bar 0.2
//! above the obstacle): displacements are measured from the initial configuration, the top
//! face does not move (`u = 0` there, eq. 3a), and the obstacle is 0.2 below the bottom face
//! (the constraint `u_d + 0.2 ≥ 0`). The whole bar starts with the vertical velocity −0.5
//! except the top face, whose dofs are eliminated.

use std::path::{Path, PathBuf};
use std::time::Instant;

use serde::{Deserialize, Serialize};
use vtkio::model::{
    Attribute, Attributes, ByteOrder, CellType, Cells, DataSet, IOBuffer, UnstructuredGridPiece,
    Version, VertexNumbers, Vtk,
};

use crate::engine::contact::{ContactSet, Truncation};
use crate::engine::error::StateField;
pub use crate::engine::fem::box_mesh::BoxMesh;
use crate::engine::fem::box_mesh::{Elasticity, VTK_HEXAHEDRON};
use crate::engine::linalg::SolveCounts;
pub use crate::engine::problem::{box_mesh, initial_dofs, BoxProblem};
use crate::engine::schemes::Integration;
use crate::harness::files::artifacts::write_atomic;
use crate::harness::files::error::Error;
use crate::harness::run::{
    drive_with, finite, paraview, snapshot_name, IntegratorFactory, Observer, RunConfig, RunResult,
    SnapshotTimes,
};

/// The contact history of a box run.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct BoxContactHistory {
    /// `t_n`.
    pub time: Vec<f64>,
    /// Mean normal displacement of the contact face plus the gap (its distance to the obstacle).
    pub mean_gap: Vec<f64>,
    /// The normal displacement plus gap of the contact node nearest the face's centre.
    pub centre_gap: Vec<f64>,
    /// Total normal contact force `Σ λ_i` (≤ 0).
    pub total_force: Vec<f64>,
    /// The multiplier of the centre node.
    pub centre_multiplier: Vec<f64>,
}

/// What a box run observes: its mesh, its step solver, its energy, its contact face and the
/// VTK files it wrote.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct BoxObservations {
    /// Elements per direction.
    pub elements: Vec<usize>,
    /// Contact constraints.
    pub contact_nodes: usize,
    /// The step solver used (`direct` or `cg`, [`crate::engine::linalg::LinearSolver`]).
    pub linear_solver: String,
    /// Why the step solver and the contact operator were chosen: the reason of the model's
    /// solver plan ([`crate::engine::solver_plan::SolverPlan`]), for the run's summary; not
    /// written (`run.json` records the choice, [`BoxObservations::linear_solver`]).
    #[serde(skip)]
    pub solver_plan: String,
    /// Its per-step solves and their CG iterations (0 for `direct`).
    pub step_solves: SolveCounts,
    /// The slab of the local contact operator (`L`, truncation ratio, size); absent with the
    /// full operator.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub contact_slab: Option<Truncation>,
    /// `(t, E_h)` per step, eq. (6).
    pub energy: Vec<(f64, f64)>,
    /// Contact history.
    pub contact: BoxContactHistory,
    /// VTK files written: the snapshots in increasing time, then, when there are any, the
    /// obstacle (`obstacle.vtu`, with an obstacle) and their collection (`fields.pvd`).
    pub vtk_files: Vec<PathBuf>,
}

/// The energy `E_h(t_n)` (note eq. 6) at every step.
#[derive(Default)]
struct EnergyTrace {
    energy: Vec<(f64, f64)>,
}

impl Observer for EnergyTrace {
    fn observe(&mut self, state: &Integration<'_>) -> Result<(), Error> {
        let energy = finite(state, StateField::Energy, state.energy().value)?;
        self.energy.push((state.time(), energy));
        Ok(())
    }
}

/// The contact face's gaps and forces at every step.
struct FaceRecorder {
    set: ContactSet,
    /// `B u + g` of the current state (scratch).
    gaps: Vec<f64>,
    centre: usize,
    history: BoxContactHistory,
}

impl FaceRecorder {
    /// The recorder of `set` on `mesh`, `centre` the constraint of the node nearest the
    /// face's centre; `None` without an obstacle.
    fn new(mesh: &BoxMesh, set: Option<&ContactSet>) -> Option<Self> {
        let set = set?.clone();
        let centre = mesh.face_centre();
        Some(Self {
            gaps: vec![0.0; set.len()],
            set,
            centre,
            history: BoxContactHistory::default(),
        })
    }
}

impl Observer for FaceRecorder {
    fn observe(&mut self, state: &Integration<'_>) -> Result<(), Error> {
        let lambda = state.multiplier().value;
        let gaps = &mut self.gaps;
        self.set.gaps_of(state.displacement(), gaps);
        let h = &mut self.history;
        h.time.push(state.time());
        let mean_gap = gaps.iter().sum::<f64>() / gaps.len() as f64;
        h.mean_gap
            .push(finite(state, StateField::Displacement, mean_gap)?);
        h.centre_gap.push(gaps[self.centre]);
        h.total_force
            .push(finite(state, StateField::Multiplier, lambda.iter().sum())?);
        h.centre_multiplier.push(lambda[self.centre]);
        Ok(())
    }
}

/// VTK snapshots ([`write_vtu`]) at the steps nearest to requested times.
struct VtkSnapshots<'a> {
    mesh: &'a BoxMesh,
    elasticity: &'a Elasticity,
    dir: &'a Path,
    pending: SnapshotTimes,
    /// The run's horizon, whose width the snapshots' names pad their times to.
    horizon: f64,
    /// The snapshots written in `dir`, each with its requested time, in increasing time.
    written: Vec<paraview::Snapshot>,
}

impl Observer for VtkSnapshots<'_> {
    fn observe(&mut self, state: &Integration<'_>) -> Result<(), Error> {
        while let Some(wanted) = self.pending.next_due(state) {
            let file = snapshot_name("field", wanted, (state.dt(), self.horizon), "vtu");
            if self.written.last().is_some_and(|last| last.file == file) {
                continue;
            }
            write_vtu(self.mesh, self.elasticity, state, &self.dir.join(&file))?;
            self.written.push(paraview::Snapshot { time: wanted, file });
        }
        Ok(())
    }
}

impl VtkSnapshots<'_> {
    /// The files of a completed run: the snapshots and, when there are any, the obstacle
    /// `obstacle_gap` below the box (when there is one) and the collection `fields.pvd` of them
    /// all ([`paraview`]), written beside them.
    fn finish(self, obstacle_gap: Option<f64>) -> Result<Vec<PathBuf>, Error> {
        let mut files: Vec<PathBuf> = self
            .written
            .iter()
            .map(|s| self.dir.join(&s.file))
            .collect();
        if files.is_empty() {
            return Ok(files);
        }
        let obstacle = match obstacle_gap {
            Some(gap) => paraview::write_obstacle(self.dir, self.mesh.lengths(), gap)?,
            None => None,
        };
        let obstacle_file = obstacle.as_ref().map(|_| paraview::OBSTACLE_FILE);
        let collection = paraview::write_collection(self.dir, &self.written, obstacle_file)?;
        files.extend(obstacle);
        files.push(collection);
        Ok(files)
    }

    /// Removes the snapshots of a run that did not complete: they are no result.
    fn discard(self) -> Result<(), Error> {
        for s in &self.written {
            let f = self.dir.join(&s.file);
            std::fs::remove_file(&f).map_err(Error::write(&f))?;
        }
        Ok(())
    }
}

/// Runs a box problem through the one time loop ([`super::drive`]) with the built-in observers (the
/// energy, the contact face's history and, when `config.observables.fields_at` asks, VTK snapshots
/// in `config.observables.fields_dir`) followed by the caller's `extra`; their time counts as
/// observation. A completed run with snapshots adds the obstacle and the collection of ParaView
/// ([`VtkSnapshots::finish`]); a run that does not complete removes the VTK snapshots it wrote:
/// they are no result. The integrator is the one-process scheme's, or the one `make` builds
/// (a distributed run's, [`crate::harness::run::distributed`]).
pub fn run_box<'r>(
    problem: &BoxProblem,
    (config, make): (&RunConfig, Option<&IntegratorFactory<'r>>),
    extra: &mut [&mut dyn Observer],
) -> Result<RunResult<BoxObservations>, Error> {
    let clock = Instant::now();
    let discretisation = problem.discretise(config.nx, config.mass, &config.settings)?;
    let mesh = &discretisation.mesh;
    let model = &discretisation.model;
    let mut energy = EnergyTrace::default();
    let mut face = FaceRecorder::new(mesh, model.contact());
    let mut vtk = VtkSnapshots {
        mesh,
        elasticity: &problem.elasticity,
        dir: config
            .observables
            .fields_dir
            .as_deref()
            .unwrap_or(Path::new(".")),
        pending: SnapshotTimes::new(&config.observables.fields_at),
        horizon: problem.horizon,
        written: Vec::new(),
    };
    let mut own: Vec<&mut dyn Observer> = vec![&mut energy];
    own.extend(face.as_mut().map(|o| o as &mut dyn Observer));
    own.push(&mut vtk);
    let stepped = drive_with(
        &discretisation,
        problem.horizon,
        (config, make),
        own,
        extra,
        clock,
    )?;
    let vtk_files = if stepped.status.is_completed() {
        vtk.finish(problem.obstacle_gap)?
    } else {
        vtk.discard()?;
        Vec::new()
    };
    let observed = BoxObservations {
        elements: mesh.counts().to_vec(),
        contact_nodes: model.contact().map_or(0, |c| c.len()),
        linear_solver: model.solver_plan().step.name().to_string(),
        solver_plan: model.solver_plan().reason.clone(),
        step_solves: stepped.step_solves,
        contact_slab: stepped.contact_truncation,
        energy: energy.energy,
        contact: face.map(|f| f.history).unwrap_or_default(),
        vtk_files,
    };
    let balance = stepped.max_balance_residual;
    Ok(RunResult::of(
        &stepped,
        model.n_dofs(),
        problem.contact.name(),
        balance,
        observed,
    ))
}

/// The point array of a snapshot that holds the contact multipliers.
pub const CONTACT_MULTIPLIER: &str = "contact_multiplier";

/// The contact multipliers `λ` (one per node of `Γ_Sig`, in [`BoxMesh::contact_nodes`]'
/// order) as a nodal array: `λ_i` at contact node `i`, 0 elsewhere and without an obstacle.
fn nodal_multipliers(mesh: &BoxMesh, lambda: &[f64]) -> Vec<f64> {
    let mut nodal = vec![0.0; mesh.n_nodes()];
    for (&node, &l) in mesh.contact_nodes().iter().zip(lambda) {
        nodal[node] = l;
    }
    nodal
}

/// Writes the displacement, the velocity, the contact multipliers and the von Mises stress (per cell, and averaged to
/// the nodes) of the current state as an XML unstructured grid (`.vtu`, ParaView).
pub fn write_vtu(
    mesh: &BoxMesh,
    elasticity: &Elasticity,
    state: &Integration<'_>,
    path: &Path,
) -> Result<(), Error> {
    let flat = |v: Vec<[f64; 3]>| v.into_iter().flatten().collect::<Vec<f64>>();
    let points: Vec<f64> = mesh.nodes().flatten().collect();
    let connectivity: Vec<u64> = mesh.elements().flatten().map(|n| n as u64).collect();
    let per = mesh.nodes_per_element() as u64;
    let offsets: Vec<u64> = (1..=mesh.n_elements() as u64).map(|k| k * per).collect();
    let cell_type = if mesh.vtk_cell_type() == VTK_HEXAHEDRON {
        CellType::Hexahedron
    } else {
        CellType::Quad
    };
    let von_mises = mesh.von_mises(state.displacement(), elasticity);
    if let Some(&bad) = von_mises.iter().find(|v| !v.is_finite()) {
        finite(state, StateField::VonMises, bad)?;
    }
    let vtk = Vtk {
        version: Version::new(),
        title: format!("signorini t = {}", state.time()),
        byte_order: ByteOrder::LittleEndian,
        file_path: None,
        data: DataSet::inline(UnstructuredGridPiece {
            points: IOBuffer::F64(points),
            cells: Cells {
                cell_verts: VertexNumbers::XML {
                    connectivity,
                    offsets,
                },
                types: vec![cell_type; mesh.n_elements()],
            },
            data: Attributes {
                point: vec![
                    Attribute::generic("displacement", 3)
                        .with_data(flat(mesh.nodal_vector(state.displacement()))),
                    Attribute::generic("velocity", 3)
                        .with_data(flat(mesh.nodal_vector(state.velocity()))),
                    Attribute::generic("von_mises", 1).with_data(mesh.nodal_average(&von_mises)),
                    Attribute::generic(CONTACT_MULTIPLIER, 1)
                        .with_data(nodal_multipliers(mesh, state.multiplier().value)),
                ],
                cell: vec![Attribute::generic("von_mises", 1).with_data(von_mises)],
            },
        }),
    };
    let mut bytes = Vec::new();
    vtk.write_xml(&mut bytes).map_err(|source| Error::Vtk {
        path: path.to_path_buf(),
        source,
    })?;
    write_atomic(path, &bytes)?;
    Ok(())
}
