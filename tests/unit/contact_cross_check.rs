//! The two contact solvers agree: on a coarse 2D bar of the note (§3), the primal–dual active
//! set method and clarabel's interior-point QP give the same displacements and contact forces
//! at every step, and complementarity holds at every step.

use signorini::engine::contact::ClarabelContact;
use signorini::engine::fem::box_mesh::{BoxMesh, Elasticity};
use signorini::engine::fem::MassVariant;
use signorini::engine::model::Model;
use signorini::engine::schemes::conventions::NitscheAcceleration;
use signorini::engine::schemes::{
    initial_state, Conventions, OneStepScheme, StepCoefficients, TimeIntegrator,
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
            let mut pdas = OneStepScheme::new(
                &model,
                scheme,
                dt,
                start.clone(),
                NitscheAcceleration::Consistent,
            )
            .unwrap();
            let mut qp =
                OneStepScheme::new(&model, scheme, dt, start, NitscheAcceleration::Consistent)
                    .unwrap()
                    .with_contact_solver(Box::new(ClarabelContact::default()));
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
