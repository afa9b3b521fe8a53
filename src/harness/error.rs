//! Errors of the harness: the engine's, plus the files it reads and writes.

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
    /// An output file could not be written.
    #[error("{0}")]
    Io(String),
}

impl From<engine::Error> for Error {
    fn from(e: engine::Error) -> Self {
        match e {
            engine::Error::Parameter(p) => Error::Parameter(p),
            engine::Error::Solve(s) => Error::Solve(s),
        }
    }
}
