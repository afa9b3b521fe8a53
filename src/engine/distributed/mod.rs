//! A box's step solve distributed over ranks (issue 36): the box cut into slabs of node layers
//! along its axis, one per rank ([`Slabs`]), each rank holding its slab's rows of the step
//! matrix and its part of every vector.
//!
//! * **Products** ([`SlabCg`]): `y = K x` on a slab reads one layer of each neighbour (the
//!   stencil couples adjacent layers only), exchanged before the product ([`Ranks::exchange`],
//!   even ranks with the rank above first, odd ranks with the rank below first, so that the
//!   pairs meet). Each row is computed as the one-process [`Stencil`] computes it.
//! * **Sums** ([`Ranks::sum`]): every inner product is each rank's partial sum, gathered and
//!   added in rank order; all ranks take every decision of the iteration on the same value,
//!   and a run with `N` ranks is reproducible bit for bit. With one rank every sum is the
//!   one-process sum.
//! * **The preconditioner**: the one-process one, unchanged. Its solves along the axes across
//!   the box are within a layer, so within a slab; the solve along the axis is an LDLᵀ sweep
//!   down the layers and one back up ([`sweep_interleaved_rows`]), passed from rank to rank as
//!   each finishes its layers, the columns of a layer in chunks so that rank `r + 1` sweeps
//!   the first chunk while rank `r` sweeps the second (a pipeline: the ranks idle for
//!   `N − 1` chunks of each sweep). The condensed `Γ_Sig` plane of `M^mod`
//!   ([`CondensedPlane`]) is on rank 0, which holds the plane and the layer it couples to. The
//!   preconditioner is therefore the same operator with any number of ranks, and so are the
//!   iterations: a distributed solve differs from the one-process solve only by the order of
//!   the partial sums of its inner products.
//!
//! The ranks are MPI processes with the `mpi` feature, or threads of one process
//! ([`ThreadRanks`], which the tests use).

#[cfg(feature = "mpi")]
mod mpi_ranks;
mod ranks;
mod slab_balance;
mod slab_cg;
mod slab_one_step;
mod slab_operator;
mod slabs;
mod threads;
mod traffic;

#[cfg(feature = "mpi")]
pub use mpi_ranks::MpiRanks;
pub use ranks::Ranks;
pub use slab_cg::SlabCg;
pub use slab_one_step::{SlabOneStep, SlabRunError};
pub use slab_operator::SlabOperator;
pub use slabs::Slabs;
pub use threads::ThreadRanks;
pub use traffic::{CountedRanks, Traffic};

#[cfg(doc)]
use crate::engine::{
    fem::stencil::Stencil,
    linalg::{sweep_interleaved_rows, CondensedPlane},
};

/// Why a box cannot be decomposed, or solved, over the ranks asked for.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum DecompositionError {
    /// No rank at all.
    #[error("ranks = 0: a distributed run needs at least one rank")]
    NoRanks,
    /// More ranks than the layers can give each one its share.
    #[error(
        "ranks = {ranks}: {layers} node layers along the axis allow at most {most} ranks (rank 0 \
         holds the {first_layers} layers next to Γ_Sig that its plane and contact need, every \
         other rank at least one); use fewer ranks or a finer mesh"
    )]
    TooManyRanks {
        /// The ranks asked for.
        ranks: usize,
        /// The box's node layers along its axis.
        layers: usize,
        /// The most ranks they allow.
        most: usize,
        /// The layers rank 0 needs.
        first_layers: usize,
    },
    /// Rank 0 could not set up what it alone holds (the initial state, the contact operator);
    /// it reports why.
    #[error("rank 0 could not set up the start or the contact operator of Γ_Sig (it reports why)")]
    RankZeroFailed,
    /// The step matrix is not what the distributed solve is for.
    #[error(
        "the distributed step solve needs a matrix-free box step matrix with a product \
         preconditioner; {0}"
    )]
    NotABoxMatrix(&'static str),
}
