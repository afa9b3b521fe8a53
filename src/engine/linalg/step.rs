//! The solver of an implicit scheme's step matrix (`M/(bΔt²) + S`, or `M/Δt² + βS` for
//! Paoli–Schatzman), direct or iterative, and the rule that chooses between them.
//!
//! * `direct`: one sparse Cholesky factorisation per run ([`SpdSolver`]), then two triangular
//!   solves per step: exact to round-off, but its fill grows like `n^{4/3}` in 3D.
//! * `cg`: preconditioned conjugate gradients ([`Pcg`]), warm started from the scheme's
//!   extrapolation of the previous steps; memory `O(n)`. On a box the matrices are matrix-free
//!   ([`crate::engine::fem::stencil`]) and the preconditioner is the product of the separable
//!   part ([`crate::engine::fem::separable`]); Jacobi otherwise.
//! * `auto` (the default): on a box, `cg` from [`AUTO_CG_FROM_DOFS`] unknowns on and `direct`
//!   below; `direct` for every other model.
//!
//! The choice is resolved once, into the [`StepSolverKind`] of the model's solver plan
//! ([`crate::engine::solver_plan`]). A matrix of bandwidth one or less (every 1D bar, a lumped
//! mass) always takes the direct (tridiagonal or diagonal) solver: it is a form, not a choice.

use std::fmt;
use std::str::FromStr;

use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use super::pcg::{Pcg, PcgWork, DEFAULT_TOLERANCE};
use super::SpdSolver;
use crate::engine::error::{ParameterError, SolveError};
use crate::engine::fem::SymmetricMatrix;

/// The size from which `auto` chooses `cg` on a box, in 2D and 3D, between measurements on this
/// 2-core machine (docs/src/bars-2d-3d.md; Crank–Nicolson, `M^mod`, T = 2, wall time): in 2D
/// the sparse Cholesky was faster at 5 440 unknowns (level 160: 0.44 s against 0.70 s) and
/// matrix-free CG at 21 120 (level 320: 3.7 s against 4.9 s; level 640, 83 200 unknowns: 26 s
/// and 41 MB against 58 s and 201 MB); in 3D they were even at 3 000 (level 40: 0.16 s
/// against 0.20 s) and CG far ahead from 19 440 (level 80: 1.7 s against 9.7 s). The regression
/// gate's boxes are smaller and keep the direct solver.
pub const AUTO_CG_FROM_DOFS: usize = 10_000;

/// Which step solver a run uses (see the module documentation).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, Serialize, Deserialize)]
pub enum LinearSolver {
    /// Sparse Cholesky.
    Direct,
    /// Preconditioned conjugate gradients.
    Cg,
    /// On a box, by its size ([`AUTO_CG_FROM_DOFS`]); on any other model, `direct`.
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

/// The step solver a run's plan resolved its [`LinearSolver`] to: `auto` is no longer one.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum StepSolverKind {
    /// Sparse Cholesky.
    Direct,
    /// Preconditioned conjugate gradients.
    Cg,
}

impl StepSolverKind {
    /// The name on the command line and in a box run's record (`direct` or `cg`).
    pub fn name(self) -> &'static str {
        match self {
            StepSolverKind::Direct => LinearSolver::Direct.name(),
            StepSolverKind::Cg => LinearSolver::Cg.name(),
        }
    }
}

/// A step matrix ready to be solved with, by the solver its plan chose.
#[derive(Debug)]
pub enum StepSolver {
    /// Factorised.
    Direct(SpdSolver),
    /// Prepared for CG, with the work vectors of the per-step solve.
    Cg {
        /// The matrix and its preconditioner.
        pcg: Box<Pcg>,
        /// The solution buffer.
        x: Vec<f64>,
        /// `r`, `z`, `p`, `K p`.
        work: PcgWork,
        /// The solves so far and their iterations.
        counts: SolveCounts,
    },
}

/// How many systems a step solver solved and, for CG, the iterations they took in all (0 for
/// the direct solver).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct SolveCounts {
    /// Systems solved (one per step and per start).
    pub solves: usize,
    /// CG iterations over all of them.
    pub iterations: usize,
}

impl StepSolver {
    /// Prepares `a` (factorised, or kept for CG) as `kind` says, but for a matrix of bandwidth
    /// one or less, which is always factorised (tridiagonal or diagonal); `name` says which
    /// matrix this is in error messages.
    pub fn new(
        a: SymmetricMatrix,
        kind: StepSolverKind,
        name: &'static str,
    ) -> Result<Self, SolveError> {
        let n = a.dim();
        if kind == StepSolverKind::Cg && a.bandwidth() > 1 {
            Ok(StepSolver::Cg {
                pcg: Box::new(Pcg::new(a, DEFAULT_TOLERANCE, name)?),
                x: vec![0.0; n],
                work: PcgWork::new(n),
                counts: SolveCounts::default(),
            })
        } else {
            SpdSolver::factor(&a, name).map(StepSolver::Direct)
        }
    }

    /// The per-step solves so far (`solve`, not `solve_columns`) and their CG iterations.
    pub fn counts(&self) -> SolveCounts {
        match self {
            StepSolver::Direct(_) => SolveCounts::default(),
            StepSolver::Cg { counts, .. } => *counts,
        }
    }

    /// The step matrix, kept by the iterative solver (`None` for the direct one, which keeps
    /// only its factor).
    pub fn matrix(&self) -> Option<&SymmetricMatrix> {
        match self {
            StepSolver::Direct(_) => None,
            StepSolver::Cg { pcg, .. } => Some(pcg.matrix()),
        }
    }

    /// Whether [`StepSolver::solve`] reads its initial guess (an iterative solve); a direct one
    /// ignores it, so a caller need not form it.
    pub fn reads_guess(&self) -> bool {
        matches!(self, StepSolver::Cg { .. })
    }

    /// Solves `K x = b`: `rhs` holds `b` on entry and `x` on exit. `guess` is CG's initial
    /// guess (the direct solver ignores it).
    pub fn solve(&mut self, rhs: &mut [f64], guess: &[f64]) -> Result<(), SolveError> {
        match self {
            StepSolver::Direct(solver) => solver.solve_in_place(rhs),
            StepSolver::Cg {
                pcg,
                x,
                work,
                counts,
            } => {
                x.copy_from_slice(guess);
                counts.iterations += pcg.solve(rhs, x, work)?;
                counts.solves += 1;
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
