//! The solver of an implicit scheme's step matrix (`M/(bΔt²) + S`, or `M/Δt² + βS` for
//! Paoli–Schatzman), direct or iterative, and the rule that chooses between them.
//!
//! * `direct`: one sparse Cholesky factorisation per run ([`SpdSolver`]), then two triangular
//!   solves per step: exact to round-off, but its fill grows like `n^{4/3}` in 3D.
//! * `cg`: Jacobi-preconditioned conjugate gradients ([`Pcg`]) on the assembled matrix, warm
//!   started from the scheme's extrapolation of the previous steps; memory `O(n)`.
//! * `auto` (the default): `cg` from [`AUTO_CG_FROM_DOFS`] unknowns on, `direct` below.
//!
//! A matrix of bandwidth one (every 1D bar) always takes the direct (tridiagonal) solver.

use std::fmt;
use std::str::FromStr;

use rayon::prelude::*;

use super::pcg::{Pcg, PcgWork, DEFAULT_TOLERANCE};
use super::SpdSolver;
use crate::engine::error::{ParameterError, SolveError};
use crate::engine::fem::SymmetricMatrix;

/// The size from which `auto` chooses `cg`: at and above it CG was faster than the sparse
/// Cholesky on the 3D boxes of the note (measured on 2 cores, README "2D and 3D bars"), below
/// it the factorisation is cheap and the direct solver keeps the regression gate's numbers.
pub const AUTO_CG_FROM_DOFS: usize = 10_000;

/// Which step solver a run uses (see the module documentation).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum LinearSolver {
    /// Sparse Cholesky.
    Direct,
    /// Jacobi-preconditioned conjugate gradients.
    Cg,
    /// `cg` from [`AUTO_CG_FROM_DOFS`] unknowns on, `direct` below.
    #[default]
    Auto,
}

/// What a linear solver may be, for error messages.
pub const LINEAR_SOLVER_NAMES: &str = "one of: direct, cg, auto";

impl LinearSolver {
    /// The name on the command line.
    pub fn name(self) -> &'static str {
        match self {
            LinearSolver::Direct => "direct",
            LinearSolver::Cg => "cg",
            LinearSolver::Auto => "auto",
        }
    }

    /// Whether a matrix of dimension `n` and `bandwidth` is solved by CG under this choice.
    fn uses_cg(self, n: usize, bandwidth: usize) -> bool {
        bandwidth > 1
            && match self {
                LinearSolver::Direct => false,
                LinearSolver::Cg => true,
                LinearSolver::Auto => n >= AUTO_CG_FROM_DOFS,
            }
    }
}

impl fmt::Display for LinearSolver {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for LinearSolver {
    type Err = ParameterError;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        [LinearSolver::Direct, LinearSolver::Cg, LinearSolver::Auto]
            .into_iter()
            .find(|v| v.name() == s)
            .ok_or_else(|| ParameterError::new("linear-solver", s, LINEAR_SOLVER_NAMES))
    }
}

/// A step matrix ready to be solved with, by the solver its [`LinearSolver`] chose.
#[derive(Debug)]
pub enum StepSolver {
    /// Factorised.
    Direct(SpdSolver),
    /// Prepared for CG, with the work vectors of the per-step solve.
    Cg {
        /// The matrix and its preconditioner.
        pcg: Pcg,
        /// The solution buffer.
        x: Vec<f64>,
        /// `r`, `z`, `p`, `K p`.
        work: PcgWork,
    },
}

impl StepSolver {
    /// Prepares `a` (factorised, or kept for CG) as `choice` decides; `name` says which matrix
    /// this is in error messages.
    pub fn new(
        a: SymmetricMatrix,
        choice: LinearSolver,
        name: &'static str,
    ) -> Result<Self, SolveError> {
        let n = a.dim();
        if choice.uses_cg(n, a.bandwidth()) {
            Ok(StepSolver::Cg {
                pcg: Pcg::new(&a, DEFAULT_TOLERANCE, name)?,
                x: vec![0.0; n],
                work: PcgWork::new(n),
            })
        } else {
            SpdSolver::factor(&a, name).map(StepSolver::Direct)
        }
    }

    /// Solves `K x = b`: `rhs` holds `b` on entry and `x` on exit. `guess` is CG's initial
    /// guess (the direct solver ignores it).
    pub fn solve(&mut self, rhs: &mut [f64], guess: &[f64]) -> Result<(), SolveError> {
        match self {
            StepSolver::Direct(solver) => solver.solve_in_place(rhs),
            StepSolver::Cg { pcg, x, work } => {
                x.copy_from_slice(guess);
                pcg.solve(rhs, x, work)?;
                rhs.copy_from_slice(x);
            }
        }
        Ok(())
    }

    /// Solves `K x_j = b_j` for every column (each holding `b_j` on entry and `x_j` on exit),
    /// in order with the direct solver, in parallel from a zero guess with CG.
    pub fn solve_columns(&self, columns: &mut [Vec<f64>]) -> Result<(), SolveError> {
        match self {
            StepSolver::Direct(solver) => {
                columns.iter_mut().for_each(|c| solver.solve_in_place(c));
                Ok(())
            }
            StepSolver::Cg { pcg, .. } => columns.par_iter_mut().try_for_each_init(
                || (PcgWork::new(pcg.dim()), vec![0.0; pcg.dim()]),
                |(work, x), column| {
                    x.fill(0.0);
                    pcg.solve(column, x, work)?;
                    column.copy_from_slice(x);
                    Ok(())
                },
            ),
        }
    }
}
