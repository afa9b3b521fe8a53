//! `signorini study`, `rejudge` and `sensitivity` below the command line: a scene's refinement
//! study (its rate tables printed, or a box's reports written), a box study's findings judged
//! again from its committed file, and a scene's round-off ensembles, held to their limits, their
//! jobs handed to the executor they are given.

use std::path::{Path, PathBuf};

use super::reference_run::cache_is_a_directory;
use crate::commands::command_error::CommandError;
use crate::commands::options::cache_dir;
use crate::commands::sharding::outputs::{complete_or_write, shard_output, Destination, Received};
use crate::harness::files::output_dir::{Replace, StagedDir};
use crate::harness::reference::fine_mesh::cache::ReferenceCache;
use crate::harness::reference::scene_sensitivity::SceneSensitivity;
use crate::harness::reference::scene_study::{SceneStudy, StudyChoices};
use crate::harness::study::budget::Limits;
use crate::harness::study::decision::Verdict;
use crate::harness::study::executor::Executor;
use crate::harness::study::progress;
use crate::harness::study::scene::Scene;
use crate::harness::study::sensitivity::EnsembleConfig;
use crate::harness::study::shard::Invocation;
use crate::studies::elastic_study::rejudge;
use crate::studies::error::Error;
use crate::studies::scene_study::JudgedStudy;
use crate::studies::tables::write_sensitivity_files;

/// A study as the user asked for it.
pub struct StudyRequest {
    /// The scene file.
    pub scene: PathBuf,
    /// The cases, norms and levels chosen over the scene's.
    pub choices: StudyChoices,
    /// Print JSON instead of markdown.
    pub json: bool,
    /// A box study's reports directory (or a shard's).
    pub out: Option<PathBuf>,
    /// A box study's reference cache, when given.
    pub cache: Option<PathBuf>,
    /// The limits it is held to.
    pub limits: Limits,
}

/// Runs the study of `request` through `executor` and returns what to print: a bar's tables
/// (or JSON), a box's report, or what it wrote; a box report says it was made by
/// `command_line`.
pub fn study(
    request: StudyRequest,
    executor: &Executor,
    invocation: &Invocation,
    command_line: &str,
) -> Result<String, CommandError> {
    let StudyRequest {
        scene,
        choices,
        json,
        out,
        cache,
        limits,
    } = request;
    let shard = shard_output(executor, out.as_deref())?;
    let study = SceneStudy::of(&Scene::load(&scene)?, choices)?;
    let cache = study_cache(&study, cache)?;
    for w in study.schemes().iter().filter_map(|s| s.warning()) {
        progress::note(&format!("warning: {w}"));
    }
    study
        .estimate(executor)
        .check(&limits)
        .map_err(Error::from)?;
    let reports = match (&shard, out) {
        (None, Some(dir)) => {
            study.check_reports_dir(&dir)?;
            let staged = StagedDir::begin("--out", &dir, Replace::Files)?.reading(&[&scene])?;
            Some((staged, dir))
        }
        _ => None,
    };
    let executed = study.run_on(executor, &cache, &mut |why| progress::note(&why))?;
    let outcome = match complete_or_write(executed, shard, invocation)? {
        Received::Complete(outcome) => JudgedStudy::of(outcome),
        Received::ShardWritten(line) => return Ok(line),
    };
    Ok(match reports {
        Some((staged, dir)) => {
            let written = outcome.write_reports(staged.path(), &dir, command_line)?;
            staged.commit()?;
            written
        }
        None => outcome.render(json, command_line)?,
    })
}

/// `signorini rejudge`: the study of the box scene `scene` committed under `out` judged again
/// from its `elastic-<d>d.json` without running anything ([`rejudge::rejudge`]), its report and
/// study rewritten there; returns what it wrote and the verdicts.
pub fn rejudge(scene: &Path, out: &Path) -> Result<String, CommandError> {
    let staged = StagedDir::begin("--out", out, Replace::Files)?;
    let (study, written) = rejudge::rejudge(scene, out, staged.path())?;
    staged.commit()?;
    let count = |v: Verdict| study.findings.iter().filter(|f| f.verdict == v).count();
    let files: Vec<String> = written
        .iter()
        .map(|f| out.join(f).display().to_string())
        .collect();
    Ok(format!(
        "re-judged {}: {} findings hold, {} fail, {} undecided",
        files.join(", "),
        count(Verdict::Holds),
        count(Verdict::Fails),
        count(Verdict::Undecided)
    ))
}

/// A sensitivity study as the user asked for it.
pub struct SensitivityRequest {
    /// The scene file.
    pub scene: PathBuf,
    /// The members and their noise.
    pub ensemble: EnsembleConfig,
    /// Where sensitivity.md and sensitivity.json go (or a shard's file).
    pub out: PathBuf,
    /// A box's reference cache, when given (default: the user's, `cache_dir`).
    pub cache: Option<PathBuf>,
    /// The limits it is held to.
    pub limits: Limits,
}

/// `signorini sensitivity`: the round-off ensembles of every case and level of the scene's
/// study, a bar's or a box's ([`SceneSensitivity`]), into `out`.
pub fn sensitivity(
    request: SensitivityRequest,
    executor: &Executor,
    invocation: &Invocation,
) -> Result<String, CommandError> {
    let SensitivityRequest {
        scene,
        ensemble,
        out,
        cache,
        limits,
    } = request;
    let scene = Scene::load(&scene)?;
    let choices = StudyChoices {
        linear_solver: scene.settings().linear_solver,
        ..StudyChoices::default()
    };
    let sensitivity = SceneSensitivity::of(SceneStudy::of(&scene, choices)?, ensemble)?;
    let cache = study_cache(sensitivity.study(), cache)?;
    sensitivity
        .estimate(executor)
        .check(&limits)
        .map_err(Error::from)?;
    let destination = Destination::begin(executor, &out)?;
    let executed = sensitivity.run_on(executor, &cache, &mut |why| progress::note(&why))?;
    let (s, staged) = match destination.receive(executed, invocation)? {
        Received::Complete(value) => value,
        Received::ShardWritten(line) => return Ok(line),
    };
    let made_by = (sensitivity.initial_noise(), "signorini sensitivity");
    write_sensitivity_files(&s, made_by, staged.path())?;
    staged.commit()?;
    let mut said = s.class_lines();
    let o = out.display();
    said.push(format!(
        "wrote {o}/sensitivity.md and {o}/sensitivity.json ({} × {} levels × {} members, {:.1} s wall)",
        plural(s.cases.len(), "case"),
        s.config.levels.len(),
        ensemble.perturbed_members(),
        s.wall_seconds
    ));
    Ok(said.join("\n"))
}

/// The reference cache of `study`: `given`, else the user's ([`cache_dir`]), read and written;
/// a path that is not a directory is refused when the study has a reference to keep there.
fn study_cache(study: &SceneStudy, given: Option<PathBuf>) -> Result<ReferenceCache, CommandError> {
    let cache = ReferenceCache::ReadWrite(cache_dir(given)?);
    if study.has_reference() {
        cache_is_a_directory(cache.dir())?;
    }
    Ok(cache)
}

/// `n` and `noun`, in the plural unless `n` is 1.
fn plural(n: usize, noun: &str) -> String {
    format!("{n} {noun}{}", if n == 1 { "" } else { "s" })
}
