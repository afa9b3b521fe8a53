//! What the fixed studies of `signorini report`, `experiment`, `golden` and `stability` will cost
//! ([`crate::harness::study::budget`]), so that their commands are held to the same limits as `run`
//! and `study` before they start: each study's case × level runs with its round-off ensemble's
//! members, as one job list ([`budget::bar_runs`]), and the studies one after the other.

use std::path::Path;

use crate::harness::problem::{MassVariant, Problem1d};
use crate::harness::reference::fine_mesh::ElasticStudyConfig;
use crate::harness::study::budget::{self, Estimate};
use crate::harness::study::executor::Executor;
use crate::harness::study::scene::Scene;
use crate::harness::study::sensitivity::EnsembleConfig;
use crate::harness::study::{Case, StudyConfig};
use crate::studies::benchmark::{bar_scene, dirichlet};
use crate::studies::elastic_study::gate::ELASTIC_2D_SCENE;
use crate::studies::error::Error;
use crate::studies::experiment::EXPERIMENT_HORIZONS;
use crate::studies::extended::{extended_cases, extended_config, extended_problem, TREATMENTS};
use crate::studies::gravity::GRAVITY_SCENE;
use crate::studies::stability::{HardCase, STABILITY_ENSEMBLE};

/// `cases` cases of `problem` at every level of `config`, each run `1 + members` times.
fn study(problem: &Problem1d, config: &StudyConfig, cases: usize, members: usize) -> Estimate {
    let runs = (cases * (1 + members)) as f64;
    budget::bar_runs(
        config
            .levels
            .iter()
            .map(|&nx| (problem, nx, config.ratio, runs)),
    )
}

/// The Tables 1–2 study and its sensitivity (`make report`, `make golden`).
fn tables(root: &Path) -> Result<Estimate, Error> {
    let config = StudyConfig::paper_default();
    let problem = dirichlet(root, config.horizon)?;
    let members = EnsembleConfig::default().perturbed_members();
    Ok(study(
        &problem,
        &config,
        Case::tables_matrix().len(),
        members,
    ))
}

/// The gravity study and its sensitivity.
fn gravity(root: &Path) -> Result<Estimate, Error> {
    let (scene, problem) = bar_scene(root, GRAVITY_SCENE)?;
    let cases = scene.default_schemes().len() * MassVariant::PAPER.len();
    let members = EnsembleConfig::default().perturbed_members();
    Ok(study(&problem, &scene.study_config(), cases, members))
}

/// The extended table: one study per contact treatment, with its sensitivity.
fn extended(root: &Path) -> Result<Estimate, Error> {
    let config = extended_config();
    let members = EnsembleConfig::default().perturbed_members();
    TREATMENTS
        .iter()
        .try_fold(Estimate::default(), |total, name| {
            let problem = extended_problem(root, name)?;
            Ok(total.then(study(&problem, &config, extended_cases().len(), members)))
        })
}

/// What `signorini report` runs: the gravity, Tables 1–2 (with the histories, a fraction of
/// it) and extended studies.
pub fn report(root: &Path) -> Result<Estimate, Error> {
    Ok(gravity(root)?.then(tables(root)?).then(extended(root)?))
}

/// What `signorini golden` runs: the studies of [`report`] and the gated 2D study with its
/// ensemble, its reference computed afresh.
pub fn golden(root: &Path) -> Result<Estimate, Error> {
    let scene = Scene::load(&root.join(ELASTIC_2D_SCENE))?;
    let Ok(problem) = scene.box_problem("a box scene: the gated 2D study's") else {
        return report(root);
    };
    let config = ElasticStudyConfig::from_scene(&scene, None)?;
    let members = config.sensitivity.map_or(0, |e| e.perturbed_members());
    let jobs = budget::jobs_per_level(&config.levels, config.cases.len(), &Executor::Local);
    let elastic = budget::box_study(
        &problem,
        &config.settings,
        &config.levels,
        config.reference_level,
        config.ratio,
        &jobs,
        1 + members,
    );
    Ok(report(root)?.then(elastic))
}

/// The stability suite over `hard` cases: every case of the tables (the paper's and the
/// rivals') on each, with its ensemble.
pub fn stability(hard: &[HardCase]) -> Estimate {
    let cases = Case::tables_matrix().len();
    let runs = (cases * (1 + STABILITY_ENSEMBLE.members)) as f64;
    budget::bar_runs(hard.iter().map(|h| (&h.problem, h.nx, h.ratio, runs)))
}

/// What `signorini experiment` runs: the Tables 1–2 study at every horizon of
/// [`EXPERIMENT_HORIZONS`], without ensembles.
pub fn experiment(root: &Path) -> Result<Estimate, Error> {
    let cases = Case::paper_matrix().len();
    EXPERIMENT_HORIZONS
        .iter()
        .try_fold(Estimate::default(), |total, &horizon| {
            let config = StudyConfig {
                horizon,
                ..StudyConfig::paper_default()
            };
            let problem = dirichlet(root, horizon)?;
            Ok(total.then(study(&problem, &config, cases, 0)))
        })
}
