//! The report's figures, drawn from the files the studies wrote.

pub mod convergence;
pub mod elastic;
pub mod from_reports;
