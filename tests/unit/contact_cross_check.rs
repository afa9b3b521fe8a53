//! The two contact solvers agree: on a coarse 2D bar of the note (§3), the primal–dual active
//! set method and clarabel's interior-point QP give the same displacements and contact forces
//! at every step, and complementarity holds at every step.

use crate::stepper::Stepper;
use signorini::engine::contact::{ClarabelContact, ContactSolver};
use signorini::engine::fem::box_mesh::{BoxMesh, Elasticity};
use signorini::engine::fem::MassVariant;
use signorini::engine::model::Model;
use signorini::engine::schemes::conventions::NitscheAcceleration;
use signorini::engine::schemes::{
    initial_state, Conventions, OneStepScheme, SchemeState, StepCoefficients,
};

fn setup(mesh: &BoxMesh, mass: MassVariant) -> (Model, Vec<f64>, Vec<f64>) {
    let model = signorini::engine::model::Model::of_box(mesh, &Elasticity::NOTE, mass, Some(0.2));
    let u0 = vec![0.0; model.n_dofs()];
    let d = mesh.dim();
    let v0 = mesh.interpolate(|_| {
        let mut v = [0.0; 3];
        v[d - 1] = -0.5;
        v
    });
    (model, u0, v0)
}

fn max_diff(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

#[test]
fn active_set_and_clarabel_agree_at_every_step() {
    for (mesh, scheme) in [
        (
            BoxMesh::note_2d(2, 20).unwrap(),
            StepCoefficients::newmark(0.25, 0.5),
        ),
        (
            BoxMesh::note_2d(4, 20).unwrap(),
            StepCoefficients::theta(1.0),
        ),
        (
            BoxMesh::note_3d(2, 2, 10).unwrap(),
            StepCoefficients::newmark(0.25, 0.5),
        ),
    ] {
        for mass in MassVariant::ON_EVERY_MESH {
            let (model, u0, v0) = setup(&mesh, mass);
            let h = mesh.element_sizes()[mesh.dim() - 1];
            let dt = h / 2.0;
            let start = initial_state(&model, &u0, &v0, &Conventions::HARNESS).unwrap();
            let mut pdas = Stepper::new(
                OneStepScheme::new(&model, scheme, dt, NitscheAcceleration::Consistent).unwrap(),
                SchemeState::start(dt, start.clone()),
            );
            let mut qp = Stepper::new(
                OneStepScheme::new(&model, scheme, dt, NitscheAcceleration::Consistent)
                    .unwrap()
                    .with_contact_solver(Box::new(ClarabelContact::default())),
                SchemeState::start(dt, start),
            );
            let contact = model.contact().unwrap();
            let mut steps_in_contact = 0;
            for step in 0..((1.0 / dt).round() as usize) {
                pdas.advance().unwrap();
                qp.advance().unwrap();
                let du = max_diff(pdas.displacement(), qp.displacement());
                let dl = max_diff(pdas.multiplier().value, qp.multiplier().value);
                assert!(
                    du <= 1e-8,
                    "{mass} step {step}: displacements differ by {du:e}"
                );
                assert!(dl <= 1e-8, "{mass} step {step}: forces differ by {dl:e}");
                for (i, &dof) in contact.dofs.iter().enumerate() {
                    let gap = pdas.displacement()[dof] + contact.gaps[i];
                    let lambda = pdas.multiplier().value[i];
                    assert!(gap >= -1e-10, "{mass} step {step}: penetration {gap:e}");
                    assert!(lambda <= 1e-10, "{mass} step {step}: tension {lambda:e}");
                    assert!((gap * lambda).abs() <= 1e-10, "{mass} step {step}");
                }
                if pdas.multiplier().value.iter().any(|&l| l < 0.0) {
                    steps_in_contact += 1;
                }
            }
            assert!(
                steps_in_contact >= 3,
                "{mass}: only {steps_in_contact} steps in contact"
            );
        }
    }
}

/// `0 ≤ μ ⟂ g + W μ ≥ 0` to `tol`.
fn assert_solves(w: &[f64], g: &[f64], mu: &[f64], tol: f64) {
    let n = g.len();
    for i in 0..n {
        let r = g[i] + (0..n).map(|j| w[i * n + j] * mu[j]).sum::<f64>();
        assert!(mu[i] >= 0.0 && r >= -tol, "{i}: μ {mu:?}, residual {r:e}");
        assert!((mu[i] * r).abs() <= tol, "{i}: μ {mu:?}, residual {r:e}");
    }
}

/// The primal–dual active set method is guaranteed to end for M-matrices only. Two SPD
/// matrices, found by a search over random ones, on which its sets cycle from the start
/// `A = {i : g_i < 0}`: a degenerate problem (`μ_0 = 0` and `(g + W μ)_0 = 0` at the solution),
/// whose sets cycle among ones of the same solution, kept as it is; and a non-degenerate one,
/// whose cycle is left for the interior-point solution's active set. Both end solved, where
/// the plain iteration reached its limit: the first at its exact solution (0, 4/3, 14/5), which
/// clarabel's interior point, slowed by the degeneracy, reaches only to about 1e-6; the second
/// at clarabel's solution to 1e-8.
#[test]
fn a_cycling_active_set_still_ends_at_the_solution() {
    use signorini::engine::contact::{ContactStatus, PrimalDualActiveSet};
    let degenerate = (
        vec![5.0, -3.0, 1.25, -3.0, 6.75, -3.75, 1.25, -3.75, 2.5],
        vec![0.5, 1.5, -2.0],
    );
    let cycling = (
        vec![
            9.041691411557336,
            6.377864243962259,
            -7.8199107369029575,
            4.962959183298697,
            6.377864243962259,
            9.898636530797964,
            -3.0672795975751153,
            -0.2021041204408216,
            -7.8199107369029575,
            -3.0672795975751153,
            8.824377944878892,
            -6.433995841884679,
            4.962959183298697,
            -0.2021041204408216,
            -6.433995841884679,
            11.798258249057968,
        ],
        vec![
            1.539714903978496,
            0.3018300946636088,
            -1.4457577961543797,
            -1.4387704709348368,
        ],
    );
    let solved = |(w, g): &(Vec<f64>, Vec<f64>)| {
        let mut mu = vec![0.0; g.len()];
        let status = PrimalDualActiveSet::default().solve(w, g, &mut mu);
        assert!(matches!(status, ContactStatus::Solved { .. }), "{status:?}");
        assert_solves(w, g, &mu, 1e-12);
        mu
    };
    let mu = solved(&degenerate);
    assert!(max_diff(&mu, &[0.0, 4.0 / 3.0, 2.8]) <= 1e-12, "{mu:?}");
    let mu = solved(&cycling);
    let mut interior = vec![0.0; mu.len()];
    ClarabelContact::default().solve(&cycling.0, &cycling.1, &mut interior);
    assert!(max_diff(&mu, &interior) <= 1e-8, "{mu:?} {interior:?}");
}
