//! Linear solvers for the symmetric positive definite systems of the implicit schemes.

mod spd;
mod tridiagonal;

pub use spd::SpdSolver;
pub use tridiagonal::TridiagonalLdlt;
