//! The settings a problem is solved with, apart from the problem: the engine validates them
//! when it discretises, a bar refuses a step solver it does not have, a round-off perturbation
//! moves only what its geometry's ensembles perturb, and a box reference's key tells settings
//! whose conventions differ apart without renaming the harness's own references.

use crate::benchmarks;
use signorini::engine::fem::MassVariant;
use signorini::engine::linalg::LinearSolver;
use signorini::engine::problem::{Perturbation, Problem, Settings};
use signorini::engine::schemes::{Conventions, Scheme};
use signorini::harness::reference::fine_mesh::cache::ReferenceKey;
use signorini::harness::study::scene::Scene;

#[test]
fn a_round_off_amplitude_that_is_not_finite_and_non_negative_is_refused_by_name() {
    let problem = benchmarks::dirichlet(3.0);
    for amplitude in [f64::NAN, -1e-13, f64::INFINITY] {
        let settings = Settings::default().with_round_off(Perturbation { amplitude, seed: 1 });
        let err = problem
            .discretise(10, MassVariant::Standard, &settings)
            .unwrap_err();
        assert_eq!(err.name, "round_off.amplitude", "{amplitude}");
    }
}

#[test]
fn a_bar_refuses_the_iterative_step_solver_and_takes_the_others() {
    let problem = benchmarks::dirichlet(3.0);
    let with = |linear_solver| Settings {
        linear_solver,
        ..Settings::default()
    };
    let err = problem
        .discretise(10, MassVariant::Standard, &with(LinearSolver::Cg))
        .unwrap_err();
    assert_eq!(err.name, "linear_solver");
    for solver in [LinearSolver::Direct, LinearSolver::Auto] {
        assert!(problem
            .discretise(10, MassVariant::Standard, &with(solver))
            .is_ok());
    }
}

#[test]
fn a_bars_round_off_moves_its_displacement_but_not_the_contact_dof() {
    let problem = benchmarks::dirichlet(3.0);
    let plain = problem
        .discretise(20, MassVariant::Standard, &Settings::default())
        .unwrap();
    let settings = Settings::default().with_round_off(Perturbation {
        amplitude: 1e-9,
        seed: 3,
    });
    let moved = problem
        .discretise(20, MassVariant::Standard, &settings)
        .unwrap();
    assert_eq!(plain.velocity, moved.velocity);
    let contact = &plain.model.contact().unwrap().dofs;
    for (i, (a, b)) in plain
        .displacement
        .iter()
        .zip(&moved.displacement)
        .enumerate()
    {
        if contact.contains(&i) {
            assert_eq!(a, b, "contact dof {i} moved");
        } else {
            assert!(a != b && (a - b).abs() <= 1e-9, "dof {i}: {a} → {b}");
        }
    }
}

#[test]
fn a_reference_key_names_conventions_only_when_they_are_not_the_harnesss() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/bar2d.json");
    let Problem::Box(problem) = Scene::load(&path).unwrap().problem() else {
        panic!("bar2d is a box scene")
    };
    let key = |conventions| {
        ReferenceKey::new(
            &problem,
            conventions,
            80,
            2.0,
            (Scheme::CRANK_NICOLSON, MassVariant::Redistributed),
            &[10, 20, 40],
            2,
        )
    };
    let harness = key(Conventions::HARNESS);
    let json = serde_json::to_string(&harness).unwrap();
    assert!(!json.contains("conventions"), "{json}");
    let other = key(Conventions::GETFEM_DEMO);
    assert_ne!(harness.stem(), other.stem());
    let differences = harness.differences(&other);
    assert_eq!(differences.len(), 1, "{differences:?}");
    assert!(
        differences[0].starts_with("conventions: cached {"),
        "{differences:?}"
    );
}
