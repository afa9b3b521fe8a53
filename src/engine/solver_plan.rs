//! How a discretisation's steps are solved, decided once: the step solver and the Delassus
//! operator of the contact steps, with every `auto` of the settings ([`LinearSolver::Auto`],
//! [`ContactOperator::Auto`]) resolved where the problem is discretised at a level, and the
//! reason in words. The model carries the plan; the schemes, the step solver and the contact
//! step read it and decide nothing.
//!
//! The rules:
//! * a bar: `direct` (its step matrices are tridiagonal) and the full operator; `cg` is refused;
//! * a box: the step solver `auto` is `cg` from [`AUTO_CG_FROM_DOFS`] unknowns on and `direct`
//!   below; the contact operator `auto` is the local one with `cg` and the full one with
//!   `direct` ([`crate::engine::contact::local`]);
//! * a model given no plan (assembled by hand): `direct` and the full operator.

use crate::engine::contact::{ContactOperator, DelassusKind};
use crate::engine::error::ParameterError;
use crate::engine::linalg::{LinearSolver, StepSolverKind, AUTO_CG_FROM_DOFS};

/// The solvers of a discretisation's steps, resolved (see the module documentation).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SolverPlan {
    /// How the implicit schemes solve their step matrices.
    pub step: StepSolverKind,
    /// Which Delassus operator the contact steps use.
    pub contact: DelassusKind,
    /// Why: each choice and the rule that made it, e.g. `step solver cg (auto: cg from 10000
    /// unknowns, this box has 19440); contact operator local (auto: local with cg)`.
    pub reason: String,
}

impl Default for SolverPlan {
    /// `direct` and the full operator, for a model given no plan.
    fn default() -> Self {
        Self {
            step: StepSolverKind::Direct,
            contact: DelassusKind::Full,
            reason: "step solver direct, contact operator full (a model given no plan)".into(),
        }
    }
}

impl SolverPlan {
    /// The plan of a 1D bar solved with the step solver `step`: `direct` and the full
    /// operator; `cg` is refused (a bar's steps are tridiagonal, solved directly).
    pub fn for_bar(step: LinearSolver) -> Result<Self, ParameterError> {
        if step == LinearSolver::Cg {
            return Err(ParameterError::new(
                "linear_solver",
                step.name(),
                "direct or auto for a bar1d (its steps are tridiagonal, solved directly)",
            ));
        }
        Ok(Self {
            step: StepSolverKind::Direct,
            contact: DelassusKind::Full,
            reason: "step solver direct (a bar's step matrices are tridiagonal); \
                     contact operator full"
                .into(),
        })
    }

    /// The plan of a box with `unknowns` dofs solved with the step solver `step` and the
    /// contact operator `contact`, each `auto` resolved by the rules of the module
    /// documentation. A local operator with the direct step solver is refused: it needs the
    /// step matrix, which the direct solver does not keep.
    pub fn for_box(
        step: LinearSolver,
        contact: ContactOperator,
        unknowns: usize,
    ) -> Result<Self, ParameterError> {
        let (step, step_reason) = box_step_solver(step, unknowns);
        let (contact, contact_reason) = match contact {
            ContactOperator::Full => (DelassusKind::Full, "as asked".to_string()),
            ContactOperator::Local => (DelassusKind::Local { layers: None }, "as asked".into()),
            ContactOperator::LocalLayers(l) => (
                DelassusKind::Local { layers: Some(l) },
                format!("{l} layers, as asked"),
            ),
            ContactOperator::Auto => {
                let kind = match step {
                    StepSolverKind::Cg => DelassusKind::Local { layers: None },
                    StepSolverKind::Direct => DelassusKind::Full,
                };
                (kind, format!("auto: {} with {}", kind.name(), step.name()))
            }
        };
        if step == StepSolverKind::Direct && contact != DelassusKind::Full {
            return Err(ParameterError::new(
                "contact_operator",
                contact.name(),
                "full or auto with the direct step solver (the local contact operator needs \
                 the step matrix, which only the cg step solver keeps)",
            ));
        }
        Ok(Self {
            step,
            contact,
            reason: format!(
                "step solver {} ({step_reason}); contact operator {} ({contact_reason})",
                step.name(),
                contact.name()
            ),
        })
    }
}

/// The step solver of a box with `unknowns` dofs when `choice` is asked for, and why: `auto` is
/// `cg` from [`AUTO_CG_FROM_DOFS`] unknowns on and `direct` below. The plan
/// ([`SolverPlan::for_box`]) and the memory budget of a box run both resolve it here, so that
/// they never disagree.
pub fn box_step_solver(choice: LinearSolver, unknowns: usize) -> (StepSolverKind, String) {
    match choice {
        LinearSolver::Direct => (StepSolverKind::Direct, "as asked".into()),
        LinearSolver::Cg => (StepSolverKind::Cg, "as asked".into()),
        LinearSolver::Auto if unknowns >= AUTO_CG_FROM_DOFS => (
            StepSolverKind::Cg,
            format!("auto: cg from {AUTO_CG_FROM_DOFS} unknowns, this box has {unknowns}"),
        ),
        LinearSolver::Auto => (
            StepSolverKind::Direct,
            format!("auto: direct below {AUTO_CG_FROM_DOFS} unknowns, this box has {unknowns}"),
        ),
    }
}
