//! The 1D benchmarks the studies run, read from their scene files: each problem is defined once,
//! by its scene.

use std::path::Path;

use crate::engine::problem::{Problem, Problem1d};
use crate::harness::error::SceneError;
use crate::harness::scene::Scene;

/// The scene `root`/`file` and its bar problem; an error naming the file when it is a box
/// scene.
pub fn bar_scene(root: &Path, file: &str) -> Result<(Scene, Problem1d), SceneError> {
    let path = root.join(file);
    let scene = Scene::load(&path)?;
    match scene.problem() {
        Problem::Bar(problem) => Ok((scene, problem)),
        Problem::Box(_) => Err(SceneError::Invalid {
            path,
            field: "geometry.kind".to_string(),
            value: "box".to_string(),
            allowed: "bar1d (this study runs a 1D bar)".to_string(),
        }),
    }
}
