//! `--shard k/n` on the commands that run job lists (`study`, `stability`, `sensitivity`,
//! `reference`, `report`, `experiment`): the option and the executor it asks for, what such a
//! command states of its own ([`sharded::Sharded`]), the command line it is given, read once
//! ([`command_line::CommandLine`]), and where its results go and how its shards are read back
//! ([`outputs`]).

use serde::{Deserialize, Serialize};

pub(crate) mod command_line;
pub(crate) mod outputs;
pub(crate) mod sharded;

use super::options::parsed;
use crate::harness::study::executor::Executor;
use crate::harness::study::shard::ShardSpec;

/// The `--shard` option of a command whose jobs are `what` (its help says so).
macro_rules! shard_args {
    ($name:ident, $what:literal) => {
        /// The `--shard` option.
        #[derive(Debug, Clone, Copy, Default, clap::Args, Serialize, Deserialize)]
        pub struct $name {
            /// The shard K/N to run (see the help text).
            #[arg(long, value_name = "K/N", value_parser = parsed::<ShardSpec>, help = concat!(
                "Run only shard K of N (1 <= K <= N) of ", $what, " and write its partial ",
                "result file shard-<command>-<K>-of-<N>.json into --out; `signorini merge` ",
                "makes the reports from the N files"
            ))]
            pub shard: Option<ShardSpec>,
        }

        impl $name {
            /// The executor of the command's jobs: this shard's share, or every job here.
            pub(crate) fn executor(&self) -> Executor {
                self.shard.map_or(Executor::Local, Executor::Shard)
            }
        }
    };
}

shard_args!(ShardArgs, "the study's case × level runs");
shard_args!(SuiteShardArgs, "the suite's scheme × mass × hard-case runs");
shard_args!(
    EnsembleShardArgs,
    "the ensembles, one per case (a box scene's: one per case × level)"
);
shard_args!(
    ReferenceShardArgs,
    "the scenes' references (the largest first)"
);
shard_args!(
    ReportShardArgs,
    "the runs of the command's studies (their job lists dealt as one)"
);
