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
    if !rows.is_empty() {
        pass(factors, rows, Pass::Whole(width));
    }
}

/// The systems [`solve_lines`] sweeps together.
const LINES: usize = 4;

/// Solves `A_c X = B` in place for consecutive systems of `n` rows of `D = factors.len()`
/// interleaved entries each (`n` the factors' size, `lines.len()` a multiple of `n·D`): the
/// first axis of a node-major grid of `D`-component vectors, one system per line of nodes.
/// [`LINES`] systems are swept together, so that their chains of dependent operations overlap
/// instead of waiting on each other; every entry gets the operations of
/// [`solve_interleaved_rows`] on its system alone, so the result is the same bit for bit.
pub fn solve_lines(factors: &[TridiagonalLdlt], lines: &mut [f64]) {
    match factors.len() {
        1 => solve_lines_of::<1>(factors, lines),
        2 => solve_lines_of::<2>(factors, lines),
        3 => solve_lines_of::<3>(factors, lines),
        _ => panic!("1 to 3 interleaved systems"),
    }
}

/// [`solve_lines`] for `D` systems per row.
fn solve_lines_of<const D: usize>(factors: &[TridiagonalLdlt], lines: &mut [f64]) {
    let n = factors[0].inv_diag.len();
    let len = n * D;
    if len == 0 {
        return;
    }
    let mut groups = lines.chunks_exact_mut(LINES * len);
    for group in &mut groups {
        for i in 1..n {
            for (c, f) in factors.iter().enumerate().take(D) {
                let l = f.lower[i];
                for k in 0..LINES {
                    let e = k * len + i * D + c;
                    group[e] -= l * group[e - D];
                }
            }
        }
        for (c, f) in factors.iter().enumerate().take(D) {
            for k in 0..LINES {
                group[k * len + (n - 1) * D + c] *= f.inv_diag[n - 1];
            }
        }
        for i in (0..n - 1).rev() {
            for (c, f) in factors.iter().enumerate().take(D) {
                let (inv, l) = (f.inv_diag[i], f.lower[i + 1]);
                for k in 0..LINES {
                    let e = k * len + i * D + c;
                    group[e] = group[e] * inv - l * group[e + D];
                }
            }
        }
    }
    for line in groups.into_remainder().chunks_exact_mut(len) {
        solve_line::<D>(factors, line);
    }
}

/// The rows of an interleaved system ([`solve_interleaved_rows`]) that one process holds, and
/// the columns a sweep of them works on: a distributed system is swept block by block, each
/// block's first (downwards) or last (upwards) row updated with the neighbouring block's row.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct RowBlock {
    /// The index in the whole system of the block's first row.
    pub first: usize,
    /// Entries per row.
    pub width: usize,
    /// The columns swept (a range of whole interleaved groups: its start a multiple of the
    /// number of systems).
    pub columns: std::ops::Range<usize>,
}

/// One of the two sweeps of the LDLᵀ solve.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Sweep {
    /// `y_i = b_i − l_i y_{i−1}`, first row to last.
    Down,
    /// `x_{n−1} = D⁻¹ y_{n−1}`, `x_i = D⁻¹ y_i − l_{i+1} x_{i+1}`, last row to first.
    Up,
}

/// One sweep of the rows `rows` (block `block` of the whole system; `rows.len()` a multiple of
/// its width) on `block.columns`: `carry` holds those columns of the row before the block
/// after the downward sweep (for [`Sweep::Down`], unused when the block starts the system) or of
/// the row after it after the upward sweep (for [`Sweep::Up`], unused when it ends the system).
/// The operations on every entry are those of [`solve_interleaved_rows`] on the whole system,
/// so the blocks swept in turn give its result bit for bit.
pub fn sweep_interleaved_rows(
    factors: &[TridiagonalLdlt],
    rows: &mut [f64],
    block: &RowBlock,
    sweep: Sweep,
    carry: &[f64],
) {
    pass(factors, rows, Pass::Block(block, sweep, carry));
}

/// What one call does to the rows of an interleaved system.
#[derive(Clone, Copy)]
enum Pass<'a> {
    /// The whole solve, rows of this width ([`solve_interleaved_rows`]).
    Whole(usize),
    /// One sweep of a block ([`sweep_interleaved_rows`]).
    Block(&'a RowBlock, Sweep, &'a [f64]),
}

/// `pass` for `factors.len()` interleaved systems.
fn pass(factors: &[TridiagonalLdlt], rows: &mut [f64], pass: Pass<'_>) {
    match factors.len() {
        1 => pass_dispatch::<1>(factors, rows, pass),
        2 => pass_dispatch::<2>(factors, rows, pass),
        3 => pass_dispatch::<3>(factors, rows, pass),
        _ => panic!("1 to 3 interleaved systems"),
    }
}

/// [`pass_rows`], compiled for AVX2 when the processor has it: the same multiplies and
/// subtractions in the same order (no fused multiply-add), so the same result bit for bit.
fn pass_dispatch<const D: usize>(factors: &[TridiagonalLdlt], rows: &mut [f64], pass: Pass<'_>) {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        // SAFETY: `pass_rows_avx2` only requires AVX2, which the processor has (checked just
        // above).
        return unsafe { pass_rows_avx2::<D>(factors, rows, pass) };
    }
    pass_rows::<D>(factors, rows, pass);
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn pass_rows_avx2<const D: usize>(factors: &[TridiagonalLdlt], rows: &mut [f64], pass: Pass<'_>) {
    pass_rows::<D>(factors, rows, pass);
}

/// `pass` for `D` systems: the whole solve as its two sweeps (entry by entry when a row is one
/// node, [`solve_line`]), or one sweep of a block ([`sweep_rows`]).
#[inline(always)]
fn pass_rows<const D: usize>(factors: &[TridiagonalLdlt], rows: &mut [f64], pass: Pass<'_>) {
    match pass {
        Pass::Whole(width) if width == D => solve_line::<D>(factors, rows),
        Pass::Whole(width) => {
            let whole = RowBlock {
                first: 0,
                width,
                columns: 0..width,
            };
            sweep_rows::<D>(factors, rows, &whole, Sweep::Down, &[]);
            sweep_rows::<D>(factors, rows, &whole, Sweep::Up, &[]);
        }
        Pass::Block(block, sweep, carry) => sweep_rows::<D>(factors, rows, block, sweep, carry),
    }
}

/// Entries per inner-loop chunk of a row: a multiple of every `D ≤ 3` and of the four lanes of
/// a 256-bit vector, so that a chunk's coefficients are the same for every chunk.
const CHUNK: usize = 12;

/// The per-entry coefficients of a row chunk of `D` interleaved systems: `pick(factor c)` at
/// the entries `j ≡ c (mod D)`.
#[inline(always)]
fn chunk_coefficients<const D: usize>(
    factors: &[TridiagonalLdlt],
    pick: impl Fn(&TridiagonalLdlt) -> f64,
) -> [f64; CHUNK] {
    std::array::from_fn(|j| pick(&factors[j % D]))
}

/// `b_j ← f(b_j, c_j, e_j, o_j)` along a row `b` with the coefficients `c`, `e` (periodic,
/// [`CHUNK`]) and the entries `o` of another row, chunk by chunk, then entry by entry on the
/// remainder (which starts at a multiple of `D`, so the coefficients stay aligned).
#[inline(always)]
fn update_row(
    b: &mut [f64],
    [c, e]: [&[f64; CHUNK]; 2],
    o: &[f64],
    f: impl Fn(f64, f64, f64, f64) -> f64,
) {
    let mut chunks = b.chunks_exact_mut(CHUNK);
    let mut others = o.chunks_exact(CHUNK);
    for (bs, os) in (&mut chunks).zip(&mut others) {
        for (((bj, cj), ej), oj) in bs.iter_mut().zip(c).zip(e).zip(os) {
            *bj = f(*bj, *cj, *ej, *oj);
        }
    }
    let rest = chunks.into_remainder();
    for (((bj, cj), ej), oj) in rest.iter_mut().zip(c).zip(e).zip(others.remainder()) {
        *bj = f(*bj, *cj, *ej, *oj);
    }
}

/// [`sweep_interleaved_rows`] for `D` systems: `L y = b` row by row downwards, or
/// `x_{n−1} = D⁻¹ y_{n−1}` and `x_i = D⁻¹ y_i − l_{i+1} x_{i+1}` upwards, on the block's columns.
#[inline(always)]
fn sweep_rows<const D: usize>(
    factors: &[TridiagonalLdlt],
    rows: &mut [f64],
    block: &RowBlock,
    sweep: Sweep,
    carry: &[f64],
) {
    let RowBlock {
        first,
        width,
        ref columns,
    } = *block;
    let n = factors[0].inv_diag.len();
    let m = rows.len() / width.max(1);
    if m == 0 || columns.is_empty() {
        return;
    }
    debug_assert_eq!(rows.len(), m * width);
    debug_assert!(first + m <= n);
    debug_assert_eq!(columns.start % D, 0);
    let row = |i: usize| i * width + columns.start..i * width + columns.end;
    match sweep {
        Sweep::Down => {
            for i in 0..m {
                let g = first + i;
                if g == 0 {
                    continue;
                }
                let l = chunk_coefficients::<D>(factors, |f| f.lower[g]);
                let (before, from) = rows.split_at_mut(i * width);
                let previous = if i == 0 { carry } else { &before[row(i - 1)] };
                update_row(&mut from[row(0)], [&l, &l], previous, |b, l, _, p| {
                    b - l * p
                });
            }
        }
        Sweep::Up => {
            for i in (0..m).rev() {
                let g = first + i;
                if g + 1 == n {
                    let last = chunk_coefficients::<D>(factors, |f| f.inv_diag[g]);
                    for bs in rows[row(i)].chunks_mut(CHUNK) {
                        bs.iter_mut().zip(&last).for_each(|(b, d)| *b *= d);
                    }
                    continue;
                }
                let l = chunk_coefficients::<D>(factors, |f| f.lower[g + 1]);
                let inv = chunk_coefficients::<D>(factors, |f| f.inv_diag[g]);
                let (upto, after) = rows.split_at_mut((i + 1) * width);
                let next = if i + 1 == m { carry } else { &after[row(0)] };
                update_row(&mut upto[row(i)], [&inv, &l], next, |b, inv, l, x| {
                    b * inv - l * x
                });
            }
        }
    }
}

/// [`solve_interleaved_rows`] for rows of exactly `D` entries (one node per row: the first axis of a grid),
/// where building a [`CHUNK`] of coefficients per row would cost more than the row: the same
/// operations in the same order, entry by entry.
#[inline(always)]
fn solve_line<const D: usize>(factors: &[TridiagonalLdlt], rows: &mut [f64]) {
    let n = factors[0].inv_diag.len();
    for i in 1..n {
        for (c, f) in factors.iter().enumerate().take(D) {
            rows[i * D + c] -= f.lower[i] * rows[(i - 1) * D + c];
        }
    }
    for (c, f) in factors.iter().enumerate().take(D) {
        rows[(n - 1) * D + c] *= f.inv_diag[n - 1];
    }
    for i in (0..n - 1).rev() {
        for (c, f) in factors.iter().enumerate().take(D) {
            rows[i * D + c] =
                rows[i * D + c] * f.inv_diag[i] - f.lower[i + 1] * rows[(i + 1) * D + c];
        }
    }
}

#[cfg(test)]
mod tests {
    use super::{solve_interleaved_rows, solve_lines, TridiagonalLdlt};

    /// Lines swept together give the bits of each line solved alone, for one to three systems
    /// per row and numbers of lines with and without a remainder.
    #[test]
    fn lines_solved_together_equal_lines_solved_alone() {
        let n = 9;
        let mut rng = fastrand::Rng::with_seed(54);
        for d in 1..=3 {
            let factors: Vec<TridiagonalLdlt> = (0..d)
                .map(|c| {
                    let diag = vec![4.0 + c as f64; n];
                    let off = vec![-1.0 - 0.5 * c as f64; n - 1];
                    TridiagonalLdlt::factor(&diag, &off).unwrap()
                })
                .collect();
            for count in [1, 4, 7, 9] {
                let b: Vec<f64> = (0..count * n * d).map(|_| rng.f64() - 0.5).collect();
                let mut together = b.clone();
                solve_lines(&factors, &mut together);
                let mut alone = b;
                alone
                    .chunks_exact_mut(n * d)
                    .for_each(|line| solve_interleaved_rows(&factors, line, d));
                let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
                assert_eq!(bits(&together), bits(&alone), "{d} systems, {count} lines");
            }
        }
    }
}
