//! Explicit Newmark (β = 0, central differences for γ = ½): the CFL bound, energy
//! conservation, second-order convergence, explicit contact with the singular masses.

mod common;

use std::collections::BTreeSet;
use std::path::Path;

use nalgebra::DMatrix;
use signorini::contact::ContactTreatment;
use signorini::elastic::{run_box, BoxProblem, BoxRunConfig};
use signorini::error::{EngineError, Error, SolveError};
use signorini::exact::{ExactSolution, SignoriniDirichlet};
use signorini::fem::{Bar1d, Elasticity, EndCondition, MassVariant, SymmetricMatrix};
use signorini::model::Model;
use signorini::norms::Norm;
use signorini::run::{self, time_grid, Observables, Problem1d, RunConfig};
use signorini::schemes::cfl::{largest_eigenvalue, stable_step};
use signorini::schemes::energy_balance::{self, ThreeLevels};
use signorini::schemes::{initial_state, integrator, ExplicitNewmark, Scheme};
use signorini::studies::benchmark;

/// The Signorini–Dirichlet benchmark of `scenes/bar1d-dirichlet.json`, to `horizon`.
fn dirichlet(horizon: f64) -> Problem1d {
    benchmark::dirichlet(Path::new(env!("CARGO_MANIFEST_DIR")), horizon).unwrap()
}

/// The clamped bar vibrating in its first mode (no obstacle, a smooth solution) of
/// `scenes/bar1d-free.json`, to `horizon`.
fn free_vibration(horizon: f64) -> Problem1d {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let (_, problem) = benchmark::bar_scene(root, "scenes/bar1d-free.json").unwrap();
    Problem1d { horizon, ..problem }
}

const MASSLESS_CONTACT: [MassVariant; 3] = [
    MassVariant::Redistributed,
    MassVariant::RedistributedConserving,
    MassVariant::SingularDynamic,
];

fn dense(m: &SymmetricMatrix) -> DMatrix<f64> {
    DMatrix::from_fn(m.dim(), m.dim(), |i, j| m.get(i, j))
}

/// `λ_max(S, M)` by a dense Cholesky and a dense symmetric eigensolver (the reference).
fn dense_largest(s: &SymmetricMatrix, m: &SymmetricMatrix) -> f64 {
    let l = dense(m).cholesky().expect("M SPD").l();
    let l_inv = l.try_inverse().unwrap();
    let a = &l_inv * dense(s) * l_inv.transpose();
    let a = (&a + a.transpose()) * 0.5;
    a.symmetric_eigenvalues().max()
}

fn massed_blocks(model: &Model) -> (SymmetricMatrix, SymmetricMatrix) {
    let r: Vec<usize> = (0..model.n_dofs())
        .filter(|i| model.massless_dofs().binary_search(i).is_err())
        .collect();
    (
        model.stiffness().principal_submatrix(&r),
        model.mass().principal_submatrix(&r),
    )
}

/// The Lanczos bound is above the dense eigenvalue and within 1e-6 of it, for every mass.
#[test]
fn lanczos_bound_matches_the_dense_eigenvalue() {
    for far_end in [EndCondition::Clamped, EndCondition::Free] {
        let bar = Bar1d::unit(30, far_end).unwrap();
        for mass in MassVariant::ALL {
            let model = Model::bar1d(&bar, mass, Some(0.0), None);
            let (s, m) = massed_blocks(&model);
            let exact = dense_largest(&s, &m);
            let bound = largest_eigenvalue(&s, &m).unwrap();
            assert!(
                bound >= exact * (1.0 - 1e-12) && bound <= exact * (1.0 + 1e-6),
                "{mass} {far_end:?}: bound {bound} vs dense {exact}"
            );
        }
    }
    // Known closed forms: the lumped P1 bar, ω²_max → 4c²/h²; consistent, 12c²/h² (clamped).
    let bar = Bar1d::unit(200, EndCondition::Clamped).unwrap();
    let h = bar.h();
    for (mass, limit) in [(MassVariant::Lumped, 4.0), (MassVariant::Standard, 12.0)] {
        let model = Model::bar1d(&bar, mass, None, None);
        let (s, m) = massed_blocks(&model);
        let w = largest_eigenvalue(&s, &m).unwrap() * h * h;
        assert!(w <= limit && w > limit * (1.0 - 1e-3), "{mass}: {w}");
    }
}

/// A Δt just above `2/ω_max` is refused before any step with the typed error carrying the
/// bound; just below, the run proceeds.
#[test]
fn cfl_violation_is_a_typed_error_naming_the_bound() {
    let problem = dirichlet(3.0);
    for mass in MASSLESS_CONTACT {
        let (bar, model) = problem.model(40, mass).unwrap();
        let (s, m) = massed_blocks(&model);
        let bound = stable_step(largest_eigenvalue(&s, &m).unwrap(), 0.5);
        let u0 = bar.interpolate(|x| SignoriniDirichlet.eval(x, 0.0).u);
        let v0 = vec![0.0; u0.len()];
        let too_large = integrator(&model, Scheme::CENTRAL_DIFFERENCE, bound * 1.01, &u0, &v0);
        match too_large {
            Err(EngineError::Solve(SolveError::CflViolated {
                dt,
                bound: b,
                gamma,
            })) => {
                assert_eq!(b, bound);
                assert_eq!(dt, bound * 1.01);
                assert_eq!(gamma, 0.5);
            }
            other => panic!("{mass}: expected CflViolated, got {:?}", other.err()),
        }
        let message = SolveError::CflViolated {
            dt: 1.0,
            bound,
            gamma: 0.5,
        }
        .to_string();
        assert!(message.contains("Δt ≤ √(2/γ)/ω_max"), "{message}");
        assert!(message.contains("2/ω_max"), "{message}");
        let start = initial_state(&model, &u0, &v0).unwrap();
        let explicit = ExplicitNewmark::new(&model, 0.5, bound * 0.99, start).unwrap();
        assert_eq!(explicit.stable_dt(), bound);
        let mut ok = integrator(&model, Scheme::CENTRAL_DIFFERENCE, bound * 0.99, &u0, &v0)
            .unwrap_or_else(|e| panic!("{mass}: {e}"));
        for _ in 0..2000 {
            ok.advance().unwrap();
        }
        assert!(ok.displacement().iter().all(|u| u.abs() < 1.0), "{mass}");
    }
}

/// Through the binary: exit code 2, the bound in the message, no output directory.
#[test]
fn cli_refuses_a_step_above_the_cfl_bound_and_writes_nothing() {
    let dir = std::env::temp_dir().join(format!("signorini-cfl-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let out = dir.to_str().unwrap();
    common::expect_error(
        &[
            "run",
            "scenes/bar1d-dirichlet.json",
            "--scheme",
            "central-difference",
            "--mass",
            "singular-dynamic",
            "--nx",
            "40",
            "--ratio",
            "0.5",
            "--out",
            out,
        ],
        2,
        &["time step too large", "Δt ≤ √(2/γ)/ω_max"],
    );
    assert!(
        !dir.exists() || std::fs::read_dir(&dir).unwrap().next().is_none(),
        "output written"
    );
    common::expect_error(
        &[
            "run",
            "scenes/bar1d-dirichlet.json",
            "--scheme",
            "central-difference",
            "--mass",
            "lumped",
            "--nx",
            "20",
        ],
        2,
        &["explicit contact requires", "singular-dynamic"],
    );
}

#[test]
fn end_to_end_run_prints_the_errors() {
    let out = common::signorini(&[
        "run",
        "scenes/bar1d-dirichlet.json",
        "--scheme",
        "central-difference",
        "--mass",
        "singular-dynamic",
        "--nx",
        "40",
    ]);
    let stdout = common::success_stdout(&out);
    assert!(
        stdout.contains("central-difference / singular-dynamic"),
        "{stdout}"
    );
    assert!(stdout.contains("u_Linf_H"), "{stdout}");
}

/// A contact dof with mass has no explicit contact treatment here: a typed error.
#[test]
fn explicit_contact_with_mass_is_refused() {
    for mass in [MassVariant::Standard, MassVariant::Lumped] {
        let bar = Bar1d::unit(20, EndCondition::Clamped).unwrap();
        let model = Model::bar1d(&bar, mass, Some(0.0), None);
        let u0 = vec![0.1; bar.n_dofs()];
        let v0 = vec![0.0; bar.n_dofs()];
        let start = initial_state(&model, &u0, &v0).unwrap();
        let err = ExplicitNewmark::new(&model, 0.5, bar.h() / 10.0, start).unwrap_err();
        assert_eq!(
            err,
            SolveError::ExplicitContactWithMass { dof: 0 },
            "{mass}"
        );
        assert!(err.to_string().contains("redistributed-conserving"));
    }
}

/// Without contact the staggered energy `E^{n+½}` is constant to round-off, for every mass
/// (with a load too), including the singular ones whose contact node is static.
#[test]
fn central_differences_conserve_the_staggered_energy_without_contact() {
    for mass in MassVariant::ALL {
        for load in [None, Some(-0.3)] {
            let bar = Bar1d::unit(40, EndCondition::Clamped).unwrap();
            let model = Model::bar1d(&bar, mass, None, load);
            let u0 = bar.interpolate(|x| (std::f64::consts::FRAC_PI_2 * x).cos());
            let v0 = bar.interpolate(|x| 0.3 * x * (1.0 - x));
            let dt = 0.5 * bar.h();
            let mut s = integrator(&model, Scheme::CENTRAL_DIFFERENCE, dt, &u0, &v0).unwrap();
            s.advance().unwrap();
            let e_half = s.energy().value;
            let (mut previous, mut per_step, mut drift): (f64, f64, f64) = (e_half, 0.0, 0.0);
            for _ in 0..2000 {
                s.advance().unwrap();
                let e = s.energy().value;
                per_step = per_step.max((e - previous).abs() / e_half.abs());
                drift = drift.max((e - e_half).abs() / e_half.abs());
                previous = e;
            }
            // Round-off: ½UᵀSU sums entries of size E/h² down to E (1/h = 40 here).
            assert!(
                per_step < 1e-11,
                "{mass} load {load:?}: step change {per_step:e}"
            );
            assert!(drift < 1e-10, "{mass} load {load:?}: drift {drift:e}");
            assert_eq!(s.energy().time, (s.step_index() as f64 - 0.5) * dt);
        }
    }
    // The check can fail: γ = 0.6 damps, and the same energy then moves far above round-off.
    let bar = Bar1d::unit(40, EndCondition::Clamped).unwrap();
    let model = Model::bar1d(&bar, MassVariant::Standard, None, None);
    let u0 = bar.interpolate(|x| (std::f64::consts::FRAC_PI_2 * x).cos());
    let damped = Scheme::Newmark {
        beta: 0.0,
        gamma: 0.6,
    };
    let mut s = integrator(&model, damped, 0.5 * bar.h(), &u0, &vec![0.0; u0.len()]).unwrap();
    s.advance().unwrap();
    let e_half = s.energy().value;
    for _ in 0..200 {
        s.advance().unwrap();
    }
    assert!((s.energy().value - e_half).abs() / e_half > 1e-6);
}

/// With contact: `E^{n+½} − E^{n−½} = −½ λ^n (u_c^{n+1} − u_c^{n−1})` at every step
/// (`energy_balance::central_difference`) for the staggered energy the scheme reports, and
/// `0 ≤ u_c ⟂ λ ≤ 0` at every step, on the Dirichlet benchmark.
#[test]
fn explicit_contact_balance_and_complementarity_every_step() {
    for mass in MASSLESS_CONTACT {
        let problem = dirichlet(3.0);
        let (bar, model) = problem.model(40, mass).unwrap();
        let exact = SignoriniDirichlet;
        let u0 = bar.interpolate(|x| exact.eval(x, 0.0).u);
        let v0 = bar.interpolate(|x| exact.eval(x, 0.0).ut);
        let (steps, dt) = time_grid(3.0, bar.h(), 10.0);
        let mut s = integrator(&model, Scheme::CENTRAL_DIFFERENCE, dt, &u0, &v0).unwrap();
        let mut u_prev = s.displacement().to_vec();
        s.advance().unwrap();
        let e0 = s.energy().value;
        let (mut worst, mut contact_steps): (f64, usize) = (0.0, 0);
        for n in 1..steps {
            let (u_now, lambda_now) = (s.displacement().to_vec(), s.multiplier().value.to_vec());
            let (gap, lambda) = (u_now[0], lambda_now[0]);
            assert!(gap >= -1e-14, "{mass} step {n}: gap {gap:e}");
            assert!(lambda <= 0.0, "{mass} step {n}: λ {lambda:e}");
            assert!((gap * lambda).abs() <= 1e-14, "{mass} step {n}");
            if lambda != 0.0 {
                contact_steps += 1;
            }
            let e_before = s.energy().value;
            s.advance().unwrap();
            let levels = ThreeLevels {
                earlier: &u_prev,
                current: &u_now,
                later: s.displacement(),
                multiplier: &lambda_now,
            };
            let b = energy_balance::central_difference(&model, dt, &levels);
            assert_eq!(b.energy_before, e_before, "{mass} step {n}");
            assert_eq!(b.energy_after, s.energy().value, "{mass} step {n}");
            worst = worst.max(b.residual().abs() / e0);
            u_prev = u_now;
        }
        assert!(contact_steps > 100, "{mass}: {contact_steps} contact steps");
        // Round-off, as without contact (NX = 40: entries of S of size 40).
        assert!(worst < 1e-11, "{mass}: balance residual {worst:e}");
        assert!(s.complementarity_violation() < 1e-12, "{mass}");
    }
}

/// Central differences are second order on the smooth first mode (no obstacle), like
/// Crank–Nicolson in `tests/engine.rs`, with Δx/Δt = 2 (below both masses' CFL bounds). The
/// lumped mass is pre-asymptotic at NX = 10 (observed order 1.69 there), hence NX ≥ 20.
#[test]
fn central_differences_converge_at_second_order_on_a_smooth_solution() {
    for mass in [MassVariant::Standard, MassVariant::Lumped] {
        let problem = free_vibration(4.0);
        let (mut hs, mut errors) = (Vec::new(), Vec::new());
        for nx in [20, 40, 80, 160] {
            let config = RunConfig {
                nx,
                ratio: 2.0,
                scheme: Scheme::CENTRAL_DIFFERENCE,
                mass,
                observables: Observables {
                    norms: BTreeSet::from([Norm::DisplacementLinfH]),
                    ..Observables::default()
                },
            };
            let r = run::run(&problem, &config).unwrap();
            hs.push(r.h.ln());
            errors.push(r.errors[&Norm::DisplacementLinfH].ln());
        }
        let n = hs.len() as f64;
        let (mx, my) = (hs.iter().sum::<f64>() / n, errors.iter().sum::<f64>() / n);
        let sxy: f64 = hs
            .iter()
            .zip(&errors)
            .map(|(x, y)| (x - mx) * (y - my))
            .sum();
        let sxx: f64 = hs.iter().map(|x| (x - mx) * (x - mx)).sum();
        let rate = sxy / sxx;
        println!("{mass}: central differences, u_Linf_H rate {rate:.4}");
        assert!((1.9..=2.1).contains(&rate), "{mass}: rate {rate}");
    }
}

#[test]
fn central_difference_preset_and_validation() {
    let s: Scheme = "central-difference".parse().unwrap();
    assert_eq!(
        s,
        Scheme::Newmark {
            beta: 0.0,
            gamma: 0.5
        }
    );
    assert!(s.is_explicit());
    assert_eq!(s.name(), "central-difference");
    assert!(!Scheme::paper_schemes().contains(&s));
    let err = "newmark(beta=0,gamma=0.4)".parse::<Scheme>().unwrap_err();
    assert_eq!(err.name, "gamma");
    let err = "newmark(beta=-0.1,gamma=0.5)"
        .parse::<Scheme>()
        .unwrap_err();
    assert_eq!(err.name, "beta");
    assert!("newmark(beta=0,gamma=0.6)".parse::<Scheme>().is_ok());
}

/// The explicit scheme runs on the Q1 bars with the singular masses: a 2D box hits the
/// obstacle, complementarity holds; a too-large step is refused.
#[test]
fn explicit_box_runs_with_massless_contact_nodes() {
    let problem = BoxProblem {
        lengths: vec![0.1, 1.0],
        elasticity: Elasticity::NOTE,
        obstacle_gap: Some(0.2),
        initial_displacement: 0.0,
        initial_velocity: -0.5,
        horizon: 1.0,
        contact: ContactTreatment::Multiplier,
        velocity_perturbation: None,
    };
    let config = |ratio: f64, mass| BoxRunConfig {
        n_axis: 10,
        ratio,
        scheme: Scheme::CENTRAL_DIFFERENCE,
        mass,
        vtk_at: Vec::new(),
        vtk_dir: None,
    };
    for mass in MASSLESS_CONTACT {
        let r = run_box(&problem, &config(8.0, mass)).unwrap();
        assert!(r.contact_solves > 0, "{mass}");
        assert!(r.complementarity_violation < 1e-10, "{mass}");
        match run_box(&problem, &config(0.5, mass)) {
            Err(Error::Solve(SolveError::CflViolated { .. })) => {}
            other => panic!("{mass}: expected CflViolated, got {:?}", other.err()),
        }
    }
}
