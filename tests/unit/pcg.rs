//! The conjugate-gradient step solver (issue 19, item 1): on a random sparse SPD system it
//! agrees with the sparse Cholesky, and 2D/3D box runs with `cg` reproduce the `direct` runs to
//! 1e-8 relative at every step, with complementarity still at 1e-10.

use std::path::Path;

use signorini::engine::contact::{ContactOperator, DelassusKind};
use signorini::engine::fem::{MassVariant, SparseAssembler};
use signorini::engine::linalg::{
    LinearSolver, Pcg, PcgWork, SpdSolver, StepSolver, StepSolverKind, AUTO_CG_FROM_DOFS,
    DEFAULT_TOLERANCE,
};
use signorini::engine::problem::{Problem, Settings};
use signorini::engine::schemes::Scheme;
use signorini::engine::solver_plan::{box_step_solver, SolverPlan};
use signorini::harness::run::elastic::BoxProblem;
use signorini::harness::run::{run, BoxRun, Observables, RunConfig};
use signorini::harness::study::scene::Scene;

/// A random symmetric matrix with `per_row` off-diagonal entries in `[−1, 1]` per row and a
/// diagonal of `2·per_row + 1` (strictly diagonally dominant, hence SPD).
fn random_spd(
    n: usize,
    per_row: usize,
    rng: &mut fastrand::Rng,
) -> signorini::engine::fem::SymmetricMatrix {
    let mut upper = Vec::new();
    for i in 0..n {
        upper.push((i * n + i, 2.0 * per_row as f64 + 1.0 + rng.f64()));
        for _ in 0..per_row / 2 {
            let j = rng.usize(0..n);
            if j != i {
                let (r, c) = (i.min(j), i.max(j));
                upper.push((c * n + r, 2.0 * rng.f64() - 1.0));
            }
        }
    }
    signorini::engine::fem::SymmetricMatrix::from_upper_contributions(n, upper)
}

#[test]
fn pcg_matches_cholesky_on_a_random_spd_system() {
    let mut rng = fastrand::Rng::with_seed(19);
    let n = 500;
    let a = random_spd(n, 8, &mut rng);
    let b: Vec<f64> = (0..n).map(|_| rng.f64() - 0.5).collect();
    let mut direct = b.clone();
    SpdSolver::factor(&a, "random")
        .unwrap()
        .solve_in_place(&mut direct);
    let pcg = Pcg::new(a.clone(), DEFAULT_TOLERANCE, "random").unwrap();
    let mut work = PcgWork::new(n);
    let scale = direct.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
    for guess in [vec![0.0; n], (0..n).map(|_| rng.f64()).collect()] {
        let mut x = guess;
        let iterations = pcg.solve(&b, &mut x, &mut work).unwrap();
        assert!((1..100).contains(&iterations), "{iterations} iterations");
        let worst = x
            .iter()
            .zip(&direct)
            .map(|(p, d)| (p - d).abs())
            .fold(0.0, f64::max);
        assert!(worst <= 1e-12 * scale, "max |x_cg − x_direct| = {worst:e}");
        // Warm-started from the solution, CG has nothing to do.
        assert_eq!(pcg.solve(&b, &mut x, &mut work).unwrap(), 0);
    }
    // The columns of the Delassus operator: the same solutions, in parallel.
    let cg = StepSolver::new(a.clone(), StepSolverKind::Cg, "random").unwrap();
    let mut columns = vec![b.clone(), b.iter().map(|x| 2.0 * x).collect()];
    cg.solve_columns(&mut columns).unwrap();
    for (k, column) in columns.iter().enumerate() {
        for (c, d) in column.iter().zip(&direct) {
            assert!((c - (k + 1) as f64 * d).abs() <= 1e-12 * scale);
        }
    }
}

#[test]
fn pcg_refuses_a_non_positive_diagonal() {
    let mut asm = SparseAssembler::new(2);
    asm.add(0, 0, 1.0);
    asm.add(1, 1, -1.0);
    let err = Pcg::new(asm.finish(), DEFAULT_TOLERANCE, "test").unwrap_err();
    assert!(err.to_string().contains("diagonal entry 1"), "{err}");
}

#[test]
fn linear_solver_names_round_trip_and_errors_name_the_option() {
    for s in [LinearSolver::Direct, LinearSolver::Cg, LinearSolver::Auto] {
        assert_eq!(s.name().parse::<LinearSolver>().unwrap(), s);
    }
    let err = "lu".parse::<LinearSolver>().unwrap_err();
    assert_eq!(err.name, "linear-solver");
    assert!(err.to_string().contains("direct, cg, auto"), "{err}");
}

#[test]
fn auto_chooses_cg_on_large_boxes_only() {
    use LinearSolver::{Auto, Cg, Direct};
    let step = |choice, unknowns| box_step_solver(choice, unknowns).0;
    assert_eq!(step(Auto, AUTO_CG_FROM_DOFS), StepSolverKind::Cg);
    assert_eq!(step(Auto, AUTO_CG_FROM_DOFS - 1), StepSolverKind::Direct);
    assert_eq!(step(Cg, 10), StepSolverKind::Cg);
    assert_eq!(
        step(Direct, 100 * AUTO_CG_FROM_DOFS),
        StepSolverKind::Direct
    );
}

#[test]
fn a_box_plan_resolves_auto_once_and_says_why() {
    let plan = SolverPlan::for_box(LinearSolver::Auto, ContactOperator::Auto, 19_440).unwrap();
    assert_eq!(plan.step, StepSolverKind::Cg);
    assert_eq!(plan.contact, DelassusKind::Local { layers: None });
    assert_eq!(
        plan.reason,
        "step solver cg (auto: cg from 10000 unknowns, this box has 19440); \
         contact operator local (auto: local with cg)"
    );
    let small = SolverPlan::for_box(LinearSolver::Auto, ContactOperator::Auto, 3_000).unwrap();
    assert_eq!(small.step, StepSolverKind::Direct);
    assert_eq!(small.contact, DelassusKind::Full);
    let fixed = SolverPlan::for_box(LinearSolver::Cg, ContactOperator::LocalLayers(3), 10).unwrap();
    assert_eq!(fixed.contact.layers(), Some(3));
    let err = SolverPlan::for_box(LinearSolver::Direct, ContactOperator::Local, 10).unwrap_err();
    assert!(err.to_string().contains("needs the step matrix"), "{err}");
}

fn box_problem(scene: &str) -> BoxProblem {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(scene);
    let Problem::Box(problem) = Scene::load(&path).unwrap().problem() else {
        panic!("{scene} is not a box scene")
    };
    problem
}

/// `|a_k − b_k| ≤ 1e-8 · max_k |b_k|` for every `k` (relative to the series' scale: the
/// contact force is exactly zero between impacts).
fn assert_series_match(what: &str, a: &[f64], b: &[f64]) {
    assert_eq!(a.len(), b.len(), "{what}");
    let scale = b.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
    for (k, (x, y)) in a.iter().zip(b).enumerate() {
        assert!(
            (x - y).abs() <= 1e-8 * scale,
            "{what} at step {k}: cg {x:e}, direct {y:e} (scale {scale:e})"
        );
    }
}

/// A run of `problem` whose steps are solved by `solver` (checked in its result).
fn run_with(
    problem: &BoxProblem,
    solver: LinearSolver,
    nx: usize,
    scheme: Scheme,
    mass: MassVariant,
) -> BoxRun {
    let config = RunConfig {
        nx,
        ratio: 2.0,
        scheme,
        mass,
        observables: Observables::default(),
        settings: Settings {
            linear_solver: solver,
            ..Settings::default()
        },
    };
    let r = run(problem, &config, &mut []).unwrap().completed().unwrap();
    assert_eq!(r.observed.linear_solver, solver.name());
    r
}

#[test]
fn box_runs_with_cg_match_direct() {
    let paoli_schatzman: Scheme = "paoli-schatzman(beta=0.25,e=0)".parse().unwrap();
    for (scene, nx) in [("scenes/bar2d.json", 40), ("scenes/bar3d.json", 20)] {
        let problem = box_problem(scene);
        for scheme in [
            Scheme::CRANK_NICOLSON,
            Scheme::BACKWARD_EULER,
            paoli_schatzman,
        ] {
            for mass in [MassVariant::Standard, MassVariant::Redistributed] {
                let what = format!("{scene} {scheme} {mass}");
                let (c, d) = (
                    run_with(&problem, LinearSolver::Cg, nx, scheme, mass),
                    run_with(&problem, LinearSolver::Direct, nx, scheme, mass),
                );
                assert!(d.contact_solves > 0, "{what}: no impact");
                assert!(c.complementarity_violation <= 1e-10, "{what}");
                let energy = |r: &BoxRun| r.observed.energy.iter().map(|e| e.1).collect::<Vec<_>>();
                assert_series_match(&format!("{what} energy"), &energy(&c), &energy(&d));
                let (hc, hd) = (&c.observed.contact, &d.observed.contact);
                assert_series_match(&format!("{what} mean gap"), &hc.mean_gap, &hd.mean_gap);
                assert_series_match(
                    &format!("{what} centre gap"),
                    &hc.centre_gap,
                    &hd.centre_gap,
                );
                assert_series_match(&format!("{what} force"), &hc.total_force, &hd.total_force);
                assert_series_match(
                    &format!("{what} centre multiplier"),
                    &hc.centre_multiplier,
                    &hd.centre_multiplier,
                );
            }
        }
    }
}
