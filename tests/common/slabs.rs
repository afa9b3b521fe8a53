//! What the tests of the distributed engine share (`tests/unit/distributed.rs`, with threads
//! as ranks, and `tests/mpi.rs`, under `mpirun`): the step matrix they solve and the measure
//! of agreement they hold the ranks' results to.

use signorini::engine::fem::{BoxMesh, Elasticity, MassVariant, SymmetricMatrix};
use signorini::engine::linalg::LinearSolver;
use signorini::engine::problem::{BoxProblem, Discretisation, Settings};
use signorini::engine::schemes::{initial_state, InitialState};

/// Crank–Nicolson's step matrix `M/(bΔt²) + S`, `b = ¼`, at `Δx/Δt = 2`, matrix-free.
pub fn step_matrix(mesh: &BoxMesh, variant: MassVariant) -> SymmetricMatrix {
    let h = 1.0 / mesh.counts()[mesh.dim() - 1] as f64;
    let alpha = 1.0 / (0.25 * (h / 2.0) * (h / 2.0));
    mesh.mass_stencil(variant, 1.0).unwrap().linear_combination(
        alpha,
        &mesh.stiffness_stencil(&Elasticity::NOTE),
        1.0,
    )
}

/// `problem` on 40 elements along the axis with the redistributed mass, its steps solved by
/// CG (as a distributed run solves them).
pub fn level_40(problem: &BoxProblem) -> Discretisation<BoxMesh> {
    let settings = Settings {
        linear_solver: LinearSolver::Cg,
        ..Settings::default()
    };
    problem
        .discretise(40, MassVariant::Redistributed, &settings)
        .unwrap()
}

/// The whole initial state of `discretisation` (the one-process start).
pub fn start_of(discretisation: &Discretisation<BoxMesh>) -> InitialState {
    initial_state(
        &discretisation.model,
        &discretisation.displacement,
        &discretisation.velocity,
        &discretisation.conventions,
    )
    .unwrap()
}

/// The largest `|a_i − b_i|` over the largest `|b_i|` (the largest `|a_i − b_i|` for a zero
/// `b`).
pub fn relative(a: &[f64], b: &[f64]) -> f64 {
    assert_eq!(a.len(), b.len());
    let scale = b.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
    let worst = a
        .iter()
        .zip(b)
        .map(|(p, q)| (p - q).abs())
        .fold(0.0, f64::max);
    if scale > 0.0 {
        worst / scale
    } else {
        worst
    }
}
