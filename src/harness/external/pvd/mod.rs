//! Another code's box run as ParaView reads it: a collection (`.pvd`, VTK's `Collection`) that
//! lists one unstructured grid (`.vtu`) per time, each with the mesh's points and nodal arrays
//! (point data). GetFEM, FEniCSx/dolfinx, deal.II, MOOSE and the harness itself write them.
//!
//! The snapshots are read by `vtkio`: inline ASCII, inline binary (base64) and appended data
//! (raw or base64), with `UInt32` or `UInt64` headers, uncompressed or zlib-compressed. A
//! collection with several parts at a time (the harness writes the obstacle as part 1) is read
//! through its part 0: the body.

mod appended_raw;

use std::io::Cursor;
use std::path::{Path, PathBuf};

use vtkio::model::{Attribute, DataSet, Piece};
use vtkio::Vtk;

use super::error::ExternalError;
use super::format::RUN_FILE;
use crate::harness::files::input::read_bytes;

/// One dataset of a collection: its time and its file (relative to the collection's directory
/// resolved).
#[derive(Debug, Clone, PartialEq)]
pub struct CollectionEntry {
    /// Its `timestep`.
    pub time: f64,
    /// Its file.
    pub file: PathBuf,
}

/// A nodal array of a snapshot.
#[derive(Debug, Clone, PartialEq)]
pub struct PointArray {
    /// Its `Name`.
    pub name: String,
    /// Its `NumberOfComponents`.
    pub components: usize,
    /// Its values, node by node (`components` per node).
    pub values: Vec<f64>,
}

/// One snapshot: the mesh's points and its nodal arrays.
#[derive(Debug, Clone, PartialEq)]
pub struct VtuSnapshot {
    /// The file it was read from.
    pub path: PathBuf,
    /// The points, `[x, y, z]` (`z = 0` in 2D).
    pub points: Vec<[f64; 3]>,
    /// The point data.
    pub arrays: Vec<PointArray>,
}

impl VtuSnapshot {
    /// The snapshot of `path` from its points' coordinates (three per point) and its point
    /// arrays, each checked to hold `NumberOfComponents` values per point.
    fn new(
        path: &Path,
        coordinates: Vec<f64>,
        arrays: Vec<PointArray>,
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
        Ok(Self {
            path: path.to_path_buf(),
            points,
            arrays,
        })
    }

    /// The point array named `name`.
    pub fn array(&self, name: &str) -> Option<&PointArray> {
        self.arrays.iter().find(|a| a.name == name)
    }
}

/// The part of a collection read: the body (the harness writes its obstacle as part 1).
pub const BODY_PART: u32 = 0;

/// Reads the collection `path`: the datasets of part [`BODY_PART`] (a dataset without `part`
/// is part 0) in increasing time, their files resolved against the collection's directory.
/// Two datasets of the body at one time, a time that is not a number, or no dataset at all is
/// refused, naming the attribute.
pub fn read_collection(path: &Path) -> Result<Vec<CollectionEntry>, ExternalError> {
    let bytes = read_bytes(path, RUN_FILE)?;
    let invalid = |field: &str, at: Option<String>, value: String, allowed: &str| {
        ExternalError::invalid(path, field, at, value, allowed)
    };
    let text = String::from_utf8(bytes).map_err(|_| {
        invalid(
            "file",
            None,
            "not UTF-8 text".into(),
            "a ParaView collection (.pvd): XML text",
        )
    })?;
    let document = roxmltree::Document::parse(&text).map_err(|e| {
        invalid(
            "file",
            None,
            format!("malformed XML ({e})"),
            "a ParaView collection (.pvd): XML text",
        )
    })?;
    let root = document.root_element();
    if root.tag_name().name() != "VTKFile" || root.attribute("type") != Some("Collection") {
        return Err(invalid(
            "VTKFile.type",
            None,
            format!("{:?}", root.attribute("type").unwrap_or("")),
            "\"Collection\" (a .pvd file)",
        ));
    }
    let directory = path.parent().unwrap_or(Path::new("."));
    let mut entries = Vec::new();
    for (k, dataset) in root
        .descendants()
        .filter(|n| n.has_tag_name("DataSet"))
        .enumerate()
    {
        let at = || Some(format!("DataSet {k}"));
        let part = match dataset.attribute("part") {
            None => BODY_PART,
            Some(p) => p
                .trim()
                .parse::<u32>()
                .map_err(|_| invalid("part", at(), format!("{p:?}"), "a non-negative integer"))?,
        };
        if part != BODY_PART {
            continue;
        }
        let time = dataset.attribute("timestep").unwrap_or("");
        let time: f64 = time
            .trim()
            .parse()
            .ok()
            .filter(|t: &f64| t.is_finite())
            .ok_or_else(|| invalid("timestep", at(), format!("{time:?}"), "a finite number"))?;
        let file = dataset
            .attribute("file")
            .filter(|f| !f.trim().is_empty())
            .ok_or_else(|| invalid("file", at(), "missing".into(), "the dataset's file name"))?;
        entries.push(CollectionEntry {
            time,
            file: directory.join(file),
        });
    }
    if entries.is_empty() {
        return Err(invalid(
            "Collection",
            None,
            "no dataset of part 0".into(),
            "one DataSet per time (part 0 or no part)",
        ));
    }
    entries.sort_by(|a, b| a.time.total_cmp(&b.time));
    if let Some(w) = entries.windows(2).find(|w| w[0].time == w[1].time) {
        return Err(invalid(
            "timestep",
            None,
            w[0].time.to_string(),
            &format!(
                "one dataset of the body per time: {} and {} are both at this time",
                w[0].file.display(),
                w[1].file.display()
            ),
        ));
    }
    Ok(entries)
}

/// Where the raw bytes of an `<AppendedData encoding="raw">` block begin (after its `_`), if
/// the file has one: `vtkio` reads inline and base64 data, not raw bytes inside XML.
fn raw_appended_start(bytes: &[u8]) -> Option<usize> {
    let tag = find(bytes, b"<AppendedData", 0)?;
    let end = find(bytes, b">", tag)?;
    let head = std::str::from_utf8(&bytes[tag..end]).ok()?;
    if !head.contains("\"raw\"") {
        return None;
    }
    find(bytes, b"_", end).map(|underscore| underscore + 1)
}

/// The first position of `needle` in `bytes` at or after `from`.
fn find(bytes: &[u8], needle: &[u8], from: usize) -> Option<usize> {
    bytes
        .get(from..)?
        .windows(needle.len())
        .position(|w| w == needle)
        .map(|p| p + from)
}

/// Reads the snapshot `path`: a VTK XML unstructured grid of one piece, its points and its
/// point data as `f64` (field data and cell data are not read).
pub fn read_snapshot(path: &Path) -> Result<VtuSnapshot, ExternalError> {
    const ALLOWED: &str = "a VTK XML unstructured grid (.vtu) of one piece: ASCII, binary or \
                           appended data, uncompressed or zlib-compressed";
    let invalid = |field: &str, value: String, allowed: &str| {
        ExternalError::invalid(path, field, None, value, allowed)
    };
    let bytes = read_bytes(path, RUN_FILE)?;
    if let Some(start) = raw_appended_start(&bytes) {
        return appended_raw::read(path, &bytes, start);
    }
    let vtk = Vtk::parse_xml(Cursor::new(bytes))
        .map_err(|e| invalid("file", format!("unreadable ({e})"), ALLOWED))?;
    let DataSet::UnstructuredGrid { pieces, .. } = vtk.data else {
        return Err(invalid("VTKFile.type", "another dataset".into(), ALLOWED));
    };
    let [Piece::Inline(piece)] = <[_; 1]>::try_from(pieces)
        .map_err(|p: Vec<_>| invalid("Piece", format!("{} pieces", p.len()), ALLOWED))?
    else {
        return Err(invalid("Piece", "a piece in another file".into(), ALLOWED));
    };
    let coordinates: Vec<f64> = piece
        .points
        .cast_into()
        .ok_or_else(|| invalid("Points", "not numbers".into(), ALLOWED))?;
    let mut arrays = Vec::new();
    for attribute in piece.data.point {
        let Attribute::DataArray(array) = attribute else {
            continue;
        };
        let Some(values) = array.data.cast_into::<f64>() else {
            continue;
        };
        arrays.push(PointArray {
            components: array.elem.num_comp() as usize,
            name: array.name,
            values,
        });
    }
    VtuSnapshot::new(path, coordinates, arrays)
}
