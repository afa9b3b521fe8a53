//! The error of a report section ([`Error`]): a study's (its runs, files, scene, shards and
//! budget: [`study::Error`]), a figure that cannot be drawn, or a run of GetFEM's demo that cannot
//! be read.

use thiserror::Error as ThisError;

use crate::harness::files::error::{self as files, ParameterError, SolveError};
use crate::harness::files::input::{InputError, JsonError};
use crate::harness::getfem::DemoRunError;
use crate::harness::render::figures::FigureError;
use crate::harness::study::budget::BudgetError;
use crate::harness::study::error as study;
use crate::harness::study::scene::SceneError;
use crate::harness::study::shard::ShardError;

/// Why a report section, or a step of one, failed.
#[derive(Debug, ThisError)]
pub enum Error {
    /// A study: a run, a file, a scene, shards or a budget.
    #[error(transparent)]
    Study(#[from] study::Error),
    /// A figure that cannot be drawn.
    #[error(transparent)]
    Figure(#[from] FigureError),
    /// A run of GetFEM's demo that cannot be read.
    #[error(transparent)]
    DemoRun(#[from] DemoRunError),
}

impl Error {
    /// The failure of time stepping this error is, if it is one.
    pub fn as_solve(&self) -> Option<&SolveError> {
        match self {
            Error::Study(study::Error::Run(files::Error::Solve(e))) => Some(e),
            _ => None,
        }
    }
}

/// `From` each error a study's error is made from, through it, so that `?` lifts it.
macro_rules! through_study {
    ($($source:ty),* $(,)?) => {$(
        impl From<$source> for Error {
            fn from(e: $source) -> Self {
                Self::Study(e.into())
            }
        }
    )*};
}

through_study!(
    files::Error,
    SceneError,
    ShardError,
    BudgetError,
    ParameterError,
    SolveError,
    InputError,
    JsonError,
);
