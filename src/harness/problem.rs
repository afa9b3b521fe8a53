//! The engine's vocabulary as the harness runs it: the problem a scene declares (a bar,
//! [`Problem1d`], or a box, [`BoxProblem`]; a bar at rest, [`AtRest`], is the exact solution a
//! study may give it), its initial data and their seeded [`Perturbation`] (and an ensemble member's
//! per-step [`StepPerturbation`]), its contact
//! treatment; the [`Settings`] it is solved with (the [`Conventions`] its schemes start and step
//! with, the linear solver, a round-off perturbation); and what each run of it chooses, its
//! [`Scheme`] and [`MassVariant`]. What these are and do is the engine's; studies name them here.

pub use crate::engine::contact::{ContactTreatment, TREATMENT_LIST};
pub use crate::engine::exact::AtRest;
pub use crate::engine::fem::MassVariant;
pub use crate::engine::linalg::LinearSolver;
pub use crate::engine::problem::{
    BoxProblem, InitialData, Perturbation, Problem, Problem1d, Profile, Settings, StepPerturbation,
    UNIT_ROUNDOFF,
};
pub use crate::engine::schemes::conventions::Start;
pub use crate::engine::schemes::{AlphaParameters, Conventions, PredictorVelocity, Scheme};
