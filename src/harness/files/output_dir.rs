//! Output directories that are whole or absent: what a command with `--out DIR` writes appears
//! in `DIR` only once all of it is written, never half, never mixed with another run's.
//!
//! A command begins a [`StagedDir`] before it computes anything and writes its files into
//! [`StagedDir::path`], a fresh staging directory `.DIR.staging-<pid>` beside `DIR` (same parent,
//! so that a rename moves it atomically). [`StagedDir::commit`] moves the files into place at the
//! end; a staged directory dropped without commit (a failed or refused run) is removed, and so is
//! every parent directory its start created.
//!
//! What is the command's own is what it can prove it wrote: the manifest it keeps in the
//! directory ([`crate::harness::files::manifest`]) lists every file it put there with the SHA-256
//! of its content, and the directory's identity when the command created it. Nothing else is ever
//! removed or replaced, whatever its name.
//!
//! - **Per-run directories** ([`Replace::Whole`]: `run --out`, `verify --out`, `getfem
//!   --export`): an existing `DIR` is accepted only when each of its files is the harness's
//!   own; one holding anything else is refused before the run starts, naming what it holds. At
//!   the end the old files give way to the new ones: a `DIR` the harness created is replaced
//!   whole by the staging directory (absent for an instant between two renames, never mixed);
//!   any other (one the user made, `.`, the working directory or one of its ancestors, a path
//!   reached through a symbolic link) is written in place, the directory itself kept.
//! - **Shared directories** ([`Replace::Files`]: `reports/`, where several commands write their
//!   files beside committed ones): each staged file is renamed onto its namesake in `DIR` at the
//!   end and every other file of `DIR` is kept; a namesake that is not the harness's own (a
//!   user's file, or one edited since) is not replaced: the commit is refused, naming it, and
//!   nothing moves. A `DIR` that does not exist yet is renamed into place whole.
//!
//! Two commands cannot write one `DIR` at once: [`StagedDir::begin`] takes an exclusive lock
//! (`flock`) on `.DIR.lock` beside it, holding the pid for the message of the one refused. The
//! kernel releases the lock when its process ends, however it ends, so a lock never goes stale;
//! and whoever holds it knows that every other `.DIR.staging-<pid>` (or `.DIR.old-<pid>`, a
//! replaced directory) belongs to a process that is gone (a killed one), and removes it when its
//! manifest shows the harness created it.
//!
//! SIGINT and SIGTERM: the first begin installs a handler thread (`signal-hook`) that waits for
//! the writes and commits in flight ([`crate::harness::files::artifacts::stop_writes`]), removes
//! every staging directory, lock and created parent of the process, then lets the signal end the
//! process as it would have. A commit is never cut in the middle by them. SIGKILL, a power loss or
//! a full disk can cut one: a commit of more than one rename is journalled before it changes
//! `DIR` ([`commit_journal`]), so the old outputs stay whole until the journal exists, and from
//! then on the next command into `DIR` completes the commit before it looks at `DIR` (a commit
//! that fails after its journal tries once more at once). A staging directory left before the
//! journal is removed by the next run into `DIR`.

use std::ffi::OsString;
use std::fs::{self, File, OpenOptions};
use std::io::{self, Read, Seek, SeekFrom, Write};
use std::os::unix::fs::MetadataExt;
use std::path::{Path, PathBuf};
use std::sync::{Mutex, MutexGuard, PoisonError};

use rustix::fs::{flock, FlockOperation};
use signal_hook::consts::{SIGINT, SIGTERM};
use signal_hook::iterator::Signals;
use signal_hook::low_level::emulate_default_handler;
use thiserror::Error;

use crate::harness::files::artifacts::{hold_writes, stop_writes};
use crate::harness::files::commit_journal::{self, journal_path, Journal};
use crate::harness::files::error::printable;
use crate::harness::files::fault::step;
use crate::harness::files::input::Shown;
use crate::harness::files::manifest::{
    entries, DirIdentity, Manifest, MANIFEST_FORMAT, NEXT_MANIFEST,
};

/// How the staged files reach the target directory (see the module's documentation).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Replace {
    /// A per-run directory, whose files are all the harness's own: its old files give way to
    /// the new ones.
    Whole,
    /// A shared directory: each staged file replaces its namesake, the other files are kept.
    Files,
}

/// Why an output directory cannot be written.
#[derive(Debug, Error)]
pub enum OutputDirError {
    /// The target exists and is not a directory.
    #[error("{option} {} is a file, not a directory", Shown(dir))]
    NotADirectory {
        /// The command-line option naming the directory.
        option: &'static str,
        /// The directory.
        dir: PathBuf,
    },
    /// The directory holds files the harness did not write (by its manifest) that the command
    /// would remove or replace.
    #[error(
        "{option} {}: holds {}, which signorini did not write (or which changed since), and \
         would {}; move {} away or choose another directory",
        Shown(dir),
        listed(entries),
        if *whole { "be removed with the run's old files" } else { "be replaced" },
        if entries.len() == 1 { "it" } else { "them" }
    )]
    Foreign {
        /// The command-line option naming the directory.
        option: &'static str,
        /// The directory.
        dir: PathBuf,
        /// The entries not the harness's, relative to the directory.
        entries: Vec<String>,
        /// Whether the directory is a per-run one ([`Replace::Whole`]).
        whole: bool,
    },
    /// Another process is writing the directory.
    #[error(
        "{option} {}: being written by another signorini process (pid {pid}); wait for it to \
         finish or choose another directory",
        Shown(dir)
    )]
    Busy {
        /// The command-line option naming the directory.
        option: &'static str,
        /// The directory.
        dir: PathBuf,
        /// The other process's id, as its lock file holds it.
        pid: String,
    },
    /// The staging directory, its lock or a parent could not be created.
    #[error("cannot create {option} {}: {source}", Shown(dir))]
    Create {
        /// The command-line option naming the directory.
        option: &'static str,
        /// The directory.
        dir: PathBuf,
        /// What the system reported.
        #[source]
        source: io::Error,
    },
    /// The directory holds a file the command reads, which its outputs would remove or replace.
    #[error(
        "{option} {}: holds {}, which this command reads: its outputs would {} it; choose \
         another directory",
        Shown(dir),
        Shown(input),
        if *whole { "remove or replace" } else { "replace" }
    )]
    HoldsInput {
        /// The command-line option naming the directory.
        option: &'static str,
        /// The directory.
        dir: PathBuf,
        /// The input file.
        input: PathBuf,
        /// Whether the directory is a per-run one ([`Replace::Whole`]).
        whole: bool,
    },
    /// The staged files could not be moved into place.
    #[error("cannot write {option} {}: {source}", Shown(dir))]
    Commit {
        /// The command-line option naming the directory.
        option: &'static str,
        /// The directory.
        dir: PathBuf,
        /// What the system reported.
        #[source]
        source: io::Error,
    },
}

impl OutputDirError {
    /// Whether the error is the user's to fix in the arguments (exit code 2): a file named as
    /// the directory, or a directory holding files the command would delete.
    pub fn is_usage(&self) -> bool {
        matches!(
            self,
            Self::NotADirectory { .. } | Self::Foreign { .. } | Self::HoldsInput { .. }
        )
    }
}

/// The first few of `entries`, and how many more.
fn listed(entries: &[String]) -> String {
    const SHOWN: usize = 5;
    let names: Vec<String> = entries.iter().take(SHOWN).map(|e| printable(e)).collect();
    match entries.len().checked_sub(SHOWN) {
        Some(more) if more > 0 => format!("{} and {more} more", names.join(", ")),
        _ => names.join(", "),
    }
}

/// What an uncommitted staged directory leaves on disk, removed on drop or on a signal.
struct Leftovers {
    id: u64,
    staging: Option<PathBuf>,
    lock: Option<PathBuf>,
    /// Parents created for the target, deepest first.
    created: Vec<PathBuf>,
}

impl Leftovers {
    fn remove(&self) {
        if let Some(staging) = &self.staging {
            let _ = fs::remove_dir_all(staging);
        }
        if let Some(lock) = &self.lock {
            let _ = fs::remove_file(lock);
        }
        for dir in &self.created {
            let _ = fs::remove_dir(dir);
        }
    }
}

/// The process's staged directories not yet committed, and whether the signal thread runs.
struct Registry {
    signals_installed: bool,
    next_id: u64,
    entries: Vec<Leftovers>,
}

static ACTIVE: Mutex<Registry> = Mutex::new(Registry {
    signals_installed: false,
    next_id: 0,
    entries: Vec::new(),
});

fn registry() -> MutexGuard<'static, Registry> {
    ACTIVE.lock().unwrap_or_else(PoisonError::into_inner)
}

/// An output directory being written: the files go to [`StagedDir::path`] and reach the target
/// at [`StagedDir::commit`]; dropped uncommitted, it leaves nothing.
#[derive(Debug)]
pub struct StagedDir {
    option: &'static str,
    target: PathBuf,
    dir: PathBuf,
    staging: PathBuf,
    replace: Replace,
    in_place: bool,
    id: u64,
    /// The files the command reads ([`StagedDir::reading`]), resolved.
    inputs: Vec<PathBuf>,
    _lock: File,
}

/// Where a command writes when given the path `target`: the directory itself (a symbolic link
/// resolved), and whether it must be kept (written in place, never swapped): a link's target,
/// the working directory and its ancestors.
fn resolve(target: &Path) -> io::Result<(PathBuf, bool)> {
    let is_link = fs::symlink_metadata(target).is_ok_and(|m| m.file_type().is_symlink());
    if is_link {
        return Ok((fs::canonicalize(target)?, true));
    }
    let Ok(real) = fs::canonicalize(target) else {
        return Ok((target.to_path_buf(), false));
    };
    let holds_cwd = std::env::current_dir()
        .and_then(fs::canonicalize)
        .is_ok_and(|cwd| cwd.starts_with(&real));
    let dir = if target.file_name().is_some() {
        target.to_path_buf()
    } else {
        real
    };
    Ok((dir, holds_cwd))
}

impl StagedDir {
    /// Starts writing the directory `target`, named by the command-line option `option`:
    /// refuses a file, a per-run directory holding files the harness did not write and a
    /// directory another process writes; creates the missing parents, takes the lock, removes
    /// the staging directories of dead processes and creates this one's.
    pub fn begin(
        option: &'static str,
        target: &Path,
        replace: Replace,
    ) -> Result<Self, OutputDirError> {
        let create = |source| OutputDirError::Create {
            option,
            dir: target.to_path_buf(),
            source,
        };
        let mut registry = registry();
        if !registry.signals_installed {
            install_signal_cleanup().map_err(create)?;
            registry.signals_installed = true;
        }
        let (dir, in_place) = resolve(target).map_err(create)?;
        let (parent, name) = split(&dir).map_err(create)?;
        let dir = parent.join(&name);
        if fs::metadata(&dir).is_ok_and(|m| !m.is_dir()) {
            return Err(OutputDirError::NotADirectory {
                option,
                dir: target.to_path_buf(),
            });
        }
        let id = registry.next_id;
        registry.next_id += 1;
        let mut leftovers = Leftovers {
            id,
            staging: None,
            lock: None,
            created: Vec::new(),
        };
        let started = (|| {
            leftovers.created = create_parents(&parent).map_err(create)?;
            let lock_path = parent.join(hidden(&name, "lock"));
            let lock = match lock(&lock_path).map_err(create)? {
                Ok(file) => file,
                Err(pid) => {
                    return Err(OutputDirError::Busy {
                        option,
                        dir: target.to_path_buf(),
                        pid,
                    })
                }
            };
            leftovers.lock = Some(lock_path);
            if commit_journal::complete(&parent, &name, &dir).map_err(create)? {
                eprintln!(
                    "{option} {}: completed the commit of an earlier run that was cut",
                    Shown(target)
                );
            }
            if replace == Replace::Whole {
                check_owned(&dir, option, target)?;
            }
            remove_stale(&parent, &name).map_err(create)?;
            let staging = parent.join(hidden(&name, &format!("staging-{}", std::process::id())));
            fs::create_dir(&staging).map_err(create)?;
            leftovers.staging = Some(staging.clone());
            Manifest::new(Some(DirIdentity::of(&staging).map_err(create)?))
                .write(&staging)
                .map_err(create)?;
            Ok((lock, staging))
        })();
        match started {
            Ok((lock, staging)) => {
                registry.entries.push(leftovers);
                Ok(Self {
                    option,
                    target: target.to_path_buf(),
                    dir,
                    staging,
                    replace,
                    in_place,
                    id,
                    inputs: Vec::new(),
                    _lock: lock,
                })
            }
            Err(e) => {
                leftovers.remove();
                Err(e)
            }
        }
    }

    /// Declares the files the command reads: a per-run directory ([`Replace::Whole`]) that
    /// holds one of them (at any depth) is refused now, before anything is computed; a shared
    /// one ([`Replace::Files`]) refuses at the commit a staged file that would replace one.
    pub fn reading<P: AsRef<Path>>(mut self, inputs: &[P]) -> Result<Self, OutputDirError> {
        self.inputs = inputs
            .iter()
            .filter_map(|p| fs::canonicalize(p).ok())
            .collect();
        if self.replace == Replace::Whole {
            let dir = fs::canonicalize(&self.dir).unwrap_or_else(|_| self.dir.clone());
            if let Some(k) = self.inputs.iter().position(|i| i.starts_with(&dir)) {
                return Err(OutputDirError::HoldsInput {
                    option: self.option,
                    dir: self.target.clone(),
                    input: inputs[k].as_ref().to_path_buf(),
                    whole: true,
                });
            }
        }
        Ok(self)
    }

    /// The staging directory, where the command writes its files.
    pub fn path(&self) -> &Path {
        &self.staging
    }

    /// Where `staged`, a path under [`StagedDir::path`], will be after the commit.
    pub fn final_path(&self, staged: &Path) -> PathBuf {
        staged
            .strip_prefix(&self.staging)
            .map_or_else(|_| staged.to_path_buf(), |rel| self.target.join(rel))
    }

    /// Moves the staged files into place (see [`Replace`]) with the manifest that proves them
    /// the harness's, then removes the staging directory and the lock. SIGINT and SIGTERM wait
    /// for it to finish.
    pub fn commit(self) -> Result<(), OutputDirError> {
        let _writes = hold_writes();
        let mut registry = registry();
        let staged = self.staged_manifest();
        let moved = match staged {
            Err(source) => Err(source),
            Ok(staged) => self.place(staged)?,
        };
        let mut leftovers = take(&mut registry, self.id);
        if moved.is_ok() {
            leftovers.iter_mut().for_each(|l| l.created.clear());
        }
        leftovers.iter().for_each(Leftovers::remove);
        moved.map_err(|source| OutputDirError::Commit {
            option: self.option,
            dir: self.target.clone(),
            source,
        })
    }

    /// The staging directory's manifest, completed with every staged file.
    fn staged_manifest(&self) -> io::Result<Manifest> {
        let mut manifest = Manifest::of(&self.staging);
        for (rel, path, _) in entries(&self.staging)? {
            manifest.record(rel, &path)?;
        }
        Ok(manifest)
    }

    /// Puts the staged files in place: the staging directory renamed to a new target or swapped
    /// with one the harness created; otherwise each file moved in, after the ownership checks
    /// (a refusal is the outer error, an I/O failure the inner one).
    fn place(&self, staged: Manifest) -> Result<io::Result<()>, OutputDirError> {
        if !self.dir.exists() {
            return Ok(staged
                .write(&self.staging)
                .and_then(|()| step(|| fs::rename(&self.staging, &self.dir))));
        }
        let existing = Manifest::of(&self.dir);
        if self.replace == Replace::Whole {
            check_owned(&self.dir, self.option, &self.target)?;
            if existing.created(&self.dir) && !self.in_place {
                return Ok(staged.write(&self.staging).and_then(|()| self.swap()));
            }
        } else {
            let dir = fs::canonicalize(&self.dir).unwrap_or_else(|_| self.dir.clone());
            if let Some(input) = staged
                .files
                .keys()
                .map(|rel| dir.join(rel))
                .find(|path| self.inputs.contains(path))
            {
                return Err(OutputDirError::HoldsInput {
                    option: self.option,
                    dir: self.target.clone(),
                    input,
                    whole: false,
                });
            }
            let foreign: Vec<String> = staged
                .files
                .keys()
                .filter(|rel| {
                    fs::symlink_metadata(self.dir.join(rel)).is_ok()
                        && !existing.owns(&self.dir, rel)
                })
                .cloned()
                .collect();
            if !foreign.is_empty() {
                return Err(OutputDirError::Foreign {
                    option: self.option,
                    dir: self.target.clone(),
                    entries: foreign,
                    whole: false,
                });
            }
        }
        Ok(self.move_in(existing, staged))
    }

    /// Moves every staged file onto its namesake in the existing target, with the target's
    /// manifest completed by the staged files; for [`Replace::Whole`] the old files not
    /// replaced are removed first. The manifest to be is staged ([`NEXT_MANIFEST`]) and the
    /// commit journalled before anything in the target changes ([`commit_journal`]).
    fn move_in(&self, mut existing: Manifest, staged: Manifest) -> io::Result<()> {
        let mut remove = Vec::new();
        if self.replace == Replace::Whole {
            remove = existing
                .files
                .keys()
                .filter(|rel| !staged.files.contains_key(*rel) && existing.owns(&self.dir, rel))
                .cloned()
                .collect();
            existing.files.clear();
        }
        existing.format = MANIFEST_FORMAT.to_string();
        existing.files.extend(staged.files);
        existing.write_as(&self.staging, NEXT_MANIFEST)?;
        self.journalled(Journal::moving(&self.staging, remove))
    }

    /// [`Replace::Whole`] on a directory the harness created: the staging directory becomes the
    /// target; the old target is renamed aside first and removed after, the two renames
    /// journalled ([`commit_journal`]).
    fn swap(&self) -> io::Result<()> {
        let (parent, name) = split(&self.dir)?;
        let old = parent.join(hidden(&name, &format!("old-{}", std::process::id())));
        self.journalled(Journal::swapping(&self.staging, &old))
    }

    /// Writes `journal`, then carries it out by [`commit_journal::complete`]; a failure past
    /// the journal is retried once at once, and otherwise left for the next command into the
    /// directory to complete.
    fn journalled(&self, journal: Journal) -> io::Result<()> {
        let (parent, name) = split(&self.dir)?;
        journal.write(&journal_path(&parent, &name))?;
        match commit_journal::complete(&parent, &name, &self.dir) {
            Ok(_) => Ok(()),
            Err(_) => commit_journal::complete(&parent, &name, &self.dir).map(|_| ()),
        }
    }
}

impl Drop for StagedDir {
    fn drop(&mut self) {
        let mut registry = registry();
        take(&mut registry, self.id)
            .iter()
            .for_each(Leftovers::remove);
    }
}

/// Removes the entry `id` from the registry and returns it (none once committed or cleaned).
fn take(registry: &mut Registry, id: u64) -> Option<Leftovers> {
    let k = registry.entries.iter().position(|l| l.id == id)?;
    Some(registry.entries.swap_remove(k))
}

/// The parent and the file name of `target` (`.` and `..` resolved first).
fn split(target: &Path) -> io::Result<(PathBuf, OsString)> {
    let target = match target.file_name() {
        Some(_) => target.to_path_buf(),
        None => fs::canonicalize(target)?,
    };
    let name = target
        .file_name()
        .ok_or_else(|| io::Error::other(format!("{} has no directory name", Shown(&target))))?;
    let parent = target
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    Ok((parent.to_path_buf(), name.to_os_string()))
}

/// `.<name>.<suffix>`, beside the target.
fn hidden(name: &OsString, suffix: &str) -> String {
    format!(".{}.{suffix}", name.to_string_lossy())
}

/// Refuses a per-run directory `dir` that holds an entry its manifest does not prove the
/// harness's.
fn check_owned(dir: &Path, option: &'static str, target: &Path) -> Result<(), OutputDirError> {
    if !dir.is_dir() {
        return Ok(());
    }
    let manifest = Manifest::of(dir);
    let found = entries(dir).map_err(|source| OutputDirError::Create {
        option,
        dir: target.to_path_buf(),
        source,
    })?;
    let foreign: Vec<String> = found
        .into_iter()
        .filter(|(rel, _, regular)| !(*regular && manifest.owns(dir, rel)))
        .map(|(rel, _, _)| rel)
        .collect();
    if foreign.is_empty() {
        return Ok(());
    }
    Err(OutputDirError::Foreign {
        option,
        dir: target.to_path_buf(),
        entries: foreign,
        whole: true,
    })
}

/// Creates `dir` and its missing parents; returns those created, deepest first.
fn create_parents(dir: &Path) -> io::Result<Vec<PathBuf>> {
    let missing: Vec<PathBuf> = dir
        .ancestors()
        .take_while(|a| !a.as_os_str().is_empty() && !a.exists())
        .map(Path::to_path_buf)
        .collect();
    let mut created = Vec::new();
    for d in missing.iter().rev() {
        match fs::create_dir(d) {
            Ok(()) => created.push(d.clone()),
            Err(e) if e.kind() == io::ErrorKind::AlreadyExists => {}
            Err(e) => {
                created.iter().rev().for_each(|c| {
                    let _ = fs::remove_dir(c);
                });
                return Err(e);
            }
        }
    }
    created.reverse();
    Ok(created)
}

/// Takes the exclusive lock `path` and writes this process's id into it; `Err(pid)` with the
/// holder's id when another process holds it.
fn lock(path: &Path) -> io::Result<Result<File, String>> {
    loop {
        let mut file = OpenOptions::new()
            .read(true)
            .write(true)
            .create(true)
            .truncate(false)
            .open(path)?;
        if let Err(e) = flock(&file, FlockOperation::NonBlockingLockExclusive) {
            if e != rustix::io::Errno::WOULDBLOCK {
                return Err(e.into());
            }
            return Ok(Err(holder_pid(&mut file)));
        }
        // The previous holder unlinks the file before it releases the lock: a lock taken on an
        // unlinked file is taken again on the path's new file.
        let held = file.metadata()?;
        let current = fs::metadata(path).ok();
        if current.is_some_and(|c| c.dev() == held.dev() && c.ino() == held.ino()) {
            file.set_len(0)?;
            write!(file, "{}", std::process::id())?;
            return Ok(Ok(file));
        }
    }
}

/// The process id the holder of a lock wrote into it. The holder writes it just after taking the
/// lock, so a refused process can find the file still empty: it reads again for up to 100 ms
/// before calling the holder unknown.
fn holder_pid(file: &mut File) -> String {
    for _ in 0..50 {
        let mut pid = String::new();
        let read = file
            .seek(SeekFrom::Start(0))
            .and_then(|_| file.take(32).read_to_string(&mut pid));
        let pid = pid.trim();
        if read.is_ok() && !pid.is_empty() {
            return printable(pid);
        }
        std::thread::sleep(std::time::Duration::from_millis(2));
    }
    "unknown".to_string()
}

/// Removes the staging and replaced directories of `name` left by other processes: the caller
/// holds the lock, so their processes are gone. Only a directory whose manifest shows the
/// harness created it is removed.
fn remove_stale(parent: &Path, name: &OsString) -> io::Result<()> {
    let prefixes = [hidden(name, "staging-"), hidden(name, "old-")];
    for entry in fs::read_dir(parent)?.flatten() {
        let entry_name = entry.file_name().to_string_lossy().into_owned();
        let stale = prefixes.iter().any(|p| {
            entry_name
                .strip_prefix(p.as_str())
                .is_some_and(|pid| !pid.is_empty() && pid.bytes().all(|b| b.is_ascii_digit()))
        });
        let path = entry.path();
        let ours = fs::symlink_metadata(&path).is_ok_and(|m| m.is_dir())
            && Manifest::of(&path).created(&path);
        if stale && ours {
            fs::remove_dir_all(path)?;
        }
    }
    Ok(())
}

/// Starts the thread that, on SIGINT or SIGTERM, removes what every uncommitted staged
/// directory left and ends the process by the signal.
fn install_signal_cleanup() -> io::Result<()> {
    let mut signals = Signals::new([SIGINT, SIGTERM])?;
    std::thread::Builder::new()
        .name("output-cleanup".to_string())
        .spawn(move || {
            if let Some(signal) = signals.forever().next() {
                let _no_more_writes = stop_writes();
                let mut registry = registry();
                registry.entries.drain(..).for_each(|l| l.remove());
                let _ = emulate_default_handler(signal);
                std::process::exit(128 + signal);
            }
        })?;
    Ok(())
}
