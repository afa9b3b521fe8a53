//! One chart: axes (linear or logarithmic), curves, legend. Every figure is made of these.

use plotters::coord::ranged1d::{AsRangedCoord, ValueFormatter};
use plotters::coord::Shift;
use plotters::prelude::*;

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
    /// Logarithmic with ticks at the powers of this base (2 or 10).
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
    /// A computed curve: the palette colour of this index, no markers.
    Line(usize),
    /// A computed curve with a marker at every point.
    Marked(usize),
}

impl Look {
    fn colour(self) -> RGBColor {
        match self {
            Look::Exact => style::EXACT,
            Look::Line(i) | Look::Marked(i) => style::colour(i),
        }
    }

    fn width(self) -> u32 {
        match self {
            Look::Exact => style::EXACT_WIDTH,
            Look::Line(_) | Look::Marked(_) => style::RUN_WIDTH,
        }
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
    /// Whether to draw the legend.
    pub legend: bool,
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

    /// Draws the chart on `area`.
    pub fn draw(self, area: &Area<'_>) -> Result<(), FigureError> {
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
        let (y0, y1) = axis_range(ys, spec.y.1, true);
        match (spec.x.1, spec.y.1) {
            (Scale::Linear, Scale::Linear) => {
                let ticks = Ticks {
                    x: (linear_labels(), style::linear_tick),
                    y: (linear_labels(), style::linear_tick),
                };
                draw_on(area, &spec, x0..x1, y0..y1, ticks)
            }
            (Scale::Log(bx), Scale::Log(by)) => {
                let ticks = Ticks {
                    x: (log_labels(x0, x1, bx), log_formatter(bx)),
                    y: (log_labels(y0, y1, by), log_formatter(by)),
                };
                draw_on(
                    area,
                    &spec,
                    (x0..x1).log_scale().base(bx),
                    (y0..y1).log_scale().base(by),
                    ticks,
                )
            }
            _ => unreachable!("the figures use linear–linear or log–log charts only"),
        }
    }
}

/// Number of labels and label formatter of each axis.
struct Ticks {
    x: (usize, fn(f64) -> String),
    y: (usize, fn(f64) -> String),
}

fn linear_labels() -> usize {
    8
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

fn log_formatter(base: f64) -> fn(f64) -> String {
    if base == 2.0 {
        style::log2_tick
    } else {
        style::log10_tick
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

fn draw_on<X, Y>(
    area: &Area<'_>,
    spec: &ChartSpec<'_>,
    xr: X,
    yr: Y,
    ticks: Ticks,
) -> Result<(), FigureError>
where
    X: AsRangedCoord<Value = f64>,
    Y: AsRangedCoord<Value = f64>,
    X::CoordDescType: ValueFormatter<f64>,
    Y::CoordDescType: ValueFormatter<f64>,
{
    let mut builder = ChartBuilder::on(area);
    if let Some(caption) = spec.caption {
        builder.caption(caption, (style::FONT, style::CAPTION_SIZE));
    }
    let mut chart = builder
        .margin(10)
        .margin_right(25)
        .x_label_area_size(50)
        .y_label_area_size(80)
        .build_cartesian_2d(xr, yr)
        .map_err(drawing)?;
    let fx = |v: &f64| (ticks.x.1)(*v);
    let fy = |v: &f64| (ticks.y.1)(*v);
    chart
        .configure_mesh()
        .x_desc(spec.x.0)
        .y_desc(spec.y.0)
        .x_labels(ticks.x.0)
        .y_labels(ticks.y.0)
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
        let anno = chart
            .draw_series(LineSeries::new(curve.points.iter().copied(), line))
            .map_err(drawing)?;
        anno.label(curve.label.as_str());
        match curve.look {
            Look::Marked(_) => {
                if curve.has_band() {
                    // The band's swatch, a shaded square, behind the line and marker.
                    let shade = colour.mix(style::BAND_OPACITY).filled();
                    anno.legend(move |(x, y)| {
                        EmptyElement::at((x, y))
                            + Polygon::new(vec![(2, -7), (18, -7), (18, 7), (2, 7)], shade)
                            + PathElement::new(vec![(0, 0), (20, 0)], line)
                            + Circle::new((10, 0), style::MARKER_RADIUS, colour.filled())
                    });
                } else {
                    anno.legend(move |(x, y)| {
                        EmptyElement::at((x, y))
                            + PathElement::new(vec![(0, 0), (20, 0)], line)
                            + Circle::new((10, 0), style::MARKER_RADIUS, colour.filled())
                    });
                }
                chart
                    .draw_series(
                        curve
                            .points
                            .iter()
                            .map(|&p| Circle::new(p, style::MARKER_RADIUS, colour.filled())),
                    )
                    .map_err(drawing)?;
            }
            Look::Exact | Look::Line(_) => {
                anno.legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], line));
            }
        }
    }

    if spec.legend {
        let position = legend_position(&chart, spec)?;
        chart
            .configure_series_labels()
            .position(position)
            .label_font((style::FONT, style::LEGEND_SIZE))
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK.mix(0.6))
            .draw()
            .map_err(drawing)?;
    }
    Ok(())
}

/// The legend position, among the corners and edge middles of the plotting area, whose box
/// covers the fewest samples of the curves and of their bands' edges (the first such in the
/// order tried).
fn legend_position<X, Y>(
    chart: &ChartContext<'_, SVGBackend<'_>, Cartesian2d<X, Y>>,
    spec: &ChartSpec<'_>,
) -> Result<SeriesLabelPosition, FigureError>
where
    X: Ranged<ValueType = f64>,
    Y: Ranged<ValueType = f64>,
{
    use SeriesLabelPosition::*;
    // The legend box as plotters lays it out: the text, 30 px of legend symbol, 10 px margins.
    let font = (style::FONT, style::LEGEND_SIZE).into_font();
    let mut text = MultiLineText::<_, &str>::new((0, 0), font);
    for c in &spec.curves {
        text.push_line(c.label.as_str());
    }
    let (tw, th) = text.estimate_dimension().map_err(drawing)?;
    let (w, h) = (tw + 30 + 20, th + 20);

    let (xr, yr) = chart.plotting_area().get_pixel_range();
    let (aw, ah) = (xr.end - xr.start, yr.end - yr.start);
    let mut samples: Vec<(i32, i32)> = Vec::new();
    // Each curve, and the upper and lower edges of its band.
    let lines = spec.curves.iter().flat_map(|c| {
        [
            c.points.clone(),
            c.band.iter().map(|b| (b.0, b.2)).collect(),
            c.band.iter().map(|b| (b.0, b.1)).collect(),
        ]
    });
    for line in lines {
        let px: Vec<(i32, i32)> = line
            .iter()
            .map(|p| {
                let (x, y) = chart.backend_coord(p);
                (x - xr.start, y - yr.start)
            })
            .collect();
        samples.extend(px.first().copied());
        for pair in px.windows(2) {
            let (a, b) = (pair[0], pair[1]);
            let n = ((b.0 - a.0).abs().max((b.1 - a.1).abs()) / 3).clamp(1, 400);
            samples.extend((1..=n).map(|k| (a.0 + (b.0 - a.0) * k / n, a.1 + (b.1 - a.1) * k / n)));
        }
    }
    let candidates = [
        UpperRight,
        UpperLeft,
        LowerRight,
        LowerLeft,
        UpperMiddle,
        LowerMiddle,
        MiddleRight,
        MiddleLeft,
    ];
    let covered = |pos: &SeriesLabelPosition| {
        let x = match pos {
            UpperLeft | MiddleLeft | LowerLeft => 5,
            UpperMiddle | MiddleMiddle | LowerMiddle => (aw - w) / 2,
            _ => aw - w - 5,
        };
        let y = match pos {
            UpperLeft | UpperMiddle | UpperRight => 5,
            MiddleLeft | MiddleMiddle | MiddleRight => (ah - h) / 2,
            _ => ah - h - 5,
        };
        samples
            .iter()
            .filter(|s| s.0 >= x && s.0 <= x + w && s.1 >= y && s.1 <= y + h)
            .count()
    };
    let mut best = (usize::MAX, UpperRight);
    for pos in candidates {
        let n = covered(&pos);
        if n < best.0 {
            best = (n, pos);
        }
    }
    Ok(best.1)
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
