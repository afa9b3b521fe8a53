//! What a study measures a case at a level against: the reference a scene declares. Above
//! [`crate::harness::study`], whose jobs ([`crate::harness::study::StudyJobs`]) it measures
//! through [`crate::harness::study::LevelMeasure`], with two implementations:
//!
//! | module | its face |
//! |---|---|
//! | [`declared`] | what a scene's runs read from another code's files are measured against: [`declared::DeclaredReference`] |
//! | [`exact`] | a bar against its closed-form solution: [`exact::ExactSolution`], [`exact::run_study`] |
//! | [`fine_mesh`] | a box against one run on a finer nested mesh: [`fine_mesh::run_fine_mesh_study_on`], the fine run in one process or across ranks ([`fine_mesh::fine_run::FineReference`]), its cache ([`fine_mesh::cache`]), the comparison of a run with it ([`fine_mesh::comparison`]), its round-off ensembles ([`fine_mesh::ensemble`]) and its check ([`fine_mesh::ReferenceCheck`]) |
//! | [`scene_run`] | one run of a scene as a user asks for it, a bar's measured against its exact solution, a box's energy and contact face observed: [`scene_run::SceneRun`] |
//! | [`scene_sensitivity`] | a scene's study run as round-off ensembles, a bar's or a box's, into one [`crate::harness::study::sensitivity::Sensitivity`]: [`scene_sensitivity::SceneSensitivity`] |
//! | [`scene_study`] | a scene's study as a user asks for it, measured against the reference its scene declares (the one place that tells the two apart for a study, as [`declared`] does for runs read from files): [`scene_study::SceneStudy`], [`scene_study::StudyOutcome`] |

pub mod declared;
pub mod exact;
pub mod fine_mesh;
pub mod scene_run;
pub mod scene_sensitivity;
pub mod scene_study;
