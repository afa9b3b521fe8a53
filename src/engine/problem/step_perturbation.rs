//! A round-off ensemble member perturbed at every step ([`StepPerturbation`]): after each step,
//! every value of the state the scheme carries into the next one
//! ([`crate::engine::schemes::TimeIntegrator::perturb_carried`]) is moved by a seeded relative
//! amount,
//!
//! `x ← x + ε |x| ξ`, `ξ` uniform in `[−1, 1]`, drawn afresh for every value of every step,
//!
//! then rounded to the nearest double as any result is.
//!
//! Why this rule: the standard model of floating-point arithmetic writes every computed result
//! as `fl(x) = x (1 + δ)`, `|δ| ≤ u` (the unit round-off, `2⁻⁵³`). Another code computing the
//! same step with other operation orders, another linear solver or other BLAS kernels lands
//! on another `x (1 + δ')` of the same size. A uniform `δ` in `±ε` on the step's outputs is
//! that model with the perturbation drawn at random, as Monte Carlo arithmetic (Verificarlo's
//! random rounding, CADNA's random rounding mode) draws it on every operation; drawing it on
//! the step's outputs only costs one pass over the state per step, and with `ε = u` it injects
//! no more than one rounding per value and step (part of the draws round back to `x`), a lower
//! estimate of a step's many roundings, never an inflated one. The perturbation is relative:
//! zeros stay zero (a clamped dof, a contact dof held at its gap, a massless dof at rest), so
//! the perturbed state satisfies the same constraints as the unperturbed one; a zero shift
//! changes no bit (the sign of a zero, which contact decisions may read, is kept).
//!
//! Reproducible: the draws come from one `fastrand` stream seeded by [`StepPerturbation::seed`],
//! consumed in the order of the steps and of the carried vectors, so the same seed gives the same
//! bits.

use serde::{Deserialize, Serialize};

/// The unit round-off of a double, `u = 2⁻⁵³ ≈ 1.1e-16`: the relative size of one rounding to
/// nearest, the per-step perturbation of an ensemble by default.
pub const UNIT_ROUNDOFF: f64 = f64::EPSILON / 2.0;

/// A seeded relative perturbation of the carried state after every step (see the module).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StepPerturbation {
    /// `ε`: every carried value moves by a uniform relative amount in `±ε`.
    pub epsilon: f64,
    /// The seed of the stream of draws: the same seed gives the same run, bit for bit.
    pub seed: u64,
}

impl StepPerturbation {
    /// The stream of draws of one run, from its first step.
    pub fn stream(&self) -> StepNoise {
        StepNoise {
            epsilon: self.epsilon,
            rng: fastrand::Rng::with_seed(self.seed),
        }
    }
}

/// The draws of one run's [`StepPerturbation`], consumed step by step.
#[derive(Debug, Clone)]
pub struct StepNoise {
    epsilon: f64,
    rng: fastrand::Rng,
}

impl StepNoise {
    /// `x ← x + ε |x| ξ` for every value of `values`, `ξ` the stream's next draws in `[−1, 1]`
    /// (one per value, whatever it is). A zero shift leaves `x` as it is, the sign of a zero
    /// included (`−0 + 0` would be `+0`): with `ε = 0` the state keeps every bit.
    pub fn perturb(&mut self, values: &mut [f64]) {
        for x in values {
            let shift = self.epsilon * x.abs() * (2.0 * self.rng.f64() - 1.0);
            if shift != 0.0 {
                *x += shift;
            }
        }
    }
}
