//! A committed 2D/3D study judged again without recomputing it: its findings are a function of
//! its rates (with their intervals) and its reference's rate-bias bounds alone, all in its
//! `elastic-<d>d.json`, so the rule of [`super::findings`] can be applied to a study written
//! before the rule changed. The findings of the file (in whatever form it wrote them) are
//! replaced, and the report is rendered again as the study's own command would render it.

use std::path::Path;

use super::files::{report_file, study_file};
use super::{report, ElasticStudy, ElasticStudyConfig};
use crate::harness::files::artifacts::{read_json, write_atomic, write_json};
use crate::harness::files::error as files;
use crate::harness::files::error::ParameterError;
use crate::harness::files::input::REPORT_DATA;
use crate::harness::study::rates_inconsistency;
use crate::harness::study::scene::Scene;
use crate::studies::error::Error;

/// The command line that ran the study of `scene` into `out`, as its report names it.
pub fn study_command(scene: &Path, out: &Path) -> String {
    format!(
        "signorini study {} --out {}",
        scene.display(),
        out.display()
    )
}

/// Reads the study of `scene` under `reports` (`elastic-<d>d.json`) whatever form its findings
/// take, and refuses a study whose levels, reference level or ratio are not the scene's, or whose
/// cases' errors and rates are not what the study wrote ([`rates_inconsistency`]: errors shorter
/// than the levels, a negative error, a rate that is not the fit of its errors).
pub fn read_committed(scene: &Scene, reports: &Path) -> Result<ElasticStudy, Error> {
    let problem = scene.box_problem("a 2D/3D box scene: only its study has findings")?;
    let path = reports.join(study_file(problem.lengths.len()));
    let mut value: serde_json::Value = read_json(&path, REPORT_DATA)?;
    if let Some(findings) = value.get_mut("findings") {
        *findings = serde_json::Value::Array(Vec::new());
    }
    let study: ElasticStudy =
        serde_json::from_value(value).map_err(|source| files::Error::Decode {
            path: path.clone(),
            source,
        })?;
    let declared = ElasticStudyConfig::from_scene(scene, None)?;
    let same = (
        &study.config.levels,
        study.config.reference_level,
        study.config.ratio,
    ) == (&declared.levels, declared.reference_level, declared.ratio);
    if !same {
        let found = format!(
            "{}: levels {:?}, reference level {}, ratio {}",
            path.display(),
            study.config.levels,
            study.config.reference_level,
            study.config.ratio
        );
        return Err(ParameterError::new(
            "study file",
            found,
            "the study of the scene given: its levels, reference level and ratio",
        )
        .into());
    }
    for (k, case) in study.study.cases.iter().enumerate() {
        if let Some((field, value, allowed)) = rates_inconsistency(&case.levels, &case.rates) {
            return Err(ParameterError::new(
                "study file",
                format!(
                    "{}: study.cases[{k}].{field} = {value} (must be {allowed})",
                    path.display()
                ),
                "a study as `signorini study` wrote it: one finite error not below 0 per \
                 level, each fit the fit of its errors, levels of increasing NX",
            )
            .into());
        }
    }
    Ok(study)
}

/// The study of `scene` committed under `reports` with its findings judged again, and its
/// report and study written into `out_dir` (the staged `reports`); returns the files written,
/// relative to it.
pub fn rejudge(
    scene_path: &Path,
    reports: &Path,
    out_dir: &Path,
) -> Result<(ElasticStudy, Vec<String>), Error> {
    let scene = Scene::load(scene_path)?;
    let mut study = read_committed(&scene, reports)?;
    study.findings = study.judged_findings();
    let d = study.dimension;
    let command = study_command(scene_path, reports);
    write_atomic(
        &out_dir.join(report_file(d)),
        report::render(&study, &command).as_bytes(),
    )?;
    write_json(&out_dir.join(study_file(d)), &study)?;
    Ok((study, vec![report_file(d), study_file(d)]))
}
