//! Prolongation between nested Q1 box meshes: the coarse field written exactly in the fine
//! space.
//!
//! When every fine element lies in one coarse element (the fine counts are integer multiples
//! `r_k` of the coarse ones), the coarse Q1 space is a subspace of the fine one and
//! `u_H = Σ_j U_j φ^H_j` has the fine nodal values
//! ```text
//! (P U)_i = u_H(a_i) = Σ_j U_j φ^H_j(a_i),
//! ```
//! the multilinear interpolation of the coarse nodal values at the fine node `a_i`. The
//! difference `P U_H − U_h` is then a fine finite element function whose norms are exact
//! quadratic forms of the fine mass and stiffness matrices: no quadrature error enters the
//! comparison with a fine-mesh reference (note §3).

use std::ops::Range;

use super::BoxMesh;
use crate::engine::error::ParameterError;

/// The prolongation `P` from a coarse to a nested fine box mesh, stored row by row (each fine
/// dof is a weighted sum of at most `2^d` coarse dofs): the whole of it, or the rows of a slab
/// of the fine mesh's node layers along its axis ([`Prolongation::of_layers`]), which read a
/// contiguous range of the coarse dofs ([`Prolongation::coarse_range`]).
#[derive(Debug, Clone, PartialEq)]
pub struct Prolongation {
    /// The coarse dofs the rows read; columns are relative to its start.
    coarse_range: Range<usize>,
    row_start: Vec<usize>,
    columns: Vec<usize>,
    weights: Vec<f64>,
}

impl Prolongation {
    /// The prolongation from `coarse` to `fine`. Errors (field `mesh`) when the boxes differ or
    /// a fine count is not a multiple of the coarse one.
    pub fn new(coarse: &BoxMesh, fine: &BoxMesh) -> Result<Self, ParameterError> {
        let layers = fine.counts()[fine.dim() - 1] + 1;
        let mut whole = Self::of_layers(coarse, fine, 0..layers)?;
        whole
            .columns
            .iter_mut()
            .for_each(|c| *c += whole.coarse_range.start);
        whole.coarse_range = 0..coarse.n_dofs();
        Ok(whole)
    }

    /// The rows of `P` (`coarse` to `fine`) of the dofs of the fine nodes whose index along the
    /// axis is in `layers`, in the fine numbering's order (a layer's dofs are contiguous, the
    /// axis being the slowest); their columns relative to the start of the coarse dofs they
    /// read, [`Prolongation::coarse_range`]. Errors as [`Prolongation::new`].
    pub fn of_layers(
        coarse: &BoxMesh,
        fine: &BoxMesh,
        layers: Range<usize>,
    ) -> Result<Self, ParameterError> {
        let d = coarse.dim();
        let nested = fine.dim() == d
            && coarse.lengths() == fine.lengths()
            && coarse
                .counts()
                .iter()
                .zip(fine.counts())
                .all(|(&c, &f)| f % c == 0);
        if !nested {
            return Err(ParameterError::new(
                "mesh",
                format!(
                    "{:?} elements inside {:?} elements",
                    coarse.counts(),
                    fine.counts()
                ),
                "nested meshes of the same box: every fine count a multiple of the coarse one",
            ));
        }
        let factor: Vec<usize> = coarse
            .counts()
            .iter()
            .zip(fine.counts())
            .map(|(&c, &f)| f / c)
            .collect();
        let coarse_node = |index: &[usize; 3]| -> usize {
            (0..d)
                .rev()
                .fold(0, |acc, k| acc * (coarse.counts()[k] + 1) + index[k])
        };
        let per_layer: usize = fine.counts()[..d - 1].iter().map(|n| n + 1).product();
        let layers =
            layers.start.min(fine.counts()[d - 1] + 1)..layers.end.min(fine.counts()[d - 1] + 1);
        let mut rows: Vec<(usize, Vec<(usize, f64)>)> = Vec::new();
        for node in layers.start * per_layer..layers.end * per_layer {
            let fine_index = fine.node_index(node);
            let mut base = [0usize; 3];
            let mut fraction = [0.0; 3];
            for k in 0..d {
                base[k] = fine_index[k] / factor[k];
                let rest = fine_index[k] % factor[k];
                fraction[k] = rest as f64 / factor[k] as f64;
            }
            let mut sources = Vec::with_capacity(1 << d);
            for corner in 0..(1usize << d) {
                let mut index = base;
                let mut weight = 1.0;
                for k in 0..d {
                    let upper = corner >> k & 1 == 1;
                    if upper {
                        index[k] += 1;
                        weight *= fraction[k];
                    } else {
                        weight *= 1.0 - fraction[k];
                    }
                }
                if weight != 0.0 {
                    sources.push((coarse_node(&index), weight));
                }
            }
            for c in 0..d {
                let Some(to) = fine.dof_of(node, c) else {
                    continue;
                };
                let row = (sources.iter())
                    .filter_map(|&(source, w)| coarse.dof_of(source, c).map(|from| (from, w)))
                    .collect();
                rows.push((to, row));
            }
        }
        debug_assert!(
            rows.windows(2).all(|w| w[0].0 + 1 == w[1].0),
            "contiguous rows"
        );
        let first = (rows.iter().flat_map(|(_, r)| r.iter().map(|&(c, _)| c)))
            .min()
            .unwrap_or(0);
        let last = (rows.iter().flat_map(|(_, r)| r.iter().map(|&(c, _)| c + 1)))
            .max()
            .unwrap_or(0);
        let mut row_start = Vec::with_capacity(rows.len() + 1);
        row_start.push(0);
        let mut columns = Vec::new();
        let mut weights = Vec::new();
        for (_, row) in rows {
            for (col, w) in row {
                columns.push(col - first);
                weights.push(w);
            }
            row_start.push(columns.len());
        }
        Ok(Self {
            coarse_range: first..last.max(first),
            row_start,
            columns,
            weights,
        })
    }

    /// The coarse dofs the rows read: `apply_into` takes them, `restrict_into` writes them.
    pub fn coarse_range(&self) -> Range<usize> {
        self.coarse_range.clone()
    }

    /// Number of fine dofs (rows).
    pub fn fine_dofs(&self) -> usize {
        self.row_start.len() - 1
    }

    /// Number of coarse dofs (columns): those of [`Prolongation::coarse_range`].
    pub fn coarse_dofs(&self) -> usize {
        self.coarse_range.len()
    }

    /// `out = P u`.
    pub fn apply_into(&self, u: &[f64], out: &mut [f64]) {
        assert_eq!(u.len(), self.coarse_dofs(), "coarse dof vector length");
        assert_eq!(out.len(), self.fine_dofs(), "fine dof vector length");
        for (i, o) in out.iter_mut().enumerate() {
            let range = self.row_start[i]..self.row_start[i + 1];
            *o = self.columns[range.clone()]
                .iter()
                .zip(&self.weights[range])
                .map(|(&j, w)| w * u[j])
                .sum();
        }
    }

    /// `out = Pᵀ v`: the restriction of a fine functional to the coarse space (with `v = M_h u`,
    /// `(Pᵀ v)_j = ∫ ρ u φ^H_j`, the coarse load vector of the fine field).
    pub fn restrict_into(&self, v: &[f64], out: &mut [f64]) {
        assert_eq!(v.len(), self.fine_dofs(), "fine dof vector length");
        assert_eq!(out.len(), self.coarse_dofs(), "coarse dof vector length");
        out.fill(0.0);
        for (i, vi) in v.iter().enumerate() {
            let range = self.row_start[i]..self.row_start[i + 1];
            for (&j, w) in self.columns[range.clone()].iter().zip(&self.weights[range]) {
                out[j] += w * vi;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Q1 functions that vanish on the Dirichlet face `z = 1` (coarse finite element functions).
    fn bilinear(x: &[f64]) -> [f64; 3] {
        let top = 1.0 - x[1];
        [(1.0 + 2.0 * x[0]) * top, (0.5 - x[0]) * top, 0.0]
    }

    fn trilinear(x: &[f64]) -> [f64; 3] {
        let top = 1.0 - x[2];
        [
            x[0] * x[1] * top,
            (1.0 + x[1]) * top,
            (x[0] - 2.0 * x[1]) * top,
        ]
    }

    #[test]
    fn reproduces_the_fine_interpolant_of_a_coarse_q1_function_in_2d() {
        let coarse = BoxMesh::new(&[0.1, 1.0], &[1, 5]).unwrap();
        let fine = BoxMesh::new(&[0.1, 1.0], &[4, 20]).unwrap();
        let p = Prolongation::new(&coarse, &fine).unwrap();
        let mut out = vec![0.0; fine.n_dofs()];
        p.apply_into(&coarse.interpolate(bilinear), &mut out);
        let expected = fine.interpolate(bilinear);
        for (a, b) in out.iter().zip(&expected) {
            assert!((a - b).abs() < 1e-14, "{a} vs {b}");
        }
    }

    #[test]
    fn reproduces_the_fine_interpolant_of_a_coarse_q1_function_in_3d() {
        let coarse = BoxMesh::new(&[0.1, 0.1, 1.0], &[1, 1, 4]).unwrap();
        let fine = BoxMesh::new(&[0.1, 0.1, 1.0], &[2, 2, 8]).unwrap();
        let p = Prolongation::new(&coarse, &fine).unwrap();
        let mut out = vec![0.0; fine.n_dofs()];
        p.apply_into(&coarse.interpolate(trilinear), &mut out);
        let expected = fine.interpolate(trilinear);
        for (a, b) in out.iter().zip(&expected) {
            assert!((a - b).abs() < 1e-14, "{a} vs {b}");
        }
    }

    /// `(P u)ᵀ v = uᵀ (Pᵀ v)` for every `u`, `v`: the restriction is the prolongation's
    /// transpose.
    #[test]
    fn restriction_is_the_transpose_of_the_prolongation() {
        let coarse = BoxMesh::new(&[0.1, 0.1, 1.0], &[1, 1, 3]).unwrap();
        let fine = BoxMesh::new(&[0.1, 0.1, 1.0], &[2, 2, 6]).unwrap();
        let p = Prolongation::new(&coarse, &fine).unwrap();
        let u: Vec<f64> = (0..p.coarse_dofs()).map(|i| (i as f64).sin()).collect();
        let v: Vec<f64> = (0..p.fine_dofs()).map(|i| (i as f64 * 0.7).cos()).collect();
        let (mut pu, mut ptv) = (vec![0.0; p.fine_dofs()], vec![0.0; p.coarse_dofs()]);
        p.apply_into(&u, &mut pu);
        p.restrict_into(&v, &mut ptv);
        let lhs: f64 = pu.iter().zip(&v).map(|(a, b)| a * b).sum();
        let rhs: f64 = u.iter().zip(&ptv).map(|(a, b)| a * b).sum();
        assert!(
            (lhs - rhs).abs() < 1e-13 * lhs.abs().max(1.0),
            "{lhs} vs {rhs}"
        );
    }

    /// A slab's rows are the whole prolongation's rows of its layers, reading its coarse
    /// range: `P_slab u[range] = (P u)[slab]`, and the slabs' restrictions add up to `Pᵀ v`.
    #[test]
    fn the_rows_of_slabs_of_layers_are_the_whole_prolongation_cut() {
        let coarse = BoxMesh::new(&[0.1, 0.1, 1.0], &[1, 1, 3]).unwrap();
        let fine = BoxMesh::new(&[0.1, 0.1, 1.0], &[2, 2, 12]).unwrap();
        let whole = Prolongation::new(&coarse, &fine).unwrap();
        let u: Vec<f64> = (0..whole.coarse_dofs()).map(|i| (i as f64).sin()).collect();
        let v: Vec<f64> = (0..whole.fine_dofs())
            .map(|i| (i as f64 * 0.7).cos())
            .collect();
        let (mut pu, mut ptv) = (vec![0.0; whole.fine_dofs()], vec![0.0; whole.coarse_dofs()]);
        whole.apply_into(&u, &mut pu);
        whole.restrict_into(&v, &mut ptv);
        let layer_dofs = 9 * 3;
        let mut summed = vec![0.0; whole.coarse_dofs()];
        for layers in [0..2, 2..7, 7..13] {
            let slab = Prolongation::of_layers(&coarse, &fine, layers.clone()).unwrap();
            let rows = layers.start * layer_dofs..(layers.end * layer_dofs).min(v.len());
            assert_eq!(slab.fine_dofs(), rows.len());
            let mut part = vec![0.0; slab.fine_dofs()];
            slab.apply_into(&u[slab.coarse_range()], &mut part);
            assert_eq!(part, pu[rows.clone()]);
            let mut restricted = vec![0.0; slab.coarse_dofs()];
            slab.restrict_into(&v[rows], &mut restricted);
            for (s, r) in summed[slab.coarse_range()].iter_mut().zip(&restricted) {
                *s += r;
            }
        }
        for (a, b) in summed.iter().zip(&ptv) {
            assert!((a - b).abs() < 1e-14, "{a} vs {b}");
        }
    }

    #[test]
    fn rejects_meshes_that_are_not_nested() {
        let coarse = BoxMesh::new(&[0.1, 1.0], &[2, 4]).unwrap();
        let fine = BoxMesh::new(&[0.1, 1.0], &[3, 8]).unwrap();
        let err = Prolongation::new(&coarse, &fine).unwrap_err();
        assert_eq!(err.name, "mesh");
        let other_box = BoxMesh::new(&[0.2, 1.0], &[4, 8]).unwrap();
        assert!(Prolongation::new(&coarse, &other_box).is_err());
    }
}
