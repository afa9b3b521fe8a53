//! Sparse symmetric matrices (assembled, or matrix-free on a structured box): assembly from
//! element contributions and allocation-free products.

use std::borrow::Cow;

use faer::sparse::{SparseColMat, SymbolicSparseColMat, Triplet};
use rayon::prelude::*;

use super::separable::SeparablePart;
use super::stencil::Stencil;

/// A symmetric sparse matrix: assembled with both triangles (faer CSC), or matrix-free on a
/// structured box ([`Stencil`]).
///
/// Both triangles are stored because faer's Cholesky silently returns a wrong answer when the
/// stored triangle does not match the requested side (DEPENDENCIES.md, faer gotchas). A matrix
/// of bandwidth one (every 1D P1 matrix) also keeps its two diagonals, so that the products of
/// the time loop run as contiguous loops instead of indexed gathers.
#[derive(Debug, Clone)]
pub struct SymmetricMatrix {
    storage: Storage,
}

/// How a [`SymmetricMatrix`] is stored.
#[derive(Debug, Clone)]
enum Storage {
    /// Every entry, with the two diagonals again when the bandwidth is one.
    Assembled {
        inner: SparseColMat<usize, f64>,
        tridiagonal: Option<Tridiagonal>,
    },
    /// The blocks of each node class of a structured box.
    Stencil(Stencil),
}

/// Rows per parallel task of an assembled product; the partial sums of a reduction are added in
/// task order, so results do not depend on the number of threads.
const ROWS_PER_TASK: usize = 4096;

/// Independent partial sums of the reductions that need no particular order of summation
/// ([`SymmetricMatrix::weighted_form`]): they let the compiler vectorise what a single running
/// sum would serialise.
const LANES: usize = 4;

/// A bilinear form `xᵀAy` with the weighted squares `Σ r_i x_i²` and `Σ r_i y_i²` of its two
/// vectors ([`SymmetricMatrix::weighted_form`]).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct WeightedForm {
    /// `xᵀAy`.
    pub value: f64,
    /// `Σ r_i x_i²`.
    pub x_squares: f64,
    /// `Σ r_i y_i²`.
    pub y_squares: f64,
}

/// `(Σ r_i x_i², Σ r_i y_i²)` in one pass over [`LANES`] partial sums.
pub fn weighted_squares(r: &[f64], x: &[f64], y: &[f64]) -> (f64, f64) {
    let (mut sx, mut sy) = ([0.0; LANES], [0.0; LANES]);
    let chunks = r
        .chunks_exact(LANES)
        .zip(x.chunks_exact(LANES))
        .zip(y.chunks_exact(LANES));
    for ((r, x), y) in chunks {
        for k in 0..LANES {
            sx[k] += r[k] * x[k] * x[k];
            sy[k] += r[k] * y[k] * y[k];
        }
    }
    let tail = r.len() - r.len() % LANES;
    for ((r, x), y) in r[tail..].iter().zip(&x[tail..]).zip(&y[tail..]) {
        sx[0] += r * x * x;
        sy[0] += r * y * y;
    }
    (sx.iter().sum(), sy.iter().sum())
}

/// The diagonal `d` and the sub-diagonal `l[i] = A[i+1, i]` of a symmetric tridiagonal matrix.
#[derive(Debug, Clone)]
struct Tridiagonal {
    d: Vec<f64>,
    l: Vec<f64>,
}

impl Tridiagonal {
    fn of(inner: &SparseColMat<usize, f64>) -> Option<Self> {
        let sym = inner.symbolic();
        let n = inner.nrows();
        let mut band = Self {
            d: vec![0.0; n],
            l: vec![0.0; n.saturating_sub(1)],
        };
        for j in 0..n {
            let range = sym.col_ptr()[j]..sym.col_ptr()[j + 1];
            for (&i, &v) in sym.row_idx()[range.clone()].iter().zip(&inner.val()[range]) {
                match i.abs_diff(j) {
                    0 => band.d[j] += v,
                    1 if i > j => band.l[j] += v,
                    1 => {}
                    _ => return None,
                }
            }
        }
        Some(band)
    }

    /// `y = A x`, row by row as `d_i x_i + l_{i−1} x_{i−1} + l_i x_{i+1}` (the first and last rows
    /// without their missing neighbour), the interior rows without a branch so that they vectorise.
    fn mul_into(&self, x: &[f64], y: &mut [f64]) {
        let n = x.len();
        assert!(self.d.len() == n && y.len() == n);
        match n {
            0 => return,
            1 => {
                y[0] = self.d[0] * x[0];
                return;
            }
            _ => {}
        }
        let (d, l) = (&self.d, &self.l);
        y[0] = d[0] * x[0] + l[0] * x[1];
        let interior = y[1..n - 1]
            .iter_mut()
            .zip(&d[1..n - 1])
            .zip(l.windows(2))
            .zip(x.windows(3));
        for (((yi, di), lw), xw) in interior {
            *yi = di * xw[1] + lw[0] * xw[0] + lw[1] * xw[2];
        }
        y[n - 1] = d[n - 1] * x[n - 1] + l[n - 2] * x[n - 2];
    }

    /// `xᵀAy` over [`LANES`] independent partial sums ([`Tridiagonal::forms`] without the
    /// weighted squares).
    fn bilinear_form(&self, x: &[f64], y: &[f64]) -> f64 {
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: `forms_avx2` only requires AVX2, which the processor has (checked just
            // above).
            return unsafe { self.forms_avx2::<false>(x, y, x) }.value;
        }
        self.forms::<false>(x, y, x).value
    }

    /// [`SymmetricMatrix::weighted_form`] of a tridiagonal matrix: one pass, each sum over
    /// [`LANES`] independent partial sums; compiled for AVX2 when the processor has it (the
    /// same operations in the same order, four lanes at a time instead of two).
    fn weighted_form(&self, x: &[f64], y: &[f64], r: &[f64]) -> WeightedForm {
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: `weighted_form_avx2` only requires AVX2, which the processor has
            // (checked just above).
            return unsafe { self.forms_avx2::<true>(x, y, r) };
        }
        self.forms::<true>(x, y, r)
    }

    /// [`Tridiagonal::forms`] compiled for AVX2.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    fn forms_avx2<const SQUARES: bool>(&self, x: &[f64], y: &[f64], r: &[f64]) -> WeightedForm {
        self.forms::<SQUARES>(x, y, r)
    }

    /// `xᵀAy` and, when `SQUARES`, `Σ r_i x_i²` and `Σ r_i y_i²` (zero otherwise, `r` unread), in
    /// one pass over [`LANES`] partial sums per sum.
    #[inline(always)]
    fn forms<const SQUARES: bool>(&self, x: &[f64], y: &[f64], r: &[f64]) -> WeightedForm {
        let n = self.d.len();
        assert!(x.len() == n && y.len() == n && r.len() == n);
        let Some(m) = n.checked_sub(1) else {
            return WeightedForm::default();
        };
        // Rows 0..m carry a diagonal and the entry right of it; row m only its diagonal.
        let (d, l, w) = (&self.d[..m], &self.l[..m], &r[..m]);
        let (x0, x1, y0, y1) = (&x[..m], &x[1..], &y[..m], &y[1..]);
        let mut lanes = [[0.0; LANES]; 3];
        let full = m - m % LANES;
        for first in (0..full).step_by(LANES) {
            let block = |s: &[f64]| -> [f64; LANES] {
                s[first..first + LANES]
                    .try_into()
                    .expect("a block of LANES")
            };
            let (d, l, w) = (block(d), block(l), block(w));
            let (x0, x1, y0, y1) = (block(x0), block(x1), block(y0), block(y1));
            for k in 0..LANES {
                let off = l[k] * (x0[k] * y1[k] + x1[k] * y0[k]);
                lanes[0][k] += d[k] * x0[k] * y0[k] + off;
                if SQUARES {
                    lanes[1][k] += w[k] * x0[k] * x0[k];
                    lanes[2][k] += w[k] * y0[k] * y0[k];
                }
            }
        }
        for i in full..m {
            lanes[0][0] += d[i] * x0[i] * y0[i] + l[i] * (x0[i] * y1[i] + x1[i] * y0[i]);
            if SQUARES {
                lanes[1][0] += w[i] * x0[i] * x0[i];
                lanes[2][0] += w[i] * y0[i] * y0[i];
            }
        }
        let [value, x_squares, y_squares] = lanes.map(|l| l.iter().sum::<f64>());
        let value = value + self.d[m] * x[m] * y[m];
        if !SQUARES {
            return WeightedForm {
                value,
                ..WeightedForm::default()
            };
        }
        WeightedForm {
            value,
            x_squares: x_squares + r[m] * x[m] * x[m],
            y_squares: y_squares + r[m] * y[m] * y[m],
        }
    }
}

impl SymmetricMatrix {
    /// Wraps a faer matrix that the caller guarantees to be symmetric with both triangles stored.
    pub fn from_faer(inner: SparseColMat<usize, f64>) -> Self {
        debug_assert_eq!(inner.nrows(), inner.ncols());
        let tridiagonal = Tridiagonal::of(&inner);
        Self {
            storage: Storage::Assembled { inner, tridiagonal },
        }
    }

    /// The matrix-free operator `stencil`.
    pub fn from_stencil(stencil: Stencil) -> Self {
        Self {
            storage: Storage::Stencil(stencil),
        }
    }

    /// A stencil's principal submatrix on its first `layers` node layers along the last axis
    /// ([`Stencil::first_layers`]), matrix-free; `None` for an assembled matrix or a cut the
    /// stencil cannot make.
    pub fn first_layers(&self, layers: usize) -> Option<SymmetricMatrix> {
        match &self.storage {
            Storage::Stencil(s) => s.first_layers(layers).map(Self::from_stencil),
            Storage::Assembled { .. } => None,
        }
    }

    /// The stencil of a matrix-free matrix; `None` for an assembled one.
    pub fn stencil(&self) -> Option<&Stencil> {
        match &self.storage {
            Storage::Stencil(s) => Some(s),
            Storage::Assembled { .. } => None,
        }
    }

    /// Whether the matrix is stored as a stencil (matrix-free) rather than assembled.
    pub fn is_stencil(&self) -> bool {
        matches!(self.storage, Storage::Stencil(_))
    }

    /// The number of rows (= columns).
    pub fn dim(&self) -> usize {
        match &self.storage {
            Storage::Assembled { inner, .. } => inner.nrows(),
            Storage::Stencil(s) => s.dim(),
        }
    }

    /// The faer matrix: borrowed when assembled, assembled from the stencil otherwise (`O(nnz)`
    /// memory: for the direct solver and the rare dense operations, never in a time loop).
    pub fn to_faer(&self) -> Cow<'_, SparseColMat<usize, f64>> {
        match &self.storage {
            Storage::Assembled { inner, .. } => Cow::Borrowed(inner),
            Storage::Stencil(_) => {
                let n = self.dim();
                let mut col_ptr = Vec::with_capacity(n + 1);
                let mut row_idx = Vec::new();
                let mut val = Vec::new();
                col_ptr.push(0);
                for j in 0..n {
                    self.for_each_in_row(j, |i, v| {
                        row_idx.push(i);
                        val.push(v);
                    });
                    col_ptr.push(row_idx.len());
                }
                let symbolic = SymbolicSparseColMat::new_checked(n, n, col_ptr, None, row_idx);
                Cow::Owned(SparseColMat::new(symbolic, val))
            }
        }
    }

    /// Entry `(i, j)`, zero when not stored.
    pub fn get(&self, i: usize, j: usize) -> f64 {
        match &self.storage {
            Storage::Assembled { inner, .. } => inner.get(i, j).copied().unwrap_or(0.0),
            Storage::Stencil(s) => s.get(i, j),
        }
    }

    /// Calls `f(j, A_ij)` for every stored entry of row `i` (column `i`, by symmetry), in
    /// increasing `j`.
    pub fn for_each_in_row(&self, i: usize, mut f: impl FnMut(usize, f64)) {
        match &self.storage {
            Storage::Assembled { inner, .. } => {
                let sym = inner.symbolic();
                let range = sym.col_ptr()[i]..sym.col_ptr()[i + 1];
                for (&j, &v) in sym.row_idx()[range.clone()].iter().zip(&inner.val()[range]) {
                    f(j, v);
                }
            }
            Storage::Stencil(s) => s.for_each_in_row(i, f),
        }
    }

    /// `Σ_j |A_ij|` of every row `i`: with it `|x|ᵀ|A||y| ≤ (Σ r_i x_i² · Σ r_i y_i²)^½`
    /// bounds the products a form `xᵀAy` sums, and so its round-off.
    pub fn abs_row_sums(&self) -> Vec<f64> {
        match &self.storage {
            Storage::Stencil(s) => s.abs_row_sums(),
            Storage::Assembled { .. } => (0..self.dim())
                .map(|i| {
                    let mut sum = 0.0;
                    self.for_each_in_row(i, |_, v| sum += v.abs());
                    sum
                })
                .collect(),
        }
    }

    /// `y = A x`, without allocation. Uses symmetry: row `i` of `A` is its column `i`.
    pub fn mul_into(&self, x: &[f64], y: &mut [f64]) {
        match &self.storage {
            Storage::Assembled {
                tridiagonal: Some(t),
                ..
            } => t.mul_into(x, y),
            _ => {
                self.mul_dot(x, y);
            }
        }
    }

    /// `y = A x`, returning `xᵀ y`: rows in parallel tasks (whose partial sums are added in a
    /// fixed order) for every matrix but a tridiagonal one. [`SymmetricMatrix::mul_into`] is
    /// this without the dot product where it would be a second pass (a tridiagonal matrix, the
    /// 1D time loop's).
    pub fn mul_dot(&self, x: &[f64], y: &mut [f64]) -> f64 {
        match &self.storage {
            Storage::Assembled {
                tridiagonal: Some(t),
                ..
            } => {
                t.mul_into(x, y);
                x.iter().zip(y.iter()).map(|(a, b)| a * b).sum()
            }
            Storage::Assembled { inner, .. } => {
                let sym = inner.symbolic();
                let (col_ptr, row_idx, val) = (sym.col_ptr(), sym.row_idx(), inner.val());
                let partial: Vec<f64> = y
                    .par_chunks_mut(ROWS_PER_TASK)
                    .enumerate()
                    .map(|(task, ys)| {
                        let first = task * ROWS_PER_TASK;
                        let mut xy = 0.0;
                        for (k, yi) in ys.iter_mut().enumerate() {
                            let range = col_ptr[first + k]..col_ptr[first + k + 1];
                            *yi = row_idx[range.clone()]
                                .iter()
                                .zip(&val[range])
                                .map(|(&r, &v)| v * x[r])
                                .sum();
                            xy += x[first + k] * *yi;
                        }
                        xy
                    })
                    .collect();
                partial.iter().sum()
            }
            Storage::Stencil(s) => s.mul_dot(x, y),
        }
    }

    /// `xᵀAy` with `Σ r_i x_i²` and `Σ r_i y_i²`, for `r` the [row sums of `|A|`](Self::abs_row_sums)
    /// a bound `(Σ r_i x_i² · Σ r_i y_i²)^½` of the products the form sums. A tridiagonal
    /// matrix takes all three in one pass of independent partial sums, so its value may differ
    /// from [`SymmetricMatrix::bilinear_form`]'s at round-off; the others take that form and
    /// one pass for the squares.
    pub fn weighted_form(&self, x: &[f64], y: &[f64], r: &[f64]) -> WeightedForm {
        if let Storage::Assembled {
            tridiagonal: Some(t),
            ..
        } = &self.storage
        {
            return t.weighted_form(x, y, r);
        }
        let (x_squares, y_squares) = weighted_squares(r, x, y);
        WeightedForm {
            value: self.bilinear_form(x, y),
            x_squares,
            y_squares,
        }
    }

    /// The quadratic form `xᵀ A x`.
    pub fn quadratic_form(&self, x: &[f64]) -> f64 {
        self.bilinear_form(x, x)
    }

    /// The bilinear form `xᵀ A y`.
    pub fn bilinear_form(&self, x: &[f64], y: &[f64]) -> f64 {
        let (inner, tridiagonal) = match &self.storage {
            Storage::Assembled { inner, tridiagonal } => (inner, tridiagonal),
            Storage::Stencil(s) => return s.bilinear_form(x, y),
        };
        if let Some(t) = tridiagonal {
            return t.bilinear_form(x, y);
        }
        let sym = inner.symbolic();
        let col_ptr = sym.col_ptr();
        let row_idx = sym.row_idx();
        let val = inner.val();
        let mut total = 0.0;
        for (j, &yj) in y.iter().enumerate() {
            if yj == 0.0 {
                continue;
            }
            let range = col_ptr[j]..col_ptr[j + 1];
            let col: f64 = row_idx[range.clone()]
                .iter()
                .zip(&val[range])
                .map(|(&r, &v)| v * x[r])
                .sum();
            total += col * yj;
        }
        total
    }

    /// `a·self + b·other`, on the union of both sparsity patterns (blockwise for two stencils
    /// of one mesh, which stay matrix-free).
    pub fn linear_combination(&self, a: f64, other: &SymmetricMatrix, b: f64) -> SymmetricMatrix {
        if let (Storage::Stencil(p), Storage::Stencil(q)) = (&self.storage, &other.storage) {
            if let Some(sum) = p.linear_combination(a, q, b) {
                return SymmetricMatrix::from_stencil(sum);
            }
        }
        let mut assembler = SparseAssembler::new(self.dim());
        assembler.add_scaled(self, a);
        assembler.add_scaled(other, b);
        assembler.finish()
    }

    /// The largest `|i - j|` over stored entries.
    pub fn bandwidth(&self) -> usize {
        let inner = match &self.storage {
            Storage::Assembled { inner, .. } => inner,
            Storage::Stencil(s) => return s.bandwidth(),
        };
        let sym = inner.symbolic();
        (0..self.dim())
            .flat_map(|j| {
                sym.row_idx()[sym.col_ptr()[j]..sym.col_ptr()[j + 1]]
                    .iter()
                    .map(move |&i| i.abs_diff(j))
            })
            .max()
            .unwrap_or(0)
    }

    /// Sum of all entries (for a mass matrix with ρ = 1: the measure of the body).
    pub fn sum_of_entries(&self) -> f64 {
        match &self.storage {
            Storage::Assembled { inner, .. } => inner.val().iter().sum(),
            Storage::Stencil(_) => {
                let mut total = 0.0;
                for i in 0..self.dim() {
                    self.for_each_in_row(i, |_, v| total += v);
                }
                total
            }
        }
    }

    /// The separable part a matrix-free operator carries ([`Stencil::with_separable_part`]).
    pub fn separable_part(&self) -> Option<&SeparablePart> {
        match &self.storage {
            Storage::Stencil(s) => s.separable_part(),
            Storage::Assembled { .. } => None,
        }
    }

    /// Whether row `i` has no non-zero entry.
    pub fn row_is_zero(&self, i: usize) -> bool {
        let mut zero = true;
        self.for_each_in_row(i, |_, v| zero &= v == 0.0);
        zero
    }
}

/// Accumulates `(i, j, v)` contributions; duplicates are summed (finite element assembly).
#[derive(Debug, Clone)]
pub struct SparseAssembler {
    dim: usize,
    triplets: Vec<Triplet<usize, usize, f64>>,
}

impl SparseAssembler {
    /// An empty `dim × dim` matrix.
    pub fn new(dim: usize) -> Self {
        Self {
            dim,
            triplets: Vec::new(),
        }
    }

    /// Adds `v` at `(i, j)`.
    pub fn add(&mut self, i: usize, j: usize, v: f64) {
        self.triplets.push(Triplet::new(i, j, v));
    }

    /// Adds a dense element matrix at the given global dofs; `None` marks an eliminated
    /// (Dirichlet) dof whose row and column are dropped.
    pub fn add_element<const N: usize>(
        &mut self,
        dofs: &[Option<usize>; N],
        element: &nalgebra::SMatrix<f64, N, N>,
    ) {
        for (a, da) in dofs.iter().enumerate() {
            let Some(i) = *da else { continue };
            for (b, db) in dofs.iter().enumerate() {
                let Some(j) = *db else { continue };
                self.add(i, j, element[(a, b)]);
            }
        }
    }

    /// Adds `scale · m`.
    pub fn add_scaled(&mut self, m: &SymmetricMatrix, scale: f64) {
        for j in 0..m.dim() {
            m.for_each_in_row(j, |i, v| self.add(i, j, scale * v));
        }
    }

    /// The assembled matrix.
    pub fn finish(self) -> SymmetricMatrix {
        let inner = SparseColMat::try_new_from_triplets(self.dim, self.dim, &self.triplets)
            .expect("assembly indices are within the matrix dimension by construction");
        SymmetricMatrix::from_faer(inner)
    }
}

impl SymmetricMatrix {
    /// The congruence `Pᵀ A P` where row `a` of `P` is
    /// `Σ_{(i, w) ∈ rows[a]} w e_iᵀ`: `(Pᵀ A P)_ij = Σ_ab A_ab P_ai P_bj`. The upper triangle is
    /// summed in a fixed order and mirrored, so the result is exactly symmetric.
    pub fn congruence(&self, rows: &[Vec<(usize, f64)>]) -> SymmetricMatrix {
        let n = self.dim();
        let mut upper: Vec<(usize, f64)> = Vec::new();
        for (b, row_b) in rows.iter().enumerate() {
            self.for_each_in_row(b, |ra, v| {
                for &(i, wi) in &rows[ra] {
                    for &(j, wj) in row_b {
                        if i <= j {
                            upper.push((j * n + i, v * wi * wj));
                        }
                    }
                }
            });
        }
        SymmetricMatrix::from_upper_contributions(n, upper)
    }

    /// The `n × n` symmetric matrix whose upper triangle sums the contributions
    /// `(column · n + row, value)` (`row ≤ column`). Duplicates are summed in the order given
    /// (the sort is stable) and each sum is stored at `(i, j)` and `(j, i)`: handing both
    /// triangles' duplicates to faer would sum them in an unspecified order (its per-column
    /// sort is unstable), leaving the matrix symmetric only to round-off; this is exactly
    /// symmetric.
    pub fn from_upper_contributions(n: usize, mut upper: Vec<(usize, f64)>) -> SymmetricMatrix {
        upper.sort_by_key(|&(key, _)| key);
        let mut asm = SparseAssembler::new(n);
        for run in upper.chunk_by(|x, y| x.0 == y.0) {
            let (j, i) = (run[0].0 / n, run[0].0 % n);
            let v: f64 = run.iter().map(|t| t.1).sum();
            asm.add(i, j, v);
            if i != j {
                asm.add(j, i, v);
            }
        }
        asm.finish()
    }

    /// The principal submatrix on `indices` (in that order). A stencil's whole and its part off
    /// the first layer (a suffix: `M^mod`'s dofs with mass) stay matrix-free
    /// ([`Stencil::without_first_layer`]); everything else is assembled.
    pub fn principal_submatrix(&self, indices: &[usize]) -> SymmetricMatrix {
        if let Storage::Stencil(stencil) = &self.storage {
            let n = self.dim();
            let suffix = indices
                .first()
                .is_some_and(|&first| first + indices.len() == n)
                && indices.windows(2).all(|w| w[1] == w[0] + 1);
            if suffix && indices.len() == n {
                return self.clone();
            }
            if let Some(cut) = stencil
                .without_first_layer()
                .filter(|cut| suffix && cut.dim() == indices.len())
            {
                return Self::from_stencil(cut);
            }
        }
        let mut local = vec![usize::MAX; self.dim()];
        for (k, &i) in indices.iter().enumerate() {
            local[i] = k;
        }
        let mut col_ptr = Vec::with_capacity(indices.len() + 1);
        let mut entries: Vec<(usize, f64)> = Vec::new();
        let mut row_idx = Vec::new();
        let mut val = Vec::new();
        col_ptr.push(0);
        for &j in indices {
            entries.clear();
            self.for_each_in_row(j, |i, v| {
                if local[i] != usize::MAX {
                    entries.push((local[i], v));
                }
            });
            entries.sort_by_key(|&(i, _)| i);
            for &(i, v) in &entries {
                row_idx.push(i);
                val.push(v);
            }
            col_ptr.push(row_idx.len());
        }
        let m = indices.len();
        let symbolic = SymbolicSparseColMat::new_checked(m, m, col_ptr, None, row_idx);
        SymmetricMatrix::from_faer(SparseColMat::new(symbolic, val))
    }
}
