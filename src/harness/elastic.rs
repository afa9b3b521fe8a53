//! Runs of the 2D/3D bars of the note (§3): a box of Q1 elements, its face `x_d = 0` on the
//! obstacle side, its face `x_d = L_d` held fixed, any scheme and mass variant, with the
//! energy (eq. 6), the contact history and VTK snapshots of displacement, velocity and von
//! Mises stress.
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

use crate::engine::contact::ContactLaw;
use crate::engine::error::SolveError;
use crate::engine::fem::box_mesh::{BoxMesh, Elasticity, VTK_HEXAHEDRON};
use crate::engine::fem::MassVariant;
use crate::engine::model::Model;
pub use crate::engine::problem::{box_mesh, initial_dofs, BoxProblem};
use crate::engine::schemes::{integrator, Scheme, TimeIntegrator};
use crate::harness::artifacts::write_atomic;
use crate::harness::error::Error;
use crate::harness::run::{time_grid, Timings};

/// One run of a box problem.
#[derive(Debug, Clone, PartialEq)]
pub struct BoxRunConfig {
    /// Elements along the axis; the cross-section gets `round(L_i / h)` elements.
    pub n_axis: usize,
    /// `Δx / Δt`.
    pub ratio: f64,
    /// The scheme.
    pub scheme: Scheme,
    /// The mass matrix.
    pub mass: MassVariant,
    /// Times of the VTK snapshots (the nearest steps).
    pub vtk_at: Vec<f64>,
    /// Where the VTK files go (required when `vtk_at` is not empty).
    pub vtk_dir: Option<PathBuf>,
}

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

/// What a box run measured.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct BoxRunResult {
    /// Elements per direction.
    pub elements: Vec<usize>,
    /// Unknowns.
    pub dofs: usize,
    /// Contact constraints.
    pub contact_nodes: usize,
    /// Steps.
    pub steps: usize,
    /// `Δt`.
    pub dt: f64,
    /// Wall-clock split (setup includes assembly, factorisation and the Delassus operator).
    pub timings: Timings,
    /// Steps that needed a complementarity solve.
    pub contact_solves: usize,
    /// Largest complementarity violation.
    pub complementarity_violation: f64,
    /// `(t, E_h)` per step, eq. (6).
    pub energy: Vec<(f64, f64)>,
    /// Contact history.
    pub contact: BoxContactHistory,
    /// VTK files written.
    pub vtk_files: Vec<PathBuf>,
    /// The contact treatment's name.
    pub contact_treatment: String,
}

/// Runs a box problem.
pub fn run_box(problem: &BoxProblem, config: &BoxRunConfig) -> Result<BoxRunResult, Error> {
    run_box_observed(problem, config, &mut |_, _, _| Ok(()))
}

/// What [`run_box_observed`] calls at every step `t_n`, `n = 0..=N`, with the mesh, the
/// integrator's state at `t_n` and its energy `E_h(t_n)` (eq. 6, already computed for the
/// history).
pub type StepObserver<'o> = dyn FnMut(&BoxMesh, &dyn TimeIntegrator, f64) -> Result<(), Error> + 'o;

/// Runs a box problem and calls `observer` at every step (after the built-in histories); its
/// time counts as observation.
pub fn run_box_observed(
    problem: &BoxProblem,
    config: &BoxRunConfig,
    observer: &mut StepObserver<'_>,
) -> Result<BoxRunResult, Error> {
    let clock = Instant::now();
    let mesh = box_mesh(problem, config.n_axis)?;
    let d = mesh.dim();
    problem.elasticity.validate(d)?;
    crate::engine::error::require_positive("ratio", config.ratio)?;
    crate::engine::error::require_positive("horizon", problem.horizon)?;
    let scheme = config.scheme.validate()?;
    let h = mesh.element_sizes()[d - 1];
    let (steps, dt) = time_grid(problem.horizon, h, config.ratio);
    mesh.check_mass(config.mass)?;
    let law = ContactLaw::boxed(problem.contact, &mesh, &problem.elasticity)?;
    let model = Model::of_box(
        &mesh,
        &problem.elasticity,
        config.mass,
        problem.obstacle_gap,
    )
    .with_contact_law(law);
    let (u0, v0) = initial_dofs(problem, &mesh);
    let mut integ = integrator(&model, scheme, dt, &u0, &v0)?;
    let setup = clock.elapsed().as_secs_f64();

    let contact_set = model.contact().cloned();
    let centre = contact_set.as_ref().and_then(|c| {
        let nodes = mesh.contact_nodes();
        let mid: Vec<f64> = problem.lengths[..d - 1].iter().map(|l| 0.5 * l).collect();
        (0..c.len()).min_by(|&a, &b| {
            let dist = |k: usize| {
                let x = mesh.nodes()[nodes[k]];
                mid.iter()
                    .enumerate()
                    .map(|(i, m)| (x[i] - m).powi(2))
                    .sum::<f64>()
            };
            dist(a).total_cmp(&dist(b))
        })
    });
    let mut result = BoxRunResult {
        elements: mesh.counts().to_vec(),
        dofs: model.n_dofs(),
        contact_nodes: contact_set.as_ref().map_or(0, |c| c.len()),
        steps,
        dt,
        timings: Timings::default(),
        contact_solves: 0,
        complementarity_violation: 0.0,
        energy: Vec::with_capacity(steps + 1),
        contact: BoxContactHistory::default(),
        vtk_files: Vec::new(),
        contact_treatment: problem.contact.name(),
    };
    let mut pending: Vec<f64> = config.vtk_at.clone();
    pending.sort_by(|a, b| b.total_cmp(a));
    let (mut stepping, mut observe) = (0.0, 0.0);
    for step in 0..=steps {
        if step > 0 {
            let c = Instant::now();
            integ.advance()?;
            if integ.displacement().iter().any(|x| !x.is_finite()) {
                return Err(SolveError::NonFinite {
                    step,
                    time: integ.time(),
                    quantity: "displacement",
                }
                .into());
            }
            stepping += c.elapsed().as_secs_f64();
        }
        let c = Instant::now();
        let t = integ.time();
        let energy = integ.energy().value;
        result.energy.push((t, energy));
        if let (Some(set), Some(centre)) = (&contact_set, centre) {
            let u = integ.displacement();
            let lambda = integ.multiplier().value;
            let gaps: Vec<f64> = set
                .dofs
                .iter()
                .zip(&set.gaps)
                .map(|(&dof, g)| u[dof] + g)
                .collect();
            result.contact.time.push(t);
            result
                .contact
                .mean_gap
                .push(gaps.iter().sum::<f64>() / gaps.len() as f64);
            result.contact.centre_gap.push(gaps[centre]);
            result.contact.total_force.push(lambda.iter().sum());
            result.contact.centre_multiplier.push(lambda[centre]);
        }
        while let Some(&wanted) = pending.last() {
            if t + 0.5 * dt < wanted {
                break;
            }
            pending.pop();
            let dir = config.vtk_dir.as_deref().unwrap_or(Path::new("."));
            let path = dir.join(format!("field-t{wanted}.vtu"));
            write_vtu(&mesh, &problem.elasticity, integ.as_ref(), &path)
                .map_err(|e| Error::Io(format!("cannot write {}: {e}", path.display())))?;
            result.vtk_files.push(path);
        }
        observer(&mesh, integ.as_ref(), energy)?;
        observe += c.elapsed().as_secs_f64();
    }
    result.contact_solves = integ.contact_solves();
    result.complementarity_violation = integ.complementarity_violation();
    result.timings = Timings {
        setup,
        stepping: stepping - integ.contact_seconds(),
        contact: integ.contact_seconds(),
        observe,
    };
    Ok(result)
}

/// Writes the displacement, the velocity and the von Mises stress (per cell, and averaged to
/// the nodes) of the current state as an XML unstructured grid (`.vtu`, ParaView).
pub fn write_vtu(
    mesh: &BoxMesh,
    elasticity: &Elasticity,
    state: &dyn TimeIntegrator,
    path: &Path,
) -> Result<(), Box<dyn std::error::Error>> {
    let flat = |v: Vec<[f64; 3]>| v.into_iter().flatten().collect::<Vec<f64>>();
    let points: Vec<f64> = mesh.nodes().iter().flatten().copied().collect();
    let connectivity: Vec<u64> = mesh.elements().flatten().map(|&n| n as u64).collect();
    let per = mesh.nodes_per_element() as u64;
    let offsets: Vec<u64> = (1..=mesh.n_elements() as u64).map(|k| k * per).collect();
    let cell_type = if mesh.vtk_cell_type() == VTK_HEXAHEDRON {
        CellType::Hexahedron
    } else {
        CellType::Quad
    };
    let von_mises = mesh.von_mises(state.displacement(), elasticity);
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
                ],
                cell: vec![Attribute::generic("von_mises", 1).with_data(von_mises)],
            },
        }),
    };
    let mut bytes = Vec::new();
    vtk.write_xml(&mut bytes)?;
    write_atomic(path, &bytes)?;
    Ok(())
}
