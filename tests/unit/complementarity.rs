//! The complementarity conditions (32d), (34d) and (36) hold at every step of every scheme of
//! Tables 1–2, with both mass matrices, on the Signorini–Dirichlet benchmark (§5.2 setting), and
//! the redistributed mass keeps the contact node in contact through the exact contact phase.

use crate::stepper::Stepper;
use signorini::engine::exact::{ExactSolution, SignoriniDirichlet};
use signorini::engine::fem::{Bar1d, EndCondition, MassVariant};
use signorini::engine::model::Model;
use signorini::engine::schemes::{initial_state, Conventions, PaoliSchatzman, Scheme, SchemeState};
use signorini::harness::run::time_grid;

const COMPLEMENTARITY_TOL: f64 = 1e-12;

fn dirichlet_setup(nx: usize, mass: MassVariant) -> (Bar1d, Model, Vec<f64>, Vec<f64>) {
    let bar = Bar1d::unit(nx, EndCondition::Clamped).unwrap();
    let model = Model::bar1d(&bar, mass, Some(0.0), None);
    let exact = SignoriniDirichlet;
    let u0 = bar.interpolate(|x| exact.eval(x, 0.0).u);
    let v0 = bar.interpolate(|x| exact.eval(x, 0.0).ut);
    (bar, model, u0, v0)
}

fn check_complementarity(what: &str, step: usize, gap: f64, lambda: f64) {
    assert!(
        gap >= -COMPLEMENTARITY_TOL,
        "{what} step {step}: gap {gap:e} < 0"
    );
    assert!(
        lambda <= COMPLEMENTARITY_TOL,
        "{what} step {step}: λ = {lambda:e} > 0"
    );
    assert!(
        (gap * lambda).abs() <= COMPLEMENTARITY_TOL,
        "{what} step {step}: gap·λ = {:e}",
        gap * lambda
    );
}

/// Eqs. (32d) and (34d): `0 ≤ u_0^{n+1} ⟂ λ^{n+1} ≤ 0` at every step; eq. (36):
/// `0 ≤ (u_0^{n+1} + e u_0^{n−1})/(1 + e) ⟂ λ^n ≤ 0` (the start step is one Newmark(β, ½)
/// step, constrained at `t_1`). Every scheme of Tables 1–2, both mass matrices, §5.2 setting.
#[test]
fn complementarity_holds_at_every_step() {
    const NX: usize = 40;
    const RATIO: f64 = 10.0;
    const HORIZON: f64 = 3.0;
    for scheme in Scheme::paper_schemes() {
        for mass in MassVariant::ALL {
            let (bar, model, u0, v0) = dirichlet_setup(NX, mass);
            let (steps, dt) = time_grid(HORIZON, bar.h(), RATIO);
            assert_eq!(steps, 1200);
            let what = format!("{scheme} {mass}");
            let mut contact_steps = 0;
            match scheme {
                Scheme::PaoliSchatzman { beta, restitution } => {
                    let start = initial_state(&model, &u0, &v0, &Conventions::HARNESS).unwrap();
                    let method = PaoliSchatzman::new(
                        &model,
                        (beta, restitution),
                        dt,
                        &start.multiplier,
                        &Conventions::HARNESS,
                    )
                    .unwrap();
                    let mut s = Stepper::new(method, SchemeState::start(dt, start));
                    for step in 1..=steps {
                        let u_older = s.previous_displacement().map(|u| u[0]);
                        let u_old = s.displacement()[0];
                        s.advance().unwrap();
                        assert_eq!(s.previous_displacement().map(|u| u[0]), Some(u_old));
                        let u_new = s.displacement()[0];
                        let constrained = match u_older {
                            None => u_new,
                            Some(u_older) => (u_new + restitution * u_older) / (1.0 + restitution),
                        };
                        let lambda = s.scheme_multiplier()[0];
                        check_complementarity(&what, step, constrained, lambda);
                        if lambda < 0.0 {
                            contact_steps += 1;
                        }
                    }
                }
                _ => {
                    let mut s = Stepper::harness(&model, scheme, dt, &u0, &v0);
                    for step in 1..=steps {
                        s.advance().unwrap();
                        assert_eq!(s.step_index(), step);
                        let gap = s.displacement()[0];
                        let lambda = s.multiplier().value[0];
                        check_complementarity(&what, step, gap, lambda);
                        if lambda < 0.0 {
                            contact_steps += 1;
                        }
                    }
                }
            }
            assert!(
                contact_steps > 0,
                "{what}: the run never touches the obstacle"
            );
            if mass == MassVariant::Redistributed {
                // With M^mod the contact node does not chatter (§4.2, §5.2): it stays in
                // contact through nearly all of the exact contact phase t ∈ (1, 2), ~400 steps.
                let exact_phase_steps = (1.0 / dt).round() as usize;
                assert!(
                    contact_steps >= exact_phase_steps * 9 / 10,
                    "{what}: only {contact_steps} contact steps, exact phase {exact_phase_steps}"
                );
            }
        }
    }
}
