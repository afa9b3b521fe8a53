//! The figures: data in, SVG text out.

use plotters::prelude::*;

use super::chart::{drawing, Area, ChartSpec, Curve, Look, Scale};
use super::{
    style, ContactPanel, ConvergenceSeries, EnergyPanel, FigureError, WorkPrecisionSeries,
};

const TIME: &str = "t";
const ERROR: &str = "error";

/// Checks every chart, then draws the figure: the title on top, then one column per entry of
/// `columns` (800 px wide for one, 600 px each for several, 500 px high), each holding its
/// charts stacked top to bottom.
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
    let size = match columns.len() {
        1 => style::SINGLE,
        n => (style::PANEL_WIDTH * n as u32, style::HEIGHT),
    };
    let mut svg = String::new();
    {
        let root: Area<'_> = SVGBackend::with_string(&mut svg, size).into_drawing_area();
        root.fill(&WHITE).map_err(drawing)?;
        let body = root
            .titled(title, (style::FONT, style::TITLE_SIZE))
            .map_err(drawing)?;
        let areas = body.split_evenly((1, columns.len()));
        for (charts, area) in columns.into_iter().zip(&areas) {
            let cells = area.split_evenly((charts.len(), 1));
            for (chart, cell) in charts.into_iter().zip(&cells) {
                chart.draw(cell)?;
            }
        }
        root.present().map_err(drawing)?;
    }
    Ok(svg)
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
/// the top chart; the bottom chart uses the same colours. The colour of a run is its position
/// in its panel, so list the runs in the same order in every panel.
///
/// Errors: `EmptyData` without panels, for a panel without runs, or when a chart has no
/// finite point; `LengthMismatch` when a run's times and values differ in length.
pub fn contact_node_figure(title: &str, panels: &[ContactPanel]) -> Result<String, FigureError> {
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
                y: ("u(0, t)", Scale::Linear),
                curves: top,
                legend: true,
            },
            ChartSpec {
                what: what_l,
                caption: None,
                x: (TIME, Scale::Linear),
                y: ("λ(t)", Scale::Linear),
                curves: bottom,
                legend: false,
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
            legend: true,
        }]);
    }
    render(title, columns)
}

/// Errors against the mesh size on log–log axes (the paper's Figures 9–10): one line with a
/// marker at each level per series, `h` on a base-2 axis, the legend `"label (slope 0.95)"`
/// with the caller's fitted rate to two decimals (just `"label"` without a fit). A series with
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
                (None, Some(fit)) => format!("{} (slope {:.2})", s.label, fit.rate),
                (None, None) => s.label.clone(),
            };
            let curve = Curve::new(what, &label, &s.h, &s.errors, Look::Marked(i))?;
            match &s.band {
                Some(band) => curve.with_band(what, &band.lower, &band.upper),
                None => Ok(curve),
            }
        })
        .collect::<Result<Vec<_>, _>>()?;
    error_figure(title, what, ("h", Scale::Log(2.0)), curves)
}

/// One log–log chart of errors (y, base 10) against `x`, with a legend.
fn error_figure(
    title: &str,
    what: &str,
    x: (&'static str, Scale),
    curves: Vec<Curve>,
) -> Result<String, FigureError> {
    render(
        title,
        vec![vec![ChartSpec {
            what: what.into(),
            caption: None,
            x,
            y: (ERROR, Scale::Log(10.0)),
            curves,
            legend: true,
        }]],
    )
}

/// Errors against wall-clock time on log–log axes: one line with a marker at each level per
/// series (one series per scheme and mass). Levels with a non-positive or non-finite time or
/// error are skipped.
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
        .map(|(i, s)| Curve::new(what, &s.label, &s.seconds, &s.errors, Look::Marked(i)))
        .collect::<Result<Vec<_>, _>>()?;
    error_figure(title, what, ("wall time (s)", Scale::Log(10.0)), curves)
}

/// Generic lines against time on linear axes, e.g. the energy histories of a stability
/// report. Each entry of `series` is `(legend, t, y)`; non-finite points are skipped.
///
/// Errors: `EmptyData` without series or when no point is finite; `LengthMismatch` when an
/// entry's `t` and `y` differ in length.
pub fn time_series_figure(
    title: &str,
    y_label: &str,
    series: &[(String, Vec<f64>, Vec<f64>)],
) -> Result<String, FigureError> {
    let what = "time-series figure";
    let curves = series
        .iter()
        .enumerate()
        .map(|(i, (label, t, y))| Curve::new(what, label, t, y, Look::Line(i)))
        .collect::<Result<Vec<_>, _>>()?;
    render(
        title,
        vec![vec![ChartSpec {
            what: what.into(),
            caption: None,
            x: (TIME, Scale::Linear),
            y: (y_label, Scale::Linear),
            curves,
            legend: true,
        }]],
    )
}
