//! The cells of another code's mesh: what a snapshot's file says of them ([`Topology`]) and the
//! elements the harness interpolates ([`CellKind`]): linear triangles and quadrilaterals in 2D,
//! linear tetrahedra and hexahedra in 3D. A cell of any other type (a pixel, a voxel, a
//! quadratic or higher-order cell, a polygon) is refused by name, never read as another
//! element.
//!
//! A field on such a mesh is a finite element function ([`ElementMesh`]: a point located in its
//! cell through a bucket grid, the field and its gradient evaluated there), and its distance to
//! a reference on the scene's structured mesh is defined once for the pair of meshes
//! ([`pair_errors`], by a stated quadrature), after the mesh is checked to cover the scene's box
//! ([`check_domain`]). Its contact face's points and their shares of it ([`ContactFace`]) turn
//! nodal contact forces into a resultant and a pressure comparable between meshes.

mod cells;
mod energy;
mod face;
mod function;
mod pair;

pub use cells::{CellKind, Cells, Topology, ALLOWED_CELLS};
pub use energy::{cell_energy, MassCells};
pub use face::ContactFace;
pub use function::{q1_shape, Cell, ElementMesh, Evaluation, INSIDE_TOLERANCE, NEWTON_STEPS};
pub use pair::{
    check_domain, gauss_legendre, pair_errors, pair_errors_each, PairErrors, Quadrature,
    DOMAIN_TOLERANCE,
};
