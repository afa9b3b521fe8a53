//! The commands behind the make targets that write `reports/` and `golden/`: `report`,
//! `experiment`, `figures` (the render step), `stability` and `golden` ([`report_run`] does
//! them). `report`, `experiment` and `stability` shard.

use std::path::PathBuf;

use clap::Args;
use serde::{Deserialize, Serialize};

use super::failure::Failure;
use super::limits::LimitArgs;
use super::options::REPORTS;
use super::sharding::command_line::CommandLine;
use super::sharding::sharded::Sharded;
use super::sharding::{ReportShardArgs, SuiteShardArgs};
use crate::harness::study::executor::Executor;
use crate::harness::study::shard::Invocation;
use crate::studies::benchmark::DIRICHLET_SCENE;
use crate::studies::gravity::GRAVITY_SCENE;

mod report_run;

/// The arguments of `signorini report`.
#[derive(Debug, Clone, Args, Serialize, Deserialize)]
pub struct ReportArgs {
    /// Output directory.
    #[arg(long, default_value = REPORTS)]
    pub out: PathBuf,
    /// The resource limits.
    #[command(flatten)]
    pub limits: LimitArgs,
    /// The shard to run.
    #[command(flatten)]
    pub shard: ReportShardArgs,
}

/// The 1D part of `make report`: the gravity benchmark, Tables 1–2 beside the paper and the
/// extended table.
impl Sharded for ReportArgs {
    fn recorded(&self, out: Option<PathBuf>) -> Self {
        Self {
            out: out.unwrap_or_else(|| PathBuf::from(REPORTS)),
            shard: ReportShardArgs::default(),
            ..self.clone()
        }
    }

    fn inputs(&self) -> Vec<PathBuf> {
        vec![PathBuf::from(GRAVITY_SCENE), PathBuf::from(DIRICHLET_SCENE)]
    }

    fn executor(&self) -> Executor {
        self.shard.executor()
    }

    fn run_with(
        self,
        executor: &Executor,
        invocation: &Invocation,
        _line: &CommandLine,
    ) -> Result<(), Failure> {
        let limits = self.limits.limits();
        let said = report_run::report(&self.out, &limits, executor, invocation)?;
        out!("{said}");
        Ok(())
    }
}

/// The arguments of `signorini experiment`.
#[derive(Debug, Clone, Args, Serialize, Deserialize)]
pub struct ExperimentArgs {
    /// Output directory.
    #[arg(long, default_value = REPORTS)]
    pub out: PathBuf,
    /// The resource limits.
    #[command(flatten)]
    pub limits: LimitArgs,
    /// The shard to run.
    #[command(flatten)]
    pub shard: ReportShardArgs,
}

/// How the Tables 1–2 rates move with the horizon and the level range (`make experiment`).
impl Sharded for ExperimentArgs {
    fn recorded(&self, out: Option<PathBuf>) -> Self {
        Self {
            out: out.unwrap_or_else(|| PathBuf::from(REPORTS)),
            shard: ReportShardArgs::default(),
            ..self.clone()
        }
    }

    fn inputs(&self) -> Vec<PathBuf> {
        vec![PathBuf::from(DIRICHLET_SCENE)]
    }

    fn executor(&self) -> Executor {
        self.shard.executor()
    }

    fn run_with(
        self,
        executor: &Executor,
        invocation: &Invocation,
        _line: &CommandLine,
    ) -> Result<(), Failure> {
        let limits = self.limits.limits();
        let said = report_run::experiment(&self.out, &limits, executor, invocation)?;
        out!("{said}");
        Ok(())
    }
}

/// The arguments of `signorini figures`.
#[derive(Debug, Args)]
pub struct FiguresArgs {
    /// The reports directory: its data is read, its cross-section pages, figures/ and README.md
    /// written.
    #[arg(long, alias = "reports", default_value = REPORTS)]
    pub out: PathBuf,
    /// The resource limits.
    #[command(flatten)]
    pub limits: LimitArgs,
}

/// The render step (`make figures`): from the data under a reports directory, the pages that
/// gather several studies (schemes.md, work-precision.md), the figures (SVG) into its figures/
/// and its README.md index.
pub fn figures(args: FiguresArgs) -> Result<(), Failure> {
    out!("{}", report_run::figures(&args.out, &args.limits.limits())?);
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
    /// The shard to run.
    #[command(flatten)]
    pub shard: SuiteShardArgs,
    /// The resource limits.
    #[command(flatten)]
    pub limits: LimitArgs,
}

/// The stability suite (`make stability`): every scheme × mass on the hard cases, with a
/// verdict each; writes stability.md and stability.json.
impl Sharded for StabilityArgs {
    fn recorded(&self, out: Option<PathBuf>) -> Self {
        Self {
            out: out.unwrap_or_else(|| PathBuf::from(REPORTS)),
            shard: SuiteShardArgs::default(),
            ..self.clone()
        }
    }

    fn inputs(&self) -> Vec<PathBuf> {
        vec![PathBuf::from(DIRICHLET_SCENE)]
    }

    fn executor(&self) -> Executor {
        self.shard.executor()
    }

    fn run_with(
        self,
        executor: &Executor,
        invocation: &Invocation,
        _line: &CommandLine,
    ) -> Result<(), Failure> {
        let (limits, subset) = (self.limits.limits(), self.ci_subset);
        let said = report_run::stability(&self.out, subset, &limits, executor, invocation)?;
        out!("{said}");
        Ok(())
    }
}

/// The arguments of `signorini golden`.
#[derive(Debug, Args)]
pub struct GoldenArgs {
    /// The repository root: its scenes/ are read and its golden/ written.
    #[arg(long, alias = "root", default_value = ".")]
    pub out: PathBuf,
    /// The resource limits.
    #[command(flatten)]
    pub limits: LimitArgs,
}

/// Regenerate the golden rates of the gated studies with their round-off sensitivity (`make
/// golden`; nothing else writes them).
pub fn golden(args: GoldenArgs) -> Result<(), Failure> {
    out!("{}", report_run::golden(&args.out, &args.limits.limits())?);
    Ok(())
}
