//! The per-step round-off perturbation of an ensemble member (`Settings::step_round_off`,
//! applied by the run loop after every step): the same seed gives the same bits, `ε = 0` gives
//! the bits of the run without it, and another seed gives another run, on a bar (a one-step
//! scheme and Paoli–Schatzman) and on a box.

use std::path::Path;

use crate::benchmarks;
use signorini::engine::fem::MassVariant;
use signorini::engine::problem::{Problem, Settings, StepPerturbation, UNIT_ROUNDOFF};
use signorini::engine::schemes::Scheme;
use signorini::harness::run::elastic::BoxProblem;
use signorini::harness::run::{run, Observables, RunConfig};
use signorini::harness::study::scene::Scene;

/// The bits of the contact node's displacement and of every error norm of a bar run of
/// `scheme` at NX = 20 (Δx/Δt = 10, the redistributed mass) with `settings`.
fn bar_bits(scheme: Scheme, settings: Settings) -> Vec<u64> {
    let config = RunConfig {
        nx: 20,
        ratio: 10.0,
        scheme,
        mass: MassVariant::Redistributed,
        observables: Observables {
            contact_history: true,
            ..Observables::all_norms()
        },
        settings,
    };
    let r = run(&benchmarks::dirichlet(3.0), &config, &mut [])
        .unwrap()
        .completed()
        .unwrap();
    let history = r.observed.contact_history.unwrap();
    let errors = r.observed.errors.values().copied();
    history
        .displacement
        .into_iter()
        .chain(errors)
        .map(f64::to_bits)
        .collect()
}

/// The bits of the centre contact node's gap of a run of `scenes/bar2d.json` at level 10
/// (Crank–Nicolson) with `settings`.
fn box_bits(settings: Settings) -> Vec<u64> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/bar2d.json");
    let Problem::Box(problem): Problem = Scene::load(&path).unwrap().problem() else {
        panic!("bar2d is a box scene")
    };
    let problem = BoxProblem {
        horizon: 1.0,
        ..problem
    };
    let config = RunConfig {
        nx: 10,
        ratio: 2.0,
        scheme: Scheme::CRANK_NICOLSON,
        mass: MassVariant::Standard,
        observables: Observables::default(),
        settings,
    };
    let r = run(&problem, &config, &mut [])
        .unwrap()
        .completed()
        .unwrap();
    r.observed
        .contact
        .centre_gap
        .into_iter()
        .map(f64::to_bits)
        .collect()
}

fn every_step(epsilon: f64, seed: u64) -> Settings {
    Settings::default().with_step_round_off(StepPerturbation { epsilon, seed })
}

fn schemes() -> [Scheme; 3] {
    let paoli_schatzman = "paoli-schatzman-e0".parse().unwrap();
    [
        Scheme::CRANK_NICOLSON,
        paoli_schatzman,
        Scheme::CENTRAL_DIFFERENCE,
    ]
}

#[test]
fn the_same_seed_gives_the_same_bits_and_another_seed_another_run() {
    for scheme in schemes() {
        let first = bar_bits(scheme, every_step(UNIT_ROUNDOFF, 3));
        assert_eq!(
            first,
            bar_bits(scheme, every_step(UNIT_ROUNDOFF, 3)),
            "{scheme}"
        );
        assert_ne!(
            first,
            bar_bits(scheme, every_step(UNIT_ROUNDOFF, 4)),
            "{scheme}"
        );
        assert_ne!(first, bar_bits(scheme, Settings::default()), "{scheme}");
    }
    let first = box_bits(every_step(UNIT_ROUNDOFF, 3));
    assert_eq!(first, box_bits(every_step(UNIT_ROUNDOFF, 3)));
    assert_ne!(first, box_bits(every_step(UNIT_ROUNDOFF, 4)));
}

#[test]
fn a_perturbation_of_size_zero_leaves_every_bit_of_the_run() {
    for scheme in schemes() {
        assert_eq!(
            bar_bits(scheme, every_step(0.0, 3)),
            bar_bits(scheme, Settings::default()),
            "{scheme}"
        );
    }
    assert_eq!(box_bits(every_step(0.0, 3)), box_bits(Settings::default()));
}

#[test]
fn an_epsilon_above_round_off_scale_is_refused_by_name() {
    let config = RunConfig {
        nx: 20,
        ratio: 10.0,
        scheme: Scheme::CRANK_NICOLSON,
        mass: MassVariant::Standard,
        observables: Observables::default(),
        settings: every_step(0.1, 1),
    };
    let error = run(&benchmarks::dirichlet(3.0), &config, &mut [])
        .unwrap_err()
        .to_string();
    assert!(error.contains("step_round_off.epsilon"), "{error}");
}
