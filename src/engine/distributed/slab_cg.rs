//! Preconditioned conjugate gradients on a slab of a box ([`SlabCg`]): the one-process
//! iteration ([`conjugate_gradient`]) in the space of the rank's part of the vectors.

use std::cell::RefCell;
use std::ops::Range;

use super::{DecompositionError, Ranks, Slabs};
use crate::engine::error::SolveError;
use crate::engine::fem::stencil::Stencil;
use crate::engine::fem::SymmetricMatrix;
use crate::engine::linalg::{
    conjugate_gradient, sweep_interleaved_rows, CgSpace, CondensedPlane, PcgWork,
    ProductPreconditioner, RowBlock, Sweep,
};

/// The chunks the columns of a layer are cut into for the pipelined sweeps along the axis
/// (with more than one rank): enough that the ranks idle for a small part of a sweep, few
/// enough that a message is worth its latency.
const SWEEP_CHUNKS: usize = 8;

/// A rank's share of the preconditioned CG solve of a box step matrix `K` (module
/// documentation of [`crate::engine::distributed`]): its slab's rows of `K`, its part of the
/// preconditioner, and the buffers of its exchanges.
pub struct SlabCg<'r, R: Ranks> {
    ranks: &'r R,
    slabs: Slabs,
    /// This rank's rows of `K`.
    rows: Stencil,
    /// Unknowns per node layer.
    layer_dofs: usize,
    /// `x` with the neighbours' layers around this rank's: `[below | own | above]`.
    with_halo: RefCell<Vec<f64>>,
    /// The product preconditioner (of the interior when the plane is condensed).
    product: ProductPreconditioner,
    /// The condensed `Γ_Sig` plane, on rank 0 when `K`'s plane is massless.
    plane: Option<CondensedPlane>,
    /// Where this rank's part of the product preconditioner begins in its vectors (after the
    /// plane on rank 0 when it is condensed).
    product_start: usize,
    /// The index of this rank's first layer among the product preconditioner's layers.
    product_first_layer: usize,
    /// The column chunks of the sweeps along the axis.
    chunks: Vec<Range<usize>>,
    /// A chunk of a neighbour's row, received.
    carry: RefCell<Vec<f64>>,
    tolerance: f64,
}

impl<'r, R: Ranks> SlabCg<'r, R> {
    /// This rank's share of the solve of `k` (the whole box's step matrix, matrix-free, with
    /// its separable part), to the relative residual `tolerance`, the box cut evenly
    /// ([`Slabs::even`]) with at least `first_layers` layers on rank 0 (and the two its
    /// condensed plane needs when `k`'s plane is massless). Refused for an assembled matrix, one
    /// without a product preconditioner, or more ranks than the layers allow.
    pub fn new(
        ranks: &'r R,
        k: &SymmetricMatrix,
        first_layers: usize,
        tolerance: f64,
    ) -> Result<Self, DecompositionError> {
        let stencil = k
            .stencil()
            .ok_or(DecompositionError::NotABoxMatrix("this one is assembled"))?;
        let part = stencil
            .separable_part()
            .ok_or(DecompositionError::NotABoxMatrix(
                "this one has no separable part",
            ))?;
        let condensed = CondensedPlane::applies_to(part);
        let first_layers = if condensed {
            first_layers.max(Slabs::FIRST_LAYERS_CONDENSED)
        } else {
            first_layers
        };
        let slabs = Slabs::even(stencil.node_layers(), ranks.size(), first_layers)?;
        let own = slabs.of(ranks.rank());
        let rows = stencil
            .layers(own.clone())
            .ok_or(DecompositionError::NotABoxMatrix("its layers do not match"))?;
        let layer_dofs = stencil.nodes_per_layer() * stencil.components();
        let no_product =
            DecompositionError::NotABoxMatrix("its product preconditioner does not exist");
        let (product, plane) = match (condensed, ranks.rank()) {
            (true, 0) => {
                let plane = CondensedPlane::of(k, part).ok_or(no_product)?;
                (plane.interior().clone(), Some(plane))
            }
            (true, _) => (
                ProductPreconditioner::of(&part.without_first_layer()).ok_or(no_product)?,
                None,
            ),
            (false, _) => (ProductPreconditioner::of(part).ok_or(no_product)?, None),
        };
        let product_start = plane.as_ref().map_or(0, CondensedPlane::plane_dofs);
        let product_first_layer = own.start + usize::from(plane.is_some()) - usize::from(condensed);
        let halo_layers = usize::from(own.start > 0) + usize::from(own.end < slabs.layers());
        let chunks = column_chunks(layer_dofs, stencil.components(), ranks.size());
        let widest = chunks.iter().map(ExactSizeIterator::len).max().unwrap_or(0);
        Ok(Self {
            ranks,
            with_halo: RefCell::new(vec![0.0; (own.len() + halo_layers) * layer_dofs]),
            slabs,
            rows,
            layer_dofs,
            product,
            plane,
            product_start,
            product_first_layer,
            chunks,
            carry: RefCell::new(vec![0.0; widest]),
            tolerance,
        })
    }

    /// The decomposition.
    pub fn slabs(&self) -> &Slabs {
        &self.slabs
    }

    /// The range of the whole box's unknowns this rank holds.
    pub fn own_dofs(&self) -> Range<usize> {
        let own = self.slabs.of(self.ranks.rank());
        own.start * self.layer_dofs..own.end * self.layer_dofs
    }

    /// Solves `K x = b` from the initial guess in `x` (this rank's parts of both), overwriting
    /// `x` with the solution, and returns the iterations spent: the same on every rank.
    pub fn solve(&self, b: &[f64], x: &mut [f64], work: &mut PcgWork) -> Result<usize, SolveError> {
        conjugate_gradient(self, self.tolerance, b, x, work)
    }

    /// The neighbours' layers next to this rank's, into `with_halo` around its own part
    /// (`below` entries before it, `own` entries long): even ranks exchange with the rank
    /// above first, odd ranks with the rank below, so that every pair meets.
    fn exchange_halos(&self, with_halo: &mut [f64], below: usize, own: usize) {
        let (rank, size) = (self.ranks.rank(), self.ranks.size());
        let up = (rank + 1 < size).then_some(rank + 1);
        let down = rank.checked_sub(1);
        let order = if rank % 2 == 0 {
            [up, down]
        } else {
            [down, up]
        };
        let layer = self.layer_dofs;
        for neighbour in order.into_iter().flatten() {
            if neighbour > rank {
                let (mine, theirs) = with_halo.split_at_mut(below + own);
                self.ranks.exchange(
                    neighbour,
                    &mine[below + own - layer..],
                    &mut theirs[..layer],
                );
            } else {
                let (theirs, mine) = with_halo.split_at_mut(below);
                self.ranks.exchange(neighbour, &mine[..layer], theirs);
            }
        }
    }

    /// The LDLᵀ sweeps of the product preconditioner along the axis on this rank's layers
    /// `z` (module documentation of [`crate::engine::distributed`]): down, each chunk of
    /// columns started from the rank below's last row, then up, from the rank above's first.
    fn sweep_along_axis(&self, z: &mut [f64]) {
        let (factors, width) = self.product.last_axis();
        let (rank, size) = (self.ranks.rank(), self.ranks.size());
        let rows = z.len() / width.max(1);
        let mut carry = self.carry.borrow_mut();
        for sweep in [Sweep::Down, Sweep::Up] {
            let (from, to, sent_row) = match sweep {
                Sweep::Down => (
                    rank.checked_sub(1),
                    (rank + 1 < size).then_some(rank + 1),
                    rows - 1,
                ),
                Sweep::Up => (
                    (rank + 1 < size).then_some(rank + 1),
                    rank.checked_sub(1),
                    0,
                ),
            };
            for columns in &self.chunks {
                let carry = &mut carry[..columns.len()];
                if let Some(from) = from {
                    self.ranks.receive(from, carry);
                }
                let block = RowBlock {
                    first: self.product_first_layer,
                    width,
                    columns: columns.clone(),
                };
                sweep_interleaved_rows(factors, z, &block, sweep, carry);
                if let Some(to) = to {
                    let start = sent_row * width;
                    self.ranks
                        .send(to, &z[start + columns.start..start + columns.end]);
                }
            }
        }
    }
}

impl<R: Ranks> CgSpace for SlabCg<'_, R> {
    fn mul_dot(&self, x: &[f64], y: &mut [f64]) -> f64 {
        let mut with_halo = self.with_halo.borrow_mut();
        let below = if self.ranks.rank() > 0 {
            self.layer_dofs
        } else {
            0
        };
        with_halo[below..below + x.len()].copy_from_slice(x);
        self.exchange_halos(&mut with_halo, below, x.len());
        self.rows
            .mul_dot_with_halo(&with_halo, below / self.rows.components(), y)
    }

    fn precondition(&self, r: &[f64], z: &mut [f64]) -> f64 {
        let (r_p, r_i) = r.split_at(self.product_start);
        let (z_p, z_i) = z.split_at_mut(self.product_start);
        z_i.copy_from_slice(r_i);
        if let Some(plane) = &self.plane {
            plane.eliminate_plane(r_p, z_p, z_i);
        }
        self.product.solve_within_layers(z_i);
        self.sweep_along_axis(z_i);
        if let Some(plane) = &self.plane {
            plane.back_substitute_plane(r_p, z_p, z_i);
        }
        r.iter().zip(z.iter()).map(|(a, b)| a * b).sum()
    }

    fn sum(&self, part: f64) -> f64 {
        self.ranks.sum(part)
    }
}

/// The column chunks of a layer of `width` entries for `ranks` ranks: one chunk for one rank
/// (nothing to pipeline), otherwise [`SWEEP_CHUNKS`] of whole nodes (`components` entries, so
/// that a chunk starts on a node's first component).
fn column_chunks(width: usize, components: usize, ranks: usize) -> Vec<Range<usize>> {
    let nodes = width / components.max(1);
    let chunks = if ranks > 1 {
        SWEEP_CHUNKS.min(nodes)
    } else {
        1
    }
    .max(1);
    (0..chunks)
        .map(|k| (k * nodes / chunks) * components..((k + 1) * nodes / chunks) * components)
        .filter(|c| !c.is_empty())
        .collect()
}
