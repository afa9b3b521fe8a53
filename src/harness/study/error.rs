//! The error of a study ([`Error`]): what its runs and files can fail with (the harness's
//! lowest floor, [`files::Error`]), and what only a study refuses: its scene, its shards
//! and its budget. The parts above the study (the reference, another code's runs) return it.

use std::fmt;

use thiserror::Error as ThisError;

use crate::engine::distributed::DecompositionError;
use crate::engine::error as engine;
use crate::harness::files::error::{self as files, ParameterError, SolveError};
use crate::harness::files::input::{InputError, JsonError};
use crate::harness::study::scene_error::SceneError;
use crate::harness::study::shard::ShardError;

/// Why a study, or a step of one, failed.
#[derive(Debug, ThisError)]
pub enum Error {
    /// A run or a file read or written.
    #[error(transparent)]
    Run(#[from] files::Error),
    /// A scene file that cannot be read or is not valid.
    #[error(transparent)]
    Scene(#[from] SceneError),
    /// A shard that cannot be run, or shards that cannot be merged.
    #[error(transparent)]
    Shard(#[from] ShardError),
    /// An estimated cost over a limit.
    #[error(transparent)]
    Budget(#[from] BudgetError),
}

/// `From` each error the lowest floor's error is made from, through it, so that `?` lifts it.
macro_rules! through_run {
    ($($source:ty),* $(,)?) => {$(
        impl From<$source> for Error {
            fn from(e: $source) -> Self {
                Self::Run(e.into())
            }
        }
    )*};
}

through_run!(
    ParameterError,
    SolveError,
    engine::Error,
    DecompositionError,
    InputError,
    JsonError,
);

/// An estimate over a limit.
#[derive(Debug, Clone, PartialEq)]
pub enum BudgetError {
    /// The estimate of `resource` exceeds its limit.
    OverLimit {
        /// What is estimated (`memory`, `files written`, `work`).
        resource: &'static str,
        /// The estimate, with its unit.
        estimate: String,
        /// The limit, with its unit and where it comes from.
        limit: String,
        /// The option that raises it.
        option: &'static str,
    },
}

impl fmt::Display for BudgetError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            BudgetError::OverLimit {
                resource,
                estimate,
                limit,
                option,
            } => write!(
                f,
                "refused before starting: the estimated {resource} is {estimate}, over the \
                 limit of {limit}; use fewer elements, steps or output times, or raise the \
                 limit with {option}"
            ),
        }
    }
}

impl std::error::Error for BudgetError {}
