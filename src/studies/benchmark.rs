//! The 1D benchmarks the studies run, read from their scene files: each problem is defined once,
//! by its scene.

use std::path::Path;

use crate::harness::problem::Problem1d;
use crate::harness::study::scene::Scene;
use crate::harness::study::scene::SceneError;

/// The Signorini–Dirichlet benchmark's scene (1D paper §5, Tables 1–2), relative to the
/// repository root.
pub const DIRICHLET_SCENE: &str = "scenes/bar1d-dirichlet.json";

/// The scene `root`/`file` and its bar problem; an error naming the file when it is a box
/// scene.
pub fn bar_scene(root: &Path, file: &str) -> Result<(Scene, Problem1d), SceneError> {
    Scene::load_bar(&root.join(file), "this study runs a 1D bar")
}

/// The Signorini–Dirichlet benchmark as `root`/[`DIRICHLET_SCENE`] declares it, run to
/// `horizon` (the studies run it over one period, three, ten or a hundred).
pub fn dirichlet(root: &Path, horizon: f64) -> Result<Problem1d, SceneError> {
    let (_, problem) = bar_scene(root, DIRICHLET_SCENE)?;
    Ok(Problem1d { horizon, ..problem })
}
