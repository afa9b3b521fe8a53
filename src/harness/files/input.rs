//! The one way the harness reads a file, whatever its format: scenes, other codes' run files,
//! golden files, shard files, cached references, GetFEM's demo runs and the reports' data.
//!
//! [`open`] refuses anything but a regular file before reading a byte (a FIFO would block, a
//! device such as `/dev/zero` never ends): the file is opened without blocking and its kind
//! is taken from the open descriptor, so a path swapped between a check and the open cannot
//! slip through. The size is checked against the kind's limit ([`Limit`]) before anything is
//! read, and reading stops with an error should the file grow past it while it is read.
//!
//! Memory: [`read_bytes`] and [`read_text`] hold the file once; [`read_json`] streams it into
//! its type, holding a 64 KiB buffer and the value (no copy of the text); [`Lines`] holds one
//! line of at most its `max_line` bytes at a time. What a value may cost beyond that is its
//! reader's to bound (each states it beside its [`Limit`]).

use std::fmt;
use std::fs::{File, OpenOptions};
use std::io::{self, BufRead, BufReader, Read};
use std::marker::PhantomData;
use std::os::unix::fs::{FileTypeExt, OpenOptionsExt};
use std::path::{Path, PathBuf};

use serde::de::{DeserializeOwned, DeserializeSeed};
use thiserror::Error;

/// What a kind of file is called in messages, and the largest such file read.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Limit {
    /// The kind of file, as messages name it (`scene file`, `run file`, …).
    pub what: &'static str,
    /// The largest size read, in bytes.
    pub max_bytes: u64,
}

/// One mebibyte.
const MIB: u64 = 1024 * 1024;

/// A scene file (the committed scenes are under 2 kB; 10⁵ field times are under 1 MB).
pub const SCENE_FILE: Limit = Limit {
    what: "scene file",
    max_bytes: 16 * MIB,
};

/// A golden file (the committed ones are under 100 kB).
pub const GOLDEN_FILE: Limit = Limit {
    what: "golden file",
    max_bytes: 16 * MIB,
};

/// A data file of a reports directory that figures and indexes are drawn from (the largest
/// committed one, a gravity run's histories, is under 10 MB).
pub const REPORT_DATA: Limit = Limit {
    what: "report data file",
    max_bytes: 128 * MIB,
};

/// The largest magnitude a number of a run read back may have (another code's box run, a cached
/// reference): 10¹⁰⁰. The bodies are of unit size, so no displacement, velocity, force or energy
/// of a run comes near it, and the norms sum squares of at most 2⁴⁰ such values without overflow
/// (a displacement of 1e308 at one node, or a cached projection of 1e300, made every error
/// `inf`).
pub const LARGEST_VALUE: f64 = 1e100;

/// The buffer [`read_json`] and [`Lines`] read through.
const BUFFER_BYTES: usize = 64 * 1024;

/// Why a file could not be read.
#[derive(Debug, Error)]
pub enum InputError {
    /// The system could not open or read it (missing, unreadable).
    #[error("cannot read {what} {}: {source}", shown(path))]
    Io {
        /// The kind of file.
        what: &'static str,
        /// The file.
        path: PathBuf,
        /// What the system reported.
        #[source]
        source: io::Error,
    },
    /// Not a regular file.
    #[error(
        "{what} {} is {found}; allowed: a regular file (a FIFO or a device can block or never \
         end, so none is read)",
        shown(path)
    )]
    NotRegular {
        /// The kind of file.
        what: &'static str,
        /// The file.
        path: PathBuf,
        /// What it is instead (`a directory`, `a FIFO`, `a character device`, …).
        found: &'static str,
    },
    /// Larger than its kind's limit.
    #[error(
        "{what} {} has {} bytes; allowed: at most {} bytes ({})",
        shown(path),
        size,
        max,
        mebibytes(*max)
    )]
    TooLarge {
        /// The kind of file.
        what: &'static str,
        /// The file.
        path: PathBuf,
        /// Its size (or the bytes read when it grew while read).
        size: u64,
        /// The limit.
        max: u64,
    },
    /// A line longer than its reader accepts.
    #[error(
        "{what} {}: line {line} is longer than {max} bytes; allowed: lines of at most {max} bytes",
        shown(path)
    )]
    LineTooLong {
        /// The kind of file.
        what: &'static str,
        /// The file.
        path: PathBuf,
        /// The 1-based line.
        line: usize,
        /// The longest line accepted.
        max: usize,
    },
    /// Text that is not UTF-8.
    #[error(
        "{what} {}: not UTF-8 text ({detail}); allowed: UTF-8 text",
        shown(path)
    )]
    NotUtf8 {
        /// The kind of file.
        what: &'static str,
        /// The file.
        path: PathBuf,
        /// Where the first invalid byte is.
        detail: String,
    },
}

impl InputError {
    /// The file the error is about.
    pub fn path(&self) -> &Path {
        match self {
            InputError::Io { path, .. }
            | InputError::NotRegular { path, .. }
            | InputError::TooLarge { path, .. }
            | InputError::LineTooLong { path, .. }
            | InputError::NotUtf8 { path, .. } => path,
        }
    }
}

/// Why a JSON file could not be read into its type.
#[derive(Debug, Error)]
pub enum JsonError {
    /// The file could not be read ([`open`]'s refusals among them).
    #[error(transparent)]
    Input(#[from] InputError),
    /// The text is not the type's JSON (serde's error, with its line and column).
    #[error("{what} {} is not a valid file of its kind (line {}, column {}): {source}", shown(path), source.line(), source.column())]
    Decode {
        /// The kind of file.
        what: &'static str,
        /// The file.
        path: PathBuf,
        /// What serde reported.
        #[source]
        source: serde_json::Error,
    },
}

/// `size` bytes in MiB, for messages.
fn mebibytes(size: u64) -> String {
    format!("{} MiB", size as f64 / MIB as f64)
}

/// `text` with its control characters (terminal escape sequences among them) escaped as
/// `\u{1b}`, so that printing what a file holds (a scene's name, description or values)
/// cannot drive the terminal.
pub fn printable(text: &str) -> String {
    text.chars()
        .map(|c| {
            if c.is_control() {
                c.escape_unicode().to_string()
            } else {
                c.to_string()
            }
        })
        .collect()
}

/// `path` as messages show it: its control characters (a newline, a terminal escape) escaped,
/// so that a message is one line and cannot drive the terminal.
pub fn shown(path: &Path) -> String {
    printable(&path.display().to_string())
}

/// A path displayed by [`shown`], for format strings.
pub struct Shown<'a>(pub &'a Path);

impl fmt::Display for Shown<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&shown(self.0))
    }
}

/// What a file that is not regular is, for messages.
pub fn kind_of(file_type: std::fs::FileType) -> &'static str {
    if file_type.is_dir() {
        "a directory"
    } else if file_type.is_fifo() {
        "a FIFO"
    } else if file_type.is_char_device() {
        "a character device"
    } else if file_type.is_block_device() {
        "a block device"
    } else if file_type.is_socket() {
        "a socket"
    } else {
        "not a regular file"
    }
}

/// An open regular file within its limit, read through a guard that fails should it grow
/// past the limit while read.
#[derive(Debug)]
pub struct Opened {
    file: File,
    path: PathBuf,
    limit: Limit,
    size: u64,
    read: u64,
}

impl Opened {
    /// The file's size when opened.
    pub fn size(&self) -> u64 {
        self.size
    }

    /// The file's path.
    pub fn path(&self) -> &Path {
        &self.path
    }
}

impl Read for Opened {
    fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        let n = self.file.read(buf)?;
        self.read += n as u64;
        if self.read > self.limit.max_bytes {
            return Err(io::Error::other(format!(
                "{} grew past its limit of {} bytes while read",
                shown(&self.path),
                self.limit.max_bytes
            )));
        }
        Ok(n)
    }
}

/// Opens `path` for reading as a file of kind `limit`: a regular file (symbolic links
/// followed) of at most `limit.max_bytes`. Nothing is read.
pub fn open(path: &Path, limit: Limit) -> Result<Opened, InputError> {
    let io = |source| InputError::Io {
        what: limit.what,
        path: path.to_path_buf(),
        source,
    };
    let file = OpenOptions::new()
        .read(true)
        .custom_flags(rustix::fs::OFlags::NONBLOCK.bits() as i32)
        .open(path)
        .map_err(io)?;
    let meta = file.metadata().map_err(io)?;
    if !meta.is_file() {
        return Err(InputError::NotRegular {
            what: limit.what,
            path: path.to_path_buf(),
            found: kind_of(meta.file_type()),
        });
    }
    if meta.len() > limit.max_bytes {
        return Err(InputError::TooLarge {
            what: limit.what,
            path: path.to_path_buf(),
            size: meta.len(),
            max: limit.max_bytes,
        });
    }
    Ok(Opened {
        file,
        path: path.to_path_buf(),
        limit,
        size: meta.len(),
        read: 0,
    })
}

/// The whole file `path` of kind `limit` ([`open`]).
pub fn read_bytes(path: &Path, limit: Limit) -> Result<Vec<u8>, InputError> {
    let mut opened = open(path, limit)?;
    let mut bytes = Vec::with_capacity(opened.size as usize);
    opened
        .read_to_end(&mut bytes)
        .map_err(|source| grew_or_io(&opened, source))?;
    Ok(bytes)
}

/// The error of a failed read of `opened`: [`InputError::TooLarge`] when it grew past its
/// limit, [`InputError::Io`] otherwise.
fn grew_or_io(opened: &Opened, source: io::Error) -> InputError {
    if opened.read > opened.limit.max_bytes {
        InputError::TooLarge {
            what: opened.limit.what,
            path: opened.path.clone(),
            size: opened.read,
            max: opened.limit.max_bytes,
        }
    } else {
        InputError::Io {
            what: opened.limit.what,
            path: opened.path.clone(),
            source,
        }
    }
}

/// The UTF-8 text of `path` of kind `limit`, a leading byte order mark removed.
pub fn read_text(path: &Path, limit: Limit) -> Result<String, InputError> {
    let bytes = read_bytes(path, limit)?;
    let mut text = String::from_utf8(bytes).map_err(|e| InputError::NotUtf8 {
        what: limit.what,
        path: path.to_path_buf(),
        detail: format!("invalid byte at offset {}", e.utf8_error().valid_up_to()),
    })?;
    if text.starts_with('\u{feff}') {
        text.drain(..'\u{feff}'.len_utf8());
    }
    Ok(text)
}

/// The JSON file `path` of kind `limit` read into a `T`, streamed (the text is never held
/// whole); a leading byte order mark is skipped.
pub fn read_json<T: DeserializeOwned>(path: &Path, limit: Limit) -> Result<T, JsonError> {
    read_json_seed(path, limit, PhantomData::<T>)
}

/// [`read_json`] through the seed `seed`, for readers that put what they read straight into
/// their own structures (e.g. a run file's numbers into flat arrays).
pub fn read_json_seed<T, S>(path: &Path, limit: Limit, seed: S) -> Result<T, JsonError>
where
    S: for<'de> DeserializeSeed<'de, Value = T>,
{
    let opened = open(path, limit)?;
    let mut reader = BufReader::with_capacity(BUFFER_BYTES, opened);
    skip_bom(&mut reader).map_err(|source| grew_or_io(reader.get_ref(), source))?;
    let mut de = serde_json::Deserializer::from_reader(&mut reader);
    let parsed = seed
        .deserialize(&mut de)
        .and_then(|value| de.end().map(|()| value));
    parsed.map_err(|source| {
        let opened = reader.get_ref();
        if source.is_io() || opened.read > opened.limit.max_bytes {
            let io = source.into();
            JsonError::Input(grew_or_io(opened, io))
        } else {
            JsonError::Decode {
                what: limit.what,
                path: path.to_path_buf(),
                source,
            }
        }
    })
}

/// Consumes a UTF-8 byte order mark at the start of `reader`, if there is one.
fn skip_bom(reader: &mut impl BufRead) -> io::Result<()> {
    const BOM: &[u8] = "\u{feff}".as_bytes();
    let mut start = Vec::with_capacity(BOM.len());
    while start.len() < BOM.len() {
        let buf = reader.fill_buf()?;
        if buf.is_empty() {
            break;
        }
        let take = (BOM.len() - start.len()).min(buf.len());
        start.extend_from_slice(&buf[..take]);
        if !BOM.starts_with(&start) {
            return Ok(());
        }
        reader.consume(take);
    }
    Ok(())
}

/// The lines of a text file, each at most `max_line` bytes (without its end), read one at a
/// time: `(line number from 1, text)` with the `\n` or `\r\n` end removed and, on the first
/// line, a byte order mark.
#[derive(Debug)]
pub struct Lines {
    reader: BufReader<Opened>,
    max_line: usize,
    number: usize,
    done: bool,
}

impl Lines {
    /// The lines of `path` of kind `limit`, each of at most `max_line` bytes.
    pub fn open(path: &Path, limit: Limit, max_line: usize) -> Result<Self, InputError> {
        Ok(Self {
            reader: BufReader::with_capacity(BUFFER_BYTES, open(path, limit)?),
            max_line,
            number: 0,
            done: false,
        })
    }

    /// The next line's bytes, or `None` at the end of the file.
    fn next_bytes(&mut self) -> Result<Option<Vec<u8>>, InputError> {
        let mut line = Vec::new();
        loop {
            let buf = match self.reader.fill_buf() {
                Ok(buf) => buf,
                Err(e) => return Err(grew_or_io(self.reader.get_ref(), e)),
            };
            if buf.is_empty() {
                return Ok((!line.is_empty()).then_some(line));
            }
            let (take, end) = match buf.iter().position(|&b| b == b'\n') {
                Some(k) => (k, true),
                None => (buf.len(), false),
            };
            if line.len() + take > self.max_line + 1 {
                let opened = self.reader.get_ref();
                return Err(InputError::LineTooLong {
                    what: opened.limit.what,
                    path: opened.path.clone(),
                    line: self.number,
                    max: self.max_line,
                });
            }
            line.extend_from_slice(&buf[..take]);
            self.reader.consume(take + usize::from(end));
            if end {
                return Ok(Some(line));
            }
        }
    }
}

impl Iterator for Lines {
    type Item = Result<(usize, String), InputError>;

    fn next(&mut self) -> Option<Self::Item> {
        if self.done {
            return None;
        }
        self.number += 1;
        let line = match self.next_bytes() {
            Ok(Some(line)) => line,
            Ok(None) => {
                self.done = true;
                return None;
            }
            Err(e) => {
                self.done = true;
                return Some(Err(e));
            }
        };
        let mut text = match String::from_utf8(line) {
            Ok(text) => text,
            Err(e) => {
                self.done = true;
                let opened = self.reader.get_ref();
                return Some(Err(InputError::NotUtf8 {
                    what: opened.limit.what,
                    path: opened.path.clone(),
                    detail: format!(
                        "line {}, byte {}",
                        self.number,
                        e.utf8_error().valid_up_to() + 1
                    ),
                }));
            }
        };
        if text.ends_with('\r') {
            text.pop();
        }
        if self.number == 1 && text.starts_with('\u{feff}') {
            text.drain(..'\u{feff}'.len_utf8());
        }
        if text.len() > self.max_line {
            self.done = true;
            let opened = self.reader.get_ref();
            return Some(Err(InputError::LineTooLong {
                what: opened.limit.what,
                path: opened.path.clone(),
                line: self.number,
                max: self.max_line,
            }));
        }
        Some(Ok((self.number, text)))
    }
}
