//! `signorini reference` below the command line: the fine-mesh references of box scenes,
//! taken from their cache when it matches, computed (their steps counted in the progress shown)
//! and cached otherwise, one scene at a time.

use std::path::{Path, PathBuf};
use std::time::Instant;

use crate::harness::files::error::Error;
use crate::harness::files::input::Shown;
use crate::harness::problem::{BoxProblem, LinearSolver};
use crate::harness::study::budget::{self, Limits};
use crate::harness::study::executor::{Executor, Jobs};
use crate::harness::study::progress;
use crate::harness::study::scene::Scene;
use crate::harness::study::shard::Invocation;
use crate::studies::elastic_study::reference::{Reference, ReferenceCache};
use crate::studies::elastic_study::{obtain_reference, ElasticStudyConfig};
use crate::studies::outputs::{complete_or_write, shard_output, CommandError, Received};

/// The references `make report` keeps, relative to the repository root.
pub const REPORT_REFERENCES: &str = "reports/data/references";

/// Refuses a reference cache `dir` that exists and is not a directory, before anything is
/// computed (its references could not be saved there).
pub fn cache_is_a_directory(dir: &Path) -> Result<(), CommandError> {
    match std::fs::metadata(dir) {
        Ok(meta) if !meta.is_dir() => Err(CommandError::Refused(format!(
            "--cache {}: is not a directory; allowed: a directory, or a path to create one",
            Shown(dir)
        ))),
        _ => Ok(()),
    }
}

/// A box scene whose reference is to be obtained, with its study configuration.
struct ReferenceJob {
    /// Its place among the command's scenes.
    index: usize,
    scene: Scene,
    problem: BoxProblem,
    config: ElasticStudyConfig,
}

/// The references of the box scenes `scenes` in `cache`, solved with `linear_solver`, each held
/// to `limits`: under a shard only its share of the scenes (the most work first), written with
/// the shard's file into `out`; a merge finds every reference in the cache. Returns what it
/// did, for the user.
pub fn references(
    scenes: &[PathBuf],
    cache: &Path,
    out: Option<&Path>,
    linear_solver: LinearSolver,
    limits: &Limits,
    executor: &Executor,
    invocation: &Invocation,
) -> Result<String, CommandError> {
    if out.is_some() && !matches!(executor, Executor::Shard(_)) {
        return Err(CommandError::Refused(
            "--out is where a shard's file goes: it takes --shard K/N (the references \
             go into --cache)"
                .into(),
        ));
    }
    let shard = shard_output(executor, out)?;
    cache_is_a_directory(cache)?;
    let mut jobs = Vec::with_capacity(scenes.len());
    let mut work = Vec::with_capacity(scenes.len());
    for path in scenes {
        let scene = Scene::load(path)?;
        let problem = scene
            .box_problem("box scenes: a reference is for them (a bar1d has an exact solution)")?;
        let mut config = ElasticStudyConfig::from_scene(&scene, None)?;
        config.settings.linear_solver = linear_solver;
        let estimate = budget::box_study(
            &problem,
            &config.settings,
            &config.levels,
            config.reference_level,
            config.ratio,
            &[],
            0,
        );
        work.push(estimate.dof_steps as usize);
        estimate.check(limits).map_err(Error::from)?;
        jobs.push(ReferenceJob {
            index: jobs.len(),
            scene,
            problem,
            config,
        });
    }
    let executed = executor.execute_in_turn(&Jobs {
        items: &jobs,
        size: &|job: &ReferenceJob| work[job.index],
        run: &|job: &ReferenceJob| obtain_and_report(job, cache),
    })?;
    let said = match complete_or_write(executed, shard, invocation)? {
        Received::Complete(said) => said.results,
        Received::ShardWritten(line) => return Ok(line),
    };
    if !matches!(executor, Executor::Merge(_)) {
        return Ok(said.join("\n"));
    }
    let mut again = Vec::with_capacity(jobs.len());
    for (job, line) in jobs.iter().zip(&said) {
        if !line.starts_with(&format!("{}:", job.scene.name)) {
            return Err(CommandError::Refused(format!(
                "the shards did not compute the reference of scene {}: {line}",
                job.scene.name
            )));
        }
        again.push(obtain_and_report(job, cache)?);
    }
    Ok(again.join("\n"))
}

/// Obtains the reference of `job` from `cache` (computing and caching it when the cache does
/// not match) and says which it was, with the time it took now.
fn obtain_and_report(job: &ReferenceJob, cache: &Path) -> Result<String, Error> {
    let clock = Instant::now();
    let store = ReferenceCache::ReadWrite(cache.to_path_buf());
    let reference = obtain_reference(&job.problem, &job.config, &store, &mut |why| {
        progress::note(&why);
    })?;
    let seconds = clock.elapsed().as_secs_f64();
    let (json, bin) = Reference::cache_paths(cache, &reference.histories.key.stem());
    let how = match reference.from_cache {
        false => format!(
            "computed in {seconds:.1} s; wrote {} and {}",
            json.display(),
            bin.display()
        ),
        true => format!(
            "read from {} in {seconds:.1} s (computing it took {:.1} s)",
            json.display(),
            reference.histories.seconds
        ),
    };
    Ok(format!(
        "{}: reference {} on {:?} elements, {} unknowns, {} samples: {how}",
        job.scene.name,
        reference.histories.key.scheme,
        reference.mesh.counts(),
        reference.histories.dofs,
        reference.samples(),
    ))
}
