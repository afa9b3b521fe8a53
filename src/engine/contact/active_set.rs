//! Primal–dual active set method (a semismooth Newton method on `min(μ, c (g + W μ)) = 0`).
//!
//! Active set `A = {i : μ_i − c_i (g + W μ)_i > 0}` with `c_i = 1 / W_ii` (scale invariant);
//! each iteration solves `W_AA μ_A = −g_A`, `μ_I = 0`. It stops when the set repeats.

use faer::linalg::solvers::Solve;
use faer::{Mat, Side};

use super::{ContactSolver, ContactStatus};

/// The active-set solver for many contact constraints.
#[derive(Debug, Clone)]
pub struct PrimalDualActiveSet {
    /// Iteration limit.
    pub max_iterations: usize,
    active: Vec<bool>,
}

impl Default for PrimalDualActiveSet {
    fn default() -> Self {
        Self {
            max_iterations: 200,
            active: Vec::new(),
        }
    }
}

impl ContactSolver for PrimalDualActiveSet {
    fn solve(&mut self, w: &[f64], g: &[f64], mu: &mut [f64]) -> ContactStatus {
        let n = g.len();
        self.active.clear();
        self.active.extend(g.iter().map(|&gi| gi < 0.0));
        for iteration in 1..=self.max_iterations {
            let idx: Vec<usize> = (0..n).filter(|&i| self.active[i]).collect();
            mu.iter_mut().for_each(|m| *m = 0.0);
            if !idx.is_empty() {
                let k = idx.len();
                let waa = Mat::from_fn(k, k, |a, b| w[idx[a] * n + idx[b]]);
                let rhs = Mat::from_fn(k, 1, |a, _| -g[idx[a]]);
                let sol = match waa.llt(Side::Lower) {
                    Ok(llt) => llt.solve(&rhs),
                    Err(_) => waa.partial_piv_lu().solve(&rhs),
                };
                for (a, &i) in idx.iter().enumerate() {
                    mu[i] = sol[(a, 0)];
                }
            }
            let mut changed = false;
            for i in 0..n {
                let wi: f64 = g[i] + (0..n).map(|j| w[i * n + j] * mu[j]).sum::<f64>();
                let now_active = mu[i] - wi / w[i * n + i] > 0.0;
                changed |= now_active != self.active[i];
                self.active[i] = now_active;
            }
            if !changed {
                return ContactStatus::Solved {
                    iterations: iteration,
                };
            }
        }
        ContactStatus::NotConverged {
            iterations: self.max_iterations,
        }
    }
}
