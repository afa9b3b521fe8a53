//! LDLᵀ factorisation of a symmetric positive definite tridiagonal matrix (Thomas algorithm,
//! factored once, solved many times).

/// `A = L D Lᵀ` with `L` unit lower bidiagonal; `lower[i]` is `L[i, i-1]` (`lower[0]` unused);
/// `D` is kept as its reciprocal so that a solve has no division.
#[derive(Debug, Clone)]
pub struct TridiagonalLdlt {
    inv_diag: Vec<f64>,
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
        Ok(Self {
            inv_diag: d.iter().map(|di| 1.0 / di).collect(),
            lower: l,
        })
    }

    /// Solves `A x = b` in place (`b` is overwritten by `x`): `L y = b`, then
    /// `Lᵀ x = D⁻¹ y`, two sweeps.
    pub fn solve_in_place(&self, b: &mut [f64]) {
        let n = b.len();
        if n == 0 {
            return;
        }
        let mut prev = b[0];
        for (bi, li) in b.iter_mut().zip(&self.lower).skip(1) {
            *bi -= li * prev;
            prev = *bi;
        }
        let mut next = b[n - 1] * self.inv_diag[n - 1];
        b[n - 1] = next;
        for i in (0..n - 1).rev() {
            next = b[i] * self.inv_diag[i] - self.lower[i + 1] * next;
            b[i] = next;
        }
    }
}
