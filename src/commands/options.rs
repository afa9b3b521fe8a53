//! The options and parsers that several subcommands share: schemes, masses, norms, contact
//! treatments, the schemes' conventions and the step solver.

use std::path::PathBuf;
use std::str::FromStr;

use serde::{Deserialize, Serialize};

use crate::harness::files::error::ParameterError;
use crate::harness::problem::{Conventions, LinearSolver, Start};
use crate::harness::reference::fine_mesh::cache::user_cache;
use crate::harness::reference::scene_study::ConventionChoice;

/// The reports directory of `make report`, relative to the repository root: the default
/// `--out` of the commands that write reports.
pub(crate) const REPORTS: &str = "reports";

/// Where a command looks up and keeps the fine-mesh references: `--cache DIR` when given, else
/// the user's cache ([`user_cache`]: `$SIGNORINI_CACHE`, its `CACHE_VARIABLE`, else the
/// platform's cache directory),
/// which every command shares, so that a reference is computed once per user and scene; a
/// machine where neither is known is refused naming `--cache`.
pub(crate) fn cache_dir(given: Option<PathBuf>) -> Result<PathBuf, ParameterError> {
    given.or_else(user_cache).ok_or_else(|| {
        ParameterError::new(
            "--cache",
            "none",
            "a directory for the fine-mesh references: --cache DIR, or SIGNORINI_CACHE, or a \
             home directory with a cache directory",
        )
    })
}

/// A value of an option read with its type's parser (a scheme, a mass, a norm, a contact
/// treatment, …): a refused value names what is allowed.
pub(crate) fn parsed<T: FromStr<Err = ParameterError>>(s: &str) -> Result<T, String> {
    s.parse().map_err(|e: ParameterError| e.to_string())
}

/// The schemes' implementation choices on the command line, over the scene's
/// ([`Conventions`]).
#[derive(Debug, Clone, Copy, clap::Args, Serialize, Deserialize)]
pub struct ConventionArgs {
    /// The schemes' implementation choices: harness or getfem-demo (GetFEM demo's start,
    /// Nitsche acceleration and Paoli–Schatzman rows). Default: the scene's, else harness.
    #[arg(long, value_parser = parsed::<Conventions>)]
    pub conventions: Option<Conventions>,
    /// The start with a massless contact node: static (its data moved into static
    /// equilibrium) or implicit-multiplier (data kept, the paper's and GetFEM's). Default: the
    /// conventions', else the scene's, else static.
    #[arg(long, value_parser = parsed::<Start>)]
    pub start: Option<Start>,
}

impl ConventionArgs {
    /// The choice these options make over a scene's conventions.
    pub(crate) fn choice(self) -> ConventionChoice {
        ConventionChoice {
            conventions: self.conventions,
            start: self.start,
        }
    }
}

/// The step solver of the implicit schemes on a box scene ([`LinearSolver`]); 1D bars always
/// use the tridiagonal solver.
#[derive(Debug, Clone, Copy, clap::Args, Serialize, Deserialize)]
pub struct LinearSolverArgs {
    /// Step solver on 2D/3D boxes: direct (sparse Cholesky), cg (matrix-free conjugate
    /// gradients with the product preconditioner) or auto (cg on 2D/3D boxes from 10 000
    /// unknowns on, direct below). 1D bars always use the tridiagonal solver.
    #[arg(long, value_parser = parsed::<LinearSolver>, default_value = "auto")]
    pub linear_solver: LinearSolver,
}
