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

/// Solves `A_c X_c = B_c` in place for the interleaved columns of `B`, stored as `n`
/// consecutive rows of `width` entries (`B_ij` at `rows[i·width + j]`), where column `j` belongs
/// to system `c = j mod factors.len()` (at most 3): the two sweeps of
/// [`TridiagonalLdlt::solve_in_place`] applied row by row, so that every inner loop runs along a
/// row. Solving along one axis of a node-major grid of `d`-component vectors stored with that
/// axis outermost is this with `width` the product of the faster axes times `d`.
pub fn solve_interleaved_rows(factors: &[TridiagonalLdlt], rows: &mut [f64], width: usize) {
    let d = factors.len();
    assert!((1..=3).contains(&d), "1 to 3 interleaved systems");
    let n = factors[0].inv_diag.len();
    if n == 0 || width == 0 {
        return;
    }
    debug_assert_eq!(rows.len(), n * width);
    debug_assert_eq!(width % d, 0);
    let coefficient = |pick: &dyn Fn(&TridiagonalLdlt) -> f64| {
        let mut c = [0.0; 3];
        for (ci, f) in c.iter_mut().zip(factors) {
            *ci = pick(f);
        }
        c
    };
    for i in 1..n {
        let (before, from) = rows.split_at_mut(i * width);
        let l = coefficient(&|f| f.lower[i]);
        let previous = &before[(i - 1) * width..];
        for (b, p) in from[..width]
            .chunks_exact_mut(d)
            .zip(previous.chunks_exact(d))
        {
            for c in 0..d {
                b[c] -= l[c] * p[c];
            }
        }
    }
    let last = coefficient(&|f| f.inv_diag[n - 1]);
    for b in rows[(n - 1) * width..].chunks_exact_mut(d) {
        for c in 0..d {
            b[c] *= last[c];
        }
    }
    for i in (0..n - 1).rev() {
        let (upto, after) = rows.split_at_mut((i + 1) * width);
        let l = coefficient(&|f| f.lower[i + 1]);
        let inv = coefficient(&|f| f.inv_diag[i]);
        for (b, x) in upto[i * width..]
            .chunks_exact_mut(d)
            .zip(after[..width].chunks_exact(d))
        {
            for c in 0..d {
                b[c] = b[c] * inv[c] - l[c] * x[c];
            }
        }
    }
}
