//! The product preconditioner of a box step matrix `αM + S` from its separable part
//! ([`crate::engine::fem::separable`], where the construction is explained):
//! `P_c = ⊗_k (a M_k + b_ck K_k)` per component, factorised axis by axis and applied as one
//! tridiagonal solve per axis.

use rayon::prelude::*;

use super::{solve_interleaved_rows, solve_lines, TridiagonalLdlt};
use crate::engine::fem::separable::SeparablePart;

/// Entries per parallel task of the solves within layers: the layers are grouped so that a
/// task is worth its scheduling. At 3D level 80 (19 197 entries, about 20 µs of solves) this
/// is one task: against four tasks of 6 144 entries, the 3D level-80 run's stepping took 0.96×
/// the time and 0.97× the CPU time (4 runs of each, in alternation, on the shared 2-core
/// machine); at level 160 (137 241 entries) there are five.
const ENTRIES_PER_TASK: usize = 32768;

/// `blockdiag_c(⊗_k F_ck)⁻¹` on node-major `d`-component dofs, each `F_ck` factorised.
#[derive(Debug, Clone)]
pub struct ProductPreconditioner {
    components: usize,
    nodes_per_axis: Vec<usize>,
    /// `factors[k][c]`.
    factors: Vec<Vec<TridiagonalLdlt>>,
}

impl ProductPreconditioner {
    /// The product preconditioner `P_c = ⊗_k (a M_k + b_ck K_k)` of `part`
    /// ([`crate::engine::fem::separable`]); `None` without a positive mass and a stiffness, or
    /// when a factor is not positive definite.
    pub fn of(part: &SeparablePart) -> Option<ProductPreconditioner> {
        let d = part.components;
        let axes = part.mass_axes.len();
        let complete = part.mass_scale.is_finite()
            && part.mass_scale > 0.0
            && part.coefficients.len() == d * axes
            && part.stiffness_axes.len() == axes;
        if !complete {
            return None;
        }
        let a = part.mass_scale.powf(1.0 / axes as f64);
        let b_scale = a.powi(axes as i32 - 1);
        let mut factors = Vec::with_capacity(axes);
        for k in 0..axes {
            let per_component = (0..d)
                .map(|c| {
                    let b = part.coefficients[c * axes + k] / b_scale;
                    let m = part.mass_axes[k].combine(a, &part.stiffness_axes[k], b);
                    TridiagonalLdlt::factor(&m.diag, &m.off).ok()
                })
                .collect::<Option<Vec<_>>>()?;
            factors.push(per_component);
        }
        Some(ProductPreconditioner {
            components: d,
            nodes_per_axis: part.mass_axes.iter().map(|m| m.diag.len()).collect(),
            factors,
        })
    }

    /// The number of unknowns.
    pub fn dim(&self) -> usize {
        self.components * self.nodes_per_axis.iter().product::<usize>()
    }

    /// `z = P⁻¹ r`: one interleaved tridiagonal solve along each axis, groups of layers in
    /// parallel for the axes within them.
    pub fn solve_into(&self, r: &[f64], z: &mut [f64]) {
        z.copy_from_slice(r);
        self.solve_in_place(z);
    }

    /// `z ← P⁻¹ z` ([`ProductPreconditioner::solve_into`] in place).
    pub fn solve_in_place(&self, z: &mut [f64]) {
        self.solve_within_layers(z);
        let (factors, width) = self.last_axis();
        solve_interleaved_rows(factors, z, width);
    }

    /// The solves of `P⁻¹` along every axis but the last, on `z` made of whole layers of the
    /// last axis (any of them: a layer's solves do not involve another): the part of
    /// [`ProductPreconditioner::solve_in_place`] that a process holding a slab of layers does
    /// alone, before the last axis's sweeps ([`ProductPreconditioner::last_axis`]).
    pub fn solve_within_layers(&self, z: &mut [f64]) {
        let within = self.factors.len().saturating_sub(1);
        let layer = self.components * self.nodes_per_axis[..within].iter().product::<usize>();
        if within == 0 || layer == 0 {
            return;
        }
        // The fewest tasks of about ENTRIES_PER_TASK entries, given equal numbers of layers:
        // a task solves along every axis within its layers, one parallel region for them all.
        let layers = z.len() / layer;
        let tasks = z.len().div_ceil(ENTRIES_PER_TASK).clamp(1, layers.max(1));
        let per_task = layers.div_ceil(tasks).max(1) * layer;
        z.par_chunks_mut(per_task)
            .for_each(|layers| self.solve_layers(layers, within));
    }

    /// The solves along the first `within` axes of `z`, whole layers of them. Along axis `k`
    /// the rows are `width` entries apart (the faster axes and the components) and `z` is a
    /// sequence of independent blocks of `nodes_k · width` entries; along the first axis a
    /// block is one line of nodes, and the lines are solved together ([`solve_lines`]).
    fn solve_layers(&self, z: &mut [f64], within: usize) {
        let mut width = self.components;
        for (factors, &nodes) in self.factors.iter().zip(&self.nodes_per_axis).take(within) {
            if width == self.components {
                solve_lines(factors, z);
            } else {
                z.chunks_exact_mut(nodes * width)
                    .for_each(|b| solve_interleaved_rows(factors, b, width));
            }
            width *= nodes;
        }
    }

    /// The factors of the last axis (one per component) and its row width (the entries of one
    /// layer): `P⁻¹` ends with the interleaved tridiagonal solve of these along the layers.
    pub fn last_axis(&self) -> (&[TridiagonalLdlt], usize) {
        let axes = self.nodes_per_axis.len();
        let layer: usize = self.nodes_per_axis[..axes.saturating_sub(1)]
            .iter()
            .product();
        let factors = self.factors.last().map_or(&[][..], Vec::as_slice);
        (factors, layer * self.components)
    }
}
