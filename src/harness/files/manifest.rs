//! What a command can prove it wrote into an output directory: the manifest
//! `.signorini-manifest.json` it keeps there, with the SHA-256 of every file it put in the
//! directory and, when it created the directory itself, the directory's identity (device and
//! inode, which a rename keeps and nothing else reproduces).
//!
//! A file is the harness's own only when the manifest lists it with the SHA-256 of its present
//! content: a file of the user's with the same name as one the harness writes (a `run.json` of
//! theirs, or one the harness wrote and they edited since) is not.
//! [`crate::harness::files::output_dir`] replaces or removes nothing else.
//!
//! Fields (format `signorini-manifest/1`): `format`; `created`, `{"device": d, "inode": i}` of
//! the directory when the harness created it, absent otherwise; `files`, each file's path
//! relative to the directory (`/`-separated) → its SHA-256 as 64 hexadecimal digits.

use std::collections::BTreeMap;
use std::fs;
use std::io;
use std::os::unix::fs::MetadataExt;
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};
use sha2::{Digest, Sha256};

use crate::harness::files::fault::step;
use crate::harness::files::input::{self, Limit};

/// The manifest's file name, in the directory it describes.
pub const MANIFEST: &str = ".signorini-manifest.json";

/// The name, inside a staging directory, of the manifest the target will have once a commit is
/// complete ([`crate::harness::files::commit_journal`]): not a file of the run.
pub const NEXT_MANIFEST: &str = ".signorini-manifest.json.next";

/// The manifest's `format`.
pub const MANIFEST_FORMAT: &str = "signorini-manifest/1";

/// A manifest as [`input`] reads it (one line of about 100 bytes per file: 16 MiB is 160 000
/// files).
const MANIFEST_FILE: Limit = Limit {
    what: "output manifest",
    max_bytes: 16 * 1024 * 1024,
};

/// A directory's identity on its file system.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DirIdentity {
    /// The device.
    pub device: u64,
    /// The inode.
    pub inode: u64,
}

impl DirIdentity {
    /// The identity of the directory `dir` (links followed).
    pub fn of(dir: &Path) -> io::Result<Self> {
        let meta = fs::metadata(dir)?;
        Ok(Self {
            device: meta.dev(),
            inode: meta.ino(),
        })
    }
}

/// The manifest of one output directory.
#[derive(Debug, Clone, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Manifest {
    /// [`MANIFEST_FORMAT`].
    pub format: String,
    /// The directory's identity when the harness created it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub created: Option<DirIdentity>,
    /// Relative path → SHA-256 of the content written.
    pub files: BTreeMap<String, String>,
}

impl Manifest {
    /// An empty manifest.
    pub fn new(created: Option<DirIdentity>) -> Self {
        Self {
            format: MANIFEST_FORMAT.to_string(),
            created,
            files: BTreeMap::new(),
        }
    }

    /// The manifest of `dir`; an empty one when there is none, or when it cannot be read or is
    /// not a manifest (then nothing in `dir` is proven the harness's).
    pub fn of(dir: &Path) -> Self {
        input::read_json::<Manifest>(&dir.join(MANIFEST), MANIFEST_FILE)
            .ok()
            .filter(|m| m.format == MANIFEST_FORMAT)
            .unwrap_or_else(|| Self::new(None))
    }

    /// Whether the harness created `dir` (its identity is the recorded one).
    pub fn created(&self, dir: &Path) -> bool {
        self.created
            .is_some_and(|c| DirIdentity::of(dir).is_ok_and(|now| now == c))
    }

    /// Whether the file `rel` of `dir` is the harness's: a regular file (not a link) listed
    /// with the SHA-256 of its present content.
    pub fn owns(&self, dir: &Path, rel: &str) -> bool {
        let Some(recorded) = self.files.get(rel) else {
            return false;
        };
        let path = dir.join(rel);
        let regular = fs::symlink_metadata(&path).is_ok_and(|m| m.file_type().is_file());
        regular && sha256_of(&path).is_ok_and(|h| &h == recorded)
    }

    /// Records `rel` with the SHA-256 of the file `path`.
    pub fn record(&mut self, rel: String, path: &Path) -> io::Result<()> {
        self.files.insert(rel, sha256_of(path)?);
        Ok(())
    }

    /// Writes the manifest into `dir` (through a temporary file and a rename).
    pub fn write(&self, dir: &Path) -> io::Result<()> {
        self.write_as(dir, MANIFEST)
    }

    /// Writes the manifest into `dir` as the file `name` (through a temporary file and a
    /// rename, each a step of a commit: [`crate::harness::files::fault::step`]).
    pub fn write_as(&self, dir: &Path, name: &str) -> io::Result<()> {
        let text = serde_json::to_string_pretty(self).map_err(io::Error::other)?;
        let tmp = dir.join(format!("{MANIFEST}.tmp-{}", std::process::id()));
        let written =
            step(|| fs::write(&tmp, text)).and_then(|()| step(|| fs::rename(&tmp, dir.join(name))));
        if written.is_err() {
            let _ = fs::remove_file(&tmp);
        }
        written
    }
}

/// The SHA-256 of the file `path`, as 64 lowercase hexadecimal digits, streamed through the hasher.
pub fn sha256_of(path: &Path) -> io::Result<String> {
    let mut hasher = Sha256::new();
    io::copy(&mut fs::File::open(path)?, &mut hasher)?;
    Ok(hex(&hasher.finalize()))
}

/// The SHA-256 of `bytes`, as 64 lowercase hexadecimal digits.
pub fn sha256(bytes: &[u8]) -> String {
    hex(&Sha256::digest(bytes))
}

/// `bytes` as lowercase hexadecimal digits, two per byte.
pub fn hex(bytes: &[u8]) -> String {
    bytes.iter().map(|b| format!("{b:02x}")).collect()
}

/// Every entry under `dir` that is not a directory, as `(relative path, path, is a regular
/// file)`, the manifest and hidden work files of the harness left out (`.…tmp-<pid>`), in
/// sorted order; directories are descended into.
pub fn entries(dir: &Path) -> io::Result<Vec<(String, PathBuf, bool)>> {
    let mut found = Vec::new();
    collect(dir, "", &mut found)?;
    found.sort();
    Ok(found)
}

fn collect(dir: &Path, prefix: &str, found: &mut Vec<(String, PathBuf, bool)>) -> io::Result<()> {
    for entry in fs::read_dir(dir)? {
        let entry = entry?;
        let name = entry.file_name().to_string_lossy().into_owned();
        if prefix.is_empty()
            && (name == MANIFEST || name == NEXT_MANIFEST || is_manifest_temporary(&name))
        {
            continue;
        }
        let rel = format!("{prefix}{name}");
        let kind = entry.file_type()?;
        if kind.is_dir() {
            collect(&entry.path(), &format!("{rel}/"), found)?;
        } else {
            found.push((rel, entry.path(), kind.is_file()));
        }
    }
    Ok(())
}

/// Whether `name` is a temporary file of [`Manifest::write`] (left by a killed process).
fn is_manifest_temporary(name: &str) -> bool {
    name.strip_prefix(MANIFEST)
        .and_then(|rest| rest.strip_prefix(".tmp-"))
        .is_some_and(|pid| !pid.is_empty() && pid.bytes().all(|b| b.is_ascii_digit()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sha256_matches_its_reference_value() {
        assert_eq!(
            sha256(b"abc"),
            "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad"
        );
    }
}
