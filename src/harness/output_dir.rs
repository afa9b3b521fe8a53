//! Output directories that are whole or absent: what a command with `--out DIR` writes appears
//! in `DIR` only once all of it is written, never half, never mixed with another run's.
//!
//! A command begins a [`StagedDir`] before it computes anything and writes its files into
//! [`StagedDir::path`], a fresh staging directory `.DIR.staging-<pid>` beside `DIR` (same parent,
//! so that a rename moves it atomically). [`StagedDir::commit`] moves the files into place at the
//! end; a staged directory dropped without commit (a failed or refused run) is removed, and so is
//! every parent directory its start created.
//!
//! - **Per-run directories** ([`Replace::Whole`]: `run --out`, `verify --out`, `getfem
//!   --export`): the staging directory is renamed to `DIR`. An existing `DIR` is replaced whole,
//!   so that no file of an earlier run stays beside the new ones, but only when each of its
//!   entries is a file the command writes (its `owns`): a directory holding anything else is
//!   refused before the run starts, and nothing of the user's is ever deleted. Between the two
//!   renames of a replacement `DIR` is absent for an instant, never mixed.
//! - **Shared directories** ([`Replace::Files`]: `reports/`, where several commands write their
//!   files beside committed ones): each staged file is renamed onto its namesake in `DIR` at the
//!   end and every other file of `DIR` is kept. A `DIR` that does not exist yet is renamed into
//!   place whole.
//!
//! Two commands cannot write one `DIR` at once: [`StagedDir::begin`] takes an exclusive lock
//! (`flock`) on `.DIR.lock` beside it, holding the pid for the message of the one refused. The
//! kernel releases the lock when its process ends, however it ends, so a lock never goes stale;
//! and whoever holds it knows that every other `.DIR.staging-<pid>` (or `.DIR.old-<pid>`, a
//! replaced directory) belongs to a process that is gone (a killed one), and removes it.
//!
//! SIGINT and SIGTERM: the first begin installs a handler thread (`signal-hook`) that waits for
//! the writes and commits in flight ([`crate::harness::artifacts::stop_writes`]), removes every
//! staging directory, lock and created parent of the process, then lets the signal end the
//! process as it would have. A commit is never cut in the middle by them. Only SIGKILL or a power
//! loss leaves a staging directory (removed by the next run into `DIR`), and only during the
//! instant of a commit a shared directory with part of the new files.

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

use crate::harness::artifacts::{hold_writes, stop_writes};

/// How the staged files reach the target directory (see the module's documentation).
#[derive(Debug, Clone, Copy)]
pub enum Replace {
    /// A per-run directory, replaced whole; an existing one only when `owns` accepts the name of
    /// each of its entries (all files).
    Whole {
        /// Whether a file name is one the command writes.
        owns: fn(&str) -> bool,
    },
    /// A shared directory: each staged file replaces its namesake, the other files are kept.
    Files,
}

/// Why an output directory cannot be written.
#[derive(Debug, Error)]
pub enum OutputDirError {
    /// The target exists and is not a directory.
    #[error("{option} {} is a file, not a directory", dir.display())]
    NotADirectory {
        /// The command-line option naming the directory.
        option: &'static str,
        /// The directory.
        dir: PathBuf,
    },
    /// A per-run directory holds something the command does not write.
    #[error(
        "{option} {}: holds {entry}, which this command does not write, and would be replaced \
         whole; remove it or choose another directory",
        dir.display()
    )]
    Foreign {
        /// The command-line option naming the directory.
        option: &'static str,
        /// The directory.
        dir: PathBuf,
        /// The entry the command does not write.
        entry: String,
    },
    /// Another process is writing the directory.
    #[error(
        "{option} {}: being written by another signorini process (pid {pid}); wait for it to \
         finish or choose another directory",
        dir.display()
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
    #[error("cannot create {option} {}: {source}", dir.display())]
    Create {
        /// The command-line option naming the directory.
        option: &'static str,
        /// The directory.
        dir: PathBuf,
        /// What the system reported.
        #[source]
        source: io::Error,
    },
    /// The staged files could not be moved into place.
    #[error("cannot write {option} {}: {source}", dir.display())]
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
        matches!(self, Self::NotADirectory { .. } | Self::Foreign { .. })
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
    id: u64,
    _lock: File,
}

impl StagedDir {
    /// Starts writing the directory `target`, named by the command-line option `option`:
    /// refuses a file, a per-run directory with foreign entries and a directory another
    /// process writes; creates the missing parents, takes the lock, removes the staging
    /// directories of dead processes and creates this one's.
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
        let (parent, name) = split(target).map_err(create)?;
        let dir = parent.join(&name);
        if fs::metadata(&dir).is_ok_and(|m| !m.is_dir()) {
            return Err(OutputDirError::NotADirectory {
                option,
                dir: target.to_path_buf(),
            });
        }
        if let Replace::Whole { owns } = replace {
            check_owned(&dir, owns, option, target)?;
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
            remove_stale(&parent, &name).map_err(create)?;
            let staging = parent.join(hidden(&name, &format!("staging-{}", std::process::id())));
            fs::create_dir(&staging).map_err(create)?;
            leftovers.staging = Some(staging.clone());
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
                    id,
                    _lock: lock,
                })
            }
            Err(e) => {
                leftovers.remove();
                Err(e)
            }
        }
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

    /// Moves the staged files into place (see [`Replace`]), then removes the staging directory
    /// and the lock. SIGINT and SIGTERM wait for it to finish.
    pub fn commit(self) -> Result<(), OutputDirError> {
        let _writes = hold_writes();
        let mut registry = registry();
        let moved = match self.replace {
            Replace::Whole { owns } => {
                check_owned(&self.dir, owns, self.option, &self.target)?;
                self.swap()
            }
            Replace::Files => self.move_files(),
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

    /// [`Replace::Whole`]: the staging directory becomes the target; an existing target is
    /// renamed aside first and removed after.
    fn swap(&self) -> io::Result<()> {
        if !self.dir.exists() {
            return fs::rename(&self.staging, &self.dir);
        }
        let (parent, name) = split(&self.dir)?;
        let old = parent.join(hidden(&name, &format!("old-{}", std::process::id())));
        fs::rename(&self.dir, &old)?;
        if let Err(e) = fs::rename(&self.staging, &self.dir) {
            let _ = fs::rename(&old, &self.dir);
            return Err(e);
        }
        fs::remove_dir_all(&old)
    }

    /// [`Replace::Files`]: every staged file onto its namesake under the target.
    fn move_files(&self) -> io::Result<()> {
        if !self.dir.exists() {
            return fs::rename(&self.staging, &self.dir);
        }
        move_tree(&self.staging, &self.dir)
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
        .ok_or_else(|| io::Error::other(format!("{} has no directory name", target.display())))?;
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

/// Refuses a per-run directory `dir` that holds an entry `owns` does not accept.
fn check_owned(
    dir: &Path,
    owns: fn(&str) -> bool,
    option: &'static str,
    target: &Path,
) -> Result<(), OutputDirError> {
    let Ok(entries) = fs::read_dir(dir) else {
        return Ok(());
    };
    for entry in entries.flatten() {
        let name = entry.file_name().to_string_lossy().into_owned();
        let is_file = entry.file_type().is_ok_and(|t| t.is_file());
        if !is_file || !(owns(&name) || owned_temporary(&name, owns)) {
            return Err(OutputDirError::Foreign {
                option,
                dir: target.to_path_buf(),
                entry: name,
            });
        }
    }
    Ok(())
}

/// Whether `name` is the temporary file of an owned file, `.<name>.tmp-<pid>` as
/// [`crate::harness::artifacts::write_atomic`] names it, left by a run killed before this
/// module staged its files.
fn owned_temporary(name: &str, owns: fn(&str) -> bool) -> bool {
    name.strip_prefix('.')
        .and_then(|rest| rest.rsplit_once(".tmp-"))
        .is_some_and(|(file, pid)| {
            owns(file) && !pid.is_empty() && pid.bytes().all(|b| b.is_ascii_digit())
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
            .and_then(|_| file.read_to_string(&mut pid));
        let pid = pid.trim();
        if read.is_ok() && !pid.is_empty() {
            return pid.to_string();
        }
        std::thread::sleep(std::time::Duration::from_millis(2));
    }
    "unknown".to_string()
}

/// Removes the staging and replaced directories of `name` left by other processes: the caller
/// holds the lock, so their processes are gone.
fn remove_stale(parent: &Path, name: &OsString) -> io::Result<()> {
    let prefixes = [hidden(name, "staging-"), hidden(name, "old-")];
    for entry in fs::read_dir(parent)?.flatten() {
        let entry_name = entry.file_name().to_string_lossy().into_owned();
        let stale = prefixes.iter().any(|p| {
            entry_name
                .strip_prefix(p.as_str())
                .is_some_and(|pid| !pid.is_empty() && pid.bytes().all(|b| b.is_ascii_digit()))
        });
        if stale {
            fs::remove_dir_all(entry.path())?;
        }
    }
    Ok(())
}

/// Renames every file under `from` onto the same relative path under `to`, creating the
/// directories missing there.
fn move_tree(from: &Path, to: &Path) -> io::Result<()> {
    for entry in fs::read_dir(from)? {
        let entry = entry?;
        let target = to.join(entry.file_name());
        if entry.file_type()?.is_dir() {
            if !target.is_dir() {
                fs::create_dir(&target)?;
            }
            move_tree(&entry.path(), &target)?;
        } else {
            fs::rename(entry.path(), &target)?;
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
