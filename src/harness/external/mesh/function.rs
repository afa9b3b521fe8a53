//! A finite element function on a conforming mesh of linear cells ([`ElementMesh`]): its
//! points, its cells (P1 triangles and tetrahedra, Q1 quadrilaterals and hexahedra), a bucket
//! grid over the cells to locate a point, and the field's value and gradient there.
//!
//! A point `x` is located in a cell by its local coordinates: barycentric for a simplex (the
//! affine map inverted exactly), `ξ ∈ [−1, 1]^d` for a Q1 cell (the multilinear map inverted by
//! Newton's method from the cell's centre, [`NEWTON_STEPS`] at most; one step on a
//! parallelogram or a parallelepiped, where the map is affine). The point is in the cell when
//! every local coordinate is inside within [`INSIDE_TOLERANCE`]; a point on a face shared by two
//! cells is given to the first cell of the bucket that holds it (the value is the same, the
//! gradient jumps: a quadrature that places points on such faces carries that in its own error,
//! [`super::pair`]).

// Components and axes are indexed as the formulas write them (`J[c][j]`, `∂N_a/∂ξ_j`).
#![allow(clippy::needless_range_loop)]

use crate::engine::fem::box_mesh::{BoxMesh, HEX_CORNERS, QUAD_CORNERS};

use super::cells::{CellKind, Cells};

/// How far outside its cell a located point's local coordinates may be: barycentric
/// coordinates down to `−1e-10`, Q1 coordinates up to `1 + 1e-10` in magnitude.
pub const INSIDE_TOLERANCE: f64 = 1e-10;

/// The most Newton steps that invert a Q1 cell's map.
pub const NEWTON_STEPS: usize = 20;

/// One cell: its kind and its vertices (indices of the mesh's points, VTK's order).
#[derive(Debug, Clone, PartialEq)]
pub struct Cell {
    /// Its element.
    pub kind: CellKind,
    /// Its vertices.
    pub vertices: Vec<usize>,
}

/// A conforming mesh of linear cells in dimension 2 or 3, with a bucket grid over its cells.
#[derive(Debug, Clone)]
pub struct ElementMesh {
    dim: usize,
    points: Vec<[f64; 3]>,
    cells: Vec<Cell>,
    /// The bucket grid: its lower corner, its bucket sizes and counts per axis.
    origin: [f64; 3],
    bucket: [f64; 3],
    buckets: [usize; 3],
    /// Per bucket, the cells whose bounding box meets it.
    members: Vec<Vec<usize>>,
}

/// A field's value (`d` components, the rest 0) and gradient (`∂u_c/∂x_j` at `[c][j]`) at a
/// point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Evaluation {
    /// `u(x)`.
    pub value: [f64; 3],
    /// `∇u(x)`.
    pub gradient: [[f64; 3]; 3],
}

impl ElementMesh {
    /// The mesh of `points` (three coordinates each, the ones past `dim` ignored) and `cells`
    /// of dimension `dim`; `Err` names a cell of another dimension or one whose vertices are not
    /// its kind's count.
    pub fn new(dim: usize, points: Vec<[f64; 3]>, cells: Vec<Cell>) -> Result<Self, String> {
        if let Some((k, c)) = cells
            .iter()
            .enumerate()
            .find(|(_, c)| c.kind.dim() != dim || c.vertices.len() != c.kind.vertices())
        {
            return Err(format!(
                "cell {k}: a {} of {} vertices in a {dim}D mesh",
                c.kind.name(),
                c.vertices.len()
            ));
        }
        let mut lower = [0.0; 3];
        let mut upper = [0.0; 3];
        for c in 0..dim {
            lower[c] = points.iter().map(|p| p[c]).fold(f64::INFINITY, f64::min);
            upper[c] = points
                .iter()
                .map(|p| p[c])
                .fold(f64::NEG_INFINITY, f64::max);
        }
        let per_axis = ((cells.len().max(1) as f64).powf(1.0 / dim as f64).ceil() as usize).max(1);
        let mut buckets = [1usize; 3];
        let mut bucket = [1.0; 3];
        for c in 0..dim {
            buckets[c] = per_axis;
            bucket[c] = ((upper[c] - lower[c]) / per_axis as f64).max(f64::MIN_POSITIVE);
        }
        let mut mesh = Self {
            dim,
            points,
            cells,
            origin: lower,
            bucket,
            buckets,
            members: vec![Vec::new(); buckets.iter().product()],
        };
        for k in 0..mesh.cells.len() {
            let (lo, hi) = mesh.cell_box(k);
            let (a, b) = (mesh.bucket_of(lo), mesh.bucket_of(hi));
            for i in a[0]..=b[0] {
                for j in a[1]..=b[1] {
                    for l in a[2]..=b[2] {
                        let at = i + buckets[0] * (j + buckets[1] * l);
                        mesh.members[at].push(k);
                    }
                }
            }
        }
        Ok(mesh)
    }

    /// The mesh of a VTK grid's `points` and `cells` in dimension `dim`; `Err` names the first
    /// cell whose type the harness does not interpolate.
    pub fn of_cells(dim: usize, points: Vec<[f64; 3]>, cells: &Cells) -> Result<Self, String> {
        let cells = cells
            .iter()
            .enumerate()
            .map(|(k, (vtk, vertices))| {
                CellKind::of_vtk(vtk, vertices.len())
                    .map(|kind| Cell {
                        kind,
                        vertices: vertices.to_vec(),
                    })
                    .ok_or_else(|| {
                        format!("cell {k}: VTK cell type {vtk} of {} points", vertices.len())
                    })
            })
            .collect::<Result<Vec<_>, _>>()?;
        Self::new(dim, points, cells)
    }

    /// The structured Q1 mesh `mesh` as cells: its nodes and its elements.
    pub fn of_box(mesh: &BoxMesh) -> Self {
        let kind = if mesh.dim() == 2 {
            CellKind::Quadrilateral
        } else {
            CellKind::Hexahedron
        };
        let cells = mesh
            .elements()
            .map(|nodes| Cell {
                kind,
                vertices: nodes.to_vec(),
            })
            .collect();
        Self::new(mesh.dim(), mesh.nodes().collect(), cells).expect("a box mesh's elements")
    }

    /// Its dimension.
    pub fn dim(&self) -> usize {
        self.dim
    }

    /// Its points.
    pub fn points(&self) -> &[[f64; 3]] {
        &self.points
    }

    /// Its cells.
    pub fn cells(&self) -> &[Cell] {
        &self.cells
    }

    /// The lower and upper corners of cell `k`'s bounding box.
    fn cell_box(&self, k: usize) -> ([f64; 3], [f64; 3]) {
        let mut lo = [0.0; 3];
        let mut hi = [0.0; 3];
        for c in 0..self.dim {
            let xs = self.cells[k].vertices.iter().map(|&v| self.points[v][c]);
            lo[c] = xs.clone().fold(f64::INFINITY, f64::min);
            hi[c] = xs.fold(f64::NEG_INFINITY, f64::max);
        }
        (lo, hi)
    }

    /// The bucket that holds `x`, clamped to the grid.
    fn bucket_of(&self, x: [f64; 3]) -> [usize; 3] {
        let mut index = [0usize; 3];
        for c in 0..self.dim {
            let i = ((x[c] - self.origin[c]) / self.bucket[c]).floor();
            index[c] = i.clamp(0.0, (self.buckets[c] - 1) as f64) as usize;
        }
        index
    }

    /// The cell that holds `x` and `x`'s local coordinates in it, if a cell does.
    pub fn locate(&self, x: [f64; 3]) -> Option<(usize, [f64; 3])> {
        let b = self.bucket_of(x);
        let at = b[0] + self.buckets[0] * (b[1] + self.buckets[1] * b[2]);
        self.members[at].iter().find_map(|&k| {
            let local = self.local(k, x)?;
            Some((k, local))
        })
    }

    /// The local coordinates of `x` in cell `k` when `x` is in it ([`INSIDE_TOLERANCE`]):
    /// barycentric `λ₁, …, λ_d` (`λ₀ = 1 − Σ λ_i`) for a simplex, `ξ` for a Q1 cell.
    fn local(&self, k: usize, x: [f64; 3]) -> Option<[f64; 3]> {
        let cell = &self.cells[k];
        let d = self.dim;
        let corner = |a: usize| self.points[cell.vertices[a]];
        if cell.kind.is_simplex() {
            let x0 = corner(0);
            let mut jacobian = [[0.0; 3]; 3];
            for (a, column) in (1..=d).enumerate() {
                for c in 0..d {
                    jacobian[c][a] = corner(column)[c] - x0[c];
                }
            }
            let mut rhs = [0.0; 3];
            for c in 0..d {
                rhs[c] = x[c] - x0[c];
            }
            let lambda = solve(d, jacobian, rhs)?;
            let sum: f64 = lambda[..d].iter().sum();
            let inside = lambda[..d].iter().all(|&l| l >= -INSIDE_TOLERANCE)
                && sum <= 1.0 + INSIDE_TOLERANCE;
            return inside.then_some(lambda);
        }
        let mut xi = [0.0; 3];
        for _ in 0..NEWTON_STEPS {
            let (shape, derivative) = q1_shape(d, xi);
            let mut residual = [0.0; 3];
            let mut jacobian = [[0.0; 3]; 3];
            for (a, &v) in cell.vertices.iter().enumerate() {
                for c in 0..d {
                    residual[c] += shape[a] * self.points[v][c];
                    for j in 0..d {
                        jacobian[c][j] += derivative[a][j] * self.points[v][c];
                    }
                }
            }
            for c in 0..d {
                residual[c] = x[c] - residual[c];
            }
            let step = solve(d, jacobian, residual)?;
            let mut moved = 0.0f64;
            for j in 0..d {
                xi[j] += step[j];
                moved = moved.max(step[j].abs());
            }
            if moved <= 1e-14 {
                break;
            }
        }
        xi[..d]
            .iter()
            .all(|v| v.abs() <= 1.0 + INSIDE_TOLERANCE)
            .then_some(xi)
    }

    /// The field `values` (`d` per point) and its gradient at `x`, if a cell holds `x`.
    pub fn evaluate(&self, values: &[f64], x: [f64; 3]) -> Option<Evaluation> {
        let (k, local) = self.locate(x)?;
        Some(self.evaluate_in(k, local, values))
    }

    /// The field `values` and its gradient at the local coordinates `local` of cell `k`.
    pub fn evaluate_in(&self, k: usize, local: [f64; 3], values: &[f64]) -> Evaluation {
        let cell = &self.cells[k];
        let d = self.dim;
        let n = cell.vertices.len();
        // The shape functions and their derivatives in the local coordinates, and the
        // Jacobian ∂x/∂(local) of the cell's map.
        let mut shape = [0.0; 8];
        let mut derivative = [[0.0; 3]; 8];
        if cell.kind.is_simplex() {
            shape[0] = 1.0 - local[..d].iter().sum::<f64>();
            for a in 1..=d {
                shape[a] = local[a - 1];
                derivative[a][a - 1] = 1.0;
            }
            for j in 0..d {
                derivative[0][j] = -1.0;
            }
        } else {
            let (s, ds) = q1_shape(d, local);
            shape = s;
            derivative = ds;
        }
        let mut jacobian = [[0.0; 3]; 3];
        for a in 0..n {
            let p = self.points[cell.vertices[a]];
            for c in 0..d {
                for j in 0..d {
                    jacobian[c][j] += derivative[a][j] * p[c];
                }
            }
        }
        let inverse = inverse(d, jacobian);
        let mut value = [0.0; 3];
        let mut gradient = [[0.0; 3]; 3];
        for a in 0..n {
            let v = cell.vertices[a];
            // ∂N_a/∂x_j = Σ_i ∂N_a/∂ξ_i ∂ξ_i/∂x_j.
            let mut dx = [0.0; 3];
            for j in 0..d {
                for i in 0..d {
                    dx[j] += derivative[a][i] * inverse[i][j];
                }
            }
            for c in 0..d {
                let u = values[v * d + c];
                value[c] += shape[a] * u;
                for j in 0..d {
                    gradient[c][j] += dx[j] * u;
                }
            }
        }
        Evaluation { value, gradient }
    }

    /// The signed measure of cell `k` (area or volume: a simplex's exactly, a Q1 cell's by
    /// 2-point Gauss per axis, exact for parallelograms and parallelepipeds).
    pub fn measure(&self, k: usize) -> f64 {
        let cell = &self.cells[k];
        let d = self.dim;
        let corner = |a: usize| self.points[cell.vertices[a]];
        if cell.kind.is_simplex() {
            let mut jacobian = [[0.0; 3]; 3];
            for (a, column) in (1..=d).enumerate() {
                for c in 0..d {
                    jacobian[c][a] = corner(column)[c] - corner(0)[c];
                }
            }
            let factorial = if d == 2 { 2.0 } else { 6.0 };
            return determinant(d, jacobian) / factorial;
        }
        let g = 1.0 / 3f64.sqrt();
        corners(d)
            .iter()
            .map(|s| self.jacobian_determinant(k, [s[0] * g, s[1] * g, s[2] * g]))
            .sum()
    }

    /// `|det J|` of Q1 cell `k`'s map at its local coordinates `xi`: the volume element of its
    /// quadrature ([`super::energy`]).
    pub fn volume_element(&self, k: usize, xi: [f64; 3]) -> f64 {
        self.jacobian_determinant(k, xi).abs()
    }

    /// `det J` of Q1 cell `k`'s map at `xi`.
    fn jacobian_determinant(&self, k: usize, xi: [f64; 3]) -> f64 {
        let cell = &self.cells[k];
        let d = self.dim;
        let (_, derivative) = q1_shape(d, xi);
        let mut jacobian = [[0.0; 3]; 3];
        for (a, &v) in cell.vertices.iter().enumerate() {
            for c in 0..d {
                for j in 0..d {
                    jacobian[c][j] += derivative[a][j] * self.points[v][c];
                }
            }
        }
        determinant(d, jacobian)
    }
}

/// The reference corners of a Q1 cell in VTK's order, three coordinates each (0 past `d`).
pub fn corners(d: usize) -> Vec<[f64; 3]> {
    if d == 2 {
        QUAD_CORNERS.iter().map(|c| [c[0], c[1], 0.0]).collect()
    } else {
        HEX_CORNERS.to_vec()
    }
}

/// The Q1 shape functions `N_a(ξ) = Π_i (1 + s_ai ξ_i) / 2` on `[−1, 1]^d` (corners `s_a` in
/// VTK's order) and their derivatives `∂N_a/∂ξ_j` at `[a][j]`.
pub fn q1_shape(d: usize, xi: [f64; 3]) -> ([f64; 8], [[f64; 3]; 8]) {
    let mut shape = [0.0; 8];
    let mut derivative = [[0.0; 3]; 8];
    for (a, s) in corners(d).iter().enumerate() {
        let factor = |i: usize| 0.5 * (1.0 + s[i] * xi[i]);
        shape[a] = (0..d).map(factor).product();
        for j in 0..d {
            derivative[a][j] = (0..d)
                .map(|i| if i == j { 0.5 * s[i] } else { factor(i) })
                .product();
        }
    }
    (shape, derivative)
}

/// The determinant of the leading `d × d` block of `m`.
fn determinant(d: usize, m: [[f64; 3]; 3]) -> f64 {
    if d == 2 {
        m[0][0] * m[1][1] - m[0][1] * m[1][0]
    } else {
        m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
            - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
            + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
    }
}

/// The inverse of the leading `d × d` block of `m` (cofactors over the determinant).
fn inverse(d: usize, m: [[f64; 3]; 3]) -> [[f64; 3]; 3] {
    let det = determinant(d, m);
    let mut inv = [[0.0; 3]; 3];
    if d == 2 {
        inv[0][0] = m[1][1] / det;
        inv[0][1] = -m[0][1] / det;
        inv[1][0] = -m[1][0] / det;
        inv[1][1] = m[0][0] / det;
        return inv;
    }
    for i in 0..3 {
        for j in 0..3 {
            let (r0, r1) = ((j + 1) % 3, (j + 2) % 3);
            let (c0, c1) = ((i + 1) % 3, (i + 2) % 3);
            inv[i][j] = (m[r0][c0] * m[r1][c1] - m[r0][c1] * m[r1][c0]) / det;
        }
    }
    inv
}

/// The solution of `m y = b` (leading `d × d` block), `None` when `m` is singular.
fn solve(d: usize, m: [[f64; 3]; 3], b: [f64; 3]) -> Option<[f64; 3]> {
    let det = determinant(d, m);
    if det == 0.0 || !det.is_finite() {
        return None;
    }
    let inv = inverse(d, m);
    let mut y = [0.0; 3];
    for i in 0..d {
        for j in 0..d {
            y[i] += inv[i][j] * b[j];
        }
    }
    Some(y)
}
