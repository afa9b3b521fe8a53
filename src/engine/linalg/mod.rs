//! Linear solvers for the symmetric positive definite systems of the implicit schemes.

mod banded;
mod condensed;
mod pcg;
mod product;
mod spd;
mod step;
mod tridiagonal;
mod twisted;

pub use banded::BandCholesky;
pub use condensed::CondensedPlane;
pub use pcg::{conjugate_gradient, dot, jacobi, CgSpace, Pcg, PcgWork, DEFAULT_TOLERANCE};
pub use product::ProductPreconditioner;
pub use spd::SpdSolver;
pub use step::{
    LinearSolver, SolveCounts, StepSolver, StepSolverKind, AUTO_CG_FROM_DOFS, LINEAR_SOLVER_NAMES,
};
pub use tridiagonal::{
    solve_interleaved_rows, solve_lines, sweep_interleaved_rows, RowBlock, Sweep, TridiagonalLdlt,
};
pub use twisted::TwistedTridiagonal;
