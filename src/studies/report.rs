//! What `signorini report` runs for the 1D tables (beside the gravity benchmark,
//! `crate::studies::gravity`, and the extended table, `crate::studies::extended`): the Tables
//! 1–2 study once, then each section that reads it writes its own files.

use std::path::Path;

use crate::harness::files::error::Error;
use crate::harness::study::{Case, Study};
use crate::studies::cost::{write_work_precision_json, write_work_precision_md};
use crate::studies::histories::{write_histories, HISTORY_LEVELS};
use crate::studies::tables::{
    tables_sensitivity, tables_study, write_sensitivity_files, write_tables,
};

/// Runs the Tables 1–2 study and its round-off sensitivity and writes, into `out_dir`, the
/// sensitivity (`sensitivity.md`, `sensitivity.json`), the tables beside the paper's
/// (`tables.md`, `rates.json`), what accuracy costs (`work-precision.md`,
/// `work-precision.json`) and the histories of the figures (`data/histories/`); returns the
/// study. `kept_from` is the reports directory a staged `out_dir` will replace files of:
/// `work-precision.md` takes the 2D/3D studies' data from it.
pub fn write_report(root: &Path, out_dir: &Path, kept_from: &Path) -> Result<Study, Error> {
    let study = tables_study(root)?;
    let cases: Vec<Case> = study.cases.iter().map(|c| c.case).collect();
    let sensitivity = tables_sensitivity(root, &cases)?;
    write_sensitivity_files(&sensitivity, out_dir)?;
    write_tables(root, &study, &sensitivity, out_dir)?;
    write_work_precision_json(&study, out_dir)?;
    write_work_precision_md(out_dir, kept_from)?;
    write_histories(root, out_dir, &HISTORY_LEVELS)?;
    Ok(study)
}
