//! Sharding a study over several machines: `--shard k/n` runs one deterministic share of a
//! study's job list ([`ShardSpec::share`], after the runner's largest-first ordering) and writes
//! the results into a partial result file ([`file`]); `signorini merge` checks the shards are
//! one invocation's and complete ([`merge`]) and runs the command again with every job's result
//! taken from them ([`plan::replay`]), so that it writes the very reports the unsharded
//! command writes.
//!
//! The runner of every study ([`crate::harness::study::run_largest_first`]) asks [`plan`] how to
//! schedule its list; the commands install the plan. A study whose reports need a second job
//! list after the first (one that depends on the first's results) cannot be sharded by this
//! scheme: its shard stops after the first list, and its merge refuses the second
//! ([`ShardError::SecondJobList`]).

pub mod codec;
pub mod file;
pub mod merge;
pub mod plan;
pub mod spec;

use std::path::PathBuf;

use thiserror::Error;

pub use file::{shard_file_name, shard_file_path, Invocation, JobResult, ShardFile, SHARD_FORMAT};
pub use spec::ShardSpec;

/// What can go wrong when sharding a study or merging its shards.
#[derive(Debug, Error)]
pub enum ShardError {
    /// Not a failure: the shard's jobs are done and recorded, and the study stops before its
    /// reports ([`plan::record_share`] catches it).
    #[error("this shard's jobs are recorded; the study stops before its reports")]
    Recorded,
    /// The command ran no job list through the runner, so there is nothing to shard.
    #[error("the command ran no job list through the study runner: nothing to shard or merge")]
    NoJobList,
    /// A second job list after the first.
    #[error(
        "the study runs a second job list after the first (it needs the first one's results): \
         it cannot be sharded yet"
    )]
    SecondJobList,
    /// The shards hold another number of results than the study has jobs.
    #[error(
        "the shards hold {shards} job results but the study has {study} jobs: the shards are \
         of another version of the study"
    )]
    JobCount {
        /// Results in the shards.
        shards: usize,
        /// Jobs in the study.
        study: usize,
    },
    /// A result could not be encoded.
    #[error("cannot encode a job result: {0}")]
    Encode(String),
    /// A result could not be decoded.
    #[error("the result of job {index} in the shards is damaged: {why}")]
    Decode {
        /// The job's index.
        index: usize,
        /// What was wrong.
        why: String,
    },
    /// No shard file was given to merge.
    #[error("no shard file given: merge takes the n files of one sharded command")]
    NoShards,
    /// A file of another format.
    #[error("{}: format {found:?}, expected {SHARD_FORMAT:?}", path.display())]
    Format {
        /// The file.
        path: PathBuf,
        /// Its format.
        found: String,
    },
    /// Two shards of different invocations.
    #[error(
        "{} and {} are shards of different invocations (their {field} differ): merge the \
         shards of one command line",
        first.display(),
        other.display()
    )]
    Mismatch {
        /// The field that differs.
        field: &'static str,
        /// The first shard.
        first: PathBuf,
        /// The other shard.
        other: PathBuf,
    },
    /// A shard number out of `1..=n`.
    #[error("{}: shard {k} of {n} is out of range (k from 1 to n)", path.display())]
    ShardNumber {
        /// The file.
        path: PathBuf,
        /// Its `k`.
        k: usize,
        /// Its `n`.
        n: usize,
    },
    /// A shard given more than once.
    #[error("shard {k}/{n} is given more than once: {}", list(paths))]
    Duplicate {
        /// The shard's `k`.
        k: usize,
        /// The number of shards.
        n: usize,
        /// The files holding it.
        paths: Vec<PathBuf>,
    },
    /// Shards missing.
    #[error(
        "missing shard{} {} (all n = {n} shards of the command are needed)",
        if missing.len() == 1 { "" } else { "s" },
        missing.iter().map(|k| format!("{k}/{n}")).collect::<Vec<_>>().join(", ")
    )]
    Missing {
        /// The `k` of each missing shard.
        missing: Vec<usize>,
        /// The number of shards.
        n: usize,
    },
    /// A job index out of the list or given twice.
    #[error(
        "{}: job {index} is out of the list of {jobs} jobs or in another shard too",
        path.display()
    )]
    JobIndex {
        /// The file.
        path: PathBuf,
        /// The index.
        index: usize,
        /// The number of jobs.
        jobs: usize,
    },
    /// A job no shard holds.
    #[error("no shard holds job {index}: the shard files are incomplete")]
    MissingJob {
        /// The index.
        index: usize,
    },
    /// The inputs differ from those the shards ran.
    #[error(
        "the shards ran {command} on other inputs than the files here ({}): a scene file \
         changed since, or the merge runs in another directory than the shards",
        inputs.iter().map(|p| p.display().to_string()).collect::<Vec<_>>().join(", ")
    )]
    InputsChanged {
        /// The command.
        command: String,
        /// Its input files.
        inputs: Vec<PathBuf>,
    },
}

impl ShardError {
    /// Whether the error is the user's to fix in the arguments (exit code 2): shard files that
    /// do not make one complete invocation.
    pub fn is_usage(&self) -> bool {
        !matches!(
            self,
            Self::Recorded | Self::NoJobList | Self::SecondJobList | Self::Encode(_)
        )
    }
}

fn list(paths: &[PathBuf]) -> String {
    paths
        .iter()
        .map(|p| p.display().to_string())
        .collect::<Vec<_>>()
        .join(", ")
}
