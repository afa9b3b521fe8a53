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

pub mod contact;
pub mod cost;
pub mod elastic;
pub mod elastic_study;
pub mod error;
pub mod exact;
pub mod extended;
pub mod fem;
pub mod figures;
pub mod golden;
pub mod linalg;
pub mod model;
pub mod norms;
pub mod output;
pub mod paper;
pub mod pipeline;
pub mod problem;
pub mod rates;
pub mod report;
pub mod run;
pub mod scene;
pub mod schemes;
pub mod sensitivity;
pub mod stability;
pub mod study;
