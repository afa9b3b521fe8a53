//! Typed errors of the engine: parameters out of range and failed solves.
//!
//! Every message names the parameter (or the step and the quantity) and the allowed range, so
//! that a user reading it knows what to change.

use serde::{Deserialize, Serialize};
use thiserror::Error;

/// A parameter outside its allowed range.
#[derive(Debug, Clone, PartialEq, Error)]
#[error("invalid {name} = {value}: allowed {allowed}")]
pub struct ParameterError {
    /// The parameter's name as the user writes it (e.g. `nx`, `dt`, `beta`).
    pub name: &'static str,
    /// The rejected value, formatted.
    pub value: String,
    /// The allowed values or range, in words.
    pub allowed: &'static str,
}

/// The longest number a message shows in positional notation: a longer one (`1e-300` is 302
/// characters so) is shown in scientific notation.
const LONGEST_POSITIONAL: usize = 24;

/// `value` as a message shows it: a number whose positional form is longer than
/// [`LONGEST_POSITIONAL`] characters in scientific notation (`1e-300`, not 300 zeros), any
/// other text as it is.
pub fn compact(value: String) -> String {
    if value.len() <= LONGEST_POSITIONAL {
        return value;
    }
    match value.trim().parse::<f64>() {
        Ok(x) => format!("{x:e}"),
        Err(_) => value,
    }
}

impl ParameterError {
    /// A parameter error for `name` with the offending `value`.
    pub fn new(name: &'static str, value: impl ToString, allowed: &'static str) -> Self {
        Self {
            name,
            value: compact(value.to_string()),
            allowed,
        }
    }

    /// The error of the parameter `key` given more than once in the string `value` of `name`
    /// (`newmark(beta=0.3,beta=0.4)`): refused rather than letting the last one win.
    pub fn repeated(name: &'static str, value: &str, key: &str) -> Self {
        Self::new(
            name,
            format!("{value} ({key} is given more than once)"),
            "each parameter at most once",
        )
    }
}

/// Checks `value` is finite and strictly positive.
pub fn require_positive(name: &'static str, value: f64) -> Result<f64, ParameterError> {
    if value.is_finite() && value > 0.0 {
        Ok(value)
    } else {
        Err(ParameterError::new(name, value, "a finite number > 0"))
    }
}

/// Checks `value` is finite and lies in the closed interval `[lo, hi]`.
pub fn require_in(
    name: &'static str,
    value: f64,
    lo: f64,
    hi: f64,
    allowed: &'static str,
) -> Result<f64, ParameterError> {
    if value.is_finite() && (lo..=hi).contains(&value) {
        Ok(value)
    } else {
        Err(ParameterError::new(name, value, allowed))
    }
}

/// A failure while time stepping.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum SolveError {
    /// The system matrix could not be factorised (not symmetric positive definite).
    #[error("the {matrix} matrix is not symmetric positive definite ({detail})")]
    Factorization {
        /// Which matrix (e.g. `Newmark system`).
        matrix: &'static str,
        /// What the factorisation reported.
        detail: String,
    },
    /// The contact complementarity problem was not solved.
    #[error("contact solver did not converge at step {step} after {iterations} iterations")]
    ContactNotConverged {
        /// Time step index.
        step: usize,
        /// Iterations spent.
        iterations: usize,
    },
    /// Explicit Newmark with `Δt` above its stability bound (checked before the first step).
    #[error(
        "time step too large for explicit Newmark (β = 0, γ = {gamma}): Δt = {dt:.6e} but the CFL \
         bound is Δt ≤ √(2/γ)/ω_max = {bound:.6e} (2/ω_max for central differences; ω_max² the \
         largest eigenvalue of S x = ω² M x on the dofs with mass); use a Δt at least {:.3} times \
         smaller (a larger ratio Δx/Δt)",
        dt / bound
    )]
    CflViolated {
        /// The requested time step.
        dt: f64,
        /// The largest stable time step `√(2/γ)/ω_max`.
        bound: f64,
        /// Newmark's γ.
        gamma: f64,
    },
    /// An iterative linear solver did not reach its tolerance.
    #[error("the {solver} solver did not converge in {iterations} iterations (relative residual {residual:e})")]
    NotConverged {
        /// Which solver.
        solver: &'static str,
        /// Iterations spent.
        iterations: usize,
        /// The relative residual reached.
        residual: f64,
    },
    /// A step whose solve cannot be trusted: the step solver missed its tolerance, or the
    /// scheme's discrete energy balance is violated beyond round-off.
    #[error("inaccurate solve at step {step} (t = {time}): {detail}")]
    Inaccurate {
        /// Time step index.
        step: usize,
        /// Time of the step.
        time: f64,
        /// What missed its bound, with the value and the bound.
        detail: String,
    },
    /// A state value became NaN or infinite.
    #[error("non-finite {quantity} at step {step} (t = {time})")]
    NonFinite {
        /// Time step index.
        step: usize,
        /// Time of the step.
        time: f64,
        /// Which part of the state.
        quantity: StateField,
    },
}

/// A part of a scheme's state at a step, or a quantity a run observes from it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum StateField {
    /// `U^n`.
    Displacement,
    /// `V^n`.
    Velocity,
    /// `λ^n`.
    Multiplier,
    /// The discrete energy `E_h(t_n)`.
    Energy,
    /// The space norms of the displacement error `u_h − u` at `t_n`, or their sum over time.
    DisplacementError,
    /// The multiplier error `λ_h − λ`, or its sum over time.
    MultiplierError,
    /// The energy error `E_h − E`, or its sum over time.
    EnergyError,
    /// The strain `∂x u_h` of a field snapshot.
    Strain,
    /// The von Mises stress of a box snapshot.
    VonMises,
}

impl std::fmt::Display for StateField {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            StateField::Displacement => "displacement",
            StateField::Velocity => "velocity",
            StateField::Multiplier => "multiplier",
            StateField::Energy => "energy",
            StateField::DisplacementError => "displacement error",
            StateField::MultiplierError => "multiplier error",
            StateField::EnergyError => "energy error",
            StateField::Strain => "strain",
            StateField::VonMises => "von Mises stress",
        })
    }
}

impl SolveError {
    /// Whether the error is a choice of parameters the user can change before running (the
    /// CFL bound) rather than a failure of the computation.
    pub fn is_usage(&self) -> bool {
        matches!(self, SolveError::CflViolated { .. })
    }
}

/// Any error of the engine: a parameter out of range or a failed solve.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum Error {
    /// A parameter out of range.
    #[error(transparent)]
    Parameter(#[from] ParameterError),
    /// Time stepping failed.
    #[error(transparent)]
    Solve(#[from] SolveError),
}
