//! Another code's box run as ParaView reads it: a collection (`.pvd`, VTK's `Collection`) that
//! lists one unstructured grid (`.vtu`) per time, each with the mesh's points and nodal arrays
//! (point data). The harness writes them, and so do other codes; those whose own files were tried
//! are committed in `tests/data/external/` (DOLFINx 0.5.2's `VTKFile`, GetFEM 5.4.2's
//! `export_to_vtu`).
//!
//! The snapshots are read by `vtkio`: inline ASCII, inline binary (base64) and appended data
//! (raw or base64), with `UInt32` or `UInt64` headers, uncompressed or zlib-compressed, `Float32`
//! or `Float64`. A collection with several parts at a time (the harness writes the obstacle as
//! part 1) is read through its part 0: the body.
//!
//! What real writers do beyond that:
//! - **a parallel grid** (`.pvtu`, VTK's `PUnstructuredGrid`: DOLFINx's `VTKFile` writes one even
//!   on one process) lists its pieces' files (`_p0_*.vtu`, …); they are read and joined into one
//!   snapshot ([`joined`]), a node that two pieces share (a ghost) kept once, and refused where
//!   the pieces disagree on it;
//! - **no `byte_order`** (DOLFINx): the attribute is optional for VTK; little-endian is taken, the
//!   order of the machines these codes run on (for ASCII data it means nothing);
//! - **`Float32` points** (GetFEM's exporter): the points keep the precision of their type
//!   ([`NodalSnapshot::point_epsilon`]), which the node match allows for.

mod appended_raw;
mod full_last_block;

use std::collections::HashMap;
use std::io::Cursor;
use std::path::{Path, PathBuf};

use vtkio::model::{Attribute, DataSet, Piece, ScalarType};
use vtkio::Vtk;

use super::error::ExternalError;
use super::format::RUN_FILE;
use super::nodal_snapshot::{epsilon_of, NodalSnapshot, PointArray};
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

/// How a binary array's header words are stored: `UInt32` or `UInt64` (the file's
/// `header_type`), in the file's byte order.
#[derive(Clone, Copy)]
struct HeaderWord {
    /// Bytes per word: 4 or 8.
    width: usize,
    /// `byte_order="BigEndian"`.
    big_endian: bool,
}

impl HeaderWord {
    /// The words of a file whose `VTKFile` element has these `header_type` and `byte_order`.
    fn of(root: roxmltree::Node<'_, '_>) -> Self {
        Self {
            width: if root.attribute("header_type") == Some("UInt64") {
                8
            } else {
                4
            },
            big_endian: root.attribute("byte_order") == Some("BigEndian"),
        }
    }

    /// The word at the start of `bytes` (at least [`HeaderWord::width`] of them).
    fn read(self, bytes: &[u8]) -> u64 {
        let mut word = [0u8; 8];
        if self.big_endian {
            word[8 - self.width..].copy_from_slice(&bytes[..self.width]);
            u64::from_be_bytes(word)
        } else {
            word[..self.width].copy_from_slice(&bytes[..self.width]);
            u64::from_le_bytes(word)
        }
    }

    /// `value` written as the word at the start of `bytes`.
    fn write(self, value: u64, bytes: &mut [u8]) {
        if self.big_endian {
            bytes[..self.width].copy_from_slice(&value.to_be_bytes()[8 - self.width..]);
        } else {
            bytes[..self.width].copy_from_slice(&value.to_le_bytes()[..self.width]);
        }
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

/// `bytes` with `byte_order="LittleEndian"` on its `VTKFile` element when the file leaves the
/// attribute out (VTK takes it as optional; `vtkio` requires it).
fn with_byte_order(mut bytes: Vec<u8>) -> Vec<u8> {
    const TAG: &[u8] = b"<VTKFile";
    let Some(tag) = find(&bytes, TAG, 0) else {
        return bytes;
    };
    let Some(end) = find(&bytes, b">", tag) else {
        return bytes;
    };
    if find(&bytes[..end], b"byte_order", tag).is_none() {
        let at = tag + TAG.len();
        bytes.splice(at..at, b" byte_order=\"LittleEndian\"".iter().copied());
    }
    bytes
}

/// What [`read_snapshot`] reads, as its errors say it.
const SNAPSHOT: &str = "a VTK XML unstructured grid (.vtu) of one piece, or a parallel one \
                        (.pvtu) whose pieces are such files: ASCII, binary or appended data, \
                        uncompressed, zlib- or LZ4-compressed";

/// Reads the snapshot `path`: a VTK XML unstructured grid of one piece, or a parallel grid
/// whose pieces are in files of their own (joined, [`joined`]); its points and its point data
/// as `f64` (field data and cell data are not read).
pub fn read_snapshot(path: &Path) -> Result<NodalSnapshot, ExternalError> {
    match read_grid(path)? {
        Grid::Inline(snapshot) => Ok(snapshot),
        Grid::Pieces(files) => {
            let directory = path.parent().unwrap_or(Path::new("."));
            let pieces = files
                .iter()
                .map(|file| match read_grid(&directory.join(file))? {
                    Grid::Inline(piece) => Ok(piece),
                    Grid::Pieces(_) => Err(ExternalError::invalid(
                        &directory.join(file),
                        "Piece",
                        None,
                        "a piece in another file",
                        SNAPSHOT,
                    )),
                })
                .collect::<Result<Vec<_>, _>>()?;
            joined(path, pieces)
        }
    }
}

/// A grid file as read: one piece inline, or the files of its pieces (a parallel grid).
enum Grid {
    Inline(NodalSnapshot),
    Pieces(Vec<String>),
}

/// Reads the grid file `path`.
fn read_grid(path: &Path) -> Result<Grid, ExternalError> {
    let invalid =
        |field: &str, value: String| ExternalError::invalid(path, field, None, value, SNAPSHOT);
    let bytes = read_bytes(path, RUN_FILE)?;
    if let Some(start) = raw_appended_start(&bytes) {
        return appended_raw::read(path, &bytes, start).map(Grid::Inline);
    }
    let vtk = Vtk::parse_xml(Cursor::new(full_last_block::with_full_last_blocks(
        with_byte_order(bytes),
    )))
    .map_err(|e| invalid("file", format!("unreadable ({e})")))?;
    let DataSet::UnstructuredGrid { pieces, .. } = vtk.data else {
        return Err(invalid("VTKFile.type", "another dataset".into()));
    };
    let sources: Option<Vec<String>> = pieces
        .iter()
        .map(|p| match p {
            Piece::Source(file, _) => Some(file.clone()),
            _ => None,
        })
        .collect();
    if let Some(files) = sources.filter(|f| !f.is_empty()) {
        return Ok(Grid::Pieces(files));
    }
    let [Piece::Inline(piece)] = <[_; 1]>::try_from(pieces)
        .map_err(|p: Vec<_>| invalid("Piece", format!("{} pieces", p.len())))?
    else {
        return Err(invalid("Piece", "a piece of another kind".into()));
    };
    let single = piece.points.scalar_type() == ScalarType::F32;
    let coordinates: Vec<f64> = piece
        .points
        .cast_into()
        .ok_or_else(|| invalid("Points", "not numbers".into()))?;
    let mut arrays = Vec::new();
    for attribute in piece.data.point {
        let Attribute::DataArray(array) = attribute else {
            continue;
        };
        let epsilon = epsilon_of(array.data.scalar_type() == ScalarType::F32);
        let values = array.data.cast_into::<f64>().ok_or_else(|| {
            invalid(
                &format!("PointData {:?}", array.name),
                "values that are not numbers".into(),
            )
        })?;
        arrays.push(PointArray {
            components: array.elem.num_comp() as usize,
            name: array.name,
            values,
            epsilon,
        });
    }
    NodalSnapshot::new(path, coordinates, epsilon_of(single), arrays).map(Grid::Inline)
}

/// The prefix of VTK's bookkeeping arrays (`vtkGhostType`, `vtkOriginalPointIds`, …), which
/// pieces may set apart at a shared point (a ghost is marked in the piece that does not own it).
const BOOKKEEPING: &str = "vtk";

/// The pieces of the parallel grid `path` as one snapshot: their points in order, a point two
/// pieces share (the same coordinates, bit for bit: a ghost node) kept once, with the first
/// piece's values. The pieces must carry the same arrays, and agree on every value at a shared
/// point but VTK's bookkeeping ([`BOOKKEEPING`]).
fn joined(path: &Path, pieces: Vec<NodalSnapshot>) -> Result<NodalSnapshot, ExternalError> {
    let mut pieces = pieces.into_iter();
    let Some(first) = pieces.next() else {
        return Err(ExternalError::invalid(
            path, "Piece", None, "none", SNAPSHOT,
        ));
    };
    let mut at: HashMap<[u64; 3], usize> = first
        .points
        .iter()
        .enumerate()
        .map(|(k, p)| (p.map(f64::to_bits), k))
        .collect();
    let mut whole = NodalSnapshot {
        path: path.to_path_buf(),
        ..first
    };
    for piece in pieces {
        let names = |s: &NodalSnapshot| -> Vec<(String, usize)> {
            s.arrays
                .iter()
                .map(|a| (a.name.clone(), a.components))
                .collect()
        };
        if names(&piece) != names(&whole) {
            return Err(ExternalError::invalid(
                &piece.path,
                "PointData",
                None,
                format!("the arrays {:?}", names(&piece)),
                format!("those of the grid's first piece, {:?}", names(&whole)),
            ));
        }
        whole.point_epsilon = whole.point_epsilon.max(piece.point_epsilon);
        for (k, p) in piece.points.iter().enumerate() {
            match at.get(&p.map(f64::to_bits)) {
                Some(&shared) => {
                    let differing = (0..whole.arrays.len())
                        .filter(|&a| !whole.arrays[a].name.starts_with(BOOKKEEPING))
                        .find(|&a| piece.arrays[a].row(k) != whole.arrays[a].row(shared));
                    if let Some(a) = differing {
                        return Err(ExternalError::invalid(
                            &piece.path,
                            format!("PointData {:?}", whole.arrays[a].name),
                            Some(format!("point {k}")),
                            format!("{:?}", piece.arrays[a].row(k)),
                            format!(
                                "the value of the piece that also holds this point ({p:?}): \
                                 {:?}",
                                whole.arrays[a].row(shared)
                            ),
                        ));
                    }
                }
                None => {
                    at.insert(p.map(f64::to_bits), whole.points.len());
                    whole.points.push(*p);
                    for (kept, added) in whole.arrays.iter_mut().zip(&piece.arrays) {
                        kept.values.extend_from_slice(added.row(k));
                    }
                }
            }
        }
    }
    Ok(whole)
}
