//! The commands behind the make targets that write `reports/` and `golden/`: `report`,
//! `experiment`, `figures`, `stability` and `golden`.

use std::path::{Path, PathBuf};

use clap::Args;

use serde::{Deserialize, Serialize};

use super::failure::{write_output, Failure};
use super::limits::LimitArgs;
use super::options::REPORTS;
use super::sharding::{this_invocation, Destination, ShardArgs};
use crate::harness::files::output_dir::{Replace, StagedDir};
use crate::harness::study::budget::Estimate;
use crate::harness::study::executor::{computed_here, Executor};
use crate::harness::study::Case;
use crate::studies::benchmark::DIRICHLET_SCENE;
use crate::studies::estimate;
use crate::studies::experiment::write_defaults_experiment;
use crate::studies::extended::write_extended_report;
use crate::studies::figures::from_reports::{reports_index, write_figures, REPORTS_INDEX};
use crate::studies::golden::write_golden;
use crate::studies::gravity::write_gravity_report;
use crate::studies::report::write_report;
use crate::studies::stability::{hard_cases, run_suite_on, write_stability_files};

/// The arguments of `signorini report`.
#[derive(Debug, Args)]
pub struct ReportArgs {
    /// Output directory.
    #[arg(long, default_value = REPORTS)]
    pub out: PathBuf,
    /// The resource limits.
    #[command(flatten)]
    pub limits: LimitArgs,
}

/// What `make report` runs: Tables 1–2 beside the paper into reports/.
pub fn report(args: ReportArgs) -> Result<(), Failure> {
    let ReportArgs { out, limits } = args;
    limits.check(estimate::report(Path::new("."))?)?;
    let staged = StagedDir::begin("--out", &out, Replace::Files)?;
    let gravity = write_gravity_report(Path::new("."), staged.path()).map_err(Failure::runtime)?;
    out!(
        "wrote {}/gravity.md and {}/gravity/ ({} cases)",
        out.display(),
        out.display(),
        gravity.cases.len()
    );
    let study = write_report(
        Path::new("."),
        staged.path(),
        &staged.final_path(staged.path()),
    )
    .map_err(Failure::runtime)?;
    out!(
        "wrote {}/tables.md and {}/rates.json ({} cases, study {:.1} s wall)",
        out.display(),
        out.display(),
        study.cases.len(),
        study.wall_seconds
    );
    write_extended_report(Path::new("."), staged.path()).map_err(Failure::runtime)?;
    staged.commit()?;
    out!("wrote {}/extended.md", out.display());
    Ok(())
}

/// The arguments of `signorini experiment`.
#[derive(Debug, Args)]
pub struct ExperimentArgs {
    /// Output directory.
    #[arg(long, default_value = REPORTS)]
    pub out: PathBuf,
}

/// How the Tables 1–2 rates move with the horizon and the level range (`make experiment`).
pub fn experiment(args: ExperimentArgs) -> Result<(), Failure> {
    let ExperimentArgs { out } = args;
    let staged = StagedDir::begin("--out", &out, Replace::Files)?;
    let md = write_defaults_experiment(Path::new("."), staged.path()).map_err(Failure::runtime)?;
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
    let index = reports_index(&names, &|file| reports.join(file).is_file());
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
