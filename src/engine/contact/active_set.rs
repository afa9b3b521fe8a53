//! Primal–dual active set method (a semismooth Newton method on `min(μ, c (g + W μ)) = 0`).
//!
//! Active set `A = {i : μ_i − c_i (g + W μ)_i > 0}` with `c_i = 1 / W_ii` (scale invariant);
//! each iteration solves `W_AA μ_A = −g_A`, `μ_I = 0`. It stops when the set repeats.
//!
//! The iteration is guaranteed to end for an M-matrix `W` (Hintermüller, Ito and Kunisch, SIAM
//! J. Optim. 13, 2002); a Delassus operator `B M⁻¹ Bᵀ` of a consistent mass in 2D or 3D need not
//! be one, and there the sets can cycle. When an earlier set comes back, its `μ` is kept if it
//! solves the problem to round-off (a degenerate problem, with a constraint where both `μ_i`
//! and `(g + W μ)_i` vanish, cycles among sets of one solution); otherwise (or at the iteration
//! limit) the solver restarts from the active set of the interior-point solution of the same
//! problem ([`super::ClarabelContact`]), and keeps that solution itself if the restart cycles
//! too. Where the plain iteration ends, nothing of this runs, and its result is unchanged.

use faer::linalg::solvers::Solve;
use faer::{Mat, Side};

use super::{ClarabelContact, ContactSolver, ContactStatus};

/// The active-set solver for many contact constraints.
#[derive(Debug, Clone)]
pub struct PrimalDualActiveSet {
    /// Iteration limit of each of the (at most two) runs of the iteration.
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

impl PrimalDualActiveSet {
    /// The iteration from the active set `self.active`: `Ok(iterations)` when a set repeats at
    /// once (`mu` is then the solution), `Err(iterations)` when an earlier set comes back or
    /// the limit is reached.
    fn iterate(&mut self, w: &[f64], g: &[f64], mu: &mut [f64]) -> Result<usize, usize> {
        let n = g.len();
        let mut seen: Vec<Vec<bool>> = Vec::new();
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
            seen.push(self.active.clone());
            self.update_active(w, g, mu);
            if seen.last() == Some(&self.active) {
                return Ok(iteration);
            }
            if seen.contains(&self.active) {
                return if solves(w, g, mu) {
                    mu.iter_mut().for_each(|m| *m = m.max(0.0));
                    Ok(iteration)
                } else {
                    Err(iteration)
                };
            }
        }
        Err(self.max_iterations)
    }

    /// `self.active` from `mu` by the rule `μ_i − (g + W μ)_i / W_ii > 0`.
    fn update_active(&mut self, w: &[f64], g: &[f64], mu: &[f64]) {
        let n = g.len();
        for i in 0..n {
            let wi: f64 = g[i] + (0..n).map(|j| w[i * n + j] * mu[j]).sum::<f64>();
            self.active[i] = mu[i] - wi / w[i * n + i] > 0.0;
        }
    }
}

/// Whether `mu` solves `0 ≤ μ ⟂ g + W μ ≥ 0` to round-off: no `μ_i` below `−10⁻¹² max |μ|` and
/// no `(g + W μ)_i` below `−10⁻¹²` of the size of `g` and `W μ` (the iteration makes `μ_i = 0`
/// off the set and `(g + W μ)_i = 0` on it exactly, up to its solve's round-off).
fn solves(w: &[f64], g: &[f64], mu: &[f64]) -> bool {
    let n = g.len();
    let wmu: Vec<f64> = (0..n)
        .map(|i| (0..n).map(|j| w[i * n + j] * mu[j]).sum::<f64>())
        .collect();
    let largest = |v: &mut dyn Iterator<Item = f64>| v.fold(0.0_f64, |m, x| m.max(x.abs()));
    let mu_scale = largest(&mut mu.iter().copied());
    let w_scale = largest(&mut g.iter().chain(&wmu).copied());
    (0..n).all(|i| mu[i] >= -1e-12 * mu_scale && g[i] + wmu[i] >= -1e-12 * w_scale)
}

impl ContactSolver for PrimalDualActiveSet {
    fn solve(&mut self, w: &[f64], g: &[f64], mu: &mut [f64]) -> ContactStatus {
        self.active.clear();
        self.active.extend(g.iter().map(|&gi| gi < 0.0));
        let spent = match self.iterate(w, g, mu) {
            Ok(iterations) => return ContactStatus::Solved { iterations },
            Err(spent) => spent,
        };
        let interior = match ClarabelContact::default().solve(w, g, mu) {
            ContactStatus::Solved { iterations } => iterations,
            ContactStatus::NotConverged { iterations } => {
                return ContactStatus::NotConverged {
                    iterations: spent + iterations,
                }
            }
        };
        let solution = mu.to_vec();
        self.update_active(w, g, &solution);
        let restarted = match self.iterate(w, g, mu) {
            Ok(iterations) => iterations,
            Err(iterations) => {
                mu.copy_from_slice(&solution);
                iterations
            }
        };
        ContactStatus::Solved {
            iterations: spent + interior + restarted,
        }
    }
}
