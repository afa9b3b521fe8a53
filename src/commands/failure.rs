//! How a command fails: a message and its exit code, from every error of the layers below.

use crate::harness::files::command_error::CommandError;
use crate::harness::files::error::{Error, ParameterError};
use crate::harness::files::output_dir::OutputDirError;
use crate::harness::study::scene::SceneError;

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

impl From<Error> for Failure {
    fn from(e: Error) -> Self {
        match e {
            Error::Parameter(p) => Self::usage(p),
            Error::Solve(s) if s.is_usage() => Self::usage(s),
            Error::Solve(s) => Self::runtime(s),
            Error::Scene(e) => Self::usage(e),
            Error::Distributed(e) => Self::usage(e),
            e @ (Error::Io { .. }
            | Error::Encode { .. }
            | Error::Decode { .. }
            | Error::Figure(_)
            | Error::Vtk { .. }) => Self::runtime(e),
            Error::DemoRun(e) => Self::usage(e),
            e @ (Error::Input(_)
            | Error::NotRegularOutput { .. }
            | Error::Budget(_)
            | Error::OutOfRange { .. }) => Self::usage(e),
            Error::Shard(e) if e.is_usage() => Self::usage(e),
            Error::Shard(e) => Self::runtime(e),
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
