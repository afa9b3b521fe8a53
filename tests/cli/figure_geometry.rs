//! Every committed figure checked against its own geometry: the layout the drawing code embeds
//! in each SVG (`signorini::harness::render::figures::layout`) and the SVG as resvg lays it
//! out with a real font.
//!
//! What a figure must satisfy:
//! - **text inside the canvas**: every `<text>` element, laid out by resvg (usvg) with a system
//!   sans-serif font, has its glyphs' box inside the canvas, and the title, captions, axis
//!   descriptions and legend labels of the layout are among them;
//! - **legends clear of the data**: no data element drawn before a legend's box (a curve, a
//!   marker, a band) reaches into that box, and the legend's labels lie inside it;
//! - **distinct, colour-blind-safe styles**: every series' colour is one of the Okabe–Ito
//!   palette's (or the exact solution's black), and two series of one chart with different
//!   labels differ in dash or marker, never by colour alone;
//! - **fitted slopes drawn**: every convergence chart (log `h` axis) draws a fitted slope for
//!   each series that is not an ensemble, its legend giving the 95 % interval; against a
//!   fine-mesh reference (a title naming `u_ref`) also the reference's bias bound;
//! - **one kind of band per legend, named**: at most one band name per chart, and no legend
//!   writes an interval as a bare `± x`;
//! - **compared panels on one scale**: charts of one scale group have the same y range (a map's
//!   panels, one colour bar);
//! - **titles that say what is drawn**: every title names the mass (or both masses) and the
//!   level (`NX = …`, `… elements`) unless its x axis carries the levels (`h`, wall time); an
//!   elastic figure's title names its reference (`u_ref` or "reference");
//! - **axes fitted to their data**: a log y axis spans at most a fifth of a decade more than
//!   its series; a contact force axis with an exact force gives it at least a tenth of its
//!   height; no tick label is written `0.00…` (scientific notation below 0.1);
//! - **distinct tick labels** along every axis and colour bar;
//! - **a tick at every level** of a logarithmic axis that has levels, and every `h` axis of a
//!   convergence plot has them.
//!
//! The `deliberate_*` tests feed a clipped title, a legend over the data, alike styles, a
//! missing fit, mixed bands and unshared scales and see each reported, so that the checks are
//! known to bite.
//!
//! The figures drawn from the histories `make report` writes (`data/histories/`,
//! `data/elastic-<d>d-histories.json`, not committed) are redrawn only by `make report`; until
//! then those of them drawn before the styles were recorded get the checks of their time (text,
//! legends, ticks), and [`LEGACY_FAMILIES`] names them.

use std::path::{Path, PathBuf};
use std::sync::{Arc, OnceLock};

use resvg::usvg;
use signorini::harness::render::figures::layout::{
    FigureLayout, Rect, SeriesKind, SeriesLayout, METADATA_ID,
};
use signorini::harness::render::figures::style::{EXACT, PALETTE};
use signorini::harness::render::figures::{convergence_figure, ConvergenceFit, ConvergenceSeries};
use signorini::harness::study::rates::RateFit;

/// The families of figures drawn from histories only `make report` writes: a committed figure of
/// these drawn before its layout recorded series styles is left to the checks of its time.
const LEGACY_FAMILIES: [&str; 5] = [
    "figures/contact-",
    "figures/energy-",
    "-contact-",
    "-energy-",
    "-von-mises-",
];

/// The directories whose figures are committed (those present).
const FIGURE_DIRS: [&str; 3] = [
    "reports/figures",
    "reports/fine/figures",
    "reports/finest/figures",
];

/// The system fonts, with `sans-serif` resolved to DejaVu Sans when it is installed.
fn fonts() -> Arc<usvg::fontdb::Database> {
    static FONTS: OnceLock<Arc<usvg::fontdb::Database>> = OnceLock::new();
    FONTS
        .get_or_init(|| {
            let mut db = usvg::fontdb::Database::new();
            db.load_system_fonts();
            assert!(
                !db.is_empty(),
                "no system font: the figure checks lay text out with one \
                 (Debian: apt-get install fonts-dejavu-core; `make test` does it)"
            );
            let family = db
                .faces()
                .flat_map(|f| f.families.iter().map(|(name, _)| name.clone()))
                .find(|name| name == "DejaVu Sans")
                .or_else(|| db.faces().next().map(|f| f.families[0].0.clone()))
                .expect("a font family");
            db.set_sans_serif_family(family);
            Arc::new(db)
        })
        .clone()
}

/// A rendered `<text>`: its content and its glyphs' box in canvas pixels.
struct RenderedText {
    text: String,
    left: f32,
    top: f32,
    right: f32,
    bottom: f32,
}

/// Every text of `svg` as resvg lays it out, and the number of `<text>` elements with content.
fn rendered_texts(svg: &str) -> (Vec<RenderedText>, usize) {
    let options = usvg::Options {
        fontdb: fonts(),
        ..usvg::Options::default()
    };
    let tree = usvg::Tree::from_str(svg, &options).expect("resvg parses the figure");
    let mut out = Vec::new();
    fn walk(group: &usvg::Group, out: &mut Vec<RenderedText>) {
        for node in group.children() {
            match node {
                usvg::Node::Group(g) => walk(g, out),
                usvg::Node::Text(t) => {
                    let b = t.abs_bounding_box();
                    out.push(RenderedText {
                        text: t.chunks().iter().map(|c| c.text()).collect::<String>(),
                        left: b.left(),
                        top: b.top(),
                        right: b.right(),
                        bottom: b.bottom(),
                    });
                }
                _ => {}
            }
        }
    }
    walk(tree.root(), &mut out);
    let doc = roxmltree::Document::parse(svg).expect("well-formed XML");
    let elements = doc
        .descendants()
        .filter(|n| n.has_tag_name("text"))
        .filter(|n| !n.text().unwrap_or("").trim().is_empty())
        .count();
    (out, elements)
}

/// A data element drawn before a legend: where its ink goes.
enum Ink {
    /// A polyline of this stroke width.
    Line(Vec<(f64, f64)>, f64),
    /// A filled circle: centre and radius.
    Dot((f64, f64), f64),
    /// A filled polygon.
    Area(Vec<(f64, f64)>),
}

fn points(n: roxmltree::Node) -> Vec<(f64, f64)> {
    n.attribute("points")
        .unwrap_or("")
        .split_whitespace()
        .filter_map(|p| {
            let (x, y) = p.split_once(',')?;
            Some((x.parse().ok()?, y.parse().ok()?))
        })
        .collect()
}

fn num(n: roxmltree::Node, a: &str) -> f64 {
    n.attribute(a).and_then(|v| v.parse().ok()).unwrap_or(0.0)
}

/// Whether the segment `a`–`b` meets the box `(x0, y0, x1, y1)`.
pub(crate) fn segment_meets(
    a: (f64, f64),
    b: (f64, f64),
    (x0, y0, x1, y1): (f64, f64, f64, f64),
) -> bool {
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
        } else if p < 0.0 {
            t0 = t0.max(q / p);
        } else {
            t1 = t1.min(q / p);
        }
    }
    t0 <= t1
}

impl Ink {
    /// Whether this ink reaches into the interior of `r` (one pixel in from its edges).
    fn meets(&self, r: &Rect) -> bool {
        let inner = |grow: f64| {
            (
                f64::from(r.x0) + 1.0 - grow,
                f64::from(r.y0) + 1.0 - grow,
                f64::from(r.x1) - 1.0 + grow,
                f64::from(r.y1) - 1.0 + grow,
            )
        };
        match self {
            Ink::Line(pts, width) => {
                let b = inner(width / 2.0);
                match pts.as_slice() {
                    [p] => segment_meets(*p, *p, b),
                    _ => pts.windows(2).any(|w| segment_meets(w[0], w[1], b)),
                }
            }
            Ink::Dot(c, radius) => segment_meets(*c, *c, inner(*radius)),
            Ink::Area(outline) => {
                let b = inner(0.0);
                let edges = outline.iter().zip(outline.iter().cycle().skip(1));
                let corner = (b.0, b.1);
                let mut inside = false;
                for (a, c) in outline.iter().zip(outline.iter().cycle().skip(1)) {
                    if (a.1 > corner.1) != (c.1 > corner.1)
                        && corner.0 < a.0 + (corner.1 - a.1) / (c.1 - a.1) * (c.0 - a.0)
                    {
                        inside = !inside;
                    }
                }
                inside || edges.into_iter().any(|(&a, &c)| segment_meets(a, c, b))
            }
        }
    }
}

/// The data elements of `svg` drawn before its `<rect>` at `(x, y)` (a legend's background),
/// or `None` when there is no such rect.
fn ink_before_legend(doc: &roxmltree::Document, at: (i32, i32)) -> Option<Vec<Ink>> {
    let mut ink = Vec::new();
    for n in doc.descendants().filter(|n| n.is_element()) {
        match n.tag_name().name() {
            "rect"
                if num(n, "x") as i32 == at.0
                    && num(n, "y") as i32 == at.1
                    && n.attribute("fill") != Some("none") =>
            {
                return Some(ink)
            }
            "polyline" if num(n, "stroke-width") > 1.0 => {
                ink.push(Ink::Line(points(n), num(n, "stroke-width")))
            }
            "circle" => ink.push(Ink::Dot((num(n, "cx"), num(n, "cy")), num(n, "r"))),
            "polygon" => ink.push(Ink::Area(points(n))),
            _ => {}
        }
    }
    None
}

/// Whether a figure's layout records its series' styles and axis ranges (drawn by the drawing
/// code that checks below rely on).
fn styled(layout: &FigureLayout) -> bool {
    layout
        .charts
        .iter()
        .all(|c| c.y.range.is_some() && c.series.iter().all(|s| !s.dash.is_empty()))
}

/// The problems of styles, fits, bands, scales, titles and axes (see the module's doc).
fn style_problems(name: &str, layout: &FigureLayout) -> Vec<String> {
    let mut out = Vec::new();
    let safe: Vec<[u8; 3]> = PALETTE
        .iter()
        .chain([&EXACT])
        .map(|c| [c.0, c.1, c.2])
        .collect();
    let series: Vec<&SeriesLayout> = layout.charts.iter().flat_map(|c| &c.series).collect();
    let drawn = |s: &&&SeriesLayout| s.kind != SeriesKind::Note;
    for s in series.iter().filter(drawn) {
        if !safe.contains(&s.colour) {
            out.push(format!(
                "{name}: series {:?} has colour {:?}, not one of the colour-blind-safe palette",
                s.label, s.colour
            ));
        }
    }
    // Within a chart: a run keeps its style from panel to panel, whatever its label says there.
    for c in &layout.charts {
        let drawn_series: Vec<&SeriesLayout> = c
            .series
            .iter()
            .filter(|s| s.kind != SeriesKind::Note)
            .collect();
        for (i, a) in drawn_series.iter().enumerate() {
            for b in &drawn_series[i + 1..] {
                if a.label != b.label && a.dash == b.dash && a.marker == b.marker {
                    out.push(format!(
                    "{name}: series {:?} and {:?} have the same dash ({}) and marker ({:?}): told \
                     apart by colour alone",
                    a.label, b.label, a.dash, a.marker
                ));
                }
            }
        }
    }
    let title = &layout.title.text;
    for (k, c) in layout.charts.iter().enumerate() {
        // Fitted slopes and bias bounds on convergence charts.
        if c.x.log && c.x.label == "h" {
            let data = c
                .series
                .iter()
                .filter(|s| s.kind == SeriesKind::Data && s.band.is_none())
                .count();
            let fits: Vec<&SeriesLayout> = c
                .series
                .iter()
                .filter(|s| s.kind == SeriesKind::Fit)
                .collect();
            if fits.len() < data {
                out.push(format!(
                    "{name}: chart {k}: {data} series without a band but {} fitted slopes drawn",
                    fits.len()
                ));
            }
            for f in &fits {
                if !(f.label.contains("95 % CI") || f.label.contains("no interval")) {
                    out.push(format!(
                        "{name}: chart {k}: the fit {:?} gives no interval",
                        f.label
                    ));
                }
                if title.contains("u_ref") && !f.label.contains("reference bias") {
                    out.push(format!(
                        "{name}: chart {k}: the fit {:?} against a reference gives no bias bound",
                        f.label
                    ));
                }
            }
        }
        // One kind of band, named; no bare ± interval.
        let mut bands: Vec<&str> = c.series.iter().filter_map(|s| s.band.as_deref()).collect();
        bands.dedup();
        if bands.len() > 1 {
            out.push(format!(
                "{name}: chart {k}: the legend mixes kinds of band {bands:?}"
            ));
        }
        for s in c
            .series
            .iter()
            .filter(|s| s.label.contains('±') && !s.label.contains("bias"))
        {
            out.push(format!(
                "{name}: chart {k}: {:?} writes an interval as a bare ±, unnamed",
                s.label
            ));
        }
        // Axes fitted to the data.
        let extent = c
            .series
            .iter()
            .filter_map(|s| s.extent)
            .fold(None, |acc: Option<[f64; 2]>, e| {
                Some(acc.map_or(e, |a| [a[0].min(e[0]), a[1].max(e[1])]))
            });
        if let (true, Some([lo, hi]), Some([a, b])) = (c.y.log, c.y.range, extent) {
            let slack = (b / a).log10().max(0.0) * 0.1 + 0.2;
            if (hi / lo).log10() > (b / a).log10() + slack {
                out.push(format!(
                    "{name}: chart {k}: the log y axis spans [{lo:.2e}, {hi:.2e}] for data in [{a:.2e}, {b:.2e}]"
                ));
            }
        }
        if c.y.label.contains('λ') {
            let exact = c
                .series
                .iter()
                .find(|s| s.kind == SeriesKind::Exact)
                .and_then(|s| s.extent);
            if let (Some([a, b]), Some([lo, hi])) = (exact, c.y.range) {
                if (b - a) < 0.1 * (hi - lo) {
                    out.push(format!(
                        "{name}: chart {k}: the exact force spans {:.2} of an axis of {:.2}: flattened",
                        b - a,
                        hi - lo
                    ));
                }
            }
        }
        let axes = [&c.x, &c.y]
            .into_iter()
            .chain(c.colour_bar.as_ref().map(|(_, a)| a));
        for axis in axes {
            for t in axis.ticks.iter().filter(|t| {
                let l = t.label.trim_start_matches('-');
                l.starts_with("0.00")
            }) {
                out.push(format!(
                    "{name}: chart {k}: the tick label {:?} on {:?} is hard to read (scientific below 0.1)",
                    t.label, axis.label
                ));
            }
        }
    }
    // Compared panels share their scale.
    for (i, a) in layout.charts.iter().enumerate() {
        for b in &layout.charts[i + 1..] {
            if a.scale_group.is_some()
                && a.scale_group == b.scale_group
                && a.colour_bar.is_none()
                && b.colour_bar.is_none()
                && a.y.range != b.y.range
            {
                out.push(format!(
                    "{name}: the charts of scale group {:?} have y ranges {:?} and {:?}",
                    a.scale_group, a.y.range, b.y.range
                ));
            }
        }
    }
    let bars = layout
        .charts
        .iter()
        .filter(|c| c.colour_bar.is_some())
        .count();
    if bars > 1 {
        out.push(format!(
            "{name}: {bars} colour bars where the panels share one scale"
        ));
    }
    // Titles: mass, level, reference.
    if !title.contains("mass") {
        out.push(format!("{name}: the title {title:?} names no mass"));
    }
    let levels_on_axis = layout
        .charts
        .iter()
        .any(|c| c.x.label == "h" || c.x.label.starts_with("wall time"));
    if !(levels_on_axis || title.contains("NX =") || title.contains("elements")) {
        out.push(format!("{name}: the title {title:?} names no level"));
    }
    if name.contains("elastic-") && !(title.contains("u_ref") || title.contains("reference")) {
        out.push(format!(
            "{name}: the title {title:?} does not name the reference"
        ));
    }
    out
}

/// The `width` and `height` attributes of the root of `svg`.
fn canvas_size(svg: &str) -> (f32, f32) {
    let doc = roxmltree::Document::parse(svg).expect("well-formed XML");
    let root = doc.root_element();
    let size = |a: &str| {
        root.attribute(a)
            .and_then(|v| v.parse().ok())
            .unwrap_or(0.0)
    };
    (size("width"), size("height"))
}

/// Every text of `svg` (named `name`) whose glyphs, laid out by resvg, leave the canvas, and
/// texts resvg could not lay out; returns the problems and the rendered texts.
fn text_problems(name: &str, svg: &str) -> (Vec<String>, Vec<RenderedText>) {
    let mut out = Vec::new();
    let (width, height) = canvas_size(svg);
    let (texts, elements) = rendered_texts(svg);
    if texts.len() != elements {
        out.push(format!(
            "{name}: resvg laid out {} of {elements} texts (a font is missing?)",
            texts.len()
        ));
    }
    for t in &texts {
        if t.left < 0.0 || t.top < 0.0 || t.right > width || t.bottom > height {
            out.push(format!(
                "{name}: text {:?} spans x {:.0}..{:.0}, y {:.0}..{:.0}, outside the {width}×{height} canvas",
                t.text, t.left, t.right, t.top, t.bottom
            ));
        }
    }
    (out, texts)
}

/// Everything wrong with the figure `svg` (named `name` in the messages), by the rules of the
/// module's doc; empty when nothing is. A figure without an embedded layout is a problem.
fn problems(name: &str, svg: &str) -> Vec<String> {
    let (mut out, texts) = text_problems(name, svg);
    let layout = match FigureLayout::from_svg(svg) {
        Some(Ok(layout)) => layout,
        Some(Err(e)) => return vec![format!("{name}: its layout does not parse: {e}")],
        None => {
            out.push(format!("{name}: no embedded layout (`{METADATA_ID}`)"));
            return out;
        }
    };
    let canvas = layout.canvas();
    let rendered = |s: &str| texts.iter().any(|t| t.text.trim() == s.trim());
    if !canvas.contains(&layout.title.rect) {
        out.push(format!(
            "{name}: the title {:?} is laid out at {:?}, outside the canvas",
            layout.title.text, layout.title.rect
        ));
    }
    let mut labels = vec![layout.title.text.clone()];
    for c in &layout.charts {
        labels.extend(c.caption.iter().map(|t| t.text.clone()));
        labels.extend([c.x.label.clone(), c.y.label.clone()]);
        if let Some(caption) = c.caption.as_ref().filter(|t| !canvas.contains(&t.rect)) {
            out.push(format!(
                "{name}: caption {:?} is laid out outside the canvas",
                caption.text
            ));
        }
    }
    for l in labels.iter().filter(|l| !l.is_empty() && !rendered(l)) {
        out.push(format!("{name}: {l:?} is not among the rendered texts"));
    }

    // Legends clear of the data, and holding their labels.
    let doc = roxmltree::Document::parse(svg).expect("well-formed XML");
    for (k, c) in layout.charts.iter().enumerate() {
        let Some(legend) = c.legend else { continue };
        match ink_before_legend(&doc, (legend.x0, legend.y0)) {
            None => out.push(format!(
                "{name}: chart {k}: no legend box at ({}, {}) in the SVG",
                legend.x0, legend.y0
            )),
            Some(ink) => {
                let covered = ink.iter().filter(|i| i.meets(&legend)).count();
                if covered > 0 {
                    out.push(format!(
                        "{name}: chart {k}: the legend at {legend:?} covers {covered} data elements"
                    ));
                }
            }
        }
        for s in &c.series {
            let inside = texts.iter().any(|t| {
                t.text.trim() == s.label
                    && t.left >= legend.x0 as f32
                    && t.right <= legend.x1 as f32
                    && t.top >= legend.y0 as f32
                    && t.bottom <= legend.y1 as f32
            });
            if !inside {
                out.push(format!(
                    "{name}: chart {k}: legend label {:?} is not inside the legend box {legend:?}",
                    s.label
                ));
            }
        }
    }

    if styled(&layout) {
        out.extend(style_problems(name, &layout));
    }

    // Tick labels distinct along each axis; a tick at every level of a log axis.
    for (k, c) in layout.charts.iter().enumerate() {
        let axes = [("x", &c.x), ("y", &c.y)]
            .into_iter()
            .chain(c.colour_bar.as_ref().map(|(_, a)| ("colour bar", a)));
        for (which, axis) in axes {
            let labels: Vec<&str> = axis.ticks.iter().map(|t| t.label.as_str()).collect();
            for (i, l) in labels.iter().enumerate() {
                if labels[..i].contains(l) {
                    out.push(format!(
                        "{name}: chart {k}: the {which} axis repeats the tick label {l:?} ({labels:?})"
                    ));
                }
            }
            if axis.log && axis.label == "h" && axis.levels.is_empty() {
                out.push(format!(
                    "{name}: chart {k}: the log {which} axis `h` has no levels"
                ));
            }
            for level in &axis.levels {
                let ticked = axis
                    .ticks
                    .iter()
                    .any(|t| (t.value / level - 1.0).abs() < 1e-9 && !t.label.is_empty());
                if axis.log && !ticked {
                    out.push(format!(
                        "{name}: chart {k}: the log {which} axis has no tick at the level {level} (ticks {labels:?})"
                    ));
                }
            }
        }
    }
    out
}

/// The committed figures: `(path, svg)` of every `.svg` under [`FIGURE_DIRS`].
fn committed_figures() -> Vec<(PathBuf, String)> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut out = Vec::new();
    for dir in FIGURE_DIRS {
        let Ok(entries) = std::fs::read_dir(root.join(dir)) else {
            continue;
        };
        let mut paths: Vec<PathBuf> = entries
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| p.extension().is_some_and(|e| e == "svg"))
            .collect();
        paths.sort();
        for p in paths {
            let svg = std::fs::read_to_string(&p).unwrap();
            out.push((p.strip_prefix(root).unwrap().to_owned(), svg));
        }
    }
    out
}

#[test]
fn every_committed_figure_keeps_its_text_legends_styles_scales_and_ticks_in_order() {
    let figures = committed_figures();
    assert!(
        figures.len() >= 100,
        "only {} committed figures found",
        figures.len()
    );
    let mut all = Vec::new();
    for (path, svg) in &figures {
        let name = path.display().to_string();
        all.extend(problems(&name, svg));
        let layout = FigureLayout::from_svg(svg).and_then(Result::ok);
        if layout.is_some_and(|l| !styled(&l)) && !LEGACY_FAMILIES.iter().any(|f| name.contains(f))
        {
            all.push(format!(
                "{name}: its layout records no series styles or axis ranges (redraw it with `make figures`)"
            ));
        }
    }
    assert!(
        all.is_empty(),
        "{} problems in the committed figures (redraw them with `make figures`):\n{}",
        all.len(),
        all.join("\n")
    );
}

/// A convergence figure of two series over seven levels, for the deliberate violations.
fn sample_figure() -> String {
    let h: Vec<f64> = (0..7).map(|k| 0.1 / 2f64.powi(k)).collect();
    let series = [("first mass", 1.0, 0.5), ("second mass", 2.0, 1.0)].map(|(label, rate, c)| {
        ConvergenceSeries {
            label: label.into(),
            errors: h.iter().map(|x| c * x.powf(rate)).collect(),
            h: h.clone(),
            fit: Some(RateFit {
                rate,
                intercept: f64::ln(c),
                ci_low: Some(rate - 0.01),
                ci_high: Some(rate + 0.01),
                levels: 7,
            }),
            band: None,
        }
    });
    convergence_figure(
        "A convergence figure, both masses",
        &series,
        &ConvergenceFit::Exact,
    )
    .unwrap()
}

/// `svg` with its embedded layout replaced by `layout`.
fn with_layout(svg: &str, layout: &FigureLayout) -> String {
    let start = svg.find("<metadata").unwrap();
    let end = svg.find("</metadata>").unwrap() + "</metadata>".len();
    let json = serde_json::to_string(layout)
        .unwrap()
        .replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;");
    format!(
        "{}<metadata id=\"{METADATA_ID}\">{json}</metadata>{}",
        &svg[..start],
        &svg[end..]
    )
}

#[test]
fn the_sample_figure_passes_the_checks() {
    let svg = sample_figure();
    assert_eq!(problems("sample", &svg), Vec::<String>::new());
}

#[test]
fn deliberate_clipped_title_is_reported_by_the_layout_and_by_the_rendered_text() {
    let svg = sample_figure();
    let mut layout = FigureLayout::from_svg(&svg).unwrap().unwrap();
    // A title too long for the canvas, drawn at the size it had: it runs off both sides.
    let long = "A convergence figure whose title goes on and on, far wider than its canvas";
    layout.title.text = long.into();
    layout.title.rect.x0 = -150;
    layout.title.rect.x1 = 950;
    let clipped = with_layout(
        &svg.replace("A convergence figure, both masses", long),
        &layout,
    );
    let found = problems("clipped", &clipped);
    println!("{}", found.join("\n"));
    assert!(
        found
            .iter()
            .any(|p| p.contains("the title") && p.contains("outside the canvas")),
        "{found:?}"
    );
    assert!(
        found
            .iter()
            .any(|p| p.contains(&format!("text {long:?} spans")) && p.contains("outside")),
        "{found:?}"
    );
}

#[test]
fn deliberate_legend_over_the_data_is_reported() {
    let svg = sample_figure();
    let mut layout = FigureLayout::from_svg(&svg).unwrap().unwrap();
    let legend = layout.charts[0].legend.unwrap();
    // Move the legend (its box in the layout and in the SVG) onto the middle of the plot.
    let plot = layout.charts[0].plot;
    let (w, h) = (legend.x1 - legend.x0, legend.y1 - legend.y0);
    let (x, y) = ((plot.x0 + plot.x1 - w) / 2, (plot.y0 + plot.y1 - h) / 2);
    let moved = Rect {
        x0: x,
        y0: y,
        x1: x + w,
        y1: y + h,
    };
    layout.charts[0].legend = Some(moved);
    let svg = svg.replace(
        &format!("<rect x=\"{}\" y=\"{}\"", legend.x0, legend.y0),
        &format!("<rect x=\"{x}\" y=\"{y}\""),
    );
    let found = problems("overlapping", &with_layout(&svg, &layout));
    println!("{}", found.join("\n"));
    assert!(
        found
            .iter()
            .any(|p| p.contains("the legend at") && p.contains("covers")),
        "{found:?}"
    );
}

#[test]
fn deliberate_repeated_ticks_missing_levels_alike_styles_and_missing_fits_are_reported() {
    let svg = sample_figure();
    let mut layout = FigureLayout::from_svg(&svg).unwrap().unwrap();
    let chart = &mut layout.charts[0];
    chart.y.ticks[1].label = chart.y.ticks[0].label.clone();
    chart.x.ticks.remove(2);
    // The second series styled as the first (series: first, its fit, second, its fit).
    chart.series[2].marker = chart.series[0].marker.clone();
    chart.series[2].colour = [255, 255, 0];
    chart.series.retain(|s| s.kind != SeriesKind::Fit);
    chart.series[0].label.push_str(" (slope 0.95 ± 0.08)");
    chart.y.range = Some([1e-9, 1.0]);
    chart.y.ticks[2].label = "0.00125".into();
    layout.title.text = "A convergence figure".into();
    let found = problems("broken", &with_layout(&svg, &layout));
    println!("{}", found.join("\n"));
    for needle in [
        "repeats the tick label",
        "has no tick at the level",
        "told apart by colour alone",
        "not one of the colour-blind-safe palette",
        "fitted slopes drawn",
        "bare ±",
        "the log y axis spans",
        "hard to read",
        "names no mass",
    ] {
        assert!(
            found.iter().any(|p| p.contains(needle)),
            "{needle}: {found:?}"
        );
    }
}

#[test]
fn deliberate_unshared_scales_two_colour_bars_and_a_flattened_force_are_reported() {
    let svg = sample_figure();
    let mut layout = FigureLayout::from_svg(&svg).unwrap().unwrap();
    let mut second = layout.charts[0].clone();
    layout.charts[0].scale_group = Some("energy".into());
    second.scale_group = Some("energy".into());
    second.y.range = Some([1e-3, 1.0]);
    second.y.label = "λ(t)".into();
    second.series[0].kind = SeriesKind::Exact;
    second.series[0].extent = Some([0.0, 1e-3]);
    let mut bar = second.clone();
    bar.scale_group = None;
    bar.colour_bar = Some((layout.charts[0].plot, second.y.clone()));
    layout.charts.extend([second, bar.clone(), bar]);
    layout.charts[0].series[0].band = Some("round-off min–max".into());
    layout.charts[0].series[2].band = Some("95 % interval".into());
    let found = style_problems("unshared", &layout);
    println!("{}", found.join("\n"));
    for needle in [
        "of scale group",
        "colour bars",
        "flattened",
        "mixes kinds of band",
    ] {
        assert!(
            found.iter().any(|p| p.contains(needle)),
            "{needle}: {found:?}"
        );
    }
}
