//! # signorini
//!
//! A verification and regression harness for dynamic contact: an elastic bar hits a rigid
//! obstacle; time integrators (Newmark, θ-method, Paoli–Schatzman) with the standard or the
//! redistributed mass matrix are run at several refinements, compared with exact solutions, and
//! their convergence rates, contact-force oscillations and energy behaviour measured.
//!
//! The equations and their numbers refer to F. Dabaghi, A. Petrov, J. Pousin, Y. Renard,
//! *Numerical approximations of a one dimensional elastodynamic contact problem based on mass
//! redistribution method* (hal-00917450, 2013), "the 1D paper".
#![warn(missing_docs)]

pub mod commands;
pub mod engine;
pub mod harness;
pub mod studies;
