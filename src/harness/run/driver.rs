//! The one time loop of every run, bar or box: the problem discretised at a level is stepped
//! to its horizon by a scheme, every state `t_n`, `n = 0..=N`, is checked for non-finite
//! values and handed to the run's observers.

use std::time::Instant;

use serde::{Deserialize, Serialize};

use crate::engine::error::{require_positive, SolveError};
use crate::engine::problem::Discretisation;
use crate::engine::schemes::{integrator, Scheme, TimeIntegrator};
use crate::harness::error::Error;

/// What a run does with each state of the scheme: accumulate a norm, record a history, write
/// a snapshot. Observers see the state at `t_0` (the initial data) and after every step.
pub trait Observer {
    /// Takes in the state `t_n` of `state`.
    fn observe(&mut self, state: &dyn TimeIntegrator) -> Result<(), Error>;
}

/// A closure is an observer (a one-off probe: a test, a sampled history).
impl<F: FnMut(&dyn TimeIntegrator) -> Result<(), Error>> Observer for F {
    fn observe(&mut self, state: &dyn TimeIntegrator) -> Result<(), Error> {
        self(state)
    }
}

/// Wall-clock time of the phases of a run, in seconds.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct Timings {
    /// Assembly, factorisation, Delassus operator and initial state.
    pub setup: f64,
    /// Time stepping, contact solves excluded.
    pub stepping: f64,
    /// Complementarity solves and their corrections.
    pub contact: f64,
    /// Observers (norms and histories).
    pub observe: f64,
}

impl Timings {
    /// The whole run.
    pub fn total(&self) -> f64 {
        self.setup + self.stepping + self.contact + self.observe
    }
}

/// The number of steps and the step that lands exactly on `horizon`.
pub fn time_grid(horizon: f64, h: f64, ratio: f64) -> (usize, f64) {
    let nominal = h / ratio;
    let steps = ((horizon / nominal) - 1e-9).ceil().max(1.0) as usize;
    (steps, horizon / steps as f64)
}

/// What the time loop itself measured.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Stepped {
    /// Steps `N`.
    pub steps: usize,
    /// `Δt = T / N`.
    pub dt: f64,
    /// Steps that needed a complementarity solve.
    pub contact_solves: usize,
    /// Largest complementarity violation.
    pub complementarity_violation: f64,
    /// Wall-clock split; `setup` counts from `started`.
    pub timings: Timings,
}

/// `times` sorted from the last to the first, so that the next one due is popped.
pub(crate) fn descending(times: &[f64]) -> Vec<f64> {
    let mut t = times.to_vec();
    t.sort_by(|a, b| b.total_cmp(a));
    t
}

/// The first non-finite value of the state, as the error that stops the run.
fn check_finite(scheme: &dyn TimeIntegrator) -> Result<(), SolveError> {
    let fields: [(&'static str, &[f64]); 3] = [
        ("displacement", scheme.displacement()),
        ("velocity", scheme.velocity()),
        ("multiplier", scheme.multiplier().value),
    ];
    for (quantity, values) in fields {
        if values.iter().any(|v| !v.is_finite()) {
            return Err(SolveError::NonFinite {
                step: scheme.step_index(),
                time: scheme.time(),
                quantity,
            });
        }
    }
    Ok(())
}

/// Steps `discretisation` from its initial dofs to `horizon` with `scheme` and
/// `Δt = T / ⌈T ratio / Δx⌉` ([`time_grid`], `Δx` the element size along the axis), handing
/// every state to each of `observers` in order. The first non-finite displacement, velocity
/// or multiplier stops the run with [`SolveError::NonFinite`]. `started` is when the run's
/// setup began (its discretisation included).
pub fn drive(
    discretisation: &Discretisation,
    horizon: f64,
    ratio: f64,
    scheme: Scheme,
    observers: &mut [&mut dyn Observer],
    started: Instant,
) -> Result<Stepped, Error> {
    require_positive("ratio", ratio)?;
    require_positive("horizon", horizon)?;
    let scheme = scheme.validate()?;
    let h = discretisation.mesh.axial_element_size();
    let (steps, dt) = time_grid(horizon, h, ratio);
    let mut integ = integrator(
        &discretisation.model,
        scheme,
        dt,
        &discretisation.displacement,
        &discretisation.velocity,
    )?;
    let setup = started.elapsed().as_secs_f64();

    let (mut stepping, mut observe) = (0.0, 0.0);
    for step in 0..=steps {
        if step > 0 {
            let clock = Instant::now();
            integ.advance()?;
            check_finite(integ.as_ref())?;
            stepping += clock.elapsed().as_secs_f64();
        }
        let clock = Instant::now();
        for o in observers.iter_mut() {
            o.observe(integ.as_ref())?;
        }
        observe += clock.elapsed().as_secs_f64();
    }
    Ok(Stepped {
        steps,
        dt,
        contact_solves: integ.contact_solves(),
        complementarity_violation: integ.complementarity_violation(),
        timings: Timings {
            setup,
            stepping: stepping - integ.contact_seconds(),
            contact: integ.contact_seconds(),
            observe,
        },
    })
}
