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

/// Colours of the computed curves, taken in order, each with a lighter partner of the same
/// hue (the two columns of the "tab20" palette): the light one draws an exact curve beside its
/// computed one, or the second mass of a scheme when a figure has more series than hues.
const PALETTE: [(RGBColor, RGBColor); 10] = [
    (RGBColor(31, 119, 180), RGBColor(174, 199, 232)), // blue
    (RGBColor(214, 39, 40), RGBColor(255, 152, 150)),  // red
    (RGBColor(44, 160, 44), RGBColor(152, 223, 138)),  // green
    (RGBColor(255, 127, 14), RGBColor(255, 187, 120)), // orange
    (RGBColor(148, 103, 189), RGBColor(197, 176, 213)), // purple
    (RGBColor(140, 86, 75), RGBColor(196, 156, 148)),  // brown
    (RGBColor(227, 119, 194), RGBColor(247, 182, 210)), // pink
    (RGBColor(23, 190, 207), RGBColor(158, 218, 229)), // cyan
    (RGBColor(188, 189, 34), RGBColor(219, 219, 141)), // olive
    (RGBColor(127, 127, 127), RGBColor(199, 199, 199)), // grey
];

/// Number of hues: a figure with more series than this repeats colours.
pub(super) const HUES: usize = PALETTE.len();

/// The palette's hues whose dark and light shades are all at least 50 apart in RGB (red,
/// green, purple, brown, pink, cyan, olive; then the rest): the hues of series taken in pairs.
const PAIR_HUES: [usize; 10] = [1, 2, 4, 5, 6, 7, 8, 0, 3, 9];

/// The palette index of the `k`-th pair of series that share a hue (dark and light).
pub(super) fn pair_hue(k: usize) -> usize {
    PAIR_HUES[k % PAIR_HUES.len()]
}

/// The `index`-th colour of the palette (cyclically past the tenth), dark or `light`.
pub(super) fn colour(index: usize, light: bool) -> RGBColor {
    let (dark, pale) = PALETTE[index % PALETTE.len()];
    if light {
        pale
    } else {
        dark
    }
}

/// The smallest of 1, 2 and 5 times a power of ten that is at least `spacing` (positive):
/// a round step for ticks at least `spacing` apart.
pub(super) fn nice_step(spacing: f64) -> f64 {
    let power = 10f64.powf(spacing.log10().floor());
    [1.0, 2.0, 5.0, 10.0]
        .into_iter()
        .map(|m| m * power)
        .find(|&s| s >= spacing * (1.0 - 1e-12))
        .unwrap_or(10.0 * power)
}

/// The number of decimals that keeps apart labels at least `step` apart: the position of the
/// step's leading digit after the point (0 for steps of 1 and more).
fn decimals_for(step: f64) -> usize {
    if step > 0.0 && step.is_finite() {
        (-step.log10()).ceil().max(0.0) as usize
    } else {
        4
    }
}

/// A tick label on a linear axis whose labels are at least `step` apart: as many decimals as
/// the step needs to keep neighbours distinct, trailing zeros removed; scientific notation for
/// very large or very small magnitudes, with as many digits as the step needs.
pub(super) fn linear_tick(v: f64, step: f64) -> String {
    let a = v.abs();
    if a < 1e-9 * step.abs().max(1e-300) || a < 1e-300 {
        return "0".into();
    }
    if !(1e-3..1e5).contains(&a) {
        let digits = if step > 0.0 && step.is_finite() {
            (a.log10().floor() - step.log10().floor()).max(1.0) as usize
        } else {
            1
        };
        return format!("{v:.digits$e}");
    }
    let s = format!("{v:.*}", decimals_for(step));
    let s = if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.')
    } else {
        s.as_str()
    };
    if s == "-0" {
        "0".into()
    } else {
        s.into()
    }
}

/// A tick label at a mesh size: `1/N` when `1/h` is (nearly) the integer N, `N` when `h` is;
/// three significant digits otherwise.
pub(super) fn level_tick(h: f64) -> String {
    let inv = 1.0 / h;
    if (inv - inv.round()).abs() < 1e-6 * inv && inv.round() >= 1.0 {
        format!("1/{}", inv.round())
    } else if (h - h.round()).abs() < 1e-6 * h {
        format!("{}", h.round())
    } else {
        format!("{h:.3}")
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
        assert_eq!(linear_tick(0.5, 0.1), "0.5");
        assert_eq!(linear_tick(0.30000000000000004, 0.1), "0.3");
        assert_eq!(linear_tick(-1e-17, 0.1), "0");
        assert_eq!(linear_tick(2.0, 0.5), "2");
        assert_eq!(linear_tick(2.5e-5, 1e-5), "2.5e-5");
        // Close values around 0.0123: the step sets the decimals, so the labels differ.
        let labels: Vec<String> = [0.012301, 0.012302, 0.012303]
            .iter()
            .map(|&v| linear_tick(v, 1e-6))
            .collect();
        assert_eq!(labels, ["0.012301", "0.012302", "0.012303"]);
        assert_eq!(nice_step(0.3), 0.5);
        assert_eq!(nice_step(0.2), 0.2);
        assert_eq!(nice_step(0.7), 1.0);
        assert_eq!(level_tick(0.1), "1/10");
        assert_eq!(level_tick(1.0 / 640.0), "1/640");
        assert_eq!(level_tick(2.0), "2");
        assert_eq!(level_tick(0.3), "0.300");
        assert_eq!(log10_tick(0.001), "1e-3");
        assert_eq!(log10_tick(0.0019999999), "2e-3");
        assert_eq!(log10_tick(0.05), "5e-2");
        assert_eq!(log10_tick(0.0029999999), "");
    }
}
