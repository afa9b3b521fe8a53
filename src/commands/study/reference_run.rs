//! `signorini reference` below the command line: the fine-mesh references of box scenes,
//! taken from their cache when it matches, computed (their steps counted in the progress shown)
//! and cached otherwise, one scene at a time.

use std::path::{Path, PathBuf};
use std::time::Instant;

use crate::commands::command_error::CommandError;
use crate::commands::options::cache_dir;
use crate::commands::sharding::outputs::{complete_or_write, shard_output, Received};
use crate::harness::files::input::Shown;
use crate::harness::problem::{BoxProblem, LinearSolver};
use crate::harness::reference::fine_mesh::cache::{self, ReferenceCache};
use crate::harness::reference::fine_mesh::fine_run::{FineReference, FineRunCost};
use crate::harness::reference::fine_mesh::{obtain_reference, reference_key, ElasticStudyConfig};
use crate::harness::run::distributed::Ranks;
use crate::harness::study::budget::{self, human_bytes, Estimate, Limits};
use crate::harness::study::error::Error;
use crate::harness::study::executor::{Executor, Jobs};
use crate::harness::study::progress;
use crate::harness::study::scene::Scene;
use crate::harness::study::shard::Invocation;
use crate::studies::cluster_plan::Measurement;

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

/// The references a user asked for.
pub struct ReferenceRequest<'a> {
    /// The box scene files.
    pub scenes: Vec<PathBuf>,
    /// Where the references are cached, when given (default: the user's, `cache_dir`).
    pub cache: Option<PathBuf>,
    /// A shard's output directory.
    pub out: Option<PathBuf>,
    /// The step solver.
    pub linear_solver: LinearSolver,
    /// The limits each reference is held to.
    pub limits: Limits,
    /// The ranks of a distributed run (this process one of them), or `None` for one process.
    pub ranks: Option<&'a dyn Ranks>,
    /// Where to write what the reference's computation cost ([`Measurement`]).
    pub measure: Option<PathBuf>,
}

/// The references of the box scenes `scenes` in `cache`, solved with `linear_solver`, each held
/// to `limits`: under a shard only its share of the scenes (the most work first), written with
/// the shard's file into `out`; a merge finds every reference in the cache. Tells `say` how
/// each reference was obtained as it is, and returns what was written last, for the user.
///
/// With ranks, every rank runs this with the same request: the scenes in turn (no shard),
/// rank 0 obtaining each reference as one process does, the others sharing its fine run's
/// steps when it computes one ([`FineReference::follow`]); they return an empty line.
pub fn references(
    request: ReferenceRequest<'_>,
    executor: &Executor,
    invocation: &Invocation,
    say: &(dyn Fn(&str) + Sync),
) -> Result<String, CommandError> {
    let ReferenceRequest {
        scenes,
        cache,
        out,
        linear_solver,
        limits,
        ranks,
        measure,
    } = request;
    let cache = cache_dir(cache)?;
    let (cache, out) = (cache.as_path(), out.as_deref());
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
    for path in &scenes {
        let scene = Scene::load(path)?;
        let problem = scene
            .box_problem("box scenes: a reference is for them (a bar1d has an exact solution)")?;
        let mut config = ElasticStudyConfig::from_scene(&scene, None)?;
        config.settings.linear_solver = linear_solver;
        let estimate = config.reference_estimate(&problem);
        work.push(estimate.dof_steps as usize);
        match ranks {
            None => estimate.check(&limits).map_err(Error::from)?,
            Some(ranks) => check_rank(estimate, (&problem, &config), &limits, ranks)?,
        }
        jobs.push(ReferenceJob {
            index: jobs.len(),
            scene,
            problem,
            config,
        });
    }
    if let Some(path) = &measure {
        return measured(&jobs, executor, (cache, ranks), path, say);
    }
    if let Some(ranks) = ranks {
        return on_ranks(&jobs, executor, (cache, ranks), say);
    }
    let executed = executor.execute_in_turn(&Jobs {
        items: &jobs,
        size: &|job: &ReferenceJob| work[job.index],
        run: &|job: &ReferenceJob| {
            obtain_and_report(job, (cache, None), say).map(|_| job.scene.name.clone())
        },
    })?;
    let names = match complete_or_write(executed, shard, invocation)? {
        Received::Complete(names) => names.results,
        Received::ShardWritten(line) => return Ok(line),
    };
    if matches!(executor, Executor::Merge(_)) {
        for (job, name) in jobs.iter().zip(&names) {
            if *name != job.scene.name {
                return Err(CommandError::Refused(format!(
                    "the shards computed the reference of scene {name}, not of {}",
                    job.scene.name
                )));
            }
            obtain_and_report(job, (cache, None), say)?;
        }
    }
    Ok(format!("the references are in {}", cache.display()))
}

/// `limits` on this rank of a reference across `ranks` (every rank together): its memory with
/// the other ranks' on its machine (rank 0 holding what one process holds, `estimate`, the
/// others [`budget::reference_rank`]), and the work on rank 0. When any rank refuses, every
/// rank stops: the one that refused says why.
fn check_rank(
    estimate: Estimate,
    (problem, config): (&BoxProblem, &ElasticStudyConfig),
    limits: &Limits,
    ranks: &dyn Ranks,
) -> Result<(), CommandError> {
    let other = budget::reference_rank(problem, config.reference_level, ranks.size());
    let sharing = ranks.on_this_machine().max(1);
    let others_here = (sharing - 1) as f64 * other.memory_bytes;
    let mine = if ranks.rank() == 0 {
        Estimate {
            memory_bytes: estimate.memory_bytes + others_here,
            ..estimate
        }
    } else {
        Estimate {
            memory_bytes: other.memory_bytes + others_here,
            ..other
        }
    };
    let own = mine.check(limits);
    let refusals = ranks.sum(if own.is_err() { 1.0 } else { 0.0 });
    match own {
        Err(e) => Err(CommandError::Refused(format!(
            "rank {} of {}, with {sharing} rank(s) on its machine (rank 0 {}, each other rank \
             {}): {e}; allowed: fewer ranks on a machine, or more memory",
            ranks.rank(),
            ranks.size(),
            human_bytes(estimate.memory_bytes),
            human_bytes(other.memory_bytes),
        ))),
        Ok(()) if refusals > 0.0 => Err(CommandError::Refused(
            "another rank's budget refused the reference (it says why)".into(),
        )),
        Ok(()) => Ok(()),
    }
}

/// The reference of the one scene of `jobs`, computed (never read from `cache`: a cached
/// reference costs nothing to measure), on `ranks` when given, and what it cost written to
/// `path` ([`Measurement`]) by rank 0.
fn measured(
    jobs: &[ReferenceJob],
    executor: &Executor,
    (cache, ranks): (&Path, Option<&dyn Ranks>),
    path: &Path,
    say: &(dyn Fn(&str) + Sync),
) -> Result<String, CommandError> {
    let [job] = jobs else {
        return Err(CommandError::Refused(format!(
            "--measure {}: measures one reference; allowed: one scene, not {}",
            path.display(),
            jobs.len()
        )));
    };
    if !matches!(executor, Executor::Local) {
        return Err(CommandError::Refused(
            "--measure measures a reference computed here; run it without --shard".into(),
        ));
    }
    let key = reference_key(&job.problem, &job.config)?;
    if cache::cache_paths(cache, &key.stem()).0.exists() {
        return Err(CommandError::Refused(format!(
            "--measure: the reference of {} is in --cache {} already, and reading it measures \
             nothing; give an empty --cache",
            job.scene.name,
            cache.display()
        )));
    }
    let reference = match ranks {
        Some(r) if r.rank() > 0 => {
            FineReference::follow(&job.problem, &job.config.settings, &key, r)?;
            None
        }
        _ => Some(obtain_and_report(job, (cache, ranks), say)?),
    };
    match Measurement::gather(&job.scene.name, reference.as_ref(), ranks) {
        Some(measurement) => {
            measurement.write(path)?;
            Ok(format!("what it cost is in {}", path.display()))
        }
        None => Ok(String::new()),
    }
}

/// The references of `jobs` on `ranks`, in turn (see [`references`]): refused under a shard
/// or a merge, whose jobs are whole references.
fn on_ranks(
    jobs: &[ReferenceJob],
    executor: &Executor,
    (cache, ranks): (&Path, &dyn Ranks),
    say: &(dyn Fn(&str) + Sync),
) -> Result<String, CommandError> {
    if !matches!(executor, Executor::Local) {
        return Err(CommandError::Refused(
            "--shard: a reference run across MPI ranks computes its scenes in turn, each \
             across every rank; run it without --shard (or shard without mpirun)"
                .into(),
        ));
    }
    for job in jobs {
        if ranks.rank() == 0 {
            obtain_and_report(job, (cache, Some(ranks)), say)?;
        } else {
            let key = reference_key(&job.problem, &job.config)?;
            FineReference::follow(&job.problem, &job.config.settings, &key, ranks)?;
        }
    }
    Ok(if ranks.rank() == 0 {
        format!(
            "the references are in {} (computed across {} ranks)",
            cache.display(),
            ranks.size()
        )
    } else {
        String::new()
    })
}

/// Obtains the reference of `job` from `cache` (computing and caching it when the cache does
/// not match), tells `say` which it was, with the time it took now, and returns it.
fn obtain_and_report(
    job: &ReferenceJob,
    (cache, ranks): (&Path, Option<&dyn Ranks>),
    say: &(dyn Fn(&str) + Sync),
) -> Result<FineReference, Error> {
    let clock = Instant::now();
    let store = ReferenceCache::ReadWrite(cache.to_path_buf());
    let reference = obtain_reference(
        &job.problem,
        &job.config,
        (&store, ranks),
        &mut |why| progress::note(&why),
        &|| Ok(()),
    )?;
    let seconds = clock.elapsed().as_secs_f64();
    let (json, bin) = cache::cache_paths(cache, &reference.histories.key.stem());
    let how = match reference.cost {
        Some(FineRunCost {
            timings: t,
            check_ranks,
            ..
        }) => format!(
            "computed and cached in {seconds:.1} s (the fine run: setup {:.1} s, steps {:.1} s, \
             contact {:.1} s, projections and check {:.1} s; the check run {}; wrote {} and {})",
            t.setup,
            t.stepping,
            t.contact,
            t.observe,
            match (ranks.map_or(1, |r| r.size()), check_ranks) {
                (1, _) => "in one process beside it".to_string(),
                (_, 1) => "in one process beside rank 0 (its contact slab leaves no layer for \
                           some rank)"
                    .to_string(),
                (_, n) => format!("across {n} ranks"),
            },
            json.display(),
            bin.display()
        ),
        None => format!(
            "the cache matches the scene's parameters; read from {} in {seconds:.1} s \
             (computing it took {:.1} s)",
            json.display(),
            reference.histories.seconds
        ),
    };
    let said = format!(
        "{}: reference {} on {:?} elements, {} unknowns, {} samples: {how}",
        job.scene.name,
        reference.histories.key.scheme,
        reference.mesh.counts(),
        reference.histories.dofs,
        reference.samples(),
    );
    progress::suspended(|| say(&said));
    Ok(reference)
}
