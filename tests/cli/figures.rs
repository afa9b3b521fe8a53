//! The SVG figures: well-formed, the expected series, legends, empty and non-finite input,
//! determinism.
//!
//! What plotters emits (inspected on its output): every line series is one `<polyline>` with
//! the series' stroke width (2 for runs, 4 for the exact curve); every legend entry adds one
//! two-point, 20 px long horizontal `<polyline>` of the same style; axes and ticks are
//! `<polyline>`s of width 1 and grid lines are `<line>`s; markers are `<circle>`s; the legend
//! box is two `<rect>`s (background, then border); an ensemble's band is one `<polygon>` with
//! the series' fill and an opacity below 1, and its legend swatch a four-point one. The demo
//! figures are written to `target/tmp/figures-demo/`, or to `$FIGURES_DEMO_DIR` when it is set,
//! for a person to look at.

use std::path::{Path, PathBuf};

use signorini::harness::render::figures::{
    contact_node_figure, convergence_figure, energy_figure, time_series_figure,
    work_precision_figure, ContactAxes, ContactPanel, ConvergenceFit, ConvergenceSeries,
    EnergyPanel, ErrorBand, FigureError, WorkPrecisionSeries,
};
use signorini::harness::run::{ContactHistory, EnergyHistory};
use signorini::harness::study::rates::RateFit;
use signorini::harness::study::sensitivity::Spread;

// ---------------------------------------------------------------------------------------------
// Reading the SVG back.

#[derive(Debug, Clone)]
struct Polyline {
    stroke: String,
    width: u32,
    points: Vec<(f64, f64)>,
}

impl Polyline {
    /// A legend symbol: two points, 20 px apart horizontally.
    fn is_legend(&self) -> bool {
        self.points.len() == 2
            && self.points[0].1 == self.points[1].1
            && self.points[1].0 - self.points[0].0 == 20.0
    }
}

/// A filled `<polygon>`: a band (or a band's legend swatch).
#[derive(Debug, Clone)]
struct Shade {
    fill: String,
    opacity: f64,
    points: Vec<(f64, f64)>,
}

struct Svg {
    width: f64,
    height: f64,
    polylines: Vec<Polyline>,
    /// The `<polygon>`s, and how many `<polyline>`s came before each.
    polygons: Vec<(Shade, usize)>,
    circles: usize,
    texts: Vec<String>,
    /// `(x, y, w, h)` of every `<rect>` after the background.
    rects: Vec<(f64, f64, f64, f64)>,
}

impl Svg {
    /// Parses `svg` (panics if it is not well-formed XML).
    fn parse(svg: &str) -> Self {
        let doc = roxmltree::Document::parse(svg).expect("well-formed XML");
        let root = doc.root_element();
        assert_eq!(root.tag_name().name(), "svg");
        let num = |n: roxmltree::Node, a: &str| -> f64 {
            n.attribute(a)
                .unwrap_or_else(|| panic!("{a} missing"))
                .parse()
                .unwrap()
        };
        let points = |n: roxmltree::Node| -> Vec<(f64, f64)> {
            n.attribute("points")
                .unwrap()
                .split_whitespace()
                .map(|p| {
                    let (x, y) = p.split_once(',').unwrap();
                    (x.parse().unwrap(), y.parse().unwrap())
                })
                .collect()
        };
        let mut polylines = Vec::new();
        let mut polygons = Vec::new();
        let mut circles = 0;
        let mut texts = Vec::new();
        let mut rects = Vec::new();
        for n in root.descendants().filter(|n| n.is_element()) {
            match n.tag_name().name() {
                "polyline" => polylines.push(Polyline {
                    stroke: n.attribute("stroke").unwrap().to_owned(),
                    width: n.attribute("stroke-width").unwrap().parse().unwrap(),
                    points: points(n),
                }),
                "polygon" => polygons.push((
                    Shade {
                        fill: n.attribute("fill").unwrap().to_owned(),
                        opacity: num(n, "opacity"),
                        points: points(n),
                    },
                    polylines.len(),
                )),
                "circle" => circles += 1,
                "text" => texts.push(n.text().unwrap_or("").trim().to_owned()),
                "rect" => rects.push((num(n, "x"), num(n, "y"), num(n, "width"), num(n, "height"))),
                _ => {}
            }
        }
        rects.remove(0); // the white background
        Self {
            width: num(root, "width"),
            height: num(root, "height"),
            polylines,
            polygons,
            circles,
            texts,
            rects,
        }
    }

    /// The data lines: wider than the axes and not legend symbols.
    fn data(&self) -> Vec<&Polyline> {
        self.polylines
            .iter()
            .filter(|p| p.width > 1 && !p.is_legend())
            .collect()
    }

    fn legend_symbols(&self) -> Vec<&Polyline> {
        self.polylines
            .iter()
            .filter(|p| p.width > 1 && p.is_legend())
            .collect()
    }

    fn data_of(&self, stroke: &str) -> usize {
        self.data().iter().filter(|p| p.stroke == stroke).count()
    }

    /// The shaded bands (more than the four corners of a legend swatch) with the `<polyline>`s
    /// drawn before each.
    fn bands(&self) -> Vec<&(Shade, usize)> {
        self.polygons
            .iter()
            .filter(|(p, _)| p.points.len() > 4)
            .collect()
    }

    fn has_text(&self, needle: &str) -> bool {
        self.texts.iter().any(|t| t.contains(needle))
    }
}

const EXACT: &str = "#000000";
const FIRST: &str = "#1F77B4";
const SECOND: &str = "#D62728";
const THIRD: &str = "#2CA02C";

// ---------------------------------------------------------------------------------------------
// Synthetic input shaped like the Signorini–Dirichlet benchmark (T = 3, contact on [1, 2]).

fn exact_u(t: f64) -> f64 {
    match t {
        t if t < 1.0 => 0.5 - 0.5 * t,
        t if t < 2.0 => 0.0,
        t => 0.5 * (t - 2.0),
    }
}

fn exact_lambda(t: f64) -> f64 {
    if (1.0..2.0).contains(&t) {
        -0.5
    } else {
        0.0
    }
}

/// A run at `nx` elements (`30 nx` steps to T = 3); `noise` scales the multiplier
/// oscillation (large for the standard mass).
fn contact_history(nx: usize, noise: f64) -> ContactHistory {
    let steps = 30 * nx;
    let time: Vec<f64> = (0..=steps).map(|k| 3.0 * k as f64 / steps as f64).collect();
    let wiggle = |t: f64| (t * 37.0 * nx as f64).sin();
    let displacement = time
        .iter()
        .map(|&t| (exact_u(t) + 0.2 / nx as f64 * (3.0 * t).sin()).max(0.0))
        .collect();
    let multiplier = time
        .iter()
        .map(|&t| {
            let l = exact_lambda(t);
            if l != 0.0 {
                l + noise * wiggle(t)
            } else {
                0.0
            }
        })
        .collect();
    ContactHistory {
        displacement_exact: time.iter().map(|&t| exact_u(t)).collect(),
        multiplier_exact: time.iter().map(|&t| exact_lambda(t)).collect(),
        multiplier_time: time.clone(),
        time,
        displacement,
        multiplier,
    }
}

fn contact_panels() -> Vec<ContactPanel> {
    vec![
        ContactPanel {
            label: "standard mass".into(),
            runs: vec![
                ("NX = 20".into(), contact_history(20, 0.6)),
                ("NX = 40".into(), contact_history(40, 0.8)),
            ],
        },
        ContactPanel {
            label: "redistributed mass".into(),
            runs: vec![
                ("NX = 20".into(), contact_history(20, 0.02)),
                ("NX = 40".into(), contact_history(40, 0.01)),
            ],
        },
    ]
}

fn energy_history(nx: usize, jump: f64) -> EnergyHistory {
    let steps = 30 * nx;
    let time: Vec<f64> = (0..=steps).map(|k| 3.0 * k as f64 / steps as f64).collect();
    EnergyHistory {
        energy: time
            .iter()
            .map(|&t| 0.125 + if t > 1.0 { jump } else { 0.0 } - 0.01 * t / nx as f64)
            .collect(),
        energy_exact: vec![0.125; time.len()],
        time,
    }
}

fn energy_panels() -> Vec<EnergyPanel> {
    vec![
        EnergyPanel {
            label: "standard mass".into(),
            runs: vec![
                ("NX = 20".into(), energy_history(20, 0.25)),
                ("NX = 40".into(), energy_history(40, 0.24)),
            ],
        },
        EnergyPanel {
            label: "redistributed mass".into(),
            runs: vec![
                ("NX = 20".into(), energy_history(20, 0.0)),
                ("NX = 40".into(), energy_history(40, 0.0)),
            ],
        },
    ]
}

fn levels() -> Vec<f64> {
    [10.0, 20.0, 40.0, 80.0, 160.0, 320.0, 640.0]
        .iter()
        .map(|nx| 1.0 / nx)
        .collect()
}

fn fit(rate: f64) -> Option<RateFit> {
    Some(RateFit {
        rate,
        intercept: 0.0,
        ci_low: Some(rate - 0.1),
        ci_high: Some(rate + 0.1),
        levels: 7,
    })
}

fn convergence_series() -> Vec<ConvergenceSeries> {
    let h = levels();
    let power = |c: f64, p: f64| h.iter().map(|x| c * x.powf(p)).collect::<Vec<_>>();
    vec![
        ConvergenceSeries {
            label: "u L∞(H), standard".into(),
            h: h.clone(),
            errors: power(0.3, 0.5),
            fit: fit(0.4951),
            band: None,
        },
        ConvergenceSeries {
            label: "u L∞(H), redistributed".into(),
            h: h.clone(),
            errors: power(0.5, 1.0),
            fit: fit(0.996),
            band: None,
        },
        ConvergenceSeries {
            label: "energy L2, redistributed".into(),
            h: h.clone(),
            errors: power(0.05, 1.0),
            fit: None,
            band: None,
        },
    ]
}

fn work_series() -> Vec<WorkPrecisionSeries> {
    let h = levels();
    vec![
        WorkPrecisionSeries {
            label: "crank-nicolson/standard".into(),
            seconds: h.iter().map(|x| 1e-5 / (x * x)).collect(),
            errors: h.iter().map(|x| 0.3 * x.sqrt()).collect(),
        },
        WorkPrecisionSeries {
            label: "crank-nicolson/redistributed".into(),
            seconds: h.iter().map(|x| 1.2e-5 / (x * x)).collect(),
            errors: h.iter().map(|x| 0.5 * x).collect(),
        },
    ]
}

/// The contact figure's axes in these tests.
const AXES: ContactAxes<'static> = ContactAxes {
    displacement: "u(0, t)",
    multiplier: "λ(t)",
};

/// Work–precision series as the figure takes them: each with its scheme and mass, read from its
/// `scheme/mass` label.
fn grouped(series: &[WorkPrecisionSeries]) -> Vec<(String, String, WorkPrecisionSeries)> {
    series
        .iter()
        .map(|s| {
            let (scheme, mass) = s.label.split_once('/').unwrap_or((&s.label, ""));
            (scheme.to_string(), mass.to_string(), s.clone())
        })
        .collect()
}

fn time_series() -> Vec<(String, Vec<f64>, Vec<f64>)> {
    let t: Vec<f64> = (0..=300).map(|k| k as f64 / 100.0).collect();
    (0..3)
        .map(|i| {
            let y = t.iter().map(|x| 0.125 + 0.01 * i as f64 * x).collect();
            (format!("case {i}"), t.clone(), y)
        })
        .collect()
}

// ---------------------------------------------------------------------------------------------

#[test]
fn contact_figure_has_two_panels_of_two_charts_with_runs_and_exact() {
    let svg = Svg::parse(&contact_node_figure("Crank–Nicolson", AXES, &contact_panels()).unwrap());
    assert_eq!((svg.width, svg.height), (1200.0, 500.0));
    // 2 panels × 2 charts × (2 runs + exact).
    assert_eq!(svg.data().len(), 12);
    assert_eq!(svg.data_of(EXACT), 4);
    assert_eq!(svg.data_of(FIRST), 4);
    assert_eq!(svg.data_of(SECOND), 4);
    // Every run's line keeps all its samples (NX = 40: 1201).
    let longest = svg.data().iter().map(|p| p.points.len()).max().unwrap();
    assert_eq!(longest, 1201);
    // The exact curve is thicker than the runs.
    assert!(svg
        .data()
        .iter()
        .all(|p| (p.stroke == EXACT) == (p.width > 2)));
    // One legend per panel (in the displacement chart): exact + 2 runs.
    assert_eq!(svg.legend_symbols().len(), 6);
    assert!(svg.has_text("standard mass") && svg.has_text("redistributed mass"));
    assert!(svg.has_text("NX = 40") && svg.has_text("exact"));
    assert!(svg.has_text("u(0, t)") && svg.has_text("λ(t)"));
    assert!(svg.has_text("Crank–Nicolson"));
}

#[test]
fn energy_figure_has_one_chart_per_panel() {
    let svg = Svg::parse(&energy_figure("Energy", &energy_panels()).unwrap());
    assert_eq!((svg.width, svg.height), (1200.0, 500.0));
    assert_eq!(svg.data().len(), 6);
    assert_eq!(svg.data_of(EXACT), 2);
    assert_eq!(svg.legend_symbols().len(), 6);
    assert!(svg.has_text("E(t)"));

    let one = energy_figure("Energy", &energy_panels()[..1]).unwrap();
    let one = Svg::parse(&one);
    assert_eq!((one.width, one.height), (800.0, 500.0));
    assert_eq!(one.data().len(), 3);
}

#[test]
fn convergence_legend_shows_the_fitted_slope_to_two_decimals() {
    let series = convergence_series();
    let svg =
        Svg::parse(&convergence_figure("Convergence", &series, &ConvergenceFit::Exact).unwrap());
    assert_eq!((svg.width, svg.height), (800.0, 500.0));
    assert_eq!(svg.data().len(), 3);
    assert_eq!(svg.legend_symbols().len(), 3);
    // One marker per level and one per legend entry.
    assert_eq!(svg.circles, 3 * 7 + 3);
    // The rate with the half-width of its 95 % interval.
    assert!(svg.has_text("u L∞(H), standard (slope 0.50 ± 0.10)"));
    assert!(svg.has_text("u L∞(H), redistributed (slope 1.00 ± 0.10)"));
    let plain = svg
        .texts
        .iter()
        .find(|t| t.starts_with("energy L2"))
        .unwrap();
    assert_eq!(plain, "energy L2, redistributed");
    // The h axis is labelled at every level, not at powers of two.
    assert!(
        ["1/10", "1/20", "1/40", "1/80", "1/160", "1/320", "1/640"]
            .iter()
            .all(|l| svg.has_text(l))
            && !svg.texts.iter().any(|t| t == "1/16"),
        "{:?}",
        svg.texts
    );
}

#[test]
fn convergence_skips_non_positive_and_non_finite_errors() {
    let mut series = convergence_series();
    series[0].errors[2] = 0.0;
    series[0].errors[4] = -1.0;
    series[1].errors[3] = f64::NAN;
    series[1].h[5] = f64::INFINITY;
    let text = convergence_figure("Convergence", &series, &ConvergenceFit::Exact).unwrap();
    assert!(!text.contains("NaN") && !text.contains("inf"));
    let svg = Svg::parse(&text);
    let lens: Vec<usize> = svg.data().iter().map(|p| p.points.len()).collect();
    assert_eq!(lens, vec![5, 5, 7]);
    assert_eq!(svg.circles, 5 + 5 + 7 + 3);
}

/// [`convergence_series`] with a band around the first series: a factor 3 either side of its
/// errors, and the ensemble's rates.
fn banded_series() -> Vec<ConvergenceSeries> {
    let mut series = convergence_series();
    let median = series[0].errors.clone();
    series[0].band = Some(ErrorBand {
        lower: median.iter().map(|e| e / 3.0).collect(),
        upper: median.iter().map(|e| e * 3.0).collect(),
        rate: Some(Spread {
            min: 0.41,
            median: 0.52,
            max: 0.63,
        }),
    });
    series
}

/// `(top, bottom)` pixel rows of the y axis: the longest vertical axis line.
fn y_axis(svg: &Svg) -> (f64, f64) {
    let axis = svg
        .polylines
        .iter()
        .filter(|p| p.width == 1 && p.points.len() == 2 && p.points[0].0 == p.points[1].0)
        .max_by(|a, b| {
            let len = |p: &Polyline| (p.points[1].1 - p.points[0].1).abs();
            len(a).total_cmp(&len(b))
        })
        .unwrap();
    (axis.points[0].1, axis.points[1].1)
}

#[test]
fn a_band_is_shaded_in_its_series_colour_beneath_every_line_and_on_the_axes() {
    let svg = Svg::parse(
        &convergence_figure("Convergence", &banded_series(), &ConvergenceFit::Exact).unwrap(),
    );
    let bands = svg.bands();
    assert_eq!(bands.len(), 1, "{:?}", svg.polygons);
    let (band, lines_before) = bands[0];
    assert_eq!(band.fill, FIRST);
    assert!(band.opacity > 0.0 && band.opacity < 0.5, "{}", band.opacity);
    // The upper edge left to right, then the lower edge back: two vertices per level.
    assert_eq!(band.points.len(), 2 * 7);
    // Beneath every line: drawn before the first data line.
    let first_line = svg
        .polylines
        .iter()
        .position(|p| p.width > 1 && !p.is_legend())
        .unwrap();
    assert!(*lines_before <= first_line);
    // The series runs through the band, halfway between its edges on the log axis.
    let line = svg.data()[0];
    assert_eq!(line.stroke, FIRST);
    for (k, &(x, y)) in line.points.iter().enumerate() {
        let (upper, lower) = (band.points[k], band.points[2 * 7 - 1 - k]);
        assert_eq!((upper.0, lower.0), (x, x));
        assert!(upper.1 < y && y < lower.1, "level {k}: {y} not in the band");
        assert!((y - 0.5 * (upper.1 + lower.1)).abs() <= 1.0, "level {k}");
    }
    // The y axis spans the band, not just the lines.
    let (top, bottom) = y_axis(&svg);
    assert!(band.points.iter().all(|p| p.1 >= top && p.1 <= bottom));
    // The legend: one shaded swatch, and the ensemble's slope with its range instead of the fit.
    let swatches: Vec<&Shade> = svg
        .polygons
        .iter()
        .map(|(p, _)| p)
        .filter(|p| p.points.len() == 4)
        .collect();
    assert_eq!(swatches.len(), 1);
    assert_eq!(swatches[0].fill, FIRST);
    assert!(svg.has_text("u L∞(H), standard (slope 0.52 [0.41, 0.63])"));
    assert!(!svg.has_text("slope 0.50"));
    assert!(svg.has_text("u L∞(H), redistributed (slope 1.00 ± 0.10)"));
}

#[test]
fn series_without_a_band_draw_no_polygon() {
    let svg = Svg::parse(
        &convergence_figure("Convergence", &convergence_series(), &ConvergenceFit::Exact).unwrap(),
    );
    assert!(svg.polygons.is_empty(), "{:?}", svg.polygons);
    let svg = Svg::parse(&work_precision_figure("W", &grouped(&work_series())).unwrap());
    assert!(svg.polygons.is_empty());
}

#[test]
fn band_levels_off_the_log_axis_are_skipped_and_mismatched_bounds_reported() {
    let mut series = banded_series();
    let band = series[0].band.as_mut().unwrap();
    band.lower[2] = 0.0;
    band.upper[4] = f64::NAN;
    // Without the ensemble's rates the legend falls back to the fit.
    band.rate = None;
    let text = convergence_figure("Convergence", &series, &ConvergenceFit::Exact).unwrap();
    assert!(!text.contains("NaN"));
    let svg = Svg::parse(&text);
    assert_eq!(svg.bands()[0].0.points.len(), 2 * 5);
    assert!(svg.has_text("u L∞(H), standard (slope 0.50 ± 0.10)"));

    let mut series = banded_series();
    series[0].band.as_mut().unwrap().upper.pop();
    match convergence_figure("Convergence", &series, &ConvergenceFit::Exact) {
        Err(FigureError::LengthMismatch { what, left, right }) => {
            assert!(
                what.contains("standard") && what.contains("band upper"),
                "{what}"
            );
            assert_eq!((left, right), (7, 6));
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn work_precision_has_one_marked_curve_per_case() {
    let svg =
        Svg::parse(&work_precision_figure("Work–precision", &grouped(&work_series())).unwrap());
    assert_eq!(svg.data().len(), 2);
    assert_eq!(svg.data_of(FIRST), 1);
    assert_eq!(svg.data_of(SECOND), 1);
    assert_eq!(svg.circles, 2 * 7 + 2);
    assert!(svg.has_text("wall time (s)"));
    assert!(svg.has_text("crank-nicolson/redistributed"));
}

#[test]
fn time_series_skips_nan_and_infinite_points() {
    let mut series = time_series();
    series[0].2[10] = f64::NAN;
    series[0].2[11] = f64::INFINITY;
    series[2].1[0] = f64::NEG_INFINITY;
    let text = time_series_figure("Stability", "E_h(t)", &series, &[]).unwrap();
    assert!(!text.contains("NaN") && !text.contains("inf"));
    let svg = Svg::parse(&text);
    assert_eq!(svg.data().len(), 3);
    assert_eq!(svg.data_of(THIRD), 1);
    let lens: Vec<usize> = svg.data().iter().map(|p| p.points.len()).collect();
    assert_eq!(lens, vec![299, 301, 300]);
    assert!(svg.has_text("E_h(t)"));
}

#[test]
fn a_series_with_nothing_finite_is_dropped_and_an_all_nan_chart_is_empty() {
    let mut series = time_series();
    series[1].2.iter_mut().for_each(|y| *y = f64::NAN);
    let svg = Svg::parse(&time_series_figure("S", "y", &series, &[]).unwrap());
    assert_eq!(svg.data().len(), 2);
    assert_eq!(svg.legend_symbols().len(), 2);
    assert_eq!(svg.data_of(SECOND), 0);

    for s in &mut series {
        s.2.iter_mut().for_each(|y| *y = f64::NAN);
    }
    assert!(matches!(
        time_series_figure("S", "y", &series, &[]),
        Err(FigureError::EmptyData { .. })
    ));
    let mut panels = contact_panels();
    for (_, run) in &mut panels[1].runs {
        run.multiplier.iter_mut().for_each(|y| *y = f64::NAN);
        run.multiplier_exact.iter_mut().for_each(|y| *y = f64::NAN);
    }
    match contact_node_figure("C", AXES, &panels) {
        Err(FigureError::EmptyData { what }) => {
            assert!(what.contains("redistributed mass") && what.contains("multiplier"))
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn empty_input_gives_empty_data() {
    let empty = |r: Result<String, FigureError>| matches!(r, Err(FigureError::EmptyData { .. }));
    assert!(empty(contact_node_figure("C", AXES, &[])));
    assert!(empty(contact_node_figure(
        "C",
        AXES,
        &[ContactPanel {
            label: "standard mass".into(),
            runs: vec![]
        }]
    )));
    assert!(empty(contact_node_figure(
        "C",
        AXES,
        &[ContactPanel {
            label: "standard mass".into(),
            runs: vec![("NX = 10".into(), ContactHistory::default())]
        }]
    )));
    assert!(empty(energy_figure("E", &[])));
    assert!(empty(energy_figure(
        "E",
        &[EnergyPanel {
            label: "standard mass".into(),
            runs: vec![("NX = 10".into(), EnergyHistory::default())]
        }]
    )));
    assert!(empty(convergence_figure("C", &[], &ConvergenceFit::Exact)));
    assert!(empty(convergence_figure(
        "C",
        &[ConvergenceSeries {
            label: "zero".into(),
            h: vec![0.1, 0.05],
            errors: vec![0.0, 0.0],
            fit: None,
            band: None,
        }],
        &ConvergenceFit::Exact
    )));
    assert!(empty(work_precision_figure("W", &grouped(&[]))));
    assert!(empty(time_series_figure("T", "y", &[], &[])));
    let err = convergence_figure("C", &[], &ConvergenceFit::Exact).unwrap_err();
    assert!(err.to_string().contains("nothing to plot"), "{err}");
}

#[test]
fn mismatched_lengths_are_reported() {
    let mut series = convergence_series();
    series[1].errors.pop();
    match convergence_figure("C", &series, &ConvergenceFit::Exact) {
        Err(FigureError::LengthMismatch { what, left, right }) => {
            assert!(what.contains("redistributed"));
            assert_eq!((left, right), (7, 6));
        }
        other => panic!("{other:?}"),
    }
    let mut panels = contact_panels();
    panels[0].runs[1].1.multiplier.pop();
    assert!(matches!(
        contact_node_figure("C", AXES, &panels),
        Err(FigureError::LengthMismatch { .. })
    ));
}

#[test]
fn identical_input_gives_identical_bytes() {
    let a = contact_node_figure("C", AXES, &contact_panels()).unwrap();
    let b = contact_node_figure("C", AXES, &contact_panels()).unwrap();
    assert_eq!(a, b);
    let a = convergence_figure("C", &convergence_series(), &ConvergenceFit::Exact).unwrap();
    let b = convergence_figure("C", &convergence_series(), &ConvergenceFit::Exact).unwrap();
    assert_eq!(a, b);
    let a = energy_figure("E", &energy_panels()).unwrap();
    assert_eq!(a, energy_figure("E", &energy_panels()).unwrap());
    let a = work_precision_figure("W", &grouped(&work_series())).unwrap();
    assert_eq!(
        a,
        work_precision_figure("W", &grouped(&work_series())).unwrap()
    );
    let a = time_series_figure("T", "y", &time_series(), &[]).unwrap();
    assert_eq!(
        a,
        time_series_figure("T", "y", &time_series(), &[]).unwrap()
    );
    // And a different input does change the output.
    let mut other = convergence_series();
    other[0].errors[0] *= 2.0;
    assert_ne!(
        convergence_figure("C", &other, &ConvergenceFit::Exact).unwrap(),
        b
    );
}

#[test]
fn constant_series_get_a_padded_axis() {
    // Exact energy constant and every run equal to it: a zero-height range on y.
    let t: Vec<f64> = (0..=30).map(|k| k as f64 / 10.0).collect();
    let flat = EnergyHistory {
        time: t.clone(),
        energy: vec![0.125; t.len()],
        energy_exact: vec![0.125; t.len()],
    };
    let panel = EnergyPanel {
        label: "flat".into(),
        runs: vec![("NX = 10".into(), flat)],
    };
    let svg = Svg::parse(&energy_figure("E", &[panel]).unwrap());
    assert_eq!(svg.data().len(), 2);
    let (top, bottom) = y_axis(&svg);
    for line in svg.data() {
        let y = line.points[0].1;
        assert!(line.points.iter().all(|p| p.1 == y));
        assert!(
            y > top + 20.0 && y < bottom - 20.0,
            "{y} in {top}..{bottom}"
        );
    }
    // A single point on log axes works too.
    let single = ConvergenceSeries {
        label: "one level".into(),
        h: vec![0.1],
        errors: vec![0.01],
        fit: None,
        band: None,
    };
    let svg = Svg::parse(&convergence_figure("C", &[single], &ConvergenceFit::Exact).unwrap());
    assert_eq!(svg.circles, 2);
}

#[test]
fn the_legend_is_inside_the_figure_and_covers_no_data_vertex() {
    for text in [
        convergence_figure("C", &convergence_series(), &ConvergenceFit::Exact).unwrap(),
        work_precision_figure("W", &grouped(&work_series())).unwrap(),
        time_series_figure("T", "y", &time_series(), &[]).unwrap(),
    ] {
        let svg = Svg::parse(&text);
        // Background and border of the one legend box.
        assert_eq!(svg.rects.len(), 2);
        let (x, y, w, h) = svg.rects[1];
        assert!(x > 0.0 && y > 0.0 && x + w < svg.width && y + h < svg.height);
        for line in svg.data() {
            for &(px, py) in &line.points {
                assert!(
                    !(px >= x && px <= x + w && py >= y && py <= y + h),
                    "({px}, {py}) under the legend {:?}",
                    svg.rects[1]
                );
            }
        }
    }
}

/// Writes every demo figure to `$FIGURES_DEMO_DIR`, or without it to `target/tmp/figures-demo/`
/// (to look at them), reads each file back and checks that it is the whole figure, well-formed
/// SVG, with its title, one line per series (and the exact curve where there is one) and the
/// band where one is given.
#[test]
fn demo_figures_are_written_whole_and_well_formed() {
    let dir = std::env::var_os("FIGURES_DEMO_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| Path::new(env!("CARGO_TARGET_TMPDIR")).join("figures-demo"));
    std::fs::create_dir_all(&dir).unwrap();
    let narrow = ConvergenceSeries {
        label: "under two decades".into(),
        h: vec![0.1, 0.05, 0.025],
        errors: vec![0.8, 0.04, 0.02],
        fit: fit(1.0),
        band: None,
    };
    // (file, title, figure, data lines, bands)
    let contact = "Crank–Nicolson, contact node";
    let energy = "Crank–Nicolson, energy";
    let figures = [
        (
            "contact.svg",
            contact,
            contact_node_figure(contact, AXES, &contact_panels()),
            // 2 panels × 2 charts × (2 runs + exact)
            12,
            0,
        ),
        (
            "energy.svg",
            energy,
            energy_figure(energy, &energy_panels()),
            // 2 panels × (2 runs + exact)
            6,
            0,
        ),
        (
            "convergence.svg",
            "Convergence",
            convergence_figure("Convergence", &convergence_series(), &ConvergenceFit::Exact),
            3,
            0,
        ),
        (
            "convergence-band.svg",
            "Convergence with a band",
            convergence_figure(
                "Convergence with a band",
                &banded_series(),
                &ConvergenceFit::Exact,
            ),
            3,
            1,
        ),
        (
            "work.svg",
            "Work–precision",
            work_precision_figure("Work–precision", &grouped(&work_series())),
            2,
            0,
        ),
        (
            "narrow.svg",
            "Under two decades",
            convergence_figure("Under two decades", &[narrow], &ConvergenceFit::Exact),
            1,
            0,
        ),
        (
            "series.svg",
            "Energy histories",
            time_series_figure("Energy histories", "E_h(t)", &time_series(), &[]),
            3,
            0,
        ),
    ];
    for (name, title, figure, lines, bands) in figures {
        let figure = figure.unwrap_or_else(|e| panic!("{name}: {e}"));
        let path = dir.join(name);
        std::fs::write(&path, &figure).unwrap();
        let written = std::fs::read_to_string(&path).unwrap();
        assert_eq!(
            written,
            figure,
            "{} is not the whole figure",
            path.display()
        );
        let svg = Svg::parse(&written);
        assert!(svg.has_text(title), "{name}: no title {title:?}");
        assert_eq!(svg.data().len(), lines, "{name}: data lines");
        assert_eq!(svg.bands().len(), bands, "{name}: bands");
    }
}
