//! How the harness's files are written, whatever their format: whole or not at all (into a
//! temporary file beside the target, then renamed), JSON through serde, CSV as columns of
//! numbers. The formats themselves (names, schema) belong to the module that writes them and
//! that its readers import: a run's files to [`crate::harness::run::run_files`], each report file
//! to its study under `crate::studies`. Whole directories are
//! [`crate::harness::files::output_dir`]'s.

use std::fs;
use std::io::Write;
use std::path::Path;
use std::sync::{PoisonError, RwLock, RwLockReadGuard, RwLockWriteGuard};

use serde::de::DeserializeOwned;
use serde::Serialize;

use crate::harness::files::error::Error;
use crate::harness::files::input::{self, Limit};

/// Writes `contents` to `path` atomically, creating the parent directory. A symbolic link is
/// followed (its target is written); an existing path that is not a regular file (a FIFO, a
/// device, a directory) is refused, never replaced.
pub fn write_atomic(path: &Path, contents: &[u8]) -> Result<(), Error> {
    let path = writable(path)?;
    write_whole(&path, contents).map_err(Error::write(&path))
}

/// Where [`write_atomic`] writes `path`: `path`, or the target of the symbolic link it is; an error
/// when that exists and is not a regular file.
pub fn writable(path: &Path) -> Result<std::path::PathBuf, Error> {
    let is_link = fs::symlink_metadata(path).is_ok_and(|m| m.file_type().is_symlink());
    let resolved = if is_link {
        fs::canonicalize(path).map_err(Error::write(path))?
    } else {
        path.to_path_buf()
    };
    match fs::metadata(&resolved) {
        Ok(meta) if !meta.is_file() => Err(Error::NotRegularOutput {
            path: path.to_path_buf(),
            found: input::kind_of(meta.file_type()),
        }),
        _ => Ok(resolved),
    }
}

/// Taken shared by every write in flight and by a directory's commit; taken exclusively by the
/// interrupt's cleanup, which thereby waits for them and then lets none start.
static WRITES: RwLock<()> = RwLock::new(());

/// Holds off [`stop_writes`] while the caller moves finished files into place (a commit of
/// [`crate::harness::files::output_dir`]). Must not be held across a call to [`write_atomic`].
pub fn hold_writes() -> RwLockReadGuard<'static, ()> {
    WRITES.read().unwrap_or_else(PoisonError::into_inner)
}

/// Waits for the writes and commits in flight to finish and blocks every later one for as long
/// as the guard lives: what the interrupt's cleanup holds until the process ends.
pub fn stop_writes() -> RwLockWriteGuard<'static, ()> {
    WRITES.write().unwrap_or_else(PoisonError::into_inner)
}

fn write_whole(path: &Path, contents: &[u8]) -> std::io::Result<()> {
    let _writing = hold_writes();
    let dir = path.parent().filter(|p| !p.as_os_str().is_empty());
    if let Some(dir) = dir {
        fs::create_dir_all(dir)?;
    }
    let name = path
        .file_name()
        .ok_or_else(|| std::io::Error::other(format!("{} is not a file path", path.display())))?;
    let tmp = path.with_file_name(format!(
        ".{}.tmp-{}",
        name.to_string_lossy(),
        std::process::id()
    ));
    let result = (|| {
        let mut f = fs::File::create(&tmp)?;
        f.write_all(contents)?;
        f.sync_all()?;
        fs::rename(&tmp, path)
    })();
    if result.is_err() {
        let _ = fs::remove_file(&tmp);
    }
    result
}

/// Writes `value` to `path` atomically as indented JSON (`serde_json::to_string_pretty`).
pub fn write_json<T: Serialize + ?Sized>(path: &Path, value: &T) -> Result<(), Error> {
    let text = serde_json::to_string_pretty(value).map_err(Error::encode(path))?;
    write_atomic(path, text.as_bytes())
}

/// Writes `value` to `path` atomically as JSON on one line (`serde_json::to_string`), for the
/// large data files only figures read.
pub fn write_json_compact<T: Serialize + ?Sized>(path: &Path, value: &T) -> Result<(), Error> {
    let text = serde_json::to_string(value).map_err(Error::encode(path))?;
    write_atomic(path, text.as_bytes())
}

/// Reads the JSON file `path`, a file of kind `limit`, into a `T` ([`input::read_json`]).
pub fn read_json<T: DeserializeOwned>(path: &Path, limit: Limit) -> Result<T, Error> {
    Ok(input::read_json(path, limit)?)
}

/// A CSV table: the `header` line, then one row per index of the `columns` (of equal length),
/// each number in scientific notation with `digits` digits after the point; a negative zero is
/// written as `0` (`x + 0.0` is `+0.0` for `x = −0.0` and `x` otherwise).
pub fn csv(header: &str, columns: &[&[f64]], digits: usize) -> String {
    let mut s = format!("{header}\n");
    let rows = columns.first().map_or(0, |c| c.len());
    for k in 0..rows {
        let row: Vec<String> = columns
            .iter()
            .map(|c| format!("{:.*e}", digits, c[k] + 0.0))
            .collect();
        s.push_str(&row.join(","));
        s.push('\n');
    }
    s
}
