//! The values of a VTK XML `DataArray`, decoded by the harness in every encoding VTK writes,
//! with every size checked against what the grid needs before anything is allocated or
//! inflated:
//! * `format="ascii"`: numbers separated by white space;
//! * `format="binary"`: base64 text inline;
//! * `format="appended"`: at `offset` into the file's `<AppendedData>` block, raw bytes
//!   (`encoding="raw"`, the offset in bytes) or base64 text (`encoding="base64"`, the offset in
//!   characters).
//!
//! Binary data (base64 or raw) starts with a header of `UInt32` or `UInt64` words
//! (`header_type`) in the file's byte order: uncompressed, the array's byte count; compressed
//! (`compressor="vtkZLibDataCompressor"` or `"vtkLZ4DataCompressor"`), `[nb, nu, np, nc_1 … nc_nb]`:
//! `nb` blocks of `nu` bytes, the last of `np` (`np = 0`: a full block), block `i` compressed to
//! `nc_i` bytes, the blocks following one after another (zlib streams, or LZ4 blocks without a
//! frame). VTK base64-encodes a compressed array's header apart from its blocks (each run padded
//! to whole quartets), and may do the same for an uncompressed one: the text is decoded run by run
//! ([`decode_runs`]), so either way gives the header's bytes then the data's.
//!
//! An array's byte count is its tuples × components × the type's size; the header must declare
//! exactly that, and each block must inflate to exactly its declared size (inflation stops one
//! byte past it), so a file cannot make the reader allocate or inflate more than its grid holds.

use std::borrow::Cow;
use std::io::Read;

use base64::engine::general_purpose::STANDARD;
use base64::Engine as _;
use flate2::read::ZlibDecoder;

use crate::harness::external::error::unquoted;

/// How a binary array's header words are stored: `UInt32` or `UInt64` (the file's
/// `header_type`), in the file's byte order.
#[derive(Clone, Copy)]
pub(super) struct HeaderWord {
    /// Bytes per word: 4 or 8.
    pub width: usize,
    /// `byte_order="BigEndian"`.
    pub big_endian: bool,
}

impl HeaderWord {
    /// The words of a file whose `VTKFile` element has these `header_type` and `byte_order`
    /// (VTK's defaults: `UInt32`, and little-endian when `byte_order` is left out, as DOLFINx
    /// does).
    pub fn of(root: roxmltree::Node<'_, '_>) -> Self {
        Self {
            width: if root.attribute("header_type") == Some("UInt64") {
                8
            } else {
                4
            },
            big_endian: root.attribute("byte_order") == Some("BigEndian"),
        }
    }

    /// The word at `at` in `bytes`, or why there is none.
    fn read(self, bytes: &[u8], at: usize) -> Result<usize, String> {
        let end = at.checked_add(self.width).filter(|&e| e <= bytes.len());
        let Some(word) = end.map(|e| &bytes[at..e]) else {
            return Err(format!("a header word at byte {at} past the data's end"));
        };
        let mut padded = [0u8; 8];
        let value = if self.big_endian {
            padded[8 - self.width..].copy_from_slice(word);
            u64::from_be_bytes(padded)
        } else {
            padded[..self.width].copy_from_slice(word);
            u64::from_le_bytes(padded)
        };
        usize::try_from(value).map_err(|_| format!("a header word {value} beyond memory"))
    }
}

/// How a compressed file's blocks are compressed: VTK's two block compressors.
#[derive(Clone, Copy)]
pub(super) enum Compressor {
    /// `vtkZLibDataCompressor`: zlib streams.
    Zlib,
    /// `vtkLZ4DataCompressor`: LZ4 blocks (no frame).
    Lz4,
}

impl Compressor {
    /// The file's compressor: `None` for none; an unknown one is refused.
    pub fn of(root: roxmltree::Node<'_, '_>) -> Result<Option<Self>, String> {
        match root.attribute("compressor") {
            None | Some("") => Ok(None),
            Some("vtkZLibDataCompressor") => Ok(Some(Self::Zlib)),
            Some("vtkLZ4DataCompressor") => Ok(Some(Self::Lz4)),
            Some(other) => Err(format!(
                "compressor {:?}: allowed none, vtkZLibDataCompressor or vtkLZ4DataCompressor",
                unquoted(other)
            )),
        }
    }
}

/// A file's `<AppendedData>` block as read.
pub(super) enum Appended<'a> {
    /// `encoding="raw"`: the bytes after its `_`.
    Raw(&'a [u8]),
    /// `encoding="base64"`: the characters after its `_`.
    Base64(&'a [u8]),
}

/// How a file's binary arrays are laid out.
pub(super) struct Layout<'a> {
    /// The header's words.
    pub word: HeaderWord,
    /// The compressor, if any.
    pub compressor: Option<Compressor>,
    /// The appended block, if any.
    pub appended: Option<Appended<'a>>,
}

/// The scalar types of VTK arrays the harness reads, with their sizes.
#[derive(Clone, Copy, PartialEq)]
pub(super) enum Scalar {
    F64,
    F32,
    I64,
    U64,
    I32,
    U32,
    I16,
    U16,
    I8,
    U8,
}

impl Scalar {
    /// The scalar of a `DataArray`'s `type`.
    pub fn of(kind: &str) -> Result<Self, String> {
        Ok(match kind {
            "Float64" => Self::F64,
            "Float32" => Self::F32,
            "Int64" => Self::I64,
            "UInt64" => Self::U64,
            "Int32" => Self::I32,
            "UInt32" => Self::U32,
            "Int16" => Self::I16,
            "UInt16" => Self::U16,
            "Int8" => Self::I8,
            "UInt8" => Self::U8,
            other => return Err(format!("type {:?}", unquoted(other))),
        })
    }

    /// Bytes per value.
    fn size(self) -> usize {
        match self {
            Self::F64 | Self::I64 | Self::U64 => 8,
            Self::F32 | Self::I32 | Self::U32 => 4,
            Self::I16 | Self::U16 => 2,
            Self::I8 | Self::U8 => 1,
        }
    }

    /// `bytes` (whole values of this type in the given byte order) as `f64`.
    fn decode(self, bytes: &[u8], big_endian: bool) -> Vec<f64> {
        macro_rules! decode {
            ($t:ty) => {{
                const N: usize = std::mem::size_of::<$t>();
                bytes
                    .chunks_exact(N)
                    .map(|c| {
                        let mut word = [0u8; N];
                        word.copy_from_slice(c);
                        (if big_endian {
                            <$t>::from_be_bytes(word)
                        } else {
                            <$t>::from_le_bytes(word)
                        }) as f64
                    })
                    .collect()
            }};
        }
        match self {
            Self::F64 => decode!(f64),
            Self::F32 => decode!(f32),
            Self::I64 => decode!(i64),
            Self::U64 => decode!(u64),
            Self::I32 => decode!(i32),
            Self::U32 => decode!(u32),
            Self::I16 => decode!(i16),
            Self::U16 => decode!(u16),
            Self::I8 => decode!(i8),
            Self::U8 => decode!(u8),
        }
    }
}

/// Where a binary array's header starts: in raw bytes, or in base64 characters.
enum Source<'a> {
    /// Raw bytes, the header at the given byte.
    Raw(&'a [u8], usize),
    /// Base64 characters, the header at the first of them.
    Base64(&'a [u8]),
}

impl Source<'_> {
    /// The array's first `n` bytes, header included (fewer when the data ends first): raw
    /// bytes borrowed, base64 decoded only as far as `n`.
    fn prefix(&self, n: usize) -> Result<Cow<'_, [u8]>, String> {
        match *self {
            Self::Raw(bytes, at) => {
                let from = at.min(bytes.len());
                Ok(Cow::Borrowed(
                    &bytes[from..from.saturating_add(n).min(bytes.len())],
                ))
            }
            Self::Base64(chars) => decode_runs(chars, n).map(Cow::Owned),
        }
    }
}

impl Layout<'_> {
    /// The `count` values of type `scalar` of the array `node` (its text inline, or its offset
    /// into the appended block), as `f64`; why they cannot be read otherwise.
    pub fn values(
        &self,
        node: roxmltree::Node<'_, '_>,
        scalar: Scalar,
        count: usize,
    ) -> Result<Vec<f64>, String> {
        let text = || node.text().unwrap_or("").as_bytes();
        let source = match node.attribute("format").unwrap_or("") {
            "ascii" => return ascii_values(text(), count),
            "binary" => Source::Base64(trimmed(text())),
            "appended" => {
                let offset: usize = node
                    .attribute("offset")
                    .unwrap_or("")
                    .trim()
                    .parse()
                    .map_err(|_| "an appended array without a numeric offset".to_string())?;
                match self.appended {
                    Some(Appended::Raw(block)) => Source::Raw(block, offset),
                    Some(Appended::Base64(chars)) => Source::Base64(
                        chars
                            .get(offset..)
                            .ok_or_else(|| format!("offset {offset} past the data's end"))?,
                    ),
                    None => return Err("an appended array in a file without <AppendedData>".into()),
                }
            }
            other => {
                return Err(format!(
                    "format {:?}: allowed ascii, binary or appended",
                    unquoted(other)
                ))
            }
        };
        let length = count
            .checked_mul(scalar.size())
            .ok_or_else(|| format!("{count} values beyond memory"))?;
        let inline = matches!(node.attribute("format"), Some("binary"));
        let data = match self.compressor {
            None => self.uncompressed(&source, length, scalar, inline)?,
            Some(compressor) => self.inflated(&source, length, compressor)?,
        };
        Ok(scalar.decode(&data, self.word.big_endian))
    }

    /// The `length` bytes of the uncompressed array at `source`: its header must declare them,
    /// but for an `inline` array whose text holds exactly a header and `length` bytes: there the
    /// text delimits the data, and GetFEM 5.4.2's exporter writes a `Float32` count of values in
    /// the header of its point data (`tests/data/external/getfem-vtu/`).
    fn uncompressed(
        &self,
        source: &Source<'_>,
        length: usize,
        scalar: Scalar,
        inline: bool,
    ) -> Result<Vec<u8>, String> {
        let width = self.word.width;
        let bytes = source.prefix(width + length + 1)?;
        let declared = self.word.read(&bytes, 0)?;
        let delimited = inline && bytes.len() == width + length;
        if declared != length && !delimited {
            return Err(format!(
                "a header of {declared} bytes where the grid needs {length} ({} values of {} \
                 bytes)",
                length / scalar.size(),
                scalar.size()
            ));
        }
        bytes
            .get(width..width + length)
            .map(<[u8]>::to_vec)
            .ok_or_else(|| format!("{length} bytes past the data's end"))
    }

    /// The `length` bytes of the compressed array at `source`.
    fn inflated(
        &self,
        source: &Source<'_>,
        length: usize,
        compressor: Compressor,
    ) -> Result<Vec<u8>, String> {
        let width = self.word.width;
        let head = source.prefix(3 * width)?;
        let (blocks, block_size, last) = (
            self.word.read(&head, 0)?,
            self.word.read(&head, width)?,
            self.word.read(&head, 2 * width)?,
        );
        let last = if last == 0 { block_size } else { last };
        let declared = match blocks {
            0 => Some(0),
            n => block_size
                .checked_mul(n - 1)
                .and_then(|b| b.checked_add(last)),
        };
        if declared != Some(length) || (blocks > 0 && (block_size == 0 || last > block_size)) {
            return Err(format!(
                "a header of {blocks} blocks of {block_size} bytes, the last of {last}, where \
                 the grid needs {length} bytes"
            ));
        }
        let header_length = (3 + blocks) * width;
        let head = source.prefix(header_length)?;
        let sizes = (0..blocks)
            .map(|k| self.word.read(&head, (3 + k) * width))
            .collect::<Result<Vec<_>, _>>()?;
        let total = sizes
            .iter()
            .try_fold(header_length, |sum, &size| sum.checked_add(size))
            .ok_or_else(|| "compressed sizes beyond memory".to_string())?;
        let bytes = source.prefix(total)?;
        let mut start = header_length;
        let mut out = Vec::with_capacity(length);
        for (k, size) in sizes.into_iter().enumerate() {
            let end = start + size;
            let compressed = bytes
                .get(start..end)
                .ok_or_else(|| format!("compressed block {k} past the data's end"))?;
            let expected = if k + 1 == blocks { last } else { block_size };
            let before = out.len();
            match compressor {
                Compressor::Zlib => {
                    ZlibDecoder::new(compressed)
                        .take(expected as u64 + 1)
                        .read_to_end(&mut out)
                        .map_err(|e| {
                            format!("zlib block {k} does not inflate ({})", unquoted(e))
                        })?;
                }
                Compressor::Lz4 => {
                    out.resize(before + expected, 0);
                    let written = lz4_flex::block::decompress_into(compressed, &mut out[before..])
                        .map_err(|e| {
                            format!("LZ4 block {k} does not decompress ({})", unquoted(e))
                        })?;
                    out.truncate(before + written);
                }
            }
            let inflated = out.len() - before;
            if inflated != expected {
                let more = if inflated > expected { " or more" } else { "" };
                return Err(format!(
                    "compressed block {k} inflates to {inflated}{more} bytes where its header \
                     says {expected}"
                ));
            }
            start = end;
        }
        Ok(out)
    }
}

/// `text` without its leading and trailing white space.
fn trimmed(text: &[u8]) -> &[u8] {
    let start = text.iter().position(|b| !b.is_ascii_whitespace());
    let end = text.iter().rposition(|b| !b.is_ascii_whitespace());
    match (start, end) {
        (Some(s), Some(e)) => &text[s..=e],
        _ => &[],
    }
}

/// Exactly `count` numbers of the white-space separated text `text`.
fn ascii_values(text: &[u8], count: usize) -> Result<Vec<f64>, String> {
    let text = std::str::from_utf8(text).map_err(|_| "ASCII data that is not text".to_string())?;
    let mut values = Vec::with_capacity(count);
    for token in text.split_ascii_whitespace() {
        if values.len() == count {
            return Err(format!("more than the {count} values the grid needs"));
        }
        let value: f64 = token
            .parse()
            .map_err(|_| format!("value {} {:?}, not a number", values.len(), unquoted(token)))?;
        values.push(value);
    }
    if values.len() != count {
        return Err(format!(
            "{} values where the grid needs {count}",
            values.len()
        ));
    }
    Ok(values)
}

/// The first `n` bytes (fewer when the text ends first) of the base64 text `chars`, decoded
/// quartet by quartet: a run ends with its padding (`=`), so that a header encoded apart from
/// its data decodes to the header's bytes then the data's. White space is skipped.
fn decode_runs(chars: &[u8], n: usize) -> Result<Vec<u8>, String> {
    let mut out = Vec::with_capacity(n.min(chars.len() / 4 * 3));
    let mut quartet = Vec::with_capacity(4);
    for (k, &c) in chars.iter().enumerate() {
        if out.len() >= n {
            break;
        }
        if c.is_ascii_whitespace() {
            continue;
        }
        quartet.push(c);
        if quartet.len() == 4 {
            STANDARD
                .decode_vec(&quartet, &mut out)
                .map_err(|_| format!("base64 text that does not decode (at character {k})"))?;
            quartet.clear();
        }
    }
    if !quartet.is_empty() && out.len() < n {
        return Err(format!(
            "base64 text of {} characters past its last whole quartet",
            quartet.len()
        ));
    }
    Ok(out)
}
