//! A snapshot's cells as its file gives them, and the element kinds the harness interpolates.

/// The cells the harness interpolates, as its refusals list them.
pub const ALLOWED_CELLS: &str = "linear cells: triangles (VTK 5, or Lagrange 69 of 3 nodes), \
                                 quadrilaterals (VTK 9, or Lagrange 70 of 4 nodes), tetrahedra \
                                 (VTK 10, or Lagrange 71 of 4 nodes), hexahedra (VTK 12, or \
                                 Lagrange 72 of 8 nodes); XDMF's Triangle, Quadrilateral, \
                                 Tetrahedron, Hexahedron";

/// An element the harness interpolates: its vertices in VTK's order (a Lagrange cell of the
/// lowest order lists the same vertices in the same order as the linear cell).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum CellKind {
    /// P1 triangle (`VTK_TRIANGLE`).
    Triangle,
    /// Q1 quadrilateral (`VTK_QUAD`: counter-clockwise).
    Quadrilateral,
    /// P1 tetrahedron (`VTK_TETRA`).
    Tetrahedron,
    /// Q1 hexahedron (`VTK_HEXAHEDRON`: the face `ξ₃ = −1` counter-clockwise, then the
    /// opposite face).
    Hexahedron,
}

impl CellKind {
    /// The kind of a VTK cell of type `vtk` with `nodes` nodes: a linear cell, or a Lagrange
    /// cell (VTK 69–72) of the linear cell's node count; `None` for any other.
    pub fn of_vtk(vtk: u8, nodes: usize) -> Option<Self> {
        let kind = match vtk {
            5 | 69 => Self::Triangle,
            9 | 70 => Self::Quadrilateral,
            10 | 71 => Self::Tetrahedron,
            12 | 72 => Self::Hexahedron,
            _ => return None,
        };
        (nodes == kind.vertices()).then_some(kind)
    }

    /// The kind of XDMF's `TopologyType` `name` (`None` for any other, `Mixed` included).
    pub fn of_xdmf(name: &str) -> Option<Self> {
        match name {
            "Triangle" => Some(Self::Triangle),
            "Quadrilateral" => Some(Self::Quadrilateral),
            "Tetrahedron" => Some(Self::Tetrahedron),
            "Hexahedron" => Some(Self::Hexahedron),
            _ => None,
        }
    }

    /// Its linear VTK cell type.
    pub fn vtk(self) -> u8 {
        match self {
            Self::Triangle => 5,
            Self::Quadrilateral => 9,
            Self::Tetrahedron => 10,
            Self::Hexahedron => 12,
        }
    }

    /// Its dimension.
    pub fn dim(self) -> usize {
        match self {
            Self::Triangle | Self::Quadrilateral => 2,
            Self::Tetrahedron | Self::Hexahedron => 3,
        }
    }

    /// Its vertices: its nodes.
    pub fn vertices(self) -> usize {
        match self {
            Self::Triangle => 3,
            Self::Quadrilateral | Self::Tetrahedron => 4,
            Self::Hexahedron => 8,
        }
    }

    /// Whether it is a simplex (P1) rather than a tensor-product cell (Q1).
    pub fn is_simplex(self) -> bool {
        matches!(self, Self::Triangle | Self::Tetrahedron)
    }

    /// Its edges, as pairs of its vertices (VTK's order).
    pub fn edges(self) -> &'static [[usize; 2]] {
        match self {
            Self::Triangle => &[[0, 1], [1, 2], [2, 0]],
            Self::Quadrilateral => &[[0, 1], [1, 2], [2, 3], [3, 0]],
            Self::Tetrahedron => &[[0, 1], [1, 2], [2, 0], [0, 3], [1, 3], [2, 3]],
            Self::Hexahedron => &[
                [0, 1],
                [1, 2],
                [2, 3],
                [3, 0],
                [4, 5],
                [5, 6],
                [6, 7],
                [7, 4],
                [0, 4],
                [1, 5],
                [2, 6],
                [3, 7],
            ],
        }
    }

    /// Its facets (edges in 2D, faces in 3D), each as its vertices in a cyclic order.
    pub fn facets(self) -> &'static [&'static [usize]] {
        match self {
            Self::Triangle => &[&[0, 1], &[1, 2], &[2, 0]],
            Self::Quadrilateral => &[&[0, 1], &[1, 2], &[2, 3], &[3, 0]],
            Self::Tetrahedron => &[&[0, 1, 2], &[0, 1, 3], &[1, 2, 3], &[0, 2, 3]],
            Self::Hexahedron => &[
                &[0, 1, 2, 3],
                &[4, 5, 6, 7],
                &[0, 1, 5, 4],
                &[1, 2, 6, 5],
                &[2, 3, 7, 6],
                &[3, 0, 4, 7],
            ],
        }
    }

    /// Its name in the plural.
    pub fn plural(self) -> &'static str {
        match self {
            Self::Triangle => "triangles",
            Self::Quadrilateral => "quadrilaterals",
            Self::Tetrahedron => "tetrahedra",
            Self::Hexahedron => "hexahedra",
        }
    }

    /// Its name, as the harness's messages say it.
    pub fn name(self) -> &'static str {
        match self {
            Self::Triangle => "triangle",
            Self::Quadrilateral => "quadrilateral",
            Self::Tetrahedron => "tetrahedron",
            Self::Hexahedron => "hexahedron",
        }
    }
}

/// A VTK grid's cells as its file lists them: per cell, its VTK type and its points.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Cells {
    /// Per cell, its VTK cell type.
    pub types: Vec<u8>,
    /// Per cell, the end of its points in `connectivity` (VTK's `offsets`): cell `k`'s are
    /// `connectivity[offsets[k − 1]..offsets[k]]`, from 0 for the first.
    pub offsets: Vec<usize>,
    /// The cells' points, cell after cell, as indices of the grid's points.
    pub connectivity: Vec<usize>,
}

impl Cells {
    /// The number of cells.
    pub fn len(&self) -> usize {
        self.types.len()
    }

    /// Whether it has no cell.
    pub fn is_empty(&self) -> bool {
        self.types.is_empty()
    }

    /// The points of cell `k`.
    pub fn cell(&self, k: usize) -> &[usize] {
        let start = if k == 0 { 0 } else { self.offsets[k - 1] };
        &self.connectivity[start..self.offsets[k]]
    }

    /// Cell `k`'s type and points.
    pub fn iter(&self) -> impl Iterator<Item = (u8, &[usize])> + '_ {
        (0..self.len()).map(|k| (self.types[k], self.cell(k)))
    }

    /// Appends a cell of type `vtk` on `points`.
    pub fn push(&mut self, vtk: u8, points: &[usize]) {
        self.types.push(vtk);
        self.connectivity.extend_from_slice(points);
        self.offsets.push(self.connectivity.len());
    }
}

/// What a snapshot's file says of its cells.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Topology {
    /// A VTK grid's cells, each with its type and points.
    Cells(Cells),
    /// An XDMF grid's `TopologyType` (its connectivity, heavy data, is not read).
    Declared(String),
}
