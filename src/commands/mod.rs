//! What each subcommand of the `signorini` binary does; `main.rs` parses the arguments and
//! dispatches here. Every command prints its summary on stdout (a closed stdout is ignored:
//! `signorini list | head` must not panic) and returns a [`Failure`] with its exit code.
//!
//! Exit codes: 0 success; 2 usage errors (bad arguments, a scene file that is missing,
//! malformed or out of range); 1 failures (a run that fails, an energy balance that
//! `--check-balance` finds violated, an output that cannot be written).

/// `println!` that ignores a closed stdout.
macro_rules! out {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        let _ = writeln!(std::io::stdout(), $($arg)*);
    }};
}

mod getfem;
mod limits;
mod list;
mod merge;
mod reports;
mod run;
mod sharding;
mod study;
mod verify;

pub use getfem::{getfem, GetfemArgs};
pub use limits::LimitArgs;
pub use list::{list, ListArgs};
pub use merge::{merge, MergeArgs};
pub use reports::{
    experiment, figures, golden, report, stability, ExperimentArgs, FiguresArgs, GoldenArgs,
    ReportArgs, StabilityArgs,
};
pub use run::{run_scene, RunArgs};
pub use sharding::ShardArgs;
pub use study::{reference, sensitivity, study_scene, ReferenceArgs, SensitivityArgs, StudyArgs};
pub use verify::{verify_runs, VerifyArgs};

use crate::engine::schemes::conventions::{Conventions, Start};
use std::io::IsTerminal;
use std::path::Path;

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

use crate::engine::contact::ContactTreatment;
use crate::engine::error::ParameterError;
use crate::engine::fem::MassVariant;
use crate::engine::linalg::LinearSolver;
use crate::engine::schemes::Scheme;
use crate::harness::artifacts::write_atomic;
use crate::harness::error::Error;
use crate::harness::norms::Norm;
use crate::harness::output_dir::OutputDirError;
use crate::harness::scene::SceneError;

pub(crate) fn parse_scheme(s: &str) -> Result<Scheme, String> {
    s.parse().map_err(|e: ParameterError| e.to_string())
}

pub(crate) fn parse_contact(s: &str) -> Result<ContactTreatment, String> {
    s.parse().map_err(|e: ParameterError| e.to_string())
}

/// The schemes' implementation choices on the command line, over the scene's
/// ([`Conventions`]).
#[derive(Debug, Clone, Copy, clap::Args)]
pub struct ConventionArgs {
    /// The schemes' implementation choices: harness or getfem-demo (GetFEM demo's start,
    /// Nitsche acceleration and Paoli–Schatzman rows). Default: the scene's, else harness.
    #[arg(long, value_parser = parse_conventions)]
    pub conventions: Option<Conventions>,
    /// The start with a massless contact node: static (its data moved into static
    /// equilibrium) or implicit-multiplier (data kept, the paper's and GetFEM's). Default: the
    /// conventions', else the scene's, else static.
    #[arg(long, value_parser = parse_start)]
    pub start: Option<Start>,
}

impl ConventionArgs {
    /// `scene`'s conventions with the options given here applied over them.
    pub fn over(self, scene: Conventions) -> Conventions {
        let mut c = self.conventions.unwrap_or(scene);
        if let Some(start) = self.start {
            c.start = start;
        }
        c
    }
}

/// The step solver of the implicit schemes on a box scene ([`LinearSolver`]); 1D bars always
/// use the tridiagonal solver.
#[derive(Debug, Clone, Copy, clap::Args)]
pub struct LinearSolverArgs {
    /// Step solver on 2D/3D boxes: direct (sparse Cholesky), cg (matrix-free conjugate
    /// gradients with the product preconditioner) or auto (cg on 2D/3D boxes from 10 000
    /// unknowns on, direct below). 1D bars always use the tridiagonal solver.
    #[arg(long, value_parser = parse_linear_solver, default_value = "auto")]
    pub linear_solver: LinearSolver,
}

fn parse_linear_solver(s: &str) -> Result<LinearSolver, String> {
    s.parse().map_err(|e: ParameterError| e.to_string())
}

fn parse_conventions(s: &str) -> Result<Conventions, String> {
    s.parse().map_err(|e: ParameterError| e.to_string())
}

fn parse_start(s: &str) -> Result<Start, String> {
    s.parse().map_err(|e: ParameterError| e.to_string())
}

/// Prints on stderr why each of `schemes` whose parameters make it unstable is so
/// ([`Scheme::warning`]); the run goes on.
pub(crate) fn warn_schemes(schemes: &[Scheme]) {
    for w in schemes.iter().filter_map(|s| s.warning()) {
        eprintln!("warning: {w}");
    }
}

pub(crate) fn parse_mass(s: &str) -> Result<MassVariant, String> {
    s.parse().map_err(|e: ParameterError| e.to_string())
}

pub(crate) fn parse_norm(s: &str) -> Result<Norm, String> {
    s.parse().map_err(|e: ParameterError| e.to_string())
}

/// A failure with its exit code.
pub struct Failure {
    /// The exit code: 2 for a usage error, 1 for a failure.
    pub code: u8,
    /// What went wrong, for the user.
    pub message: String,
}

impl Failure {
    fn usage(e: impl std::fmt::Display) -> Self {
        Self {
            code: 2,
            message: e.to_string(),
        }
    }

    fn runtime(e: impl std::fmt::Display) -> Self {
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

impl From<OutputDirError> for Failure {
    fn from(e: OutputDirError) -> Self {
        if e.is_usage() {
            Self::usage(e)
        } else {
            Self::runtime(e)
        }
    }
}

fn write_output(path: &Path, contents: &[u8]) -> Result<(), Failure> {
    write_atomic(path, contents).map_err(Failure::from)
}

fn progress_bar(len: usize) -> ProgressBar {
    let visible = std::io::stderr().is_terminal() && std::env::var_os("CI").is_none();
    let bar = ProgressBar::with_draw_target(
        Some(len as u64),
        if visible {
            ProgressDrawTarget::stderr()
        } else {
            ProgressDrawTarget::hidden()
        },
    );
    bar.set_style(
        ProgressStyle::with_template("{bar:40} {pos}/{len} runs, {elapsed} elapsed, ETA {eta}")
            .expect("valid template"),
    );
    bar
}
