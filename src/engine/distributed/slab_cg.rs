//! Preconditioned conjugate gradients on a slab of a box ([`SlabCg`]): the one-process
//! iteration ([`conjugate_gradient`]) in the space of the rank's part of the vectors.

use std::cell::RefCell;
use std::ops::Range;

use super::{DecompositionError, Ranks, SlabOperator, Slabs};
use crate::engine::error::SolveError;
use crate::engine::fem::SymmetricMatrix;
use crate::engine::linalg::{
    conjugate_gradient, dot, jacobi, sweep_interleaved_rows, CgSpace, CondensedPlane, PcgWork,
    ProductPreconditioner, RowBlock, Sweep,
};

/// The chunks the columns of a layer are cut into for the pipelined sweeps along the axis
/// (with more than one rank): enough that the ranks idle for a small part of a sweep, few
/// enough that a message is worth its latency.
const SWEEP_CHUNKS: usize = 8;

/// A rank's share of the preconditioned CG solve of a box step matrix `K` (module
/// documentation of [`crate::engine::distributed`]): its slab's rows of `K`, its part of the
/// preconditioner, and the buffers of its exchanges.
pub struct SlabCg<'r, R: Ranks + ?Sized> {
    ranks: &'r R,
    slabs: Slabs,
    /// This rank's rows of `K`.
    rows: SlabOperator<'r, R>,
    /// `P⁻¹` on this rank's part.
    preconditioner: SlabPreconditioner,
    /// A chunk of a neighbour's row, received.
    carry: RefCell<Vec<f64>>,
    tolerance: f64,
}

/// A rank's part of the preconditioner `P⁻¹` of [`SlabCg`]: the one-process one
/// ([`crate::engine::linalg::Pcg`]) cut along the slabs.
enum SlabPreconditioner {
    /// The product preconditioner, with the condensed `Γ_Sig` plane on rank 0 when `K`'s plane
    /// is massless.
    Product {
        /// The product preconditioner (of the interior when the plane is condensed).
        product: ProductPreconditioner,
        /// The condensed plane, on rank 0.
        plane: Option<Box<CondensedPlane>>,
        /// Where this rank's part of the product preconditioner begins in its vectors (after
        /// the plane on rank 0 when it is condensed).
        start: usize,
        /// The index of this rank's first layer among the product preconditioner's layers.
        first_layer: usize,
        /// The column chunks of the sweeps along the axis.
        chunks: Vec<Range<usize>>,
    },
    /// `D⁻¹` on this rank's rows, `D = diag K`, for a matrix without a product
    /// preconditioner (the mass alone).
    Jacobi(Vec<f64>),
}

impl<'r, R: Ranks + ?Sized> SlabCg<'r, R> {
    /// This rank's share of the solve of `k` (the whole box's step matrix, matrix-free, with
    /// its separable part), to the relative residual `tolerance`, the box cut evenly
    /// ([`Slabs::even`]) with at least `first_layers` layers on rank 0 (and the two its
    /// condensed plane needs when `k`'s plane is massless). Refused for an assembled matrix or
    /// more ranks than the layers allow.
    pub fn new(
        ranks: &'r R,
        k: &SymmetricMatrix,
        first_layers: usize,
        tolerance: f64,
    ) -> Result<Self, DecompositionError> {
        let stencil = k
            .stencil()
            .ok_or(DecompositionError::NotABoxMatrix("this one is assembled"))?;
        let condensed = stencil
            .separable_part()
            .is_some_and(CondensedPlane::applies_to);
        let first_layers = if condensed {
            first_layers.max(Slabs::FIRST_LAYERS_CONDENSED)
        } else {
            first_layers
        };
        let slabs = Slabs::even(stencil.node_layers(), ranks.size(), first_layers)?;
        Self::on_slabs(ranks, k, slabs, tolerance)
    }

    /// [`SlabCg::new`] on the given decomposition `slabs` (rank 0 holding at least two layers
    /// when `k`'s plane is massless). The preconditioner is the one-process one: the product
    /// preconditioner of `k`'s separable part, with its massless plane condensed, or Jacobi's
    /// when `k` has none (the mass alone).
    pub fn on_slabs(
        ranks: &'r R,
        k: &SymmetricMatrix,
        slabs: Slabs,
        tolerance: f64,
    ) -> Result<Self, DecompositionError> {
        let stencil = k
            .stencil()
            .ok_or(DecompositionError::NotABoxMatrix("this one is assembled"))?;
        let rows = SlabOperator::new(ranks, stencil, &slabs)?;
        let own = slabs.of(ranks.rank());
        let product = |part| ProductPreconditioner::of(part).filter(|p| p.dim() == k.dim());
        let preconditioner = match stencil.separable_part() {
            Some(part) if CondensedPlane::applies_to(part) => {
                if own.start == 0 && own.len() < Slabs::FIRST_LAYERS_CONDENSED {
                    return Err(DecompositionError::NotABoxMatrix(
                        "its condensed plane needs two layers on rank 0",
                    ));
                }
                let plane = (own.start == 0)
                    .then(|| CondensedPlane::of(k, part).map(Box::new))
                    .flatten();
                let interior = match &plane {
                    Some(plane) => Some(plane.interior().clone()),
                    None => ProductPreconditioner::of(&part.without_first_layer()),
                };
                let interior = interior.ok_or(DecompositionError::NotABoxMatrix(
                    "its product preconditioner does not exist",
                ))?;
                let start = plane.as_ref().map_or(0, |p| p.plane_dofs());
                SlabPreconditioner::Product {
                    chunks: column_chunks(&interior, ranks.size()),
                    product: interior,
                    first_layer: (own.start + usize::from(plane.is_some())) - 1,
                    plane,
                    start,
                }
            }
            Some(part) if product(part).is_some() => {
                let product = product(part).expect("just checked");
                SlabPreconditioner::Product {
                    chunks: column_chunks(&product, ranks.size()),
                    product,
                    plane: None,
                    start: 0,
                    first_layer: own.start,
                }
            }
            _ => {
                let rows = rows.rows();
                SlabPreconditioner::Jacobi((0..rows.dim()).map(|i| 1.0 / rows.get(i, i)).collect())
            }
        };
        let widest = match &preconditioner {
            SlabPreconditioner::Product { chunks, .. } => {
                chunks.iter().map(ExactSizeIterator::len).max().unwrap_or(0)
            }
            SlabPreconditioner::Jacobi(_) => 0,
        };
        Ok(Self {
            ranks,
            slabs,
            rows,
            preconditioner,
            carry: RefCell::new(vec![0.0; widest]),
            tolerance,
        })
    }

    /// The range of the whole box's unknowns this rank holds.
    pub fn own_dofs(&self) -> Range<usize> {
        self.rows.own_dofs()
    }

    /// The decomposition.
    pub fn slabs(&self) -> &Slabs {
        &self.slabs
    }

    /// Solves `K x = b` from the initial guess in `x` (this rank's parts of both), overwriting
    /// `x` with the solution, and returns the iterations spent: the same on every rank.
    pub fn solve(&self, b: &[f64], x: &mut [f64], work: &mut PcgWork) -> Result<usize, SolveError> {
        conjugate_gradient(self, self.tolerance, b, x, work)
    }

    /// The LDLᵀ sweeps of the product preconditioner along the axis on this rank's layers
    /// `z` (module documentation of [`crate::engine::distributed`]): down, each chunk of
    /// columns started from the rank below's last row, then up, from the rank above's first.
    fn sweep_along_axis(
        &self,
        product: &ProductPreconditioner,
        first_layer: usize,
        chunks: &[Range<usize>],
        z: &mut [f64],
    ) {
        let (factors, width) = product.last_axis();
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
            for columns in chunks {
                let carry = &mut carry[..columns.len()];
                if let Some(from) = from {
                    self.ranks.receive(from, carry);
                }
                let block = RowBlock {
                    first: first_layer,
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

impl<R: Ranks + ?Sized> CgSpace for SlabCg<'_, R> {
    fn mul_dot(&self, x: &[f64], y: &mut [f64]) -> f64 {
        self.rows.mul_dot(x, y)
    }

    fn precondition(&self, r: &[f64], z: &mut [f64]) -> f64 {
        let (product, plane, start, first_layer, chunks) = match &self.preconditioner {
            SlabPreconditioner::Jacobi(inverse_diagonal) => return jacobi(inverse_diagonal, r, z),
            SlabPreconditioner::Product {
                product,
                plane,
                start,
                first_layer,
                chunks,
            } => (product, plane, *start, *first_layer, chunks),
        };
        let (r_p, r_i) = r.split_at(start);
        let (z_p, z_i) = z.split_at_mut(start);
        z_i.copy_from_slice(r_i);
        if let Some(plane) = plane {
            plane.eliminate_plane(r_p, z_p, z_i);
        }
        product.solve_within_layers(z_i);
        self.sweep_along_axis(product, first_layer, chunks, z_i);
        if let Some(plane) = plane {
            plane.back_substitute_plane(r_p, z_p, z_i);
        }
        dot(r, z)
    }

    fn sum(&self, part: f64) -> f64 {
        self.ranks.sum(part)
    }
}

/// The column chunks of a layer of `product`'s last axis for `ranks` ranks: one chunk for one
/// rank (nothing to pipeline), otherwise [`SWEEP_CHUNKS`] of whole nodes (so that a chunk
/// starts on a node's first component).
fn column_chunks(product: &ProductPreconditioner, ranks: usize) -> Vec<Range<usize>> {
    let (factors, width) = product.last_axis();
    let components = factors.len().max(1);
    let nodes = width / components;
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
