//! A scene file that could not be read or is not valid ([`SceneError`]), naming the file and
//! the field and saying what is allowed.

use std::fmt;
use std::path::PathBuf;

use crate::harness::files::input::{printable, InputError, Shown};

/// A scene that could not be read or is not valid.
#[derive(Debug)]
pub enum SceneError {
    /// The file cannot be read, is not a regular file or is too large.
    Input(InputError),
    /// Malformed JSON, an unknown or missing field, or a value of the wrong type.
    Json {
        /// The scene file.
        path: PathBuf,
        /// 1-based line.
        line: usize,
        /// 1-based column.
        column: usize,
        /// serde's message (names the field and, for unknown fields, the allowed ones).
        message: String,
    },
    /// A value out of range or inconsistent with the rest of the scene.
    Invalid {
        /// The scene file.
        path: PathBuf,
        /// The field, dotted (`material.density`).
        field: String,
        /// The offending value.
        value: String,
        /// What is allowed.
        allowed: String,
    },
}

impl fmt::Display for SceneError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SceneError::Input(e) => e.fmt(f),
            SceneError::Json {
                path,
                line,
                column,
                message,
            } => write!(
                f,
                "scene file {} is not a valid scene (line {line}, column {column}): {message}",
                Shown(path)
            ),
            SceneError::Invalid {
                path,
                field,
                value,
                allowed,
            } => write!(
                f,
                "scene file {}: invalid {field} = {}; allowed: {}",
                Shown(path),
                printable(value),
                printable(allowed)
            ),
        }
    }
}

impl SceneError {
    /// Appends `detail` to what an [`SceneError::Invalid`] says is allowed.
    pub(crate) fn with_detail(self, detail: String) -> Self {
        match self {
            SceneError::Invalid {
                path,
                field,
                value,
                allowed,
            } => SceneError::Invalid {
                path,
                field,
                value,
                allowed: if allowed.is_empty() {
                    detail
                } else {
                    format!("{allowed} ({detail})")
                },
            },
            other => other,
        }
    }
}

impl std::error::Error for SceneError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            SceneError::Input(e) => Some(e),
            _ => None,
        }
    }
}
