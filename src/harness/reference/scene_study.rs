//! A refinement study of a scene as a user asks for it (`signorini study`): the scene's own
//! study (its schemes, the paper's two masses, its norms, levels and ratio) with the user's
//! choices over it, measured against the reference the scene declares: the one study
//! ([`run_study_on`]) of its cases × levels, a bar's against its exact solution
//! ([`ExactSolution`]), a box's against its fine-mesh reference ([`run_fine_mesh_study_on`]).
//! The choice between the two is made here, once, from the scene's problem; what comes back
//! ([`StudyOutcome`]) is measured, and judged by the report that renders it.

use std::collections::BTreeSet;
use std::path::Path;

use super::exact::ExactSolution;
use super::fine_mesh::cache::ReferenceCache;
use super::fine_mesh::{
    run_fine_mesh_study_on, ElasticHistories, ElasticStudyConfig, FineMeshStudy,
};
use crate::harness::files::error::ParameterError;
use crate::harness::problem::{
    BoxProblem, ContactTreatment, Conventions, LinearSolver, MassVariant, Problem, Problem1d,
    Scheme, Settings, Start,
};
use crate::harness::run::norms::Norm;
use crate::harness::study::budget::{self, Estimate};
use crate::harness::study::error::Error;
use crate::harness::study::executor::{Executed, Executor};
use crate::harness::study::scene::Scene;
use crate::harness::study::sensitivity::EnsembleConfig;
use crate::harness::study::{run_study_on, Case, Study, StudyConfig};

/// What a user chooses over a scene's study; each empty list or `None` keeps the scene's.
#[derive(Debug, Clone, Default)]
pub struct StudyChoices {
    /// The schemes (default: the scene's, else the paper's seven).
    pub schemes: Vec<Scheme>,
    /// The masses (default: the paper's two).
    pub masses: Vec<MassVariant>,
    /// The norms of a bar study (default: the scene's; a box study measures every norm).
    pub norms: Vec<Norm>,
    /// The levels.
    pub levels: Vec<usize>,
    /// `Δx/Δt`.
    pub ratio: Option<f64>,
    /// The level of a box study's fine-mesh reference.
    pub reference_level: Option<usize>,
    /// The contact treatment of every case.
    pub contact: Option<ContactTreatment>,
    /// The schemes' conventions.
    pub conventions: ConventionChoice,
    /// The step solver.
    pub linear_solver: LinearSolver,
}

/// The conventions a user chooses over a scene's: a named set, and a start over it; `None`
/// keeps the scene's.
#[derive(Debug, Clone, Copy, Default)]
pub struct ConventionChoice {
    /// The named set.
    pub conventions: Option<Conventions>,
    /// The start.
    pub start: Option<Start>,
}

impl ConventionChoice {
    /// `scene`'s conventions with the choices applied over them.
    fn over(self, scene: Conventions) -> Conventions {
        let mut c = self.conventions.unwrap_or(scene);
        if let Some(start) = self.start {
            c.start = start;
        }
        c
    }
}

/// `scene`'s settings with the user's conventions and step solver over them: what every run of
/// a study or a run of the scene is solved with.
pub fn chosen_settings(
    scene: &Scene,
    conventions: ConventionChoice,
    linear_solver: LinearSolver,
) -> Settings {
    let settings = scene.settings();
    Settings {
        conventions: conventions.over(settings.conventions),
        linear_solver,
        ..settings
    }
}

/// A scene's study with the user's choices applied, measured against the reference the scene
/// declares: a bar's exact solution, or a box's fine-mesh reference.
#[derive(Debug, Clone)]
pub enum SceneStudy {
    /// Against the exact solution (a bar): its cases × levels and norms.
    Exact {
        /// The scene's name.
        scene: String,
        /// The problem.
        problem: Problem1d,
        /// The cases.
        cases: Vec<Case>,
        /// The norms measured.
        norms: BTreeSet<Norm>,
        /// Levels, ratio, horizon.
        config: StudyConfig,
    },
    /// Against the fine-mesh reference (a box): its cases × levels, every norm.
    FineMesh {
        /// The problem.
        problem: BoxProblem,
        /// Levels, reference, cases and ensemble.
        config: ElasticStudyConfig,
    },
}

/// What a study hands back, measured and not yet judged: its rates against the exact solution,
/// or against the fine-mesh reference with the reference's check and the figure data.
#[derive(Debug, Clone)]
#[allow(clippy::large_enum_variant)] // one per study, moved once
pub enum StudyOutcome {
    /// Against the exact solution.
    Exact {
        /// The scene's name.
        scene: String,
        /// The study.
        study: Study,
    },
    /// Against the fine-mesh reference.
    FineMesh {
        /// The study and the reference check.
        study: FineMeshStudy,
        /// The figure data.
        histories: ElasticHistories,
    },
}

impl SceneStudy {
    /// The study of `scene` with `choices` over its own. A reference level for a bar is
    /// refused naming `reference_level`; a mass given with `--mass` that a chosen scheme is not
    /// defined with is refused naming `--mass` (with the default masses, such a pair is left
    /// out, [`Case::matrix`]).
    pub fn of(scene: &Scene, choices: StudyChoices) -> Result<Self, Error> {
        let schemes = if choices.schemes.is_empty() {
            scene.default_schemes()
        } else {
            choices.schemes
        };
        let masses = if choices.masses.is_empty() {
            MassVariant::PAPER.to_vec()
        } else {
            let undefined = choices
                .masses
                .iter()
                .find(|&&mass| schemes.iter().any(|s| !s.is_defined_with(mass)));
            if let Some(mass) = undefined {
                return Err(ParameterError::new(
                    "--mass",
                    mass.name(),
                    "a mass every chosen scheme is defined with: contact-stabilised Newmark \
                     needs standard or lumped (its predictor is an M-projection, blind to \
                     massless dofs)",
                )
                .into());
            }
            choices.masses
        };
        let settings = chosen_settings(scene, choices.conventions, choices.linear_solver);
        match scene.problem() {
            Problem::Box(mut problem) => {
                problem.contact = choices.contact.unwrap_or(problem.contact);
                let mut config = ElasticStudyConfig::from_scene(scene, choices.reference_level)?;
                config.settings = settings;
                if !choices.levels.is_empty() {
                    config.levels = choices.levels;
                }
                config.ratio = choices.ratio.unwrap_or(config.ratio);
                config.cases = Case::matrix(&schemes, &masses);
                Ok(Self::FineMesh { problem, config })
            }
            Problem::Bar(mut problem) => {
                if let Some(level) = choices.reference_level {
                    return Err(ParameterError::new(
                        "--reference-level",
                        level,
                        "none: a fine-mesh reference is for box scenes (a bar1d study compares \
                         with its exact solution)",
                    )
                    .into());
                }
                problem.contact = choices.contact.unwrap_or(problem.contact);
                let mut config = scene.study_config();
                config.settings = settings;
                if !choices.levels.is_empty() {
                    config.levels = choices.levels;
                }
                config.ratio = choices.ratio.unwrap_or(config.ratio);
                Ok(Self::Exact {
                    scene: scene.name.clone(),
                    problem,
                    cases: Case::matrix(&schemes, &masses),
                    norms: if choices.norms.is_empty() {
                        scene.observables.norms.clone()
                    } else {
                        choices.norms.into_iter().collect()
                    },
                    config,
                })
            }
        }
    }

    /// The schemes the study runs, case by case.
    pub fn schemes(&self) -> Vec<Scheme> {
        let cases = match self {
            Self::Exact { cases, .. } => cases,
            Self::FineMesh { config, .. } => &config.cases,
        };
        cases.iter().map(|c| c.scheme).collect()
    }

    /// Whether the study compares with a fine-mesh reference (and reads or fills its cache).
    pub fn has_reference(&self) -> bool {
        matches!(self, Self::FineMesh { .. })
    }

    /// Refuses a reports directory `dir` for a study that has no report files (a bar's, which
    /// prints its tables), naming `--out`.
    pub fn check_reports_dir(&self, dir: &Path) -> Result<(), Error> {
        match self {
            Self::FineMesh { .. } => Ok(()),
            Self::Exact { .. } => Err(ParameterError::new(
                "--out",
                dir.display(),
                "none for a bar1d scene: report files are for box scenes (a bar1d study prints \
                 its tables; --out takes a shard's file with --shard)",
            )
            .into()),
        }
    }

    /// The estimate of what `executor` computes of the study here ([`budget`]).
    pub fn estimate(&self, executor: &Executor) -> Estimate {
        self.estimate_with(executor, None)
    }

    /// [`SceneStudy::estimate`] with every job also running the members of `ensemble` (a
    /// box's own `discretisation.sensitivity` when `None`).
    pub(super) fn estimate_with(
        &self,
        executor: &Executor,
        ensemble: Option<EnsembleConfig>,
    ) -> Estimate {
        match self {
            Self::Exact {
                problem,
                cases,
                config,
                ..
            } => {
                let runs_per_job = ensemble.map_or(0, |e| e.perturbed_members()) as f64 + 1.0;
                let runs: Vec<f64> = budget::jobs_per_level(&config.levels, cases.len(), executor)
                    .iter()
                    .map(|jobs| jobs * runs_per_job)
                    .collect();
                budget::bar_study(problem, &config.levels, config.ratio, &runs)
            }
            Self::FineMesh { problem, config } => {
                let members = ensemble
                    .or(config.sensitivity)
                    .map_or(0, |e| e.perturbed_members());
                budget::box_study(
                    problem,
                    &config.settings,
                    &config.levels,
                    config.reference_level,
                    config.ratio,
                    &budget::jobs_per_level(&config.levels, config.cases.len(), executor),
                    members.saturating_add(1),
                )
            }
        }
    }

    /// Runs the study's jobs through `executor`; a box study obtains its reference from
    /// `cache` first (`note` hears why a cache was not used).
    pub fn run_on(
        &self,
        executor: &Executor,
        cache: &ReferenceCache,
        note: &mut dyn FnMut(String),
    ) -> Result<Executed<StudyOutcome>, Error> {
        match self {
            Self::Exact {
                scene,
                problem,
                cases,
                norms,
                config,
            } => {
                let jobs = ExactSolution::jobs(problem, cases, norms, config)?;
                run_study_on(executor, &jobs)?.reduce(|(study, _)| {
                    Ok(StudyOutcome::Exact {
                        scene: scene.clone(),
                        study,
                    })
                })
            }
            Self::FineMesh { problem, config } => {
                run_fine_mesh_study_on(executor, problem, config, cache, note)?
                    .reduce(|(study, histories)| Ok(StudyOutcome::FineMesh { study, histories }))
            }
        }
    }
}
