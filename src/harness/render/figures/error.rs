//! Why a figure could not be drawn ([`FigureError`]).

use thiserror::Error;

/// Why a figure could not be drawn.
#[derive(Debug, Clone, PartialEq, Eq, Error)]
pub enum FigureError {
    /// The drawing library reported an error (its message).
    #[error("drawing failed: {0}")]
    Drawing(String),
    /// Nothing finite was left to draw.
    #[error("nothing to plot: {what}")]
    EmptyData {
        /// What was empty (the figure, panel or series).
        what: String,
    },
    /// Two inputs that describe the same runs disagree (e.g. an ensemble run at other levels
    /// than the study it is drawn with).
    #[error("inconsistent inputs: {what}")]
    Inconsistent {
        /// What disagrees with what.
        what: String,
    },
    /// Two sequences that pair up point by point have different lengths.
    #[error("{what}: {left} abscissae but {right} values")]
    LengthMismatch {
        /// Which series.
        what: String,
        /// Length of the abscissae (times, mesh sizes, seconds).
        left: usize,
        /// Length of the values.
        right: usize,
    },
}
