//! GetFEM's public 1D contact demo (`interface/tests/python/demo_dynamic_contact_1D.py`) as an
//! external witness: its runs read from `tests/data/getfem/` ([`read_run`], [`list_runs`]) and its
//! error norms computed its way, from the stored series ([`DemoSeries::norms`]) or from any
//! harness run on the Signorini–Dirichlet bar ([`DemoNorms`]), and its energy from the states of
//! a harness run ([`DemoEnergy`]).

pub mod anchor;
mod demo_run;
mod energy;
pub(crate) mod error;
mod exact;
mod norms;

pub use demo_run::{
    list_runs, read_run, DemoConfig, DemoFinalState, DemoMass, DemoRun, DemoRunFile, DemoRunName,
    DemoVersion, MAX_COMPRESSED_BYTES, MAX_JSON_BYTES,
};
pub use energy::DemoEnergy;
pub use error::DemoRunError;
pub use exact::demo_exact;
pub use norms::{DemoErrorNorms, DemoNorms, DemoSeries};
