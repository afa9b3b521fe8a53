//! `signorini merge`: reading a sharded command's partial result files back, checked to be the
//! shards of one invocation, complete, and of unchanged inputs ([`crate::harness::study::shard`]). The
//! dispatcher runs the recorded request again with every job's result taken from them
//! ([`crate::harness::study::executor::Executor::Merge`]): it writes the very files the unsharded
//! command writes.

use std::path::PathBuf;

use clap::Args;
use serde::de::DeserializeOwned;

use super::failure::Failure;
use super::limits::LimitArgs;
use crate::harness::files::artifacts::read_json;
use crate::harness::study::budget;
use crate::harness::study::executor::Executor;
use crate::harness::study::shard::merge::{merge as merge_shards, Merged};
use crate::harness::study::shard::{codec, ShardError, ShardFile, SHARD_FILE};

/// The memory a shard file takes per byte of it ([`SHARD_FILE`]'s bound) and its results'
/// decoding, at most half a byte per hexadecimal digit.
const SHARD_MEMORY_PER_BYTE: f64 = 8.5;

/// The arguments of `signorini merge`.
#[derive(Debug, Args)]
pub struct MergeArgs {
    /// Where the reports go: the `--out` the unsharded command would be given (default: that
    /// command's; a 1D study prints its tables).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// The partial result files of the n shards (`shard-<command>-<k>-of-<n>.json`).
    #[arg(required = true)]
    pub shards: Vec<PathBuf>,
    /// The resource limits of reading the shards (the merged command keeps its own, recorded
    /// with its request).
    #[command(flatten)]
    pub limits: LimitArgs,
}

/// The shards of one invocation, read and checked: what the dispatcher runs again.
pub(crate) struct MergedShards {
    /// The subcommand the shards ran.
    pub command: String,
    /// Its recorded request, encoded.
    request: String,
    /// The command line the reports say they were made by.
    pub command_line: String,
    /// The executor that hands every job's result from the shards to the study.
    pub executor: Executor,
}

impl MergedShards {
    /// The request the shards recorded, as the options of their command.
    pub(crate) fn request<A: DeserializeOwned>(&self) -> Result<A, Failure> {
        codec::read(&self.request).map_err(|e| {
            Failure::usage(format!(
                "the shards' request does not read as `{}` options: {e}",
                self.command
            ))
        })
    }
}

/// Reads the shards of `args`, checks they are the `n` shards of one invocation whose inputs are
/// unchanged, and returns what the dispatcher runs again.
pub(crate) fn read_shards(args: &MergeArgs) -> Result<MergedShards, Failure> {
    let bytes: f64 = budget::file_sizes(&args.shards).iter().sum();
    args.limits
        .check(budget::reading(bytes, SHARD_MEMORY_PER_BYTE))?;
    let files = args
        .shards
        .iter()
        .map(|path| {
            read_json::<ShardFile>(path, SHARD_FILE)
                .map(|file| (path.clone(), file))
                .map_err(Failure::usage)
        })
        .collect::<Result<Vec<_>, _>>()?;
    let Merged {
        invocation,
        identity,
        jobs,
    } = merge_shards(files)?;
    if invocation.identity()? != identity {
        return Err(ShardError::InputsChanged {
            command: invocation.command,
            inputs: invocation.inputs,
        }
        .into());
    }
    let mut argv = vec!["signorini".to_string(), invocation.command.clone()];
    argv.extend(invocation.arguments.iter().cloned());
    if let Some(out) = &args.out {
        argv.extend(["--out".to_string(), out.display().to_string()]);
    }
    Ok(MergedShards {
        command: invocation.command,
        request: invocation.request,
        command_line: argv.join(" "),
        executor: Executor::Merge(jobs),
    })
}

impl From<ShardError> for Failure {
    fn from(e: ShardError) -> Self {
        crate::harness::files::error::Error::from(e).into()
    }
}
