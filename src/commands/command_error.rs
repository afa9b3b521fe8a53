//! How a command fails below the command line ([`CommandError`]): an error of the harness, an
//! output directory that cannot be written, options that do not go together, or a step that
//! could not be done. The command line gives each its exit code.

use thiserror::Error;

use crate::harness::files::error::{self as files, ParameterError, SolveError};
use crate::harness::files::input::{InputError, JsonError};
use crate::harness::files::output_dir::OutputDirError;
use crate::harness::getfem::DemoRunError;
use crate::harness::render::figures::FigureError;
use crate::harness::study::budget::BudgetError;
use crate::harness::study::error as study;
use crate::harness::study::scene::SceneError;
use crate::harness::study::shard::ShardError;
use crate::studies::error::Error;

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

/// `From` each error a report section's error is made from, through it, so that `?` lifts it.
macro_rules! through_section {
    ($($source:ty),* $(,)?) => {$(
        impl From<$source> for CommandError {
            fn from(e: $source) -> Self {
                Self::Harness(e.into())
            }
        }
    )*};
}

through_section!(
    study::Error,
    files::Error,
    SceneError,
    ShardError,
    BudgetError,
    FigureError,
    DemoRunError,
    ParameterError,
    SolveError,
    InputError,
    JsonError,
);
