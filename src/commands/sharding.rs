//! `--shard k/n` on the commands that run a study (`study`, `stability`, `sensitivity`,
//! `reference`): the option, and how a shard writes its partial result file into `--out`
//! ([`crate::harness::shard`]).

use std::path::{Path, PathBuf};

use super::Failure;
use crate::engine::error::ParameterError;
use crate::harness::artifacts::write_json;
use crate::harness::error::Error;
use crate::harness::output_dir::{Replace, StagedDir};
use crate::harness::shard::plan::{self, Share};
use crate::harness::shard::{shard_file_name, Invocation, ShardSpec};

/// The `--shard` option.
#[derive(Debug, Clone, Copy, clap::Args)]
pub struct ShardArgs {
    /// Run only shard K of N of the study's jobs (1 <= K <= N) and write its partial result
    /// file `shard-<command>-<K>-of-<N>.json` into --out; `signorini merge` makes the reports
    /// from the N files.
    #[arg(long, value_name = "K/N", value_parser = parse_shard)]
    pub shard: Option<ShardSpec>,
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
/// [`PER_SHARD_OPTIONS`]) and the files it reads.
pub(crate) fn this_invocation(command: &str, inputs: Vec<PathBuf>) -> Invocation {
    Invocation {
        command: command.to_string(),
        arguments: shard_arguments(),
        inputs,
    }
}

/// Runs `study` as shard `spec` of `invocation` and writes its partial result file into `out`
/// (whole or not at all).
pub(crate) fn write_shard<T>(
    invocation: &Invocation,
    spec: ShardSpec,
    out: &Path,
    study: impl FnOnce() -> Result<T, Error>,
) -> Result<(), Failure> {
    let staged = StagedDir::begin("--out", out, Replace::Files)?;
    let share = plan::record_share(spec, study)?;
    write_share(invocation, spec, out, staged, share)
}

/// Writes shard `spec`'s `share` of `invocation` into `staged`, the staging of `out`, and
/// commits it.
pub(crate) fn write_share(
    invocation: &Invocation,
    spec: ShardSpec,
    out: &Path,
    staged: StagedDir,
    share: Share,
) -> Result<(), Failure> {
    let name = shard_file_name(&invocation.command, spec);
    let (ran, jobs) = (share.results.len(), share.jobs);
    let file = invocation.shard_file(spec, share)?;
    write_json(&staged.path().join(&name), &file)?;
    staged.commit()?;
    out!(
        "wrote {} (shard {spec}: {ran} of {jobs} jobs)",
        out.join(&name).display()
    );
    Ok(())
}
