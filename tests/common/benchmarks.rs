//! The benchmarks the tests run, read from their scene files (their only definition).

use std::path::Path;

use signorini::engine::problem::Problem1d;
use signorini::studies::benchmark;

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// The Signorini–Dirichlet benchmark of `scenes/bar1d-dirichlet.json` (§5), to `horizon`.
pub fn dirichlet(horizon: f64) -> Problem1d {
    benchmark::dirichlet(root(), horizon).expect("scenes/bar1d-dirichlet.json loads")
}

/// The clamped bar vibrating in its first mode (no obstacle, a smooth solution) of
/// `scenes/bar1d-free.json`, to `horizon`.
pub fn free_vibration(horizon: f64) -> Problem1d {
    let (_, problem) = benchmark::bar_scene(root(), "scenes/bar1d-free.json")
        .expect("scenes/bar1d-free.json loads");
    Problem1d { horizon, ..problem }
}
