//! The errors of the harness's lowest floor, which every part above it can return: the engine's
//! (its [`ParameterError`], with the check [`require_positive`] that makes one, and its
//! [`SolveError`]), a box that cannot be shared over ranks, and the files read and written. Each
//! part above has its own error for what only it can refuse (a scene, a shard, a budget:
//! [`crate::harness::study::error::Error`]; a figure; GetFEM's demo runs), and knows this one.

use std::path::{Path, PathBuf};

use thiserror::Error;

use crate::engine::error as engine;
pub use crate::engine::error::{require_positive, ParameterError, SolveError};
pub use crate::harness::files::input::printable;
use crate::harness::files::input::{shown, InputError, JsonError, Shown};

/// An error of a run or of a file read or written.
#[derive(Debug, Error)]
pub enum Error {
    /// A parameter out of range.
    #[error(transparent)]
    Parameter(#[from] ParameterError),
    /// Time stepping failed.
    #[error(transparent)]
    Solve(#[from] SolveError),
    /// A box cannot be run over the ranks asked for.
    #[error(transparent)]
    Distributed(#[from] crate::engine::distributed::DecompositionError),
    /// A file could not be read or written.
    #[error("cannot {action} {}: {source}", Shown(path))]
    Io {
        /// `read` or `write`.
        action: &'static str,
        /// The file.
        path: PathBuf,
        /// What the system reported.
        #[source]
        source: std::io::Error,
    },
    /// Data could not be encoded as JSON.
    #[error("cannot encode {what} as JSON: {source}")]
    Encode {
        /// What was being encoded (its file).
        what: String,
        /// What serde reported.
        #[source]
        source: serde_json::Error,
    },
    /// A JSON file is not what its reader expects.
    #[error("{} is not a valid file of its kind: {source}", Shown(path))]
    Decode {
        /// The file.
        path: PathBuf,
        /// What serde reported.
        #[source]
        source: serde_json::Error,
    },
    /// A VTK file could not be written.
    #[error("cannot write {}: {source}", Shown(path))]
    Vtk {
        /// The file.
        path: PathBuf,
        /// What vtkio reported.
        #[source]
        source: vtkio::Error,
    },
    /// A value in a file out of its range (a negative tolerance or error, a non-finite rate).
    #[error("{}: {field} = {value}; allowed: {allowed}", Shown(path))]
    OutOfRange {
        /// The file.
        path: PathBuf,
        /// The field, dotted (`tolerances.rate_abs`, `cases[2].norms.u_L2_H.errors[1]`).
        field: String,
        /// Its value.
        value: f64,
        /// What is allowed.
        allowed: &'static str,
    },
    /// An input file is missing, not a regular file or over its size limit.
    #[error(transparent)]
    Input(#[from] InputError),
    /// A file to write exists and is not a regular file (a FIFO, a device, a directory).
    #[error(
        "{} is {found}; allowed: a regular file or a new name (nothing but a regular file is \
         replaced)",
        Shown(path)
    )]
    NotRegularOutput {
        /// The file.
        path: PathBuf,
        /// What it is.
        found: &'static str,
    },
}

impl From<JsonError> for Error {
    fn from(e: JsonError) -> Self {
        match e {
            JsonError::Input(e) => Error::Input(e),
            JsonError::Decode { path, source, .. } => Error::Decode { path, source },
        }
    }
}

impl Error {
    /// The error of encoding the content of `path`.
    pub fn encode(path: &Path) -> impl FnOnce(serde_json::Error) -> Self + '_ {
        move |source| Error::Encode {
            what: shown(path),
            source,
        }
    }

    /// The error of reading `path`.
    pub fn read(path: &Path) -> impl FnOnce(std::io::Error) -> Self + '_ {
        move |source| Error::Io {
            action: "read",
            path: path.to_path_buf(),
            source,
        }
    }

    /// The error of writing `path`.
    pub fn write(path: &Path) -> impl FnOnce(std::io::Error) -> Self + '_ {
        move |source| Error::Io {
            action: "write",
            path: path.to_path_buf(),
            source,
        }
    }
}

impl From<engine::Error> for Error {
    fn from(e: engine::Error) -> Self {
        match e {
            engine::Error::Parameter(p) => Error::Parameter(p),
            engine::Error::Solve(s) => Error::Solve(s),
        }
    }
}
