//! The partial result file a shard writes, `shard-<command>-<k>-of-<n>.json` (format
//! [`SHARD_FORMAT`]), and the identity that tells whether shards are of one invocation.
//!
//! Fields (stable within a format version; a new version is a new `format` string):
//!
//! | field | what |
//! | --- | --- |
//! | `format` | `"signorini-shard/6"` |
//! | `signorini` | the version of the binary that ran the shard |
//! | `command` | the subcommand: `study`, `stability`, `sensitivity`, `reference`, `report` or `experiment` |
//! | `arguments` | its arguments as typed, less `--shard` and `--out`: what the merge's report says it was made by |
//! | `request` | the typed command, tagged with the subcommand's name, its parsed options less `--shard` and `--out`, as hexadecimal MessagePack: what the merge runs again (it parses no command line) |
//! | `inputs` | the files the command reads (scene files), whose contents the identity covers |
//! | `identity` | 16 hexadecimal digits: FNV-1a (64 bits) of `signorini`, `command`, `arguments`, `request` and the contents of `inputs` |
//! | `k`, `n` | shard `k` of `n` |
//! | `jobs` | the number of jobs in the whole job list |
//! | `lists` | the job lists the command handed to its executor, in order, that make up the whole list: `jobs` (the list's count) and `wall_seconds` (this shard's wall time on its share of it) |
//! | `results` | this shard's jobs: `index` (the job's place in the whole list), `result` |
//! | `checksum` | 64 hexadecimal digits: SHA-256 of the file's compact JSON with `checksum` empty |
//!
//! The checksum covers every other field (the parameters through `identity`, and the results):
//! a file changed or damaged after its shard wrote it is refused by the merge
//! ([`ShardFile::verify`]). Files of versions 1 to 5 (no request, no lists, version 4's job results, or
//! version 5's request of bare options) are refused with the reason.
//!
//! A `result` is the job's result as hexadecimal MessagePack ([`super::codec`]); for the
//! `reference` command it is the scene's name, the reference itself being in the cache.

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use super::ShardSpec;
use crate::harness::files::input::{self, Limit, SCENE_FILE};
use crate::harness::files::manifest::sha256;
use crate::harness::study::error::Error;

/// A shard file, as [`crate::harness::files::input`] reads it: at most 64 MiB. Its strings are held
/// as read, so the file takes at most about eight times its size in memory (a list of empty
/// strings, 3 bytes each in the file and 24 in memory), 512 MiB.
pub const SHARD_FILE: Limit = Limit {
    what: "shard file",
    max_bytes: 64 * 1024 * 1024,
};

/// The `format` of the files this version writes and reads.
pub const SHARD_FORMAT: &str = "signorini-shard/6";

/// One job's result, [`super::codec::encode`]d, with the job's index in its list.
#[derive(Debug, Clone, PartialEq)]
pub struct EncodedResult {
    /// The job's index in its list (the order the study gives its jobs, not the run order).
    pub index: usize,
    /// The job's result, [`super::codec::encode`]d.
    pub result: String,
}

/// One of the job lists a command hands to its executor, as a shard ran it: the list's size and
/// the shard's time on its share of it.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ListRun {
    /// The number of jobs in the list.
    pub jobs: usize,
    /// The shard's wall time on its share of the list, seconds (in a merge, the longest of the
    /// shards' times).
    pub wall_seconds: f64,
}

/// What one shard ran: the job lists of its command and the results of its share of them.
#[derive(Debug, Clone, PartialEq)]
pub struct Share {
    /// The lists, in the order the command handed them: their jobs make up the whole list, each
    /// list's numbered on from the previous one's.
    pub lists: Vec<ListRun>,
    /// The results of this shard's jobs, by index in the whole list.
    pub results: Vec<EncodedResult>,
}

impl Share {
    /// The number of jobs in the whole list.
    pub fn jobs(&self) -> usize {
        self.lists.iter().map(|l| l.jobs).sum()
    }
}

/// One shard's partial result file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ShardFile {
    /// [`SHARD_FORMAT`].
    pub format: String,
    /// The version of the binary that ran the shard.
    pub signorini: String,
    /// The subcommand.
    pub command: String,
    /// Its arguments, less `--shard` and `--out`.
    pub arguments: Vec<String>,
    /// The typed command, its parsed options less `--shard` and `--out`, tagged with the
    /// subcommand's name, [`super::codec::encode`]d (absent from
    /// files of earlier formats, which the merge refuses by their `format`).
    #[serde(default)]
    pub request: String,
    /// The files it reads.
    pub inputs: Vec<PathBuf>,
    /// [`Invocation::identity`].
    pub identity: String,
    /// This shard's number, from 1.
    pub k: usize,
    /// The number of shards.
    pub n: usize,
    /// The number of jobs in the whole list.
    pub jobs: usize,
    /// The job lists that make up the whole list, with this shard's time on each (absent from
    /// files of earlier formats, which the merge refuses by their `format`).
    #[serde(default)]
    pub lists: Vec<ListRun>,
    /// This shard's jobs.
    pub results: Vec<JobResult>,
    /// SHA-256 of the file with this field empty ([`ShardFile::checksum_of`]).
    #[serde(default)]
    pub checksum: String,
}

impl ShardFile {
    /// The SHA-256 of this file's compact JSON with `checksum` empty, as 64 hexadecimal digits.
    pub fn checksum_of(&self) -> String {
        let blank = ShardFile {
            checksum: String::new(),
            ..self.clone()
        };
        sha256(serde_json::to_string(&blank).unwrap_or_default().as_bytes())
    }

    /// The file with its checksum set.
    pub fn sealed(mut self) -> Self {
        self.checksum = self.checksum_of();
        self
    }

    /// Whether the checksum is the content's.
    pub fn verify(&self) -> bool {
        self.checksum == self.checksum_of()
    }
}

/// One job of a shard file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct JobResult {
    /// The job's index in its list.
    pub index: usize,
    /// The job's result (see the module's documentation).
    pub result: String,
}

/// A command as the shards and the merge see it: what must be equal for shards to merge.
#[derive(Debug, Clone, PartialEq)]
pub struct Invocation {
    /// The subcommand.
    pub command: String,
    /// Its arguments, less `--shard` and `--out`, as typed.
    pub arguments: Vec<String>,
    /// The typed command, its parsed options less `--shard` and `--out`, tagged with the
    /// subcommand's name, [`super::codec::encode`]d: what a merge runs again.
    pub request: String,
    /// The files it reads.
    pub inputs: Vec<PathBuf>,
}

impl Invocation {
    /// FNV-1a (64 bits, as 16 hexadecimal digits) of this binary's version, the command, its
    /// arguments, its request and the contents of its inputs, each part preceded by its length.
    pub fn identity(&self) -> Result<String, Error> {
        let mut hash = Fnv1a::default();
        hash.part(env!("CARGO_PKG_VERSION").as_bytes());
        hash.part(self.command.as_bytes());
        for a in &self.arguments {
            hash.part(a.as_bytes());
        }
        hash.part(self.request.as_bytes());
        for path in &self.inputs {
            hash.part(path.to_string_lossy().as_bytes());
            hash.part(&input::read_bytes(path, SCENE_FILE)?);
        }
        Ok(format!("{:016x}", hash.0))
    }

    /// The file of shard `spec` of this invocation with the results of its `share`.
    pub fn shard_file(&self, spec: ShardSpec, share: Share) -> Result<ShardFile, Error> {
        Ok(ShardFile {
            format: SHARD_FORMAT.to_string(),
            signorini: env!("CARGO_PKG_VERSION").to_string(),
            command: self.command.clone(),
            arguments: self.arguments.clone(),
            request: self.request.clone(),
            inputs: self.inputs.clone(),
            identity: self.identity()?,
            k: spec.k,
            n: spec.n,
            jobs: share.jobs(),
            lists: share.lists,
            results: share
                .results
                .into_iter()
                .map(|EncodedResult { index, result }| JobResult { index, result })
                .collect(),
            checksum: String::new(),
        }
        .sealed())
    }
}

/// The name of shard `spec`'s file of `command` in its `--out` directory.
pub fn shard_file_name(command: &str, spec: ShardSpec) -> String {
    format!("shard-{command}-{}-of-{}.json", spec.k, spec.n)
}

/// Where `dir`'s shard file of `command` goes.
pub fn shard_file_path(dir: &Path, command: &str, spec: ShardSpec) -> PathBuf {
    dir.join(shard_file_name(command, spec))
}

/// FNV-1a, 64 bits: a hash that every build and platform computes alike.
struct Fnv1a(u64);

impl Default for Fnv1a {
    fn default() -> Self {
        Self(0xcbf2_9ce4_8422_2325)
    }
}

impl Fnv1a {
    fn bytes(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.0 = (self.0 ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3);
        }
    }

    fn part(&mut self, bytes: &[u8]) {
        self.bytes(&(bytes.len() as u64).to_le_bytes());
        self.bytes(bytes);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fnv1a_matches_its_reference_values() {
        let mut h = Fnv1a::default();
        h.bytes(b"a");
        assert_eq!(h.0, 0xaf63_dc4c_8601_ec8c);
    }

    #[test]
    fn the_identity_tells_arguments_apart() {
        let a = Invocation {
            command: "study".into(),
            arguments: vec!["x".into(), "y".into()],
            request: String::new(),
            inputs: vec![],
        };
        let b = Invocation {
            arguments: vec!["xy".into()],
            ..a.clone()
        };
        assert_ne!(a.identity().unwrap(), b.identity().unwrap());
    }
}
