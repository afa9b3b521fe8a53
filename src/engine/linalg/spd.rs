//! One factorisation per run, one solve per step: a tridiagonal factorisation for 1D bars, from
//! both ends at once ([`TwistedTridiagonal`]; the Thomas algorithm was already about three times
//! faster than a general sparse Cholesky at the same size, DEPENDENCIES.md §1), and faer's sparse
//! Cholesky (AMD ordering) for everything else.

use faer::sparse::linalg::solvers::Llt;
use faer::Side;

use super::TwistedTridiagonal;
use crate::engine::error::SolveError;
use crate::engine::fem::SymmetricMatrix;

/// A factorised symmetric positive definite matrix.
#[derive(Debug)]
pub enum SpdSolver {
    /// Bandwidth one: the twisted factorisation.
    Tridiagonal(TwistedTridiagonal),
    /// General sparsity: faer's supernodal/simplicial Cholesky.
    Cholesky(Llt<usize, f64>),
}

impl SpdSolver {
    /// Factorises `a`; `name` says which matrix this is in the error message.
    pub fn factor(a: &SymmetricMatrix, name: &'static str) -> Result<Self, SolveError> {
        if a.bandwidth() <= 1 {
            let n = a.dim();
            let diag: Vec<f64> = (0..n).map(|i| a.get(i, i)).collect();
            let off: Vec<f64> = (1..n).map(|i| a.get(i, i - 1)).collect();
            TwistedTridiagonal::factor(&diag, &off)
                .map(SpdSolver::Tridiagonal)
                .map_err(|pivot| SolveError::Factorization {
                    matrix: name,
                    detail: format!("non-positive pivot at row {pivot}"),
                })
        } else {
            a.to_faer()
                .sp_cholesky(Side::Lower)
                .map(SpdSolver::Cholesky)
                .map_err(|e| SolveError::Factorization {
                    matrix: name,
                    detail: format!("{e:?}"),
                })
        }
    }

    /// Solves `A X = B` in place for the columns of `B`, stored one after the other, each of
    /// length `n` (several right-hand sides read the factor once).
    pub fn solve_columns_in_place(&self, b: &mut [f64], n: usize) {
        match self {
            SpdSolver::Tridiagonal(f) => b
                .chunks_exact_mut(n.max(1))
                .for_each(|c| f.solve_in_place(c)),
            SpdSolver::Cholesky(llt) => {
                use faer::linalg::solvers::SolveCore;
                let columns = b.len() / n.max(1);
                let mat = faer::MatMut::from_column_major_slice_mut(b, n, columns);
                llt.solve_in_place_with_conj(faer::Conj::No, mat);
            }
        }
    }

    /// Solves `A x = b` in place.
    pub fn solve_in_place(&self, b: &mut [f64]) {
        self.solve_columns_in_place(b, b.len());
    }
}
