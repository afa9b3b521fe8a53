//! The commands behind the make targets that write `reports/` and `golden/`: `report`,
//! `experiment`, `figures`, `stability` and `golden`. `report`, `experiment` and `stability`
//! shard: each hands its job lists to the executor `--shard` asks for.

use std::path::{Path, PathBuf};

use clap::Args;

use serde::{Deserialize, Serialize};

use super::failure::{write_output, Failure};
use super::limits::LimitArgs;
use super::options::REPORTS;
use super::sharding::{share_of_work, this_invocation, Destination, ShardArgs};
use crate::harness::files::error::Error;
use crate::harness::files::output_dir::{Replace, StagedDir};
use crate::harness::study::budget::Estimate;
use crate::harness::study::executor::{computed_here, Executor};
use crate::harness::study::Case;
use crate::studies::benchmark::DIRICHLET_SCENE;
use crate::studies::estimate;
use crate::studies::experiment::{defaults_experiment, write_defaults_experiment};
use crate::studies::extended::{extended_studies_in, write_extended_report};
use crate::studies::figures::from_reports::write_figures;
use crate::studies::golden::write_golden;
use crate::studies::gravity::{gravity_benchmark, write_gravity_report, GRAVITY_SCENE};
use crate::studies::report::{tables_report, write_report};
use crate::studies::reports_index::{reports_index, REPORTS_INDEX};
use crate::studies::stability::{hard_cases, run_suite_on, write_stability_files};

/// The arguments of `signorini report`.
#[derive(Debug, Clone, Args, Serialize, Deserialize)]
pub struct ReportArgs {
    /// Output directory.
    #[arg(long, default_value = REPORTS)]
    pub out: PathBuf,
    /// The resource limits.
    #[command(flatten)]
    pub limits: LimitArgs,
    /// Run one shard of the studies' jobs (all of the report's lists dealt as one).
    #[command(flatten)]
    pub shard: ShardArgs,
}

/// The files `report` reads: the scenes of its benchmarks.
fn report_inputs() -> Vec<PathBuf> {
    vec![PathBuf::from(GRAVITY_SCENE), PathBuf::from(DIRICHLET_SCENE)]
}

/// What `make report` runs: Tables 1–2 beside the paper into reports/.
pub fn report(args: ReportArgs) -> Result<(), Failure> {
    let executor = args.shard.executor();
    report_with(args, &executor)
}

/// [`report`] with the job lists of its studies (the gravity benchmark's, the tables' and the
/// extended table's, one after the other) handed to `executor`.
pub(crate) fn report_with(args: ReportArgs, executor: &Executor) -> Result<(), Failure> {
    let invocation = this_invocation(
        "report",
        &ReportArgs {
            out: PathBuf::from(REPORTS),
            shard: ShardArgs::default(),
            ..args.clone()
        },
        report_inputs(),
    )?;
    let ReportArgs {
        out,
        limits,
        shard: _,
    } = args;
    let root = Path::new(".");
    limits.check(share_of_work(estimate::report(root)?, executor))?;
    let destination = Destination::begin(executor, &out)?;
    let executed = executor
        .execute_lists(|batch| {
            let gravity = gravity_benchmark(root, batch)?;
            let tables = tables_report(root, batch)?;
            let extended = extended_studies_in(root, batch)?;
            Ok(gravity.zip(tables).zip(extended))
        })
        .map_err(study_failure)?;
    let Some((((gravity, tables), extended), staged)) =
        destination.receive(executed, &invocation)?
    else {
        return Ok(());
    };
    write_gravity_report(&gravity, staged.path()).map_err(Failure::runtime)?;
    out!(
        "wrote {}/gravity.md and {}/gravity/ ({} cases)",
        out.display(),
        out.display(),
        gravity.study.cases.len()
    );
    write_report(&tables, staged.path(), &staged.final_path(staged.path()))
        .map_err(Failure::runtime)?;
    out!(
        "wrote {}/tables.md and {}/rates.json ({} cases, study {:.1} s wall)",
        out.display(),
        out.display(),
        tables.study.cases.len(),
        tables.study.wall_seconds
    );
    write_extended_report(&extended, staged.path()).map_err(Failure::runtime)?;
    staged.commit()?;
    out!("wrote {}/extended.md", out.display());
    Ok(())
}

/// A failure of a study of `report` or `experiment`: shards a merge refuses are a usage error
/// (exit 2), as for every sharded command; anything else a failure (exit 1).
fn study_failure(e: Error) -> Failure {
    match e {
        Error::Shard(_) => e.into(),
        e => Failure::runtime(e),
    }
}

/// The arguments of `signorini experiment`.
#[derive(Debug, Clone, Args, Serialize, Deserialize)]
pub struct ExperimentArgs {
    /// Output directory.
    #[arg(long, default_value = REPORTS)]
    pub out: PathBuf,
    /// Run one shard of the studies' jobs (the three horizons' lists dealt as one).
    #[command(flatten)]
    pub shard: ShardArgs,
}

/// How the Tables 1–2 rates move with the horizon and the level range (`make experiment`).
pub fn experiment(args: ExperimentArgs) -> Result<(), Failure> {
    let executor = args.shard.executor();
    experiment_with(args, &executor)
}

/// [`experiment`] with the job lists of its studies handed to `executor`.
pub(crate) fn experiment_with(args: ExperimentArgs, executor: &Executor) -> Result<(), Failure> {
    let invocation = this_invocation(
        "experiment",
        &ExperimentArgs {
            out: PathBuf::from(REPORTS),
            shard: ShardArgs::default(),
        },
        vec![PathBuf::from(DIRICHLET_SCENE)],
    )?;
    let out = args.out;
    let destination = Destination::begin(executor, &out)?;
    let executed = executor
        .execute_lists(|batch| defaults_experiment(Path::new("."), batch))
        .map_err(study_failure)?;
    let Some((experiment, staged)) = destination.receive(executed, &invocation)? else {
        return Ok(());
    };
    let md = write_defaults_experiment(&experiment, staged.path()).map_err(Failure::runtime)?;
    staged.commit()?;
    let summary: Vec<&str> = md.lines().skip(4).take(7).collect();
    out!(
        "{}\nwrote {}/defaults-experiment.md",
        summary.join("\n"),
        out.display()
    );
    Ok(())
}

/// The arguments of `signorini figures`.
#[derive(Debug, Args)]
pub struct FiguresArgs {
    /// The reports directory.
    #[arg(long, default_value = REPORTS)]
    pub reports: PathBuf,
}

/// Draw the figures (SVG) from the data under a reports directory into its figures/
/// (`make figures`), and write its README.md index.
pub fn figures(args: FiguresArgs) -> Result<(), Failure> {
    let FiguresArgs { reports } = args;
    let staged = StagedDir::begin("--reports", &reports, Replace::Files)?;
    let (names, missing) = write_figures(&reports, staged.path()).map_err(Failure::runtime)?;
    let index = reports_index(&reports, &names);
    write_output(&staged.path().join(REPORTS_INDEX), index.as_bytes())?;
    staged.commit()?;
    out!(
        "wrote {} figures into {}/figures and {}/README.md",
        names.len(),
        reports.display(),
        reports.display()
    );
    for m in missing {
        out!("skipped (input missing): {m}");
    }
    Ok(())
}

/// The arguments of `signorini stability`.
#[derive(Debug, Clone, Args, Serialize, Deserialize)]
pub struct StabilityArgs {
    /// Output directory.
    #[arg(long, default_value = REPORTS)]
    pub out: PathBuf,
    /// Only the fast subset that CI guards.
    #[arg(long)]
    pub ci_subset: bool,
    /// Run one shard of the suite's runs.
    #[command(flatten)]
    pub shard: ShardArgs,
    /// The resource limits.
    #[command(flatten)]
    pub limits: LimitArgs,
}

impl StabilityArgs {
    /// The files the suite reads: the Signorini–Dirichlet scene.
    pub(crate) fn inputs(&self) -> Vec<PathBuf> {
        vec![PathBuf::from(DIRICHLET_SCENE)]
    }
}

/// The stability suite (`make stability`): every scheme × mass on the hard cases, with a
/// verdict each; writes stability.md and stability.json.
pub fn stability(args: StabilityArgs) -> Result<(), Failure> {
    let executor = args.shard.executor();
    stability_with(args, &executor)
}

/// [`stability`] with its runs handed to `executor`.
pub(crate) fn stability_with(args: StabilityArgs, executor: &Executor) -> Result<(), Failure> {
    let invocation = this_invocation(
        "stability",
        &StabilityArgs {
            out: PathBuf::from(REPORTS),
            shard: ShardArgs::default(),
            ..args.clone()
        },
        args.inputs(),
    )?;
    let StabilityArgs {
        out,
        ci_subset,
        shard: _,
        limits,
    } = args;
    let hard = hard_cases(Path::new("."), ci_subset)?;
    let suite = estimate::stability(&hard);
    // A shard runs its share of the jobs, at most the whole suite's memory; a merge runs none.
    let jobs = hard.len() * Case::paper_matrix().len();
    let share = computed_here(&vec![1; jobs], executor).len() as f64 / jobs.max(1) as f64;
    limits.check(Estimate {
        dof_steps: suite.dof_steps * share,
        ..suite
    })?;
    let destination = Destination::begin(executor, &out)?;
    let executed = run_suite_on(executor, &hard, &Case::paper_matrix())?;
    let Some((records, staged)) = destination.receive(executed, &invocation)? else {
        return Ok(());
    };
    write_stability_files(staged.path(), &hard, &records).map_err(Failure::runtime)?;
    staged.commit()?;
    let flagged = records
        .iter()
        .filter(|r| {
            !matches!(
                r.verdict,
                crate::studies::stability::Verdict::Stable
                    | crate::studies::stability::Verdict::Dissipative
            )
        })
        .count();
    out!(
        "wrote {}/stability.md ({} runs, {} flagged)",
        out.display(),
        records.len(),
        flagged
    );
    Ok(())
}

/// The arguments of `signorini golden`.
#[derive(Debug, Args)]
pub struct GoldenArgs {
    /// The repository root (scenes/ and golden/ are under it).
    #[arg(long, default_value = ".")]
    pub root: PathBuf,
    /// The resource limits.
    #[command(flatten)]
    pub limits: LimitArgs,
}

/// Regenerate the golden rates of the gated studies with their round-off sensitivity (`make
/// golden`; nothing else writes them): golden/rates-1d-dirichlet.json,
/// rates-1d-gravity.json, rates-1d-extended.json and rates-2d.json.
pub fn golden(args: GoldenArgs) -> Result<(), Failure> {
    let GoldenArgs { root, limits } = args;
    limits.check(estimate::golden(&root)?.writing(4.0))?;
    for (name, golden) in write_golden(&root).map_err(Failure::runtime)? {
        out!("wrote {name} ({} cases)", golden.cases.len());
    }
    Ok(())
}
