//! The memory estimate of a box run follows its step solver (issue 19): the matrix-free `cg`
//! path is linear in the unknowns, the Cholesky fill's is not, so the 3D level-320 reference
//! (1.05 M unknowns) fits the 6 GB with `auto` and would not with `direct`.

use std::path::Path;

use signorini::elastic::BoxProblem;
use signorini::harness::budget;
use signorini::linalg::LinearSolver;
use signorini::problem::Problem;
use signorini::scene::Scene;

fn bar3d(solver: LinearSolver) -> BoxProblem {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/bar3d.json");
    let Problem::Box(problem) = Scene::load(&path).unwrap().problem() else {
        panic!("bar3d is a box scene")
    };
    BoxProblem {
        linear_solver: solver,
        ..problem
    }
}

#[test]
fn a_box_runs_memory_estimate_follows_its_step_solver() {
    let gib = |solver, nx| {
        budget::box_run(&bar3d(solver), nx, 2.0, 0, false).memory_bytes / 1024f64.powi(3)
    };
    let (auto, direct) = (gib(LinearSolver::Auto, 320), gib(LinearSolver::Direct, 320));
    assert!(auto < 6.0, "auto (cg) at level 320: {auto} GiB");
    assert!(
        direct > 4.0 * auto,
        "direct at level 320: {direct} GiB, cg {auto} GiB"
    );
    // Below the auto threshold the two choices are the same solver.
    assert_eq!(gib(LinearSolver::Auto, 20), gib(LinearSolver::Direct, 20));
    // Measured peaks (README "2D and 3D bars") stay under the estimate: 83 MB at level 80,
    // 439 MB at level 160.
    assert!(gib(LinearSolver::Auto, 80) * 1024.0 > 83.0);
    assert!(gib(LinearSolver::Auto, 160) * 1024.0 > 439.0);
}
