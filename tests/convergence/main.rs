//! What the studies measure: convergence orders on a smooth solution, the golden gates of the
//! 1D, extended and 2D studies, the round-off sensitivity ensembles that decide how each case is
//! gated, and the stability suite's CI subset. The equivalent-rewrite test of the gate is not
//! here: it sets a process-wide hook, so it has a binary of its own (`tests/roundoff_gate.rs`).

#[path = "../common/benchmarks.rs"]
mod benchmarks;
#[path = "../common/mod.rs"]
mod common;
#[path = "../common/timings.rs"]
mod timings;

mod box_sensitivity;
mod elastic_study;
mod gate;
mod report_shards;
mod sensitivity;
mod smooth;
mod stability;
