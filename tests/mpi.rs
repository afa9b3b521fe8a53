//! The slab-decomposed step solve of issue 36 under MPI (`make mpi-check`, which installs Open
//! MPI and builds with the `mpi` feature; without it this file is empty). The test runs this
//! binary's [`mpi_rank_body`] under `mpirun` on one and on two ranks: each rank computes the
//! one-process product, preconditioner and solve of 2D and 3D step matrices with either mass,
//! and checks its slab's part of the distributed ones: products and preconditioner equal bit
//! for bit, the solve in as many iterations and equal to 1e-12 of the solution's scale, and
//! bit for bit on one rank. Then the reference's Crank–Nicolson `M^mod` run of the 3D bar at
//! level 40 over `T = 1`: energies, multipliers and the final displacement equal to the
//! one-process run's to 1e-10 of their scale (bit for bit on one rank).
#![cfg(feature = "mpi")]

use std::path::Path;
use std::process::Command;

use signorini::engine::distributed::{MpiRanks, Ranks, SlabCg, SlabOneStep};
use signorini::engine::fem::{BoxMesh, Elasticity, MassVariant, SymmetricMatrix};
use signorini::engine::linalg::{CgSpace, LinearSolver, Pcg, PcgWork, DEFAULT_TOLERANCE};
use signorini::engine::problem::Settings;
use signorini::engine::schemes::conventions::{NitscheAcceleration, PredictorForm};
use signorini::engine::schemes::{initial_state, OneStepScheme, StepCoefficients, TimeIntegrator};
use signorini::harness::study::scene::Scene;

#[test]
fn mpi_ranks_compute_the_one_process_solve() {
    let exe = std::env::current_exe().expect("this test binary");
    for ranks in ["1", "2"] {
        let out = Command::new("mpirun")
            .args(["--oversubscribe", "-n", ranks])
            .arg(&exe)
            .args(["--exact", "mpi_rank_body", "--ignored", "--nocapture"])
            .env("OMPI_ALLOW_RUN_AS_ROOT", "1")
            .env("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1")
            .output()
            .expect("mpirun runs (make mpi-check installs Open MPI)");
        let stdout = String::from_utf8_lossy(&out.stdout);
        assert!(
            out.status.success(),
            "mpirun -n {ranks}: {}\n{stdout}\n{}",
            out.status,
            String::from_utf8_lossy(&out.stderr)
        );
        let n: usize = ranks.parse().unwrap();
        for rank in 0..n {
            let line = format!("rank {rank} of {n}: 4 cases and the run agree");
            assert!(stdout.contains(&line), "no `{line}` in\n{stdout}");
        }
    }
}

/// Crank–Nicolson's step matrix `M/(bΔt²) + S`, `b = ¼`, at `Δx/Δt = 2`, matrix-free.
fn step_matrix(mesh: &BoxMesh, variant: MassVariant) -> SymmetricMatrix {
    let h = 1.0 / mesh.counts()[mesh.dim() - 1] as f64;
    let alpha = 1.0 / (0.25 * (h / 2.0) * (h / 2.0));
    mesh.mass_stencil(variant, 1.0).unwrap().linear_combination(
        alpha,
        &mesh.stiffness_stencil(&Elasticity::NOTE),
        1.0,
    )
}

#[test]
#[ignore = "a rank of mpi_ranks_compute_the_one_process_solve, under mpirun"]
fn mpi_rank_body() {
    let ranks = MpiRanks::initialise().expect("MPI initialises once");
    let boxes = [
        BoxMesh::new(&[0.2, 1.0], &[4, 20]).unwrap(),
        BoxMesh::new(&[0.1, 0.1, 1.0], &[3, 2, 16]).unwrap(),
    ];
    let mut agreed = 0;
    for mesh in &boxes {
        for variant in [MassVariant::Redistributed, MassVariant::Standard] {
            let k = step_matrix(mesh, variant);
            let n = k.dim();
            let mut rng = fastrand::Rng::with_seed(36);
            let x: Vec<f64> = (0..n).map(|_| rng.f64() - 0.5).collect();
            let whole = Pcg::new(k.clone(), DEFAULT_TOLERANCE, "K").unwrap();
            let (mut kx, mut px) = (vec![0.0; n], vec![0.0; n]);
            whole.mul_dot(&x, &mut kx);
            whole.precondition(&x, &mut px);
            let mut expected = vec![0.0; n];
            let iterations = whole
                .solve(&x, &mut expected, &mut PcgWork::new(n))
                .unwrap();
            let scale = expected.iter().fold(0.0_f64, |m, v| m.max(v.abs()));

            let cg = SlabCg::new(&ranks, &k, 1, DEFAULT_TOLERANCE).unwrap();
            let own = cg.own_dofs();
            let (mut y, mut z) = (vec![0.0; own.len()], vec![0.0; own.len()]);
            cg.mul_dot(&x[own.clone()], &mut y);
            cg.precondition(&x[own.clone()], &mut z);
            let what = format!("{:?} {variant:?}, rank {}", mesh.counts(), ranks.rank());
            assert!(y == kx[own.clone()], "K x, {what}");
            assert!(z == px[own.clone()], "P⁻¹ x, {what}");
            let mut solution = vec![0.0; own.len()];
            let spent = cg
                .solve(&x[own.clone()], &mut solution, &mut PcgWork::new(own.len()))
                .unwrap();
            assert_eq!(spent, iterations, "{what}");
            if ranks.size() == 1 {
                assert!(solution == expected, "{what}: not bit for bit on one rank");
            }
            let worst = solution
                .iter()
                .zip(&expected[own])
                .map(|(p, q)| (p - q).abs())
                .fold(0.0, f64::max);
            assert!(worst <= 1e-12 * scale, "{what}: {worst:e} of {scale:e}");
            agreed += 1;
        }
    }
    crank_nicolson_run_agrees(&ranks);
    println!(
        "rank {} of {}: {agreed} cases and the run agree",
        ranks.rank(),
        ranks.size()
    );
}

/// The reference's scheme on `ranks` against the one-process run (every rank runs the latter
/// whole and checks its own part).
fn crank_nicolson_run_agrees(ranks: &MpiRanks) {
    let mut problem = Scene::load(Path::new("scenes/bar3d.json"))
        .unwrap()
        .box_problem("a box")
        .unwrap();
    problem.horizon = 1.0;
    let settings = Settings {
        linear_solver: LinearSolver::Cg,
        ..Settings::default()
    };
    let discretisation = problem
        .discretise(40, MassVariant::Redistributed, &settings)
        .unwrap();
    let model = &discretisation.model;
    let (coef, dt, steps) = (StepCoefficients::newmark(0.25, 0.5), 1.0 / 80.0, 80);
    let start = initial_state(
        model,
        &discretisation.displacement,
        &discretisation.velocity,
        &settings.conventions,
    )
    .unwrap();
    let mut whole = OneStepScheme::new(
        model,
        coef,
        dt,
        start.clone(),
        NitscheAcceleration::Consistent,
    )
    .unwrap();
    let mut run =
        SlabOneStep::new(ranks, model, coef, dt, &start, PredictorForm::Expanded).unwrap();
    let relative = |a: &[f64], b: &[f64]| {
        let scale = b
            .iter()
            .fold(0.0_f64, |m, x| m.max(x.abs()))
            .max(f64::MIN_POSITIVE);
        a.iter()
            .zip(b)
            .map(|(p, q)| (p - q).abs())
            .fold(0.0, f64::max)
            / scale
    };
    let one_rank = ranks.size() == 1;
    for step in 0..=steps {
        if step > 0 {
            whole.advance().unwrap();
            run.advance().unwrap();
        }
        let (expected, got) = (whole.energy().value, run.energy());
        assert!(
            (one_rank && got == expected) || (got - expected).abs() <= 1e-10 * expected.abs(),
            "step {step}: energy {got:e} against {expected:e}"
        );
        if ranks.rank() == 0 {
            let (expected, got) = (&whole.state().lambda, run.multipliers());
            assert!(
                (one_rank && got == expected) || relative(got, expected) <= 1e-10,
                "step {step}: λ"
            );
        }
    }
    let own = run.own_dofs();
    let (expected, got) = (&whole.state().u[own], run.displacement());
    assert!(
        (one_rank && got == expected) || relative(got, expected) <= 1e-10,
        "U at T"
    );
    assert_eq!(run.step_solves().iterations, whole.step_solves().iterations);
}
