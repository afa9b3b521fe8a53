//! The cells of another code's mesh: what a snapshot's file says of them ([`Topology`]) and the
//! elements the harness interpolates ([`CellKind`]): linear triangles and quadrilaterals in 2D,
//! linear tetrahedra and hexahedra in 3D. A cell of any other type (a pixel, a voxel, a
//! quadratic or higher-order cell, a polygon) is refused by name, never read as another
//! element.

mod cells;

pub use cells::{CellKind, Cells, Topology, ALLOWED_CELLS};
