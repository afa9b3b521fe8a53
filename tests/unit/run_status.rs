//! A run that goes non-finite ends with a status, the way a solver reports one: it stops at the
//! first non-finite value and reports no number.

use crate::benchmarks;
use signorini::engine::fem::MassVariant;
use signorini::engine::schemes::Scheme;
use signorini::harness::run::norms::Norm;
use signorini::harness::run::{run, Observables, RunConfig, RunStatus};

/// Newmark with β = 0.01, γ = ½ is only conditionally stable (`ω Δt < 1/√(γ/2 − β)`): at
/// `Δx/Δt = 0.5` the highest mode of a 400-element bar has `ω Δt ≈ 4` and overflows.
fn unstable() -> RunConfig {
    RunConfig {
        nx: 400,
        ratio: 0.5,
        scheme: Scheme::Newmark {
            beta: 0.01,
            gamma: 0.5,
        },
        mass: MassVariant::Standard,
        observables: Observables {
            norms: Norm::ALL
                .into_iter()
                .filter(|&n| n != Norm::MultiplierL2)
                .collect(),
            energy_history: true,
            ..Observables::default()
        },
        settings: Default::default(),
    }
}

#[test]
fn a_diverging_run_stops_with_its_status_and_no_norms() {
    let r =
        run(&benchmarks::free_vibration(2.0), &unstable(), &mut []).expect("the setup is valid");
    let RunStatus::Diverged { step, time, .. } = r.status.clone() else {
        panic!("expected a diverged run, got {:?}", r.status);
    };
    assert!(
        step > 1 && step < r.steps,
        "stopped at step {step} of {}",
        r.steps
    );
    assert!((time - step as f64 * r.dt).abs() < 1e-12);
    assert!(
        r.observed.errors.is_empty(),
        "a diverged run reported {:?}",
        r.observed.errors
    );
    assert!(r.observed.multiplier_variation.is_none());
    let energy = r.observed.energy_history.as_ref().expect("requested");
    assert!(energy.time.last().is_some_and(|&t| t < time));
    assert!(r.completed().is_err());
}

#[test]
fn a_completed_run_says_so() {
    let config = RunConfig {
        scheme: Scheme::CRANK_NICOLSON,
        ratio: 1.0,
        ..unstable()
    };
    let r = run(&benchmarks::free_vibration(0.5), &config, &mut []).unwrap();
    assert_eq!(r.status, RunStatus::Completed);
    assert_eq!(r.observed.errors.len(), 6);
    assert!(r.completed().is_ok());
}
