//! How a command fails: a message and its exit code, from every error of the layers below.

use crate::commands::command_error::CommandError;
use crate::harness::files::error::{self as files, ParameterError};
use crate::harness::files::output_dir::OutputDirError;
use crate::harness::study::error as study;
use crate::harness::study::scene::SceneError;
use crate::studies::error as section;

/// A failure with its exit code.
pub struct Failure {
    /// The exit code: 2 for a usage error, 1 for a failure.
    pub code: u8,
    /// What went wrong, for the user.
    pub message: String,
}

impl Failure {
    pub(crate) fn usage(e: impl std::fmt::Display) -> Self {
        Self {
            code: 2,
            message: e.to_string(),
        }
    }

    pub(crate) fn runtime(e: impl std::fmt::Display) -> Self {
        Self {
            code: 1,
            message: e.to_string(),
        }
    }
}

impl From<SceneError> for Failure {
    fn from(e: SceneError) -> Self {
        Self::usage(e)
    }
}

impl From<files::Error> for Failure {
    fn from(e: files::Error) -> Self {
        use files::Error;
        match e {
            Error::Parameter(p) => Self::usage(p),
            Error::Solve(s) if s.is_usage() => Self::usage(s),
            Error::Solve(s) => Self::runtime(s),
            Error::Distributed(e) => Self::usage(e),
            e @ (Error::Io { .. }
            | Error::Encode { .. }
            | Error::Decode { .. }
            | Error::Vtk { .. }) => Self::runtime(e),
            e @ (Error::Input(_) | Error::NotRegularOutput { .. } | Error::OutOfRange { .. }) => {
                Self::usage(e)
            }
        }
    }
}

impl From<study::Error> for Failure {
    fn from(e: study::Error) -> Self {
        use study::Error;
        match e {
            Error::Run(e) => e.into(),
            Error::Scene(e) => Self::usage(e),
            Error::Budget(e) => Self::usage(e),
            Error::Shard(e) if e.is_usage() => Self::usage(e),
            Error::Shard(e) => Self::runtime(e),
        }
    }
}

impl From<section::Error> for Failure {
    fn from(e: section::Error) -> Self {
        use section::Error;
        match e {
            Error::Study(e) => e.into(),
            Error::Figure(e) => Self::runtime(e),
            Error::DemoRun(e) => Self::usage(e),
        }
    }
}

impl From<ParameterError> for Failure {
    fn from(e: ParameterError) -> Self {
        Self::usage(e)
    }
}

impl From<OutputDirError> for Failure {
    fn from(e: OutputDirError) -> Self {
        if e.is_usage() {
            Self::usage(e)
        } else {
            Self::runtime(e)
        }
    }
}

impl From<CommandError> for Failure {
    fn from(e: CommandError) -> Self {
        match e {
            CommandError::Harness(e) => e.into(),
            CommandError::OutputDir(e) => e.into(),
            CommandError::Refused(why) => Self::usage(why),
            CommandError::Failed(why) => Self::runtime(why),
        }
    }
}
