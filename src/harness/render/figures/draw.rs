//! The figures: data in, SVG text out.

use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::chart::{drawing, Area, ChartSpec, Curve, Legend, Look, Scale};
use super::layout::{centred_text, text_width, FigureLayout, TextBox};
use super::{
    style, ContactPanel, ConvergenceSeries, EnergyPanel, FigureError, WorkPrecisionSeries,
};

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
    let (mut width, height) = match columns.len() {
        1 => style::SINGLE,
        n => (style::PANEL_WIDTH * n as u32, style::HEIGHT),
    };
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

/// The contact node of each run against time, one column per panel (the paper's Figures 7,
/// 11, 13: standard mass left, redistributed right).
///
/// Each column has two charts: on top the displacement `u_h(0, t)` of every run against
/// `time`, on the bottom the multiplier `λ_h` against `multiplier_time`. Each chart also shows
/// the exact curve (black, thick, beneath the runs) taken from the panel's first run
/// (`displacement_exact` at `time`, `multiplier_exact` at `multiplier_time`). The legend is in
/// the bottom chart, where the multiplier's long stretches at zero leave room; the top chart
/// uses the same colours. The colour of a run is its position
/// in its panel, so list the runs in the same order in every panel.
///
/// Errors: `EmptyData` without panels, for a panel without runs, or when a chart has no
/// finite point; `LengthMismatch` when a run's times and values differ in length.
pub fn contact_node_figure(title: &str, panels: &[ContactPanel]) -> Result<String, FigureError> {
    contact_node_figure_labelled(title, ("u(0, t)", "λ(t)"), panels)
}

/// [`contact_node_figure`] with the y axes described as `axes` (displacement, multiplier),
/// for a contact node other than the 1D bar's `x = 0`.
///
/// Errors: those of [`contact_node_figure`].
pub fn contact_node_figure_labelled(
    title: &str,
    axes: (&str, &str),
    panels: &[ContactPanel],
) -> Result<String, FigureError> {
    if panels.is_empty() {
        return Err(empty("contact figure: no panel"));
    }
    let mut columns = Vec::with_capacity(panels.len());
    for panel in panels {
        let (_, first) = panel
            .runs
            .first()
            .ok_or_else(|| empty(format!("contact panel '{}': no run", panel.label)))?;
        let what_u = format!("contact panel '{}': displacement", panel.label);
        let what_l = format!("contact panel '{}': multiplier", panel.label);
        let mut top = vec![Curve::new(
            &what_u,
            "exact",
            &first.time,
            &first.displacement_exact,
            Look::Exact,
        )?];
        let mut bottom = vec![Curve::new(
            &what_l,
            "exact",
            &first.multiplier_time,
            &first.multiplier_exact,
            Look::Exact,
        )?];
        for (i, (label, run)) in panel.runs.iter().enumerate() {
            top.push(Curve::new(
                &what_u,
                label,
                &run.time,
                &run.displacement,
                Look::Line(i),
            )?);
            bottom.push(Curve::new(
                &what_l,
                label,
                &run.multiplier_time,
                &run.multiplier,
                Look::Line(i),
            )?);
        }
        columns.push(vec![
            ChartSpec {
                what: what_u,
                caption: Some(panel.label.as_str()),
                x: (TIME, Scale::Linear),
                y: (axes.0, Scale::Linear),
                curves: top,
                legend: Legend::None,
                x_at_levels: false,
            },
            ChartSpec {
                what: what_l,
                caption: None,
                x: (TIME, Scale::Linear),
                y: (axes.1, Scale::Linear),
                curves: bottom,
                legend: Legend::Inside,
                x_at_levels: false,
            },
        ]);
    }
    render(title, columns)
}

/// The energy of each run against time, one column per panel (the paper's Figures 8, 12): the
/// energy `E_h(t)` of every run and the exact energy (black, thick, beneath the runs) taken
/// from the panel's first run. Colours follow the runs' positions in their panel.
///
/// Errors: `EmptyData` without panels, for a panel without runs, or when a panel has no finite
/// point; `LengthMismatch` when a run's times and energies differ in length.
pub fn energy_figure(title: &str, panels: &[EnergyPanel]) -> Result<String, FigureError> {
    if panels.is_empty() {
        return Err(empty("energy figure: no panel"));
    }
    let mut columns = Vec::with_capacity(panels.len());
    for panel in panels {
        let (_, first) = panel
            .runs
            .first()
            .ok_or_else(|| empty(format!("energy panel '{}': no run", panel.label)))?;
        let what = format!("energy panel '{}'", panel.label);
        let mut curves = vec![Curve::new(
            &what,
            "exact",
            &first.time,
            &first.energy_exact,
            Look::Exact,
        )?];
        for (i, (label, run)) in panel.runs.iter().enumerate() {
            curves.push(Curve::new(
                &what,
                label,
                &run.time,
                &run.energy,
                Look::Line(i),
            )?);
        }
        columns.push(vec![ChartSpec {
            what,
            caption: Some(panel.label.as_str()),
            x: (TIME, Scale::Linear),
            y: ("E(t)", Scale::Linear),
            curves,
            legend: Legend::Inside,
            x_at_levels: false,
        }]);
    }
    render(title, columns)
}

/// Errors against the mesh size on log–log axes (the paper's Figures 9–10): one line with a
/// marker at each level per series, `h` on a base-2 axis ticked at every level (`1/N`), the
/// legend `"label (slope 0.95 ± 0.04)"` with the caller's fitted rate and the half-width of its
/// 95 % interval to two decimals (`"label (slope 0.95)"` without an interval, just `"label"`
/// without a fit). A series with
/// a band also gets the band shaded in its colour (beneath every line) and a shaded swatch in
/// the legend; the band's rate, when given, replaces the fit in the legend as
/// `"label (slope 0.52 [0.41, 0.63])"`: median, then minimum and maximum. Levels with a
/// non-positive or non-finite `h` or error are skipped, and so are band levels with a
/// non-positive or non-finite bound.
///
/// Errors: `EmptyData` without series or when no series has a drawable level;
/// `LengthMismatch` when a series' `h`, `errors` or band bounds differ in length.
pub fn convergence_figure(
    title: &str,
    series: &[ConvergenceSeries],
) -> Result<String, FigureError> {
    let what = "convergence figure";
    let curves = series
        .iter()
        .enumerate()
        .map(|(i, s)| {
            let band_rate = s.band.as_ref().and_then(|b| b.rate);
            let label = match (band_rate, &s.fit) {
                (Some(r), _) => format!(
                    "{} (slope {:.2} [{:.2}, {:.2}])",
                    s.label, r.median, r.min, r.max
                ),
                (None, Some(fit)) => match (fit.ci_low, fit.ci_high) {
                    (Some(low), Some(high)) => format!(
                        "{} (slope {:.2} ± {:.2})",
                        s.label,
                        fit.rate,
                        0.5 * (high - low)
                    ),
                    _ => format!("{} (slope {:.2})", s.label, fit.rate),
                },
                (None, None) => s.label.clone(),
            };
            let curve = Curve::new(what, &label, &s.h, &s.errors, Look::Marked(i, false))?;
            match &s.band {
                Some(band) => curve.with_band(what, &band.lower, &band.upper),
                None => Ok(curve),
            }
        })
        .collect::<Result<Vec<_>, _>>()?;
    error_figure(title, what, ("h", Scale::Log(2.0)), curves, true)
}

/// One log–log chart of errors (y, base 10) against `x`, with a legend inside the chart where
/// it covers no data (`levels`: the x axis is ticked at the data's abscissae) or, for a
/// work–precision chart, on its right.
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
            legend: if levels {
                Legend::Inside
            } else {
                Legend::Right
            },
            x_at_levels: levels,
        }]],
    )
}

/// Errors against wall-clock time on log–log axes: one line with a marker at each level per
/// series (one series per scheme and mass), the legend on the right of the chart. Up to ten
/// series take one hue each; with more, consecutive pairs share a hue (from hues whose shades
/// all stay apart), the second of each pair in its lighter shade (so list each scheme's masses next to each other). Levels with a
/// non-positive or non-finite time or error are skipped.
///
/// Errors: `EmptyData` without series or when no series has a drawable level;
/// `LengthMismatch` when a series' `seconds` and `errors` differ in length.
pub fn work_precision_figure(
    title: &str,
    series: &[WorkPrecisionSeries],
) -> Result<String, FigureError> {
    let what = "work-precision figure";
    let curves = series
        .iter()
        .enumerate()
        .map(|(i, s)| {
            let look = if series.len() > style::HUES {
                Look::Marked(style::pair_hue(i / 2), i % 2 == 1)
            } else {
                Look::Marked(i, false)
            };
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

/// How the curves of a [`line_figure`] are coloured.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Colouring {
    /// One hue per series, in order.
    OnePerSeries,
    /// The series come in pairs, a computed curve then its exact counterpart: each pair takes
    /// one hue, the exact curve in its lighter shade, thicker, drawn beneath the computed one.
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
    lines(title, (x_label, y_label), series, colouring, Legend::Inside)
}

/// Generic lines against time on linear axes, e.g. the energy histories of a stability
/// report, one hue per series, the legend on the right of the chart (long legends would hide
/// the curves). Each entry of `series` is `(legend, t, y)`; non-finite points are skipped.
///
/// Errors: `EmptyData` without series or when no point is finite; `LengthMismatch` when an
/// entry's `t` and `y` differ in length.
pub fn time_series_figure(
    title: &str,
    y_label: &str,
    series: &[(String, Vec<f64>, Vec<f64>)],
) -> Result<String, FigureError> {
    lines(
        title,
        (TIME, y_label),
        series,
        Colouring::OnePerSeries,
        Legend::Right,
    )
}

/// The chart of [`line_figure`] and [`time_series_figure`].
fn lines(
    title: &str,
    (x_label, y_label): (&str, &str),
    series: &[(String, Vec<f64>, Vec<f64>)],
    colouring: Colouring,
    legend: Legend,
) -> Result<String, FigureError> {
    let what = "line figure";
    let mut curves = series
        .iter()
        .enumerate()
        .map(|(i, (label, x, y))| {
            let look = match colouring {
                Colouring::OnePerSeries => Look::Line(i),
                Colouring::ComputedAndExact if i % 2 == 0 => Look::Line(i / 2),
                Colouring::ComputedAndExact => Look::ExactOf(i / 2),
            };
            Curve::new(what, label, x, y, look)
        })
        .collect::<Result<Vec<_>, _>>()?;
    if colouring == Colouring::ComputedAndExact {
        // Each exact curve beneath its computed one.
        for pair in curves.chunks_mut(2) {
            pair.reverse();
        }
    }
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
        }]],
    )
}
