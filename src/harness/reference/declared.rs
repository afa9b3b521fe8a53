//! The reference a scene declares, for measuring runs the harness did not compute (another
//! code's, read from its files): a bar's exact solution, or a box's fine-mesh reference with the
//! levels it is projected on. The choice between the two is made here, once, from the scene's
//! problem, as [`super::scene_study::SceneStudy::of`] makes it for a study.

use super::fine_mesh::ElasticStudyConfig;
use crate::harness::files::error::Error;
use crate::harness::problem::{BoxProblem, Problem, Problem1d};
use crate::harness::study::scene::Scene;

/// What a scene's runs are measured against.
pub enum DeclaredReference {
    /// A bar's closed-form solution (the 1D paper's Appendix).
    Exact(Problem1d),
    /// A box's run on a finer nested mesh, not obtained yet.
    FineMesh(FineMeshDeclared),
}

/// A box scene's fine-mesh reference as its scene declares it.
pub struct FineMeshDeclared {
    /// The box.
    pub problem: BoxProblem,
    /// Its study's levels, ratio, reference level and settings.
    pub config: ElasticStudyConfig,
    /// The finest fitted level ([`ElasticStudyConfig::validate`]).
    pub finest: usize,
}

impl DeclaredReference {
    /// The reference `scene` declares; a box's study configuration checked (errors name the
    /// field).
    pub fn of(scene: &Scene) -> Result<Self, Error> {
        match scene.problem() {
            Problem::Bar(problem) => Ok(Self::Exact(problem)),
            Problem::Box(problem) => {
                let config = ElasticStudyConfig::from_scene(scene, None)?;
                let finest = config.validate()?;
                Ok(Self::FineMesh(FineMeshDeclared {
                    problem,
                    config,
                    finest,
                }))
            }
        }
    }
}
