//! Contact-stabilised Newmark (`engine::schemes::contact_stabilised_newmark`), both velocity
//! updates: without an obstacle it is Crank–Nicolson to round-off; its balance (CSN-E) holds at
//! every step with contact, in 1D and on boxes, and read with the other variant's velocity it
//! does not; the predictor-velocity variant never gains energy; a mass with massless dofs and a
//! penalty treatment are refused naming the field.

use crate::stepper::Stepper;
use signorini::engine::contact::{ContactLaw, ContactTreatment};
use signorini::engine::fem::box_mesh::BoxMesh;
use signorini::engine::fem::{Bar1d, EndCondition, MassVariant};
use signorini::engine::schemes::energy_balance::{self, BALANCE_TOLERANCE};
use signorini::engine::schemes::{integrator, Conventions, PredictorVelocity, Scheme};

use super::rival_schemes::{
    dirichlet, dt, falling_box, history, largest_difference, monitored, plain, snapshot_plain,
    steps, NX,
};

const CARRIED: Scheme = Scheme::ContactStabilisedNewmark {
    velocity: PredictorVelocity::Carried,
};
const PROJECTED: Scheme = Scheme::ContactStabilisedNewmark {
    velocity: PredictorVelocity::Projected,
};

/// The masses the method is defined with: no massless dof.
const DEFINITE: [MassVariant; 2] = [MassVariant::Standard, MassVariant::Lumped];

#[test]
fn without_contact_it_is_crank_nicolson() {
    for mass in DEFINITE {
        let (model, u0, v0) = dirichlet(mass, false);
        // Crank–Nicolson recovers `A^{n+1}` from `U^{n+1}` dividing by `¼Δt²`, the corrector
        // returns `V^{n+1}` multiplying by `2/Δt`: each step leaves up to `ε |U| / Δt` in `V`;
        // the bound is that, summed over the steps.
        let largest = u0.iter().chain(&v0).fold(0.0_f64, |m, x| m.max(x.abs()));
        let scale = steps() as f64 * f64::EPSILON * largest / dt();
        let newmark = history(&model, Scheme::CRANK_NICOLSON, &u0, &v0);
        for scheme in [CARRIED, PROJECTED] {
            let stabilised = history(&model, scheme, &u0, &v0);
            let worst = largest_difference(&newmark, &stabilised);
            assert!(
                worst <= scale,
                "{scheme}, {mass}: differs from Crank–Nicolson by {worst:e} (round-off {scale:e})"
            );
        }
    }
}

#[test]
fn its_balance_holds_every_step_in_1d_and_on_boxes() {
    for mass in DEFINITE {
        let (model, u0, v0) = dirichlet(mass, true);
        for scheme in [CARRIED, PROJECTED] {
            let worst = monitored(&model, scheme, &u0, &v0, dt(), steps());
            assert!(worst < 1e-13, "{scheme}, {mass}: residual {worst:e}");
        }
    }
    for mesh in [
        BoxMesh::note_2d(2, 16).unwrap(),
        BoxMesh::note_3d(2, 2, 8).unwrap(),
    ] {
        let d = mesh.dim();
        for mass in DEFINITE {
            let (model, u0, v0, dt) = falling_box(&mesh, mass);
            for scheme in [CARRIED, PROJECTED] {
                let worst = monitored(&model, scheme, &u0, &v0, dt, (1.5 / dt).round() as usize);
                assert!(worst < 1e-12, "{d}D {scheme}, {mass}: residual {worst:e}");
            }
        }
    }
}

/// Every step of the predictor-velocity variant loses energy or keeps it to round-off (of the
/// products its change sums, [`energy_balance::StepBalance::magnitude`]), and
/// (CSN-E) read with the carried velocity's terms leaves a residual far above the tolerance at
/// the steps whose predictor was projected: the two identities are the two schemes'.
#[test]
fn the_predictor_velocity_variant_never_gains_energy() {
    for mass in DEFINITE {
        let (model, u0, v0) = dirichlet(mass, true);
        let mut s = Stepper::harness(&model, PROJECTED, dt(), &u0, &v0);
        let e0 = s.energy().value;
        let (mut projected_steps, mut worst_as_carried, mut worst): (usize, f64, f64) =
            (0, 0.0, 0.0);
        for n in 0..steps() {
            let before = snapshot_plain(&s.observed());
            s.advance().unwrap();
            let after = snapshot_plain(&s.observed());
            let predictor = s.projected_predictor().unwrap().to_vec();
            let free = before.0.iter().zip(&before.1).map(|(u, v)| u + dt() * v);
            if predictor.iter().zip(free).any(|(p, f)| p != &f) {
                projected_steps += 1;
            }
            for (velocity, slot) in [
                (PredictorVelocity::Projected, &mut worst),
                (PredictorVelocity::Carried, &mut worst_as_carried),
            ] {
                let b = energy_balance::contact_stabilised_newmark(
                    &model,
                    velocity,
                    dt(),
                    (&plain(&before), &plain(&after)),
                    &predictor,
                );
                *slot = slot.max(b.residual().abs() / b.magnitude);
                if velocity == PredictorVelocity::Projected {
                    // `ΔE` in the difference form: subtracting the energies would leave the
                    // round-off of `½UᵀSU`, larger than a step's change.
                    let gain = b.change;
                    assert!(
                        gain <= 1e-14 * b.magnitude,
                        "{mass} step {n}: ΔE = {gain:e}"
                    );
                }
            }
        }
        assert!(
            projected_steps > 0,
            "{mass}: no step projected its predictor"
        );
        assert!(worst < 1e-14, "{mass}: (CSN-E) {worst:e}");
        assert!(
            worst_as_carried > BALANCE_TOLERANCE,
            "{mass}: the carried velocity's identity on this run: {worst_as_carried:e}"
        );
        assert!(
            s.energy().value < (1.0 - 1e-6) * e0,
            "{mass}: no energy lost"
        );
    }
}

#[test]
fn a_massless_dof_and_a_penalty_are_refused_naming_the_field() {
    let (model, u0, v0) = dirichlet(MassVariant::Redistributed, true);
    for scheme in [CARRIED, PROJECTED] {
        let e = integrator(&model, scheme, dt(), &u0, &v0, &Conventions::HARNESS)
            .err()
            .unwrap()
            .to_string();
        assert!(e.contains("mass") && e.contains("massless"), "{e}");
    }
    let bar = Bar1d::unit(NX, EndCondition::Clamped).unwrap();
    let (model, u0, v0) = dirichlet(MassVariant::Standard, true);
    let penalty = model.with_contact_law(
        ContactLaw::bar1d(ContactTreatment::Penalty { gamma0: 10.0 }, &bar).unwrap(),
    );
    let e = integrator(&penalty, CARRIED, dt(), &u0, &v0, &Conventions::HARNESS)
        .err()
        .unwrap()
        .to_string();
    assert!(
        e.contains("contact") && e.contains("contact-stabilised Newmark"),
        "{e}"
    );
}
