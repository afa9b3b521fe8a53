//! Contact at the constrained dofs, reduced to the Delassus operator.
//!
//! Each implicit step solves `K U = r − Bᵀλ` with `0 ≤ B U + c ⟂ λ ≤ 0`. With `μ = −λ ≥ 0`,
//! `U = U_free + K⁻¹Bᵀμ` and the constraint values are `g_free + W μ`, `W = B K⁻¹ Bᵀ` (the
//! Delassus operator, computed once per factorisation). What remains is the linear
//! complementarity problem `0 ≤ μ ⟂ g_free + W μ ≥ 0`, solved by a [`ContactSolver`].
//!
//! `W` and the correction `K⁻¹Bᵀμ` come from one solve per constraint ([`Delassus`]) or from
//! a slab of dofs around the contact face ([`local`]): the local operator with the iterative
//! step solver, the full one with the direct solver ([`ContactOperator`], resolved once into a
//! [`DelassusKind`]).
//!
//! The penalty and Nitsche treatments ([`ContactTreatment`]) lead to the same problem with a
//! shifted operator (see [`law`]), so the same solvers serve every treatment.

mod active_set;
mod closed_form;
mod delassus;
pub mod law;
pub mod local;
mod qp;
mod set;
mod treatment;

pub use active_set::PrimalDualActiveSet;
pub use closed_form::ClosedFormContact;
pub use delassus::{ContactStep, Delassus};
pub use law::{ConstraintRow, ContactLaw};
pub use local::{
    ContactOperator, DelassusKind, LocalDelassus, SlabSolve, Truncation, CG_SLAB_FROM_DOFS,
};
pub use qp::ClarabelContact;
pub use set::ContactSet;
pub use treatment::{ContactTreatment, TREATMENT_LIST, TREATMENT_NAMES};

/// Outcome of one complementarity solve.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ContactStatus {
    /// Solved; `iterations` is 1 for a closed form.
    Solved {
        /// Iterations spent.
        iterations: usize,
    },
    /// The iteration limit was reached.
    NotConverged {
        /// Iterations spent.
        iterations: usize,
    },
}

/// Solves `0 ≤ μ ⟂ g + W μ ≥ 0` for a symmetric positive definite `W` (or, for one constraint,
/// a positive scalar).
pub trait ContactSolver: Send + Sync + std::fmt::Debug {
    /// `w` is row-major `n × n`, `g` the free constraint values; writes `mu`.
    fn solve(&mut self, w: &[f64], g: &[f64], mu: &mut [f64]) -> ContactStatus;
}

/// The solver suited to `n` constraints: the closed form for one, the active-set method otherwise.
pub fn default_solver(n: usize) -> Box<dyn ContactSolver> {
    if n == 1 {
        Box::new(ClosedFormContact)
    } else {
        Box::new(PrimalDualActiveSet::default())
    }
}
