//! What accuracy costs (`make report`): error against wall time per case (work–precision), and
//! the estimated time to reach a target error from the log–log fit `ln e = a + b ln s` over the
//! levels; the files of this section are `work-precision.md` and `work-precision.json`
//! ([`WorkPrecisionFile`]).

use std::fmt::Write as _;
use std::path::Path;

use serde::{Deserialize, Serialize};

use crate::harness::artifacts::{write_atomic, write_json};
use crate::harness::error::Error;
use crate::harness::norms::Norm;
use crate::harness::rates::fit_rate;
use crate::harness::study::{CaseStudy, Study};

/// The work–precision table and the cost to reach the targets, under a reports directory.
pub const WORK_PRECISION_MD: &str = "work-precision.md";

/// The title of `work-precision.md`.
const WORK_PRECISION_TITLE: &str = "# What accuracy costs";

/// [`WorkPrecisionFile`], under a reports directory.
pub const WORK_PRECISION_JSON: &str = "work-precision.json";

/// The norm of the markdown table and of the cost to reach the targets.
pub const COST_NORM: Norm = Norm::DisplacementLinfH;

/// What the measured seconds are.
const TIMING_NOTE: &str = "seconds are the wall time of each run inside the parallel study (2 \
                           runs at a time on 2 cores), setup + stepping + contact + observers";

/// The targets of the cost table, in `L∞(0,T;H)`.
pub const TARGETS: [f64; 3] = [1e-2, 3e-3, 1e-3];

/// One case's error against wall time for one norm.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct WorkPrecision {
    /// `scheme/mass`.
    pub case: String,
    /// Norm key.
    pub norm: Norm,
    /// Wall seconds of each level's run.
    pub seconds: Vec<f64>,
    /// `steps × dofs` of each level.
    pub dof_steps: Vec<usize>,
    /// The error of each level.
    pub errors: Vec<f64>,
}

/// The estimated cost of reaching a target error.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CostToTarget {
    /// `scheme/mass`.
    pub case: String,
    /// The target error.
    pub target: f64,
    /// Estimated wall seconds; `None` when the error does not decrease with cost.
    pub seconds: Option<f64>,
    /// Whether the target lies outside the measured error range.
    pub extrapolated: bool,
}

/// Work–precision data of every case and norm of a study.
pub fn work_precision(study: &Study) -> Vec<WorkPrecision> {
    study
        .cases
        .iter()
        .flat_map(|c| {
            c.rates.iter().map(move |r| WorkPrecision {
                case: c.case.id(),
                norm: r.norm,
                seconds: c.levels.iter().map(|l| l.timings.total()).collect(),
                dof_steps: c.levels.iter().map(|l| l.steps * l.dofs).collect(),
                errors: r.errors.clone(),
            })
        })
        .collect()
}

/// The cost of reaching `target` in `norm` for one case: with `ln e = b ln s + a` fitted over
/// the levels, `s* = exp((ln target − a) / b)`; no estimate when `b ≥ 0`.
pub fn cost_to_target(case: &CaseStudy, norm: Norm, target: f64) -> Option<CostToTarget> {
    let r = case.norm(norm)?;
    let seconds: Vec<f64> = case.levels.iter().map(|l| l.timings.total()).collect();
    let fit = fit_rate(&seconds, &r.errors)?;
    let (lo, hi) = r
        .errors
        .iter()
        .fold((f64::INFINITY, 0.0_f64), |(lo, hi), &e| {
            (lo.min(e), hi.max(e))
        });
    let seconds = (fit.rate < 0.0).then(|| ((target.ln() - fit.intercept) / fit.rate).exp());
    Some(CostToTarget {
        case: case.case.id(),
        target,
        seconds,
        extrapolated: !(lo..=hi).contains(&target),
    })
}

/// The cost of reaching each of [`TARGETS`] in `norm` for every case of `study`: target by
/// target, cases ranked by estimated time (no estimate last).
pub fn costs_to_targets(study: &Study, norm: Norm) -> Vec<CostToTarget> {
    let mut all = Vec::new();
    for target in TARGETS {
        let mut rows: Vec<CostToTarget> = study
            .cases
            .iter()
            .filter_map(|c| cost_to_target(c, norm, target))
            .collect();
        rows.sort_by(|a, b| {
            let key = |c: &CostToTarget| c.seconds.unwrap_or(f64::INFINITY);
            key(a).total_cmp(&key(b))
        });
        all.extend(rows);
    }
    all
}

/// The cost-to-target table of `costs` ([`costs_to_targets`] in `norm`): one block per target,
/// cases in the given order.
pub fn cost_table(costs: &[CostToTarget], norm: Norm) -> String {
    let mut md = String::new();
    for target in TARGETS {
        let _ = writeln!(
            md,
            "\n#### Target {} = {target:.0e}\n\n| rank | case | estimated wall time | |\n|---|---|---|---|",
            norm.key()
        );
        for (k, r) in costs.iter().filter(|r| r.target == target).enumerate() {
            let time = r.seconds.map_or(
                "not reached (error does not fall with cost)".to_string(),
                |s| format!("{s:.3e} s"),
            );
            let mark = if r.extrapolated { "extrapolated" } else { "" };
            let _ = writeln!(md, "| {} | {} | {} | {} |", k + 1, r.case, time, mark);
        }
    }
    md
}

/// `work-precision.json`: every case's error against wall time in every norm, and the cost to
/// reach the targets in [`COST_NORM`]. `make figures` reads it back.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct WorkPrecisionFile {
    /// The crate version that wrote it.
    pub signorini_version: String,
    /// What the seconds are.
    pub note: String,
    /// [`work_precision`] of the study.
    pub work_precision: Vec<WorkPrecision>,
    /// The norm of `cost_to_target`.
    pub cost_to_target_norm: Norm,
    /// [`costs_to_targets`] in that norm.
    pub cost_to_target: Vec<CostToTarget>,
}

/// `work-precision.md`: the error in [`COST_NORM`] against wall time per case and level, and
/// the cost-to-target table of `costs`.
pub fn render(study: &Study, costs: &[CostToTarget]) -> String {
    let norm = COST_NORM;
    let mut md = format!(
        "{WORK_PRECISION_TITLE}\n\nTables 1–2 study (`make report`), {TIMING_NOTE}. Error in {} \
         against wall time; the other norms are in `work-precision.json`.\n\n\
         | case | NX | dof-steps | wall s | ns per dof-step | {} |\n|---|---|---|---|---|---|\n",
        norm.label(),
        norm.key()
    );
    for c in &study.cases {
        let Some(r) = c.norm(norm) else { continue };
        for (l, e) in c.levels.iter().zip(&r.errors) {
            let dof_steps = l.steps * l.dofs;
            md.push_str(&format!(
                "| {} | {} | {} | {:.3e} | {:.1} | {:.3e} |\n",
                c.case.id(),
                l.nx,
                dof_steps,
                l.timings.total(),
                l.timings.total() * 1e9 / dof_steps as f64,
                e
            ));
        }
    }
    md.push_str(&format!(
        "\n## Cost to reach a target error\n\nFrom the least-squares fit of ln(error) on \
         ln(wall time) over the levels; *extrapolated* marks a target outside the measured \
         errors.\n{}",
        cost_table(costs, norm)
    ));
    md
}

/// The sections other studies keep in `work-precision.md` (the 2D and 3D boxes' costs), each
/// between the lines `<!-- NAME -->` and `<!-- /NAME -->`.
const KEPT_SECTIONS: [&str; 2] = ["box-2d", "box-3d"];

/// The opening and closing marker lines of section `name`.
fn markers(name: &str) -> (String, String) {
    (format!("<!-- {name} -->"), format!("<!-- /{name} -->"))
}

/// Section `name` of `text` with its markers, when there is one.
fn section<'t>(text: &'t str, name: &str) -> Option<&'t str> {
    let (open, close) = markers(name);
    let start = text.find(&open)?;
    let end = start + text[start..].find(&close)? + close.len();
    Some(&text[start..end])
}

/// The content of section `name` of `text`, without its markers.
fn section_body<'t>(text: &'t str, name: &str) -> Option<&'t str> {
    let (open, close) = markers(name);
    Some(section(text, name)?[open.len()..].trim_end_matches(close.as_str()))
}

/// `text` with section `name` replaced by `body` (appended when absent).
pub fn splice_section(text: &str, name: &str, body: &str) -> String {
    let (open, close) = markers(name);
    let new = format!("{open}\n{}\n{close}", body.trim());
    match section(text, name) {
        Some(old) => text.replacen(old, &new, 1),
        None => format!("{}\n\n{new}\n", text.trim_end()),
    }
}

/// Writes `out_dir/work-precision.md` as `kept_from/work-precision.md` (the reports directory a
/// staged `out_dir` will replace files of) with section `name` replaced by `body`; a missing
/// file is started with its title (`make report-fine`'s directory has no Tables study).
pub fn write_work_precision_section(
    out_dir: &Path,
    kept_from: &Path,
    name: &str,
    body: &str,
) -> Result<(), Error> {
    let text = std::fs::read_to_string(kept_from.join(WORK_PRECISION_MD))
        .unwrap_or_else(|_| WORK_PRECISION_TITLE.to_string());
    write_atomic(
        &out_dir.join(WORK_PRECISION_MD),
        splice_section(&text, name, body).as_bytes(),
    )
}

/// `work-precision.md` and `work-precision.json` of `study` into `out_dir`, keeping the
/// [`KEPT_SECTIONS`] of `kept_from/work-precision.md` (the reports directory a staged `out_dir`
/// will replace files of).
pub fn write_work_precision(study: &Study, out_dir: &Path, kept_from: &Path) -> Result<(), Error> {
    let costs = costs_to_targets(study, COST_NORM);
    let file = WorkPrecisionFile {
        signorini_version: env!("CARGO_PKG_VERSION").to_string(),
        note: TIMING_NOTE.to_string(),
        work_precision: work_precision(study),
        cost_to_target_norm: COST_NORM,
        cost_to_target: costs,
    };
    let path = out_dir.join(WORK_PRECISION_MD);
    let previous = std::fs::read_to_string(kept_from.join(WORK_PRECISION_MD)).unwrap_or_default();
    let text = KEPT_SECTIONS
        .iter()
        .filter_map(|name| Some((name, section_body(&previous, name)?)))
        .fold(render(study, &file.cost_to_target), |text, (name, kept)| {
            splice_section(&text, name, kept)
        });
    write_atomic(&path, text.as_bytes())?;
    write_json(&out_dir.join(WORK_PRECISION_JSON), &file)?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_section_is_replaced_in_place_and_appended_when_absent() {
        let text = splice_section("# Costs\n\n1D table", "box-2d", "2D table");
        assert_eq!(
            text,
            "# Costs\n\n1D table\n\n<!-- box-2d -->\n2D table\n<!-- /box-2d -->\n"
        );
        let text = splice_section(&text, "box-3d", "3D table");
        let text = splice_section(&text, "box-2d", "new 2D table");
        assert!(text.contains("<!-- box-2d -->\nnew 2D table\n<!-- /box-2d -->"));
        assert!(!text.contains("\n2D table"));
        assert!(text.ends_with("<!-- box-3d -->\n3D table\n<!-- /box-3d -->\n"));
        assert_eq!(
            section_body(&text, "box-3d").map(str::trim),
            Some("3D table")
        );
    }
}
