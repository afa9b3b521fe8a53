//! One time of a box run as a file holds it, whatever the file (a VTK grid, an XDMF grid):
//! the mesh's points, what the file says of its cells, and the nodal arrays, each checked to hold
//! its components at every point.

use std::path::{Path, PathBuf};

use super::error::ExternalError;
use super::mesh::Topology;

/// A nodal array of a snapshot.
#[derive(Debug, Clone, PartialEq)]
pub struct PointArray {
    /// Its `Name`.
    pub name: String,
    /// Its `NumberOfComponents`.
    pub components: usize,
    /// Its values, node by node (`components` per node).
    pub values: Vec<f64>,
    /// The machine epsilon of its type in the file ([`epsilon_of`]): how finely the file could
    /// write its values.
    pub epsilon: f64,
}

impl PointArray {
    /// The values of point `k`: its `components`.
    pub fn row(&self, k: usize) -> &[f64] {
        &self.values[k * self.components..(k + 1) * self.components]
    }
}

/// One snapshot: the mesh's points and its nodal arrays.
#[derive(Debug, Clone, PartialEq)]
pub struct NodalSnapshot {
    /// The file it was read from.
    pub path: PathBuf,
    /// The points, `[x, y, z]` (`z = 0` in 2D).
    pub points: Vec<[f64; 3]>,
    /// The machine epsilon of the points' type in the file: `f64::EPSILON` for `Float64` (or
    /// integers), `f32::EPSILON` for `Float32`; a point is its node within this relative
    /// rounding.
    pub point_epsilon: f64,
    /// The point data.
    pub arrays: Vec<PointArray>,
    /// The cells, when the file gives them (a VTK grid with cells, an XDMF grid's topology
    /// type); `None` for a grid without cells.
    pub topology: Option<Topology>,
}

/// The machine epsilon of a points type: single precision's for `Float32`, double's
/// otherwise.
pub fn epsilon_of(single: bool) -> f64 {
    if single {
        f64::from(f32::EPSILON)
    } else {
        f64::EPSILON
    }
}

impl NodalSnapshot {
    /// The snapshot of `path` from its points' coordinates (three per point, of a type whose
    /// machine epsilon is `point_epsilon`), its point arrays, each checked to hold
    /// `NumberOfComponents` values per point, and its cells (a VTK grid's are checked to name
    /// its points).
    pub fn new(
        path: &Path,
        coordinates: Vec<f64>,
        point_epsilon: f64,
        arrays: Vec<PointArray>,
        topology: Option<Topology>,
    ) -> Result<Self, ExternalError> {
        let invalid = |field: &str, value: String, allowed: String| {
            ExternalError::invalid(path, field, None, value, allowed)
        };
        if coordinates.len() % 3 != 0 {
            return Err(invalid(
                "Points",
                format!("{} coordinates", coordinates.len()),
                "three coordinates per point".into(),
            ));
        }
        let points: Vec<[f64; 3]> = coordinates
            .chunks_exact(3)
            .map(|c| [c[0], c[1], c[2]])
            .collect();
        for a in &arrays {
            if a.components == 0 || a.values.len() != a.components * points.len() {
                return Err(invalid(
                    &format!("PointData {:?}", a.name),
                    format!("{} values", a.values.len()),
                    format!(
                        "NumberOfComponents × points = {} × {}",
                        a.components,
                        points.len()
                    ),
                ));
            }
        }
        if let Some(Topology::Cells(cells)) = &topology {
            if let Some(k) = cells.connectivity.iter().position(|&p| p >= points.len()) {
                return Err(invalid(
                    "Cells connectivity",
                    format!("point {} at entry {k}", cells.connectivity[k]),
                    format!("a point of the grid's {}", points.len()),
                ));
            }
        }
        Ok(Self {
            path: path.to_path_buf(),
            points,
            point_epsilon,
            arrays,
            topology,
        })
    }

    /// The point array named `name`.
    pub fn array(&self, name: &str) -> Option<&PointArray> {
        self.arrays.iter().find(|a| a.name == name)
    }
}
