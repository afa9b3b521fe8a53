//! Time integrators of the 1D paper (§3.2), written against [`Model`](crate::model::Model):
//!
//! * the Newmark family (eq. 32) and the θ-method (eq. 34), both one-step schemes with the
//!   contact condition at `t_{n+1}` ([`OneStepScheme`]);
//! * the Paoli–Schatzman scheme (eq. 36), a two-step scheme with the contact condition on
//!   `(u^{n+1} + e u^{n−1}) / (1 + e)` ([`PaoliSchatzman`]);
//! * explicit Newmark, β = 0 (central differences for γ = ½), with its CFL bound checked
//!   before the run ([`ExplicitNewmark`], [`cfl`]).
//!
//! Every scheme stays well defined with a singular mass matrix (see [`start`]).

pub mod cfl;
mod explicit;
pub mod massless;
mod one_step;
mod paoli_schatzman;
mod scheme;
pub mod start;

pub use explicit::ExplicitNewmark;
#[doc(hidden)]
pub use one_step::REASSOCIATED_PREDICTOR;
pub use one_step::{OneStepScheme, StepCoefficients};
pub use paoli_schatzman::PaoliSchatzman;
pub use scheme::{Scheme, SCHEME_NAMES};

use crate::error::SolveError;

/// A value with the time it approximates.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Timed<T> {
    /// The time.
    pub time: f64,
    /// The value.
    pub value: T,
}

/// A time integrator holding its state `(U^n, V^n, λ^n)`.
pub trait TimeIntegrator: Send {
    /// Advances from `t_n` to `t_{n+1}`.
    fn advance(&mut self) -> Result<(), SolveError>;
    /// The index `n` of the current state.
    fn step_index(&self) -> usize;
    /// `t_n = n Δt`.
    fn time(&self) -> f64 {
        self.step_index() as f64 * self.dt()
    }
    /// The time step `Δt`.
    fn dt(&self) -> f64;
    /// `U^n`.
    fn displacement(&self) -> &[f64];
    /// The velocity the scheme carries (`V^n`; `(U^n − U^{n−1})/Δt` at `t_{n−½}` for
    /// Paoli–Schatzman).
    fn velocity(&self) -> &[f64];
    /// The contact multipliers (`λ ≤ 0`, one per contact dof) with the time they approximate.
    fn multiplier(&self) -> Timed<&[f64]>;
    /// The scheme's discrete energy with the time it approximates (computed on demand).
    fn energy(&self) -> Timed<f64>;
    /// How many steps needed a complementarity solve.
    fn contact_solves(&self) -> usize;
    /// Wall-clock seconds spent in those solves.
    fn contact_seconds(&self) -> f64;
    /// The largest complementarity violation of any step so far (on the constrained quantity
    /// of the scheme: `u^{n+1}`, or `(u^{n+1} + e u^{n−1})/(1 + e)` for Paoli–Schatzman).
    fn complementarity_violation(&self) -> f64;
}
