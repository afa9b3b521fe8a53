//! The journal of a commit that takes more than one rename, so that a commit cut anywhere
//! (SIGKILL, a power loss, a full disk) leaves the old outputs whole or is completed by the next
//! command into the directory.
//!
//! Before the first change to the target `DIR`, the commit writes `.DIR.journal` beside it
//! (through a temporary file and a rename: the journal is whole or absent). It names the staging
//! directory, the replaced directory (a swap) and the old files to remove; the manifest the
//! directory will have is already in the staging directory ([`NEXT_MANIFEST`]). From then on the
//! commit only moves and removes, and can always be rolled forward: every staged file is whole
//! before the journal exists. [`complete`] rolls a journal forward: it removes what is listed,
//! renames what is still staged onto its place, installs the manifest, and removes the journal,
//! the staging and the replaced directory. The next command into `DIR` calls it under the
//! directory's lock, before it looks at `DIR`; a commit that fails after its journal calls it at
//! once.
//!
//! Each file operation goes through [`crate::harness::files::fault::step`], where the tests of
//! `tests/cli/commit_faults.rs` cut it.

use std::ffi::OsString;
use std::fs;
use std::io;
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use crate::harness::files::fault::step;
use crate::harness::files::manifest::{entries, MANIFEST, NEXT_MANIFEST};

/// The journal's format.
const JOURNAL_FORMAT: &str = "signorini-commit-journal/1";

/// A commit in progress, as `.DIR.journal` records it.
#[derive(Debug, Serialize, Deserialize)]
pub struct Journal {
    /// [`JOURNAL_FORMAT`].
    format: String,
    /// The staging directory's name (beside `DIR`).
    staging: String,
    /// The replaced directory's name (beside `DIR`) when the commit swaps `DIR` whole.
    old: Option<String>,
    /// The old files of `DIR` to remove, relative to it.
    remove: Vec<String>,
}

/// `.<name>.journal`, beside the target.
pub fn journal_path(parent: &Path, name: &OsString) -> PathBuf {
    parent.join(format!(".{}.journal", name.to_string_lossy()))
}

impl Journal {
    /// A commit that moves the files of `staging` into the target, removing `remove` first.
    pub fn moving(staging: &Path, remove: Vec<String>) -> Self {
        Self {
            format: JOURNAL_FORMAT.to_string(),
            staging: file_name(staging),
            old: None,
            remove,
        }
    }

    /// A commit that renames the target to `old` and `staging` to the target.
    pub fn swapping(staging: &Path, old: &Path) -> Self {
        Self {
            format: JOURNAL_FORMAT.to_string(),
            staging: file_name(staging),
            old: Some(file_name(old)),
            remove: Vec::new(),
        }
    }

    /// Writes the journal to `path`, whole or not at all.
    pub fn write(&self, path: &Path) -> io::Result<()> {
        let text = serde_json::to_string(self).map_err(io::Error::other)?;
        let tmp = path.with_extension(format!("tmp-{}", std::process::id()));
        let written = step(|| fs::write(&tmp, text)).and_then(|()| step(|| fs::rename(&tmp, path)));
        if written.is_err() {
            let _ = fs::remove_file(&tmp);
        }
        written
    }
}

/// The last component of `path`, as the journal records names.
fn file_name(path: &Path) -> String {
    path.file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default()
}

/// Rolls forward the commit into `dir` that the journal `.<name>.journal` in `parent` records, if
/// there is one: whether there was. The caller holds the directory's lock.
pub fn complete(parent: &Path, name: &OsString, dir: &Path) -> io::Result<bool> {
    let path = journal_path(parent, name);
    let text = match fs::read_to_string(&path) {
        Ok(text) => text,
        Err(e) if e.kind() == io::ErrorKind::NotFound => return Ok(false),
        Err(e) => return Err(e),
    };
    let journal: Journal = serde_json::from_str(&text).map_err(io::Error::other)?;
    if journal.format != JOURNAL_FORMAT || !plain(&journal.staging) {
        return Err(io::Error::other(format!(
            "{} is not a commit journal signorini wrote",
            path.display()
        )));
    }
    let staging = parent.join(&journal.staging);
    match &journal.old {
        Some(old) if plain(old) => {
            let old = parent.join(old);
            if staging.is_dir() {
                if dir.exists() && !old.exists() {
                    step(|| fs::rename(dir, &old))?;
                }
                step(|| fs::rename(&staging, dir))?;
            }
            step(|| fs::remove_file(&path))?;
            if old.is_dir() {
                step(|| fs::remove_dir_all(&old))?;
            }
        }
        Some(_) => return Err(io::Error::other("a journal naming a path, not a name")),
        None => {
            for rel in &journal.remove {
                match step(|| fs::remove_file(dir.join(rel))) {
                    Err(e) if e.kind() != io::ErrorKind::NotFound => return Err(e),
                    _ => {}
                }
            }
            if staging.is_dir() {
                for (rel, from, _) in entries(&staging)? {
                    let to = dir.join(&rel);
                    if let Some(parent) = to.parent() {
                        fs::create_dir_all(parent)?;
                    }
                    step(|| fs::rename(&from, &to))?;
                }
                let next = staging.join(NEXT_MANIFEST);
                if next.exists() {
                    step(|| fs::rename(&next, dir.join(MANIFEST)))?;
                }
            }
            step(|| fs::remove_file(&path))?;
            if staging.is_dir() {
                fs::remove_dir_all(&staging)?;
            }
        }
    }
    Ok(true)
}

/// Whether `name` is one path component (the journal names entries beside the target only).
fn plain(name: &str) -> bool {
    !name.is_empty() && !name.contains('/') && name != "." && name != ".."
}
