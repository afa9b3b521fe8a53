//! The SVG figures: well-formed, the expected series in their styles, legends, bands, empty and
//! non-finite input, determinism.
//!
//! The tests read the [`FigureLayout`] each figure embeds (its charts, plotting areas, legend
//! boxes, series with their kind, colour, dash, marker and extent, axis ranges and ticks) and
//! check the drawn SVG against it. What the drawing emits (inspected on its output): a solid
//! curve is one `<polyline>` through all its points, a broken one (dashed, dotted) one short
//! `<polyline>` per dash; computed curves, exact curves and fitted slopes have stroke width 2,
//! axes 1, grid lines are `<line>`s; a circle marker is a `<circle>`, a square, triangle or
//! diamond marker an opaque `<polygon>` of at most four corners; an ensemble's band is a
//! translucent `<polygon>` of two vertices per level and its legend swatch a translucent
//! four-corner one; a legend is a translucent white `<rect>` and its border, followed by its
//! symbols and labels. The demo figures are written to `target/tmp/figures-demo/`, or to
//! `$FIGURES_DEMO_DIR` when it is set, for a person to look at.
//!
//! What `figure_geometry.rs` checks on every committed figure (text inside the canvas, legend
//! labels inside their box, colour-blind-safe and distinct styles, a fitted slope per series,
//! shared scales, a tick at every level) is not repeated here.

use std::path::{Path, PathBuf};

use plotters::style::RGBColor;
use signorini::harness::render::figures::layout::{FigureLayout, Rect, SeriesKind};
use signorini::harness::render::figures::style::{EXACT, PALETTE};
use signorini::harness::render::figures::{
    contact_node_figure, convergence_figure, energy_figure, line_figure, time_series_figure,
    work_precision_figure, Colouring, ContactAxes, ContactPanel, ConvergenceFit, ConvergenceSeries,
    EnergyPanel, ErrorBand, FigureError, WorkPrecisionSeries,
};
use signorini::harness::run::{ContactHistory, EnergyHistory};
use signorini::harness::study::rates::RateFit;
use signorini::harness::study::sensitivity::Spread;

// ---------------------------------------------------------------------------------------------
// Reading the SVG back.

/// A `<polyline>`: a solid curve, one dash of a broken curve, an axis or a legend symbol.
#[derive(Debug, Clone)]
struct Polyline {
    stroke: String,
    width: u32,
    points: Vec<(f64, f64)>,
    /// Its position among the SVG's elements.
    order: usize,
}

/// A filled `<polygon>`: a band or its legend swatch (translucent), or a marker (opaque).
#[derive(Debug, Clone)]
struct Shade {
    fill: String,
    opacity: f64,
    points: Vec<(f64, f64)>,
    order: usize,
}

/// A marker: a `<circle>`, or an opaque `<polygon>` of at most four corners, by its centre.
#[derive(Debug, Clone)]
struct Marker {
    fill: String,
    centre: (f64, f64),
}

/// One series of a chart's layout: `(label, kind, colour, dash, marker)`.
type Entry = (String, SeriesKind, [u8; 3], String, Option<String>);

/// A figure as drawn: its embedded layout and the SVG elements the tests look at.
struct Svg {
    layout: FigureLayout,
    polylines: Vec<Polyline>,
    polygons: Vec<Shade>,
    markers: Vec<Marker>,
    texts: Vec<String>,
    /// `(rect, order)` of every filled `<rect>` after the background (the legends' boxes).
    boxes: Vec<(Rect, usize)>,
}

/// The SVG spelling of a colour, `#RRGGBB`.
fn hex(c: RGBColor) -> String {
    format!("#{:02X}{:02X}{:02X}", c.0, c.1, c.2)
}

/// The `[r, g, b]` of a colour, as the layout records it.
fn rgb(c: RGBColor) -> [u8; 3] {
    [c.0, c.1, c.2]
}

/// Whether `p` lies in `r` (edges included).
fn within(r: &Rect, p: (f64, f64)) -> bool {
    p.0 >= f64::from(r.x0)
        && p.0 <= f64::from(r.x1)
        && p.1 >= f64::from(r.y0)
        && p.1 <= f64::from(r.y1)
}

/// Whether the segment `a`–`b` meets the inside of `r` shrunk by one pixel.
fn segment_meets(a: (f64, f64), b: (f64, f64), r: &Rect) -> bool {
    let inner = (
        f64::from(r.x0) + 1.0,
        f64::from(r.y0) + 1.0,
        f64::from(r.x1) - 1.0,
        f64::from(r.y1) - 1.0,
    );
    crate::figure_geometry::segment_meets(a, b, inner)
}

impl Svg {
    /// Parses `svg` (panics if it is not well-formed XML, has no layout or one that does not
    /// parse, or holds a non-finite number).
    fn parse(svg: &str) -> Self {
        assert!(
            !svg.contains("NaN") && !svg.contains("inf"),
            "a non-finite number in the figure"
        );
        let layout = FigureLayout::from_svg(svg)
            .expect("an embedded layout")
            .expect("a layout that parses");
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
        assert_eq!(
            (num(root, "width"), num(root, "height")),
            (f64::from(layout.width), f64::from(layout.height)),
            "the canvas is the layout's"
        );
        let mut out = Self {
            layout,
            polylines: Vec::new(),
            polygons: Vec::new(),
            markers: Vec::new(),
            texts: Vec::new(),
            boxes: Vec::new(),
        };
        for (order, n) in root.descendants().filter(|n| n.is_element()).enumerate() {
            match n.tag_name().name() {
                "polyline" => out.polylines.push(Polyline {
                    stroke: n.attribute("stroke").unwrap().to_owned(),
                    width: n.attribute("stroke-width").unwrap().parse().unwrap(),
                    points: points(n),
                    order,
                }),
                "polygon" => {
                    let shade = Shade {
                        fill: n.attribute("fill").unwrap().to_owned(),
                        opacity: num(n, "opacity"),
                        points: points(n),
                        order,
                    };
                    if shade.opacity == 1.0 && shade.points.len() <= 4 {
                        let k = shade.points.len() as f64;
                        let (sx, sy) = shade
                            .points
                            .iter()
                            .fold((0.0, 0.0), |(a, b), p| (a + p.0, b + p.1));
                        out.markers.push(Marker {
                            fill: shade.fill.clone(),
                            centre: (sx / k, sy / k),
                        });
                    }
                    out.polygons.push(shade);
                }
                "circle" => out.markers.push(Marker {
                    fill: n.attribute("fill").unwrap().to_owned(),
                    centre: (num(n, "cx"), num(n, "cy")),
                }),
                "text" => out.texts.push(n.text().unwrap_or("").trim().to_owned()),
                "rect" if n.attribute("fill") != Some("none") => {
                    let (x, y) = (num(n, "x") as i32, num(n, "y") as i32);
                    let rect = Rect {
                        x0: x,
                        y0: y,
                        x1: x + num(n, "width") as i32,
                        y1: y + num(n, "height") as i32,
                    };
                    out.boxes.push((rect, order));
                }
                _ => {}
            }
        }
        out.boxes.remove(0); // the white background
        out
    }

    /// The legend boxes of the layout.
    fn legends(&self) -> Vec<Rect> {
        self.layout.charts.iter().filter_map(|c| c.legend).collect()
    }

    /// Whether `p` lies in a legend box.
    fn in_legend(&self, p: (f64, f64)) -> bool {
        self.legends().iter().any(|r| within(r, p))
    }

    /// The strokes of curves (width 2) in `colour` that are not legend symbols: a solid curve's
    /// one polyline, a broken curve's dashes.
    fn strokes(&self, colour: RGBColor) -> Vec<&Polyline> {
        self.polylines
            .iter()
            .filter(|p| p.width == 2 && p.stroke == hex(colour))
            .filter(|p| !p.points.iter().all(|&q| self.in_legend(q)))
            .collect()
    }

    /// The number of points of each stroke in `colour` (in drawing order).
    fn stroke_lengths(&self, colour: RGBColor) -> Vec<usize> {
        self.strokes(colour)
            .iter()
            .map(|p| p.points.len())
            .collect()
    }

    /// The markers in `colour`: `(on the chart, in a legend)`.
    fn markers_of(&self, colour: RGBColor) -> (usize, usize) {
        let (legend, chart): (Vec<&Marker>, Vec<&Marker>) = self
            .markers
            .iter()
            .filter(|m| m.fill == hex(colour))
            .partition(|m| self.in_legend(m.centre));
        (chart.len(), legend.len())
    }

    /// The translucent polygons with more than four corners: the shaded bands.
    fn bands(&self) -> Vec<&Shade> {
        self.polygons
            .iter()
            .filter(|p| p.opacity < 1.0 && p.points.len() > 4)
            .collect()
    }

    /// The translucent four-corner polygons: the bands' legend swatches.
    fn swatches(&self) -> Vec<&Shade> {
        self.polygons
            .iter()
            .filter(|p| p.opacity < 1.0 && p.points.len() == 4)
            .collect()
    }

    /// Whether some text element is exactly `text`.
    fn has_text(&self, text: &str) -> bool {
        self.texts.iter().any(|t| t == text)
    }

    /// `(label, kind, colour, dash, marker)` of every series of chart `k`, in legend order.
    fn series(&self, k: usize) -> Vec<Entry> {
        self.layout.charts[k]
            .series
            .iter()
            .map(|s| {
                (
                    s.label.clone(),
                    s.kind,
                    s.colour,
                    s.dash.clone(),
                    s.marker.clone(),
                )
            })
            .collect()
    }

    /// The series of the whole figure drawn as curves (computed, exact or fit), and how many of
    /// them have a band.
    fn curves_and_bands(&self) -> (usize, usize) {
        let all = self.layout.charts.iter().flat_map(|c| &c.series);
        let curves = all.clone().filter(|s| s.kind != SeriesKind::Note).count();
        (curves, all.filter(|s| s.band.is_some()).count())
    }
}

/// `(label, kind, colour, dash, marker)` as [`Svg::series`] gives it.
fn entry(
    label: &str,
    kind: SeriesKind,
    colour: RGBColor,
    dash: &str,
    marker: Option<&str>,
) -> Entry {
    (
        label.to_owned(),
        kind,
        rgb(colour),
        dash.to_owned(),
        marker.map(str::to_owned),
    )
}

const FIRST: RGBColor = PALETTE[0];
const SECOND: RGBColor = PALETTE[1];
const THIRD: RGBColor = PALETTE[2];

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
    let layout = &svg.layout;
    // Two panels of 600 px, the legend panel beneath each adding to the 500 px.
    assert_eq!(layout.width, 1200);
    assert!(layout.height > 500, "{}", layout.height);
    // Per panel: displacement on top (caption, no legend), multiplier below (legend beneath).
    assert_eq!(layout.charts.len(), 4);
    for (k, c) in layout.charts.iter().enumerate() {
        assert!(layout.canvas().contains(&c.plot), "chart {k}");
        let top = k % 2 == 0;
        assert_eq!(c.y.label, if top { "u(0, t)" } else { "λ(t)" });
        assert_eq!(c.legend.is_some(), !top, "chart {k}");
        if let Some(legend) = c.legend {
            assert!(layout.canvas().contains(&legend) && legend.y0 >= c.plot.y1);
        }
        // Two runs and the exact curve, each run in the style of its position in the panel.
        assert_eq!(
            svg.series(k),
            vec![
                entry("NX = 20", SeriesKind::Data, FIRST, "solid", Some("circle")),
                entry(
                    "NX = 40",
                    SeriesKind::Data,
                    SECOND,
                    "dashed",
                    Some("square")
                ),
                entry("exact", SeriesKind::Exact, EXACT, "dashed", None),
            ],
            "chart {k}"
        );
        // The exact curve is drawn over the runs.
        let inside = |p: &&Polyline| p.points.iter().all(|&q| within(&c.plot, q));
        let last_run = [FIRST, SECOND]
            .iter()
            .flat_map(|&colour| svg.strokes(colour))
            .filter(inside)
            .map(|p| p.order)
            .max()
            .unwrap();
        let first_exact = svg
            .strokes(EXACT)
            .into_iter()
            .filter(inside)
            .map(|p| p.order)
            .min()
            .unwrap();
        assert!(last_run < first_exact, "chart {k}");
    }
    assert_eq!(
        layout.charts[0].caption.as_ref().unwrap().text,
        "standard mass"
    );
    assert_eq!(
        layout.charts[2].caption.as_ref().unwrap().text,
        "redistributed mass"
    );
    // The solid run (NX = 20) keeps all its 601 samples in each chart, in one line.
    assert_eq!(svg.stroke_lengths(FIRST), vec![601; 4]);
    assert!(svg.has_text("standard mass") && svg.has_text("redistributed mass"));
    assert!(svg.has_text("NX = 40") && svg.has_text("exact"));
    assert!(svg.has_text("u(0, t)") && svg.has_text("λ(t)"));
    assert!(svg.has_text("Crank–Nicolson"));
}

#[test]
fn energy_figure_has_one_chart_per_panel() {
    let svg = Svg::parse(&energy_figure("Energy", &energy_panels()).unwrap());
    assert_eq!(svg.layout.width, 1200);
    assert_eq!(svg.layout.charts.len(), 2);
    for k in 0..2 {
        assert_eq!(
            svg.series(k),
            vec![
                entry("NX = 20", SeriesKind::Data, FIRST, "solid", Some("circle")),
                entry(
                    "NX = 40",
                    SeriesKind::Data,
                    SECOND,
                    "dashed",
                    Some("square")
                ),
                entry("exact", SeriesKind::Exact, EXACT, "dashed", None),
            ]
        );
        assert!(svg.layout.charts[k].legend.is_some());
    }
    assert_eq!(svg.stroke_lengths(FIRST), vec![601; 2]);
    assert!(svg.has_text("E(t)"));

    let one = Svg::parse(&energy_figure("Energy", &energy_panels()[..1]).unwrap());
    assert_eq!(one.layout.width, 800);
    assert_eq!(one.layout.charts.len(), 1);
    assert_eq!(one.series(0).len(), 3);
    assert_eq!(one.stroke_lengths(FIRST), vec![601]);
}

#[test]
fn convergence_draws_each_fit_with_its_slope_and_interval() {
    let series = convergence_series();
    let svg =
        Svg::parse(&convergence_figure("Convergence", &series, &ConvergenceFit::Exact).unwrap());
    assert_eq!(svg.layout.width, 800);
    assert_eq!(svg.layout.charts.len(), 1);
    // Each series with a marker at every level, followed by its fitted slope (broken, in its
    // colour) with the rate and its 95 % interval to two decimals; the third has no fit.
    assert_eq!(
        svg.series(0),
        vec![
            entry(
                "u L∞(H), standard",
                SeriesKind::Data,
                FIRST,
                "solid",
                Some("circle")
            ),
            entry(
                "fit: slope 0.50, 95 % CI [0.40, 0.60]",
                SeriesKind::Fit,
                FIRST,
                "dashed",
                None
            ),
            entry(
                "u L∞(H), redistributed",
                SeriesKind::Data,
                SECOND,
                "solid",
                Some("square")
            ),
            entry(
                "fit: slope 1.00, 95 % CI [0.90, 1.10]",
                SeriesKind::Fit,
                SECOND,
                "dotted",
                None
            ),
            entry(
                "energy L2, redistributed",
                SeriesKind::Data,
                THIRD,
                "solid",
                Some("triangle-up")
            ),
        ]
    );
    for label in svg.series(0).iter().map(|s| &s.0) {
        assert!(svg.has_text(label), "{label}");
    }
    // One marker per level and one per legend entry; each series one line through its levels,
    // and the fits drawn as dashes besides.
    for colour in [FIRST, SECOND, THIRD] {
        assert_eq!(svg.markers_of(colour), (7, 1));
        assert_eq!(svg.stroke_lengths(colour).iter().max(), Some(&7));
    }
    assert!(svg.strokes(FIRST).len() > 2 && svg.strokes(SECOND).len() > 2);
    assert_eq!(svg.strokes(THIRD).len(), 1);
    // The h axis is labelled at every level, not at powers of two.
    let x = &svg.layout.charts[0].x;
    let labels: Vec<&str> = x.ticks.iter().map(|t| t.label.as_str()).collect();
    assert_eq!(
        labels,
        ["1/640", "1/320", "1/160", "1/80", "1/40", "1/20", "1/10"],
        "{:?}",
        svg.texts
    );
    assert!(labels.iter().all(|l| svg.has_text(l)) && !svg.has_text("1/16"));
}

#[test]
fn convergence_skips_non_positive_and_non_finite_errors() {
    let mut series = convergence_series();
    series[0].errors[2] = 0.0;
    series[0].errors[4] = -1.0;
    series[1].errors[3] = f64::NAN;
    series[1].h[5] = f64::INFINITY;
    let svg =
        Svg::parse(&convergence_figure("Convergence", &series, &ConvergenceFit::Exact).unwrap());
    for (colour, levels) in [(FIRST, 5), (SECOND, 5), (THIRD, 7)] {
        assert_eq!(svg.markers_of(colour), (levels, 1));
        assert_eq!(svg.stroke_lengths(colour).iter().max(), Some(&levels));
    }
    // The extents recorded are those of the drawable levels.
    let extent = svg.layout.charts[0].series[0].extent.unwrap();
    let kept: Vec<f64> = [0, 1, 3, 5, 6]
        .iter()
        .map(|&k| series[0].errors[k])
        .collect();
    assert_eq!(extent, [kept[4], kept[0]]);
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

#[test]
fn a_band_is_shaded_in_its_series_colour_beneath_every_line_and_on_the_axes() {
    let svg = Svg::parse(
        &convergence_figure("Convergence", &banded_series(), &ConvergenceFit::Exact).unwrap(),
    );
    let bands = svg.bands();
    assert_eq!(bands.len(), 1, "{:?}", svg.polygons);
    let band = bands[0];
    assert_eq!(band.fill, hex(FIRST));
    assert!(band.opacity > 0.0 && band.opacity < 0.5, "{}", band.opacity);
    // The upper edge left to right, then the lower edge back: two vertices per level.
    assert_eq!(band.points.len(), 2 * 7);
    // Beneath every line: drawn before the first curve.
    let first_line = svg
        .polylines
        .iter()
        .filter(|p| p.width == 2)
        .map(|p| p.order)
        .min()
        .unwrap();
    assert!(band.order < first_line);
    // The series runs through the band, halfway between its edges on the log axis.
    let line = svg
        .strokes(FIRST)
        .into_iter()
        .find(|p| p.points.len() == 7)
        .expect("the banded series' line");
    for (k, &(x, y)) in line.points.iter().enumerate() {
        let (upper, lower) = (band.points[k], band.points[2 * 7 - 1 - k]);
        assert_eq!((upper.0, lower.0), (x, x));
        assert!(upper.1 < y && y < lower.1, "level {k}: {y} not in the band");
        assert!((y - 0.5 * (upper.1 + lower.1)).abs() <= 1.0, "level {k}");
    }
    // The y axis spans the band, not just the lines.
    let chart = &svg.layout.charts[0];
    assert!(band.points.iter().all(|&p| within(&chart.plot, p)));
    // The legend: one shaded swatch in the series' colour, the band named with the ensemble's
    // slopes; an ensemble gets no fitted slope, the other series keep theirs.
    let swatches = svg.swatches();
    assert_eq!(swatches.len(), 1);
    assert_eq!(swatches[0].fill, hex(FIRST));
    assert!(swatches[0].points.iter().all(|&p| svg.in_legend(p)));
    let banded =
        "u L∞(H), standard, round-off min–max shaded; their slopes 0.41 to 0.63 (median 0.52)";
    assert!(svg.has_text(banded));
    assert_eq!(chart.series[0].label, banded);
    assert_eq!(chart.series[0].band.as_deref(), Some("round-off min–max"));
    assert_eq!(chart.series[1].kind, SeriesKind::Data);
    assert!(!svg.texts.iter().any(|t| t.contains("slope 0.50")));
    assert!(svg.has_text("fit: slope 1.00, 95 % CI [0.90, 1.10]"));
}

#[test]
fn series_without_a_band_draw_no_shaded_polygon() {
    for text in [
        convergence_figure("Convergence", &convergence_series(), &ConvergenceFit::Exact).unwrap(),
        work_precision_figure("W", &grouped(&work_series())).unwrap(),
    ] {
        let svg = Svg::parse(&text);
        assert!(
            svg.polygons.iter().all(|p| p.opacity == 1.0),
            "{:?}",
            svg.polygons
        );
        assert_eq!(svg.curves_and_bands().1, 0);
    }
}

#[test]
fn band_levels_off_the_log_axis_are_skipped_and_mismatched_bounds_reported() {
    let mut series = banded_series();
    let band = series[0].band.as_mut().unwrap();
    band.lower[2] = 0.0;
    band.upper[4] = f64::NAN;
    // Without the ensemble's rates the legend names the band alone.
    band.rate = None;
    let svg =
        Svg::parse(&convergence_figure("Convergence", &series, &ConvergenceFit::Exact).unwrap());
    assert_eq!(svg.bands()[0].points.len(), 2 * 5);
    assert!(svg.has_text("u L∞(H), standard, round-off min–max shaded"));
    // The line keeps all its levels.
    assert_eq!(svg.markers_of(FIRST), (7, 1));

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
    // One scheme: one colour and marker; its two masses told apart by dash.
    assert_eq!(
        svg.series(0),
        vec![
            entry(
                "crank-nicolson/standard",
                SeriesKind::Data,
                FIRST,
                "solid",
                Some("circle")
            ),
            entry(
                "crank-nicolson/redistributed",
                SeriesKind::Data,
                FIRST,
                "dashed",
                Some("circle")
            ),
        ]
    );
    assert_eq!(svg.markers_of(FIRST), (2 * 7, 2));
    assert_eq!(svg.stroke_lengths(FIRST).iter().max(), Some(&7));
    // The legend stands right of the chart.
    let chart = &svg.layout.charts[0];
    assert!(chart.legend.unwrap().x0 >= chart.plot.x1);
    assert!(svg.has_text("wall time (s)"));
    assert!(svg.has_text("crank-nicolson/redistributed"));
}

#[test]
fn time_series_skips_nan_and_infinite_points() {
    let mut series = time_series();
    series[0].2[10] = f64::NAN;
    series[0].2[11] = f64::INFINITY;
    series[2].1[0] = f64::NEG_INFINITY;
    let svg = Svg::parse(&time_series_figure("Stability", "E_h(t)", &series, &[]).unwrap());
    let chart = &svg.layout.charts[0];
    let labels: Vec<&str> = chart.series.iter().map(|s| s.label.as_str()).collect();
    assert_eq!(labels, ["case 0", "case 1", "case 2"]);
    // The first (solid) curve is one line through its 299 finite points.
    assert_eq!(svg.stroke_lengths(FIRST), vec![299]);
    // The extents are those of the finite points: the third lost its first (0.125 at t = 0).
    let extents: Vec<[f64; 2]> = chart.series.iter().map(|s| s.extent.unwrap()).collect();
    assert_eq!(extents[0], [0.125, 0.125]);
    assert_eq!(extents[1], [0.125, 0.125 + 0.01 * 3.0]);
    assert_eq!(extents[2], [series[2].2[1], series[2].2[300]]);
    assert_eq!(chart.x.range, Some([0.0, 3.0]));
    assert!(!svg.strokes(THIRD).is_empty());
    assert!(svg.has_text("E_h(t)"));
}

#[test]
fn a_series_with_nothing_finite_is_dropped_and_an_all_nan_chart_is_empty() {
    let mut series = time_series();
    series[1].2.iter_mut().for_each(|y| *y = f64::NAN);
    let svg = Svg::parse(&time_series_figure("S", "y", &series, &[]).unwrap());
    let labels: Vec<String> = svg.series(0).into_iter().map(|s| s.0).collect();
    assert_eq!(labels, ["case 0", "case 2"]);
    assert!(!svg.has_text("case 1"));
    // Nothing in the dropped series' colour, neither curve nor marker nor legend symbol.
    assert!(!svg.polylines.iter().any(|p| p.stroke == hex(SECOND)));
    assert!(!svg.markers.iter().any(|m| m.fill == hex(SECOND)));
    assert!(!svg.strokes(FIRST).is_empty() && !svg.strokes(THIRD).is_empty());

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
    let chart = &svg.layout.charts[0];
    let [lo, hi] = chart.y.range.unwrap();
    assert!(lo < 0.125 && 0.125 < hi && hi - lo >= 0.01, "{lo}..{hi}");
    // The run (one solid line) and the exact curve (dashes) lie flat, well inside the chart.
    assert_eq!(svg.stroke_lengths(FIRST), vec![31]);
    assert!(!svg.strokes(EXACT).is_empty());
    let (top, bottom) = (f64::from(chart.plot.y0), f64::from(chart.plot.y1));
    let y = svg.strokes(FIRST)[0].points[0].1;
    for line in svg.strokes(FIRST).into_iter().chain(svg.strokes(EXACT)) {
        assert!(line.points.iter().all(|p| p.1 == y), "{:?}", line.points);
    }
    assert!(
        y > top + 20.0 && y < bottom - 20.0,
        "{y} in {top}..{bottom}"
    );
    // A single point on log axes works too: its marker inside the chart, padded axes round it.
    let single = ConvergenceSeries {
        label: "one level".into(),
        h: vec![0.1],
        errors: vec![0.01],
        fit: None,
        band: None,
    };
    let svg = Svg::parse(&convergence_figure("C", &[single], &ConvergenceFit::Exact).unwrap());
    assert_eq!(svg.markers_of(FIRST), (1, 1));
    let chart = &svg.layout.charts[0];
    let ([x0, x1], [y0, y1]) = (chart.x.range.unwrap(), chart.y.range.unwrap());
    assert!(x0 < 0.1 && 0.1 < x1 && y0 < 0.01 && 0.01 < y1);
    let marker = svg
        .markers
        .iter()
        .find(|m| !svg.in_legend(m.centre))
        .unwrap();
    let plot = chart.plot;
    assert!(
        marker.centre.0 > f64::from(plot.x0) + 20.0
            && marker.centre.0 < f64::from(plot.x1) - 20.0
            && marker.centre.1 > f64::from(plot.y0) + 20.0
            && marker.centre.1 < f64::from(plot.y1) - 20.0,
        "{:?} in {plot:?}",
        marker.centre
    );
}

#[test]
fn the_legend_is_inside_the_figure_and_covers_no_data() {
    for text in [
        convergence_figure("C", &convergence_series(), &ConvergenceFit::Exact).unwrap(),
        work_precision_figure("W", &grouped(&work_series())).unwrap(),
        time_series_figure("T", "y", &time_series(), &[]).unwrap(),
        // The legend inside the chart, where it covers no data.
        line_figure("L", ("t", "y"), &time_series(), Colouring::OnePerSeries).unwrap(),
    ] {
        let svg = Svg::parse(&text);
        let chart = &svg.layout.charts[0];
        let legend = chart.legend.unwrap();
        assert!(svg.layout.canvas().contains(&legend), "{legend:?}");
        // The box the SVG draws is the layout's, and everything drawn before it is data or
        // axes: no curve segment and no marker of those reaches into it.
        let drawn_at = svg
            .boxes
            .iter()
            .find(|(r, _)| *r == legend)
            .map(|&(_, order)| order)
            .expect("the legend box in the SVG");
        for line in svg
            .polylines
            .iter()
            .filter(|p| p.order < drawn_at && p.width > 1)
        {
            for w in line.points.windows(2) {
                assert!(
                    !segment_meets(w[0], w[1], &legend),
                    "{w:?} under the legend {legend:?}"
                );
            }
        }
        // Each legend entry with a marker holds one; no data marker lies in the box.
        let chart_markers = svg
            .markers
            .iter()
            .filter(|m| !svg.in_legend(m.centre))
            .count();
        let legend_markers = svg.markers.len() - chart_markers;
        assert_eq!(
            legend_markers,
            chart.series.iter().filter(|s| s.marker.is_some()).count()
        );
    }
}

/// Writes every demo figure to `$FIGURES_DEMO_DIR`, or without it to `target/tmp/figures-demo/`
/// (to look at them), reads each file back and checks that it is the whole figure, well-formed
/// SVG, with its title, one curve per series (the exact curves and fitted slopes among them) and
/// the band where one is given.
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
    // (file, title, figure, curves, bands)
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
            // 3 series, 2 fits
            5,
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
            // 3 series, the fit of the one without a band
            4,
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
            // the series and its fit
            2,
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
    for (name, title, figure, curves, bands) in figures {
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
        assert_eq!(svg.layout.title.text, title, "{name}");
        assert_eq!(
            svg.curves_and_bands(),
            (curves, bands),
            "{name}: curves and bands"
        );
        assert_eq!(svg.bands().len(), bands, "{name}: bands drawn");
        assert_eq!(svg.swatches().len(), bands, "{name}: band swatches");
    }
}
