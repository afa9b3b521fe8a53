//! The plan of a reference too large for one machine (issue 36): what references computed here
//! on 1 to 4 ranks cost ([`Measurement`], `signorini reference --measure`), a cost model
//! fitted to them ([`fit`]), and its prediction for a finer reference on `N` nodes of a stated
//! size (`signorini cluster-plan`, `make cluster-plan`).

pub mod fit;
pub mod measurement;
pub mod plan;

pub use measurement::Measurement;
