//! Errors of the harness: the engine's, plus the files it reads and writes.

use std::path::{Path, PathBuf};

use thiserror::Error;

use crate::engine::error::{self as engine, ParameterError, SolveError};

/// Any error of a harness run or study.
#[derive(Debug, Error)]
pub enum Error {
    /// A parameter out of range.
    #[error(transparent)]
    Parameter(#[from] ParameterError),
    /// Time stepping failed.
    #[error(transparent)]
    Solve(#[from] SolveError),
    /// A file could not be read or written.
    #[error("cannot {action} {}: {source}", path.display())]
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
        /// What was being encoded.
        what: &'static str,
        /// What serde reported.
        #[source]
        source: serde_json::Error,
    },
    /// A VTK file could not be written.
    #[error("cannot write {}: {source}", path.display())]
    Vtk {
        /// The file.
        path: PathBuf,
        /// What vtkio reported.
        #[source]
        source: vtkio::Error,
    },
}

impl Error {
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
