//! The contact face `Γ_C = {x_d = 0}` of another code's mesh ([`ContactFace`]): the points on
//! it and each point's share of it, `a_i = ∫_{Γ_C} φ_i`, the lumped face mass of its shape
//! function `φ_i` (half of each edge in 2D; a third of each triangle, and the bilinear shape
//! function's integral over each quadrilateral, in 3D).
//!
//! The shares turn nodal contact forces into a pressure that is a function on the face,
//! comparable between meshes whose contact nodes differ (docs/src/external-runs.md, "A code's
//! own mesh"): a code's nodal multiplier `λ_i` is a force, the integral of the pressure against
//! `φ_i`, so `p_i = λ_i / a_i` is the pressure at point `i` as a lumped face mass recovers it,
//! and the pressure at any point of the face is the face's interpolant of the `p_i`. That
//! interpolant is the trace of the cells' own interpolant ([`ElementMesh::evaluate`] at a point
//! of the face): a shape function of a vertex off a facet vanishes on it.

use super::function::{q1_shape, ElementMesh};

/// The points of a mesh on its contact face and their shares of it.
#[derive(Debug, Clone, PartialEq)]
pub struct ContactFace {
    /// `a_i = ∫_{Γ_C} φ_i` per point of the mesh (0 off the face).
    shares: Vec<f64>,
}

impl ContactFace {
    /// The contact face of `mesh`: the cells' facets whose vertices all lie on `x_d = 0`
    /// (within `tolerance`), each facet's measure shared among its vertices.
    pub fn of(mesh: &ElementMesh, tolerance: f64) -> Self {
        let d = mesh.dim();
        let points = mesh.points();
        let on = |p: &[f64; 3]| p[d - 1].abs() <= tolerance;
        let mut shares = vec![0.0; points.len()];
        for cell in mesh.cells() {
            for facet in cell.kind.facets() {
                let vertices: Vec<usize> = facet.iter().map(|&a| cell.vertices[a]).collect();
                if !vertices.iter().all(|&v| on(&points[v])) {
                    continue;
                }
                let corners: Vec<[f64; 3]> = vertices.iter().map(|&v| points[v]).collect();
                for (v, share) in vertices.iter().zip(facet_shares(&corners)) {
                    shares[*v] += share;
                }
            }
        }
        Self { shares }
    }

    /// `a_i` of point `i` (0 off the face).
    #[cfg(test)]
    fn share(&self, i: usize) -> f64 {
        self.shares[i]
    }

    /// Whether point `i` is on the face (its share is positive).
    pub fn holds(&self, i: usize) -> bool {
        self.shares[i] > 0.0
    }

    /// The face's measure: `Σ_i a_i` (the shape functions sum to 1).
    pub fn measure(&self) -> f64 {
        self.shares.iter().sum()
    }

    /// The resultant `Σ_i λ_i` of nodal forces `lambda` (one per point of the mesh) over the
    /// face's points.
    pub fn resultant(&self, lambda: &[f64]) -> f64 {
        lambda
            .iter()
            .zip(&self.shares)
            .filter(|(_, &a)| a > 0.0)
            .map(|(l, _)| l)
            .sum()
    }

    /// The pressure of nodal forces `lambda` at the point `x` of the face: the interpolant of
    /// `p_i = λ_i / a_i` evaluated through the cells of `mesh` (this face's mesh); `None` when
    /// no cell holds `x`.
    pub fn pressure_at(&self, mesh: &ElementMesh, lambda: &[f64], x: [f64; 3]) -> Option<f64> {
        let d = mesh.dim();
        let mut field = vec![0.0; lambda.len() * d];
        for (i, (&l, &a)) in lambda.iter().zip(&self.shares).enumerate() {
            if a > 0.0 {
                field[i * d] = l / a;
            }
        }
        mesh.evaluate(&field, x).map(|e| e.value[0])
    }
}

/// `∫ φ_a` over the facet of `corners` (on the plane `x_d = 0`) for each of its vertices: an
/// edge's half length each, a triangle's third of its area, and for a quadrilateral (vertices in
/// cyclic order) the bilinear shape functions' integrals by 2 × 2 Gauss points (exact: the
/// integrand is bilinear times the map's Jacobian, linear per axis).
fn facet_shares(corners: &[[f64; 3]]) -> Vec<f64> {
    let difference = |a: [f64; 3], b: [f64; 3]| [b[0] - a[0], b[1] - a[1]];
    match corners.len() {
        2 => {
            let [dx, dy] = difference(corners[0], corners[1]);
            vec![0.5 * dx.hypot(dy); 2]
        }
        3 => {
            let ([ax, ay], [bx, by]) = (
                difference(corners[0], corners[1]),
                difference(corners[0], corners[2]),
            );
            vec![(ax * by - ay * bx).abs() / 6.0; 3]
        }
        _ => {
            let g = 1.0 / 3f64.sqrt();
            let mut shares = vec![0.0; 4];
            for (s, t) in [(-g, -g), (g, -g), (g, g), (-g, g)] {
                let (shape, derivative) = q1_shape(2, [s, t, 0.0]);
                let mut jacobian = [[0.0; 2]; 2];
                for (a, corner) in corners.iter().enumerate() {
                    for c in 0..2 {
                        for j in 0..2 {
                            jacobian[c][j] += derivative[a][j] * corner[c];
                        }
                    }
                }
                let det = (jacobian[0][0] * jacobian[1][1] - jacobian[0][1] * jacobian[1][0]).abs();
                for (share, n) in shares.iter_mut().zip(shape) {
                    *share += n * det;
                }
            }
            shares
        }
    }
}

#[cfg(test)]
pub(super) mod tests {
    use super::*;
    use crate::harness::external::mesh::{Cell, CellKind};

    /// The box `lengths` cut into `n` cells per axis, each square split into two triangles or
    /// each cube into six Kuhn tetrahedra.
    pub(in crate::harness::external::mesh) fn split_box(lengths: &[f64], n: usize) -> ElementMesh {
        let d = lengths.len();
        let per = n + 1;
        let index = |i: [usize; 3]| i[0] + per * (i[1] + per * i[2]);
        let mut points = Vec::new();
        for k in 0..if d == 3 { per } else { 1 } {
            for j in 0..per {
                for i in 0..per {
                    let mut p = [0.0; 3];
                    for (c, m) in [i, j, k].into_iter().enumerate().take(d) {
                        p[c] = lengths[c] * m as f64 / n as f64;
                    }
                    points.push(p);
                }
            }
        }
        let mut cells = Vec::new();
        for k in 0..if d == 3 { n } else { 1 } {
            for j in 0..n {
                for i in 0..n {
                    let at = |di: usize, dj: usize, dk: usize| index([i + di, j + dj, k + dk]);
                    if d == 2 {
                        cells.push([at(0, 0, 0), at(1, 0, 0), at(1, 1, 0)].to_vec());
                        cells.push([at(0, 0, 0), at(1, 1, 0), at(0, 1, 0)].to_vec());
                        continue;
                    }
                    let (a, b) = (at(0, 0, 0), at(1, 1, 1));
                    for path in [
                        [at(1, 0, 0), at(1, 1, 0)],
                        [at(1, 0, 0), at(1, 0, 1)],
                        [at(0, 1, 0), at(1, 1, 0)],
                        [at(0, 1, 0), at(0, 1, 1)],
                        [at(0, 0, 1), at(1, 0, 1)],
                        [at(0, 0, 1), at(0, 1, 1)],
                    ] {
                        cells.push(vec![a, path[0], path[1], b]);
                    }
                }
            }
        }
        let kind = if d == 2 {
            CellKind::Triangle
        } else {
            CellKind::Tetrahedron
        };
        let cells = cells
            .into_iter()
            .map(|vertices| Cell { kind, vertices })
            .collect();
        ElementMesh::new(d, points, cells).unwrap()
    }

    #[test]
    fn shares_sum_to_the_face_and_recover_a_linear_pressure() {
        for lengths in [vec![0.1, 1.0], vec![0.1, 0.2, 1.0]] {
            let d = lengths.len();
            let mesh = split_box(&lengths, 4);
            let face = ContactFace::of(&mesh, 1e-12);
            let area: f64 = lengths[..d - 1].iter().product();
            approx::assert_relative_eq!(face.measure(), area, max_relative = 1e-14);
            // Nodal forces of the linear pressure p(x) = 2 + 3 x1 lumped: λ_i = p(x_i) a_i.
            let pressure = |p: &[f64; 3]| 2.0 + 3.0 * p[0];
            let lambda: Vec<f64> = mesh
                .points()
                .iter()
                .enumerate()
                .map(|(i, p)| pressure(p) * face.share(i))
                .collect();
            let x = [
                0.3 * lengths[0],
                if d == 3 { 0.6 * lengths[1] } else { 0.0 },
                0.0,
            ];
            let at = face.pressure_at(&mesh, &lambda, x).unwrap();
            approx::assert_relative_eq!(at, pressure(&x), max_relative = 1e-12);
            let total: f64 = lambda.iter().sum();
            approx::assert_relative_eq!(face.resultant(&lambda), total, max_relative = 1e-14);
            let off = (0..mesh.points().len()).filter(|&i| !face.holds(i)).count();
            assert_eq!(off, mesh.points().len() - (5usize).pow(d as u32 - 1));
        }
    }

    #[test]
    fn a_quadrilateral_facet_shares_its_bilinear_integrals() {
        // A trapezoid: the bilinear shape functions' integrals are not a quarter each.
        let corners = [
            [0.0, 0.0, 0.0],
            [2.0, 0.0, 0.0],
            [1.5, 1.0, 0.0],
            [0.5, 1.0, 0.0],
        ];
        let shares = facet_shares(&corners);
        approx::assert_relative_eq!(shares.iter().sum::<f64>(), 1.5, max_relative = 1e-14);
        // The map's Jacobian is (3 − η)/8 on [−1, 1]², so ∫ N_0 = ∫∫ (1 − ξ)(1 − η)(3 − η)/32
        // = 5/12 and ∫ N_2 = ∫∫ (1 + ξ)(1 + η)(3 − η)/32 = 1/3.
        approx::assert_relative_eq!(shares[0], 5.0 / 12.0, max_relative = 1e-14);
        approx::assert_relative_eq!(shares[2], 1.0 / 3.0, max_relative = 1e-14);
    }
}
