//! A scheme with the state it steps, as a unit test drives one scheme alone: what the harness's
//! time loop holds apart (the method and the state it hands to it), held together for the
//! length of a test.

use std::ops::Deref;

use signorini::engine::error::SolveError;
use signorini::engine::model::Model;
use signorini::engine::schemes::{
    integrator, Conventions, Integration, Integrator, Scheme, SchemeState, StepStatistics,
    TimeIntegrator, Timed,
};

/// A scheme and its state.
pub struct Stepper<'m> {
    /// The method.
    pub scheme: Box<dyn TimeIntegrator + 'm>,
    /// The state it advances.
    pub state: SchemeState,
}

impl<'m> Stepper<'m> {
    /// `scheme` from `state`.
    pub fn new(scheme: impl TimeIntegrator + 'm, state: SchemeState) -> Self {
        Self {
            scheme: Box::new(scheme),
            state,
        }
    }

    /// The factory's `scheme` on `model` with the harness's conventions, from `U^0 = u0`,
    /// `V^0 = v0` with step `dt`; a scheme the factory refuses fails the test.
    pub fn harness(model: &'m Model, scheme: Scheme, dt: f64, u0: &[f64], v0: &[f64]) -> Self {
        Self::from(integrator(model, scheme, dt, u0, v0, &Conventions::HARNESS).unwrap())
    }

    /// One step of the state.
    pub fn advance(&mut self) -> Result<(), SolveError> {
        self.scheme.advance(&mut self.state)
    }

    /// The scheme's energy of the state.
    pub fn energy(&self) -> Timed<f64> {
        self.scheme.energy(&self.state)
    }

    /// What the steps cost.
    pub fn statistics(&self) -> StepStatistics {
        self.scheme.statistics()
    }

    /// The state with its scheme, as the time loop hands it to an observer.
    pub fn observed(&self) -> Integration<'_> {
        Integration {
            scheme: self.scheme.as_ref(),
            state: &self.state,
        }
    }
}

impl<'m> From<Integrator<'m>> for Stepper<'m> {
    fn from((scheme, state): Integrator<'m>) -> Self {
        Self { scheme, state }
    }
}

impl Deref for Stepper<'_> {
    type Target = SchemeState;

    fn deref(&self) -> &SchemeState {
        &self.state
    }
}
