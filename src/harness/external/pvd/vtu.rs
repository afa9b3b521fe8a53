//! A VTK XML grid file read by the harness: an unstructured grid (`.vtu`) of one piece, its
//! points and point arrays decoded by [`super::array_data`], or a parallel grid (`.pvtu`) whose
//! pieces are files of their own. The XML is parsed after its nesting depth is checked
//! ([`crate::harness::external::xml_depth`]); an `<AppendedData>` block is set apart first, so
//! that raw bytes never go through the XML parser. The cells are read, each with its VTK type and
//! its points ([`Cells`]: `connectivity`, `offsets`, `types`, checked to be consistent and to name
//! the grid's points; what a cell's type means is for the reader of the box run to judge); cell
//! data are not read.
//!
//! Every array of the point data is read or the file is refused, naming the array and why: an
//! array that cannot be read is never dropped (which would let another array be taken for it).

use std::borrow::Cow;
use std::path::Path;

use super::array_data::{Appended, Compressor, HeaderWord, Layout, Scalar};
use super::{find, Grid, SNAPSHOT};
use crate::harness::external::error::{unquoted, ExternalError};
use crate::harness::external::format::MAX_VALUES;
use crate::harness::external::mesh::{Cells, Topology};
use crate::harness::external::nodal_snapshot::{epsilon_of, NodalSnapshot, PointArray};
use crate::harness::external::xml_depth::check_depth;

/// The grid file `path` whose bytes are `bytes`.
pub(super) fn read(path: &Path, bytes: &[u8]) -> Result<Grid, ExternalError> {
    let invalid =
        |field: &str, value: String| ExternalError::invalid(path, field, None, value, SNAPSHOT);
    let (xml, appended) = split_appended(bytes).map_err(|why| invalid("AppendedData", why))?;
    check_depth(path, &xml)?;
    let text =
        std::str::from_utf8(&xml).map_err(|_| invalid("file", "not UTF-8 XML text".into()))?;
    let document = roxmltree::Document::parse(text)
        .map_err(|e| invalid("file", format!("malformed XML ({})", unquoted(e))))?;
    let root = document.root_element();
    if !root.has_tag_name("VTKFile") {
        return Err(invalid("file", "not a VTKFile".into()));
    }
    match root.attribute("type").unwrap_or("") {
        "UnstructuredGrid" => {}
        "PUnstructuredGrid" => {
            let files: Vec<String> = root
                .descendants()
                .filter(|n| n.has_tag_name("Piece"))
                .filter_map(|n| n.attribute("Source").map(str::to_string))
                .collect();
            if files.is_empty() {
                return Err(invalid("Piece", "no piece with a Source".into()));
            }
            return Ok(Grid::Pieces(files));
        }
        other => return Err(invalid("VTKFile.type", format!("{:?}", unquoted(other)))),
    }
    let layout = Layout {
        word: HeaderWord::of(root),
        compressor: Compressor::of(root).map_err(|why| invalid("VTKFile", why))?,
        appended,
    };
    let pieces: Vec<_> = root
        .descendants()
        .filter(|n| n.has_tag_name("Piece"))
        .collect();
    let [piece] = pieces[..] else {
        return Err(invalid("Piece", format!("{} pieces", pieces.len())));
    };
    let points: usize = piece
        .attribute("NumberOfPoints")
        .unwrap_or("")
        .trim()
        .parse()
        .ok()
        .filter(|&n: &usize| n <= MAX_VALUES / 3)
        .ok_or_else(|| {
            invalid(
                "Piece.NumberOfPoints",
                format!(
                    "{:?}",
                    unquoted(piece.attribute("NumberOfPoints").unwrap_or(""))
                ),
            )
        })?;
    let mut budget = MAX_VALUES;
    let mut read_array = |node: roxmltree::Node<'_, '_>, field: &str| {
        let components: usize = node
            .attribute("NumberOfComponents")
            .unwrap_or("1")
            .trim()
            .parse()
            .ok()
            .filter(|&c: &usize| c >= 1)
            .ok_or_else(|| invalid(field, "NumberOfComponents not a positive integer".into()))?;
        let scalar =
            Scalar::of(node.attribute("type").unwrap_or("")).map_err(|why| invalid(field, why))?;
        let count = components
            .checked_mul(points)
            .filter(|&c| c <= budget)
            .ok_or_else(|| {
                invalid(
                    field,
                    format!("more than {MAX_VALUES} values in the file's point arrays"),
                )
            })?;
        budget -= count;
        let values = layout
            .values(node, scalar, count)
            .map_err(|why| invalid(field, why))?;
        Ok::<_, ExternalError>(PointArray {
            name: node.attribute("Name").unwrap_or("").to_string(),
            components,
            values,
            epsilon: epsilon_of(scalar == Scalar::F32),
        })
    };
    let point_array = piece
        .children()
        .find(|n| n.has_tag_name("Points"))
        .and_then(|p| p.children().find(|n| n.has_tag_name("DataArray")))
        .ok_or_else(|| invalid("Points", "missing".into()))?;
    let coordinates = read_array(point_array, "Points")?;
    let mut arrays = Vec::new();
    if let Some(data) = piece.children().find(|n| n.has_tag_name("PointData")) {
        for node in data.children().filter(|n| n.has_tag_name("DataArray")) {
            let field = format!(
                "PointData {:?}",
                unquoted(node.attribute("Name").unwrap_or(""))
            );
            arrays.push(read_array(node, &field)?);
        }
    }
    let topology =
        read_cells(piece, &layout, points).map_err(|(field, why)| invalid(field, why))?;
    NodalSnapshot::new(
        path,
        coordinates.values,
        coordinates.epsilon,
        arrays,
        topology.map(Topology::Cells),
    )
    .map(Grid::Inline)
}

/// The cells of `piece` (of `points` points), `None` when it declares none
/// (`NumberOfCells="0"` or no `<Cells>`): its `offsets` and `types` (one per cell) and its
/// `connectivity` (as many as the last offset says), read as integers in the grid's range, at
/// most [`MAX_VALUES`] numbers in all (each count checked before its array is read); the field
/// and why, otherwise.
fn read_cells(
    piece: roxmltree::Node<'_, '_>,
    layout: &Layout<'_>,
    points: usize,
) -> Result<Option<Cells>, (&'static str, String)> {
    let declared = piece.attribute("NumberOfCells").unwrap_or("0").trim();
    let count: usize = declared
        .parse()
        .ok()
        .filter(|&n: &usize| n <= MAX_VALUES / 2)
        .ok_or_else(|| ("Piece.NumberOfCells", format!("{:?}", unquoted(declared))))?;
    let Some(cells) = piece.children().find(|n| n.has_tag_name("Cells")) else {
        return match count {
            0 => Ok(None),
            _ => Err(("Cells", format!("missing, where NumberOfCells is {count}"))),
        };
    };
    if count == 0 {
        return Ok(None);
    }
    let integers = |name: &'static str, count: usize, below: usize| {
        let field = match name {
            "offsets" => "Cells offsets",
            "types" => "Cells types",
            _ => "Cells connectivity",
        };
        let node = cells
            .children()
            .find(|n| n.has_tag_name("DataArray") && n.attribute("Name") == Some(name))
            .ok_or((field, "missing".to_string()))?;
        let scalar =
            Scalar::of(node.attribute("type").unwrap_or("")).map_err(|why| (field, why))?;
        let values = layout
            .values(node, scalar, count)
            .map_err(|why| (field, why))?;
        values
            .iter()
            .map(|&v| {
                (v >= 0.0 && v.fract() == 0.0 && v < below as f64)
                    .then_some(v as usize)
                    .ok_or_else(|| {
                        (
                            field,
                            format!("{v}, where an integer from 0 to {} is allowed", below - 1),
                        )
                    })
            })
            .collect::<Result<Vec<usize>, _>>()
    };
    let offsets = integers("offsets", count, MAX_VALUES - 2 * count + 1)?;
    if let Some(w) = offsets.windows(2).find(|w| w[1] < w[0]) {
        return Err((
            "Cells offsets",
            format!("{} after {}: offsets never decrease", w[1], w[0]),
        ));
    }
    let types = integers("types", count, 256)?;
    let connectivity = integers("connectivity", offsets[count - 1], points.max(1))?;
    Ok(Some(Cells {
        types: types.into_iter().map(|t| t as u8).collect(),
        offsets,
        connectivity,
    }))
}

/// The file's XML (everything before an `<AppendedData>` element, closed) and its appended
/// block: raw bytes or base64 characters after the block's `_`.
fn split_appended(bytes: &[u8]) -> Result<(Cow<'_, [u8]>, Option<Appended<'_>>), String> {
    let Some(tag) = find(bytes, b"<AppendedData", 0) else {
        return Ok((Cow::Borrowed(bytes), None));
    };
    let end = find(bytes, b">", tag).ok_or("an unterminated <AppendedData> tag")?;
    let underscore = find(bytes, b"_", end).ok_or("no `_` before the appended data")? + 1;
    let head = &bytes[tag..end];
    let appended = if find(head, b"\"raw\"", 0).is_some() || find(head, b"'raw'", 0).is_some() {
        Appended::Raw(&bytes[underscore..])
    } else {
        let stop = find(bytes, b"<", underscore).unwrap_or(bytes.len());
        Appended::Base64(&bytes[underscore..stop])
    };
    let mut xml = bytes[..tag].to_vec();
    xml.extend_from_slice(b"</VTKFile>");
    Ok((Cow::Owned(xml), Some(appended)))
}
