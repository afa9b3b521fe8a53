//! The twisted factorisation of a symmetric positive definite tridiagonal matrix, eliminated
//! from both ends towards a middle row ("burn at both ends"): the same work as the LDLᵀ sweeps
//! of [`super::TridiagonalLdlt`], in two independent chains of half the length that a processor
//! runs side by side. A tridiagonal solve is latency-bound (each row waits on the previous one),
//! so two chains take about half the time of one.
//!
//! With `a_i` the diagonal, `b_i = A[i+1, i]` and the twist row `k`: the top pivots
//! `p_0 = a_0`, `p_i = a_i − b_{i−1}²/p_{i−1}` (`i < k`), the bottom pivots `q_{n−1} = a_{n−1}`,
//! `q_i = a_i − b_i²/q_{i+1}` (`i > k`), and the twist pivot
//! `γ_k = a_k − b_{k−1}²/p_{k−1} − b_k²/q_{k+1}`. A solve of `A x = r` eliminates
//! `y_i = r_i − (b_{i−1}/p_{i−1}) y_{i−1}` downwards to row `k − 1` and
//! `z_i = r_i − (b_i/q_{i+1}) z_{i+1}` upwards to row `k + 1`, takes
//! `x_k = (r_k − (b_{k−1}/p_{k−1}) y_{k−1} − (b_k/q_{k+1}) z_{k+1}) / γ_k`, then substitutes
//! outwards: `x_i = y_i/p_i − (b_i/p_i) x_{i+1}` above `k`, `x_i = z_i/q_i − (b_{i−1}/q_i) x_{i−1}`
//! below. Every pivot of a positive definite matrix is positive (each is a Schur complement's).

/// `A = N Δ Nᵀ` twisted at the middle row (see the module documentation).
#[derive(Debug, Clone)]
pub struct TwistedTridiagonal {
    /// The twist row `k = ⌊(n − 1)/2⌋`.
    twist: usize,
    /// The elimination factor of row `i` towards the twist: `b_{i−1}/p_{i−1}` for `0 < i ≤ k`,
    /// `b_i/q_{i+1}` for `k < i < n − 1` (row `k`'s factor from below is `twist_from_below`).
    towards_twist: Vec<f64>,
    /// `b_k/q_{k+1}`, the twist row's factor from below (0 when `k = n − 1`).
    twist_from_below: f64,
    /// `1/p_i` above the twist, `1/γ_k` at it, `1/q_i` below it.
    inv_pivot: Vec<f64>,
}

impl TwistedTridiagonal {
    /// Factorises the matrix with diagonal `diag` and off-diagonal `off[i] = A[i+1, i]`.
    /// Returns the index of a non-positive pivot on failure (the first one met from either end).
    pub fn factor(diag: &[f64], off: &[f64]) -> Result<Self, usize> {
        let n = diag.len();
        debug_assert_eq!(off.len() + 1, n.max(1));
        let twist = n.saturating_sub(1) / 2;
        let mut towards_twist = vec![0.0; n];
        let mut inv_pivot = vec![0.0; n];
        let positive = |pivot: f64, i: usize| match pivot > 0.0 && pivot.is_finite() {
            true => Ok(1.0 / pivot),
            false => Err(i),
        };
        let mut above = 0.0;
        for i in 0..twist {
            let mut p = diag[i];
            if i > 0 {
                towards_twist[i] = off[i - 1] * inv_pivot[i - 1];
                p -= towards_twist[i] * off[i - 1];
            }
            inv_pivot[i] = positive(p, i)?;
            above = off[i] * inv_pivot[i];
        }
        let mut below = 0.0;
        for i in (twist + 1..n).rev() {
            let mut q = diag[i];
            if i + 1 < n {
                towards_twist[i] = off[i] * inv_pivot[i + 1];
                q -= towards_twist[i] * off[i];
            }
            inv_pivot[i] = positive(q, i)?;
            below = off[i - 1] * inv_pivot[i];
        }
        if n == 0 {
            return Ok(Self {
                twist,
                towards_twist,
                twist_from_below: 0.0,
                inv_pivot,
            });
        }
        let mut gamma = diag[twist];
        if twist > 0 {
            towards_twist[twist] = above;
            gamma -= above * off[twist - 1];
        }
        if twist + 1 < n {
            gamma -= below * off[twist];
        }
        inv_pivot[twist] = positive(gamma, twist)?;
        Ok(Self {
            twist,
            towards_twist,
            twist_from_below: below,
            inv_pivot,
        })
    }

    /// Solves `A x = r` in place (`r` is overwritten by `x`): both eliminations towards the twist
    /// row side by side, its value, then both substitutions outwards side by side.
    pub fn solve_in_place(&self, r: &mut [f64]) {
        let n = r.len();
        assert_eq!(n, self.inv_pivot.len());
        if n == 0 {
            return;
        }
        let (k, f, inv) = (self.twist, &self.towards_twist, &self.inv_pivot);
        // Top chain: rows 1..k (downwards); bottom chain: rows n−2 down to k+1 (upwards). The
        // bottom one has at most one row more. Each chain carries its last value in a register
        // (reading it back from `r` would put a store-to-load forwarding into the chain).
        let (top_rows, bottom_rows) = (k.saturating_sub(1), (n - 1).saturating_sub(k + 1));
        let common = top_rows.min(bottom_rows);
        let (mut up, mut down) = (r[0], r[n - 1]);
        for j in 0..common {
            let (t, b) = (1 + j, n - 2 - j);
            up = r[t] - f[t] * up;
            down = r[b] - f[b] * down;
            r[t] = up;
            r[b] = down;
        }
        for t in 1 + common..k {
            up = r[t] - f[t] * up;
            r[t] = up;
        }
        for b in (k + 1..n - 1 - common).rev() {
            down = r[b] - f[b] * down;
            r[b] = down;
        }
        let mut twist = r[k];
        if k > 0 {
            twist -= f[k] * r[k - 1];
        }
        if k + 1 < n {
            twist -= self.twist_from_below * r[k + 1];
        }
        let x = twist * inv[k];
        r[k] = x;
        // Outwards: x_i = y_i/p_i − f_{i+1} x_{i+1} above, x_i = z_i/q_i − f_{i−1} x_{i−1} below,
        // the first row below the twist with `twist_from_below`.
        let (mut up, mut down) = (x, x);
        if k + 1 < n {
            down = r[k + 1] * inv[k + 1] - self.twist_from_below * x;
            r[k + 1] = down;
        }
        let (up_rows, down_rows) = (k, (n - 1 - k).saturating_sub(1));
        let common = up_rows.min(down_rows);
        for j in 0..common {
            let (t, b) = (k - 1 - j, k + 2 + j);
            up = r[t] * inv[t] - f[t + 1] * up;
            down = r[b] * inv[b] - f[b - 1] * down;
            r[t] = up;
            r[b] = down;
        }
        for t in (0..k - common).rev() {
            up = r[t] * inv[t] - f[t + 1] * up;
            r[t] = up;
        }
        for b in k + 2 + common..n {
            down = r[b] * inv[b] - f[b - 1] * down;
            r[b] = down;
        }
    }
}
