//! The figures: data in, SVG text out.

use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::chart::{axis_range, drawing, Area, ChartSpec, Curve, Legend, Scale, BELOW_GAP};
use super::layout::{centred_text, text_width, FigureLayout, SeriesKind, TextBox};
use super::style::{Dash, Look};
use super::{
    style, ContactPanel, ConvergenceSeries, EnergyPanel, FigureError, WorkPrecisionSeries,
};
use crate::harness::run::ContactHistory;

const TIME: &str = "t";
const ERROR: &str = "error";

/// Checks every chart, then draws the figure: the title on top, then one column per entry of
/// `columns` (800 px wide for one, 600 px each for several, 500 px high; widened by the legend
/// of a chart whose legend stands on its right), each holding its charts stacked top to
/// bottom. The figure's [`FigureLayout`] is embedded in the SVG.
fn render(title: &str, columns: Vec<Vec<ChartSpec<'_>>>) -> Result<String, FigureError> {
    let columns = columns
        .into_iter()
        .map(|charts| {
            charts
                .into_iter()
                .map(ChartSpec::into_drawable)
                .collect::<Result<Vec<_>, _>>()
        })
        .collect::<Result<Vec<_>, _>>()?;
    let (mut width, mut height) = match columns.len() {
        1 => style::SINGLE,
        n => (style::PANEL_WIDTH * n as u32, style::HEIGHT),
    };
    // A legend beneath its chart adds its height, and widens a canvas narrower than it.
    for charts in &columns {
        for c in charts.iter().filter(|c| c.legend == Legend::Below) {
            let (w, h) = c.legend_size();
            height = height.max(style::HEIGHT + (h + 2 * BELOW_GAP) as u32);
            width = width.max(w as u32 + 40);
        }
    }
    width += columns
        .iter()
        .map(|charts| {
            charts
                .iter()
                .filter(|c| c.legend == Legend::Right)
                .map(|c| c.legend_width() as u32 + 10)
                .max()
                .unwrap_or(0)
        })
        .sum::<u32>();
    let mut svg = String::new();
    let mut charts = Vec::new();
    let title_box;
    {
        let root: Area<'_> = SVGBackend::with_string(&mut svg, (width, height)).into_drawing_area();
        root.fill(&WHITE).map_err(drawing)?;
        let (text, body) = draw_title(&root, title)?;
        title_box = text;
        let areas = body.split_evenly((1, columns.len()));
        for (column, area) in columns.into_iter().zip(&areas) {
            let cells = area.split_evenly((column.len(), 1));
            for (chart, cell) in column.into_iter().zip(&cells) {
                charts.push(chart.draw(cell)?);
            }
        }
        root.present().map_err(drawing)?;
    }
    let layout = FigureLayout {
        width,
        height,
        title: title_box,
        charts,
    };
    layout.embed(&mut svg).map_err(drawing)?;
    Ok(svg)
}

/// Draws `title` centred at the top of `root`, at the title size or smaller so that it fits
/// the canvas' width with 10 px to spare each side; returns its box and the area below it.
pub(super) fn draw_title<'b>(
    root: &Area<'b>,
    title: &str,
) -> Result<(TextBox, Area<'b>), FigureError> {
    let (width, _) = root.dim_in_pixel();
    let mut size = style::TITLE_SIZE as f64;
    while size > 10.0 && text_width(title, size) > width as i32 - 20 {
        size -= 1.0;
    }
    let top = 6;
    let font = (style::FONT, size)
        .into_font()
        .color(&BLACK)
        .pos(Pos::new(HPos::Center, VPos::Top));
    root.draw(&Text::new(title, (width as i32 / 2, top), font))
        .map_err(drawing)?;
    let text = centred_text(title, size, width as i32 / 2, top);
    let below = (text.rect.y1 + 6) as u32;
    let (_, body) = root.split_vertically(below);
    Ok((text, body))
}

fn empty(what: impl Into<String>) -> FigureError {
    FigureError::EmptyData { what: what.into() }
}

/// The y range shared by one row of a contact figure, whose computed and exact values `values`
/// takes from a run's history: all runs' values (and the exact ones), cut relative to the exact
/// values of the panels' first runs or, without any, to those runs' values (see
/// [`shared_range`]).
fn row_range(
    panels: &[ContactPanel],
    values: fn(&ContactHistory) -> (&Vec<f64>, &Vec<f64>),
) -> Option<(f64, f64)> {
    let runs = || panels.iter().flat_map(|p| p.runs.iter().map(|(_, r)| r));
    let firsts = || panels.iter().filter_map(|p| p.runs.first().map(|(_, r)| r));
    let data = finite_range(runs().flat_map(|r| values(r).0.iter().chain(values(r).1)))?;
    let anchor = finite_range(firsts().flat_map(|r| values(r).1))
        .or_else(|| finite_range(firsts().flat_map(|r| values(r).0)));
    Some(shared_range(data, anchor))
}

/// The descriptions of a contact figure's y axes (displacement, multiplier).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ContactAxes<'a> {
    /// The displacement's axis, e.g. `"u(0, t)"`.
    pub displacement: &'a str,
    /// The multiplier's axis, e.g. `"λ(t)"`.
    pub multiplier: &'a str,
}

/// The finite values of `y`, with their smallest and largest: `None` when there is none.
fn finite_range<'v>(y: impl IntoIterator<Item = &'v f64>) -> Option<(f64, f64)> {
    y.into_iter()
        .copied()
        .filter(|v| v.is_finite())
        .fold(None, |acc, v| {
            Some(acc.map_or((v, v), |(lo, hi): (f64, f64)| (lo.min(v), hi.max(v))))
        })
}

/// The y range shared by compared charts whose values span `data` and whose anchor (the exact
/// curve, or the reference) spans `anchor`: the data's range, cut to the anchor's range widened
/// by twice its span each side (so that spikes far beyond the anchor do not flatten it), padded
/// by 5 %.
fn shared_range(data: (f64, f64), anchor: Option<(f64, f64)>) -> (f64, f64) {
    let (mut lo, mut hi) = data;
    if let Some((a, b)) = anchor {
        let reach = 2.0 * (b - a).max(1e-3 * a.abs().max(b.abs()));
        if reach > 0.0 {
            lo = lo.max(a - reach);
            hi = hi.min(b + reach);
        }
    }
    axis_range([lo, hi].into_iter(), Scale::Linear, true)
}

/// The legend of a run whose `values` are shown on an axis `(lo, hi)` that may cut them:
/// `label` and, when cut, where and how far the run goes (`"NX = 40 (axis cut at −1.57;
/// reaches −21.2)"`).
fn clipped_label(label: &str, values: &[f64], (lo, hi): (f64, f64)) -> String {
    match finite_range(values) {
        Some((min, _)) if min < lo => format!(
            "{label} (axis cut at {}; reaches {})",
            signed(lo, 2),
            signed(min, 1)
        ),
        Some((_, max)) if max > hi => format!(
            "{label} (axis cut at {}; reaches {})",
            signed(hi, 2),
            signed(max, 1)
        ),
        _ => label.to_owned(),
    }
}

/// The contact node of each run against time, one column per panel (the paper's Figures 7,
/// 11, 13: standard mass left, redistributed right).
///
/// Each column has two charts: on top the displacement of every run against `time`, on the
/// bottom the multiplier against `multiplier_time`, their y axes described by `axes`. Each
/// chart also shows the exact curve (black, dashed, over the runs) taken from the panel's first
/// run (`displacement_exact` at `time`, `multiplier_exact` at `multiplier_time`), when it has
/// finite values. The charts of a row share their y axis. That axis spans the runs' values cut
/// to the exact curve's range (the first run's, without an exact curve) widened by twice its
/// span each side, so that force spikes of one panel do not flatten the exact force: a run
/// whose values are cut says so in the legend, with the value it reaches. The legend stands
/// beneath the bottom chart of each panel. The style of a run is its position in its panel, so list the
/// runs in the same order in every panel.
///
/// Errors: `EmptyData` without panels, for a panel without runs, or when a chart has no
/// finite point; `LengthMismatch` when a run's times and values differ in length.
pub fn contact_node_figure(
    title: &str,
    axes: ContactAxes<'_>,
    panels: &[ContactPanel],
) -> Result<String, FigureError> {
    if panels.is_empty() {
        return Err(empty("contact figure: no panel"));
    }
    let mut firsts = Vec::with_capacity(panels.len());
    for panel in panels {
        let (_, first) = panel
            .runs
            .first()
            .ok_or_else(|| empty(format!("contact panel '{}': no run", panel.label)))?;
        firsts.push(first);
    }
    let u_range = row_range(panels, |r| (&r.displacement, &r.displacement_exact));
    let l_range = row_range(panels, |r| (&r.multiplier, &r.multiplier_exact));
    let mut columns = Vec::with_capacity(panels.len());
    for (panel, first) in panels.iter().zip(&firsts) {
        let what_u = format!("contact panel '{}': displacement", panel.label);
        let what_l = format!("contact panel '{}': multiplier", panel.label);
        let mut top = Vec::new();
        let mut bottom = Vec::new();
        for (i, (label, run)) in panel.runs.iter().enumerate() {
            top.push(Curve::new(
                &what_u,
                &match u_range {
                    Some(r) => clipped_label(label, &run.displacement, r),
                    None => label.clone(),
                },
                &run.time,
                &run.displacement,
                Look::line(i),
            )?);
            bottom.push(Curve::new(
                &what_l,
                &match l_range {
                    Some(r) => clipped_label(label, &run.multiplier, r),
                    None => label.clone(),
                },
                &run.multiplier_time,
                &run.multiplier,
                Look::line(i),
            )?);
        }
        top.push(Curve::exact(
            &what_u,
            "exact",
            &first.time,
            &first.displacement_exact,
        )?);
        bottom.push(Curve::exact(
            &what_l,
            "exact",
            &first.multiplier_time,
            &first.multiplier_exact,
        )?);
        columns.push(vec![
            ChartSpec {
                what: what_u,
                caption: Some(panel.label.as_str()),
                x: (TIME, Scale::Linear),
                y: (axes.displacement, Scale::Linear),
                curves: top,
                legend: Legend::None,
                x_at_levels: false,
                y_range: u_range,
                scale_group: Some("displacement".into()),
            },
            ChartSpec {
                what: what_l,
                caption: None,
                x: (TIME, Scale::Linear),
                y: (axes.multiplier, Scale::Linear),
                curves: bottom,
                legend: Legend::Below,
                x_at_levels: false,
                y_range: l_range,
                scale_group: Some("multiplier".into()),
            },
        ]);
    }
    render(title, columns)
}

/// The energy of each run against time, one column per panel (the paper's Figures 8, 12): the
/// energy `E_h(t)` of every run and the exact energy (black, dashed, over the runs) taken from
/// the panel's first run, when it has finite values. The panels share their y axis, fitted to
/// all of them, and each has its legend beneath it. The style of a run is its position in its
/// panel.
///
/// Errors: `EmptyData` without panels, for a panel without runs, or when a panel has no finite
/// point; `LengthMismatch` when a run's times and energies differ in length.
pub fn energy_figure(title: &str, panels: &[EnergyPanel]) -> Result<String, FigureError> {
    if panels.is_empty() {
        return Err(empty("energy figure: no panel"));
    }
    let all: Vec<f64> = panels
        .iter()
        .flat_map(|p| {
            p.runs
                .iter()
                .flat_map(|(_, r)| r.energy.iter().chain(&r.energy_exact))
        })
        .copied()
        .collect();
    let y_range = finite_range(&all).map(|d| shared_range(d, None));
    let mut columns = Vec::with_capacity(panels.len());
    for panel in panels {
        let (_, first) = panel
            .runs
            .first()
            .ok_or_else(|| empty(format!("energy panel '{}': no run", panel.label)))?;
        let what = format!("energy panel '{}'", panel.label);
        let mut curves = Vec::new();
        for (i, (label, run)) in panel.runs.iter().enumerate() {
            curves.push(Curve::new(
                &what,
                label,
                &run.time,
                &run.energy,
                Look::line(i),
            )?);
        }
        curves.push(Curve::exact(
            &what,
            "exact",
            &first.time,
            &first.energy_exact,
        )?);
        columns.push(vec![ChartSpec {
            what,
            caption: Some(panel.label.as_str()),
            x: (TIME, Scale::Linear),
            y: ("E(t)", Scale::Linear),
            curves,
            legend: Legend::Below,
            x_at_levels: false,
            y_range,
            scale_group: Some("energy".into()),
        }]);
    }
    render(title, columns)
}

/// The one kind of band of a convergence figure, as its legend and layout name it.
pub const ROUND_OFF_BAND: &str = "round-off min–max";

/// How far a bias of the reference the errors were measured against can move a fitted slope.
#[derive(Debug, Clone, PartialEq)]
pub enum ConvergenceFit {
    /// The errors are against the exact solution: no bias.
    Exact,
    /// The errors are against a fine-mesh reference: per series, the bound on how far its bias
    /// can move the slope (`None`: unbounded).
    Reference(Vec<Option<f64>>),
}

/// A slope to two decimals with a true minus sign.
fn slope(v: f64) -> String {
    signed(v, 2)
}

/// `v` with `decimals` decimals and a true minus sign.
fn signed(v: f64, decimals: usize) -> String {
    format!("{v:.decimals$}").replace('-', "−")
}

/// Errors against the mesh size on log–log axes (the paper's Figures 9–10): one line with a
/// marker at each level per series, `h` on a base-2 axis ticked at every level (`1/N`), and for
/// each series with a fit, its fitted slope `e = e^c h^p` drawn broken (dashed, dotted, …) in the series' colour over
/// its levels, its legend `"fit: slope 0.95, 95 % CI [0.87, 1.03]"`. Against a fine-mesh
/// reference (`bias`) the legend adds the reference's bias bound and the interval it widens to
/// (`"; reference bias ±0.40 → [−0.94, 0.04]"`, or `"; reference bias unbounded"`): what
/// decides a rate. A series with a band gets it shaded in its colour (beneath every line) and a
/// shaded swatch in the legend; the one kind of band these figures have is an ensemble's
/// round-off min–max, named in its legend with the members' slopes (median, then range).
/// Levels with a non-positive or non-finite `h` or error are skipped, and so are band levels
/// with a non-positive or non-finite bound.
///
/// Errors: `EmptyData` without series or when no series has a drawable level;
/// `LengthMismatch` when a series' `h`, `errors` or band bounds differ in length, or `bias`
/// has not one bound per series.
pub fn convergence_figure(
    title: &str,
    series: &[ConvergenceSeries],
    bias: &ConvergenceFit,
) -> Result<String, FigureError> {
    let what = "convergence figure";
    if let ConvergenceFit::Reference(b) = bias {
        if b.len() != series.len() {
            return Err(FigureError::LengthMismatch {
                what: "convergence figure: bias bounds".into(),
                left: series.len(),
                right: b.len(),
            });
        }
    }
    let mut curves = Vec::new();
    for (i, s) in series.iter().enumerate() {
        let look = Look::marked(i, Dash::Solid);
        let curve = match &s.band {
            Some(band) => {
                let rates = band.rate.map_or(String::new(), |r| {
                    format!(
                        "; their slopes {} to {} (median {})",
                        slope(r.min),
                        slope(r.max),
                        slope(r.median)
                    )
                });
                Curve::new(
                    what,
                    &format!("{}, {ROUND_OFF_BAND} shaded{rates}", s.label),
                    &s.h,
                    &s.errors,
                    look,
                )?
                .with_band(what, ROUND_OFF_BAND, &band.lower, &band.upper)?
            }
            None => Curve::new(what, &s.label, &s.h, &s.errors, look)?,
        };
        curves.push(curve);
        let Some(fit) = s.fit.filter(|_| s.band.is_none()) else {
            continue;
        };
        let mut label = match (fit.ci_low, fit.ci_high) {
            (Some(low), Some(high)) => format!(
                "fit: slope {}, 95 % CI [{}, {}]",
                slope(fit.rate),
                slope(low),
                slope(high)
            ),
            _ => format!("fit: slope {} (no interval: two levels)", slope(fit.rate)),
        };
        if let ConvergenceFit::Reference(bounds) = bias {
            match (bounds[i], fit.ci_low, fit.ci_high) {
                (Some(b), Some(low), Some(high)) => label.push_str(&format!(
                    "; reference bias ±{b:.2} → [{}, {}]",
                    slope(low - b),
                    slope(high + b)
                )),
                (Some(b), _, _) => label.push_str(&format!("; reference bias ±{b:.2}")),
                (None, _, _) => label.push_str("; reference bias unbounded"),
            }
        }
        let levels: Vec<f64> =
            s.h.iter()
                .zip(&s.errors)
                .filter(|(h, e)| **h > 0.0 && h.is_finite() && **e > 0.0 && e.is_finite())
                .map(|(h, _)| *h)
                .collect();
        let fitted: Vec<f64> = levels
            .iter()
            .map(|h| (fit.intercept + fit.rate * h.ln()).exp())
            .collect();
        curves.push(
            Curve::new(what, &label, &levels, &fitted, Look::fit_of(i, look))?
                .of_kind(SeriesKind::Fit),
        );
    }
    error_figure(title, what, ("h", Scale::Log(2.0)), curves, true)
}

/// One log–log chart of errors (y, base 10) against `x`, with a legend beneath the chart
/// (`levels`: the x axis is ticked at the data's abscissae; the series, their fits and the
/// bias bounds make long legends) or, for a work–precision chart, on its right.
fn error_figure(
    title: &str,
    what: &str,
    x: (&'static str, Scale),
    curves: Vec<Curve>,
    levels: bool,
) -> Result<String, FigureError> {
    render(
        title,
        vec![vec![ChartSpec {
            what: what.into(),
            caption: None,
            x,
            y: (ERROR, Scale::Log(10.0)),
            curves,
            legend: if levels { Legend::Below } else { Legend::Right },
            x_at_levels: levels,
            y_range: None,
            scale_group: None,
        }]],
    )
}

/// Errors against wall-clock time on log–log axes: one line with a marker at each level per
/// series, the legend on the right of the chart, the error axis fitted to the data. Each series
/// is one case `group/member` (a scheme and a mass): the cases of one group take one colour and
/// one marker, in the order the groups first appear, and the members of a group the dashes in
/// order (solid, dashed, …), so that list each group's members in the same order. Levels with a
/// non-positive or non-finite time or error are skipped.
///
/// Errors: `EmptyData` without series or when no series has a drawable level;
/// `LengthMismatch` when a series' `seconds` and `errors` differ in length.
pub fn work_precision_figure(
    title: &str,
    series: &[(String, String, WorkPrecisionSeries)],
) -> Result<String, FigureError> {
    let what = "work-precision figure";
    let mut groups: Vec<&str> = Vec::new();
    let mut members: Vec<&str> = Vec::new();
    let curves = series
        .iter()
        .map(|(group, member, s)| {
            let g = groups.iter().position(|x| x == group).unwrap_or_else(|| {
                groups.push(group);
                groups.len() - 1
            });
            let m = members.iter().position(|x| x == member).unwrap_or_else(|| {
                members.push(member);
                members.len() - 1
            });
            let look = Look::marked(g, Dash::ORDER[m % Dash::ORDER.len()]);
            Curve::new(what, &s.label, &s.seconds, &s.errors, look)
        })
        .collect::<Result<Vec<_>, _>>()?;
    error_figure(
        title,
        what,
        ("wall time (s)", Scale::Log(10.0)),
        curves,
        false,
    )
}

/// How the curves of a [`line_figure`] are styled.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Colouring {
    /// One colour, dash and marker per series, in order.
    OnePerSeries,
    /// The series come in pairs, a computed curve then its exact counterpart: each pair takes
    /// one colour, the computed curve solid with markers, the exact one broken (dashed, dotted,
    /// … by pair) and drawn over it.
    ComputedAndExact,
}

/// Generic lines on linear axes described `x_label` and `y_label`, with a legend inside the
/// chart where it covers no data. Each entry of `series` is `(legend, x, y)`; non-finite points
/// are skipped.
///
/// Errors: `EmptyData` without series or when no point is finite; `LengthMismatch` when an
/// entry's `x` and `y` differ in length.
pub fn line_figure(
    title: &str,
    (x_label, y_label): (&str, &str),
    series: &[(String, Vec<f64>, Vec<f64>)],
    colouring: Colouring,
) -> Result<String, FigureError> {
    lines(
        title,
        (x_label, y_label),
        series,
        colouring,
        &[],
        Legend::Inside,
    )
}

/// Generic lines against time on linear axes, e.g. the energy histories of a stability
/// report, one colour, dash and marker per series, the legend on the right of the chart (long
/// legends would hide the curves), ending with `notes`: legend entries with nothing drawn (runs
/// left out, and why). Each entry of `series` is `(legend, t, y)`; non-finite points are
/// skipped.
///
/// Errors: `EmptyData` without series or when no point is finite; `LengthMismatch` when an
/// entry's `t` and `y` differ in length.
pub fn time_series_figure(
    title: &str,
    y_label: &str,
    series: &[(String, Vec<f64>, Vec<f64>)],
    notes: &[String],
) -> Result<String, FigureError> {
    lines(
        title,
        (TIME, y_label),
        series,
        Colouring::OnePerSeries,
        notes,
        Legend::Right,
    )
}

/// The chart of [`line_figure`] and [`time_series_figure`].
fn lines(
    title: &str,
    (x_label, y_label): (&str, &str),
    series: &[(String, Vec<f64>, Vec<f64>)],
    colouring: Colouring,
    notes: &[String],
    legend: Legend,
) -> Result<String, FigureError> {
    let what = "line figure";
    let mut curves = series
        .iter()
        .enumerate()
        .map(|(i, (label, x, y))| match colouring {
            Colouring::OnePerSeries => Curve::new(what, label, x, y, Look::line(i)),
            Colouring::ComputedAndExact if i % 2 == 0 => {
                Curve::new(what, label, x, y, Look::marked(i / 2, Dash::Solid))
            }
            Colouring::ComputedAndExact => Ok(Curve::new(
                what,
                label,
                x,
                y,
                Look::fit_of(i / 2, Look::marked(i / 2, Dash::Solid)),
            )?
            .of_kind(SeriesKind::Exact)),
        })
        .collect::<Result<Vec<_>, _>>()?;
    curves.extend(notes.iter().map(|n| Curve::note(n)));
    render(
        title,
        vec![vec![ChartSpec {
            what: what.into(),
            caption: None,
            x: (x_label, Scale::Linear),
            y: (y_label, Scale::Linear),
            curves,
            legend,
            x_at_levels: false,
            y_range: None,
            scale_group: None,
        }]],
    )
}
