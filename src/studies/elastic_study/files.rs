//! The files of a 2D/3D study under a reports directory: `elastic-<d>d.md`, `elastic-<d>d.json`
//! ([`ElasticStudy`]: the study, the reference check and the findings) and
//! `data/elastic-<d>d-histories.json` ([`super::ElasticHistories`], the figure data), which
//! `make figures` reads back; the fine-mesh references are cached under [`REFERENCE_CACHE`].
//! `work-precision.md` is rendered again from the studies' data, this one's included
//! ([`crate::studies::cost::render_work_precision`]).

use std::path::Path;

use super::{run_elastic_study, ElasticStudy};
use crate::harness::files::artifacts::{write_atomic, write_json, write_json_compact};
use crate::harness::reference::fine_mesh::cache::ReferenceCache;
use crate::harness::reference::fine_mesh::{ElasticHistories, ElasticStudyConfig};
use crate::harness::run::elastic::BoxProblem;
use crate::studies::cost::{write_work_precision_md, WORK_PRECISION_MD};
use crate::studies::error::Error;

/// Where the fine-mesh references of the 2D/3D studies are cached, under a reports directory.
pub const REFERENCE_CACHE: &str = "data/references";

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

/// Runs a 2D/3D study and writes its report, the study and the figure data into `out_dir`,
/// and `work-precision.md` rendered from the studies' data in `out_dir` and `kept_from` (the
/// reports directory a staged `out_dir` will replace files of); the reference is looked up (and kept) in
/// `cache`; the report says it was made by `command`.
pub fn write_elastic_report(
    problem: &BoxProblem,
    config: &ElasticStudyConfig,
    out_dir: &Path,
    kept_from: &Path,
    cache: &ReferenceCache,
    command: &str,
    note: &mut dyn FnMut(String),
) -> Result<ElasticStudy, Error> {
    let (study, histories) = run_elastic_study(problem, config, cache, note)?;
    write_elastic_files(&study, &histories, out_dir, kept_from, command)?;
    Ok(study)
}

/// Writes a 2D/3D study's report, the study and its figure data (`histories`) into `out_dir`,
/// and `work-precision.md` rendered from the studies' data in `out_dir` and `kept_from`; the
/// report says it was made by `command`. Returns the files written, relative to `out_dir`.
pub fn write_elastic_files(
    study: &ElasticStudy,
    histories: &ElasticHistories,
    out_dir: &Path,
    kept_from: &Path,
    command: &str,
) -> Result<Vec<String>, Error> {
    let d = study.dimension;
    write_atomic(
        &out_dir.join(report_file(d)),
        super::report::render(study, command).as_bytes(),
    )?;
    write_json(&out_dir.join(study_file(d)), study)?;
    write_work_precision_md(out_dir, kept_from)?;
    write_json_compact(&out_dir.join(histories_file(d)), histories)?;
    Ok(vec![
        report_file(d),
        study_file(d),
        WORK_PRECISION_MD.to_string(),
        histories_file(d),
    ])
}
