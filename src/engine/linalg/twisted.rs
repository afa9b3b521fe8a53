//! The twisted factorisation of a symmetric positive definite tridiagonal matrix ("burn at both
//! ends"): eliminated from the first row down and from the last row up at once, the two meeting
//! at a middle row `k`. A solve is then two chains of dependent operations of half the length,
//! run side by side, where the Thomas algorithm has one chain of the whole length; a chain waits
//! on the latency of each multiply and subtract, so the latency of a solve is about halved
//! (`make bench` measures what the 1D runs gain, against a baseline built beside them).
//!
//! With `A` of diagonal `a_i` and off-diagonal `c_i = A_{i+1,i}`:
//! ```text
//! rows i < k (downwards):  d_0 = a_0,        l_i = c_{i−1}/d_{i−1},  d_i = a_i − l_i c_{i−1}
//! rows i > k (upwards):    e_{n−1} = a_{n−1}, m_i = c_i/e_{i+1},      e_i = a_i − m_i c_i
//! row k:                   γ = a_k − l_k c_{k−1} − m_k c_k
//! ```
//! and `A x = b` is solved by `y_i = b_i − l_i y_{i−1}` (i < k), `z_i = b_i − m_i z_{i+1}` (i > k),
//! `x_k = (b_k − l_k y_{k−1} − m_k z_{k+1}) / γ`, then outwards
//! `x_i = y_i/d_i − l_{i+1} x_{i+1}` (i < k) and `x_i = z_i/e_i − m_{i−1} x_{i−1}` (i > k).
//! It is the LDLᵀ factorisation of `A` with its rows and columns taken in the order
//! `0, …, k − 1, n − 1, …, k + 1, k` (eliminating a row of either half updates only the next row
//! of that half, or row `k`: no fill), so every pivot is a Schur complement of `A`, positive for
//! a positive definite `A`, and it keeps the backward stability of LDLᵀ on such a matrix, as the
//! Thomas algorithm does. With `k = n − 1` it is the Thomas algorithm.

/// `A` factored from both ends towards the middle row `k` (see the module documentation). The
/// pivots are kept as reciprocals, so that a solve divides nowhere.
#[derive(Debug, Clone)]
pub struct TwistedTridiagonal {
    /// `1/d_i` of the rows `i < k`.
    inv_top: Vec<f64>,
    /// `l_{i+1}` of the rows `i < k`: what couples row `i` to the row below it.
    lower_next: Vec<f64>,
    /// `1/γ`.
    inv_middle: f64,
    /// `1/e_i` of the rows `i > k`, from row `k + 1`.
    inv_bottom: Vec<f64>,
    /// `m_{i−1}` of the rows `i > k`, from row `k + 1`: what couples row `i` to the row above it.
    upper_previous: Vec<f64>,
}

impl TwistedTridiagonal {
    /// Factorises the matrix with diagonal `diag` and off-diagonal `off[i] = A[i+1, i]`, meeting
    /// at the middle row `n / 2`. Returns the index of the first non-positive pivot found on
    /// failure.
    pub fn factor(diag: &[f64], off: &[f64]) -> Result<Self, usize> {
        let n = diag.len();
        debug_assert_eq!(off.len() + 1, n.max(1));
        if n == 0 {
            return Ok(Self {
                inv_top: Vec::new(),
                lower_next: Vec::new(),
                inv_middle: 0.0,
                inv_bottom: Vec::new(),
                upper_previous: Vec::new(),
            });
        }
        let k = n / 2;
        let positive = |p: f64, i: usize| {
            if p > 0.0 && p.is_finite() {
                Ok(p)
            } else {
                Err(i)
            }
        };
        let mut d: Vec<f64> = Vec::with_capacity(k);
        let mut lower_next: Vec<f64> = Vec::with_capacity(k);
        for i in 0..k {
            let p = match lower_next.last() {
                Some(&l_i) => diag[i] - l_i * off[i - 1],
                None => diag[i],
            };
            d.push(positive(p, i)?);
            lower_next.push(off[i] / d[i]);
        }
        let mut e = vec![0.0; n - k - 1];
        let mut upper_previous = vec![0.0; n - k - 1];
        for j in (0..n - k - 1).rev() {
            let i = k + 1 + j;
            let p = match upper_previous.get(j + 1) {
                Some(&m_i) => diag[i] - m_i * off[i],
                None => diag[i],
            };
            e[j] = positive(p, i)?;
            upper_previous[j] = off[i - 1] / e[j];
        }
        let mut gamma = diag[k];
        if let Some(&l_k) = lower_next.last() {
            gamma -= l_k * off[k - 1];
        }
        if let Some(&m_k) = upper_previous.first() {
            gamma -= m_k * off[k];
        }
        Ok(Self {
            inv_top: d.iter().map(|p| 1.0 / p).collect(),
            lower_next,
            inv_middle: 1.0 / positive(gamma, k)?,
            inv_bottom: e.iter().map(|p| 1.0 / p).collect(),
            upper_previous,
        })
    }

    /// Solves `A x = b` in place (`b` is overwritten by `x`): the two eliminations towards row
    /// `k`, then the two substitutions away from it, each pair in one loop whose two chains
    /// carry their last value in a register.
    pub fn solve_in_place(&self, b: &mut [f64]) {
        let k = self.inv_top.len();
        if b.is_empty() {
            return;
        }
        assert_eq!(
            b.len(),
            k + 1 + self.inv_bottom.len(),
            "a right-hand side of the factor's size"
        );
        let (top, rest) = b.split_at_mut(k);
        let (centre, bottom) = rest.split_first_mut().expect("k < n");
        let (l, m) = (&self.lower_next, &self.upper_previous);

        // y_{i+1} = b_{i+1} − l_{i+1} y_i downwards, z_i = b_i − m_i z_{i+1} upwards.
        let mut y = top.first().copied().unwrap_or(0.0);
        let mut z = bottom.last().copied().unwrap_or(0.0);
        let down = top.iter_mut().skip(1).zip(l);
        let up = bottom.iter_mut().zip(m.iter().skip(1)).rev();
        for_each_pair(
            down,
            up,
            |(bi, li)| {
                y = *bi - li * y;
                *bi = y;
            },
            |(bi, mi)| {
                z = *bi - mi * z;
                *bi = z;
            },
        );
        let from_top = l.last().map_or(0.0, |l_k| l_k * y);
        let from_bottom = m.first().map_or(0.0, |m_k| m_k * z);
        let x_k = (*centre - from_top - from_bottom) * self.inv_middle;
        *centre = x_k;

        // x_i = y_i/d_i − l_{i+1} x_{i+1} downwards from k, x_i = z_i/e_i − m_{i−1} x_{i−1}
        // upwards.
        let (mut below, mut above) = (x_k, x_k);
        let down = top.iter_mut().zip(&self.inv_top).zip(l).rev();
        let up = bottom.iter_mut().zip(&self.inv_bottom).zip(m);
        for_each_pair(
            down,
            up,
            |((xi, inv), li)| {
                below = *xi * inv - li * below;
                *xi = below;
            },
            |((xi, inv), mi)| {
                above = *xi * inv - mi * above;
                *xi = above;
            },
        );
    }
}

/// Calls `f` on every item of `a` and `g` on every item of `b`, the `j`-th of each in the same
/// iteration, so that the two chains of dependent operations overlap.
#[inline(always)]
fn for_each_pair<A: Iterator, B: Iterator>(
    mut a: A,
    mut b: B,
    mut f: impl FnMut(A::Item),
    mut g: impl FnMut(B::Item),
) {
    loop {
        match (a.next(), b.next()) {
            (None, None) => return,
            (x, y) => {
                if let Some(x) = x {
                    f(x);
                }
                if let Some(y) = y {
                    g(y);
                }
            }
        }
    }
}
