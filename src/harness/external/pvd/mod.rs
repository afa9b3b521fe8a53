//! Another code's box run as ParaView reads it: a collection (`.pvd`, VTK's `Collection`) that
//! lists one unstructured grid (`.vtu`) per time, each with the mesh's points and nodal arrays
//! (point data). The harness writes them, and so do other codes; those whose own files were tried
//! are committed in `tests/data/external/` (DOLFINx 0.5.2's `VTKFile`, GetFEM 5.4.2's
//! `export_to_vtu`).
//!
//! The snapshots are read by the harness itself ([`vtu`], [`array_data`]), not by a VTK library
//! (`vtkio` panicked or silently dropped an array on malformed data): inline ASCII, inline binary
//! (base64) and appended data (raw or base64), with `UInt32` or `UInt64` headers, uncompressed,
//! zlib- or LZ4-compressed, `Float32`, `Float64` or integer arrays. Every size is checked against
//! what the grid needs before anything is allocated, and a collection lists at most
//! [`MAX_DATASETS`] datasets. A collection with several parts at a time (the harness writes the
//! obstacle as part 1) is read through its part 0: the body.
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

mod array_data;
mod vtu;

use std::collections::{HashMap, HashSet};
use std::path::{Path, PathBuf};

use super::error::{unquoted, ExternalError};
use super::format::RUN_FILE;
use super::mesh::{Cells, Topology};
use super::nodal_snapshot::NodalSnapshot;
use super::xml_depth::check_depth;
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

/// The part of a collection read: the body (the harness writes its obstacle as part 1).
pub const BODY_PART: u32 = 0;

/// The most datasets of the body a collection may list: 2¹⁸ (the finest reference, 2560 steps,
/// written at every step, lists 2561 of its body).
pub const MAX_DATASETS: usize = 1 << 18;

/// The most parts a collection may list at each time (the harness writes two: the body and the
/// obstacle): its datasets are counted before the XML is parsed, so that a collection of millions
/// of datasets is refused before its tree is built.
pub const MAX_PARTS: usize = 4;

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
    check_depth(path, text.as_bytes())?;
    let listed = text.matches("<DataSet").count();
    if listed > MAX_DATASETS * MAX_PARTS {
        return Err(invalid(
            "Collection",
            None,
            format!("{listed} datasets"),
            &format!("at most {MAX_DATASETS} of the body, of at most {MAX_PARTS} parts"),
        ));
    }
    let document = roxmltree::Document::parse(&text).map_err(|e| {
        invalid(
            "file",
            None,
            format!("malformed XML ({})", unquoted(e)),
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
        if entries.len() == MAX_DATASETS {
            return Err(invalid(
                "Collection",
                None,
                format!("more than {MAX_DATASETS} datasets of part 0"),
                &format!("at most {MAX_DATASETS}"),
            ));
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

/// The first position of `needle` in `bytes` at or after `from`.
fn find(bytes: &[u8], needle: &[u8], from: usize) -> Option<usize> {
    bytes
        .get(from..)?
        .windows(needle.len())
        .position(|w| w == needle)
        .map(|p| p + from)
}

/// What [`read_snapshot`] reads, as its errors say it.
const SNAPSHOT: &str = "a VTK XML unstructured grid (.vtu) of one piece, or a parallel one \
                        (.pvtu) whose pieces are such files: ASCII, binary or appended data, \
                        uncompressed, zlib- or LZ4-compressed";

/// Reads the snapshot `path`: a VTK XML unstructured grid of one piece, or a parallel grid
/// whose pieces are in files of their own (joined, [`joined`]); its points and its point data
/// as `f64`, and its cells (field data and cell data are not read).
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

/// Reads the grid file `path` ([`vtu::read`]).
fn read_grid(path: &Path) -> Result<Grid, ExternalError> {
    vtu::read(path, &read_bytes(path, RUN_FILE)?)
}

/// The prefix of VTK's bookkeeping arrays (`vtkGhostType`, `vtkOriginalPointIds`, …), which
/// pieces may set apart at a shared point (a ghost is marked in the piece that does not own it).
const BOOKKEEPING: &str = "vtk";

/// The pieces of the parallel grid `path` as one snapshot: their points in order, a point two
/// pieces share (the same coordinates, bit for bit: a ghost node) kept once, with the first
/// piece's values. The pieces must carry the same arrays, and agree on every value at a shared
/// point but VTK's bookkeeping ([`BOOKKEEPING`]). Their cells are joined on the joined points, a
/// cell two pieces list (a ghost cell: the same type on the same points) kept once; a piece
/// without cells adds none.
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
    let mut cells = JoinedCells::default();
    cells.add(
        whole.topology.take(),
        &(0..whole.points.len()).collect::<Vec<_>>(),
    );
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
        let mut joined_index = Vec::with_capacity(piece.points.len());
        for (k, p) in piece.points.iter().enumerate() {
            match at.get(&p.map(f64::to_bits)) {
                Some(&shared) => {
                    joined_index.push(shared);
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
                    joined_index.push(whole.points.len());
                    at.insert(p.map(f64::to_bits), whole.points.len());
                    whole.points.push(*p);
                    for (kept, added) in whole.arrays.iter_mut().zip(&piece.arrays) {
                        kept.values.extend_from_slice(added.row(k));
                    }
                }
            }
        }
        cells.add(piece.topology, &joined_index);
    }
    whole.topology = cells.cells.map(Topology::Cells);
    Ok(whole)
}

/// The cells of a parallel grid's pieces, joined ([`joined`]).
#[derive(Default)]
struct JoinedCells {
    /// The cells so far, when a piece had some.
    cells: Option<Cells>,
    /// Each kept cell's type and joined points.
    seen: HashSet<(u8, Vec<usize>)>,
}

impl JoinedCells {
    /// Adds the cells of a piece (`topology`) whose point `k` is joined point `joined_index[k]`.
    fn add(&mut self, topology: Option<Topology>, joined_index: &[usize]) {
        let Some(Topology::Cells(piece)) = topology else {
            return;
        };
        let cells = self.cells.get_or_insert_with(Cells::default);
        for (vtk, points) in piece.iter() {
            let points: Vec<usize> = points.iter().map(|&p| joined_index[p]).collect();
            if self.seen.insert((vtk, points.clone())) {
                cells.push(vtk, &points);
            }
        }
    }
}
