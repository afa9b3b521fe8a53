//! Preconditioned conjugate gradients for the step matrices of the 2D/3D boxes.
//!
//! At `Δx/Δt` fixed the step matrix `K = M/(bΔt²) + S` is mass-dominated: `Δt² S` and `M` scale
//! alike with `h`, so the condition number of `P^{-1/2} K P^{-1/2}` is bounded independently of
//! the mesh and CG converges in a fixed number of iterations. `P` is the product preconditioner
//! of the separable part a matrix-free box matrix carries
//! ([`ProductPreconditioner::of`]), with `M^mod`'s massless `Γ_Sig` plane condensed exactly
//! ([`CondensedPlane`]), and `D = diag K` (Jacobi) for any other matrix. Memory is
//! the matrix itself (no fill; nothing per entry when it is a
//! [`Stencil`](crate::engine::fem::stencil::Stencil)) and four work vectors.
//!
//! The algorithm (Saad, *Iterative Methods for Sparse Linear Systems*, Alg. 9.1), from the
//! initial guess `x₀`:
//! ```text
//! r₀ = b − K x₀,  z₀ = P⁻¹ r₀,  p₀ = z₀
//! α_k = r_kᵀz_k / p_kᵀK p_k,  x_{k+1} = x_k + α_k p_k,  r_{k+1} = r_k − α_k K p_k
//! z_{k+1} = P⁻¹ r_{k+1},  β_k = r_{k+1}ᵀz_{k+1} / r_kᵀz_k,  p_{k+1} = z_{k+1} + β_k p_k
//! ```
//! stopping when `‖r_k‖₂ ≤ tol ‖b‖₂` (relative to the right-hand side, not to `r₀`, so that a
//! good initial guess saves iterations instead of tightening the test) and the true residual
//! `‖b − K x_k‖₂` meets the same test ([`Pcg::solve`]: the recurrence's `r_k` can drift from
//! it by round-off, and a solve is never taken for one on the recurrence's word alone).

use super::{CondensedPlane, ProductPreconditioner};
use crate::engine::error::SolveError;
use crate::engine::fem::SymmetricMatrix;

/// The relative residual `‖b − Kx‖₂ / ‖b‖₂` at which [`Pcg`] stops by default. With it, the
/// energies, gaps and contact forces of 2D and 3D box runs agree with the direct solver's to
/// 9e-10 of each history's scale at every step; at 1e-12 the contact force differed by up to
/// 1e-8, so 1e-13 is the loosest power of ten with a tenfold margin under 1e-8
/// (`tests/unit/pcg.rs`).
pub const DEFAULT_TOLERANCE: f64 = 1e-13;

/// The iteration limit: far above the few tens a bounded condition number needs, so reaching
/// it means the matrix is not what this solver is for.
const MAX_ITERATIONS: usize = 2000;

/// How much a restart from the true residual ([`Pcg::solve`]) must reduce it to be followed by
/// another: a true residual that no longer halves is round-off the iteration cannot go below
/// (the matrix is too ill-conditioned for the tolerance), and the solve fails.
const RESTART_PROGRESS: f64 = 2.0;

/// A symmetric positive definite matrix prepared for preconditioned CG.
#[derive(Debug)]
pub struct Pcg {
    matrix: SymmetricMatrix,
    preconditioner: Preconditioner,
    tolerance: f64,
}

/// `P⁻¹` of the preconditioned iteration.
#[derive(Debug)]
enum Preconditioner {
    /// `D⁻¹`, `D = diag K`.
    Jacobi(Vec<f64>),
    /// The product preconditioner of the matrix's separable part
    /// ([`ProductPreconditioner::of`]).
    Product(ProductPreconditioner),
    /// The massless plane condensed, the product preconditioner on the interior
    /// ([`CondensedPlane`]).
    Condensed(Box<CondensedPlane>),
}

impl Preconditioner {
    /// `z = P⁻¹ r`, returning `rᵀz`.
    fn apply(&self, r: &[f64], z: &mut [f64]) -> f64 {
        match self {
            Preconditioner::Jacobi(inverse_diagonal) => return jacobi(inverse_diagonal, r, z),
            Preconditioner::Product(p) => p.solve_into(r, z),
            Preconditioner::Condensed(p) => p.solve_into(r, z),
        }
        dot(r, z)
    }
}

/// The work vectors of one solve (`r`, `z`, `p`, `K p`), reusable across solves of one size.
#[derive(Debug, Clone)]
pub struct PcgWork {
    r: Vec<f64>,
    z: Vec<f64>,
    p: Vec<f64>,
    q: Vec<f64>,
}

impl PcgWork {
    /// Work vectors for systems of dimension `n`.
    pub fn new(n: usize) -> Self {
        Self {
            r: vec![0.0; n],
            z: vec![0.0; n],
            p: vec![0.0; n],
            q: vec![0.0; n],
        }
    }
}

/// `z = D⁻¹ r` (Jacobi's preconditioner, `D = diag K`, given as `D⁻¹`), returning `rᵀz`.
pub fn jacobi(inverse_diagonal: &[f64], r: &[f64], z: &mut [f64]) -> f64 {
    let mut rz = 0.0;
    for ((zi, ri), di) in z.iter_mut().zip(r).zip(inverse_diagonal) {
        *zi = ri * di;
        rz += ri * *zi;
    }
    rz
}

/// `xᵀy`, summed in order.
pub fn dot(x: &[f64], y: &[f64]) -> f64 {
    x.iter().zip(y).map(|(a, b)| a * b).sum()
}

impl Pcg {
    /// Prepares `a` with the relative residual `tolerance`; fails (naming `name`) when a
    /// diagonal entry is not positive, which no symmetric positive definite matrix has.
    pub fn new(a: SymmetricMatrix, tolerance: f64, name: &'static str) -> Result<Self, SolveError> {
        let inverse_diagonal = (0..a.dim())
            .map(|i| {
                let d = a.get(i, i);
                if d > 0.0 && d.is_finite() {
                    Ok(1.0 / d)
                } else {
                    Err(SolveError::Factorization {
                        matrix: name,
                        detail: format!("diagonal entry {i} is {d:e}, not > 0"),
                    })
                }
            })
            .collect::<Result<Vec<f64>, SolveError>>()?;
        let preconditioner = match a.separable_part() {
            Some(part) if CondensedPlane::applies_to(part) => {
                CondensedPlane::of(&a, part).map(|c| Preconditioner::Condensed(Box::new(c)))
            }
            Some(part) => ProductPreconditioner::of(part)
                .filter(|p| p.dim() == a.dim())
                .map(Preconditioner::Product),
            None => None,
        }
        .unwrap_or(Preconditioner::Jacobi(inverse_diagonal));
        Ok(Self {
            matrix: a,
            preconditioner,
            tolerance,
        })
    }

    /// The matrix `K`.
    pub fn matrix(&self) -> &SymmetricMatrix {
        &self.matrix
    }

    /// The dimension.
    pub fn dim(&self) -> usize {
        self.matrix.dim()
    }

    /// Solves `K x = b` from the initial guess in `x`, overwriting it with the solution, and
    /// returns the iterations spent (0 when the guess already satisfies the tolerance): the
    /// iteration of [`conjugate_gradient`] on the whole vectors of one process.
    pub fn solve(&self, b: &[f64], x: &mut [f64], work: &mut PcgWork) -> Result<usize, SolveError> {
        conjugate_gradient(self, self.tolerance, b, x, work)
    }
}

impl CgSpace for Pcg {
    fn mul_dot(&self, x: &[f64], y: &mut [f64]) -> f64 {
        self.matrix.mul_dot(x, y)
    }

    fn precondition(&self, r: &[f64], z: &mut [f64]) -> f64 {
        self.preconditioner.apply(r, z)
    }

    fn sum(&self, part: f64) -> f64 {
        part
    }
}

/// What the conjugate-gradient iteration needs of the space its vectors live in: the products
/// with `K` and `P⁻¹` on this process's part of the vectors, each returning its part of an
/// inner product, and the sum of such parts over the processes that hold the rest (none in
/// one process; the ranks of a distributed run, [`crate::engine::distributed`]). Every
/// decision of the iteration is taken on summed values, so every process takes the same.
pub trait CgSpace {
    /// `y = K x` on this part, returning this part of `xᵀ y`.
    fn mul_dot(&self, x: &[f64], y: &mut [f64]) -> f64;
    /// `z = P⁻¹ r` on this part, returning this part of `rᵀ z`.
    fn precondition(&self, r: &[f64], z: &mut [f64]) -> f64;
    /// The sum of every process's `part`, the same on each.
    fn sum(&self, part: f64) -> f64;
}

/// Solves `K x = b` in `space` from the initial guess in `x` to the relative residual
/// `tolerance`, overwriting `x` with the solution, and returns the iterations spent (0 when the
/// guess already satisfies the tolerance).
///
/// The iteration's residual `r_k` is updated by recurrence, which drifts from the true
/// residual `b − K x_k` by round-off (much more so on an ill-conditioned `K`). So when `r_k`
/// meets the tolerance the true residual is computed, and the solve ends only when it meets
/// the tolerance too; otherwise the iteration restarts from `x_k` with the true residual
/// (residual replacement, van der Vorst and Ye, SIAM J. Sci. Comput. 22, 2000) for as long
/// as each restart reduces it by [`RESTART_PROGRESS`]. Fails, with the true relative
/// residual reached, when the tolerance is not met within the iteration limit or the
/// restarts stagnate: the caller must not take `x` for a solution.
pub fn conjugate_gradient(
    space: &impl CgSpace,
    tolerance: f64,
    b: &[f64],
    x: &mut [f64],
    work: &mut PcgWork,
) -> Result<usize, SolveError> {
    let PcgWork { r, z, p, q } = work;
    let b_norm = space.sum(dot(b, b)).sqrt();
    let target = tolerance * b_norm;
    let true_residual = |x: &[f64], r: &mut [f64]| {
        space.mul_dot(x, r);
        r.iter_mut().zip(b).for_each(|(ri, bi)| *ri = bi - *ri);
        space.sum(dot(r, r)).sqrt()
    };
    let mut residual = true_residual(x, r);
    let mut iteration = 0;
    loop {
        if residual <= target {
            return Ok(iteration);
        }
        let restarted_from = residual;
        let mut rz = space.sum(space.precondition(r, z));
        p.copy_from_slice(z);
        while iteration < MAX_ITERATIONS {
            iteration += 1;
            let alpha = rz / space.sum(space.mul_dot(p, q));
            let mut rr = 0.0;
            for (((xi, ri), pi), qi) in x.iter_mut().zip(r.iter_mut()).zip(p.iter()).zip(q.iter()) {
                *xi += alpha * pi;
                *ri -= alpha * qi;
                rr += *ri * *ri;
            }
            let rr = space.sum(rr);
            if rr.sqrt() <= target || !rr.is_finite() {
                break;
            }
            let rz_next = space.sum(space.precondition(r, z));
            let beta = rz_next / rz;
            rz = rz_next;
            p.iter_mut()
                .zip(z.iter())
                .for_each(|(pi, zi)| *pi = zi + beta * *pi);
        }
        residual = true_residual(x, r);
        let progressed = residual * RESTART_PROGRESS <= restarted_from;
        if residual <= target {
            return Ok(iteration);
        }
        if iteration >= MAX_ITERATIONS || !progressed {
            break;
        }
    }
    Err(SolveError::NotConverged {
        solver: "conjugate gradient",
        iterations: iteration,
        residual: residual / b_norm,
    })
}
