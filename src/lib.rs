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

pub mod engine;
pub mod harness;
pub mod studies;

pub use engine::{contact, exact, fem, linalg, model, problem, schemes};
pub use harness::artifacts as output;
pub use harness::{elastic, golden, norms, rates, run, scene, sensitivity, study};
pub use studies::tables::paper;
pub use studies::{cost, elastic_study, extended, pipeline, stability};

/// The markdown renderers of a study (`harness::report`), the oscillation words
/// (`harness::verdicts`) and the tables beside the paper's (`studies::tables::agreement`) under
/// their old path.
pub mod report {
    pub use crate::harness::report::*;
    pub use crate::harness::verdicts::{oscillation_word, OSCILLATES_FROM};
    pub use crate::studies::tables::agreement::*;
}

/// The errors of every layer (`engine::error` and `harness::error`) under their old path.
pub mod error {
    pub use crate::engine::error::{
        require_in, require_positive, Error as EngineError, ParameterError, SolveError,
    };
    pub use crate::harness::error::Error;
}

/// The figures: the drawing primitives (`harness::figures`) and the report's figures
/// (`studies::figures`) under their old path.
pub mod figures {
    pub use crate::harness::figures::*;
    pub use crate::studies::figures::{convergence, elastic, from_reports};
}
