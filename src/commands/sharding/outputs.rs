//! Where a command's results go: a shard's partial result file ([`ShardOutput`]) or the reports
//! staged in `--out` ([`Destination`]), the share of the work a shard is held to
//! ([`share_of_work`]), and the shards of one invocation read back for `merge` ([`read_shards`]).

use std::path::{Path, PathBuf};

use serde::de::DeserializeOwned;

use crate::commands::command_error::CommandError;
use crate::harness::files::artifacts::{read_json, write_json};
use crate::harness::files::output_dir::{Replace, StagedDir};
use crate::harness::study::budget::{self, Estimate, Limits};
use crate::harness::study::executor::{Executed, Executor};
use crate::harness::study::shard::merge::{merge, Merged};
use crate::harness::study::shard::{
    codec, shard_file_name, Invocation, ShardError, ShardFile, ShardSpec, Share, SHARD_FILE,
};
use crate::studies::error::Error;

/// Where a shard's partial result file goes: `out`, staged before the shard runs (an `--out`
/// that cannot be written is refused before any job).
pub struct ShardOutput {
    spec: ShardSpec,
    out: PathBuf,
    staged: StagedDir,
}

impl ShardOutput {
    /// Stages `out` for shard `spec`'s file.
    pub fn begin(spec: ShardSpec, out: &Path) -> Result<Self, CommandError> {
        Ok(Self {
            spec,
            out: out.to_path_buf(),
            staged: StagedDir::begin("--out", out, Replace::Files)?,
        })
    }

    /// Writes the shard's `share` of `invocation`, commits it and says what it wrote.
    pub fn write(self, invocation: &Invocation, share: Share) -> Result<String, CommandError> {
        let Self { spec, out, staged } = self;
        let name = shard_file_name(&invocation.command, spec);
        let (ran, jobs) = (share.results.len(), share.jobs());
        let file = invocation.shard_file(spec, share)?;
        write_json(&staged.path().join(&name), &file)?;
        staged.commit()?;
        Ok(format!(
            "wrote {} (shard {spec}: {ran} of {jobs} jobs)",
            out.join(&name).display()
        ))
    }
}

/// What an executor's results became: the complete result, or a shard's file, written.
pub enum Received<T> {
    /// The complete result, to write or print.
    Complete(T),
    /// A shard's share written into its file: what was written, for the user.
    ShardWritten(String),
}

/// The complete result of a study, or what a shard wrote once its share is written into its
/// file (`shard`, begun when the executor is a shard's).
pub fn complete_or_write<T>(
    executed: Executed<T>,
    shard: Option<ShardOutput>,
    invocation: &Invocation,
) -> Result<Received<T>, CommandError> {
    match (executed, shard) {
        (Executed::Complete(value), _) => Ok(Received::Complete(value)),
        (Executed::Share(share), Some(shard)) => {
            shard.write(invocation, share).map(Received::ShardWritten)
        }
        (Executed::Share(_), None) => Err(CommandError::Failed(
            "the study ran a shard's share without the shard's --out".into(),
        )),
    }
}

/// Where a command that writes into a reports directory `--out` puts what its executor hands
/// back: a shard's partial result file, or the reports, staged.
pub enum Destination {
    /// A shard's file.
    Shard(ShardOutput),
    /// The reports, staged in `--out`.
    Reports(StagedDir),
}

impl Destination {
    /// The destination of `executor`'s results in `out`, begun before any job runs.
    pub fn begin(executor: &Executor, out: &Path) -> Result<Self, CommandError> {
        Ok(match executor {
            Executor::Shard(spec) => Self::Shard(ShardOutput::begin(*spec, out)?),
            Executor::Local | Executor::Merge(_) => {
                Self::Reports(StagedDir::begin("--out", out, Replace::Files)?)
            }
        })
    }

    /// The complete result with the staged reports to write it into, or what a shard wrote
    /// once its share is written into its file.
    pub fn receive<T>(
        self,
        executed: Executed<T>,
        invocation: &Invocation,
    ) -> Result<Received<(T, StagedDir)>, CommandError> {
        match (executed, self) {
            (Executed::Complete(value), Self::Reports(staged)) => {
                Ok(Received::Complete((value, staged)))
            }
            (Executed::Share(share), Self::Shard(shard)) => {
                shard.write(invocation, share).map(Received::ShardWritten)
            }
            (Executed::Complete(_), Self::Shard(_)) | (Executed::Share(_), Self::Reports(_)) => {
                Err(CommandError::Failed(
                    "the study's executor and its output disagree (a shard's share is written \
                     only into a shard's file)"
                        .into(),
                ))
            }
        }
    }
}

/// The part of a command's work `estimate` that `executor` computes here: all of it locally,
/// about 1/n of its dof-steps for shard k/n (its share of every job list, dealt round the
/// shards), none of them for a merge. Its memory is a run's whatever the executor.
pub fn share_of_work(estimate: Estimate, executor: &Executor) -> Estimate {
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
pub fn shard_output(
    executor: &Executor,
    out: Option<&Path>,
) -> Result<Option<ShardOutput>, CommandError> {
    match (executor, out) {
        (Executor::Shard(spec), Some(out)) => ShardOutput::begin(*spec, out).map(Some),
        (Executor::Shard(_), None) => Err(CommandError::Refused(
            "--shard needs --out DIR: the directory its partial result file goes into".into(),
        )),
        _ => Ok(None),
    }
}

/// The memory a shard file takes per byte of it ([`SHARD_FILE`]'s bound) and its results'
/// decoding, at most half a byte per hexadecimal digit.
const SHARD_MEMORY_PER_BYTE: f64 = 8.5;

/// The shards of one invocation, read and checked: what `merge` runs again, with every job's
/// result taken from them.
pub struct MergedShards<C> {
    /// The command the shards ran, as they recorded it.
    pub command: C,
    /// The name of its subcommand, as its shards' files give it.
    pub name: String,
    /// Its arguments as typed, less `--shard` and `--out`.
    pub arguments: Vec<String>,
    /// The executor that hands every job's result from the shards to the command.
    pub executor: Executor,
}

/// Reads the shard files `paths` (their reading held to `limits`), checks they are the `n`
/// shards of one invocation whose inputs are unchanged, and returns what `merge` runs again:
/// the typed command `C` the shards recorded.
pub fn read_shards<C: DeserializeOwned>(
    paths: &[PathBuf],
    limits: &Limits,
) -> Result<MergedShards<C>, CommandError> {
    let bytes: f64 = budget::file_sizes(paths).iter().sum();
    budget::reading(bytes, SHARD_MEMORY_PER_BYTE)
        .check(limits)
        .map_err(Error::from)?;
    let files = paths
        .iter()
        .map(|path| {
            read_json::<ShardFile>(path, SHARD_FILE)
                .map(|file| (path.clone(), file))
                .map_err(|e| CommandError::Refused(e.to_string()))
        })
        .collect::<Result<Vec<_>, _>>()?;
    let Merged {
        invocation,
        identity,
        jobs,
    } = merge(files).map_err(Error::from)?;
    if invocation.identity()? != identity {
        let changed = ShardError::InputsChanged {
            command: invocation.command,
            inputs: invocation.inputs,
        };
        return Err(Error::from(changed).into());
    }
    let command = codec::read(&invocation.request).map_err(|e| {
        CommandError::Refused(format!(
            "the shards' command does not read as one of signorini's sharded commands: {e}"
        ))
    })?;
    Ok(MergedShards {
        command,
        name: invocation.command,
        arguments: invocation.arguments,
        executor: Executor::Merge(jobs),
    })
}
