//! What makes a box run one scene in ParaView: the collection `fields.pvd`, which lists the VTK
//! snapshots with their times (one time series, File → Open `fields.pvd`), and `obstacle.vtu`,
//! the obstacle plane `x_d = −gap` (a segment in 2D, a quad in 3D) somewhat wider than the box.
//!
//! The obstacle is part 1 of the collection at every time, beside the snapshot (part 0), not a
//! dataset listed once: ParaView's PVD reader reads, at each time, the datasets listed at that
//! time (one block per part), so listed at every time the plane stays in view whatever the time,
//! at the cost of one line per time; every line points at the same small file, written once.

use std::path::{Path, PathBuf};

use vtkio::model::{
    Attributes, ByteOrder, CellType, Cells, DataSet, IOBuffer, UnstructuredGridPiece, Version,
    VertexNumbers, Vtk,
};

use crate::harness::files::artifacts::write_atomic;
use crate::harness::files::error::Error;

/// The collection of a box run's snapshots.
pub const COLLECTION_FILE: &str = "fields.pvd";

/// The obstacle plane of a box run.
pub const OBSTACLE_FILE: &str = "obstacle.vtu";

/// How far the obstacle reaches past the box on each side, as a fraction of the box's width.
pub const OBSTACLE_MARGIN: f64 = 0.2;

/// A snapshot of a collection: its time and its file's name, relative to the collection.
#[derive(Debug, Clone, PartialEq)]
pub struct Snapshot {
    /// The time it shows.
    pub time: f64,
    /// Its file's name.
    pub file: String,
}

/// `value` with the characters XML does not allow in a quoted attribute value escaped.
fn attribute(value: &str) -> String {
    let mut escaped = String::with_capacity(value.len());
    for c in value.chars() {
        match c {
            '&' => escaped.push_str("&amp;"),
            '<' => escaped.push_str("&lt;"),
            '>' => escaped.push_str("&gt;"),
            '"' => escaped.push_str("&quot;"),
            '\'' => escaped.push_str("&apos;"),
            c => escaped.push(c),
        }
    }
    escaped
}

/// One `<DataSet>` line of a collection: `file` as part `part` at `time` (written with all the
/// digits of the `f64`, so that it reads back the same).
fn dataset_line(time: f64, part: usize, file: &str) -> String {
    format!(
        "    <DataSet timestep=\"{time}\" group=\"\" part=\"{part}\" file=\"{}\"/>\n",
        attribute(file)
    )
}

/// The text of a collection file (VTK's `Collection` format, ParaView's `.pvd`): `snapshots` in
/// the order given as part 0, each with the file `obstacle`, when there is one, as part 1 at the
/// same time.
pub fn collection_xml(snapshots: &[Snapshot], obstacle: Option<&str>) -> String {
    let mut xml = String::from("<?xml version=\"1.0\"?>\n");
    xml.push_str("<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n");
    xml.push_str("  <Collection>\n");
    for s in snapshots {
        xml.push_str(&dataset_line(s.time, 0, &s.file));
        if let Some(file) = obstacle {
            xml.push_str(&dataset_line(s.time, 1, file));
        }
    }
    xml.push_str("  </Collection>\n</VTKFile>\n");
    xml
}

/// Writes the collection of `snapshots` (and of `obstacle`, see [`collection_xml`]) as
/// [`COLLECTION_FILE`] in `dir`; the file written.
pub fn write_collection(
    dir: &Path,
    snapshots: &[Snapshot],
    obstacle: Option<&str>,
) -> Result<PathBuf, Error> {
    let path = dir.join(COLLECTION_FILE);
    write_atomic(&path, collection_xml(snapshots, obstacle).as_bytes())?;
    Ok(path)
}

/// `[−m L, (1 + m) L]`, the extent across of a box of width `length` plus the margin
/// [`OBSTACLE_MARGIN`] on each side.
fn widened(length: f64) -> [f64; 2] {
    [-OBSTACLE_MARGIN * length, (1.0 + OBSTACLE_MARGIN) * length]
}

/// The points and the cell of the obstacle below a box of lengths `lengths` (the last along the
/// axis): in 2D the segment `x₂ = −gap` as a line, in 3D the rectangle `x₃ = −gap` as a quad
/// (corners counter-clockwise seen from the box), each [`OBSTACLE_MARGIN`] wider than the box
/// on each side; `None` for a box of another dimension.
fn obstacle_geometry(lengths: &[f64], gap: f64) -> Option<(Vec<[f64; 3]>, CellType)> {
    match *lengths {
        [width, _] => {
            let [a, b] = widened(width);
            Some((vec![[a, -gap, 0.0], [b, -gap, 0.0]], CellType::Line))
        }
        [width, depth, _] => {
            let [a, b] = widened(width);
            let [c, d] = widened(depth);
            let z = -gap;
            Some((
                vec![[a, c, z], [b, c, z], [b, d, z], [a, d, z]],
                CellType::Quad,
            ))
        }
        _ => None,
    }
}

/// The obstacle below a box of lengths `lengths` as an unstructured grid of one cell
/// ([`obstacle_geometry`]); `None` for a box neither 2D nor 3D.
pub fn obstacle_vtk(lengths: &[f64], gap: f64) -> Option<Vtk> {
    let (points, cell_type) = obstacle_geometry(lengths, gap)?;
    let n = points.len() as u64;
    Some(Vtk {
        version: Version::new(),
        title: format!("signorini obstacle x_d = {}", -gap),
        byte_order: ByteOrder::LittleEndian,
        file_path: None,
        data: DataSet::inline(UnstructuredGridPiece {
            points: IOBuffer::F64(points.into_iter().flatten().collect()),
            cells: Cells {
                cell_verts: VertexNumbers::XML {
                    connectivity: (0..n).collect(),
                    offsets: vec![n],
                },
                types: vec![cell_type],
            },
            data: Attributes::new(),
        }),
    })
}

/// Writes the obstacle `gap` below a box of lengths `lengths` ([`obstacle_vtk`]) as
/// [`OBSTACLE_FILE`] in `dir`: the file written, `None` (nothing written) for a box neither 2D
/// nor 3D.
pub fn write_obstacle(dir: &Path, lengths: &[f64], gap: f64) -> Result<Option<PathBuf>, Error> {
    let Some(vtk) = obstacle_vtk(lengths, gap) else {
        return Ok(None);
    };
    let path = dir.join(OBSTACLE_FILE);
    let mut bytes = Vec::new();
    vtk.write_xml(&mut bytes).map_err(|source| Error::Vtk {
        path: path.clone(),
        source,
    })?;
    write_atomic(&path, &bytes)?;
    Ok(Some(path))
}
