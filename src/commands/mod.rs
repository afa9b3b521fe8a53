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
    experiment, figures, golden, report, stability, ExperimentArgs, FiguresArgs, GoldenArgs,
    ReportArgs, StabilityArgs,
};
pub use run::{run_scene, RunArgs};
pub use sharding::{
    EnsembleShardArgs, ReferenceShardArgs, ReportShardArgs, ShardArgs, SuiteShardArgs,
};
pub use study::reference_run::{references, ReferenceRequest};
pub use study::{
    reference, rejudge, sensitivity, study_scene, ReferenceArgs, RejudgeArgs, SensitivityArgs,
    StudyArgs,
};
pub use verify::{league, verify_runs, LeagueArgs, VerifyArgs};

use std::path::PathBuf;

use options::REPORTS;

use crate::harness::study::progress::{self, Shown};
use sharding::outputs::read_shards;

/// Shows the progress of this process's subcommand on stderr while the guard lives (on a
/// terminal, without `CI`).
pub fn show_progress() -> Shown {
    let command: Vec<String> = std::env::args().skip(1).take(1).collect();
    progress::show(&format!("signorini {}", command.join(" ")))
}

/// `signorini merge`: reads the shards of one invocation ([`read_shards`]) and runs their
/// recorded request again with every job's result taken from them, with `--out` when given (else
/// the command's default): it writes, or prints, what the unsharded command does. A `reference`
/// merge finds every reference in the shared cache.
pub fn merge(args: MergeArgs) -> Result<(), Failure> {
    let shards = read_shards(&args.shards, args.out.as_deref(), &args.limits.limits())?;
    let (executor, out) = (&shards.executor, args.out);
    let reports = out.clone().unwrap_or_else(|| PathBuf::from(REPORTS));
    match shards.command.as_str() {
        "study" => {
            let request = StudyArgs {
                out,
                ..shards.request()?
            };
            study::study_scene_with(request, &shards.command_line, executor)
        }
        "stability" => {
            let request = StabilityArgs {
                out: reports,
                ..shards.request()?
            };
            reports::stability_with(request, executor)
        }
        "sensitivity" => {
            let request = SensitivityArgs {
                out: reports,
                ..shards.request()?
            };
            study::sensitivity_with(request, executor)
        }
        "reference" => study::reference_with(shards.request()?, executor, None),
        "report" => {
            let request = ReportArgs {
                out: reports,
                ..shards.request()?
            };
            reports::report_with(request, executor)
        }
        "experiment" => {
            let request = ExperimentArgs {
                out: reports,
                ..shards.request()?
            };
            reports::experiment_with(request, executor)
        }
        other => Err(Failure::usage(format!(
            "the shards are of `{other}`; allowed: shards of study, stability, sensitivity, \
             reference, report or experiment"
        ))),
    }
}
