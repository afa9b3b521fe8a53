//! What accuracy costs (`make report`): error against wall time per case (work–precision), and
//! the estimated time to reach a target error from the log–log fit `ln e = a + b ln s` over the
//! levels. `signorini report` writes this section's data, `work-precision.json`
//! ([`WorkPrecisionFile`]); its page, `work-precision.md`, gathers the Tables study and the 2D/3D
//! studies, and the render step builds it from their data files ([`work_precision_page`]).

use std::fmt::Write as _;
use std::path::Path;

use serde::{Deserialize, Serialize};

use crate::harness::files::artifacts::write_json;
use crate::harness::run::norms::Norm;
use crate::harness::study::rates::fit_rate;
use crate::harness::study::{CaseStudy, Study};
use crate::studies::error::Error;

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

/// What `work-precision.md` takes of a box study's `elastic-{d}d.json` (its other fields are
/// not needed here).
#[derive(Debug, Deserialize)]
pub struct BoxCosts {
    dimension: usize,
    study: Study,
    reference: ReferenceCost,
}

/// The reference run of a box study, as `elastic-{d}d.json` records it.
#[derive(Debug, Deserialize)]
struct ReferenceCost {
    case: String,
    level: usize,
    dofs: usize,
    steps: usize,
    seconds: f64,
    next_coarser: usize,
    from_cache: bool,
}

/// The `d`-D box section of `work-precision.md`: the wall time per dof-step of every case and
/// level of the study, and of its reference run.
fn box_section(costs: &BoxCosts) -> String {
    let d = costs.dimension;
    let norm = COST_NORM;
    let mut md = format!(
        "## {d}D bar (note §3): cost per dof-step\n\n\
         The {d}D study's runs (`elastic-{d}d.md`): wall time of each run inside the parallel \
         study (2 runs at a time on 2 cores), setup + stepping + contact + the comparison with \
         the reference; the step solver is the default (`auto`: the sparse Cholesky in 2D and \
         below 10 000 unknowns in 3D, matrix-free CG above). Error in {} against the \
         reference.\n\n\
         | case | level | unknowns | steps | dof-steps | wall s | ns per dof-step | {} |\n\
         |---|---|---|---|---|---|---|---|\n",
        norm.label(),
        norm.key()
    );
    for c in &costs.study.cases {
        let Some(r) = c.norm(norm) else { continue };
        for (l, e) in c.levels.iter().zip(&r.errors) {
            let dof_steps = l.steps * l.dofs;
            let _ = writeln!(
                md,
                "| {} | {} | {} | {} | {} | {:.3e} | {:.1} | {:.3e} |",
                c.case.id(),
                l.nx,
                l.dofs,
                l.steps,
                dof_steps,
                l.timings.total(),
                l.timings.total() * 1e9 / dof_steps as f64,
                e
            );
        }
    }
    let r = &costs.reference;
    let dof_steps = (r.dofs * r.steps) as f64;
    let _ = writeln!(
        md,
        "\nThe reference ({} on {} elements along the axis): {} unknowns × {} steps in {:.1} s, \
         {:.1} ns per dof-step, with the check run on {} elements beside it and the projections \
         on every level recorded as it runs ({}).",
        r.case,
        r.level,
        r.dofs,
        r.steps,
        r.seconds,
        r.seconds * 1e9 / dof_steps,
        r.next_coarser,
        if r.from_cache {
            "the run that filled the cache"
        } else {
            "computed for this study"
        }
    );
    md
}

/// `work-precision.md` of the Tables study `tables` ([`render`], its title alone without one)
/// and of the box studies `boxes` ([`box_section`], in the order given). The render step reads
/// them from a reports directory's `rates.json` and `elastic-2d.json`, `elastic-3d.json`.
pub fn work_precision_page(tables: Option<&Study>, boxes: &[BoxCosts]) -> String {
    let mut md = match tables {
        Some(study) => render(study, &costs_to_targets(study, COST_NORM)),
        None => WORK_PRECISION_TITLE.to_string(),
    };
    for costs in boxes {
        md = format!("{}\n\n{}", md.trim_end(), box_section(costs));
    }
    md
}

/// Writes `work-precision.json` of `study` into `out_dir`.
pub fn write_work_precision_json(study: &Study, out_dir: &Path) -> Result<(), Error> {
    let file = WorkPrecisionFile {
        signorini_version: env!("CARGO_PKG_VERSION").to_string(),
        note: TIMING_NOTE.to_string(),
        work_precision: work_precision(study),
        cost_to_target_norm: COST_NORM,
        cost_to_target: costs_to_targets(study, COST_NORM),
    };
    Ok(write_json(&out_dir.join(WORK_PRECISION_JSON), &file)?)
}
