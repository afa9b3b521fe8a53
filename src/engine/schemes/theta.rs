//! The θ-method, 1D paper eq. (34):
//! ```text
//! U^{n+1} = U^n + Δt ((1 − θ) V^n + θ V^{n+1})                       (34a)
//! V^{n+1} = V^n + Δt ((1 − θ) A^n + θ A^{n+1})                       (34b)
//! M A^{n+1} + S U^{n+1} = F − Bᵀλ^{n+1}                              (34c)
//! 0 ≤ B U^{n+1} + g ⟂ λ^{n+1} ≤ 0                                     (34d)
//! ```
//! θ ∈ (0, 1]: θ = 1 is backward Euler, θ = ½ coincides with Crank–Nicolson. Eliminating
//! `V^{n+1}` from (34a) with (34b) gives
//! `U^{n+1} = U^n + Δt V^n + Δt² (θ(1 − θ) A^n + θ² A^{n+1})`, the common one-step form of
//! [`super::OneStepScheme`] with `(a, b, c, d) = (θ(1 − θ), θ², 1 − θ, θ)`
//! ([`StepCoefficients::theta`]); `A^0` comes from (34c) at `t = 0` ([`super::initial_state`]).
//! Unlike Newmark's, these coefficients have `a + b = θ ≠ ½` unless θ = ½: the θ-method is not
//! a member of the Newmark family.
//!
//! The energy balance of (34) is eq. (35) ([`super::energy_balance::theta`]).

use super::StepCoefficients;

impl StepCoefficients {
    /// θ-method, eq. (34a–b): `(a, b, c, d) = (θ(1 − θ), θ², 1 − θ, θ)`.
    pub fn theta(theta: f64) -> Self {
        Self {
            a: theta * (1.0 - theta),
            b: theta * theta,
            c: 1.0 - theta,
            d: theta,
        }
    }
}
