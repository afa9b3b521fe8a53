//! A smooth solution without obstacle: the first mode of the bar free at `x = 0` and clamped at
//! `x = 1`, `u = cos(πx/2) cos(πt/2)` (`L = 1`, `c = 1`), energy `π²/16`. It lets the harness
//! verify second-order convergence where no contact degrades the rate.

use std::f64::consts::FRAC_PI_2;

use super::{ExactSolution, Pointwise};

/// `u = cos(πx/2) cos(πt/2)`.
#[derive(Debug, Clone, Copy, Default)]
pub struct ClampedFreeMode;

impl ExactSolution for ClampedFreeMode {
    fn name(&self) -> &'static str {
        "clamped-free-mode"
    }

    fn eval(&self, x: f64, t: f64) -> Pointwise {
        let (sx, cx) = (FRAC_PI_2 * x).sin_cos();
        let (st, ct) = (FRAC_PI_2 * t).sin_cos();
        Pointwise {
            u: cx * ct,
            ux: -FRAC_PI_2 * sx * ct,
            ut: -FRAC_PI_2 * cx * st,
        }
    }

    fn contact_multiplier(&self, _t: f64) -> f64 {
        0.0
    }

    fn energy(&self, _t: f64) -> f64 {
        FRAC_PI_2 * FRAC_PI_2 / 4.0
    }

    fn breakpoints(&self, _t: f64, _out: &mut Vec<f64>) {}

    fn gauss_points(&self) -> usize {
        4
    }
}
