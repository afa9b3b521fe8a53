//! Space–time maps: a field sampled on a grid of times × positions drawn as coloured cells (the
//! note's Figures 4–5, the von Mises stress along the bar over time).

use std::cell::RefCell;

use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::chart::{drawing, Area};
use super::draw::draw_title;
use super::layout::{centred_text, AxisLayout, ChartLayout, FigureLayout, Rect, Tick};
use super::{style, FigureError};

/// One panel of [`space_time_map`].
#[derive(Debug, Clone, Default, PartialEq)]
pub struct SpaceTimePanel {
    /// Caption, e.g. `"standard mass"`.
    pub label: String,
    /// Sample times (increasing).
    pub time: Vec<f64>,
    /// Positions of the cells' centres (increasing, evenly spaced).
    pub position: Vec<f64>,
    /// `values[k][j]`: position `j` at `time[k]`.
    pub values: Vec<Vec<f64>>,
}

/// Viridis at five stops, interpolated linearly: perceptually ordered, readable in grey.
const STOPS: [(f64, f64, f64); 5] = [
    (68.0, 1.0, 84.0),
    (59.0, 82.0, 139.0),
    (33.0, 145.0, 140.0),
    (94.0, 201.0, 98.0),
    (253.0, 231.0, 37.0),
];

fn colour_of(fraction: f64) -> RGBColor {
    let f = fraction.clamp(0.0, 1.0) * (STOPS.len() - 1) as f64;
    let i = (f.floor() as usize).min(STOPS.len() - 2);
    let w = f - i as f64;
    let mix = |a: f64, b: f64| (a + w * (b - a)).round() as u8;
    let (a, b) = (STOPS[i], STOPS[i + 1]);
    RGBColor(mix(a.0, b.0), mix(a.1, b.1), mix(a.2, b.2))
}

/// Panels side by side (600 px each, 800 px for a lone one, 500 px high), time on the x axis, position on the y axis,
/// each cell coloured by its value on one scale shared by all panels, from 0 to the largest
/// finite value of any, which one colour bar right of the last panel shows with its ticks.
/// Non-finite values are left white. The figure's layout is embedded as in every figure.
///
/// Errors: `EmptyData` without panels or when a panel has no positive finite value;
/// `LengthMismatch` when a panel has not one row per time or not one value per position.
pub fn space_time_map(title: &str, panels: &[SpaceTimePanel]) -> Result<String, FigureError> {
    if panels.is_empty() {
        return Err(FigureError::EmptyData {
            what: "space-time map: no panel".into(),
        });
    }
    let mut tops = Vec::with_capacity(panels.len());
    for p in panels {
        let what = format!("space-time map '{}'", p.label);
        if p.values.len() != p.time.len() {
            return Err(FigureError::LengthMismatch {
                what,
                left: p.time.len(),
                right: p.values.len(),
            });
        }
        if let Some(row) = p.values.iter().find(|r| r.len() != p.position.len()) {
            return Err(FigureError::LengthMismatch {
                what,
                left: p.position.len(),
                right: row.len(),
            });
        }
        let top = p
            .values
            .iter()
            .flatten()
            .copied()
            .filter(|v| v.is_finite())
            .fold(f64::NEG_INFINITY, f64::max);
        if !(top.is_finite() && top > 0.0) {
            return Err(FigureError::EmptyData {
                what: format!("{what}: no positive finite value"),
            });
        }
        tops.push(top);
    }
    let width = (style::PANEL_WIDTH * panels.len() as u32).max(style::SINGLE.0);
    let height = style::HEIGHT;
    let mut svg = String::new();
    let mut charts = Vec::new();
    let title_box;
    {
        let root: Area<'_> = SVGBackend::with_string(&mut svg, (width, height)).into_drawing_area();
        root.fill(&WHITE).map_err(drawing)?;
        let (text, body) = draw_title(&root, title)?;
        title_box = text;
        let top = tops.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        let last = panels.len() - 1;
        for (k, (panel, area)) in panels
            .iter()
            .zip(body.split_evenly((1, panels.len())))
            .enumerate()
        {
            charts.push(draw_panel(panel, &area, top, k == last)?);
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

fn half_step(v: &[f64], k: usize) -> f64 {
    match (v.get(k.wrapping_sub(1)), v.get(k + 1)) {
        (_, Some(next)) => 0.5 * (next - v[k]),
        (Some(prev), None) => 0.5 * (v[k] - prev),
        (None, None) => 0.5,
    }
}

/// Room right of a panel's plotting area for its colour bar and the bar's tick labels.
const BAR_ROOM: i32 = 95;
/// Width of the colour bar.
const BAR_WIDTH: i32 = 16;
/// Number of colour steps drawn in the bar.
const BAR_STEPS: i32 = 64;
/// Number of intervals between the bar's ticks, at least (the step is rounded up to 1, 2 or 5
/// times a power of ten).
const BAR_INTERVALS: usize = 4;

/// Draws one panel, coloured from 0 to `top`, and the colour bar when `bar`; returns its
/// layout.
fn draw_panel(
    panel: &SpaceTimePanel,
    area: &Area<'_>,
    top: f64,
    bar: bool,
) -> Result<ChartLayout, FigureError> {
    let (Some(&t0), Some(&t1)) = (panel.time.first(), panel.time.last()) else {
        return Err(FigureError::EmptyData {
            what: format!("space-time map '{}': no time", panel.label),
        });
    };
    let (Some(&x0), Some(&x1)) = (panel.position.first(), panel.position.last()) else {
        return Err(FigureError::EmptyData {
            what: format!("space-time map '{}': no position", panel.label),
        });
    };
    let dx = half_step(&panel.position, 0);
    let (t_hi, x_lo, x_hi) = (t1.max(t0 + 1e-12), x0 - dx, x1 + dx);
    let mut chart = ChartBuilder::on(area)
        .caption(panel.label.as_str(), (style::FONT, style::CAPTION_SIZE))
        .margin(10)
        .margin_right(BAR_ROOM)
        .x_label_area_size(45)
        .y_label_area_size(60)
        .build_cartesian_2d(t0..t_hi, x_lo..x_hi)
        .map_err(drawing)?;
    let x_ticks = RefCell::new(Vec::new());
    let y_ticks = RefCell::new(Vec::new());
    let (x_step, y_step) = ((t_hi - t0) / 10.0, (x_hi - x_lo) / 10.0);
    let record = |ticks: &RefCell<Vec<Tick>>, v: f64, step: f64, magnitude: f64| {
        let label = style::linear_tick(v, step, magnitude);
        ticks.borrow_mut().push(Tick {
            value: v,
            label: label.clone(),
        });
        label
    };
    chart
        .configure_mesh()
        .disable_mesh()
        .x_desc("t")
        .y_desc("height above the contact face")
        .axis_desc_style((style::FONT, style::AXIS_DESC_SIZE))
        .label_style((style::FONT, style::TICK_SIZE))
        .x_label_formatter(&|v| record(&x_ticks, *v, x_step, t0.abs().max(t_hi.abs())))
        .y_label_formatter(&|v| record(&y_ticks, *v, y_step, x_lo.abs().max(x_hi.abs())))
        .draw()
        .map_err(drawing)?;
    let cells = panel.time.iter().enumerate().flat_map(|(k, &t)| {
        let (ta, tb) = (
            t - half_step(&panel.time, k).min(t - t0),
            t + half_step(&panel.time, k),
        );
        panel
            .position
            .iter()
            .zip(&panel.values[k])
            .filter(|(_, v)| v.is_finite())
            .map(move |(&x, &v)| {
                Rectangle::new(
                    [(ta, x - dx), (tb.min(t1), x + dx)],
                    colour_of(v / top).filled(),
                )
            })
    });
    chart.draw_series(cells).map_err(drawing)?;
    let plot = Rect::spanning(chart.plotting_area().get_pixel_range());
    let bar = if bar {
        Some(colour_bar(area, plot, top)?)
    } else {
        None
    };
    let (ax, ay) = area.get_base_pixel();
    let (aw, _) = area.dim_in_pixel();
    Ok(ChartLayout {
        plot,
        caption: Some(centred_text(
            &panel.label,
            style::CAPTION_SIZE as f64,
            ax + aw as i32 / 2,
            ay + 10,
        )),
        x: AxisLayout {
            label: "t".into(),
            ticks: x_ticks.into_inner(),
            range: Some([t0, t_hi]),
            ..AxisLayout::default()
        },
        y: AxisLayout {
            label: "height above the contact face".into(),
            ticks: y_ticks.into_inner(),
            range: Some([x_lo, x_hi]),
            ..AxisLayout::default()
        },
        legend: None,
        series: Vec::new(),
        colour_bar: bar,
        scale_group: Some(format!("von Mises stress, 0 to {top}")),
    })
}

/// Draws the colour bar of a panel whose plotting area is `plot` (canvas pixels), from 0 at
/// the bottom to `top`, with its ticks; returns its box and axis.
fn colour_bar(area: &Area<'_>, plot: Rect, top: f64) -> Result<(Rect, AxisLayout), FigureError> {
    let (bx, by) = area.get_base_pixel();
    let bar = Rect {
        x0: plot.x1 + 12,
        y0: plot.y0,
        x1: plot.x1 + 12 + BAR_WIDTH,
        y1: plot.y1,
    };
    let (x0, x1) = (bar.x0 - bx, bar.x1 - bx);
    let row = |k: i32| bar.y1 - by - (bar.y1 - bar.y0) * k / BAR_STEPS;
    for k in 0..BAR_STEPS {
        let fraction = (f64::from(k) + 0.5) / f64::from(BAR_STEPS);
        area.draw(&Rectangle::new(
            [(x0, row(k + 1)), (x1, row(k))],
            colour_of(fraction).filled(),
        ))
        .map_err(drawing)?;
    }
    area.draw(&Rectangle::new([(x0, row(BAR_STEPS)), (x1, row(0))], BLACK))
        .map_err(drawing)?;
    let font = (style::FONT, style::TICK_SIZE)
        .into_font()
        .color(&BLACK)
        .pos(Pos::new(HPos::Left, VPos::Center));
    let step = style::nice_step(top / BAR_INTERVALS as f64);
    let mut ticks = Vec::new();
    let count = (top / step * (1.0 + 1e-9)).floor() as usize;
    for k in 0..=count {
        let value = step * k as f64;
        let y = bar.y1 - by - (f64::from(bar.y1 - bar.y0) * value / top).round() as i32;
        area.draw(&PathElement::new(vec![(x1, y), (x1 + 4, y)], BLACK))
            .map_err(drawing)?;
        let label = style::linear_tick(value, step, top);
        area.draw(&Text::new(label.clone(), (x1 + 7, y), font.clone()))
            .map_err(drawing)?;
        ticks.push(Tick { value, label });
    }
    Ok((
        bar,
        AxisLayout {
            label: "von Mises stress".into(),
            ticks,
            range: Some([0.0, top]),
            ..AxisLayout::default()
        },
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn panel(label: &str, scale: f64) -> SpaceTimePanel {
        SpaceTimePanel {
            label: label.into(),
            time: vec![0.0, 0.5, 1.0],
            position: vec![0.25, 0.75],
            values: vec![
                vec![0.0, scale],
                vec![scale, 0.0],
                vec![0.5 * scale, f64::NAN],
            ],
        }
    }

    #[test]
    fn the_panels_share_one_scale_and_one_colour_bar() {
        let svg = space_time_map("t", &[panel("a", 1.0), panel("b", 2.0)]).unwrap();
        // Only the second panel's largest value is yellow (twice: the cell and the map's
        // value in the second panel at two times), and the bar's top step is just short of it.
        let layout = FigureLayout::from_svg(&svg).unwrap().unwrap();
        let bars: Vec<_> = layout
            .charts
            .iter()
            .map(|c| c.colour_bar.is_some())
            .collect();
        assert_eq!(
            bars,
            [false, true],
            "one colour bar, right of the last panel"
        );
        let top = &layout.charts[1].colour_bar.as_ref().unwrap().1.ticks;
        assert_eq!(
            top.last().unwrap().label,
            "2",
            "ticks up to the largest of both panels"
        );
        assert_eq!(layout.charts[0].scale_group, layout.charts[1].scale_group);
        assert_eq!(
            svg.matches("#FDE725").count(),
            2,
            "the largest value, in panel b only"
        );
    }

    #[test]
    fn rejects_ragged_rows_and_empty_input() {
        let mut bad = panel("a", 1.0);
        bad.values[1].pop();
        assert!(matches!(
            space_time_map("t", &[bad]),
            Err(FigureError::LengthMismatch { .. })
        ));
        assert!(matches!(
            space_time_map("t", &[]),
            Err(FigureError::EmptyData { .. })
        ));
        let zero = SpaceTimePanel {
            values: vec![vec![0.0, 0.0]; 3],
            ..panel("z", 1.0)
        };
        assert!(matches!(
            space_time_map("t", &[zero]),
            Err(FigureError::EmptyData { .. })
        ));
    }

    #[test]
    fn colour_map_runs_from_dark_purple_to_yellow() {
        assert_eq!(colour_of(0.0), RGBColor(68, 1, 84));
        assert_eq!(colour_of(1.0), RGBColor(253, 231, 37));
        assert_eq!(colour_of(2.0), colour_of(1.0));
    }
}
