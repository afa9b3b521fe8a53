//! `--shard k/n` on the commands that run a study (`study`, `stability`, `sensitivity`,
//! `reference`, `report`, `experiment`): the option, the executor it asks for, the share of the
//! work a shard is held to, and how a shard writes its partial result file into `--out`
//! ([`crate::harness::study::shard`]).

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use super::failure::Failure;
use crate::harness::files::artifacts::write_json;
use crate::harness::files::error::ParameterError;
use crate::harness::files::output_dir::{Replace, StagedDir};
use crate::harness::study::budget::Estimate;
use crate::harness::study::executor::{Executed, Executor};
use crate::harness::study::shard::{codec, shard_file_name, Invocation, ShardSpec, Share};

/// The `--shard` option.
#[derive(Debug, Clone, Copy, Default, clap::Args, Serialize, Deserialize)]
pub struct ShardArgs {
    /// Run only shard K of N of the study's jobs (1 <= K <= N) and write its partial result
    /// file `shard-<command>-<K>-of-<N>.json` into --out; `signorini merge` makes the reports
    /// from the N files.
    #[arg(long, value_name = "K/N", value_parser = parse_shard)]
    pub shard: Option<ShardSpec>,
}

impl ShardArgs {
    /// The executor of the study's jobs: this shard's share, or every job here.
    pub(crate) fn executor(&self) -> Executor {
        self.shard.map_or(Executor::Local, Executor::Shard)
    }
}

fn parse_shard(s: &str) -> Result<ShardSpec, String> {
    s.parse().map_err(|e: ParameterError| e.to_string())
}

/// The options that the shards of one invocation may give differently: dropped from the
/// recorded arguments (`--out` is the merge's to give).
const PER_SHARD_OPTIONS: [&str; 2] = ["--shard", "--out"];

/// This process's arguments after the subcommand, less [`PER_SHARD_OPTIONS`] and their values.
fn shard_arguments() -> Vec<String> {
    let mut kept = Vec::new();
    let mut args = std::env::args().skip(2);
    while let Some(a) = args.next() {
        if PER_SHARD_OPTIONS.contains(&a.as_str()) {
            args.next();
        } else if !PER_SHARD_OPTIONS
            .iter()
            .any(|o| a.starts_with(&format!("{o}=")))
        {
            kept.push(a);
        }
    }
    kept
}

/// This process's command as its shards record it: `command`, its arguments (less
/// [`PER_SHARD_OPTIONS`]), its parsed options `request` (with `--shard` and `--out` cleared by
/// the caller) and the files it reads.
pub(crate) fn this_invocation<A: Serialize>(
    command: &str,
    request: &A,
    inputs: Vec<PathBuf>,
) -> Result<Invocation, Failure> {
    Ok(Invocation {
        command: command.to_string(),
        arguments: shard_arguments(),
        request: codec::encode(request).map_err(Failure::runtime)?,
        inputs,
    })
}

/// Where a shard's partial result file goes: `out`, staged before the shard runs (an `--out`
/// that cannot be written is refused before any job).
pub(crate) struct ShardOutput {
    spec: ShardSpec,
    out: PathBuf,
    staged: StagedDir,
}

impl ShardOutput {
    /// Stages `out` for shard `spec`'s file.
    pub(crate) fn begin(spec: ShardSpec, out: &Path) -> Result<Self, Failure> {
        Ok(Self {
            spec,
            out: out.to_path_buf(),
            staged: StagedDir::begin("--out", out, Replace::Files)?,
        })
    }

    /// Writes the shard's `share` of `invocation` and commits it.
    pub(crate) fn write(self, invocation: &Invocation, share: Share) -> Result<(), Failure> {
        let Self { spec, out, staged } = self;
        let name = shard_file_name(&invocation.command, spec);
        let (ran, jobs) = (share.results.len(), share.jobs());
        let file = invocation.shard_file(spec, share)?;
        write_json(&staged.path().join(&name), &file)?;
        staged.commit()?;
        out!(
            "wrote {} (shard {spec}: {ran} of {jobs} jobs)",
            out.join(&name).display()
        );
        Ok(())
    }
}

/// The complete result of a study, or `None` once a shard's share is written into its file
/// (`shard`, begun when the executor is a shard's).
pub(crate) fn complete_or_write<T>(
    executed: Executed<T>,
    shard: Option<ShardOutput>,
    invocation: &Invocation,
) -> Result<Option<T>, Failure> {
    match (executed, shard) {
        (Executed::Complete(value), _) => Ok(Some(value)),
        (Executed::Share(share), Some(shard)) => shard.write(invocation, share).map(|()| None),
        (Executed::Share(_), None) => Err(Failure::runtime(
            "the study ran a shard's share without the shard's --out",
        )),
    }
}

/// Where a command that writes into a reports directory `--out` puts what its executor hands
/// back: a shard's partial result file, or the reports, staged.
pub(crate) enum Destination {
    /// A shard's file.
    Shard(ShardOutput),
    /// The reports, staged in `--out`.
    Reports(StagedDir),
}

impl Destination {
    /// The destination of `executor`'s results in `out`, begun before any job runs.
    pub(crate) fn begin(executor: &Executor, out: &Path) -> Result<Self, Failure> {
        Ok(match executor {
            Executor::Shard(spec) => Self::Shard(ShardOutput::begin(*spec, out)?),
            Executor::Local | Executor::Merge(_) => {
                Self::Reports(StagedDir::begin("--out", out, Replace::Files)?)
            }
        })
    }

    /// The complete result with the staged reports to write it into, or `None` once a shard's
    /// share is written into its file.
    pub(crate) fn receive<T>(
        self,
        executed: Executed<T>,
        invocation: &Invocation,
    ) -> Result<Option<(T, StagedDir)>, Failure> {
        match (executed, self) {
            (Executed::Complete(value), Self::Reports(staged)) => Ok(Some((value, staged))),
            (Executed::Share(share), Self::Shard(shard)) => {
                shard.write(invocation, share).map(|()| None)
            }
            (Executed::Complete(_), Self::Shard(_)) | (Executed::Share(_), Self::Reports(_)) => {
                Err(Failure::runtime(
                    "the study's executor and its output disagree (a shard's share is written \
                     only into a shard's file)",
                ))
            }
        }
    }
}

/// The part of a command's work `estimate` that `executor` computes here: all of it locally,
/// about 1/n of its dof-steps for shard k/n (its share of every job list, dealt round the
/// shards), none of them for a merge. Its memory is a run's whatever the executor.
pub(crate) fn share_of_work(estimate: Estimate, executor: &Executor) -> Estimate {
    let share = match executor {
        Executor::Local => 1.0,
        Executor::Shard(spec) => 1.0 / spec.n as f64,
        Executor::Merge(_) => 0.0,
    };
    Estimate {
        dof_steps: estimate.dof_steps * share,
        ..estimate
    }
}

/// The output of shard `executor` in `out` (`None` for another executor), begun; `--shard`
/// without `--out` is refused.
pub(crate) fn shard_output(
    executor: &Executor,
    out: Option<&Path>,
) -> Result<Option<ShardOutput>, Failure> {
    match (executor, out) {
        (Executor::Shard(spec), Some(out)) => ShardOutput::begin(*spec, out).map(Some),
        (Executor::Shard(_), None) => Err(Failure::usage(SHARD_NEEDS_OUT)),
        _ => Ok(None),
    }
}

/// Why `--shard` without `--out` is refused.
pub(crate) const SHARD_NEEDS_OUT: &str =
    "--shard needs --out DIR: the directory its partial result file goes into";
