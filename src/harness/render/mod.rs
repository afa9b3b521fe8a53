//! What the harness's results look like to a reader: markdown convergence tables and SVG
//! figures. Everything here renders numbers already computed (by [`crate::harness::run`] and
//! [`crate::harness::study`], which it sits above) and computes, fits or resamples nothing.
//!
//! | module | its face |
//! |---|---|
//! | [`report`] | [`report::convergence_tables`], [`report::convergence_table`], [`report::not_run_section`] |
//! | [`figures`] | [`figures::contact_node_figure`], [`figures::energy_figure`], [`figures::convergence_figure`], [`figures::work_precision_figure`], [`figures::time_series_figure`] and their panels and series; [`figures::heatmap::space_time_map`] |

pub mod figures;
pub mod report;
