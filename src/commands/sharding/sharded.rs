//! What a command whose job lists shard states of its own ([`Sharded`]): the options its shards
//! record and a merge runs again with its own `--out`, the files they read, the executor its
//! `--shard` asks for and how it runs with an executor. Running it, as typed, as a shard or as a
//! merge, is one path for every such command (the dispatcher's `ShardableCommand`).

use std::path::PathBuf;

use super::command_line::CommandLine;
use crate::commands::failure::Failure;
use crate::harness::study::executor::Executor;
use crate::harness::study::shard::Invocation;

/// A command whose job lists shard (`--shard k/n`) and merge (`signorini merge`).
pub trait Sharded: Sized {
    /// Its options with `--shard` cleared and `--out` set to `out` (`None`: the command's
    /// default): as its shards record them (`None`, since each shard gives its own), or as a
    /// merge runs them again (the merge's `--out`).
    fn recorded(&self, out: Option<PathBuf>) -> Self;

    /// The files it reads, whose contents a shard's identity covers.
    fn inputs(&self) -> Vec<PathBuf>;

    /// The executor its `--shard` asks for: that shard's share, or every job here.
    fn executor(&self) -> Executor;

    /// Runs it with its job lists handed to `executor`: a shard's file records `invocation`,
    /// a report says it was made by `line`.
    fn run_with(
        self,
        executor: &Executor,
        invocation: &Invocation,
        line: &CommandLine,
    ) -> Result<(), Failure>;

    /// Runs it as typed, with the executor of its own `--shard`.
    fn run(self, invocation: &Invocation, line: &CommandLine) -> Result<(), Failure> {
        let executor = self.executor();
        self.run_with(&executor, invocation, line)
    }
}
