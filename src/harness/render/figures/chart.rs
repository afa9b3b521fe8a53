//! One chart: axes (linear or logarithmic), curves, legend. Every figure is made of these.
//!
//! A chart places its legend where it covers no data: inside the plotting area in the first
//! free corner or edge middle; failing that, above the data in headroom added to the y axis;
//! failing that, outside the plotting area on its right. Drawing it returns its
//! [`ChartLayout`]: where everything went, for the figure's embedded layout.

use std::cell::RefCell;

use plotters::coord::ranged1d::{AsRangedCoord, ValueFormatter};
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::layout::{centred_text, text_height, text_width, AxisLayout, ChartLayout, Rect};
use super::layout::{SeriesLayout, Tick};
use super::{style, FigureError};

/// The drawing area every chart is drawn on.
pub(super) type Area<'b> = DrawingArea<SVGBackend<'b>, Shift>;

/// Turns any error of the drawing library into [`FigureError::Drawing`].
pub(super) fn drawing<E: std::fmt::Display>(e: E) -> FigureError {
    FigureError::Drawing(e.to_string())
}

/// How an axis maps its values.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Scale {
    /// Linear.
    Linear,
    /// Logarithmic in this base (2 or 10).
    Log(f64),
}

impl Scale {
    fn accepts(self, v: f64) -> bool {
        v.is_finite() && (self == Scale::Linear || v > 0.0)
    }
}

/// How a curve is drawn.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Look {
    /// The exact solution: black, thick.
    Exact,
    /// The exact counterpart of the computed curve `Line(i)`: the lighter shade of its colour,
    /// thick (drawn beneath it when listed first).
    ExactOf(usize),
    /// A computed curve: the palette colour of this index, no markers.
    Line(usize),
    /// A computed curve with a marker at every point: the palette colour of this index, its
    /// lighter shade when the flag is set.
    Marked(usize, bool),
}

impl Look {
    fn colour(self) -> RGBColor {
        match self {
            Look::Exact => style::EXACT,
            Look::ExactOf(i) => style::colour(i, true),
            Look::Line(i) => style::colour(i, false),
            Look::Marked(i, light) => style::colour(i, light),
        }
    }

    fn width(self) -> u32 {
        match self {
            Look::Exact | Look::ExactOf(_) => style::EXACT_WIDTH,
            Look::Line(_) | Look::Marked(..) => style::RUN_WIDTH,
        }
    }

    fn marked(self) -> bool {
        matches!(self, Look::Marked(..))
    }
}

/// One curve: legend text, its points as given, the band shaded around it, and how it is drawn.
#[derive(Debug, Clone)]
pub(super) struct Curve {
    pub label: String,
    pub points: Vec<(f64, f64)>,
    /// `(x, lower, upper)` of a band shaded in the curve's colour beneath every line; empty for
    /// none.
    pub band: Vec<(f64, f64, f64)>,
    pub look: Look,
}

impl Curve {
    /// Pairs `x` and `y` point by point; they must have the same length.
    pub fn new(
        what: &str,
        label: &str,
        x: &[f64],
        y: &[f64],
        look: Look,
    ) -> Result<Self, FigureError> {
        if x.len() != y.len() {
            return Err(FigureError::LengthMismatch {
                what: format!("{what} '{label}'"),
                left: x.len(),
                right: y.len(),
            });
        }
        Ok(Self {
            label: label.to_owned(),
            points: x.iter().copied().zip(y.iter().copied()).collect(),
            band: Vec::new(),
            look,
        })
    }

    /// Adds a band between `lower` and `upper` at the curve's abscissae; both must have as
    /// many values as the curve has points.
    pub fn with_band(
        mut self,
        what: &str,
        lower: &[f64],
        upper: &[f64],
    ) -> Result<Self, FigureError> {
        for (side, values) in [("band lower", lower), ("band upper", upper)] {
            if values.len() != self.points.len() {
                return Err(FigureError::LengthMismatch {
                    what: format!("{what} '{}' ({side})", self.label),
                    left: self.points.len(),
                    right: values.len(),
                });
            }
        }
        self.band = self
            .points
            .iter()
            .zip(lower.iter().zip(upper))
            .map(|(&(x, _), (&lo, &hi))| (x, lo, hi))
            .collect();
        Ok(self)
    }

    /// Whether the band encloses an area (it needs two levels).
    fn has_band(&self) -> bool {
        self.band.len() > 1
    }
}

/// Where a chart's legend goes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Legend {
    /// No legend.
    None,
    /// Inside the plotting area where it covers no data (see the module's doc), outside on the
    /// right if nowhere inside is free.
    Inside,
    /// Outside the plotting area on its right, whatever the data (for long legends).
    Right,
}

/// Everything one chart needs.
pub(super) struct ChartSpec<'s> {
    /// Names the chart in an [`FigureError::EmptyData`].
    pub what: String,
    /// Caption above the chart.
    pub caption: Option<&'s str>,
    /// Description and scale of the x axis.
    pub x: (&'s str, Scale),
    /// Description and scale of the y axis.
    pub y: (&'s str, Scale),
    /// Curves in drawing order (the first is drawn beneath the others).
    pub curves: Vec<Curve>,
    /// Where the legend goes.
    pub legend: Legend,
    /// Whether a logarithmic x axis is ticked at the abscissae of the data (the levels of a
    /// convergence plot, labelled `1/N`) rather than at 1, 2 and 5 times the powers of ten.
    pub x_at_levels: bool,
}

/// Margin right of the plotting area when the legend is not there.
const RIGHT_MARGIN: i32 = 25;
/// Gap between the plotting area's edge and a legend inside it.
const INSET: i32 = 8;
/// Height of one legend row.
fn legend_row() -> i32 {
    text_height(style::LEGEND_SIZE as f64) + 4
}

impl ChartSpec<'_> {
    /// Keeps only the points (and band levels) the axes can show (finite; positive on a log
    /// axis) and drops the curves left without a point. `EmptyData` when no curve is left.
    pub fn into_drawable(mut self) -> Result<Self, FigureError> {
        let (sx, sy) = (self.x.1, self.y.1);
        for c in &mut self.curves {
            c.points.retain(|&(x, y)| sx.accepts(x) && sy.accepts(y));
            c.band
                .retain(|&(x, lo, hi)| sx.accepts(x) && sy.accepts(lo) && sy.accepts(hi));
        }
        self.curves.retain(|c| !c.points.is_empty());
        if self.curves.is_empty() {
            return Err(FigureError::EmptyData { what: self.what });
        }
        Ok(self)
    }

    /// The legend box's width in pixels.
    pub fn legend_width(&self) -> i32 {
        self.legend_size().0
    }

    /// The legend box's width and height in pixels.
    fn legend_size(&self) -> (i32, i32) {
        let text = self
            .curves
            .iter()
            .map(|c| text_width(&c.label, style::LEGEND_SIZE as f64))
            .max()
            .unwrap_or(0);
        (text + 50, self.curves.len() as i32 * legend_row() + 12)
    }

    /// Draws the chart on `area` and returns where everything went.
    pub fn draw(self, area: &Area<'_>) -> Result<ChartLayout, FigureError> {
        let spec = self.into_drawable()?;
        let xs = spec
            .curves
            .iter()
            .flat_map(|c| c.points.iter().map(|p| p.0));
        let ys = spec.curves.iter().flat_map(|c| {
            c.points
                .iter()
                .map(|p| p.1)
                .chain(c.band.iter().flat_map(|b| [b.1, b.2]))
        });
        let (x0, x1) = axis_range(xs, spec.x.1, false);
        let (mut y0, mut y1) = axis_range(ys, spec.y.1, true);
        let mut levels: Vec<f64> = if spec.x_at_levels {
            spec.curves
                .iter()
                .flat_map(|c| c.points.iter().map(|p| p.0))
                .collect()
        } else {
            Vec::new()
        };
        levels.sort_by(f64::total_cmp);
        levels.dedup_by(|a, b| (*a / *b - 1.0).abs() < 1e-9);

        let (lw, lh) = spec.legend_size();
        let mut right = RIGHT_MARGIN;
        let mut legend_at = None;
        if spec.legend == Legend::Inside {
            let plot = plot_rect(area, spec.caption, right)?;
            let free = |y0: f64, y1: f64, upper_only: bool| {
                let map = Mapping::new(plot, (x0, x1, spec.x.1), (y0, y1, spec.y.1));
                let shapes = map.shapes(&spec.curves);
                candidates(plot, (lw, lh), upper_only)
                    .into_iter()
                    .find(|r| !shapes.iter().any(|s| s.hits(r)))
            };
            legend_at = free(y0, y1, false);
            if legend_at.is_none() {
                // Headroom: widen the y axis upwards until the legend's height is free of data.
                let f = f64::from(lh + 2 * INSET) / f64::from(plot.y1 - plot.y0);
                if f < 0.5 {
                    let top = match spec.y.1 {
                        Scale::Linear => y0 + (y1 - y0) / (1.0 - f),
                        Scale::Log(_) => y0 * (y1 / y0).powf(1.0 / (1.0 - f)),
                    };
                    if let Some(r) = free(y0, top, true) {
                        (y0, y1) = (y0, top);
                        legend_at = Some(r);
                    }
                }
            }
        }
        if spec.legend != Legend::None && legend_at.is_none() {
            right = lw + RIGHT_MARGIN + 10;
            let plot = plot_rect(area, spec.caption, right)?;
            legend_at = Some(Rect {
                x0: plot.x1 + 10,
                y0: plot.y0,
                x1: plot.x1 + 10 + lw,
                y1: plot.y0 + lh,
            });
        }

        let x_step = (x1 - x0) / LINEAR_LABELS as f64;
        let y_step = (y1 - y0) / LINEAR_LABELS as f64;
        let drawn = match (spec.x.1, spec.y.1) {
            (Scale::Linear, Scale::Linear) => draw_on(
                area,
                &spec,
                x0..x1,
                y0..y1,
                right,
                Labels {
                    x: (LINEAR_LABELS, &|v| style::linear_tick(v, x_step)),
                    y: (LINEAR_LABELS, &|v| style::linear_tick(v, y_step)),
                },
            )?,
            (Scale::Log(bx), Scale::Log(by)) => {
                let ticks = if spec.x_at_levels {
                    levels.clone()
                } else {
                    round_log_ticks(x0, x1)
                };
                let x_label: &dyn Fn(f64) -> String = if spec.x_at_levels {
                    &style::level_tick
                } else {
                    &style::log10_tick
                };
                draw_on(
                    area,
                    &spec,
                    (x0..x1).log_scale().base(bx).with_key_points(ticks),
                    (y0..y1).log_scale().base(by),
                    right,
                    Labels {
                        x: (LINEAR_LABELS, x_label),
                        y: (log_labels(y0, y1, by), &style::log10_tick),
                    },
                )?
            }
            _ => unreachable!("the figures use linear–linear or log–log charts only"),
        };
        let (plot, x_ticks, y_ticks) = drawn;
        if let Some(at) = legend_at {
            draw_legend(area, at, &spec.curves)?;
        }
        let (ax, ay) = area.get_base_pixel();
        let (aw, _) = area.dim_in_pixel();
        Ok(ChartLayout {
            plot,
            caption: spec
                .caption
                .map(|c| centred_text(c, style::CAPTION_SIZE as f64, ax + aw as i32 / 2, ay + 10)),
            x: AxisLayout {
                label: spec.x.0.to_owned(),
                log: matches!(spec.x.1, Scale::Log(_)),
                ticks: x_ticks,
                levels,
            },
            y: AxisLayout {
                label: spec.y.0.to_owned(),
                log: matches!(spec.y.1, Scale::Log(_)),
                ticks: y_ticks,
                levels: Vec::new(),
            },
            legend: legend_at,
            series: if spec.legend == Legend::None {
                Vec::new()
            } else {
                spec.curves
                    .iter()
                    .map(|c| {
                        let RGBColor(r, g, b) = c.look.colour();
                        SeriesLayout {
                            label: c.label.clone(),
                            colour: [r, g, b],
                        }
                    })
                    .collect()
            },
            colour_bar: None,
        })
    }
}

/// Labels asked of a linear axis (plotters puts at most this many, at round values).
const LINEAR_LABELS: usize = 8;

/// Number of labels and label formatter of each axis.
struct Labels<'f> {
    x: (usize, &'f dyn Fn(f64) -> String),
    y: (usize, &'f dyn Fn(f64) -> String),
}

/// 1, 2 and 5 times the powers of ten within `[lo, hi]`: the ticks of a logarithmic x axis
/// that is not ticked at levels.
fn round_log_ticks(lo: f64, hi: f64) -> Vec<f64> {
    let mut out = Vec::new();
    let mut k = lo.log10().floor() as i32;
    while 10f64.powi(k) <= hi {
        for m in [1.0, 2.0, 5.0] {
            let v = m * 10f64.powi(k);
            if v >= lo && v <= hi {
                out.push(v);
            }
        }
        k += 1;
    }
    out
}

/// How many labels to ask of a log axis over `[lo, hi]`. Plotters puts a label at each power
/// of the base and, when asked for many more labels than there are powers, at 2, 3, …, 9
/// times each power. Those intermediate labels are wanted only on a base-10 axis spanning
/// less than two decades (otherwise it would show one or two labels); `axis_range` starts such
/// an axis at a power of ten.
fn log_labels(lo: f64, hi: f64, base: f64) -> usize {
    let decades = (hi / lo).ln() / base.ln();
    if base == 10.0 && decades < 2.0 + 1e-9 {
        12
    } else {
        8
    }
}

/// The axis range of `values` (all drawable on `scale`, at least one).
///
/// A linear axis spans the data exactly (`pad`: plus 5 % of the span each side); a log axis
/// is padded by 5 % of its span in log space each side and widened to contain a power of its
/// base so that it has a labelled tick; a base-10 axis spanning less than two decades starts
/// at a power of ten, so that its labels at 1, 2, …, 9 times that power cover it. All values equal: the range is widened around them
/// (±10 % of the value, ±1 at zero; a factor of the base on a log axis).
pub(super) fn axis_range(values: impl Iterator<Item = f64>, scale: Scale, pad: bool) -> (f64, f64) {
    let (lo, hi) = values.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
        (lo.min(v), hi.max(v))
    });
    match scale {
        Scale::Linear => {
            let magnitude = lo.abs().max(hi.abs());
            if hi - lo <= 1e-12 * magnitude || hi == lo {
                let d = if magnitude > 0.0 {
                    0.1 * magnitude
                } else {
                    1.0
                };
                (lo - d, hi + d)
            } else if pad {
                let d = 0.05 * (hi - lo);
                (lo - d, hi + d)
            } else {
                (lo, hi)
            }
        }
        Scale::Log(base) => {
            let (mut lo, mut hi) = if hi / lo <= 1.0 + 1e-12 {
                (lo / base, hi * base)
            } else {
                let f = (hi / lo).powf(0.05);
                (lo / f, hi * f)
            };
            let log = |v: f64| v.ln() / base.ln();
            let (below, above) = (log(lo).ceil(), log(hi).floor());
            if base == 10.0 && log(hi) - log(lo) < 2.0 {
                // Labels go at each power and at 2…9 times it (see `log_labels`): start at a
                // power so that they cover the whole axis.
                // (Slightly below the power: plotters finds the first tick by rounding up.)
                lo = base.powf(log(lo).floor()) * (1.0 - 1e-9);
            } else if below > above {
                // No power of the base inside: extend to the nearer one.
                let down = base.powf(above);
                let up = base.powf(below);
                // (Slightly past the power: plotters finds its ticks by rounding.)
                if log(lo) - log(down) <= log(up) - log(hi) {
                    lo = down * (1.0 - 1e-9);
                } else {
                    hi = up * (1.0 + 1e-9);
                }
            }
            (lo, hi)
        }
    }
}

/// The plotting area (in canvas pixels) that a chart on `area` with this caption and right
/// margin gets, found by laying the chart out on a scratch canvas of the same size.
fn plot_rect(area: &Area<'_>, caption: Option<&str>, right: i32) -> Result<Rect, FigureError> {
    let (w, h) = area.dim_in_pixel();
    let base = area.get_base_pixel();
    let canvas = (base.0 as u32 + w, base.1 as u32 + h);
    let mut scratch = String::new();
    let root = SVGBackend::with_string(&mut scratch, canvas).into_drawing_area();
    let same = root.shrink(base, (w, h));
    let chart = builder(&same, caption, right)
        .build_cartesian_2d(0f64..1f64, 0f64..1f64)
        .map_err(drawing)?;
    Ok(Rect::spanning(chart.plotting_area().get_pixel_range()))
}

/// The chart builder with the figures' margins and label areas.
fn builder<'a, 'b>(
    area: &'a Area<'b>,
    caption: Option<&str>,
    right: i32,
) -> ChartBuilder<'a, 'b, SVGBackend<'b>> {
    let mut builder = ChartBuilder::on(area);
    if let Some(caption) = caption {
        builder.caption(caption, (style::FONT, style::CAPTION_SIZE));
    }
    builder
        .margin(10)
        .margin_right(right)
        .x_label_area_size(50)
        .y_label_area_size(95);
    builder
}

/// Data coordinates to canvas pixels, as plotters maps them (to within a pixel).
struct Mapping {
    plot: Rect,
    x: (f64, f64, Scale),
    y: (f64, f64, Scale),
}

impl Mapping {
    fn new(plot: Rect, x: (f64, f64, Scale), y: (f64, f64, Scale)) -> Self {
        Self { plot, x, y }
    }

    fn fraction((lo, hi, scale): (f64, f64, Scale), v: f64) -> f64 {
        match scale {
            Scale::Linear => (v - lo) / (hi - lo),
            Scale::Log(_) => (v / lo).ln() / (hi / lo).ln(),
        }
    }

    fn px(&self, (x, y): (f64, f64)) -> (f64, f64) {
        let p = &self.plot;
        (
            f64::from(p.x0) + Self::fraction(self.x, x) * f64::from(p.x1 - p.x0),
            f64::from(p.y1) - Self::fraction(self.y, y) * f64::from(p.y1 - p.y0),
        )
    }

    /// What each curve puts on the canvas: its line (or dots), and its band as a polygon.
    fn shapes(&self, curves: &[Curve]) -> Vec<Shape> {
        let mut out = Vec::new();
        for c in curves {
            let reach = if c.look.marked() {
                f64::from(style::MARKER_RADIUS)
            } else {
                f64::from(c.look.width())
            };
            out.push(Shape::Line {
                points: c.points.iter().map(|&p| self.px(p)).collect(),
                reach,
            });
            if c.has_band() {
                let outline = c
                    .band
                    .iter()
                    .map(|b| self.px((b.0, b.2)))
                    .chain(c.band.iter().rev().map(|b| self.px((b.0, b.1))))
                    .collect();
                out.push(Shape::Polygon(outline));
            }
        }
        out
    }
}

/// Something drawn in the plotting area, in canvas pixels.
enum Shape {
    /// A polyline (or a lone point) and how far its ink reaches from it.
    Line { points: Vec<(f64, f64)>, reach: f64 },
    /// A filled polygon.
    Polygon(Vec<(f64, f64)>),
}

impl Shape {
    /// Whether the shape puts ink inside `r`.
    fn hits(&self, r: &Rect) -> bool {
        match self {
            Shape::Line { points, reach } => {
                let grown = (
                    f64::from(r.x0) - reach,
                    f64::from(r.y0) - reach,
                    f64::from(r.x1) + reach,
                    f64::from(r.y1) + reach,
                );
                match points.as_slice() {
                    [p] => inside(*p, grown),
                    _ => points.windows(2).any(|w| segment_hits(w[0], w[1], grown)),
                }
            }
            Shape::Polygon(outline) => {
                let box_ = (
                    f64::from(r.x0),
                    f64::from(r.y0),
                    f64::from(r.x1),
                    f64::from(r.y1),
                );
                let corner = (box_.0, box_.1);
                outline
                    .iter()
                    .zip(outline.iter().cycle().skip(1))
                    .any(|(&a, &b)| segment_hits(a, b, box_))
                    || in_polygon(corner, outline)
            }
        }
    }
}

/// Whether `p` lies in the box `(x0, y0, x1, y1)`.
fn inside(p: (f64, f64), (x0, y0, x1, y1): (f64, f64, f64, f64)) -> bool {
    p.0 >= x0 && p.0 <= x1 && p.1 >= y0 && p.1 <= y1
}

/// Whether the segment `a`–`b` meets the box `(x0, y0, x1, y1)` (Liang–Barsky clipping).
fn segment_hits(a: (f64, f64), b: (f64, f64), (x0, y0, x1, y1): (f64, f64, f64, f64)) -> bool {
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    for (p, q) in [
        (-dx, a.0 - x0),
        (dx, x1 - a.0),
        (-dy, a.1 - y0),
        (dy, y1 - a.1),
    ] {
        if p == 0.0 {
            if q < 0.0 {
                return false;
            }
        } else {
            let t = q / p;
            if p < 0.0 {
                t0 = t0.max(t);
            } else {
                t1 = t1.min(t);
            }
        }
    }
    t0 <= t1
}

/// Whether `p` lies inside the polygon `outline` (even–odd rule).
fn in_polygon(p: (f64, f64), outline: &[(f64, f64)]) -> bool {
    let mut inside = false;
    for (a, b) in outline.iter().zip(outline.iter().cycle().skip(1)) {
        if (a.1 > p.1) != (b.1 > p.1) && p.0 < a.0 + (p.1 - a.1) / (b.1 - a.1) * (b.0 - a.0) {
            inside = !inside;
        }
    }
    inside
}

/// The legend boxes to try inside `plot`, in order: the corners, then the edge middles (only
/// the upper positions when `upper_only`).
fn candidates(plot: Rect, (w, h): (i32, i32), upper_only: bool) -> Vec<Rect> {
    let left = plot.x0 + INSET;
    let right = plot.x1 - INSET - w;
    let centre = (plot.x0 + plot.x1 - w) / 2;
    let top = plot.y0 + INSET;
    let bottom = plot.y1 - INSET - h;
    let middle = (plot.y0 + plot.y1 - h) / 2;
    let mut at = vec![(right, top), (left, top), (centre, top)];
    if !upper_only {
        at.extend([
            (right, bottom),
            (left, bottom),
            (centre, bottom),
            (right, middle),
            (left, middle),
        ]);
    }
    at.into_iter()
        .filter(|&(x, y)| x >= plot.x0 && y >= plot.y0 && x + w <= plot.x1 && y + h <= plot.y1)
        .map(|(x, y)| Rect {
            x0: x,
            y0: y,
            x1: x + w,
            y1: y + h,
        })
        .collect()
}

/// Draws the legend box `at` (canvas pixels) on `area`: a white box with a grey border, then
/// per curve its symbol (line, marker, band swatch) and its label.
fn draw_legend(area: &Area<'_>, at: Rect, curves: &[Curve]) -> Result<(), FigureError> {
    let (bx, by) = area.get_base_pixel();
    let (x0, y0, x1, y1) = (at.x0 - bx, at.y0 - by, at.x1 - bx, at.y1 - by);
    area.draw(&Rectangle::new(
        [(x0, y0), (x1, y1)],
        WHITE.mix(0.9).filled(),
    ))
    .map_err(drawing)?;
    area.draw(&Rectangle::new([(x0, y0), (x1, y1)], BLACK.mix(0.6)))
        .map_err(drawing)?;
    let font = (style::FONT, style::LEGEND_SIZE)
        .into_font()
        .color(&BLACK)
        .pos(Pos::new(HPos::Left, VPos::Center));
    for (i, c) in curves.iter().enumerate() {
        let y = y0 + 6 + i as i32 * legend_row() + legend_row() / 2;
        let x = x0 + 10;
        let colour = c.look.colour();
        let line = colour.stroke_width(c.look.width());
        if c.has_band() {
            area.draw(&Polygon::new(
                vec![
                    (x + 2, y - 7),
                    (x + 18, y - 7),
                    (x + 18, y + 7),
                    (x + 2, y + 7),
                ],
                colour.mix(style::BAND_OPACITY).filled(),
            ))
            .map_err(drawing)?;
        }
        area.draw(&PathElement::new(vec![(x, y), (x + 20, y)], line))
            .map_err(drawing)?;
        if c.look.marked() {
            area.draw(&Circle::new(
                (x + 10, y),
                style::MARKER_RADIUS,
                colour.filled(),
            ))
            .map_err(drawing)?;
        }
        area.draw(&Text::new(c.label.as_str(), (x + 30, y), font.clone()))
            .map_err(drawing)?;
    }
    Ok(())
}

/// Draws the axes, bands and curves of `spec` on `area` with these coordinates; returns the
/// plotting area (canvas pixels) and the labelled ticks of each axis.
fn draw_on<X, Y>(
    area: &Area<'_>,
    spec: &ChartSpec<'_>,
    xr: X,
    yr: Y,
    right: i32,
    labels: Labels<'_>,
) -> Result<(Rect, Vec<Tick>, Vec<Tick>), FigureError>
where
    X: AsRangedCoord<Value = f64>,
    Y: AsRangedCoord<Value = f64>,
    X::CoordDescType: ValueFormatter<f64>,
    Y::CoordDescType: ValueFormatter<f64>,
{
    let mut chart = builder(area, spec.caption, right)
        .build_cartesian_2d(xr, yr)
        .map_err(drawing)?;
    let x_ticks = RefCell::new(Vec::new());
    let y_ticks = RefCell::new(Vec::new());
    let record = |ticks: &RefCell<Vec<Tick>>, f: &dyn Fn(f64) -> String, v: f64| {
        let label = f(v);
        let mut ticks = ticks.borrow_mut();
        if !label.is_empty() && !ticks.iter().any(|t: &Tick| t.value == v) {
            ticks.push(Tick {
                value: v,
                label: label.clone(),
            });
        }
        label
    };
    let fx = |v: &f64| record(&x_ticks, labels.x.1, *v);
    let fy = |v: &f64| record(&y_ticks, labels.y.1, *v);
    chart
        .configure_mesh()
        .x_desc(spec.x.0)
        .y_desc(spec.y.0)
        .x_labels(labels.x.0)
        .y_labels(labels.y.0)
        .max_light_lines(4)
        .x_label_formatter(&fx)
        .y_label_formatter(&fy)
        .label_style((style::FONT, style::TICK_SIZE))
        .axis_desc_style((style::FONT, style::AXIS_DESC_SIZE))
        .draw()
        .map_err(drawing)?;

    // Every band beneath every line, so that a band never hides another curve.
    for curve in spec.curves.iter().filter(|c| c.has_band()) {
        let outline: Vec<(f64, f64)> = curve
            .band
            .iter()
            .map(|b| (b.0, b.2))
            .chain(curve.band.iter().rev().map(|b| (b.0, b.1)))
            .collect();
        chart
            .draw_series(std::iter::once(Polygon::new(
                outline,
                curve.look.colour().mix(style::BAND_OPACITY).filled(),
            )))
            .map_err(drawing)?;
    }

    for curve in &spec.curves {
        let colour = curve.look.colour();
        let line = colour.stroke_width(curve.look.width());
        chart
            .draw_series(LineSeries::new(curve.points.iter().copied(), line))
            .map_err(drawing)?;
        if curve.look.marked() {
            chart
                .draw_series(
                    curve
                        .points
                        .iter()
                        .map(|&p| Circle::new(p, style::MARKER_RADIUS, colour.filled())),
                )
                .map_err(drawing)?;
        }
    }
    let plot = Rect::spanning(chart.plotting_area().get_pixel_range());
    Ok((plot, x_ticks.into_inner(), y_ticks.into_inner()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn degenerate_ranges_are_padded_and_log_ranges_hold_a_power() {
        assert_eq!(
            axis_range([2.0, 2.0].into_iter(), Scale::Linear, true),
            (1.8, 2.2)
        );
        assert_eq!(
            axis_range([0.0].into_iter(), Scale::Linear, false),
            (-1.0, 1.0)
        );
        assert_eq!(
            axis_range([0.0, 3.0].into_iter(), Scale::Linear, false),
            (0.0, 3.0)
        );
        // Under two decades on base 10: starts just below a power of ten.
        let (lo, hi) = axis_range([0.02, 0.08].into_iter(), Scale::Log(10.0), true);
        assert!(
            lo < 0.01 && lo > 0.0099 && hi > 0.08 && hi < 0.1,
            "{lo} {hi}"
        );
        // No power of two inside: extended to the nearer one.
        let (lo, hi) = axis_range([0.45, 0.48].into_iter(), Scale::Log(2.0), true);
        assert!(lo > 0.25 && hi > 0.5 && hi < 0.5001, "{lo} {hi}");
        let (lo, hi) = axis_range([0.3, 0.35].into_iter(), Scale::Log(2.0), true);
        assert!(lo < 0.25 && lo > 0.2499 && hi < 0.5, "{lo} {hi}");
        let (lo, hi) = axis_range([0.3].into_iter(), Scale::Log(2.0), true);
        assert!(lo <= 0.15 && hi >= 0.6);
    }
}
