//! `signorini merge`: the reports of a sharded command from its shards' partial result files,
//! the very files the command writes unsharded ([`crate::harness::shard`]).

use std::path::PathBuf;

use clap::{Args, Parser, Subcommand};

use super::reports::{stability, StabilityArgs};
use super::study::{reference, sensitivity, study_scene_as, ReferenceArgs, SensitivityArgs};
use super::{Failure, LimitArgs, StudyArgs};
use crate::harness::artifacts::read_json;
use crate::harness::budget;
use crate::harness::shard::merge::{merge as merge_shards, Merged};
use crate::harness::shard::plan::replay;
use crate::harness::shard::{Invocation, ShardError, ShardFile, SHARD_FILE};

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
    /// with its arguments).
    #[command(flatten)]
    pub limits: LimitArgs,
}

/// A command that can be sharded, parsed from the arguments its shards recorded.
#[derive(Parser)]
#[command(name = "signorini")]
struct Recorded {
    #[command(subcommand)]
    command: Shardable,
}

#[derive(Subcommand)]
enum Shardable {
    Study(StudyArgs),
    Stability(StabilityArgs),
    Sensitivity(SensitivityArgs),
    Reference(ReferenceArgs),
}

impl Shardable {
    /// The files the command reads.
    fn inputs(&self) -> Vec<PathBuf> {
        match self {
            Self::Study(a) => a.inputs(),
            Self::Stability(a) => a.inputs(),
            Self::Sensitivity(a) => a.inputs(),
            Self::Reference(a) => a.inputs(),
        }
    }
}

/// Checks the shards are the `n` shards of one invocation, then runs that invocation (with
/// `--out`, when given) with every job's result taken from them: it writes, or prints, what the
/// unsharded command does. A `reference` merge runs the command on the shared cache.
pub fn merge(args: MergeArgs) -> Result<(), Failure> {
    let MergeArgs {
        out,
        shards,
        limits,
    } = args;
    let bytes: f64 = budget::file_sizes(&shards).iter().sum();
    limits.check(budget::reading(bytes, SHARD_MEMORY_PER_BYTE))?;
    let files = shards
        .into_iter()
        .map(|path| {
            read_json::<ShardFile>(&path, SHARD_FILE)
                .map(|file| (path, file))
                .map_err(Failure::usage)
        })
        .collect::<Result<Vec<_>, _>>()?;
    let Merged {
        invocation,
        identity,
        results,
    } = merge_shards(files)?;
    let mut argv = vec!["signorini".to_string(), invocation.command.clone()];
    argv.extend(invocation.arguments.iter().cloned());
    if let Some(out) = &out {
        argv.extend(["--out".to_string(), out.display().to_string()]);
    }
    let recorded = Recorded::try_parse_from(&argv)
        .map_err(|e| Failure::usage(format!("the shards' arguments do not parse: {e}")))?;
    let here = Invocation {
        inputs: recorded.command.inputs(),
        ..invocation.clone()
    };
    if here != invocation || here.identity()? != identity {
        return Err(ShardError::InputsChanged {
            command: invocation.command,
            inputs: invocation.inputs,
        }
        .into());
    }
    let command_line = argv.join(" ");
    match recorded.command {
        Shardable::Study(a) => replay(results, || study_scene_as(a, &command_line)),
        Shardable::Stability(a) => replay(results, || stability(a)),
        Shardable::Sensitivity(a) => replay(results, || sensitivity(a)),
        Shardable::Reference(a) => reference(a),
    }
}

impl From<ShardError> for Failure {
    fn from(e: ShardError) -> Self {
        crate::harness::error::Error::from(e).into()
    }
}
