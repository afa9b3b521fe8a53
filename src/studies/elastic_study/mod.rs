//! The 2D/3D bars of the note (§3) studied against their fine-mesh reference: the note's
//! Figures 1–8 recomputed, and its statements judged.
//!
//! The study itself, its reference, the comparison of every run with it and the round-off
//! ensembles are the harness's ([`crate::harness::reference::fine_mesh`]); this section adds the
//! note's findings as tested verdicts ([`findings`], which [`rejudge`] applies again to a
//! committed study's file), the report ([`report`]), its files ([`files`]), the regression gate
//! of the 2D/3D studies ([`gate`]) and the note's findings judged on another code's runs
//! ([`external`]).

pub mod external;
pub mod files;
pub mod findings;
pub mod gate;
pub mod rejudge;
pub mod report;

use serde::{Deserialize, Serialize};

use crate::harness::reference::fine_mesh::cache::ReferenceCache;
use crate::harness::reference::fine_mesh::{
    run_fine_mesh_study, ElasticHistories, ElasticStudyConfig, FineMeshStudy, ReferenceCheck,
};
use crate::harness::run::elastic::BoxProblem;
use crate::harness::study::error::Error;
use crate::harness::study::sensitivity::Sensitivity;
use crate::harness::study::Study;
use findings::{note_findings, Finding};

/// A 2D or 3D study.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ElasticStudy {
    /// `d`.
    pub dimension: usize,
    /// The levels, reference and cases.
    pub config: ElasticStudyConfig,
    /// Errors, rates and per-level records of every case (norm keys as the 1D tables; see
    /// [`crate::harness::reference::fine_mesh::comparison`] for what each measures here).
    pub study: Study,
    /// Whether the reference is fine enough.
    pub reference: ReferenceCheck,
    /// The note's statements, tested.
    pub findings: Vec<Finding>,
    /// The round-off sensitivity of every case, when `config.sensitivity` asks for an ensemble.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sensitivity: Option<Sensitivity>,
}

impl ElasticStudy {
    /// The study measured against the fine-mesh reference, with the note's findings judged on
    /// its rates and its reference's rate-bias bounds.
    pub fn judged(measured: FineMeshStudy) -> Self {
        let FineMeshStudy {
            dimension,
            config,
            study,
            reference,
            sensitivity,
        } = measured;
        let findings = note_findings(&study, &|c, n| reference.case_bias(c, n));
        Self {
            dimension,
            config,
            study,
            reference,
            findings,
            sensitivity,
        }
    }

    /// The note's findings judged again from the study's rates and its reference's rate-bias
    /// bounds: what the study itself computed, since the findings are a function of both alone.
    pub fn judged_findings(&self) -> Vec<Finding> {
        note_findings(&self.study, &|c, n| self.reference.case_bias(c, n))
    }
}

/// The study of `config` on `problem` against its fine-mesh reference
/// ([`run_fine_mesh_study`]: the reference read from `cache` when its key matches, computed
/// otherwise; `note` hears why a cache was not used), with the note's findings.
pub fn run_elastic_study(
    problem: &BoxProblem,
    config: &ElasticStudyConfig,
    cache: &ReferenceCache,
    note: &mut dyn FnMut(String),
) -> Result<(ElasticStudy, ElasticHistories), Error> {
    let (measured, histories) = run_fine_mesh_study(problem, config, cache, note)?;
    Ok((ElasticStudy::judged(measured), histories))
}
