//! The memory estimate of a box run follows its step solver (issue 19): the matrix-free `cg`
//! path is linear in the unknowns, the Cholesky fill's is not, so the 3D level-320 reference
//! (1.05 M unknowns) fits the 6 GB with `auto` and would not with `direct`.

use std::path::Path;

use signorini::engine::linalg::LinearSolver;
use signorini::engine::problem::{Problem, Settings};
use signorini::harness::run::elastic::BoxProblem;
use signorini::harness::study::budget;
use signorini::harness::study::executor::Executor;
use signorini::harness::study::scene::Scene;

fn bar3d() -> BoxProblem {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/bar3d.json");
    let Problem::Box(problem) = Scene::load(&path).unwrap().problem() else {
        panic!("bar3d is a box scene")
    };
    problem
}

/// The default settings with the step solver `solver`.
fn solved_by(linear_solver: LinearSolver) -> Settings {
    Settings {
        linear_solver,
        ..Settings::default()
    }
}

#[test]
fn a_box_runs_memory_estimate_follows_its_step_solver() {
    let gib = |solver, nx| {
        budget::box_run(&bar3d(), &solved_by(solver), nx, 2.0, 0, false).memory_bytes
            / 1024f64.powi(3)
    };
    let (auto, direct) = (gib(LinearSolver::Auto, 320), gib(LinearSolver::Direct, 320));
    assert!(auto < 6.0, "auto (cg) at level 320: {auto} GiB");
    assert!(
        direct > 4.0 * auto,
        "direct at level 320: {direct} GiB, cg {auto} GiB"
    );
    // Below the auto threshold the two choices are the same solver.
    assert_eq!(gib(LinearSolver::Auto, 20), gib(LinearSolver::Direct, 20));
    // Measured peaks (CN `M^mod`, `/usr/bin/time`) stay under the estimate: 55.6 MB at level
    // 80, 89.5 MB at level 160, 273 MB at level 320.
    let mib = |nx| gib(LinearSolver::Auto, nx) * 1024.0;
    for (nx, measured) in [(80, 55.6), (160, 89.5), (320, 273.0)] {
        assert!(mib(nx) > measured, "level {nx}: {} MiB", mib(nx));
    }
}

/// A shard's budget is its share's (issue 19, item 4): the shards' job counts per level add up
/// to the whole study's, each level's jobs go round the shards from the largest level down, and
/// a shard's work is a fraction of the study's.
#[test]
fn a_shard_is_budgeted_for_its_own_jobs() {
    use signorini::harness::study::shard::ShardSpec;

    let levels = [10, 20, 40, 80];
    let whole = budget::jobs_per_level(&levels, 4, &Executor::Local);
    assert_eq!(whole, [4.0; 4]);
    let shards: Vec<Vec<f64>> = (1..=3)
        .map(|k| budget::jobs_per_level(&levels, 4, &Executor::Shard(ShardSpec { k, n: 3 })))
        .collect();
    for l in 0..levels.len() {
        let sum: f64 = shards.iter().map(|s| s[l]).sum();
        assert_eq!(sum, 4.0, "level {}", levels[l]);
    }
    // The largest-first order deals level 80's four jobs to shards 1, 2, 3, 1.
    assert_eq!(shards[0][3], 2.0);
    assert_eq!(shards[1][3], 1.0);
    let (problem, settings) = (bar3d(), Settings::default());
    let work = |jobs: &[f64]| {
        budget::box_study(&problem, &settings, &levels[..3], 80, 2.0, jobs, 9).dof_steps
    };
    let reference = work(&[0.0; 3]);
    let (all, one) = (
        work(&budget::jobs_per_level(&levels[..3], 4, &Executor::Local)),
        work(&budget::jobs_per_level(
            &levels[..3],
            4,
            &Executor::Shard(ShardSpec { k: 1, n: 4 }),
        )),
    );
    assert!(
        one - reference < 0.5 * (all - reference),
        "a quarter of the jobs: {one} of {all} dof-steps, the reference's {reference}"
    );
}

/// A box study's memory estimate holds its measured peak (`/usr/bin/time`, the reference
/// computed, 4 cases × 9 runs per level): 159 MB for `scenes/bar3d.json` (levels 10–40 against
/// 160) and 9.12 GB for `scenes/bar3d-finest.json` (10–160 against 640, 2026-11-26), whose
/// projections hold two Cholesky factors of the level-160 norm matrices: without them the
/// estimate was 6.9 GiB.
#[test]
fn a_box_studys_memory_estimate_holds_its_measured_peak() {
    let (problem, settings) = (bar3d(), Settings::default());
    for (levels, reference, measured_kb) in [
        (&[10, 20, 40][..], 160, 159_116.0),
        (&[10, 20, 40, 80, 160][..], 640, 9_115_872.0),
    ] {
        let jobs = budget::jobs_per_level(levels, 4, &Executor::Local);
        let estimate =
            budget::box_study(&problem, &settings, levels, reference, 2.0, &jobs, 9).memory_bytes;
        assert!(
            estimate > 1024.0 * measured_kb,
            "levels {levels:?} against {reference}: estimated {estimate} bytes, measured {measured_kb} kB"
        );
    }
}
