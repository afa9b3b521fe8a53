//! A scene's study as a report: the outcome of the study a user asked for
//! ([`crate::harness::reference::scene_study`]) judged ([`JudgedStudy`]), printed as the rate
//! tables of a bar or the report of a box, or written as a box's report files.

use std::path::Path;

use crate::harness::files::error as files;
use crate::harness::reference::fine_mesh::ElasticHistories;
use crate::harness::reference::scene_study::StudyOutcome;
use crate::harness::render::report::convergence_tables;
use crate::harness::study::Study;
use crate::studies::elastic_study::files::write_elastic_files;
use crate::studies::elastic_study::{report, ElasticStudy};
use crate::studies::error::Error;

/// `n` and `noun`, in the plural unless `n` is 1: `1 case`, `7 levels`.
fn counted(n: usize, noun: &str) -> String {
    format!("{n} {noun}{}", if n == 1 { "" } else { "s" })
}

/// A study's outcome judged: the rates against the exact solution as they are, or the study
/// against the fine-mesh reference with the note's findings and its figure data.
#[allow(clippy::large_enum_variant)] // one per study, moved once
pub enum JudgedStudy {
    /// Against the exact solution.
    Exact {
        /// The scene's name.
        scene: String,
        /// The study.
        study: Study,
    },
    /// Against the fine-mesh reference.
    FineMesh {
        /// The study, the reference check and the findings.
        study: ElasticStudy,
        /// The figure data.
        histories: ElasticHistories,
    },
}

impl JudgedStudy {
    /// `outcome` judged: a fine-mesh study's findings judged on its rates.
    pub fn of(outcome: StudyOutcome) -> Self {
        match outcome {
            StudyOutcome::Exact { scene, study } => Self::Exact { scene, study },
            StudyOutcome::FineMesh { study, histories } => Self::FineMesh {
                study: ElasticStudy::judged(study),
                histories,
            },
        }
    }

    /// The outcome as a person reads it: a bar's rate tables and a line with its size and
    /// time, or a box's report saying it was made by `command`; as JSON with `json`.
    pub fn render(&self, json: bool, command: &str) -> Result<String, Error> {
        let encode = files::Error::encode(Path::new("stdout"));
        Ok(match (self, json) {
            (Self::Exact { study, .. }, true) => {
                serde_json::to_string_pretty(study).map_err(encode)?
            }
            (Self::FineMesh { study, .. }, true) => {
                serde_json::to_string_pretty(study).map_err(encode)?
            }
            (Self::Exact { scene, study }, false) => format!(
                "{}\n\n{scene}: {} × {}, {:.2} s wall",
                convergence_tables(study).trim_end(),
                counted(study.cases.len(), "case"),
                counted(study.config.levels.len(), "level"),
                study.wall_seconds
            ),
            (Self::FineMesh { study, .. }, false) => {
                report::render(study, command).trim_end().into()
            }
        })
    }

    /// Writes a box study's report, study and figure data into `out_dir` and returns what was
    /// written (named under `shown_dir`), for the user; a bar's study has none
    /// ([`crate::harness::reference::scene_study::SceneStudy::check_reports_dir`]): it writes
    /// nothing and returns its rendering.
    pub fn write_reports(
        &self,
        out_dir: &Path,
        shown_dir: &Path,
        command: &str,
    ) -> Result<String, Error> {
        let Self::FineMesh { study, histories } = self else {
            return self.render(false, command);
        };
        let written: Vec<String> = write_elastic_files(study, histories, out_dir, command)?
            .iter()
            .map(|f| shown_dir.join(f).display().to_string())
            .collect();
        let mut summary = format!(
            "wrote {} ({}, study {:.1} s wall)",
            written.join(", "),
            counted(study.study.cases.len(), "case"),
            study.study.wall_seconds,
        );
        if let Some(s) = &study.sensitivity {
            for line in s.class_lines() {
                summary.push_str(&format!("\n{line}"));
            }
            summary.push_str(&format!(
                "\nround-off ensemble: {} members per case and level, run in the study's jobs \
                 ({:.1} s of run time summed over them)",
                s.ensemble.members, s.wall_seconds
            ));
        }
        Ok(summary)
    }
}
