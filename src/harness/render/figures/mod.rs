//! SVG figures of data the harness already produced: contact-node histories, energy histories,
//! convergence and work–precision plots, and generic time series. Data in, SVG text out.
//!
//! Every function takes the numbers as they are and only draws them: nothing is recomputed,
//! resampled or fitted here (a fitted slope is drawn from the caller's [`RateFit`], an
//! ensemble's spread from its [`ErrorBand`], a reference's bias bound is the caller's). The
//! result is the SVG document as a string; callers write it where they want.
//!
//! The style is the same everywhere: white background, 800×500 px for one panel and 600 px of
//! width per panel when there are several side by side (1200×500 for two; wider by its legend
//! when a legend stands right of its chart), a title shrunk to fit the canvas, labelled axes,
//! a legend where it covers no data (inside the chart, in headroom above the data, or on its
//! right), log–log axes wherever errors are shown with a tick at every level of a convergence
//! plot, tick labels with as many decimals as their spacing needs (scientific below 0.1), and
//! every series told apart by colour and by line style or marker: colours from the Okabe–Ito
//! palette (safe for the common colour-vision deficiencies), dash patterns and marker shapes
//! (see [`style`]). An exact solution is black and dashed, drawn over the computed curves.
//! Panels that are compared side by side share their y axis. Every figure embeds its
//! [`FigureLayout`] (see [`layout`]). The output is deterministic: the same input gives the
//! same bytes.
//!
//! Non-finite values (and non-positive ones on a log axis) are skipped point by point; a series
//! left with no point is dropped. When nothing drawable is left in a chart the function returns
//! [`FigureError::EmptyData`]. An axis whose values are all equal is padded so the chart still
//! has a range.
//!
//! [`RateFit`]: crate::harness::study::rates::RateFit

mod chart;
mod draw;
mod error;
pub mod heatmap;
pub mod layout;
pub mod style;

pub use draw::{
    contact_node_figure, convergence_figure, energy_figure, line_figure, time_series_figure,
    work_precision_figure, Colouring, ContactAxes, ConvergenceFit,
};
pub use layout::FigureLayout;

use crate::harness::run::{ContactHistory, EnergyHistory};
use crate::harness::study::rates::RateFit;
use crate::harness::study::sensitivity::Spread;
pub use error::FigureError;

/// A named SVG document: the file name and its text.
pub type Figure = (String, String);

/// One panel of [`contact_node_figure`]: the runs of one mass matrix.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ContactPanel {
    /// The panel's caption, e.g. `"standard mass"`.
    pub label: String,
    /// `(legend, history)` per run, e.g. `("NX = 40", …)`. The exact curves are taken from the
    /// first run's `displacement_exact` and `multiplier_exact`.
    pub runs: Vec<(String, ContactHistory)>,
}

/// One panel of [`energy_figure`]: the runs of one mass matrix.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct EnergyPanel {
    /// The panel's caption, e.g. `"redistributed mass"`.
    pub label: String,
    /// `(legend, history)` per run. The exact energy is taken from the first run.
    pub runs: Vec<(String, EnergyHistory)>,
}

/// One curve of [`convergence_figure`]: the error of one norm (or case) against `h`.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ConvergenceSeries {
    /// The legend text; the slope is appended as `" (slope 0.95)"`, or as
    /// `" (slope 0.52 [0.41, 0.63])"` for a band's rate.
    pub label: String,
    /// Mesh size of each level.
    pub h: Vec<f64>,
    /// The error at each level (same length as `h`); the ensemble median when there is a band.
    pub errors: Vec<f64>,
    /// The fitted rate shown in the legend, if any (not drawn as a line). A band's rate, when
    /// it has one, is shown instead.
    pub fit: Option<RateFit>,
    /// The spread of an ensemble around `errors`, drawn as a shaded band; `None` for a single
    /// run.
    pub band: Option<ErrorBand>,
}

/// The spread of an ensemble of runs (e.g. round-off perturbed members) at each level of a
/// [`ConvergenceSeries`]: shaded, in the series' colour, between `lower` and `upper`.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ErrorBand {
    /// The smallest error of the ensemble at each level (same length as the series' `h`).
    pub lower: Vec<f64>,
    /// The largest error of the ensemble at each level (same length as the series' `h`).
    pub upper: Vec<f64>,
    /// The ensemble's rates (one fitted per member over all levels): the legend shows their
    /// median and range in place of the series' `fit`.
    pub rate: Option<Spread>,
}

/// One curve of [`work_precision_figure`]: the error of one case against its wall time.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct WorkPrecisionSeries {
    /// The legend text, e.g. `"crank-nicolson/redistributed"`.
    pub label: String,
    /// Wall-clock seconds of each level.
    pub seconds: Vec<f64>,
    /// The error at each level (same length as `seconds`).
    pub errors: Vec<f64>,
}
