//! What can be wrong with another code's run files: each error names the file, the field (and
//! the sample, line or column where relevant) and what is allowed, as the scene errors do.

use std::path::PathBuf;

use thiserror::Error;

use crate::engine::error::compact;
use crate::harness::files::error as files;
use crate::harness::files::input::{InputError, JsonError, Shown};
use crate::harness::study::error::Error;

/// A run file that cannot be read, or whose content is not a valid run of the scene; a series
/// of runs that cannot be fitted; or an error of the harness while verifying.
#[derive(Debug, Error)]
pub enum ExternalError {
    /// The file cannot be read: missing, unreadable, not a regular file, over its size limit
    /// or with a line too long.
    #[error(transparent)]
    Input(#[from] InputError),
    /// Malformed JSON, an unknown or missing field, or a value of the wrong type.
    #[error(
        "run file {} is not a valid run (line {line}, column {column}): {message}",
        Shown(path)
    )]
    Json {
        /// The run file.
        path: PathBuf,
        /// 1-based line.
        line: usize,
        /// 1-based column.
        column: usize,
        /// serde's message (names the field and, for an unknown one, the allowed ones).
        message: String,
    },
    /// A value that is missing, out of range, of the wrong length or inconsistent with the
    /// scene or the rest of the file.
    #[error("run file {}: invalid {field} = {value}{}; allowed: {allowed}", Shown(path), at.as_ref().map(|a| format!(" (at {a})")).unwrap_or_default())]
    Invalid {
        /// The run file.
        path: PathBuf,
        /// The field (`mesh.nodes`, `time`, `u3`, …).
        field: String,
        /// Where in the file: `samples[12]`, `line 17, column 4`; `None` for a whole field.
        at: Option<String>,
        /// The offending value.
        value: String,
        /// What is allowed.
        allowed: String,
    },
    /// The runs of one label do not form a refinement series.
    #[error("series {label:?}: {problem}")]
    Series {
        /// The configuration label the files share.
        label: String,
        /// What is wrong, naming the files.
        problem: String,
    },
    /// The harness failed (the reference, an observer, an output file).
    #[error(transparent)]
    Harness(#[from] Error),
}

impl ExternalError {
    /// The error of reading the JSON run file `path`: unreadable, or malformed at a line and
    /// column.
    pub fn of_json(path: &std::path::Path, error: JsonError) -> Self {
        match error {
            JsonError::Input(e) => ExternalError::Input(e),
            JsonError::Decode { source, .. } => ExternalError::Json {
                path: path.to_path_buf(),
                line: source.line(),
                column: source.column(),
                message: source.to_string(),
            },
        }
    }

    /// The error of the field `field` of `path`, at `at` when given.
    pub fn invalid(
        path: &std::path::Path,
        field: impl Into<String>,
        at: Option<String>,
        value: impl std::fmt::Display,
        allowed: impl Into<String>,
    ) -> Self {
        ExternalError::Invalid {
            path: path.to_path_buf(),
            field: field.into(),
            at,
            value: compact(value.to_string()),
            allowed: allowed.into(),
        }
    }
}

/// The longest parser message an error repeats ([`unquoted`]).
const LONGEST_PARSER_MESSAGE: usize = 160;

/// A parser's message about a file, without what it quotes of the file: every quoted run
/// (`"…"`, escapes inside it skipped) becomes `"…"`, and the message is cut at
/// [`LONGEST_PARSER_MESSAGE`] characters. The file may be one a run file pointed to (a `.pvd`'s
/// `file=`, an XDMF item's HDF5 file), not one the user wrote: its content is never repeated.
pub fn unquoted(message: impl std::fmt::Display) -> String {
    let message = message.to_string();
    let mut out = String::new();
    let mut chars = message.chars();
    while let Some(c) = chars.next() {
        out.push(c);
        if c == '"' {
            while let Some(q) = chars.next() {
                match q {
                    '\\' => {
                        chars.next();
                    }
                    '"' => break,
                    _ => {}
                }
            }
            out.push_str("…\"");
        }
    }
    match out.char_indices().nth(LONGEST_PARSER_MESSAGE) {
        Some((cut, _)) => format!("{}…", &out[..cut]),
        None => out,
    }
}

/// A run's or a file's error lifts through the study's, so that `?` takes it.
impl From<files::Error> for ExternalError {
    fn from(e: files::Error) -> Self {
        Self::Harness(e.into())
    }
}
