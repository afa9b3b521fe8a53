//! The round-off sensitivity of a scene's study (`signorini sensitivity`), for a bar or a box:
//! every case × level of its [`SceneStudy`] run as an ensemble of perturbed members
//! ([`crate::harness::study::sensitivity::Member`]) beside its unperturbed run, and each case
//! classified by the one set of rules ([`crate::harness::study::sensitivity::classify_cases`]).
//! A bar's members are measured against its exact solution
//! ([`crate::harness::study::sensitivity::run_sensitivity_on`]; noise on the initial
//! displacement), a box's against its fine-mesh reference, inside the study's own jobs
//! ([`crate::harness::reference::fine_mesh::ensemble`]; noise on the initial velocity): what
//! comes back is the same [`Sensitivity`].

use super::fine_mesh::cache::ReferenceCache;
use super::fine_mesh::{run_fine_mesh_study_on, ElasticStudyConfig};
use super::scene_study::SceneStudy;
use crate::harness::study::budget::Estimate;
use crate::harness::study::error::Error;
use crate::harness::study::executor::{Executed, Executor};
use crate::harness::study::sensitivity::{
    run_sensitivity_on, EnsembleConfig, InitialNoise, Sensitivity,
};

/// A scene's study run as a round-off ensemble of `ensemble`'s members at every case × level.
#[derive(Debug, Clone)]
pub struct SceneSensitivity {
    study: SceneStudy,
    ensemble: EnsembleConfig,
}

impl SceneSensitivity {
    /// `study` with `ensemble`'s members at every case × level (a box's own
    /// `discretisation.sensitivity` replaced by it); the ensemble checked before anything runs.
    pub fn of(study: SceneStudy, ensemble: EnsembleConfig) -> Result<Self, Error> {
        ensemble.validate()?;
        let study = match study {
            SceneStudy::FineMesh { problem, config } => SceneStudy::FineMesh {
                problem,
                config: ElasticStudyConfig {
                    sensitivity: Some(ensemble),
                    ..config
                },
            },
            exact @ SceneStudy::Exact { .. } => exact,
        };
        Ok(Self { study, ensemble })
    }

    /// The study whose cases the ensemble perturbs.
    pub fn study(&self) -> &SceneStudy {
        &self.study
    }

    /// The initial data its initial-data members carry their noise on: a bar's displacement, a
    /// box's velocity.
    pub fn initial_noise(&self) -> InitialNoise {
        match self.study {
            SceneStudy::Exact { .. } => InitialNoise::Displacement,
            SceneStudy::FineMesh { .. } => InitialNoise::Velocity,
        }
    }

    /// The estimate of what `executor` computes here: each job runs the unperturbed case and
    /// its `2K` members.
    pub fn estimate(&self, executor: &Executor) -> Estimate {
        self.study.estimate_with(executor, Some(self.ensemble))
    }

    /// Runs the ensembles through `executor`; a box's study obtains its reference from `cache`
    /// first (`note` hears why a cache was not used).
    pub fn run_on(
        &self,
        executor: &Executor,
        cache: &ReferenceCache,
        note: &mut dyn FnMut(String),
    ) -> Result<Executed<Sensitivity>, Error> {
        match &self.study {
            SceneStudy::Exact {
                problem,
                cases,
                norms,
                config,
                ..
            } => run_sensitivity_on(executor, problem, cases, norms, config, self.ensemble),
            SceneStudy::FineMesh { problem, config } => run_fine_mesh_study_on(
                executor, problem, config, cache, note,
            )?
            .reduce(|(study, _)| {
                Ok(study
                    .sensitivity
                    .expect("a box study whose configuration carries an ensemble classifies it"))
            }),
        }
    }
}
