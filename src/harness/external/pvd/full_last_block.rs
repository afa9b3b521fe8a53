//! vtkio 0.7.0-rc2 sizes a compressed base64 array as `nu·(nb − 1) + np` (`nb` blocks of `nu`
//! bytes, the last of `np`), so it reads short an array whose last block is full, for which VTK
//! writes `np = 0` (`tests/data/external/vtk-encodings/*-block64.vtu`, `*-block88.vtu`). Before
//! vtkio parses a compressed file, every such header's `np` is set to `nu` here: the same array
//! as VTK reads it, its header re-encoded to the same number of characters, so that every other
//! byte, and every appended offset, stays where it was.
//!
//! A compressed base64 array starts with its header `[nb, nu, np, nb compressed sizes]` of
//! `UInt32` or `UInt64` words (`header_type`), base64-encoded on its own (the blocks follow,
//! encoded apart): inline, the text of a `DataArray format="binary"`; appended, the characters
//! of an `<AppendedData encoding="base64">` block at the array's `offset`.

use base64::engine::general_purpose::STANDARD;
use base64::Engine as _;

use super::HeaderWord;

/// `bytes` (a `.vtu` read whole, parsed as XML text) with every compressed base64 header whose
/// last block is full given that block's size as its last size; unchanged when it has none, is
/// not compressed, or is not XML text.
pub(super) fn with_full_last_blocks(mut bytes: Vec<u8>) -> Vec<u8> {
    let Some((starts, word)) = header_starts(&bytes) else {
        return bytes;
    };
    for start in starts {
        if let Some((at, encoded)) = fixed_header(&bytes, start, word) {
            bytes[at..at + encoded.len()].copy_from_slice(&encoded);
        }
    }
    bytes
}

/// Where each compressed base64 array's header starts in `bytes`, with how its words are
/// stored; `None` when the file is not compressed XML text.
fn header_starts(bytes: &[u8]) -> Option<(Vec<usize>, HeaderWord)> {
    let text = std::str::from_utf8(bytes).ok()?;
    let document = roxmltree::Document::parse(text).ok()?;
    let root = document.root_element();
    root.attribute("compressor").filter(|c| !c.is_empty())?;
    let skip_space = |at: usize| at + text[at..].len() - text[at..].trim_start().len();
    let appended = root
        .descendants()
        .find(|n| n.has_tag_name("AppendedData") && n.attribute("encoding") == Some("base64"))
        .and_then(|n| n.first_child())
        .and_then(|t| {
            let range = t.range();
            text[range.clone()].find('_').map(|u| range.start + u + 1)
        });
    let mut starts = Vec::new();
    for array in root.descendants().filter(|n| n.has_tag_name("DataArray")) {
        match array.attribute("format") {
            Some("binary") => {
                if let Some(t) = array.first_child().filter(|t| t.is_text()) {
                    starts.push(skip_space(t.range().start));
                }
            }
            Some("appended") => {
                let offset = array
                    .attribute("offset")
                    .and_then(|o| o.parse::<usize>().ok());
                if let (Some(base), Some(offset)) = (appended, offset) {
                    starts.push(base + offset);
                }
            }
            _ => {}
        }
    }
    Some((starts, HeaderWord::of(root)))
}

/// The header at `start` re-encoded with its last size set to its block size, when its last
/// block is full (`np = 0` with at least one block): where it starts and its characters.
fn fixed_header(bytes: &[u8], start: usize, word: HeaderWord) -> Option<(usize, Vec<u8>)> {
    let fixed_chars = 4 * word.width;
    let head = STANDARD
        .decode(bytes.get(start..start + fixed_chars)?)
        .ok()?;
    let (blocks, block_size, last) = (
        word.read(&head),
        word.read(&head[word.width..]),
        word.read(&head[2 * word.width..]),
    );
    if blocks == 0 || last != 0 {
        return None;
    }
    let length = (3 + usize::try_from(blocks).ok()?).checked_mul(word.width)?;
    let chars = 4 * length.div_ceil(3);
    let mut header = STANDARD.decode(bytes.get(start..start + chars)?).ok()?;
    if header.len() != length {
        return None;
    }
    word.write(block_size, &mut header[2 * word.width..]);
    let encoded = STANDARD.encode(&header).into_bytes();
    (encoded.len() == chars).then_some((start, encoded))
}
