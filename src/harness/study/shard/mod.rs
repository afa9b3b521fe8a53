//! Sharding a study over several machines: `--shard k/n` hands the study's job list to
//! [`crate::harness::study::executor::Executor::Shard`], which runs one deterministic share of it
//! ([`ShardSpec::share`], after the largest-first ordering); the command writes the results into
//! a partial result file ([`mod@file`]) with its typed request. `signorini merge` checks the
//! shards are one invocation's and complete ([`merge`]) and runs the request again with
//! [`crate::harness::study::executor::Executor::Merge`], which reads every job's result from them, so
//! that it writes the very reports the unsharded command writes. Its errors ([`ShardError`])
//! are with the harness's others.

pub mod codec;
mod error;
pub mod file;
pub mod merge;
pub mod range;
pub mod spec;

pub use file::{
    shard_file_name, shard_file_path, EncodedResult, Invocation, JobResult, ListRun, ShardFile,
    Share, SHARD_FILE, SHARD_FORMAT,
};
pub use merge::MergedJobs;
pub use range::InRange;
pub use spec::ShardSpec;

pub use error::ShardError;
