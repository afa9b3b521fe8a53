//! Cholesky factorisation `A = L Lᵀ` of a symmetric positive definite band matrix, in band
//! storage (no fill outside the band), for the small systems solved at every CG iteration: the
//! massless plane of [`super::CondensedPlane`], 243 unknowns of half-bandwidth about 30 at 3D
//! level 80, where a general sparse solve spends more in its bookkeeping than in arithmetic.

use crate::engine::fem::SymmetricMatrix;

/// `A = L Lᵀ` with `L` lower triangular of half-bandwidth `width`: row `i` of `L` holds
/// `L[i, i − width ..= i]` at `rows[i·(width + 1) ..][.. width + 1]` (entries before column 0
/// are zero), and `1 / L[i, i]` is kept apart so that a solve has no division.
#[derive(Debug, Clone)]
pub struct BandCholesky {
    width: usize,
    rows: Vec<f64>,
    inverse_diagonal: Vec<f64>,
}

impl BandCholesky {
    /// The half-bandwidth of `a`: the largest `i − j` of an entry `a_ij ≠ 0`.
    pub fn width_of(a: &SymmetricMatrix) -> usize {
        let mut width = 0;
        for i in 0..a.dim() {
            a.for_each_in_row(i, |j, v| {
                if j < i && v != 0.0 {
                    width = width.max(i - j);
                }
            });
        }
        width
    }

    /// Factorises `a` in a band of half-bandwidth `width` (at least [`BandCholesky::width_of`]
    /// `a`); `None` when a pivot is not positive.
    pub fn factor(a: &SymmetricMatrix, width: usize) -> Option<Self> {
        let n = a.dim();
        let stride = width + 1;
        let mut rows = vec![0.0; n * stride];
        for i in 0..n {
            a.for_each_in_row(i, |j, v| {
                if j <= i && i - j <= width {
                    rows[i * stride + width + j - i] = v;
                }
            });
        }
        let mut inverse_diagonal = vec![0.0; n];
        for i in 0..n {
            let first = i.saturating_sub(width);
            for j in first..=i {
                // L[i, j] = (A[i, j] − Σ_{k < j} L[i, k] L[j, k]) / L[j, j], k within both bands.
                let from = first.max(j.saturating_sub(width));
                let row_i = &rows[i * stride + width + from - i..i * stride + width + j - i];
                let row_j = &rows[j * stride + width + from - j..j * stride + width];
                let sum = dot(row_i, row_j);
                let entry = rows[i * stride + width + j - i] - sum;
                if j < i {
                    rows[i * stride + width + j - i] = entry * inverse_diagonal[j];
                } else {
                    if !(entry > 0.0 && entry.is_finite()) {
                        return None;
                    }
                    let pivot = entry.sqrt();
                    rows[i * stride + width] = pivot;
                    inverse_diagonal[i] = 1.0 / pivot;
                }
            }
        }
        Some(Self {
            width,
            rows,
            inverse_diagonal,
        })
    }

    /// Solves `A x = b` in place: `L y = b` row by row, then `Lᵀ x = y` from the last row up,
    /// each row of `L` read contiguously.
    pub fn solve_in_place(&self, b: &mut [f64]) {
        let (width, stride) = (self.width, self.width + 1);
        for i in 0..b.len() {
            let first = i.saturating_sub(width);
            let row = &self.rows[i * stride + width + first - i..i * stride + width];
            let sum = dot(row, &b[first..i]);
            b[i] = (b[i] - sum) * self.inverse_diagonal[i];
        }
        for i in (0..b.len()).rev() {
            let xi = b[i] * self.inverse_diagonal[i];
            b[i] = xi;
            let first = i.saturating_sub(width);
            let row = &self.rows[i * stride + width + first - i..i * stride + width];
            b[first..i]
                .iter_mut()
                .zip(row)
                .for_each(|(y, l)| *y -= l * xi);
        }
    }
}

/// `xᵀy` in four interleaved partial sums (independent additions, unlike a sum in order).
fn dot(x: &[f64], y: &[f64]) -> f64 {
    let mut sums = [0.0; 4];
    let (xs, ys) = (x.chunks_exact(4), y.chunks_exact(4));
    let tail: f64 = (xs.remainder().iter().zip(ys.remainder()))
        .map(|(a, b)| a * b)
        .sum();
    for (a, b) in xs.zip(ys) {
        for ((s, a), b) in sums.iter_mut().zip(a).zip(b) {
            *s += a * b;
        }
    }
    (sums[0] + sums[1]) + (sums[2] + sums[3]) + tail
}

#[cfg(test)]
mod tests {
    use super::BandCholesky;
    use crate::engine::fem::SymmetricMatrix;
    use crate::engine::linalg::SpdSolver;

    /// A random band matrix of half-bandwidth `width`, strictly diagonally dominant (SPD).
    fn random_band(n: usize, width: usize, rng: &mut fastrand::Rng) -> SymmetricMatrix {
        let mut upper = Vec::new();
        for j in 0..n {
            upper.push((j * n + j, 2.0 * width as f64 + 1.0 + rng.f64()));
            for i in j.saturating_sub(width)..j {
                if rng.bool() {
                    upper.push((j * n + i, 2.0 * rng.f64() - 1.0));
                }
            }
        }
        SymmetricMatrix::from_upper_contributions(n, upper)
    }

    #[test]
    fn band_cholesky_matches_the_sparse_cholesky() {
        let mut rng = fastrand::Rng::with_seed(54);
        for (n, width) in [(1, 0), (7, 1), (243, 30), (100, 99)] {
            let a = random_band(n, width, &mut rng);
            assert!(BandCholesky::width_of(&a) <= width);
            let b: Vec<f64> = (0..n).map(|_| rng.f64() - 0.5).collect();
            let mut sparse = b.clone();
            SpdSolver::factor(&a, "band")
                .unwrap()
                .solve_in_place(&mut sparse);
            let mut band = b.clone();
            BandCholesky::factor(&a, BandCholesky::width_of(&a))
                .unwrap()
                .solve_in_place(&mut band);
            let scale = sparse.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
            for (p, q) in band.iter().zip(&sparse) {
                assert!(
                    (p - q).abs() <= 1e-13 * scale,
                    "n {n}, width {width}: {p} against {q}"
                );
            }
        }
    }

    #[test]
    fn band_cholesky_refuses_an_indefinite_matrix() {
        let a = SymmetricMatrix::from_upper_contributions(2, vec![(0, 1.0), (2, 2.0), (3, 1.0)]);
        assert!(BandCholesky::factor(&a, 1).is_none());
    }
}
