//! How a command fails below the command line ([`CommandError`]): an error of the harness, an
//! output directory that cannot be written, options that do not go together, or a step that
//! could not be done. The command line gives each its exit code.

use thiserror::Error;

use super::error::{Error, ParameterError, SceneError};
use super::output_dir::OutputDirError;

/// How a command fails below the command line; the command gives each its exit code.
#[derive(Debug, Error)]
pub enum CommandError {
    /// An error of the harness (its own exit code: usage or failure).
    #[error(transparent)]
    Harness(#[from] Error),
    /// An output directory that cannot be staged or committed.
    #[error(transparent)]
    OutputDir(#[from] OutputDirError),
    /// Options that do not go together (a usage error).
    #[error("{0}")]
    Refused(String),
    /// A step that could not be done (a failure).
    #[error("{0}")]
    Failed(String),
}

impl From<SceneError> for CommandError {
    fn from(e: SceneError) -> Self {
        Self::Harness(e.into())
    }
}

impl From<ParameterError> for CommandError {
    fn from(e: ParameterError) -> Self {
        Self::Harness(e.into())
    }
}
