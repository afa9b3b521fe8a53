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

pub use engine::{contact, exact, fem, linalg, model, problem, schemes};
pub use harness::artifacts as output;
pub use harness::{elastic, golden, norms, rates, run, scene, sensitivity, study};
pub use studies::tables::paper;
pub use studies::{cost, elastic_study, extended, stability};

/// The markdown renderers of a study (`harness::report`), the oscillation words
/// (`harness::verdicts`) and the tables beside the paper's (`studies::tables::agreement`) under
/// their old path.
pub mod report {
    pub use crate::harness::report::*;
    pub use crate::harness::verdicts::{oscillation_word, OSCILLATES_FROM};
    pub use crate::studies::tables::agreement::*;
}

/// What `signorini report`, `experiment`, `stability` and `golden` run, each now in the module
/// of its report section (`studies::tables`, `gravity`, `histories`, `cost`, `experiment`,
/// `extended`, `stability`, `elastic_study`, `report`, `golden`), under its old path.
pub mod pipeline {
    pub use crate::harness::golden::read_golden;
    pub use crate::studies::elastic_study::files::{write_elastic_report, REFERENCE_CACHE};
    pub use crate::studies::elastic_study::gate::{
        elastic_gate_sensitivity, elastic_gate_study, ELASTIC_2D_SCENE,
        ELASTIC_GATE_REFERENCE_LEVEL, GOLDEN_ELASTIC_2D,
    };
    pub use crate::studies::experiment::{
        write_defaults_experiment, EXPERIMENT_HORIZONS, EXPERIMENT_RANGES,
    };
    pub use crate::studies::extended::{
        extended_studies_with_sensitivity, read_extended_golden, write_extended_report,
        GOLDEN_EXTENDED,
    };
    pub use crate::studies::golden::write_golden;
    pub use crate::studies::gravity::{
        gravity_sensitivity, gravity_study, write_gravity_report, GOLDEN_GRAVITY, GRAVITY_SCENE,
    };
    pub use crate::studies::histories::{write_histories, HISTORY_LEVELS};
    pub use crate::studies::report::write_report;
    pub use crate::studies::stability::write_stability;
    pub use crate::studies::tables::{
        tables_sensitivity, tables_study, write_sensitivity_files, GOLDEN_TABLES, LONGER_HORIZON,
    };
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
    pub use crate::studies::figures::{convergence, elastic};

    /// The report's figures drawn from the files the studies wrote
    /// (`studies::figures::from_reports`), with the histories' format
    /// (`studies::histories::SchemeHistories`), under their old path.
    pub mod from_reports {
        pub use crate::studies::figures::from_reports::*;
        pub use crate::studies::histories::SchemeHistories;
    }
}
