//! The harness: scenes, runs and what they observe, norms, convergence rates, studies over
//! cases and levels, box runs compared across nested meshes, round-off ensembles, golden files,
//! and the renderers of reports and figures. It drives the engine and knows nothing of any particular study.

pub mod external;
pub mod files;
pub mod getfem;
pub mod problem;
pub mod render;
pub mod run;
pub mod study;
