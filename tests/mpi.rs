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
use signorini::engine::fem::{BoxMesh, MassVariant};
use signorini::engine::linalg::{CgSpace, Pcg, PcgWork, DEFAULT_TOLERANCE};
use signorini::engine::schemes::conventions::{NitscheAcceleration, PredictorForm};
use signorini::engine::schemes::{OneStepScheme, SchemeState, StepCoefficients, TimeIntegrator};
use signorini::harness::study::scene::Scene;

#[path = "common/slabs.rs"]
mod slabs;
use slabs::{level_40, relative, start_of, step_matrix};

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
    let discretisation = level_40(&problem);
    let model = &discretisation.model;
    let (coef, dt, steps) = (StepCoefficients::newmark(0.25, 0.5), 1.0 / 80.0, 80);
    let start = start_of(&discretisation);
    let mut whole = OneStepScheme::new(model, coef, dt, NitscheAcceleration::Consistent).unwrap();
    let mut state = SchemeState::start(dt, start.clone());
    let mut run = SlabOneStep::new(
        ranks,
        model,
        coef,
        dt,
        (ranks.rank() == 0).then_some(&start),
        PredictorForm::Expanded,
    )
    .unwrap();
    let one_rank = ranks.size() == 1;
    for step in 0..=steps {
        if step > 0 {
            whole.advance(&mut state).unwrap();
            run.advance().unwrap();
        }
        let (expected, got) = (whole.energy(&state).value, run.energy());
        assert!(
            (one_rank && got == expected) || (got - expected).abs() <= 1e-10 * expected.abs(),
            "step {step}: energy {got:e} against {expected:e}"
        );
        if ranks.rank() == 0 {
            let (expected, got) = (&state.lambda, run.multipliers());
            assert!(
                (one_rank && got == expected) || relative(got, expected) <= 1e-10,
                "step {step}: λ"
            );
        }
    }
    let own = run.own_dofs();
    let (expected, got) = (&state.u[own], run.displacement());
    assert!(
        (one_rank && got == expected) || relative(got, expected) <= 1e-10,
        "U at T"
    );
    assert_eq!(
        run.statistics().step_solves.iterations,
        whole.statistics().step_solves.iterations
    );
}

/// Runs `signorini` with `args` (under `mpirun -n N` when `ranks` is given), expecting success.
fn signorini(ranks: Option<&str>, args: &[&str]) -> String {
    let binary = env!("CARGO_BIN_EXE_signorini");
    let mut command = match ranks {
        Some(n) => {
            let mut c = Command::new("mpirun");
            c.args(["--oversubscribe", "-n", n, binary]);
            c
        }
        None => Command::new(binary),
    };
    let out = command
        .args(args)
        .env("OMPI_ALLOW_RUN_AS_ROOT", "1")
        .env("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1")
        .output()
        .expect("signorini runs");
    let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
    assert!(
        out.status.success(),
        "{ranks:?} {args:?}: {}\n{stdout}\n{}",
        out.status,
        String::from_utf8_lossy(&out.stderr)
    );
    stdout
}

/// The one file of `dir` ending in `suffix`.
fn cached(dir: &Path, suffix: &str) -> std::path::PathBuf {
    let found: Vec<_> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.to_string_lossy().ends_with(suffix))
        .collect();
    assert_eq!(found.len(), 1, "{dir:?}: {found:?}");
    found[0].clone()
}

/// The numbers of a JSON value, depth first, with their paths.
fn numbers(value: &serde_json::Value, path: String, into: &mut Vec<(String, f64)>) {
    match value {
        serde_json::Value::Number(n) => into.push((path, n.as_f64().unwrap())),
        serde_json::Value::Array(items) => {
            for (i, v) in items.iter().enumerate() {
                numbers(v, format!("{path}[{i}]"), into);
            }
        }
        serde_json::Value::Object(fields) => {
            for (k, v) in fields {
                numbers(v, format!("{path}.{k}"), into);
            }
        }
        _ => {}
    }
}

/// `mpirun -n 2 signorini reference` of small 2D and 3D bars (levels 10, 20; reference 40)
/// against the one-process command: the cached histories, check distances and projections
/// equal to 1e-10 of each one's scale; `mpirun -n 1` (one rank: the one-process code) bit for
/// bit; and the study on top of each cache (its errors and rates, `--json`) equal to 1e-9.
#[test]
fn a_reference_across_two_mpi_ranks_is_the_one_process_reference() {
    let root = std::env::temp_dir().join(format!("signorini-mpi-{}", std::process::id()));
    for dim in ["2d", "3d"] {
        let scene_text = std::fs::read_to_string(format!("scenes/bar{dim}.json")).unwrap();
        let mut scene: serde_json::Value = serde_json::from_str(&scene_text).unwrap();
        scene["discretisation"]["levels"] = serde_json::json!([10, 20]);
        scene["discretisation"]["reference_level"] = serde_json::json!(40);
        scene["discretisation"]["schemes"] = serde_json::json!(["crank-nicolson"]);
        let dir = root.join(dim);
        std::fs::create_dir_all(&dir).unwrap();
        let scene_path = dir.join("scene.json");
        std::fs::write(&scene_path, scene.to_string()).unwrap();
        let scene_arg = scene_path.to_str().unwrap();
        let caches: Vec<std::path::PathBuf> = ["one-process", "two-ranks", "one-rank"]
            .map(|c| dir.join(c))
            .into();
        let cache = |k: usize| caches[k].to_str().unwrap().to_string();
        let cg = ["--linear-solver", "cg"];
        signorini(
            None,
            &[&["reference", scene_arg, "--cache", &cache(0)][..], &cg].concat(),
        );
        let said = signorini(Some("2"), &["reference", scene_arg, "--cache", &cache(1)]);
        assert!(said.contains("computed across 2 ranks"), "{said}");
        // The check run on 20 elements: its contact slab takes every layer.
        assert!(
            said.contains("check run in one process beside rank 0"),
            "{said}"
        );
        signorini(
            Some("1"),
            &[&["reference", scene_arg, "--cache", &cache(2)][..], &cg].concat(),
        );
        let (whole, whole_bin) = read_cache(&caches[0]);
        let (two, two_bin) = read_cache(&caches[1]);
        let (one, one_bin) = read_cache(&caches[2]);
        assert!(
            one_bin == whole_bin,
            "{dim}: one rank's projections not bit for bit"
        );
        for series in HISTORIES {
            assert!(
                history(&one, series) == history(&whole, series),
                "{dim}: {series} on one rank"
            );
            let d = relative(&history(&two, series), &history(&whole, series));
            assert!(d <= 1e-10, "{dim}: {series} on two ranks: {d:e}");
        }
        assert_eq!(one["check"], whole["check"], "{dim}: one rank's check");
        let d = relative(&two_bin, &whole_bin);
        assert!(d <= 1e-10, "{dim}: projections on two ranks: {d:e}");
        let study = |k: usize| {
            let out = signorini(
                None,
                &[
                    &["study", scene_arg, "--cache", &cache(k), "--json"][..],
                    &cg,
                ]
                .concat(),
            );
            let json: serde_json::Value = serde_json::from_str(&out).unwrap();
            let mut found = Vec::new();
            numbers(&json["study"]["cases"], String::new(), &mut found);
            found
        };
        let (on_whole, on_two) = (study(0), study(1));
        assert_eq!(on_whole.len(), on_two.len());
        assert!(
            on_whole.iter().any(|(p, _)| p.contains("rate")),
            "{on_whole:?}"
        );
        for ((path, a), (_, b)) in on_two.iter().zip(&on_whole) {
            if ["timings", "seconds", "wall"]
                .iter()
                .any(|t| path.contains(t))
            {
                continue;
            }
            assert!(
                (a - b).abs() <= 1e-9 * b.abs().max(1e-300),
                "{dim}: {path}: {a:e} against {b:e}"
            );
        }
    }
    let _ = std::fs::remove_dir_all(&root);
}

/// The 3D bar's reference on 80 elements under `mpirun -n 2`: its check run on 40 elements is
/// distributed over the two ranks too (stepped by the reference's steps), and the cached
/// histories, check distances and projections are the one-process ones to 1e-10 of each one's
/// scale.
#[test]
fn the_check_run_of_a_reference_across_two_mpi_ranks_is_shared_by_them() {
    let dir = std::env::temp_dir().join(format!("signorini-mpi-check-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let mut scene: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string("scenes/bar3d.json").unwrap()).unwrap();
    scene["discretisation"]["levels"] = serde_json::json!([20, 40]);
    scene["discretisation"]["reference_level"] = serde_json::json!(80);
    scene["discretisation"]["schemes"] = serde_json::json!(["crank-nicolson"]);
    let scene_path = dir.join("scene.json");
    std::fs::write(&scene_path, scene.to_string()).unwrap();
    let scene_arg = scene_path.to_str().unwrap();
    let (whole_dir, two_dir) = (dir.join("one-process"), dir.join("two-ranks"));
    signorini(
        None,
        &[
            "reference",
            scene_arg,
            "--cache",
            whole_dir.to_str().unwrap(),
            "--linear-solver",
            "cg",
        ],
    );
    let said = signorini(
        Some("2"),
        &["reference", scene_arg, "--cache", two_dir.to_str().unwrap()],
    );
    assert!(said.contains("the check run across 2 ranks"), "{said}");
    let (whole, whole_bin) = read_cache(&whole_dir);
    let (two, two_bin) = read_cache(&two_dir);
    for series in HISTORIES {
        let d = relative(&history(&two, series), &history(&whole, series));
        assert!(d <= 1e-10, "{series} on two ranks: {d:e}");
    }
    let distances = |j: &serde_json::Value| -> Vec<f64> {
        (j["check"]["distance"].as_object().unwrap().values())
            .filter_map(serde_json::Value::as_f64)
            .collect()
    };
    assert!(!distances(&whole).is_empty(), "{}", whole["check"]);
    let d = relative(&distances(&two), &distances(&whole));
    assert!(d <= 1e-10, "check distances on two ranks: {d:e}");
    let d = relative(&two_bin, &whole_bin);
    assert!(d <= 1e-10, "projections on two ranks: {d:e}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// The scalar histories of a cached reference.
const HISTORIES: [&str; 4] = [
    "energy",
    "total_force",
    "centre_displacement",
    "centre_multiplier",
];

/// The history `series` of a cached reference's JSON.
fn history(json: &serde_json::Value, series: &str) -> Vec<f64> {
    (json[series].as_array().unwrap().iter())
        .map(|v| v.as_f64().unwrap())
        .collect()
}

/// The JSON and the binary values of the one reference cached in `dir`.
fn read_cache(dir: &Path) -> (serde_json::Value, Vec<f64>) {
    let json =
        serde_json::from_str(&std::fs::read_to_string(cached(dir, ".json")).unwrap()).unwrap();
    let bin = std::fs::read(cached(dir, ".bin")).unwrap();
    let values = bin
        .chunks_exact(8)
        .map(|b| f64::from_le_bytes(b.try_into().unwrap()))
        .collect();
    (json, values)
}

/// A decomposition the mesh cannot give (the 3D bar's reference on 20 elements: rank 0 needs
/// the local contact operator's slab, more layers than there are) stops every rank at once,
/// each saying why, with a failing exit status: no rank is left waiting.
#[test]
fn a_decomposition_the_mesh_cannot_give_stops_every_rank() {
    let dir = std::env::temp_dir().join(format!("signorini-mpi-refused-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let mut scene: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string("scenes/bar3d.json").unwrap()).unwrap();
    scene["discretisation"]["levels"] = serde_json::json!([10]);
    scene["discretisation"]["reference_level"] = serde_json::json!(20);
    let scene_path = dir.join("scene.json");
    std::fs::write(&scene_path, scene.to_string()).unwrap();
    let out = Command::new("mpirun")
        .args([
            "--oversubscribe",
            "-n",
            "2",
            env!("CARGO_BIN_EXE_signorini"),
        ])
        .args(["reference", scene_path.to_str().unwrap(), "--cache"])
        .arg(dir.join("cache"))
        .env("OMPI_ALLOW_RUN_AS_ROOT", "1")
        .env("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1")
        .output()
        .expect("mpirun runs");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "{stderr}");
    assert!(
        stderr.contains("error: rank") && stderr.contains("allow at most"),
        "{stderr}"
    );
    assert!(
        !dir.join("cache").exists()
            || std::fs::read_dir(dir.join("cache"))
                .unwrap()
                .next()
                .is_none()
    );
    let _ = std::fs::remove_dir_all(&dir);
}
