//! Finite element spaces and the assembly of mass, stiffness and load.
//!
//! The 1D bar of the paper (P1 elements on `[0, L]`, Section 3.1) lives in [`bar1d`]; the
//! global sparse assembly and the symmetric matrix-vector product in [`sparse`]; the mass-matrix
//! variants (standard, redistributed) in [`mass`]; the prolongation between nested box meshes in
//! [`prolongation`].

pub mod bar1d;
pub mod box_mesh;
pub mod mass;
pub mod prolongation;
pub mod separable;
pub mod sparse;
pub mod stencil;

pub use bar1d::{Bar1d, EndCondition};
pub use box_mesh::{BoxMesh, Elasticity};
pub use mass::MassVariant;
pub use prolongation::Prolongation;
pub use sparse::{SparseAssembler, SymmetricMatrix};
