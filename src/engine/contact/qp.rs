//! The complementarity problem as a convex quadratic program, solved by clarabel's
//! interior-point method: the independent check of the active-set solver.
//!
//! `0 ≤ μ ⟂ g + W μ ≥ 0` with `W` symmetric positive definite is the KKT system of
//! `min ½ μᵀ W μ + gᵀ μ` subject to `μ ≥ 0` (clarabel form: `A μ + s = b`, `A = −I`, `b = 0`,
//! `s ∈ ℝⁿ₊`; its dual `z = g + W μ`).

use clarabel::algebra::CscMatrix;
use clarabel::solver::{DefaultSettings, DefaultSolver, IPSolver, NonnegativeConeT, SolverStatus};

use super::{ContactSolver, ContactStatus};

/// Clarabel on the contact QP.
#[derive(Debug, Clone, Copy)]
pub struct ClarabelContact {
    /// Absolute and relative gap and feasibility tolerance of the interior-point method.
    pub tolerance: f64,
}

impl Default for ClarabelContact {
    /// Tolerance 1e-12: tight enough to agree with the active-set solution to 1e-8.
    fn default() -> Self {
        Self { tolerance: 1e-12 }
    }
}

impl ContactSolver for ClarabelContact {
    fn solve(&mut self, w: &[f64], g: &[f64], mu: &mut [f64]) -> ContactStatus {
        let n = g.len();
        // The problem is homogeneous in (μ, g): solve it for g / s with s = max |g_i| so that
        // the interior-point tolerances are relative to the data (at a first touch g ~ 1e-9).
        let scale = g.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
        if scale == 0.0 {
            mu.iter_mut().for_each(|m| *m = 0.0);
            return ContactStatus::Solved { iterations: 0 };
        }
        let q: Vec<f64> = g.iter().map(|x| x / scale).collect();
        let (mut rows, mut cols, mut vals) = (Vec::new(), Vec::new(), Vec::new());
        for j in 0..n {
            for i in 0..=j {
                let v = w[i * n + j];
                if v != 0.0 {
                    rows.push(i);
                    cols.push(j);
                    vals.push(v);
                }
            }
        }
        let p = CscMatrix::new_from_triplets(n, n, rows, cols, vals);
        let a =
            CscMatrix::new_from_triplets(n, n, (0..n).collect(), (0..n).collect(), vec![-1.0; n]);
        let settings = DefaultSettings {
            verbose: false,
            tol_gap_abs: self.tolerance,
            tol_gap_rel: self.tolerance,
            tol_feas: self.tolerance,
            presolve_enable: false,
            ..DefaultSettings::default()
        };
        let cones = [NonnegativeConeT(n)];
        let Ok(mut solver) = DefaultSolver::new(&p, &q, &a, &vec![0.0; n], &cones, settings) else {
            return ContactStatus::NotConverged { iterations: 0 };
        };
        solver.solve();
        let iterations = solver.solution.iterations as usize;
        match solver.solution.status {
            SolverStatus::Solved | SolverStatus::AlmostSolved => {
                for (m, x) in mu.iter_mut().zip(&solver.solution.x) {
                    *m = scale * x.max(0.0);
                }
                ContactStatus::Solved { iterations }
            }
            _ => ContactStatus::NotConverged { iterations },
        }
    }
}
