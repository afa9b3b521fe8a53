//! A `.vtu` whose arrays are appended raw bytes (`<AppendedData encoding="raw">`, ParaView's
//! default): the XML before the block gives each array's type, components and offset into the
//! block; at the offset, a header (`UInt32`, or `UInt64` when `header_type` says so) and the
//! array's bytes in the file's byte order. A zlib-compressed array
//! (`compressor="vtkZLibDataCompressor"`) has the header `[blocks, block size, last block's
//! size, compressed size of each block]` and its blocks one after another; an LZ4-compressed one
//! (`compressor="vtkLZ4DataCompressor"`) the same header, its blocks LZ4 blocks without a frame.

use std::io::Read;
use std::path::Path;

use flate2::read::ZlibDecoder;

use super::{HeaderWord, NodalSnapshot, PointArray};
use crate::harness::external::error::ExternalError;
use crate::harness::external::format::MAX_FILE_BYTES;

/// The snapshot `path` whose bytes are `bytes` and whose raw block starts at `start`.
pub fn read(path: &Path, bytes: &[u8], start: usize) -> Result<NodalSnapshot, ExternalError> {
    let invalid = |field: &str, value: String, allowed: &str| {
        ExternalError::invalid(path, field, None, value, allowed)
    };
    let tag = super::find(bytes, b"<AppendedData", 0).unwrap_or(0);
    let head = std::str::from_utf8(&bytes[..tag])
        .map_err(|_| invalid("file", "not UTF-8 before <AppendedData>".into(), "XML text"))?;
    let xml = format!("{head}</VTKFile>");
    let document = roxmltree::Document::parse(&xml)
        .map_err(|e| invalid("file", format!("malformed XML ({e})"), "XML text"))?;
    let root = document.root_element();
    let layout = Layout {
        word: HeaderWord::of(root),
        compressor: match root.attribute("compressor") {
            None | Some("") => None,
            Some("vtkZLibDataCompressor") => Some(Compressor::Zlib),
            Some("vtkLZ4DataCompressor") => Some(Compressor::Lz4),
            Some(other) => {
                return Err(invalid(
                    "compressor",
                    format!("{other:?}"),
                    "none, vtkZLibDataCompressor or vtkLZ4DataCompressor",
                ))
            }
        },
        block: &bytes[start..],
    };
    let piece = root
        .descendants()
        .find(|n| n.has_tag_name("Piece"))
        .ok_or_else(|| invalid("Piece", "missing".into(), "one Piece"))?;
    let array_of = |node: roxmltree::Node<'_, '_>| -> Result<PointArray, ExternalError> {
        let name = node.attribute("Name").unwrap_or("").to_string();
        let field = format!("DataArray {name:?}");
        let components: usize = node
            .attribute("NumberOfComponents")
            .unwrap_or("1")
            .parse()
            .map_err(|_| invalid(&field, "NumberOfComponents".into(), "a positive integer"))?;
        if node.attribute("format") != Some("appended") {
            return Err(invalid(
                &field,
                format!("format {:?}", node.attribute("format").unwrap_or("")),
                "appended, as every array of a file with raw appended data",
            ));
        }
        let offset: usize = node
            .attribute("offset")
            .unwrap_or("")
            .parse()
            .map_err(|_| invalid(&field, "offset".into(), "a byte offset into the block"))?;
        let kind = node.attribute("type").unwrap_or("");
        let values = layout
            .values(offset, kind)
            .map_err(|why| invalid(&field, why, "an array of the block"))?;
        Ok(PointArray {
            name,
            components: components.max(1),
            values,
            epsilon: super::epsilon_of(kind == "Float32"),
        })
    };
    let points = piece
        .descendants()
        .find(|n| n.has_tag_name("Points"))
        .and_then(|p| p.children().find(|n| n.has_tag_name("DataArray")))
        .ok_or_else(|| invalid("Points", "missing".into(), "the points' DataArray"))?;
    let coordinates = array_of(points)?.values;
    let single = points.attribute("type") == Some("Float32");
    let mut arrays = Vec::new();
    if let Some(data) = piece.children().find(|n| n.has_tag_name("PointData")) {
        for node in data.children().filter(|n| n.has_tag_name("DataArray")) {
            arrays.push(array_of(node)?);
        }
    }
    NodalSnapshot::new(path, coordinates, super::epsilon_of(single), arrays)
}
/// How the block is laid out.
struct Layout<'a> {
    word: HeaderWord,
    compressor: Option<Compressor>,
    block: &'a [u8],
}

/// How a compressed file's blocks are compressed: VTK's two block compressors.
#[derive(Clone, Copy)]
enum Compressor {
    /// `vtkZLibDataCompressor`: zlib streams.
    Zlib,
    /// `vtkLZ4DataCompressor`: LZ4 blocks (no frame), each of its header's uncompressed size.
    Lz4,
}

impl Layout<'_> {
    /// The unsigned integer of the header's width at `at`.
    fn header(&self, at: usize) -> Result<usize, String> {
        let bytes = self
            .block
            .get(at..at + self.word.width)
            .ok_or_else(|| format!("header at byte {at} past the block's end"))?;
        Ok(self.word.read(bytes) as usize)
    }

    /// The bytes of the array at `offset` (decompressed when the file is compressed: the header
    /// `[blocks, block size, last block's size (0: a whole block), compressed size of each
    /// block]`, then the blocks).
    fn bytes(&self, offset: usize) -> Result<Vec<u8>, String> {
        let width = self.word.width;
        let Some(compressor) = self.compressor else {
            let length = self.header(offset)?;
            let from = offset + width;
            return self
                .block
                .get(from..from.saturating_add(length))
                .map(<[u8]>::to_vec)
                .ok_or_else(|| format!("{length} bytes at {from} past the block's end"));
        };
        let blocks = self.header(offset)?;
        let (block_size, last_size) = (
            self.header(offset + width)?,
            self.header(offset + 2 * width)?,
        );
        let sizes: Vec<usize> = (0..blocks)
            .map(|k| self.header(offset + (3 + k) * width))
            .collect::<Result<_, _>>()?;
        let mut at = offset + (3 + blocks) * width;
        let mut out = Vec::new();
        for (k, size) in sizes.into_iter().enumerate() {
            let compressed = self
                .block
                .get(at..at.saturating_add(size))
                .ok_or_else(|| format!("a compressed block at {at} past the block's end"))?;
            match compressor {
                Compressor::Zlib => {
                    ZlibDecoder::new(compressed)
                        .take(MAX_FILE_BYTES)
                        .read_to_end(&mut out)
                        .map_err(|e| format!("a zlib block that does not inflate ({e})"))?;
                }
                Compressor::Lz4 => {
                    let whole = k + 1 < blocks || last_size == 0;
                    let length = if whole { block_size } else { last_size };
                    if out.len().saturating_add(length) > MAX_FILE_BYTES as usize {
                        return Err(format!("blocks of more than {MAX_FILE_BYTES} bytes"));
                    }
                    let block = lz4_flex::block::decompress(compressed, length)
                        .map_err(|e| format!("an LZ4 block that does not decompress ({e})"))?;
                    out.extend(block);
                }
            }
            at += size;
        }
        Ok(out)
    }

    /// The array at `offset` of the VTK type `kind`, as `f64`.
    fn values(&self, offset: usize, kind: &str) -> Result<Vec<f64>, String> {
        let bytes = self.bytes(offset)?;
        let be = self.word.big_endian;
        macro_rules! decode {
            ($t:ty) => {{
                const N: usize = std::mem::size_of::<$t>();
                bytes
                    .chunks_exact(N)
                    .map(|c| {
                        let word: [u8; N] = c.try_into().expect("chunks of N bytes");
                        (if be {
                            <$t>::from_be_bytes(word)
                        } else {
                            <$t>::from_le_bytes(word)
                        }) as f64
                    })
                    .collect()
            }};
        }
        Ok(match kind {
            "Float64" => decode!(f64),
            "Float32" => decode!(f32),
            "Int64" => decode!(i64),
            "UInt64" => decode!(u64),
            "Int32" => decode!(i32),
            "UInt32" => decode!(u32),
            "Int16" => decode!(i16),
            "UInt16" => decode!(u16),
            "Int8" => decode!(i8),
            "UInt8" => decode!(u8),
            other => return Err(format!("type {other:?}")),
        })
    }
}
