//! The files of a 2D/3D study under a reports directory: `elastic-<d>d.md`, `elastic-<d>d.json`
//! ([`ElasticStudy`]: the study, the reference check and the findings) and
//! `data/elastic-<d>d-histories.json` ([`super::ElasticHistories`], the figure data), which
//! `make figures` reads back (the fine-mesh references are in the user's cache,
//! [`crate::harness::reference::fine_mesh::cache::user_cache`]).
//! The render step builds `work-precision.md` from the studies' data, this one's included
//! ([`crate::studies::render`]).

use std::path::Path;

use super::ElasticStudy;
use crate::harness::files::artifacts::{write_atomic, write_json, write_json_compact};
use crate::harness::reference::fine_mesh::ElasticHistories;
use crate::studies::error::Error;

/// The report of the `dimension`-D study, under a reports directory.
pub fn report_file(dimension: usize) -> String {
    format!("elastic-{dimension}d.md")
}

/// The `dimension`-D study ([`ElasticStudy`]), under a reports directory.
pub fn study_file(dimension: usize) -> String {
    format!("elastic-{dimension}d.json")
}

/// The figure data of the `dimension`-D study ([`super::ElasticHistories`]), under a reports
/// directory.
pub fn histories_file(dimension: usize) -> String {
    format!("data/elastic-{dimension}d-histories.json")
}

/// Writes a 2D/3D study's report, the study and its figure data (`histories`) into `out_dir`;
/// the report says it was made by `command`. Returns the files written, relative to `out_dir`.
pub fn write_elastic_files(
    study: &ElasticStudy,
    histories: &ElasticHistories,
    out_dir: &Path,
    command: &str,
) -> Result<Vec<String>, Error> {
    let d = study.dimension;
    write_atomic(
        &out_dir.join(report_file(d)),
        super::report::render(study, command).as_bytes(),
    )?;
    write_json(&out_dir.join(study_file(d)), study)?;
    write_json_compact(&out_dir.join(histories_file(d)), histories)?;
    Ok(vec![report_file(d), study_file(d), histories_file(d)])
}
