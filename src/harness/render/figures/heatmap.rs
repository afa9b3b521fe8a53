//! Space–time maps: a field sampled on a grid of times × positions drawn as coloured cells (the
//! note's Figures 4–5, the von Mises stress along the bar over time).

use plotters::prelude::*;

use super::chart::{drawing, Area};
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

/// Panels side by side (600 px each, 500 px high), time on the x axis, position on the y axis,
/// each cell coloured by its value on one scale shared by all panels (0 to the largest finite
/// value; the caption of each panel states that maximum). Non-finite values are left white.
///
/// Errors: `EmptyData` without panels or when no value is finite; `LengthMismatch` when a
/// panel has not one row per time or not one value per position.
pub fn space_time_map(title: &str, panels: &[SpaceTimePanel]) -> Result<String, FigureError> {
    if panels.is_empty() {
        return Err(FigureError::EmptyData {
            what: "space-time map: no panel".into(),
        });
    }
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
    }
    let top = panels
        .iter()
        .flat_map(|p| p.values.iter().flatten())
        .copied()
        .filter(|v| v.is_finite())
        .fold(f64::NEG_INFINITY, f64::max);
    if !(top.is_finite() && top > 0.0) {
        return Err(FigureError::EmptyData {
            what: "space-time map: no positive finite value".into(),
        });
    }
    let mut svg = String::new();
    {
        let size = (style::PANEL_WIDTH * panels.len() as u32, style::HEIGHT);
        let root: Area<'_> = SVGBackend::with_string(&mut svg, size).into_drawing_area();
        root.fill(&WHITE).map_err(drawing)?;
        let body = root
            .titled(title, (style::FONT, style::TITLE_SIZE))
            .map_err(drawing)?;
        for (panel, area) in panels.iter().zip(body.split_evenly((1, panels.len()))) {
            draw_panel(panel, &area, top)?;
        }
        root.present().map_err(drawing)?;
    }
    Ok(svg)
}

fn half_step(v: &[f64], k: usize) -> f64 {
    match (v.get(k.wrapping_sub(1)), v.get(k + 1)) {
        (_, Some(next)) => 0.5 * (next - v[k]),
        (Some(prev), None) => 0.5 * (v[k] - prev),
        (None, None) => 0.5,
    }
}

fn draw_panel(panel: &SpaceTimePanel, area: &Area<'_>, top: f64) -> Result<(), FigureError> {
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
    let caption = format!("{} (colour 0 – {top:.3})", panel.label);
    let mut chart = ChartBuilder::on(area)
        .caption(caption, (style::FONT, style::CAPTION_SIZE))
        .margin(10)
        .x_label_area_size(45)
        .y_label_area_size(60)
        .build_cartesian_2d(t0..t1.max(t0 + 1e-12), (x0 - dx)..(x1 + dx))
        .map_err(drawing)?;
    chart
        .configure_mesh()
        .disable_mesh()
        .x_desc("t")
        .y_desc("height above the contact face")
        .axis_desc_style((style::FONT, style::AXIS_DESC_SIZE))
        .label_style((style::FONT, style::TICK_SIZE))
        .x_label_formatter(&|v| style::linear_tick(*v))
        .y_label_formatter(&|v| style::linear_tick(*v))
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
    Ok(())
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
    fn draws_one_cell_per_finite_value_on_a_shared_scale() {
        let svg = space_time_map("t", &[panel("a", 1.0), panel("b", 2.0)]).unwrap();
        assert!(svg.contains("colour 0 – 2.000"));
        let yellow = svg.matches("#FDE725").count();
        assert_eq!(yellow, 2, "the largest value of the second panel, twice");
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
