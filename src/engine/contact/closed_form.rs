//! One contact constraint: `μ = max(0, −g / W)`.

use super::{ContactSolver, ContactStatus};

/// The scalar complementarity problem in closed form (the 1D bar's single contact node).
#[derive(Debug, Clone, Copy, Default)]
pub struct ClosedFormContact;

impl ContactSolver for ClosedFormContact {
    fn solve(&mut self, w: &[f64], g: &[f64], mu: &mut [f64]) -> ContactStatus {
        assert_eq!(g.len(), 1, "the closed form handles exactly one constraint");
        mu[0] = (-g[0] / w[0]).max(0.0);
        ContactStatus::Solved { iterations: 1 }
    }
}
