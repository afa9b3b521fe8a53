//! Another code's runs verified with the harness (`signorini verify`): the external-run format
//! (docs/src/external-runs.md), read from JSON or CSV and checked against the
//! scene, replayed as a time integrator through the harness's own observers, grouped by label
//! into refinement series fitted by the harness's own fit, rendered as Tables 1–2 and gated by
//! the harness's own comparison.
//!
//! | file | what |
//! |---|---|
//! | [`format`] | the run in memory, the format's versions, limits and declarations (mass, energy definition), and its checks against the scene |
//! | [`json`], [`csv`] | the two forms of a file, each read into an [`ExternalRun`] |
//! | [`load`] | a file of either form, read and checked |
//! | [`pvd`], [`box_run`] | a box scene's run: a ParaView collection or the JSON format's box form, matched to the scene's mesh and time grid |
//! | [`mesh`] | the cells of a snapshot's mesh, and the elements the harness interpolates |
//! | [`replay`] | the samples as a [`crate::engine::schemes::TimeIntegrator`], through the observers |
//! | [`rerun`] | the harness's own run of a bar file's declared scheme and mass, compared sample by sample |
//! | [`verify`] | every file measured against the scene's reference (a bar's replayed against its exact solution, a box's compared with its fine-mesh reference), grouped into series, fitted |
//! | [`report`], [`golden`] | the tables; the golden file and its gate |
//! | [`error`] | what can be wrong, naming the file and the field |

pub mod box_run;
pub mod csv;
pub mod error;
pub mod format;
pub mod golden;
pub mod json;
pub mod load;
pub mod mesh;
pub mod nodal_snapshot;
pub mod pvd;
pub mod replay;
pub mod report;
pub mod rerun;
pub mod snapshot_series;
pub mod verify;
pub mod xdmf;
pub mod xml_depth;

pub use error::ExternalError;
pub use format::ExternalRun;
pub use golden::{compare, VerifyGolden};
pub use verify::{verify, Measured, Verification, VerifySources};
