//! A rank's rows of a box operator and its products with the neighbours' layers
//! ([`SlabOperator`]).

use std::cell::RefCell;
use std::ops::Range;

use super::{DecompositionError, Ranks, Slabs};
use crate::engine::fem::stencil::Stencil;

/// A rank's slab of a matrix-free box operator `A`: its rows, and the buffer that holds a
/// vector with one layer of each neighbour around the rank's part for a product.
pub struct SlabOperator<'r, R: Ranks + ?Sized> {
    ranks: &'r R,
    /// This rank's rows of `A`.
    rows: Stencil,
    /// This rank's node layers.
    own: Range<usize>,
    /// Unknowns per node layer.
    layer_dofs: usize,
    /// `x` with the neighbours' layers around this rank's: `[below | own | above]`.
    with_halo: RefCell<Vec<f64>>,
}

impl<'r, R: Ranks + ?Sized> SlabOperator<'r, R> {
    /// This rank's share of `a` (the whole box's operator) cut into `slabs`.
    pub fn new(ranks: &'r R, a: &Stencil, slabs: &Slabs) -> Result<Self, DecompositionError> {
        if slabs.layers() != a.node_layers() || slabs.ranks() != ranks.size() {
            return Err(DecompositionError::NotABoxMatrix(
                "its layers or the ranks do not match the decomposition",
            ));
        }
        let own = slabs.of(ranks.rank());
        let rows = a
            .layers(own.clone())
            .ok_or(DecompositionError::NotABoxMatrix("its layers do not match"))?;
        let layer_dofs = a.nodes_per_layer() * a.components();
        let halo_layers = usize::from(own.start > 0) + usize::from(own.end < slabs.layers());
        Ok(Self {
            ranks,
            with_halo: RefCell::new(vec![0.0; (own.len() + halo_layers) * layer_dofs]),
            rows,
            own,
            layer_dofs,
        })
    }

    /// The range of the whole box's unknowns this rank holds.
    pub fn own_dofs(&self) -> Range<usize> {
        self.own.start * self.layer_dofs..self.own.end * self.layer_dofs
    }

    /// This rank's rows of `A`.
    pub fn rows(&self) -> &Stencil {
        &self.rows
    }

    /// `y = A x` on this rank's rows (`x`, `y` its parts), returning its part of `xᵀ y`: the
    /// neighbours' layers exchanged first, then each row computed as in one process. Every
    /// rank calls it together.
    pub fn mul_dot(&self, x: &[f64], y: &mut [f64]) -> f64 {
        let mut with_halo = self.with_halo.borrow_mut();
        let below = if self.own.start > 0 {
            self.layer_dofs
        } else {
            0
        };
        with_halo[below..below + x.len()].copy_from_slice(x);
        self.exchange_halos(&mut with_halo, below, x.len());
        self.rows
            .mul_dot_with_halo(&with_halo, below / self.rows.components(), y)
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
}
