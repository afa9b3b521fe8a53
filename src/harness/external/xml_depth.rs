//! The nesting depth of an XML text, measured before any parser builds its tree: a document
//! nested deeper than [`MAX_XML_DEPTH`] is refused, so that a small file of a hundred thousand
//! nested elements cannot exhaust the stack of the parser or of the tree's drop.
//!
//! The scan is one pass with no allocation: an element's start tag (`<name …>`, its attribute
//! values' `>` and `/>` inside quotes skipped) opens a level unless it closes itself (`/>`), an end
//! tag (`</name>`) closes one; comments, processing instructions, CDATA sections and the document
//! type declaration open none.

use std::path::Path;

use super::error::ExternalError;

/// The deepest nesting of elements an XML file the harness reads may have: 64. The formats it
/// reads nest six levels (VTK: `VTKFile`, the grid, `Piece`, `PointData`, `DataArray`) to ten
/// (XDMF: `Xdmf`, `Domain`, the temporal and spatial collections, `Grid`, `Attribute`,
/// `DataItem`, an `xi:include`).
pub const MAX_XML_DEPTH: usize = 64;

/// Refuses the XML text `text` of the file `path` when its elements nest deeper than
/// [`MAX_XML_DEPTH`], naming the depth reached.
pub fn check_depth(path: &Path, text: &[u8]) -> Result<(), ExternalError> {
    let deepest = deepest_nesting(text, MAX_XML_DEPTH + 1);
    if deepest > MAX_XML_DEPTH {
        return Err(ExternalError::invalid(
            path,
            "file",
            None,
            format!("XML elements nested more than {MAX_XML_DEPTH} deep"),
            format!("at most {MAX_XML_DEPTH} levels of nesting"),
        ));
    }
    Ok(())
}

/// The deepest nesting of elements in `text`, counted up to `stop` (the scan ends there).
fn deepest_nesting(text: &[u8], stop: usize) -> usize {
    let (mut depth, mut deepest, mut at) = (0usize, 0usize, 0usize);
    while let Some(open) = find_byte(text, b'<', at) {
        let rest = &text[open + 1..];
        at = if rest.starts_with(b"!--") {
            end_of(text, open, b"-->")
        } else if rest.starts_with(b"![CDATA[") {
            end_of(text, open, b"]]>")
        } else if rest.starts_with(b"?") {
            end_of(text, open, b"?>")
        } else if rest.starts_with(b"!") || rest.starts_with(b"/") {
            if rest.starts_with(b"/") {
                depth = depth.saturating_sub(1);
            }
            end_of_tag(text, open)
        } else {
            let end = end_of_tag(text, open);
            if !text[..end].ends_with(b"/>") {
                depth += 1;
                deepest = deepest.max(depth);
                if deepest >= stop {
                    return deepest;
                }
            }
            end
        };
    }
    deepest
}

/// The first position of `byte` in `text` at or after `from`.
fn find_byte(text: &[u8], byte: u8, from: usize) -> Option<usize> {
    text.get(from..)?
        .iter()
        .position(|&b| b == byte)
        .map(|p| p + from)
}

/// Just past the first `marker` after `open` (the text's end when there is none).
fn end_of(text: &[u8], open: usize, marker: &[u8]) -> usize {
    text[open..]
        .windows(marker.len())
        .position(|w| w == marker)
        .map_or(text.len(), |p| open + p + marker.len())
}

/// Just past the `>` that ends the tag starting at `open`, a `>` inside a quoted attribute
/// value skipped (the text's end when there is none).
fn end_of_tag(text: &[u8], open: usize) -> usize {
    let mut quote = None;
    for (k, &b) in text.iter().enumerate().skip(open + 1) {
        match (quote, b) {
            (None, b'"' | b'\'') => quote = Some(b),
            (Some(q), _) if b == q => quote = None,
            (None, b'>') => return k + 1,
            _ => {}
        }
    }
    text.len()
}

#[cfg(test)]
mod tests {
    use super::deepest_nesting;

    #[test]
    fn elements_comments_and_quoted_markup_are_counted_as_they_nest() {
        let text = br#"<?xml version="1.0"?><!-- <a><b> --><VTKFile a="/>"><Grid><Piece/>
            <![CDATA[<x><y>]]><Data x='>'>1</Data></Grid></VTKFile>"#;
        assert_eq!(deepest_nesting(text, 100), 3);
        let deep = "<a>".repeat(1000) + &"</a>".repeat(1000);
        assert_eq!(deepest_nesting(deep.as_bytes(), 65), 65);
        assert_eq!(deepest_nesting(deep.as_bytes(), 2000), 1000);
    }
}
