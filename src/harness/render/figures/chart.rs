//! One chart: axes (linear or logarithmic), curves, legend. Every figure is made of these.
//!
//! A chart places its legend where it covers no data: inside the plotting area in the first
//! free corner or edge middle; failing that, above the data in headroom added to the y axis;
//! failing that, outside the plotting area on its right. Drawing it returns its
//! [`ChartLayout`]: where everything went, for the figure's embedded layout.
//!
//! Bands are drawn first, then the computed curves and fitted slopes, then the exact curves on
//! top of them (dashed, so that the computed curves show through).

use std::cell::RefCell;

use plotters::coord::ranged1d::{AsRangedCoord, ValueFormatter};
use plotters::coord::Shift;
use plotters::element::DashedPathElement;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::layout::{centred_text, text_height, text_width, AxisLayout, ChartLayout, Rect};
use super::layout::{SeriesKind, SeriesLayout, Tick};
use super::style::{Look, Marker};
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

/// One curve: legend text, its points as given, the band shaded around it, how it is drawn
/// and what it is.
#[derive(Debug, Clone)]
pub(super) struct Curve {
    pub label: String,
    pub points: Vec<(f64, f64)>,
    /// `(x, lower, upper)` of a band shaded in the curve's colour beneath every line; empty for
    /// none.
    pub band: Vec<(f64, f64, f64)>,
    /// What the band shows, named in the layout.
    pub band_name: Option<String>,
    pub look: Look,
    pub kind: SeriesKind,
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
            band_name: None,
            look,
            kind: SeriesKind::Data,
        })
    }

    /// The exact solution `y` at `x` (black, dashed, drawn over the computed curves).
    pub fn exact(what: &str, label: &str, x: &[f64], y: &[f64]) -> Result<Self, FigureError> {
        Ok(Self {
            kind: SeriesKind::Exact,
            ..Self::new(what, label, x, y, Look::exact())?
        })
    }

    /// A legend entry with nothing drawn (in the legend's text colour, without a symbol).
    pub fn note(label: &str) -> Self {
        Self {
            label: label.to_owned(),
            points: Vec::new(),
            band: Vec::new(),
            band_name: None,
            look: Look::exact(),
            kind: SeriesKind::Note,
        }
    }

    /// This curve as another kind.
    pub fn of_kind(self, kind: SeriesKind) -> Self {
        Self { kind, ..self }
    }

    /// Adds a band between `lower` and `upper` at the curve's abscissae; both must have as
    /// many values as the curve has points.
    pub fn with_band(
        mut self,
        what: &str,
        name: &str,
        lower: &[f64],
        upper: &[f64],
    ) -> Result<Self, FigureError> {
        self.band_name = Some(name.to_owned());
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
    /// In a panel of its own beneath the chart (for long legends of many series).
    Below,
}

/// Room between a chart and a legend beneath it, and under that legend.
pub(super) const BELOW_GAP: i32 = 10;

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
    /// The y axis' range when the caller sets it (panels that share a scale, an axis that
    /// clips outliers); fitted to the data otherwise. A linear axis set so clips the curves at
    /// its ends.
    pub y_range: Option<(f64, f64)>,
    /// The group of compared charts this one belongs to (recorded in the layout).
    pub scale_group: Option<String>,
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
        self.curves
            .retain(|c| !c.points.is_empty() || c.kind == SeriesKind::Note);
        if self.curves.iter().all(|c| c.kind == SeriesKind::Note) {
            return Err(FigureError::EmptyData { what: self.what });
        }
        Ok(self)
    }

    /// The legend box's width in pixels.
    pub fn legend_width(&self) -> i32 {
        self.legend_size().0
    }

    /// The legend box's width and height in pixels.
    pub fn legend_size(&self) -> (i32, i32) {
        let text = self
            .curves
            .iter()
            .map(|c| text_width(&c.label, style::LEGEND_SIZE as f64))
            .max()
            .unwrap_or(0);
        (text + 56, self.curves.len() as i32 * legend_row() + 12)
    }

    /// Draws the chart on `area` and returns where everything went.
    pub fn draw(self, whole: &Area<'_>) -> Result<ChartLayout, FigureError> {
        let spec = self.into_drawable()?;
        let (lw, lh) = spec.legend_size();
        let (_, whole_height) = whole.dim_in_pixel();
        let upper;
        let area = if spec.legend == Legend::Below {
            upper = whole
                .split_vertically(whole_height as i32 - lh - 2 * BELOW_GAP)
                .0;
            &upper
        } else {
            whole
        };
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
        let (mut y0, mut y1) = spec
            .y_range
            .unwrap_or_else(|| axis_range(ys, spec.y.1, true));
        let runs: Vec<Vec<Vec<(f64, f64)>>> = spec
            .curves
            .iter()
            .map(|c| clipped_runs(&c.points, (y0, y1)))
            .collect();
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

        let mut right = RIGHT_MARGIN;
        let mut legend_at = None;
        if spec.legend == Legend::Inside {
            let plot = plot_rect(area, spec.caption, right)?;
            let free = |y0: f64, y1: f64, upper_only: bool| {
                let map = Mapping::new(plot, (x0, x1, spec.x.1), (y0, y1, spec.y.1));
                let shapes = map.shapes(&spec.curves, &runs);
                candidates(plot, (lw, lh), upper_only)
                    .into_iter()
                    .find(|r| !shapes.iter().any(|s| s.hits(r)))
            };
            legend_at = free(y0, y1, false);
            if legend_at.is_none() && spec.y_range.is_none() {
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
        if spec.legend == Legend::Below {
            let plot = plot_rect(area, spec.caption, right)?;
            let (wx, wy) = whole.get_base_pixel();
            let (ww, _) = whole.dim_in_pixel();
            let x0 = plot.x0.min(wx + ww as i32 - lw - 10).max(wx + 10);
            let y0 = wy + whole_height as i32 - lh - BELOW_GAP;
            legend_at = Some(Rect {
                x0,
                y0,
                x1: x0 + lw,
                y1: y0 + lh,
            });
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
        let (x_mag, y_mag) = (x0.abs().max(x1.abs()), y0.abs().max(y1.abs()));
        let drawn = match (spec.x.1, spec.y.1) {
            (Scale::Linear, Scale::Linear) => draw_on(
                area,
                &spec,
                &runs,
                (y0, y1),
                x0..x1,
                y0..y1,
                right,
                Labels {
                    x: (LINEAR_LABELS, &|v| style::linear_tick(v, x_step, x_mag)),
                    y: (LINEAR_LABELS, &|v| style::linear_tick(v, y_step, y_mag)),
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
                let y_ticks = round_log_ticks(y0, y1);
                draw_on(
                    area,
                    &spec,
                    &runs,
                    (y0, y1),
                    (x0..x1).log_scale().base(bx).with_key_points(ticks),
                    (y0..y1).log_scale().base(by).with_key_points(y_ticks),
                    right,
                    Labels {
                        x: (LINEAR_LABELS, x_label),
                        y: (LINEAR_LABELS, &style::log10_tick),
                    },
                )?
            }
            _ => unreachable!("the figures use linear–linear or log–log charts only"),
        };
        let (plot, x_ticks, y_ticks) = drawn;
        if let Some(at) = legend_at {
            draw_legend(whole, at, &spec.curves)?;
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
                range: Some([x0, x1]),
            },
            y: AxisLayout {
                label: spec.y.0.to_owned(),
                log: matches!(spec.y.1, Scale::Log(_)),
                ticks: y_ticks,
                levels: Vec::new(),
                range: Some([y0, y1]),
            },
            legend: legend_at,
            series: spec.curves.iter().map(series_layout).collect(),
            colour_bar: None,
            scale_group: spec.scale_group.clone(),
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

/// 1, 2 and 5 times the powers of ten within `[lo, hi]`: the ticks of a logarithmic axis
/// that is not ticked at levels; 1, 2, …, 9 times them when that gives fewer than three (an
/// axis fitted to data spanning less than a decade).
fn round_log_ticks(lo: f64, hi: f64) -> Vec<f64> {
    let ticks = |multiples: &[f64]| {
        let mut out = Vec::new();
        let mut k = lo.log10().floor() as i32;
        while 10f64.powi(k) <= hi {
            for m in multiples {
                let v = m * 10f64.powi(k);
                if v >= lo && v <= hi {
                    out.push(v);
                }
            }
            k += 1;
        }
        out
    };
    let round = ticks(&[1.0, 2.0, 5.0]);
    if round.len() >= 3 {
        round
    } else {
        ticks(&[1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0])
    }
}

/// The layout of one curve: its style, kind, band and the extent of its values (its band's
/// included).
fn series_layout(c: &Curve) -> SeriesLayout {
    let RGBColor(r, g, b) = c.look.colour;
    let values = c
        .points
        .iter()
        .map(|p| p.1)
        .chain(c.band.iter().flat_map(|b| [b.1, b.2]));
    let extent = values.fold(None, |acc: Option<[f64; 2]>, v| {
        Some(acc.map_or([v, v], |[lo, hi]| [lo.min(v), hi.max(v)]))
    });
    SeriesLayout {
        label: c.label.clone(),
        colour: [r, g, b],
        dash: c.look.dash.name().to_owned(),
        marker: c.look.marker.map(|m| m.name().to_owned()),
        kind: c.kind,
        band: c.band_name.clone().filter(|_| c.has_band()),
        extent,
    }
}

/// The stretches of `points` inside `[y0, y1]`, each ending where the curve leaves the range
/// (at the crossing, interpolated linearly) and starting where it comes back: a curve clipped
/// by an axis the caller set. A segment whose two ends are both outside is left out.
fn clipped_runs(points: &[(f64, f64)], (y0, y1): (f64, f64)) -> Vec<Vec<(f64, f64)>> {
    let inside = |y: f64| y >= y0 && y <= y1;
    // Where the segment a–b, one end inside, crosses the end of the range the other is beyond.
    let edge = |a: (f64, f64), b: (f64, f64)| {
        let outside = if inside(a.1) { b.1 } else { a.1 };
        let y = if outside < y0 { y0 } else { y1 };
        let t = (y - a.1) / (b.1 - a.1);
        (a.0 + t * (b.0 - a.0), y)
    };
    let mut out: Vec<Vec<(f64, f64)>> = Vec::new();
    let mut run: Vec<(f64, f64)> = Vec::new();
    for (k, &p) in points.iter().enumerate() {
        let prev = k.checked_sub(1).map(|j| points[j]);
        if inside(p.1) {
            if let Some(a) = prev.filter(|a| !inside(a.1)) {
                run.push(edge(a, p));
            }
            run.push(p);
        } else if let Some(a) = prev.filter(|a| inside(a.1)) {
            run.push(edge(a, p));
            out.push(std::mem::take(&mut run));
        }
    }
    if !run.is_empty() {
        out.push(run);
    }
    out
}

/// The axis range of `values` (all drawable on `scale`, at least one).
///
/// A linear axis spans the data exactly (`pad`: plus 5 % of the span each side); a log axis
/// is padded by 5 % of its span in log space each side (its ticks, [`round_log_ticks`], need
/// no power of ten inside); a base-2 axis without a power of two inside is widened to the
/// nearer one. All values equal: the range is widened around them (±10 % of the value, ±1 at
/// zero; a factor of the base on a log axis).
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
            if base != 10.0 && below > above {
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

    /// What each curve puts on the canvas: its line (the stretches `runs` inside the y axis)
    /// or dots, and its band as a polygon.
    fn shapes(&self, curves: &[Curve], runs: &[Vec<Vec<(f64, f64)>>]) -> Vec<Shape> {
        let mut out = Vec::new();
        for (c, runs) in curves.iter().zip(runs) {
            let reach = if c.look.marker.is_some() {
                f64::from(style::MARKER_RADIUS + 1)
            } else {
                f64::from(c.look.width)
            };
            for run in runs {
                out.push(Shape::Line {
                    points: run.iter().map(|&p| self.px(p)).collect(),
                    reach,
                });
            }
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
/// per curve its symbol (line in its dash, marker, band swatch; none for a note) and its label.
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
        let x = x0 + 6;
        if c.kind != SeriesKind::Note {
            let colour = c.look.colour;
            if c.has_band() {
                area.draw(&Polygon::new(
                    vec![
                        (x + 4, y - 7),
                        (x + 30, y - 7),
                        (x + 30, y + 7),
                        (x + 4, y + 7),
                    ],
                    colour.mix(style::BAND_OPACITY).filled(),
                ))
                .map_err(drawing)?;
            }
            stroke(area, &[(x, y), (x + 34, y)], c.look)?;
            if let Some(m) = c.look.marker {
                mark(area, (x + 17, y), m, colour)?;
            }
        }
        area.draw(&Text::new(c.label.as_str(), (x + 42, y), font.clone()))
            .map_err(drawing)?;
    }
    Ok(())
}

/// Strokes the polyline `points` (pixels of `area`) in `look`'s colour, width and dash.
fn stroke(area: &Area<'_>, points: &[(i32, i32)], look: Look) -> Result<(), FigureError> {
    let line = look.colour.stroke_width(look.width);
    match look.dash.pattern() {
        None => area.draw(&PathElement::new(points.to_vec(), line)),
        Some((dash, gap)) => area.draw(&DashedPathElement::new(
            points.iter().copied(),
            dash,
            gap,
            line,
        )),
    }
    .map_err(drawing)
}

/// The outline of `marker` around `(0, 0)` in pixels, for the shapes drawn as polygons.
fn marker_outline(marker: Marker) -> Vec<(i32, i32)> {
    let r = style::MARKER_RADIUS as i32;
    match marker {
        Marker::Square | Marker::OpenSquare => vec![(-r, -r), (r, -r), (r, r), (-r, r)],
        Marker::TriangleUp => vec![(0, -r - 1), (r + 1, r), (-r - 1, r)],
        Marker::TriangleDown => vec![(0, r + 1), (r + 1, -r), (-r - 1, -r)],
        Marker::Diamond => vec![(0, -r - 1), (r + 1, 0), (0, r + 1), (-r - 1, 0)],
        Marker::Circle | Marker::Ring => Vec::new(),
    }
}

/// Draws `marker` at the pixel `at` of `area`.
fn mark(
    area: &Area<'_>,
    at: (i32, i32),
    marker: Marker,
    colour: RGBColor,
) -> Result<(), FigureError> {
    let r = style::MARKER_RADIUS as i32;
    let shifted = |v: Vec<(i32, i32)>| {
        v.into_iter()
            .map(|(x, y)| (at.0 + x, at.1 + y))
            .collect::<Vec<_>>()
    };
    match marker {
        Marker::Circle => area.draw(&Circle::new(at, r, colour.filled())),
        Marker::Ring => area.draw(&Circle::new(at, r, colour.stroke_width(2))),
        Marker::OpenSquare => {
            let mut outline = shifted(marker_outline(marker));
            outline.push(outline[0]);
            area.draw(&PathElement::new(outline, colour.stroke_width(2)))
        }
        _ => area.draw(&Polygon::new(
            shifted(marker_outline(marker)),
            colour.filled(),
        )),
    }
    .map_err(drawing)
}

/// The most markers along one curve: a dense curve (a time series) is marked at every k-th
/// point so that it has at most this many.
const MARKERS_ALONG_A_CURVE: usize = 14;

/// Draws the axes, bands and curves of `spec` on `area` with these coordinates, each curve
/// along its stretches `runs` inside the y axis (`y_bounds`), the exact curves last; returns
/// the plotting area (canvas pixels) and the labelled ticks of each axis.
#[allow(clippy::too_many_arguments)]
fn draw_on<X, Y>(
    area: &Area<'_>,
    spec: &ChartSpec<'_>,
    runs: &[Vec<Vec<(f64, f64)>>],
    y_bounds: (f64, f64),
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
                curve.look.colour.mix(style::BAND_OPACITY).filled(),
            )))
            .map_err(drawing)?;
    }

    // The computed curves and fits, then the exact ones on top.
    let order = spec
        .curves
        .iter()
        .zip(runs)
        .filter(|(c, _)| c.kind != SeriesKind::Exact)
        .chain(
            spec.curves
                .iter()
                .zip(runs)
                .filter(|(c, _)| c.kind == SeriesKind::Exact),
        );
    for (k, (curve, runs)) in order.enumerate() {
        let look = curve.look;
        let line = look.colour.stroke_width(look.width);
        for run in runs {
            match look.dash.pattern() {
                None => chart
                    .draw_series(LineSeries::new(run.iter().copied(), line))
                    .map(|_| ()),
                Some((dash, gap)) => chart
                    .draw_series(DashedLineSeries::new(run.iter().copied(), dash, gap, line))
                    .map(|_| ()),
            }
            .map_err(drawing)?;
        }
        if let Some(m) = look.marker {
            let (bx, by) = area.get_base_pixel();
            let (y0, y1) = y_bounds;
            let every = curve.points.len().div_ceil(MARKERS_ALONG_A_CURVE).max(1);
            // Staggered by the curve's position, so that coinciding curves show each marker.
            let offset = (k * every / 3) % every;
            for p in curve
                .points
                .iter()
                .skip(offset)
                .step_by(every)
                .filter(|p| p.1 >= y0 && p.1 <= y1)
            {
                let (x, y) = chart.backend_coord(p);
                mark(area, (x - bx, y - by), m, look.colour)?;
            }
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
        // Base 10: fitted to the data, 5 % of the span in log space each side.
        let (lo, hi) = axis_range([0.02, 0.08].into_iter(), Scale::Log(10.0), true);
        assert!(
            lo > 0.018 && lo < 0.02 && hi > 0.08 && hi < 0.09,
            "{lo} {hi}"
        );
        assert_eq!(round_log_ticks(0.018, 0.09).len(), 8, "2e-2 … 9e-2");
        // No power of two inside: extended to the nearer one.
        let (lo, hi) = axis_range([0.45, 0.48].into_iter(), Scale::Log(2.0), true);
        assert!(lo > 0.25 && hi > 0.5 && hi < 0.5001, "{lo} {hi}");
        let (lo, hi) = axis_range([0.3, 0.35].into_iter(), Scale::Log(2.0), true);
        assert!(lo < 0.25 && lo > 0.2499 && hi < 0.5, "{lo} {hi}");
        let (lo, hi) = axis_range([0.3].into_iter(), Scale::Log(2.0), true);
        assert!(lo <= 0.15 && hi >= 0.6);
    }
}
