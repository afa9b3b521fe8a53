//! The geometry of a drawn figure, as the drawing code laid it out: canvas, title, and per
//! chart its plotting area, legend box, series styles and extents, axis descriptions, ranges
//! and tick labels.
//!
//! Every figure carries its layout inside its SVG, as JSON in a `<metadata>` element (which
//! renderers ignore), so that a test can check any committed figure against its own geometry
//! without the data it was drawn from: titles inside the canvas, legends clear of the data,
//! distinct styles and tick labels, a tick at every level of a log axis, fitted slopes drawn,
//! compared panels on one scale.

use serde::{Deserialize, Serialize};

/// The `id` of the `<metadata>` element that holds a figure's layout.
pub const METADATA_ID: &str = "signorini-figure-layout";

/// A rectangle in pixels of the canvas: `x0 ≤ x1` left to right, `y0 ≤ y1` top to bottom.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct Rect {
    /// Left edge.
    pub x0: i32,
    /// Top edge.
    pub y0: i32,
    /// Right edge.
    pub x1: i32,
    /// Bottom edge.
    pub y1: i32,
}

impl Rect {
    /// The rectangle spanned by the pixel ranges `(x, y)` of a plotting area
    /// (`get_pixel_range`).
    pub fn spanning((x, y): (std::ops::Range<i32>, std::ops::Range<i32>)) -> Self {
        Self {
            x0: x.start,
            y0: y.start,
            x1: x.end,
            y1: y.end,
        }
    }

    /// Whether `other` lies wholly inside this rectangle (edges included).
    pub fn contains(&self, other: &Rect) -> bool {
        other.x0 >= self.x0 && other.x1 <= self.x1 && other.y0 >= self.y0 && other.y1 <= self.y1
    }
}

/// A line of text and the box it is estimated to take (from its font size and a generous
/// per-character width; the rendered glyphs are what a test should trust).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TextBox {
    /// The text as drawn.
    pub text: String,
    /// Its estimated extent.
    pub rect: Rect,
}

/// One labelled tick of an axis.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Tick {
    /// The value at the tick.
    pub value: f64,
    /// Its label as drawn.
    pub label: String,
}

/// One axis of a chart (or a colour bar).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct AxisLayout {
    /// The axis description, e.g. `"h"`.
    pub label: String,
    /// Whether the axis is logarithmic.
    pub log: bool,
    /// The labelled ticks, in the order drawn.
    pub ticks: Vec<Tick>,
    /// The levels the data sit at along this axis (the mesh sizes of a convergence plot), each
    /// of which must carry a tick; empty when the axis has none.
    pub levels: Vec<f64>,
    /// The axis' range `[low, high]` as drawn; `None` in a figure drawn before it was recorded.
    #[serde(default)]
    pub range: Option<[f64; 2]>,
}

/// What a series of a chart is.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum SeriesKind {
    /// Computed values (or a reference's).
    #[default]
    Data,
    /// The exact solution.
    Exact,
    /// A fitted slope, `C·h^p` over the levels of the series it fits.
    Fit,
    /// A legend entry with nothing drawn (a run left out, e.g. a diverged one).
    Note,
}

/// One series as the legend names it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SeriesLayout {
    /// The legend text.
    pub label: String,
    /// Its stroke colour, `[r, g, b]`.
    pub colour: [u8; 3],
    /// Its dash ([`super::style::Dash::name`]).
    #[serde(default)]
    pub dash: String,
    /// Its marker ([`super::style::Marker::name`]), if any.
    #[serde(default)]
    pub marker: Option<String>,
    /// What it is.
    #[serde(default)]
    pub kind: SeriesKind,
    /// What its shaded band shows (e.g. `"round-off min–max of 16 runs"`), if it has one.
    #[serde(default)]
    pub band: Option<String>,
    /// The smallest and largest of its values drawn (y), if any is.
    #[serde(default)]
    pub extent: Option<[f64; 2]>,
}

/// One chart (or one panel of a map).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ChartLayout {
    /// The plotting area: where the data are drawn.
    pub plot: Rect,
    /// The caption above the chart, if any.
    pub caption: Option<TextBox>,
    /// The horizontal axis.
    pub x: AxisLayout,
    /// The vertical axis.
    pub y: AxisLayout,
    /// The legend box, if the chart has a legend; everything drawn before it in the SVG is
    /// data or axes, everything inside it after it is the legend.
    pub legend: Option<Rect>,
    /// The series, in legend order (those of a chart without a legend too).
    pub series: Vec<SeriesLayout>,
    /// The colour bar of a map: its box and its axis.
    pub colour_bar: Option<(Rect, AxisLayout)>,
    /// Charts of a figure with the same group are compared and share their y axis (a map's
    /// panels, their colour scale).
    #[serde(default)]
    pub scale_group: Option<String>,
}

/// A whole figure.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FigureLayout {
    /// Canvas width in pixels.
    pub width: u32,
    /// Canvas height in pixels.
    pub height: u32,
    /// The title at the top of the canvas.
    pub title: TextBox,
    /// The charts, column by column, top to bottom.
    pub charts: Vec<ChartLayout>,
}

impl FigureLayout {
    /// The canvas as a rectangle.
    pub fn canvas(&self) -> Rect {
        Rect {
            x0: 0,
            y0: 0,
            x1: self.width as i32,
            y1: self.height as i32,
        }
    }

    /// Appends this layout to `svg` (a whole SVG document) as a `<metadata>` element just
    /// before the closing `</svg>`, its JSON escaped for XML.
    pub(super) fn embed(&self, svg: &mut String) -> Result<(), serde_json::Error> {
        let json = serde_json::to_string(self)?;
        let escaped = json
            .replace('&', "&amp;")
            .replace('<', "&lt;")
            .replace('>', "&gt;");
        let at = svg.rfind("</svg>").unwrap_or(svg.len());
        svg.insert_str(
            at,
            &format!("<metadata id=\"{METADATA_ID}\">{escaped}</metadata>\n"),
        );
        Ok(())
    }

    /// Reads the layout embedded in `svg` by the drawing code: `None` when the document has
    /// none (or is not XML), `Some(Err)` when its JSON does not parse.
    pub fn from_svg(svg: &str) -> Option<Result<Self, serde_json::Error>> {
        let start = svg.find(&format!("<metadata id=\"{METADATA_ID}\">"))?;
        let body = &svg[start..];
        let open = body.find('>')? + 1;
        let close = body.find("</metadata>")?;
        let json = body[open..close]
            .replace("&lt;", "<")
            .replace("&gt;", ">")
            .replace("&amp;", "&");
        Some(serde_json::from_str(&json))
    }
}

/// Estimated width in pixels of `text` drawn at plotters font size `size` (the SVG's font size
/// is `size / 1.24`): 0.6 em per character, more than the average glyph of common sans-serif
/// fonts, so that boxes err on the large side.
pub(super) fn text_width(text: &str, size: f64) -> i32 {
    (text.chars().count() as f64 * 0.6 * size / 1.24).ceil() as i32
}

/// Estimated height in pixels of a line of text at plotters font size `size`.
pub(super) fn text_height(size: f64) -> i32 {
    (1.2 * size / 1.24).ceil() as i32
}

/// The box of `text` at plotters font size `size`, centred horizontally on `cx`, its top at
/// `top`.
pub(super) fn centred_text(text: &str, size: f64, cx: i32, top: i32) -> TextBox {
    let w = text_width(text, size);
    TextBox {
        text: text.to_owned(),
        rect: Rect {
            x0: cx - w / 2,
            y0: top,
            x1: cx - w / 2 + w,
            y1: top + text_height(size),
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_layout_survives_its_round_trip_through_an_svg() {
        let layout = FigureLayout {
            width: 800,
            height: 500,
            title: centred_text("a < b & c", 28.0, 400, 5),
            charts: vec![],
        };
        let mut svg = String::from("<svg>\n</svg>\n");
        layout.embed(&mut svg).unwrap();
        assert!(svg.contains("a &lt; b &amp; c"), "{svg}");
        assert!(svg.ends_with("</metadata>\n</svg>\n"), "{svg}");
        assert_eq!(FigureLayout::from_svg(&svg).unwrap().unwrap(), layout);
        assert!(FigureLayout::from_svg("<svg/>").is_none());
    }
}
