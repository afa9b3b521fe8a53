//! The studies behind the report's sections, one module per section with the files it writes
//! (their names and formats, which the readers import): the paper's tables, gravity, the
//! histories, which scheme to trust, what accuracy costs, the defaults experiment, the extended
//! table, stability, the
//! 2D/3D elastic study, and the figures drawn from their files; `report` and `golden` run them.
//! The commands below the command line are here too (`*_run`, `scene_run`, `scene_study`), with
//! where their results go (`outputs`).

pub mod benchmark;
pub mod catalogue;
pub mod cluster_plan;
pub mod cost;
pub mod elastic_study;
pub mod estimate;
pub mod experiment;
pub mod extended;
pub mod figures;
pub mod getfem;
pub mod getfem_run;
pub mod golden;
pub mod gravity;
pub mod histories;
pub mod league;
pub mod outputs;
pub mod reference_run;
pub mod report;
pub mod report_run;
pub mod reports_index;
pub mod scene_run;
pub mod scene_study;
pub mod schemes;
pub mod stability;
pub mod study_run;
pub mod tables;
pub mod verify_run;
