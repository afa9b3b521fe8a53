//! The bar at rest touching the obstacle (grazing contact): `u ≡ 0`, `λ ≡ 0`, zero energy. Any
//! motion or contact force a scheme produces from these data is spurious.

use super::{ExactSolution, Pointwise};

/// `u ≡ 0`.
#[derive(Debug, Clone, Copy, Default)]
pub struct AtRest;

impl ExactSolution for AtRest {
    fn name(&self) -> &'static str {
        "at-rest"
    }

    fn eval(&self, _x: f64, _t: f64) -> Pointwise {
        Pointwise {
            u: 0.0,
            ux: 0.0,
            ut: 0.0,
        }
    }

    fn contact_multiplier(&self, _t: f64) -> f64 {
        0.0
    }

    fn energy(&self, _t: f64) -> f64 {
        0.0
    }

    fn breakpoints(&self, _t: f64, _out: &mut Vec<f64>) {}

    fn gauss_points(&self) -> usize {
        2
    }
}
