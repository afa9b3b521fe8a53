//! The stability bound of explicit Newmark (β = 0).
//!
//! Newmark(0, γ), γ ≥ ½, is stable on `M Ü + S U = F` iff `Δt ω_max ≤ √(2/γ)` (`= 2` for central
//! differences), `ω_max²` the largest eigenvalue of `S x = ω² M x` (Hughes, *The Finite Element
//! Method*, §9.1.4: `Ω_crit = (γ/2 − β)^{−1/2}`). With massless dofs `Z` the dynamics live on the
//! dofs with mass `R`; the massless ones are condensed statically, or held by the obstacle. Both
//! give a stiffness `⪯ S_RR` on `R` (a Schur complement `S_RR − S_RZ S_ZZ⁻¹ S_ZR` only lowers
//! it), so the bound uses `ω_max² = λ_max(S_RR, M_RR)`, valid in every contact state.
//!
//! `λ_max` comes from the Lanczos method in the `M_RR` inner product with full
//! reorthogonalisation, from a pseudo-random start vector with a fixed seed (deterministic),
//! run until the top Ritz pair `(θ, x)` has a residual `r = ‖S x − θ M x‖_{M⁻¹} ≤ 10⁻⁸ θ` (or
//! the Krylov space is exhausted). The value returned is `θ + r`: some eigenvalue lies within
//! `r` of `θ` (the residual bound for a symmetric pencil), and it is the largest one as long as
//! the start vector has a component along its eigenvector, which a random vector has with
//! probability one. `tests/explicit.rs` compares it with a dense eigensolver for every mass.

use crate::engine::error::SolveError;
use crate::engine::fem::SymmetricMatrix;
use crate::engine::linalg::SpdSolver;

/// Relative residual at which the top Ritz value is accepted.
const RELATIVE_RESIDUAL: f64 = 1e-8;

/// An upper bound of the largest eigenvalue of `s x = λ m x`, `m` symmetric positive definite.
pub fn largest_eigenvalue(s: &SymmetricMatrix, m: &SymmetricMatrix) -> Result<f64, SolveError> {
    let n = s.dim();
    if n == 0 {
        return Ok(0.0);
    }
    let m_solver = SpdSolver::factor(m, "mass (dofs with inertia)")?;
    // A pseudo-random start vector with a fixed seed: every eigenvector has a component of
    // order 1/√n in it. (A smooth start, dominated by the low modes, can leave the top mode of a
    // free bar, the alternating one, out of reach: Lanczos then converges to the second.)
    let mut rng = fastrand::Rng::with_seed(0x5EED);
    let mut q: Vec<f64> = (0..n).map(|_| rng.f64() - 0.5).collect();
    let norm = m.quadratic_form(&q).sqrt();
    q.iter_mut().for_each(|x| *x /= norm);
    let mut basis: Vec<Vec<f64>> = Vec::new();
    let mut m_basis: Vec<Vec<f64>> = Vec::new();
    let (mut alpha, mut beta) = (Vec::new(), Vec::new());
    let mut w = vec![0.0; n];
    let mut mq = vec![0.0; n];
    loop {
        m.mul_into(&q, &mut mq);
        s.mul_into(&q, &mut w);
        let a: f64 = w.iter().zip(&q).map(|(x, y)| x * y).sum();
        m_solver.solve_in_place(&mut w);
        basis.push(q.clone());
        m_basis.push(mq.clone());
        alpha.push(a);
        // Full reorthogonalisation in the M inner product (twice is enough).
        for _ in 0..2 {
            for (v, mv) in basis.iter().zip(&m_basis) {
                let c: f64 = w.iter().zip(mv).map(|(x, y)| x * y).sum();
                w.iter_mut().zip(v).for_each(|(x, y)| *x -= c * y);
            }
        }
        let b = m.quadratic_form(&w).max(0.0).sqrt();
        let k = alpha.len();
        let (theta, last) = top_ritz(&alpha, &beta);
        let residual = b * last.abs();
        if residual <= RELATIVE_RESIDUAL * theta.abs() || k == n || b <= f64::EPSILON * theta {
            return Ok(theta + residual);
        }
        beta.push(b);
        q.iter_mut().zip(&w).for_each(|(x, y)| *x = y / b);
    }
}

/// The largest eigenvalue `θ` of the Lanczos tridiagonal `T_k` (diagonal `alpha`, off-diagonal
/// `beta`) by Sturm-sequence bisection, and the last component of its unit eigenvector by two
/// steps of inverse iteration.
fn top_ritz(alpha: &[f64], beta: &[f64]) -> (f64, f64) {
    let k = alpha.len();
    // Gershgorin interval of T_k.
    let radius = |i: usize| {
        (if i > 0 { beta[i - 1].abs() } else { 0.0 })
            + (if i + 1 < k { beta[i].abs() } else { 0.0 })
    };
    let mut lo = (0..k)
        .map(|i| alpha[i] - radius(i))
        .fold(f64::INFINITY, f64::min);
    let mut hi = (0..k)
        .map(|i| alpha[i] + radius(i))
        .fold(f64::NEG_INFINITY, f64::max);
    // Number of eigenvalues of T_k greater than x (sign changes of the LDLᵀ pivots of T − x).
    let above = |x: f64| {
        let mut d = 1.0;
        let mut count = 0;
        for i in 0..k {
            let b2 = if i > 0 {
                beta[i - 1] * beta[i - 1]
            } else {
                0.0
            };
            d = alpha[i] - x - if i > 0 { b2 / d } else { 0.0 };
            if d == 0.0 {
                d = -f64::EPSILON * (x.abs() + 1.0);
            }
            if d > 0.0 {
                count += 1;
            }
        }
        count
    };
    while hi - lo > 4.0 * f64::EPSILON * hi.abs().max(lo.abs()) {
        let mid = 0.5 * (lo + hi);
        if mid <= lo || mid >= hi {
            break;
        }
        if above(mid) >= 1 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let theta = hi;
    // Inverse iteration with (T − σ I), σ just above θ: a tridiagonal solve per sweep.
    let sigma = theta + 1e3 * f64::EPSILON * theta.abs().max(1.0);
    let mut x = vec![1.0; k];
    for _ in 0..3 {
        solve_shifted(alpha, beta, sigma, &mut x);
        let norm = x.iter().map(|v| v * v).sum::<f64>().sqrt();
        x.iter_mut().for_each(|v| *v /= norm);
    }
    (theta, x[k - 1])
}

/// Solves `(T − σ I) y = x` in place (Gaussian elimination without pivoting; `T − σ I` is
/// negative definite for `σ > λ_max(T)`).
fn solve_shifted(alpha: &[f64], beta: &[f64], sigma: f64, x: &mut [f64]) {
    let k = alpha.len();
    let mut d = vec![0.0; k];
    d[0] = alpha[0] - sigma;
    for i in 1..k {
        let l = beta[i - 1] / d[i - 1];
        d[i] = alpha[i] - sigma - l * beta[i - 1];
        x[i] -= l * x[i - 1];
    }
    x[k - 1] /= d[k - 1];
    for i in (0..k - 1).rev() {
        x[i] = (x[i] - beta[i] * x[i + 1]) / d[i];
    }
}

/// The largest stable `Δt` of Newmark(0, γ) for `ω_max² = omega2`: `√(2/γ) / ω_max`.
pub fn stable_step(omega2: f64, gamma: f64) -> f64 {
    (2.0 / gamma).sqrt() / omega2.sqrt()
}
