//! Sharding a study over several machines: `--shard k/n` runs one deterministic share of a
//! study's job list ([`ShardSpec::share`], after the runner's largest-first ordering) and writes
//! the results into a partial result file ([`mod@file`]); `signorini merge` checks the shards are
//! one invocation's and complete ([`merge`]) and runs the command again with every job's result
//! taken from them ([`plan::replay`]), so that it writes the very reports the unsharded
//! command writes.
//!
//! The runner of every study ([`crate::harness::study::run_largest_first`]) asks [`plan`] how to
//! schedule its list; the commands install the plan. A study whose reports need a second job
//! list after the first (one that depends on the first's results) cannot be sharded by this
//! scheme: its shard stops after the first list, and its merge refuses the second
//! ([`ShardError::SecondJobList`]). Its errors ([`ShardError`]) are with the harness's others.

pub mod codec;
pub mod file;
pub mod merge;
pub mod plan;
pub mod range;
pub mod spec;

pub use file::{
    shard_file_name, shard_file_path, Invocation, JobResult, ShardFile, SHARD_FILE, SHARD_FORMAT,
};
pub use range::InRange;
pub use spec::ShardSpec;

pub use crate::harness::error::ShardError;
