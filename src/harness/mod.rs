//! The harness: scenes, runs and what they observe, norms, convergence rates, studies over
//! cases and levels, box runs compared across nested meshes, round-off ensembles, golden files,
//! and the renderers of reports and figures. It drives the engine and knows nothing of any
//! particular study.
//!
//! It is cut into parts, each a directory whose `mod.rs` says what it is and lists its face (the
//! engine's vocabulary and the verdict words are one file each). Bottom to top: a part imports
//! only the parts listed before it (`tests/architecture.rs`).
//!
//! | part | what |
//! |---|---|
//! | [`problem`] | the engine's vocabulary as the harness runs it, re-exported for the layers above: `Problem`, `Settings`, `Scheme`, `MassVariant`, … |
//! | [`files`] | reading and writing any file, output directories whole or absent, the harness's [`files::error::Error`] |
//! | [`run`] | one run of a bar or a box: the loop, its observers, norms, results and files; box runs compared across nested meshes |
//! | [`study`] | runs over cases × levels: jobs and their executor, sharding, fits, round-off ensembles, the regression gate, scenes, budgets |
//! | [`vocabulary`] | every verdict word the reports print, defined once: its quantity, its threshold, the interval that decides it |
//! | [`reference`] | what a study measures a case at a level against: a bar's exact solution, a box's fine-mesh reference (its run, cache, comparison, ensembles and check) |
//! | [`render`] | markdown tables and SVG figures of what the parts below computed |
//! | [`external`] | another code's runs, verified through the harness's observers, fits, tables and gate |
//! | [`getfem`] | GetFEM's 1D demo as a witness: its runs read, its norms and energy computed its way |

pub mod external;
pub mod files;
pub mod getfem;
pub mod problem;
pub mod reference;
pub mod render;
pub mod run;
pub mod study;
pub mod vocabulary;
