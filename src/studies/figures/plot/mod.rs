//! The drawing of the report's figures: data in, SVG text out.
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
pub mod heatmap;
pub mod layout;
pub mod style;

pub use draw::{
    contact_node_figure, convergence_figure, energy_figure, line_figure, time_series_figure,
    work_precision_figure, Colouring, ContactAxes, ConvergenceFit,
};
pub use layout::FigureLayout;

pub use crate::harness::render::figures::{
    ContactPanel, ConvergenceSeries, EnergyPanel, ErrorBand, Figure, FigureError,
    WorkPrecisionSeries,
};
