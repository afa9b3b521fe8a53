//! What `signorini report` runs for the 1D tables (beside the gravity benchmark,
//! `crate::studies::gravity`, and the extended table, `crate::studies::extended`): the Tables
//! 1–2 study, its round-off sensitivity, the study again at the longer horizon, its M^mod cases
//! under the implicit-multiplier start and the histories of the figures, as five job lists that
//! depend on none of their results ([`tables_report`]); then each section that reads them
//! writes its own files ([`write_report`]).

use std::collections::BTreeSet;
use std::path::Path;

use crate::harness::reference::exact::ExactSolution;
use crate::harness::run::norms::Norm;
use crate::harness::study::executor::Batch;
use crate::harness::study::sensitivity::{
    EnsembleConfig, InitialNoise, Sensitivity, SensitivityJobs,
};
use crate::harness::study::{Case, Study, StudyConfig};
use crate::studies::benchmark::dirichlet;
use crate::studies::cost::write_work_precision_json;
use crate::studies::error::Error;
use crate::studies::histories::{write_histories, HistoryJobs, SchemeHistories, HISTORY_LEVELS};
use crate::studies::tables::starts::{implicit_start, massless_contact};
use crate::studies::tables::{write_sensitivity_files, write_tables, LONGER_HORIZON};

/// The results behind the 1D tables' files.
pub struct TablesReport {
    /// The Tables 1–2 study.
    pub study: Study,
    /// The round-off sensitivity of its cases.
    sensitivity: Sensitivity,
    /// The study at [`LONGER_HORIZON`], every case and norm.
    longer: Study,
    /// The study's M^mod cases under the implicit-multiplier start.
    implicit: Study,
    /// The histories of the figures.
    histories: Vec<SchemeHistories>,
}

/// Hands the 1D tables' job lists to `batch` and returns what they make (`None` for a shard):
/// the Tables 1–2 study (every paper case and every rival, [`Case::tables_matrix`], at the
/// default levels, all seven norms), the
/// round-off ensembles of every case, the study at [`LONGER_HORIZON`] of every case (so that the
/// list does not depend on which cases disagree with the paper: the disagreements look their
/// rates up in it), the M^mod cases under the implicit-multiplier start and the histories at
/// [`HISTORY_LEVELS`]. A case the study could not run keeps no ensemble and no implicit-start
/// run, as if they had not run. `root` is the repository root.
pub fn tables_report(root: &Path, batch: &mut Batch<'_>) -> Result<Option<TablesReport>, Error> {
    let config = StudyConfig::paper_default();
    let problem = dirichlet(root, config.horizon)?;
    let cases = Case::tables_matrix();
    let norms: BTreeSet<Norm> = Norm::ALL.into_iter().collect();
    let longer_config = StudyConfig {
        horizon: LONGER_HORIZON,
        ..config.clone()
    };
    let longer_problem = dirichlet(root, LONGER_HORIZON)?;
    let implicit_config = implicit_start(&config);
    let implicit_cases = massless_contact(cases.iter().copied());
    let study = ExactSolution::jobs(&problem, &cases, &norms, &config)?;
    let ensembles =
        SensitivityJobs::new(&problem, &cases, &norms, &config, EnsembleConfig::default())?;
    let longer = ExactSolution::jobs(&longer_problem, &cases, &norms, &longer_config)?;
    let implicit = ExactSolution::jobs(&problem, &implicit_cases, &norms, &implicit_config)?;
    let histories = HistoryJobs::new(root, &HISTORY_LEVELS)?;
    let ran = (
        batch.execute(&study.list())?,
        batch.execute(&ensembles.list())?,
        batch.execute(&longer.list())?,
        batch.execute(&implicit.list())?,
        batch.execute(&histories.list())?,
    );
    let (Some(runs), Some(members), Some(longer_runs), Some(implicit_runs), Some(history_runs)) =
        ran
    else {
        return Ok(None);
    };
    let study = study.reduce(runs, &cases);
    let kept: Vec<Case> = study.cases.iter().map(|c| c.case).collect();
    Ok(Some(TablesReport {
        sensitivity: ensembles.reduce(members, &kept)?,
        longer: longer.reduce(longer_runs, &cases),
        implicit: implicit.reduce(implicit_runs, &massless_contact(kept)),
        histories: histories.reduce(history_runs.results),
        study,
    }))
}

/// Writes, into `out_dir`, the sensitivity (`sensitivity.md`, `sensitivity.json`), the tables
/// beside the paper's (`tables.md`, `rates.json`, `rates-longer-horizon.json`), what accuracy
/// costs (`work-precision.json`) and the histories of the figures (`data/histories/`) of
/// `report`: this section's data and pages only. The pages that gather it with other sections'
/// data, `schemes.md` and `work-precision.md`, are the render step's
/// ([`crate::studies::render`]).
pub fn write_report(report: &TablesReport, out_dir: &Path) -> Result<(), Error> {
    let TablesReport {
        study,
        sensitivity,
        longer,
        implicit,
        histories,
    } = report;
    write_sensitivity_files(
        sensitivity,
        (InitialNoise::Displacement, "make report"),
        out_dir,
    )?;
    write_tables(study, sensitivity, longer, implicit, out_dir)?;
    write_work_precision_json(study, sensitivity, out_dir)?;
    write_histories(histories, out_dir)?;
    Ok(())
}
