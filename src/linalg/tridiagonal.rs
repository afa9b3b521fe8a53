//! LDLᵀ factorisation of a symmetric positive definite tridiagonal matrix (Thomas algorithm,
//! factored once, solved many times).

/// `A = L D Lᵀ` with `L` unit lower bidiagonal; `lower[i]` is `L[i, i-1]` (`lower[0]` unused).
#[derive(Debug, Clone)]
pub struct TridiagonalLdlt {
    diag: Vec<f64>,
    lower: Vec<f64>,
}

impl TridiagonalLdlt {
    /// Factorises the matrix with diagonal `diag` and off-diagonal `off[i] = A[i+1, i]`.
    /// Returns the index of the first non-positive pivot on failure.
    pub fn factor(diag: &[f64], off: &[f64]) -> Result<Self, usize> {
        let n = diag.len();
        debug_assert_eq!(off.len() + 1, n.max(1));
        let mut d = vec![0.0; n];
        let mut l = vec![0.0; n];
        for i in 0..n {
            let mut di = diag[i];
            if i > 0 {
                l[i] = off[i - 1] / d[i - 1];
                di -= l[i] * off[i - 1];
            }
            if !(di > 0.0 && di.is_finite()) {
                return Err(i);
            }
            d[i] = di;
        }
        Ok(Self { diag: d, lower: l })
    }

    /// Solves `A x = b` in place (`b` is overwritten by `x`).
    pub fn solve_in_place(&self, b: &mut [f64]) {
        let n = b.len();
        for i in 1..n {
            b[i] -= self.lower[i] * b[i - 1];
        }
        b.iter_mut().zip(&self.diag).for_each(|(x, d)| *x /= d);
        for i in (0..n.saturating_sub(1)).rev() {
            b[i] -= self.lower[i + 1] * b[i + 1];
        }
    }
}
