//! `signorini study`, `sensitivity` and `reference`: refinement studies of a scene, their
//! round-off ensembles and the fine-mesh references of box scenes.

use std::path::{Path, PathBuf};

use clap::Args;

use serde::{Deserialize, Serialize};

use super::failure::Failure;
use super::limits::LimitArgs;
use super::options::{
    parse_contact, parse_mass, parse_norm, parse_scheme, progress_bar, warn_schemes,
    ConventionArgs, LinearSolverArgs, REPORTS,
};
use super::sharding::{complete_or_write, shard_output, this_invocation, Destination, ShardArgs};
use crate::harness::files::error::Error;
use crate::harness::files::input::Shown;
use crate::harness::files::output_dir::{Replace, StagedDir};
use crate::harness::problem::{BoxProblem, ContactTreatment, MassVariant, Scheme};
use crate::harness::run::norms::Norm;
use crate::harness::study::executor::{Executor, Jobs};
use crate::harness::study::scene::Scene;
use crate::harness::study::sensitivity::{run_sensitivity_on, EnsembleConfig};
use crate::harness::study::{budget, Case};
use crate::studies::elastic_study::files::REFERENCE_CACHE;
use crate::studies::elastic_study::reference::ReferenceCache;
use crate::studies::elastic_study::{obtain_reference, ElasticStudyConfig};
use crate::studies::scene_study::{SceneStudy, StudyChoices};
use crate::studies::tables::write_sensitivity_files;

/// The arguments of `signorini study`.
#[derive(Debug, Clone, Args, Serialize, Deserialize)]
pub struct StudyArgs {
    /// The scene file.
    pub scene: PathBuf,
    /// Schemes (repeat the option for several); default: the scene's
    /// `discretisation.schemes`, else the paper's seven.
    #[arg(long, value_parser = parse_scheme)]
    pub scheme: Vec<Scheme>,
    /// Mass variants, comma-separated; default: the paper's two (standard, redistributed).
    #[arg(long, value_delimiter = ',', value_parser = parse_mass)]
    pub mass: Vec<MassVariant>,
    /// Norms, comma-separated; default: the scene's.
    #[arg(long, value_delimiter = ',', value_parser = parse_norm)]
    pub norm: Vec<Norm>,
    /// Levels NX, comma-separated and increasing; default: the scene's.
    #[arg(long, value_delimiter = ',')]
    pub levels: Vec<usize>,
    /// Δx/Δt (default: the scene's).
    #[arg(long, allow_hyphen_values = true)]
    pub ratio: Option<f64>,
    /// Print JSON instead of markdown.
    #[arg(long)]
    pub json: bool,
    /// Box scenes: elements along the axis of the fine-mesh reference (default: the
    /// scene's `discretisation.reference_level`).
    #[arg(long)]
    pub reference_level: Option<usize>,
    /// Box scenes: write `elastic-<d>d.md`, `elastic-<d>d.json` and the figure data into this
    /// reports directory instead of printing.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Box scenes: where the fine-mesh reference is looked up and kept. Default: with --out,
    /// OUT/data/references (read and written); without, reports/data/references, read only (a
    /// study without --out or --cache writes nothing).
    #[arg(long)]
    pub cache: Option<PathBuf>,
    /// Contact treatment of every case: multiplier, penalty(gamma0=G),
    /// nitsche(theta=T,gamma0=G) (1D only). Default: the scene's, else multiplier.
    #[arg(long, value_parser = parse_contact)]
    pub contact: Option<ContactTreatment>,
    /// The schemes' implementation choices.
    #[command(flatten)]
    pub conventions: ConventionArgs,
    /// The step solver of a box scene.
    #[command(flatten)]
    pub solver: LinearSolverArgs,
    /// The resource limits.
    #[command(flatten)]
    pub limits: LimitArgs,
    /// Run one shard of the study's jobs (with --out: where its partial result file goes).
    #[command(flatten)]
    pub shard: ShardArgs,
}

impl StudyArgs {
    /// The files the study reads: its scene.
    pub(crate) fn inputs(&self) -> Vec<PathBuf> {
        vec![self.scene.clone()]
    }
}

/// `values` without repetitions, in their order; each repeated one is named on stderr
/// (`--mass standard,standard` runs the case once).
fn distinct<T: PartialEq + std::fmt::Display>(option: &str, values: Vec<T>) -> Vec<T> {
    let mut kept: Vec<T> = Vec::with_capacity(values.len());
    for v in values {
        if kept.contains(&v) {
            eprintln!("note: {option} {v} is given more than once; its cases run once");
        } else {
            kept.push(v);
        }
    }
    kept
}

/// A refinement study of a scene: the rate table of the selected cases and norms, as
/// markdown or JSON. Nothing outside the selection is computed.
pub fn study_scene(args: StudyArgs) -> Result<(), Failure> {
    let executor = args.shard.executor();
    study_scene_with(args, &invocation(), &executor)
}

/// [`study_scene`] with its jobs handed to `executor`, whose box report says it was made by
/// `command_line`.
pub(crate) fn study_scene_with(
    args: StudyArgs,
    command_line: &str,
    executor: &Executor,
) -> Result<(), Failure> {
    let invocation = this_invocation(
        "study",
        &StudyArgs {
            out: None,
            shard: ShardArgs::default(),
            ..args.clone()
        },
        args.inputs(),
    )?;
    let StudyArgs {
        scene,
        scheme,
        mass,
        norm,
        levels,
        ratio,
        json,
        reference_level,
        out,
        cache,
        contact,
        conventions,
        solver,
        limits,
        shard: _,
    } = args;
    let shard = shard_output(executor, out.as_deref())?;
    let scene = Scene::load(&scene)?;
    let study = SceneStudy::of(
        &scene,
        StudyChoices {
            schemes: distinct("--scheme", scheme),
            masses: distinct("--mass", mass),
            norms: norm,
            levels,
            ratio,
            reference_level,
            contact,
            conventions: conventions.choice(),
            linear_solver: solver.linear_solver,
        },
    )?;
    let cache = match (cache, &out) {
        (Some(dir), _) => ReferenceCache::ReadWrite(dir),
        (None, Some(out)) => ReferenceCache::ReadWrite(out.join(REFERENCE_CACHE)),
        (None, None) => ReferenceCache::ReadOnly(PathBuf::from(REPORT_REFERENCES)),
    };
    if study.has_reference() {
        cache_is_a_directory(cache.dir())?;
    }
    warn_schemes(&study.schemes());
    limits.check(study.estimate(executor))?;
    let reports = match (&shard, out) {
        (None, Some(dir)) => {
            study.check_reports_dir(&dir)?;
            Some((StagedDir::begin("--out", &dir, Replace::Files)?, dir))
        }
        _ => None,
    };
    let bar = progress_bar(study.runs());
    let mut note = |why: String| eprintln!("{why}; computing the reference");
    let executed = study.run_on(executor, &cache, &|| bar.inc(1), &mut note);
    bar.finish_and_clear();
    let Some(outcome) = complete_or_write(executed?, shard, &invocation)? else {
        return Ok(());
    };
    match reports {
        Some((staged, dir)) => {
            let written = outcome
                .write_reports(
                    staged.path(),
                    &staged.final_path(staged.path()),
                    &dir,
                    command_line,
                )
                .map_err(Failure::from)?;
            staged.commit()?;
            out!("{written}");
        }
        None => out!("{}", outcome.render(json, command_line)?),
    }
    Ok(())
}

/// The arguments of `signorini sensitivity`.
#[derive(Debug, Clone, Args, Serialize, Deserialize)]
pub struct SensitivityArgs {
    /// The scene file (a bar1d scene with an obstacle).
    pub scene: PathBuf,
    /// Perturbed members per case and level (2 to 1024).
    #[arg(long, default_value_t = 16)]
    pub members: usize,
    /// Relative noise amplitude, in (0, 1e-3].
    #[arg(long, default_value = "1e-13", allow_hyphen_values = true)]
    pub amplitude: f64,
    /// Output directory.
    #[arg(long, default_value = REPORTS)]
    pub out: PathBuf,
    /// Run one shard of the ensemble's case × level jobs.
    #[command(flatten)]
    pub shard: ShardArgs,
    /// The resource limits.
    #[command(flatten)]
    pub limits: LimitArgs,
}

impl SensitivityArgs {
    /// The files the ensemble reads: its scene.
    pub(crate) fn inputs(&self) -> Vec<PathBuf> {
        vec![self.scene.clone()]
    }
}

/// Round-off sensitivity of a bar1d scene's study (`make report`): every case and level run
/// as an ensemble of members with seeded noise of relative size A on the initial
/// displacement; writes sensitivity.md and sensitivity.json with each case's class.
pub fn sensitivity(args: SensitivityArgs) -> Result<(), Failure> {
    let executor = args.shard.executor();
    sensitivity_with(args, &executor)
}

/// [`sensitivity`] with its ensembles handed to `executor`.
pub(crate) fn sensitivity_with(args: SensitivityArgs, executor: &Executor) -> Result<(), Failure> {
    let invocation = this_invocation(
        "sensitivity",
        &SensitivityArgs {
            out: PathBuf::from(REPORTS),
            shard: ShardArgs::default(),
            ..args.clone()
        },
        args.inputs(),
    )?;
    let SensitivityArgs {
        scene,
        members,
        amplitude,
        out,
        shard: _,
        limits,
    } = args;
    let scene = Scene::load(&scene)?;
    let problem = scene.bar_problem(
        "bar1d scenes: the sensitivity command is for them (a box scene's ensemble is its \
         discretisation.sensitivity, run by `signorini study`)",
    )?;
    let cases = Case::matrix(&scene.default_schemes(), &MassVariant::PAPER);
    let ensemble = EnsembleConfig { members, amplitude };
    let norms = &scene.observables.norms;
    let config = scene.study_config();
    let runs_per_job = members as f64 + 1.0;
    let jobs = budget::jobs_per_level(&config.levels, cases.len(), executor);
    let runs: Vec<f64> = jobs.iter().map(|j| j * runs_per_job).collect();
    limits.check(budget::bar_study(
        &problem,
        &config.levels,
        config.ratio,
        &runs,
    ))?;
    let destination = Destination::begin(executor, &out)?;
    let executed = run_sensitivity_on(executor, &problem, &cases, norms, &config, ensemble)?;
    let Some((s, staged)) = destination.receive(executed, &invocation)? else {
        return Ok(());
    };
    write_sensitivity_files(&s, staged.path())
        .map_err(|e| Failure::runtime(format!("cannot write into {}: {e}", out.display())))?;
    staged.commit()?;
    for c in &s.cases {
        out!("  {:36} {}", c.case, c.class.name());
    }
    out!(
        "wrote {}/sensitivity.md and {}/sensitivity.json ({} cases × {} levels × {} members, {:.1} s wall)",
        out.display(),
        out.display(),
        s.cases.len(),
        s.config.levels.len(),
        members,
        s.wall_seconds
    );
    Ok(())
}

/// Refuses a reference cache `dir` that exists and is not a directory, before anything is
/// computed (its references could not be saved there).
fn cache_is_a_directory(dir: &Path) -> Result<(), Failure> {
    match std::fs::metadata(dir) {
        Ok(meta) if !meta.is_dir() => Err(Failure::usage(format!(
            "--cache {}: is not a directory; allowed: a directory, or a path to create one",
            Shown(dir)
        ))),
        _ => Ok(()),
    }
}

/// The arguments of `signorini reference`.
#[derive(Debug, Clone, Args, Serialize, Deserialize)]
pub struct ReferenceArgs {
    /// Box scene files.
    #[arg(required = true)]
    pub scenes: Vec<PathBuf>,
    /// Where the references are cached.
    #[arg(long, default_value = REPORT_REFERENCES)]
    pub cache: PathBuf,
    /// With --shard: the directory the shard's partial result file goes into (the references
    /// themselves go into --cache).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// The step solver.
    #[command(flatten)]
    pub solver: LinearSolverArgs,
    /// The resource limits.
    #[command(flatten)]
    pub limits: LimitArgs,
    /// Compute only shard K of N of the scenes' references (the largest first).
    #[command(flatten)]
    pub shard: ShardArgs,
}

impl ReferenceArgs {
    /// The files the command reads: its scenes.
    pub(crate) fn inputs(&self) -> Vec<PathBuf> {
        self.scenes.clone()
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

/// The fine-mesh reference of a box scene (`make reference`): reuses the cache when its
/// parameters match the scene's, says which differ otherwise, and recomputes it. Under
/// `--shard k/n` only that shard's share of the scenes (the most work first), whose job results
/// are the scenes' names: the references are in the cache.
pub fn reference(args: ReferenceArgs) -> Result<(), Failure> {
    let executor = args.shard.executor();
    reference_with(args, &executor)
}

/// [`reference`] with its scenes handed to `executor`, one at a time (each reference takes the
/// whole machine). A merge finds every reference in the cache ([`obtain_and_report`]).
pub(crate) fn reference_with(args: ReferenceArgs, executor: &Executor) -> Result<(), Failure> {
    let invocation = this_invocation(
        "reference",
        &ReferenceArgs {
            out: None,
            shard: ShardArgs::default(),
            ..args.clone()
        },
        args.inputs(),
    )?;
    let ReferenceArgs {
        scenes,
        cache,
        out,
        solver,
        limits,
        shard: _,
    } = args;
    if out.is_some() && !matches!(executor, Executor::Shard(_)) {
        return Err(Failure::usage(
            "--out is where a shard's file goes: it takes --shard K/N (the references \
             go into --cache)",
        ));
    }
    let shard = shard_output(executor, out.as_deref())?;
    cache_is_a_directory(&cache)?;
    let mut jobs = Vec::with_capacity(scenes.len());
    let mut work = Vec::with_capacity(scenes.len());
    for path in scenes {
        let scene = Scene::load(&path)?;
        let problem = scene
            .box_problem("box scenes: a reference is for them (a bar1d has an exact solution)")?;
        let mut config = ElasticStudyConfig::from_scene(&scene, None)?;
        config.settings.linear_solver = solver.linear_solver;
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
        limits.check(estimate)?;
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
        run: &|job: &ReferenceJob| obtain_and_report(job, &cache),
    })?;
    let Some(names) = complete_or_write(executed, shard, &invocation)? else {
        return Ok(());
    };
    if matches!(executor, Executor::Merge(_)) {
        for (job, name) in jobs.iter().zip(&names.results) {
            if *name != job.scene.name {
                return Err(Failure::usage(format!(
                    "the shards computed the reference of scene {name}, not of {}",
                    job.scene.name
                )));
            }
            obtain_and_report(job, &cache)?;
        }
    }
    Ok(())
}

/// Obtains the reference of `job` from `cache` (computing and caching it when the cache does
/// not match), says which it was, and returns the scene's name.
fn obtain_and_report(job: &ReferenceJob, cache: &std::path::Path) -> Result<String, Error> {
    let mut computed = false;
    let store = ReferenceCache::ReadWrite(cache.to_path_buf());
    let reference = obtain_reference(&job.problem, &job.config, &store, &mut |why| {
        computed = true;
        eprintln!("{why}; computing it");
    })?;
    out!(
        "{}: reference {} on {:?} elements, {} unknowns, {} samples: {} ({:.1} s)",
        job.scene.name,
        reference.histories.key.scheme,
        reference.mesh.counts(),
        reference.histories.dofs,
        reference.samples(),
        if computed {
            "computed and cached"
        } else {
            "the cache matches the scene's parameters"
        },
        reference.histories.seconds
    );
    Ok(job.scene.name.clone())
}

/// The references `make report` keeps, relative to the repository root.
const REPORT_REFERENCES: &str = "reports/data/references";

/// This process's command line as a user types it: `signorini` and the arguments.
pub(crate) fn invocation() -> String {
    std::iter::once("signorini".to_string())
        .chain(std::env::args().skip(1))
        .collect::<Vec<_>>()
        .join(" ")
}
