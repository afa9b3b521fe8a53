//! The shared look of every figure: sizes, fonts, palette, dashes, markers and tick labels.

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
/// Stroke width of an exact solution (dashed, drawn over the computed curves) and of a fitted
/// slope.
pub(super) const EXACT_WIDTH: u32 = 2;
/// Radius of the markers of convergence and work–precision curves.
pub(super) const MARKER_RADIUS: u32 = 4;
/// Opacity of an ensemble's shaded band (and of its legend swatch) in its curve's colour.
pub(super) const BAND_OPACITY: f64 = 0.2;

/// The exact solution's colour.
pub const EXACT: RGBColor = RGBColor(0, 0, 0);

/// Colours of the computed curves, taken in order: the Okabe–Ito palette (Okabe and Ito 2008,
/// "Color Universal Design"), told apart with the common colour-vision deficiencies, without its
/// black (the exact solution's) and with its yellow, too pale on white, replaced by a grey.
pub const PALETTE: [RGBColor; 7] = [
    RGBColor(0, 114, 178),   // blue
    RGBColor(213, 94, 0),    // vermillion
    RGBColor(0, 158, 115),   // bluish green
    RGBColor(204, 121, 167), // reddish purple
    RGBColor(230, 159, 0),   // orange
    RGBColor(86, 180, 233),  // sky blue
    RGBColor(102, 102, 102), // grey
];

/// The `index`-th colour of the palette (cyclically past the seventh).
pub(super) fn colour(index: usize) -> RGBColor {
    PALETTE[index % PALETTE.len()]
}

/// How a line is stroked: its dash and gap lengths in pixels, `None` for a solid line.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Dash {
    /// Solid.
    Solid,
    /// Dashes of 10 px, gaps of 5 px.
    Dashed,
    /// Dots of 2 px, gaps of 4 px.
    Dotted,
    /// Dashes of 20 px, gaps of 6 px.
    LongDashed,
    /// Dots of 2 px, gaps of 9 px.
    LooselyDotted,
}

impl Dash {
    /// The dashes taken in order by the series of a chart without markers.
    pub const ORDER: [Dash; 4] = [Dash::Solid, Dash::Dashed, Dash::Dotted, Dash::LongDashed];

    /// Dash and gap in pixels, `None` when solid.
    pub(super) fn pattern(self) -> Option<(u32, u32)> {
        match self {
            Dash::Solid => None,
            Dash::Dashed => Some((10, 5)),
            Dash::Dotted => Some((2, 4)),
            Dash::LongDashed => Some((20, 6)),
            Dash::LooselyDotted => Some((2, 9)),
        }
    }

    /// Its name in a figure's layout.
    pub fn name(self) -> &'static str {
        match self {
            Dash::Solid => "solid",
            Dash::Dashed => "dashed",
            Dash::Dotted => "dotted",
            Dash::LongDashed => "long-dashed",
            Dash::LooselyDotted => "loosely-dotted",
        }
    }
}

/// The shape of a curve's markers.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Marker {
    /// A filled disc.
    Circle,
    /// A filled square.
    Square,
    /// A filled triangle pointing up.
    TriangleUp,
    /// A filled diamond.
    Diamond,
    /// A filled triangle pointing down.
    TriangleDown,
    /// A ring.
    Ring,
    /// An open square.
    OpenSquare,
}

impl Marker {
    /// The markers taken in order by the series (or groups of series) of a chart.
    pub const ORDER: [Marker; 7] = [
        Marker::Circle,
        Marker::Square,
        Marker::TriangleUp,
        Marker::Diamond,
        Marker::TriangleDown,
        Marker::Ring,
        Marker::OpenSquare,
    ];

    /// The `index`-th marker (cyclically).
    pub(super) fn nth(index: usize) -> Marker {
        Self::ORDER[index % Self::ORDER.len()]
    }

    /// Its name in a figure's layout.
    pub fn name(self) -> &'static str {
        match self {
            Marker::Circle => "circle",
            Marker::Square => "square",
            Marker::TriangleUp => "triangle-up",
            Marker::Diamond => "diamond",
            Marker::TriangleDown => "triangle-down",
            Marker::Ring => "ring",
            Marker::OpenSquare => "open-square",
        }
    }
}

/// How one curve is drawn: its colour, dash, marker (if any) and stroke width.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Look {
    /// The stroke (and marker) colour.
    pub colour: RGBColor,
    /// The stroke's dash.
    pub dash: Dash,
    /// The marker at every point, if any.
    pub marker: Option<Marker>,
    /// The stroke width.
    pub width: u32,
}

impl Look {
    /// The exact solution: black, dashed, drawn over the computed curves.
    pub fn exact() -> Self {
        Self {
            colour: EXACT,
            dash: Dash::Dashed,
            marker: None,
            width: EXACT_WIDTH,
        }
    }

    /// The `index`-th curve of a time series: the `index`-th colour, dash and marker (the
    /// markers sparse along a dense curve), so that two curves differ in all three.
    pub fn line(index: usize) -> Self {
        Self {
            colour: colour(index),
            dash: Dash::ORDER[index % Dash::ORDER.len()],
            marker: Some(Marker::nth(index)),
            width: RUN_WIDTH,
        }
    }

    /// A computed curve with a marker at every point: colour and marker of `index`, `dash`.
    pub fn marked(index: usize, dash: Dash) -> Self {
        Self {
            colour: colour(index),
            dash,
            marker: Some(Marker::nth(index)),
            width: RUN_WIDTH,
        }
    }

    /// The fitted slope of the `index`-th curve, `curve`: in its colour, no marker, broken by
    /// the `index`-th of the four broken dashes (so that two fits differ in dash too).
    pub fn fit_of(index: usize, curve: Look) -> Self {
        const FITS: [Dash; 4] = [
            Dash::Dashed,
            Dash::Dotted,
            Dash::LongDashed,
            Dash::LooselyDotted,
        ];
        Self {
            colour: curve.colour,
            dash: FITS[index % FITS.len()],
            marker: None,
            width: EXACT_WIDTH,
        }
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

/// A tick label on a linear axis whose labels are at least `step` apart and whose largest
/// value in magnitude is `magnitude`: as many decimals as the step needs to keep neighbours
/// distinct, trailing zeros removed; scientific notation on an axis whose values are all
/// below 0.1 in magnitude or reach 10⁵ (`1.246e-3`, never `0.001246`), with as many digits as
/// the step needs.
pub(super) fn linear_tick(v: f64, step: f64, magnitude: f64) -> String {
    let a = v.abs();
    if a < 1e-9 * step.abs().max(1e-300) || a < 1e-300 {
        return "0".into();
    }
    if !(1e-1..1e5).contains(&magnitude) {
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
        assert_eq!(linear_tick(0.5, 0.1, 1.0), "0.5");
        assert_eq!(linear_tick(0.30000000000000004, 0.1, 1.0), "0.3");
        assert_eq!(linear_tick(-1e-17, 0.1, 1.0), "0");
        assert_eq!(linear_tick(2.0, 0.5, 2.0), "2");
        assert_eq!(linear_tick(2.5e-5, 1e-5, 3e-5), "2.5e-5");
        assert_eq!(linear_tick(0.001246, 2e-6, 0.00125), "1.246e-3");
        assert_eq!(linear_tick(0.0095, 0.0005, 0.0105), "9.5e-3");
        assert_eq!(linear_tick(0.05, 0.01, 0.12), "0.05");
        // Close values around 0.0123: the step sets the digits, so the labels differ.
        let labels: Vec<String> = [0.012301, 0.012302, 0.012303]
            .iter()
            .map(|&v| linear_tick(v, 1e-6, 0.0124))
            .collect();
        assert_eq!(labels, ["1.2301e-2", "1.2302e-2", "1.2303e-2"]);
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
