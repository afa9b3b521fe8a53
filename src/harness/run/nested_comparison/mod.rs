//! Box runs compared with a finer run on nested meshes: the norm matrices of a mesh
//! ([`norm_matrices::NormMatrices`]), the projections of a fine run on coarser levels recorded while
//! it runs ([`projection::ProjectionRecorder`]), a coarser run compared with it in lockstep in
//! the fine space ([`check`]), the fine side of the projections on a distributed run's slabs
//! ([`slab_fine`]), and the time series of the errors both produce
//! ([`error_series::ErrorSeries`]). The meshes and time grids are nested, so a coarse state is
//! compared with the fine one exactly, at common times; neither trajectory is stored.

pub mod check;
pub mod error_series;
pub mod norm_matrices;
pub mod projection;
pub mod slab_fine;
