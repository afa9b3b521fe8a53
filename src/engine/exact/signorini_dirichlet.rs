//! The Signorini–Dirichlet benchmark (1D paper §5.1, Figures 5–6): `L = 1`, `u^0 = ½ − x/2`,
//! `v^0 = 0`, clamped at `x = 1`, obstacle at `x = 0`. Piecewise affine, periodic of period 3;
//! energy `1/8`.
//!
//! Each unit time interval (phase `k = ⌊t mod 3⌋`, local time `τ`) is split by the
//! characteristics `x = τ` and `x = 1 − τ` into the regions
//! I (`x ≥ τ`, `x + τ ≤ 1`), II (`x < τ`, `x + τ ≤ 1`), III (`x ≥ τ`, `x + τ > 1`),
//! IV (`x < τ`, `x + τ > 1`):
//!
//! | phase | I | II | III | IV |
//! |---|---|---|---|---|
//! | 0 (eq. 41) | `(1 − x)/2` | `(1 − τ)/2` | `(1 − x)/2` | `(1 − τ)/2` |
//! | 1 (eq. 42) | `−τ/2` | `−x/2` | `(x − 1)/2` | `(τ − 1)/2` |
//! | 2 | `τ/2` | `τ/2` | `(1 − x)/2` | `(1 − x)/2` |
//!
//! Eq. (42a) prints `−½(t_1 − t)` in region I; the solution is `−½(t − t_1)` (continuity with
//! region II across `x = τ` and the initial velocity `−½` at `t_1`; docs/src/errata.md).

use super::{ExactSolution, Pointwise};

/// The exact solution of §5.1.
#[derive(Debug, Clone, Copy, Default)]
pub struct SignoriniDirichlet;

impl SignoriniDirichlet {
    /// The period in time.
    pub const PERIOD: f64 = 3.0;

    /// The phase `k = ⌊t mod 3⌋ ∈ {0, 1, 2}` and the local time `τ ∈ [0, 1)`.
    fn phase(t: f64) -> (usize, f64) {
        let tp = t.rem_euclid(Self::PERIOD);
        let phase = (tp.floor() as usize).min(2);
        (phase, tp - phase as f64)
    }

    /// The table above: region from the characteristics through `x`, value from the phase.
    #[inline]
    fn eval_in_phase(phase: usize, tau: f64, x: f64) -> Pointwise {
        let left_of_wave = x < tau; // η = x − τ < 0
        let past_reflection = x + tau > 1.0; // ξ = x + τ > 1
        let (u, ux, ut) = match (phase, left_of_wave, past_reflection) {
            (0, false, _) => (0.5 - 0.5 * x, -0.5, 0.0),
            (0, true, _) => (0.5 - 0.5 * tau, 0.0, -0.5),
            (1, false, false) => (-0.5 * tau, 0.0, -0.5),
            (1, true, false) => (-0.5 * x, -0.5, 0.0),
            (1, false, true) => (0.5 * x - 0.5, 0.5, 0.0),
            (1, true, true) => (0.5 * tau - 0.5, 0.0, 0.5),
            (_, _, false) => (0.5 * tau, 0.0, 0.5),
            (_, _, true) => (0.5 - 0.5 * x, -0.5, 0.0),
        };
        Pointwise { u, ux, ut }
    }
}

impl ExactSolution for SignoriniDirichlet {
    fn name(&self) -> &'static str {
        "signorini-dirichlet"
    }

    fn eval(&self, x: f64, t: f64) -> Pointwise {
        let (phase, tau) = Self::phase(t);
        Self::eval_in_phase(phase, tau, x)
    }

    fn eval_many(&self, t: f64, xs: &[f64], out: &mut [Pointwise]) {
        let (phase, tau) = Self::phase(t);
        for (o, &x) in out.iter_mut().zip(xs) {
            *o = Self::eval_in_phase(phase, tau, x);
        }
    }

    fn contact_multiplier(&self, t: f64) -> f64 {
        let tp = t.rem_euclid(Self::PERIOD);
        if (1.0..2.0).contains(&tp) {
            -0.5
        } else {
            0.0
        }
    }

    fn energy(&self, _t: f64) -> f64 {
        0.125
    }

    fn breakpoints(&self, t: f64, out: &mut Vec<f64>) {
        let tau = t.rem_euclid(Self::PERIOD).fract();
        let (a, b) = if tau <= 0.5 {
            (tau, 1.0 - tau)
        } else {
            (1.0 - tau, tau)
        };
        for p in [a, b] {
            if p > 0.0 && p < 1.0 && out.last() != Some(&p) {
                out.push(p);
            }
        }
    }

    fn gauss_points(&self) -> usize {
        2
    }
}
