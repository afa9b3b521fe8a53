//! `signorini merge`: the arguments of reading a sharded command's partial result files back
//! ([`super::sharding::outputs::read_shards`]); the dispatcher runs the typed command they
//! recorded again with every job's result taken from them: it writes the very files the
//! unsharded command writes.

use std::path::PathBuf;

use clap::Args;

use super::limits::LimitArgs;

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
