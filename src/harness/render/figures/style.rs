//! The shared look of every figure: sizes, fonts, palette and tick labels.

use plotters::style::RGBColor;

/// Size of a figure with one panel.
pub(super) const SINGLE: (u32, u32) = (800, 500);
/// Width of each panel when several stand side by side (two panels: 1200 px).
pub(super) const PANEL_WIDTH: u32 = 600;
/// Height of a figure (one row of panels).
pub(super) const HEIGHT: u32 = 500;

/// Font family of all text (no font file is needed: the SVG names the family).
pub(super) const FONT: &str = "sans-serif";
/// Figure title.
pub(super) const TITLE_SIZE: u32 = 28;
/// Caption of one chart (panel label).
pub(super) const CAPTION_SIZE: u32 = 22;
/// Axis descriptions.
pub(super) const AXIS_DESC_SIZE: u32 = 20;
/// Tick labels.
pub(super) const TICK_SIZE: u32 = 16;
/// Legend text.
pub(super) const LEGEND_SIZE: u32 = 16;

/// Stroke width of computed curves.
pub(super) const RUN_WIDTH: u32 = 2;
/// Stroke width of the exact solution, drawn beneath the computed curves.
pub(super) const EXACT_WIDTH: u32 = 4;
/// Radius of the markers of convergence and work–precision curves.
pub(super) const MARKER_RADIUS: u32 = 4;
/// Opacity of an ensemble's shaded band (and of its legend swatch) in its curve's colour.
pub(super) const BAND_OPACITY: f64 = 0.2;

/// The exact solution's colour.
pub(super) const EXACT: RGBColor = RGBColor(0, 0, 0);

/// Colours of the computed curves, taken in order (and cyclically past the tenth).
const PALETTE: [RGBColor; 10] = [
    RGBColor(31, 119, 180),  // blue
    RGBColor(214, 39, 40),   // red
    RGBColor(44, 160, 44),   // green
    RGBColor(255, 127, 14),  // orange
    RGBColor(148, 103, 189), // purple
    RGBColor(140, 86, 75),   // brown
    RGBColor(227, 119, 194), // pink
    RGBColor(23, 190, 207),  // cyan
    RGBColor(188, 189, 34),  // olive
    RGBColor(127, 127, 127), // grey
];

/// The `index`-th colour of the palette.
pub(super) fn colour(index: usize) -> RGBColor {
    PALETTE[index % PALETTE.len()]
}

/// A tick label on a linear axis: at most four decimals, trailing zeros removed; scientific
/// notation for very large or very small magnitudes.
pub(super) fn linear_tick(v: f64) -> String {
    let a = v.abs();
    if a < 1e-12 {
        return "0".into();
    }
    if !(1e-3..1e5).contains(&a) {
        return format!("{v:.1e}");
    }
    let s = format!("{v:.4}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" {
        "0".into()
    } else {
        s.into()
    }
}

/// A tick label on a logarithmic axis of base 2: `1/2^k` is written as the fraction `1/8`,
/// `2^k` as the integer; anything else in scientific notation.
pub(super) fn log2_tick(v: f64) -> String {
    let k = v.log2().round();
    if (v.log2() - k).abs() < 1e-9 {
        if k >= 0.0 {
            format!("{}", 2f64.powi(k as i32))
        } else {
            format!("1/{}", 2f64.powi(-k as i32))
        }
    } else {
        format!("{v:.2e}")
    }
}

/// A tick label on a logarithmic axis of base 10: `1e-3`, `2e-3`, `5e-3`, `1e-2`, …; ticks at
/// 3, 4, 6, 7, 8, 9 times a power stay unlabelled (their labels would crowd the top of each
/// decade).
pub(super) fn log10_tick(v: f64) -> String {
    let label = format!("{v:.0e}");
    match label.as_bytes().first() {
        Some(b'1' | b'2' | b'5') => label,
        _ => String::new(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tick_labels_are_short() {
        assert_eq!(linear_tick(0.5), "0.5");
        assert_eq!(linear_tick(0.30000000000000004), "0.3");
        assert_eq!(linear_tick(-1e-17), "0");
        assert_eq!(linear_tick(2.0), "2");
        assert_eq!(linear_tick(2.5e-5), "2.5e-5");
        assert_eq!(log2_tick(0.125), "1/8");
        assert_eq!(log2_tick(4.0), "4");
        assert_eq!(log10_tick(0.001), "1e-3");
        assert_eq!(log10_tick(0.0019999999), "2e-3");
        assert_eq!(log10_tick(0.05), "5e-2");
        assert_eq!(log10_tick(0.0029999999), "");
    }
}
