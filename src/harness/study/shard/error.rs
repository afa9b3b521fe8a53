//! What can go wrong when sharding a study or merging its shards ([`ShardError`]).

use std::path::PathBuf;

use thiserror::Error;

use crate::harness::files::input::{printable, shown, Shown};

/// What can go wrong when sharding a study or merging its shards (`crate::harness::study::shard`).
#[derive(Debug, Error)]
pub enum ShardError {
    /// The shards hold another number of results for a job list than the study's list has jobs.
    #[error(
        "the shards hold {shards} job results for job list {list} but the study has {study} jobs \
         in it: the shards are of another version of the study"
    )]
    JobCount {
        /// The list, from 1 in the order the study hands its lists.
        list: usize,
        /// Results in the shards for it.
        shards: usize,
        /// Jobs in the study's list.
        study: usize,
    },
    /// A command handed no result back from job lists run here or merged: a defect of the
    /// command, not of the shards.
    #[error("the command made nothing of its job lists' results (a defect: please report it)")]
    NoResult,
    /// The shards hold more job lists than the study hands its executor.
    #[error(
        "the shards hold {shards} job lists but the study has {study}: the shards are of \
         another version of the study"
    )]
    ListCount {
        /// Lists in the shards.
        shards: usize,
        /// Lists of the study.
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
    #[error(
        "{}: format {}, expected {expected:?} (a shard file of another version of signorini: \
         run the shards again with this one)",
        Shown(path),
        printable(&format!("{found:?}"))
    )]
    Format {
        /// The file.
        path: PathBuf,
        /// Its format.
        found: String,
        /// The format this version reads.
        expected: &'static str,
    },
    /// Two shards of different invocations.
    #[error(
        "{} and {} are shards of different invocations (their {field} differ): merge the \
         shards of one command line",
        Shown(first),
        Shown(other)
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
    #[error("{}: shard {k} of {n} is out of range (k from 1 to n)", Shown(path))]
    ShardNumber {
        /// The file.
        path: PathBuf,
        /// Its `k`.
        k: usize,
        /// Its `n`.
        n: usize,
    },
    /// A shard given more than once.
    #[error("shard {k}/{n} is given more than once: {}", path_list(paths))]
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
        ranges(missing, *n)
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
        Shown(path)
    )]
    JobIndex {
        /// The file.
        path: PathBuf,
        /// The index.
        index: usize,
        /// The number of jobs.
        jobs: usize,
    },
    /// A shard file whose content is not what its shard wrote (its checksum differs).
    #[error(
        "{}: its checksum does not match its content: the file was changed or damaged after \
         its shard wrote it; run that shard again",
        Shown(path)
    )]
    Checksum {
        /// The file.
        path: PathBuf,
    },
    /// A shard file whose job lists do not make up its whole list.
    #[error(
        "{}: its job lists hold {listed} jobs but jobs = {jobs}: the file is not a shard's",
        Shown(path)
    )]
    Lists {
        /// The file.
        path: PathBuf,
        /// The jobs its lists hold.
        listed: usize,
        /// Its `jobs`.
        jobs: usize,
    },
    /// A count in a shard file over what a merge accepts.
    #[error("{}: {field} = {value}; allowed: at most {max}", Shown(path))]
    TooMany {
        /// The file.
        path: PathBuf,
        /// The field (`n`, `jobs`).
        field: &'static str,
        /// Its value.
        value: usize,
        /// The largest accepted.
        max: usize,
    },
    /// A job result whose values are not a result's (non-finite, or out of their range).
    #[error("the result of job {index} in the shards is out of range: {why}")]
    OutOfRange {
        /// The job's index.
        index: usize,
        /// The value and its range.
        why: String,
    },
    /// A job result whose error norms are not the ones its study asks for (a forged shard).
    #[error(
        "the shards' result of {case} at level {level} holds errors = [{}]; allowed: the \
         errors of the norms the study asks for, [{}]",
        found.join(", "),
        asked.join(", ")
    )]
    Norms {
        /// The case's id.
        case: String,
        /// The level.
        level: usize,
        /// The norms of its errors.
        found: Vec<String>,
        /// The norms of the study.
        asked: Vec<String>,
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
        inputs.iter().map(|p| shown(p)).collect::<Vec<_>>().join(", ")
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
        !matches!(self, Self::Encode(_) | Self::NoResult)
    }
}

/// The shard numbers `ks` (ascending) of `n` as ranges, `2/8, 4/8–6/8`, the first ten ranges
/// and how many more: a message stays one short line whatever `n` is.
fn ranges(ks: &[usize], n: usize) -> String {
    const SHOWN: usize = 10;
    let mut spans: Vec<(usize, usize)> = Vec::new();
    for &k in ks {
        match spans.last_mut() {
            Some((_, last)) if *last + 1 == k => *last = k,
            _ => spans.push((k, k)),
        }
    }
    let mut text: Vec<String> = spans
        .iter()
        .take(SHOWN)
        .map(|&(a, b)| {
            if a == b {
                format!("{a}/{n}")
            } else {
                format!("{a}/{n}–{b}/{n}")
            }
        })
        .collect();
    if spans.len() > SHOWN {
        text.push(format!("and {} more ranges", spans.len() - SHOWN));
    }
    text.join(", ")
}

/// `paths`, separated by commas.
fn path_list(paths: &[PathBuf]) -> String {
    paths
        .iter()
        .map(|p| shown(p))
        .collect::<Vec<_>>()
        .join(", ")
}
