//! How a problem is solved, apart from what it is: the settings every run takes beside its
//! [`crate::engine::problem::Problem`] (as Clarabel takes its settings beside the data). The
//! problem holds the physics and the discretisation (geometry, material, obstacle, load,
//! initial data, horizon, contact treatment); the settings hold the implementation choices that
//! do not change the continuous problem nor its discretisation: the conventions of the
//! schemes, the step solver, the Delassus operator of the contact steps, and the round-off
//! perturbation of an ensemble member. The resource limits of a run are not read by the engine:
//! they are checked against an estimate before any run starts (`crate::harness::study::budget`).

use super::Perturbation;
use crate::engine::contact::ContactOperator;
use crate::engine::error::ParameterError;
use crate::engine::linalg::LinearSolver;
use crate::engine::schemes::Conventions;

/// The implementation choices of a run; [`Settings::default`] is the harness's.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Settings {
    /// The schemes' conventions (the start, the Nitsche acceleration, Paoli–Schatzman's
    /// massless rows and first step, the predictor's summation).
    pub conventions: Conventions,
    /// How the implicit schemes solve their step matrices (`auto`: by size on a box, direct
    /// otherwise).
    pub linear_solver: LinearSolver,
    /// Which Delassus operator the contact steps of a box use (`auto`: by step solver).
    pub contact_operator: ContactOperator,
    /// A round-off ensemble member's seeded perturbation of the initial data: added to every
    /// displacement dof but the contact dofs of a bar (after the scene's own perturbation), to
    /// every velocity dof of a box. `None` for the problem as stated.
    pub round_off: Option<Perturbation>,
}

impl Default for Settings {
    fn default() -> Self {
        Self {
            conventions: Conventions::HARNESS,
            linear_solver: LinearSolver::default(),
            contact_operator: ContactOperator::default(),
            round_off: None,
        }
    }
}

impl Settings {
    /// `Ok` when every setting can be applied: a round-off perturbation's amplitude is finite
    /// and `>= 0`; the named error otherwise.
    pub fn validate(&self) -> Result<(), ParameterError> {
        match self.round_off {
            Some(p) if !(p.amplitude.is_finite() && p.amplitude >= 0.0) => Err(
                ParameterError::new("round_off.amplitude", p.amplitude, "a finite number >= 0"),
            ),
            _ => Ok(()),
        }
    }

    /// These settings with the round-off perturbation `round_off`.
    pub fn with_round_off(self, round_off: Perturbation) -> Self {
        Self {
            round_off: Some(round_off),
            ..self
        }
    }
}
