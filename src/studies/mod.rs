//! The studies behind the report's sections, one module per section with the files it writes
//! (their names and formats, which the readers import): the paper's tables, gravity, the
//! histories, which scheme to trust, what accuracy costs, the defaults experiment, the extended
//! table, stability, the
//! 2D/3D elastic study, each writing its own files; the render step (`render`) builds from those
//! files the pages that gather several sections, the figures and the index; `report` and
//! `golden` run them.
//! Below them, what the commands share with the studies: a scene's refinement study judged
//! (`scene_study`); the commands themselves, their back-ends and their shards' files are
//! `crate::commands`'.

pub mod benchmark;
pub mod cluster_plan;
pub mod cost;
pub mod elastic_study;
pub mod error;
pub mod estimate;
pub mod experiment;
pub mod extended;
pub mod figures;
pub mod getfem;
pub mod golden;
pub mod gravity;
pub mod histories;
pub mod league;
pub mod render;
pub mod report;
pub mod reports_index;
pub mod scene_study;
pub mod schemes;
pub mod stability;
pub mod tables;
