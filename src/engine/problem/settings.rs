//! How a problem is solved, apart from what it is: the settings every run takes beside its
//! [`crate::engine::problem::Problem`] (as Clarabel takes its settings beside the data). The
//! problem holds the physics and the discretisation (geometry, material, obstacle, load,
//! initial data, horizon, contact treatment); the settings hold the implementation choices that
//! do not change the continuous problem nor its discretisation: the conventions of the
//! schemes, the step solver, the Delassus operator of the contact steps, and the round-off
//! perturbations of an ensemble member (of the initial data, or of the state after every step). The resource limits of a run are not read by the engine:
//! they are checked against an estimate before any run starts (`crate::harness::study::budget`).

use super::{Perturbation, StepPerturbation};
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
    /// A round-off ensemble member's seeded relative perturbation of the state the scheme
    /// carries, applied by the run loop after every step ([`StepPerturbation`]). `None` (the
    /// default): the steps as computed, bit for bit.
    pub step_round_off: Option<StepPerturbation>,
}

impl Default for Settings {
    fn default() -> Self {
        Self {
            conventions: Conventions::HARNESS,
            linear_solver: LinearSolver::default(),
            contact_operator: ContactOperator::default(),
            round_off: None,
            step_round_off: None,
        }
    }
}

impl Settings {
    /// `Ok` when every setting can be applied: a round-off perturbation's amplitude is finite
    /// and `>= 0`, a per-step perturbation's `ε` is in `[0, 1e-3]` (round-off scale, far below
    /// anything physical); the named error otherwise.
    pub fn validate(&self) -> Result<(), ParameterError> {
        if let Some(p) = self.round_off {
            if !(p.amplitude.is_finite() && p.amplitude >= 0.0) {
                return Err(ParameterError::new(
                    "round_off.amplitude",
                    p.amplitude,
                    "a finite number >= 0",
                ));
            }
        }
        match self.step_round_off {
            Some(p) if !(0.0..=1e-3).contains(&p.epsilon) => Err(ParameterError::new(
                "step_round_off.epsilon",
                p.epsilon,
                "a relative size in [0, 1e-3]",
            )),
            _ => Ok(()),
        }
    }

    /// These settings for a run distributed over ranks, whose steps are solved by CG: the step
    /// solver `auto` becomes `cg`, `direct` is refused.
    pub fn distributed(&self) -> Result<Self, ParameterError> {
        if self.linear_solver == LinearSolver::Direct {
            return Err(ParameterError::new(
                "linear-solver",
                "direct",
                "cg or auto for a reference across MPI ranks (its steps are solved by CG)",
            ));
        }
        Ok(Self {
            linear_solver: LinearSolver::Cg,
            ..*self
        })
    }

    /// These settings with the round-off perturbation `round_off`.
    pub fn with_round_off(self, round_off: Perturbation) -> Self {
        Self {
            round_off: Some(round_off),
            ..self
        }
    }

    /// These settings with the per-step round-off perturbation `step_round_off`.
    pub fn with_step_round_off(self, step_round_off: StepPerturbation) -> Self {
        Self {
            step_round_off: Some(step_round_off),
            ..self
        }
    }
}
