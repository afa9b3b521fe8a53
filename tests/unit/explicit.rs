//! Explicit Newmark (β = 0, central differences for γ = ½): the CFL bound, explicit contact with
//! the singular masses, on the bar and the 2D box. Its energy conservation and contact balance
//! are in `energy_balance.rs`, its second-order convergence in `tests/convergence/smooth.rs`.

use crate::stepper::Stepper;
use crate::{benchmarks, common};
use signorini::engine::problem::Settings;
use signorini::engine::schemes::{
    initial_state, integrator, Conventions, ExplicitNewmark, Scheme, SchemeState,
};

use nalgebra::DMatrix;
use signorini::engine::contact::{ContactOperator, ContactTreatment};
use signorini::engine::error::{Error as EngineError, SolveError};
use signorini::engine::exact::{ExactSolution, SignoriniDirichlet};
use signorini::engine::fem::{Bar1d, Elasticity, EndCondition, MassVariant, SymmetricMatrix};
use signorini::engine::linalg::LinearSolver;
use signorini::engine::model::Model;
use signorini::engine::schemes::cfl::{largest_eigenvalue, stable_step};
use signorini::harness::files::error::Error;
use signorini::harness::run::elastic::BoxProblem;
use signorini::harness::run::{run, Observables, RunConfig};

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
    let problem = benchmarks::dirichlet(3.0);
    for mass in MASSLESS_CONTACT {
        let (bar, model) = problem.model(40, mass).unwrap();
        let (s, m) = massed_blocks(&model);
        let bound = stable_step(largest_eigenvalue(&s, &m).unwrap(), 0.5);
        let u0 = bar.interpolate(|x| SignoriniDirichlet.eval(x, 0.0).u);
        let v0 = vec![0.0; u0.len()];
        let too_large = integrator(
            &model,
            Scheme::CENTRAL_DIFFERENCE,
            bound * 1.01,
            &u0,
            &v0,
            &Conventions::HARNESS,
        );
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
        let explicit = ExplicitNewmark::new(&model, 0.5, bound * 0.99).unwrap();
        assert_eq!(explicit.stable_dt(), bound);
        let mut ok = Stepper::from(
            integrator(
                &model,
                Scheme::CENTRAL_DIFFERENCE,
                bound * 0.99,
                &u0,
                &v0,
                &Conventions::HARNESS,
            )
            .unwrap_or_else(|e| panic!("{mass}: {e}")),
        );
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

/// A contact dof with mass gets the Taylor–Flanagan step: the bar released onto the obstacle
/// never drives its contact node into it at more than `O(Δt²)`, every impulse is compressive,
/// and the velocity of the stopped node after the impulse is the `γΔt A` of the step.
#[test]
fn explicit_contact_with_mass_takes_the_taylor_flanagan_step() {
    for mass in [MassVariant::Standard, MassVariant::Lumped] {
        let bar = Bar1d::unit(20, EndCondition::Clamped).unwrap();
        let model = Model::bar1d(&bar, mass, Some(0.0), None);
        let u0 = vec![0.1; bar.n_dofs()];
        let v0 = vec![-1.0; bar.n_dofs()];
        let dt = bar.h() / 2.0;
        let start = initial_state(&model, &u0, &v0, &Conventions::HARNESS).unwrap();
        let mut s = Stepper::new(
            ExplicitNewmark::new(&model, 0.5, dt).unwrap(),
            SchemeState::start(dt, start),
        );
        let (mut impulses, mut deepest) = (0, 0.0_f64);
        for _ in 0..200 {
            s.advance().unwrap();
            let lambda = s.multiplier().value[0];
            assert!(lambda <= 0.0, "{mass}: adhesive impulse {lambda}");
            impulses += usize::from(lambda < 0.0);
            deepest = deepest.min(s.displacement()[0]);
        }
        assert!(impulses > 0, "{mass}: the bar never hit the obstacle");
        assert!(deepest > -dt * dt * 10.0, "{mass}: penetration {deepest:e}");
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
    };
    let config = |ratio: f64, mass| RunConfig {
        nx: 10,
        ratio,
        scheme: Scheme::CENTRAL_DIFFERENCE,
        mass,
        observables: Observables::default(),
        settings: Settings {
            conventions: Conventions::HARNESS,
            linear_solver: LinearSolver::Direct,
            contact_operator: ContactOperator::Full,
            round_off: None,
            step_round_off: None,
        },
    };
    for mass in MASSLESS_CONTACT {
        let r = run(&problem, &config(8.0, mass), &mut []).unwrap();
        assert!(r.contact_solves > 0, "{mass}");
        assert!(r.complementarity_violation < 1e-10, "{mass}");
        match run(&problem, &config(0.5, mass), &mut []) {
            Err(Error::Solve(SolveError::CflViolated { .. })) => {}
            other => panic!("{mass}: expected CflViolated, got {:?}", other.err()),
        }
    }
}
