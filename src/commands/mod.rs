//! What each subcommand of the `signorini` binary does; `main.rs` parses the arguments and
//! dispatches here. Every command prints its summary on stdout (a closed stdout is ignored:
//! `signorini list | head` must not panic) and returns a [`Failure`] with its exit code.
//!
//! Exit codes: 0 success; 2 usage errors (bad arguments, a scene file that is missing,
//! malformed or out of range); 1 failures (a run that fails, an energy balance that
//! `--check-balance` finds violated, an output that cannot be written).

/// `println!` that ignores a closed stdout.
macro_rules! out {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        let _ = writeln!(std::io::stdout(), $($arg)*);
    }};
}

mod cluster_plan;
mod command_error;
mod failure;
mod getfem;
mod limits;
mod list;
mod merge;
mod options;
mod reports;
mod run;
mod sharding;
mod study;
mod verify;

pub use cluster_plan::{cluster_plan, ClusterPlanArgs};
pub use failure::Failure;
pub use getfem::{getfem, getfem_box, GetfemArgs, GetfemBoxArgs};
pub use limits::LimitArgs;
pub use list::{list, ListArgs};
pub use merge::MergeArgs;
pub use options::{ConventionArgs, LinearSolverArgs};
pub use reports::{
    figures, golden, ExperimentArgs, FiguresArgs, GoldenArgs, ReportArgs, StabilityArgs,
};
pub use run::{run_scene, RunArgs};
pub use sharding::command_line::CommandLine;
pub use sharding::{
    EnsembleShardArgs, ReferenceShardArgs, ReportShardArgs, ShardArgs, SuiteShardArgs,
};
pub use study::reference_run::{references, ReferenceRequest};
pub use study::{rejudge, ReferenceArgs, RejudgeArgs, SensitivityArgs, StudyArgs};
pub use verify::{league, verify_runs, LeagueArgs, VerifyArgs};

use std::path::PathBuf;

use serde::{Deserialize, Serialize};

use crate::harness::study::executor::Executor;
use crate::harness::study::progress::{self, Shown};
use crate::harness::study::shard::{codec, Invocation};
use sharding::outputs::read_shards;
use sharding::sharded::Sharded;

/// Shows the progress of the subcommand of `line` on stderr while the guard lives (on a
/// terminal, without `CI`).
pub fn show_progress(line: &CommandLine) -> Shown {
    progress::show(&format!("signorini {}", line.subcommand()))
}

/// A command whose job lists shard, with its options as parsed: what `main.rs` runs, what its
/// shards record in their files (tagged with its subcommand's name) and what `merge` reads back
/// and runs again.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum ShardableCommand {
    /// `signorini study`.
    Study(StudyArgs),
    /// `signorini stability`.
    Stability(StabilityArgs),
    /// `signorini sensitivity`.
    Sensitivity(SensitivityArgs),
    /// `signorini reference`.
    Reference(ReferenceArgs),
    /// `signorini report`.
    Report(ReportArgs),
    /// `signorini experiment`.
    Experiment(ExperimentArgs),
}

impl ShardableCommand {
    /// Its subcommand's name, which names its shards' files.
    pub fn name(&self) -> &'static str {
        match self {
            Self::Study(_) => "study",
            Self::Stability(_) => "stability",
            Self::Sensitivity(_) => "sensitivity",
            Self::Reference(_) => "reference",
            Self::Report(_) => "report",
            Self::Experiment(_) => "experiment",
        }
    }

    /// Runs the command as typed on `line`: every job here, or the share of its `--shard`.
    pub fn run(self, line: &CommandLine) -> Result<(), Failure> {
        self.run_on(None, line)
    }

    /// Runs the command with `merged`'s results and `--out` when given (a merge), else as typed.
    fn run_on(
        self,
        merged: Option<(&Executor, Option<PathBuf>)>,
        line: &CommandLine,
    ) -> Result<(), Failure> {
        match self {
            Self::Study(args) => run_sharded(args, Self::Study, merged, line),
            Self::Stability(args) => run_sharded(args, Self::Stability, merged, line),
            Self::Sensitivity(args) => run_sharded(args, Self::Sensitivity, merged, line),
            Self::Reference(args) => run_sharded(args, Self::Reference, merged, line),
            Self::Report(args) => run_sharded(args, Self::Report, merged, line),
            Self::Experiment(args) => run_sharded(args, Self::Experiment, merged, line),
        }
    }
}

/// The one path of every sharded command `args` (`typed` makes it a [`ShardableCommand`]): the
/// invocation its shards record (its recorded options as the typed command, the arguments of
/// `line` and the files it reads), then the command run with `merged`'s results and `--out`, or
/// as typed.
fn run_sharded<C: Sharded>(
    args: C,
    typed: fn(C) -> ShardableCommand,
    merged: Option<(&Executor, Option<PathBuf>)>,
    line: &CommandLine,
) -> Result<(), Failure> {
    let recorded = typed(args.recorded(None));
    let invocation = Invocation {
        command: recorded.name().to_string(),
        arguments: line.shard_arguments(),
        request: codec::encode(&recorded).map_err(|e| Failure::runtime(e.to_string()))?,
        inputs: args.inputs(),
    };
    match merged {
        Some((executor, out)) => args.recorded(out).run_with(executor, &invocation, line),
        None => args.run(&invocation, line),
    }
}

/// `signorini merge`: reads the shards of one invocation ([`read_shards`]) and runs the command
/// they recorded again with every job's result taken from them, with `--out` when given (else
/// the command's default): it writes, or prints, what the unsharded command does, and a report
/// says it was made by the unsharded command line. A `reference` merge finds every reference in
/// the shared cache.
pub fn merge(args: MergeArgs) -> Result<(), Failure> {
    let shards = read_shards::<ShardableCommand>(&args.shards, &args.limits.limits())?;
    let name = shards.command.name();
    if name != shards.name {
        return Err(Failure::usage(format!(
            "the shards' files name the command `{}` but recorded `{name}`",
            shards.name
        )));
    }
    let line = CommandLine::of_merge(name, &shards.arguments, args.out.as_deref());
    let merged = Some((&shards.executor, args.out));
    shards.command.run_on(merged, &line)
}
