//! Jacobi-preconditioned conjugate gradients for the step matrices of the 2D/3D boxes.
//!
//! At `Δx/Δt` fixed the step matrix `K = M/(bΔt²) + S` is mass-dominated: `Δt² S` and `M` scale
//! alike with `h`, so the condition number of `D^{-1/2} K D^{-1/2}` (`D = diag K`) is bounded
//! independently of the mesh and CG converges in a fixed number of iterations. Memory is the
//! matrix itself (no fill) and four work vectors.
//!
//! The algorithm (Saad, *Iterative Methods for Sparse Linear Systems*, Alg. 9.1), from the
//! initial guess `x₀`:
//! ```text
//! r₀ = b − K x₀,  z₀ = D⁻¹ r₀,  p₀ = z₀
//! α_k = r_kᵀz_k / p_kᵀK p_k,  x_{k+1} = x_k + α_k p_k,  r_{k+1} = r_k − α_k K p_k
//! z_{k+1} = D⁻¹ r_{k+1},  β_k = r_{k+1}ᵀz_{k+1} / r_kᵀz_k,  p_{k+1} = z_{k+1} + β_k p_k
//! ```
//! stopping when `‖r_k‖₂ ≤ tol ‖b‖₂` (relative to the right-hand side, not to `r₀`, so that a
//! good initial guess saves iterations instead of tightening the test).

use rayon::prelude::*;

use crate::engine::error::SolveError;
use crate::engine::fem::SymmetricMatrix;

/// The relative residual `‖b − Kx‖₂ / ‖b‖₂` at which [`Pcg`] stops by default. With it, the
/// energies, gaps and contact forces of 2D and 3D box runs agree with the direct solver's to
/// 9e-10 of each history's scale at every step; at 1e-12 the contact force differed by up to
/// 1e-8, so 1e-13 is the loosest power of ten with a tenfold margin under 1e-8
/// (`tests/unit/pcg.rs`). Each decade costs about three iterations at Δx/Δt = 2.
pub const DEFAULT_TOLERANCE: f64 = 1e-13;

/// The iteration limit: far above the few tens a bounded condition number needs, so reaching
/// it means the matrix is not what this solver is for.
const MAX_ITERATIONS: usize = 2000;

/// Rows per parallel task of the matrix-vector product. The partial sums are added in row order,
/// so the result does not depend on the number of threads.
const ROWS_PER_TASK: usize = 4096;

/// `K` in compressed rows with 32-bit column indices: 12 bytes per entry instead of the 16 of
/// faer's `usize` indices, which matters because the product is bound by memory bandwidth.
#[derive(Debug, Clone)]
struct Csr {
    row_ptr: Vec<usize>,
    col: Vec<u32>,
    val: Vec<f64>,
}

impl Csr {
    /// The rows of the symmetric `a` (its columns); `None` beyond 2³² unknowns.
    fn of(a: &SymmetricMatrix) -> Option<Self> {
        let inner = a.as_faer();
        let sym = inner.symbolic();
        let col = sym
            .row_idx()
            .iter()
            .map(|&i| u32::try_from(i).ok())
            .collect::<Option<Vec<u32>>>()?;
        Some(Self {
            row_ptr: sym.col_ptr().to_vec(),
            col,
            val: inner.val().to_vec(),
        })
    }

    /// `y = K x`, returning `xᵀ y`; rows in parallel blocks of [`ROWS_PER_TASK`].
    fn mul_dot(&self, x: &[f64], y: &mut [f64]) -> f64 {
        let partial: Vec<f64> = y
            .par_chunks_mut(ROWS_PER_TASK)
            .enumerate()
            .map(|(block, ys)| {
                let first = block * ROWS_PER_TASK;
                let mut xy = 0.0;
                for (k, yi) in ys.iter_mut().enumerate() {
                    let i = first + k;
                    let range = self.row_ptr[i]..self.row_ptr[i + 1];
                    *yi = self.col[range.clone()]
                        .iter()
                        .zip(&self.val[range])
                        .map(|(&j, &v)| v * x[j as usize])
                        .sum();
                    xy += x[i] * *yi;
                }
                xy
            })
            .collect();
        partial.iter().sum()
    }
}

/// A symmetric positive definite matrix prepared for Jacobi-preconditioned CG.
#[derive(Debug, Clone)]
pub struct Pcg {
    source: SymmetricMatrix,
    matrix: Csr,
    inverse_diagonal: Vec<f64>,
    tolerance: f64,
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

fn dot(x: &[f64], y: &[f64]) -> f64 {
    x.iter().zip(y).map(|(a, b)| a * b).sum()
}

impl Pcg {
    /// Prepares `a` with the relative residual `tolerance`; fails (naming `name`) when a
    /// diagonal entry is not positive, which no symmetric positive definite matrix has, or
    /// when `a` has 2³² unknowns or more.
    pub fn new(
        a: &SymmetricMatrix,
        tolerance: f64,
        name: &'static str,
    ) -> Result<Self, SolveError> {
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
        let matrix = Csr::of(a).ok_or_else(|| SolveError::Factorization {
            matrix: name,
            detail: format!("{} unknowns, more than 2³² − 1", a.dim()),
        })?;
        Ok(Self {
            source: a.clone(),
            matrix,
            inverse_diagonal,
            tolerance,
        })
    }

    /// The matrix `K`.
    pub fn matrix(&self) -> &SymmetricMatrix {
        &self.source
    }

    /// The dimension.
    pub fn dim(&self) -> usize {
        self.inverse_diagonal.len()
    }

    /// Solves `K x = b` from the initial guess in `x`, overwriting it with the solution, and
    /// returns the iterations spent (0 when the guess already satisfies the tolerance). Fails
    /// when the tolerance is not reached within the iteration limit.
    pub fn solve(&self, b: &[f64], x: &mut [f64], work: &mut PcgWork) -> Result<usize, SolveError> {
        let PcgWork { r, z, p, q } = work;
        let b_norm = dot(b, b).sqrt();
        let target = self.tolerance * b_norm;
        self.matrix.mul_dot(x, r);
        r.iter_mut().zip(b).for_each(|(ri, bi)| *ri = bi - *ri);
        let mut residual = dot(r, r).sqrt();
        if residual <= target {
            return Ok(0);
        }
        for ((zi, pi), (ri, di)) in z
            .iter_mut()
            .zip(p.iter_mut())
            .zip(r.iter().zip(&self.inverse_diagonal))
        {
            *zi = ri * di;
            *pi = *zi;
        }
        let mut rz = dot(r, z);
        for iteration in 1..=MAX_ITERATIONS {
            let alpha = rz / self.matrix.mul_dot(p, q);
            let mut rr = 0.0;
            for (((xi, ri), pi), qi) in x.iter_mut().zip(r.iter_mut()).zip(p.iter()).zip(q.iter()) {
                *xi += alpha * pi;
                *ri -= alpha * qi;
                rr += *ri * *ri;
            }
            residual = rr.sqrt();
            if residual <= target {
                return Ok(iteration);
            }
            let mut rz_next = 0.0;
            for ((zi, ri), di) in z.iter_mut().zip(r.iter()).zip(&self.inverse_diagonal) {
                *zi = ri * di;
                rz_next += *ri * *zi;
            }
            let beta = rz_next / rz;
            rz = rz_next;
            p.iter_mut()
                .zip(z.iter())
                .for_each(|(pi, zi)| *pi = zi + beta * *pi);
        }
        Err(SolveError::NotConverged {
            solver: "conjugate gradient",
            iterations: MAX_ITERATIONS,
            residual: residual / b_norm,
        })
    }
}
