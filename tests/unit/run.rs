//! One run (`run::run`): only the requested norms are evaluated, bad input is a parameter error
//! naming the parameter (never a panic), the scheme and mass names of Tables 1–2 parse, and the
//! time grid lands on the horizon.

use crate::benchmarks;
use std::panic::{catch_unwind, AssertUnwindSafe};

use approx::assert_abs_diff_eq;
use signorini::engine::fem::MassVariant;
use signorini::engine::schemes::Scheme;
use signorini::harness::files::error::Error;
use signorini::harness::run::norms::Norm;
use signorini::harness::run::{self, time_grid, Observables, Problem1d, RunConfig};

fn only(norms: &[Norm]) -> Observables {
    Observables {
        norms: norms.iter().copied().collect(),
        ..Observables::default()
    }
}

/// Only the requested norms are evaluated (the Tables 1–2 columns are independent).
#[test]
fn space_norms_are_evaluated_only_when_requested() {
    let problem = benchmarks::dirichlet(1.5);
    let config = |norms: &[Norm]| RunConfig {
        nx: 10,
        ratio: 10.0,
        scheme: Scheme::CRANK_NICOLSON,
        mass: MassVariant::Standard,
        observables: only(norms),
        settings: Default::default(),
    };
    let energy_only = run::run(
        &problem,
        &config(&[Norm::EnergyLinf, Norm::EnergyL2]),
        &mut [],
    )
    .unwrap();
    assert_eq!(energy_only.observed.space_norm_evaluations, 0);
    assert_eq!(
        energy_only
            .observed
            .errors
            .keys()
            .copied()
            .collect::<Vec<_>>(),
        vec![Norm::EnergyLinf, Norm::EnergyL2]
    );
    assert_eq!(energy_only.steps, 150);

    let with_u = run::run(&problem, &config(&[Norm::DisplacementLinfH]), &mut []).unwrap();
    assert_eq!(with_u.observed.space_norm_evaluations, with_u.steps + 1);
    assert!(with_u.observed.errors[&Norm::DisplacementLinfH] > 0.0);

    let free = benchmarks::free_vibration(1.0);
    let result = run::run(&free, &config(&[Norm::MultiplierL2]), &mut []);
    match result {
        Err(Error::Parameter(p)) => assert_eq!(p.name, "norm"),
        other => panic!("lambda_L2 without obstacle must be rejected, got {other:?}"),
    }
}

/// Bad input through `run::run` is a `ParameterError` naming the parameter (the ranges of
/// eqs. 32, 34, 36: β > 0, γ ≥ 0, θ ∈ (0, 1], e ∈ [0, 1]), never a panic.
#[test]
fn run_rejects_bad_input_naming_the_parameter() {
    let base = RunConfig {
        nx: 8,
        ratio: 10.0,
        scheme: Scheme::CRANK_NICOLSON,
        mass: MassVariant::Standard,
        observables: only(&[Norm::DisplacementLinfH]),
        settings: Default::default(),
    };
    let problem = benchmarks::dirichlet(0.5);
    assert!(run::run(&problem, &base, &mut []).is_ok());

    let with = |f: &dyn Fn(&mut RunConfig)| {
        let mut c = base.clone();
        f(&mut c);
        c
    };
    let mut cases: Vec<(&str, Problem1d, RunConfig)> = vec![
        ("nx", problem.clone(), with(&|c| c.nx = 0)),
        ("ratio", problem.clone(), with(&|c| c.ratio = 0.0)),
        ("ratio", problem.clone(), with(&|c| c.ratio = -1.0)),
        ("ratio", problem.clone(), with(&|c| c.ratio = f64::NAN)),
        (
            "beta",
            problem.clone(),
            with(&|c| {
                c.scheme = Scheme::Newmark {
                    beta: -1.0,
                    gamma: 0.5,
                }
            }),
        ),
        (
            "theta",
            problem.clone(),
            with(&|c| c.scheme = Scheme::Theta { theta: 1.5 }),
        ),
        (
            "theta",
            problem.clone(),
            with(&|c| c.scheme = Scheme::Theta { theta: 0.0 }),
        ),
        (
            "e",
            problem.clone(),
            with(&|c| {
                c.scheme = Scheme::PaoliSchatzman {
                    beta: 0.25,
                    restitution: 2.0,
                }
            }),
        ),
        (
            "gamma",
            problem.clone(),
            with(&|c| {
                c.scheme = Scheme::Newmark {
                    beta: 0.25,
                    gamma: -0.1,
                }
            }),
        ),
    ];
    for horizon in [0.0, -1.0, f64::NAN] {
        let mut p = problem.clone();
        p.horizon = horizon;
        cases.push(("horizon", p, base.clone()));
    }
    for (name, problem, config) in cases {
        let outcome = catch_unwind(AssertUnwindSafe(|| run::run(&problem, &config, &mut [])));
        let result = outcome.unwrap_or_else(|_| panic!("{name}: run panicked on {config:?}"));
        match result {
            Err(Error::Parameter(p)) => {
                assert_eq!(p.name, name, "{config:?}");
                let message = Error::Parameter(p).to_string();
                assert!(
                    message.contains(&format!("{name} = ")),
                    "message {message:?} does not name {name}"
                );
            }
            other => panic!("{name}: expected a parameter error, got {other:?}"),
        }
    }
}

/// The scheme and mass names of Tables 1–2 parse; unknown names are rejected with the list of
/// valid ones.
#[test]
fn scheme_and_mass_names_parse() {
    assert_eq!(
        "crank-nicolson".parse::<Scheme>().unwrap(),
        Scheme::CRANK_NICOLSON
    );
    assert_eq!(
        "newmark(beta=0.3,gamma=0.6)".parse::<Scheme>().unwrap(),
        Scheme::Newmark {
            beta: 0.3,
            gamma: 0.6
        }
    );
    let err = "bogus".parse::<Scheme>().unwrap_err();
    assert!(err.to_string().contains("crank-nicolson"), "{err}");
    assert!(err.to_string().contains("bogus"), "{err}");
    // Parsed parameters are validated too.
    let err = "theta(theta=1.5)".parse::<Scheme>().unwrap_err();
    assert_eq!(err.name, "theta");

    assert_eq!(
        "standard".parse::<MassVariant>().unwrap(),
        MassVariant::Standard
    );
    assert_eq!(
        "redistributed".parse::<MassVariant>().unwrap(),
        MassVariant::Redistributed
    );
    let err = "heavy".parse::<MassVariant>().unwrap_err();
    assert!(err.to_string().contains("heavy"), "{err}");
    assert!(err.to_string().contains("standard"), "{err}");
}

/// §5.2: `Δx/Δt = 10`; the grid lands exactly on the horizon.
#[test]
fn time_grid_lands_on_the_horizon() {
    let (steps, dt) = time_grid(3.0, 0.1, 10.0);
    assert_eq!(steps, 300);
    assert_abs_diff_eq!(dt * steps as f64, 3.0, epsilon = 1e-12);
    assert_abs_diff_eq!(dt, 0.01, epsilon = 1e-15);

    // A nominal step that does not divide the horizon: round the step count up, so that
    // Δt never exceeds h / ratio.
    let (steps, dt) = time_grid(1.0, 0.3, 1.0);
    assert_eq!(steps, 4);
    assert_abs_diff_eq!(dt, 0.25, epsilon = 1e-15);
    for (horizon, h, ratio) in [
        (3.0, 1.0 / 40.0, 10.0),
        (4.0, 0.0125, 1.0),
        (6.0, 0.05, 10.0),
    ] {
        let (steps, dt) = time_grid(horizon, h, ratio);
        assert_eq!(steps, (horizon * ratio / h).round() as usize);
        assert_abs_diff_eq!(dt * steps as f64, horizon, epsilon = 1e-12);
        assert!(dt <= h / ratio * (1.0 + 1e-12));
    }
}

/// A run's CSV files write a negative zero (a field's value at a clamped end, say) as `0`, not
/// `-0.000…e0`, and every other number as it is.
#[test]
fn a_negative_zero_is_written_as_zero_in_a_csv() {
    let text = signorini::harness::files::artifacts::csv("x,y", &[&[-0.0, 1.0], &[0.0, -2.5]], 3);
    assert_eq!(text, "x,y\n0.000e0,0.000e0\n1.000e0,-2.500e0\n");
}
