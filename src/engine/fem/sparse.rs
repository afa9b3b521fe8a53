//! Sparse symmetric matrices: assembly from element contributions and allocation-free products.

use faer::sparse::{SparseColMat, Triplet};

/// A symmetric sparse matrix stored with both triangles (faer CSC).
///
/// Both triangles are stored because faer's Cholesky silently returns a wrong answer when the
/// stored triangle does not match the requested side (DEPENDENCIES.md, faer gotchas). A matrix
/// of bandwidth one (every 1D P1 matrix) also keeps its two diagonals, so that the products of
/// the time loop run as contiguous loops instead of indexed gathers.
#[derive(Debug, Clone)]
pub struct SymmetricMatrix {
    inner: SparseColMat<usize, f64>,
    tridiagonal: Option<Tridiagonal>,
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

    fn mul_into(&self, x: &[f64], y: &mut [f64]) {
        let n = x.len();
        for i in 0..n {
            let mut acc = self.d[i] * x[i];
            if i > 0 {
                acc += self.l[i - 1] * x[i - 1];
            }
            if i + 1 < n {
                acc += self.l[i] * x[i + 1];
            }
            y[i] = acc;
        }
    }

    fn bilinear_form(&self, x: &[f64], y: &[f64]) -> f64 {
        let diag: f64 = self
            .d
            .iter()
            .zip(x)
            .zip(y)
            .map(|((d, a), b)| d * a * b)
            .sum();
        let off: f64 = self
            .l
            .iter()
            .zip(x.windows(2).zip(y.windows(2)))
            .map(|(l, (xw, yw))| l * (xw[0] * yw[1] + xw[1] * yw[0]))
            .sum();
        diag + off
    }
}

impl SymmetricMatrix {
    /// Wraps a faer matrix that the caller guarantees to be symmetric with both triangles stored.
    pub fn from_faer(inner: SparseColMat<usize, f64>) -> Self {
        debug_assert_eq!(inner.nrows(), inner.ncols());
        let tridiagonal = Tridiagonal::of(&inner);
        Self { inner, tridiagonal }
    }

    /// The number of rows (= columns).
    pub fn dim(&self) -> usize {
        self.inner.nrows()
    }

    /// The faer matrix.
    pub fn as_faer(&self) -> &SparseColMat<usize, f64> {
        &self.inner
    }

    /// Entry `(i, j)`, zero when not stored.
    pub fn get(&self, i: usize, j: usize) -> f64 {
        self.inner.get(i, j).copied().unwrap_or(0.0)
    }

    /// Calls `f(j, A_ij)` for every stored entry of row `i` (column `i`, by symmetry).
    pub fn for_each_in_row(&self, i: usize, mut f: impl FnMut(usize, f64)) {
        let sym = self.inner.symbolic();
        let range = sym.col_ptr()[i]..sym.col_ptr()[i + 1];
        for (&j, &v) in sym.row_idx()[range.clone()]
            .iter()
            .zip(&self.inner.val()[range])
        {
            f(j, v);
        }
    }

    /// `y = A x`, without allocation. Uses symmetry: row `i` of `A` is its column `i`.
    pub fn mul_into(&self, x: &[f64], y: &mut [f64]) {
        if let Some(t) = &self.tridiagonal {
            return t.mul_into(x, y);
        }
        let sym = self.inner.symbolic();
        let col_ptr = sym.col_ptr();
        let row_idx = sym.row_idx();
        let val = self.inner.val();
        for (i, yi) in y.iter_mut().enumerate() {
            let range = col_ptr[i]..col_ptr[i + 1];
            *yi = row_idx[range.clone()]
                .iter()
                .zip(&val[range])
                .map(|(&r, &v)| v * x[r])
                .sum();
        }
    }

    /// The quadratic form `xᵀ A x`.
    pub fn quadratic_form(&self, x: &[f64]) -> f64 {
        self.bilinear_form(x, x)
    }

    /// The bilinear form `xᵀ A y`.
    pub fn bilinear_form(&self, x: &[f64], y: &[f64]) -> f64 {
        if let Some(t) = &self.tridiagonal {
            return t.bilinear_form(x, y);
        }
        let sym = self.inner.symbolic();
        let col_ptr = sym.col_ptr();
        let row_idx = sym.row_idx();
        let val = self.inner.val();
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

    /// `a·self + b·other`, on the union of both sparsity patterns.
    pub fn linear_combination(&self, a: f64, other: &SymmetricMatrix, b: f64) -> SymmetricMatrix {
        let mut assembler = SparseAssembler::new(self.dim());
        assembler.add_scaled(self, a);
        assembler.add_scaled(other, b);
        assembler.finish()
    }

    /// The largest `|i - j|` over stored entries.
    pub fn bandwidth(&self) -> usize {
        let sym = self.inner.symbolic();
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
        self.inner.val().iter().sum()
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
        let a = m.as_faer();
        let sym = a.symbolic();
        for j in 0..m.dim() {
            let range = sym.col_ptr()[j]..sym.col_ptr()[j + 1];
            for (&i, &v) in sym.row_idx()[range.clone()].iter().zip(&a.val()[range]) {
                self.add(i, j, scale * v);
            }
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
        let a = self.as_faer();
        let sym = a.symbolic();
        let mut upper: Vec<(usize, f64)> = Vec::new();
        for (b, row_b) in rows.iter().enumerate() {
            let range = sym.col_ptr()[b]..sym.col_ptr()[b + 1];
            for (&ra, &v) in sym.row_idx()[range.clone()].iter().zip(&a.val()[range]) {
                for &(i, wi) in &rows[ra] {
                    for &(j, wj) in row_b {
                        if i <= j {
                            upper.push((j * n + i, v * wi * wj));
                        }
                    }
                }
            }
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

    /// The principal submatrix on `indices` (in that order).
    pub fn principal_submatrix(&self, indices: &[usize]) -> SymmetricMatrix {
        let mut local = vec![usize::MAX; self.dim()];
        for (k, &i) in indices.iter().enumerate() {
            local[i] = k;
        }
        let a = self.as_faer();
        let sym = a.symbolic();
        let mut asm = SparseAssembler::new(indices.len());
        for (kj, &j) in indices.iter().enumerate() {
            let range = sym.col_ptr()[j]..sym.col_ptr()[j + 1];
            for (&i, &v) in sym.row_idx()[range.clone()].iter().zip(&a.val()[range]) {
                if local[i] != usize::MAX {
                    asm.add(local[i], kj, v);
                }
            }
        }
        asm.finish()
    }
}
