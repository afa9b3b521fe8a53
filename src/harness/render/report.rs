//! Markdown rendering of a study: the per-level convergence tables, and the cells of a round-off
//! chaotic case's rate. It renders what the analysis (`crate::harness::study`,
//! `crate::harness::study::sensitivity`) computed and fits nothing.

use std::fmt::Write as _;

use crate::harness::run::norms::Norm;
use crate::harness::run::physics::{
    Physics, ENERGY_GAIN_TOLERANCE, FACE_SCALE_FLOOR, PENETRATION_TOLERANCE,
};
use crate::harness::study::rates::RateFit;
use crate::harness::study::sensitivity::{Sensitivity, Spread};
use crate::harness::study::{CaseStudy, LevelRecord, NormRates, Study};

/// The ensemble spread of the rate of `norm` when `c` is round-off chaotic in `sensitivity`.
pub(crate) fn chaotic_spread(
    c: &CaseStudy,
    norm: Norm,
    sensitivity: Option<&Sensitivity>,
) -> Option<Spread> {
    let s = sensitivity?.case(&c.case.id())?;
    if !s.chaotic {
        return None;
    }
    s.rates.get(norm.key()).copied()
}

/// A round-off chaotic case's rate: the ensemble median marked `†`, then `[min, max]`.
pub(crate) fn chaotic_rate(s: &Spread) -> String {
    format!("{:.2}† [{:.2}, {:.2}]", s.median, s.min, s.max)
}

/// A fit as `rate [ci_low, ci_high]` (the 95 % interval when defined), `—` when undefined.
pub(crate) fn fmt_fit(f: Option<RateFit>) -> String {
    match f {
        Some(RateFit {
            rate,
            ci_low: Some(lo),
            ci_high: Some(hi),
            ..
        }) => format!("{rate:.2} [{lo:.2}, {hi:.2}]"),
        Some(f) => format!("{:.2}", f.rate),
        None => "—".to_string(),
    }
}

/// For every case, the errors of every norm per level with the observed order, then the
/// least-squares rate over all levels (95 % interval) and over the last three, then what the
/// time loop measured of its runs' physics ([`physics_paragraph`]).
pub fn convergence_tables(study: &Study) -> String {
    let tables: String = study
        .cases
        .iter()
        .map(|c| {
            let mut heading = format!("{} — {}", c.case.scheme.label(), c.case.mass.name());
            let physics = study.physics.get(&c.case.id());
            if physics.is_some_and(|levels| levels.iter().any(Physics::flagged)) {
                heading.push_str(" — **physics flagged**");
            }
            let mut table = convergence_table(&heading, &c.levels, &c.rates);
            if let Some(levels) = physics {
                table.push_str(&physics_paragraph(&c.levels, levels));
            }
            table
        })
        .collect();
    tables + &not_run_section(study)
}

/// The physics of a case's runs, one per level ([`Physics`]): every flagged level with its
/// figures (`- **NX = 320**: penetrates 4.767e-1 (95.647 % of D = 4.984e-1) at t = 8.3406`), or,
/// when none is flagged, the largest judged penetration `p / max(D, D_min)` and the largest
/// `E_max/E_0` over the levels, so a reader sees how far from its tolerance each stayed.
pub fn physics_paragraph(levels: &[LevelRecord], physics: &[Physics]) -> String {
    let flagged: String = levels
        .iter()
        .zip(physics)
        .filter_map(|(level, p)| p.flags().map(|f| format!("- **NX = {}**: {f}\n", level.nx)))
        .collect();
    if !flagged.is_empty() {
        return format!(
            "Physics flagged (tolerances: penetration {} % of the face's displacement scale, \
             energy gain {} % of E_0):\n\n{flagged}\n",
            100.0 * PENETRATION_TOLERANCE,
            100.0 * ENERGY_GAIN_TOLERANCE
        );
    }
    let worst = |f: fn(&Physics) -> f64| physics.iter().map(f).fold(f64::NAN, f64::max);
    format!(
        "Physics, every level: largest p / max(D, {FACE_SCALE_FLOOR:e}) {:.1e} (tolerance {PENETRATION_TOLERANCE:e}), \
         largest energy gain (E_max − E_0)/|E_0| {:.1e} (tolerance {ENERGY_GAIN_TOLERANCE:e}), \
         no pulling contact force: nothing flagged.\n\n",
        worst(Physics::judged_penetration),
        worst(Physics::energy_gain),
    )
}

/// The cases of `study` not run to completion, each with the level and the reason its run
/// stopped; empty when there are none.
pub fn not_run_section(study: &Study) -> String {
    if study.not_run.is_empty() {
        return String::new();
    }
    let mut out = String::from(
        "#### Not run

These cases have no errors or rates: a run of theirs stopped before the \
         horizon, and a run that stopped has no norm.\n\n| case | level | why the run stopped |\n\
         |---|---|---|\n",
    );
    for n in &study.not_run {
        let _ = writeln!(out, "| {} | {} | {} |", n.case.id(), n.nx, n.reason());
    }
    out.push('\n');
    out
}

/// One series of levels under the heading `heading`: the errors of every norm per level with
/// the observed order, then the least-squares rate over all levels (95 % interval) and over the
/// last three (the row says it fits all of them when there are three or fewer).
pub fn convergence_table(heading: &str, levels: &[LevelRecord], rates: &[NormRates]) -> String {
    let mut out = String::new();
    let _ = writeln!(out, "#### {heading}\n");
    let _ = write!(out, "| NX | h | Δt |");
    for r in rates {
        let _ = write!(out, " {} | order |", r.norm.key());
    }
    let _ = writeln!(out);
    let _ = writeln!(out, "|---|---|---|{}", "---|---|".repeat(rates.len()));
    for (k, level) in levels.iter().enumerate() {
        let _ = write!(out, "| {} | {:.3e} | {:.3e} |", level.nx, level.h, level.dt);
        for r in rates {
            let order = r.orders[k].map_or("—".to_string(), |o| format!("{o:.2}"));
            let _ = write!(out, " {:.3e} | {} |", r.errors[k], order);
        }
        let _ = writeln!(out);
    }
    let _ = write!(out, "| fit, all levels (95 % CI) | | |");
    for r in rates {
        let _ = write!(out, " {} | |", fmt_fit(r.fit));
    }
    let _ = writeln!(out);
    let last = match levels.len() {
        n if n > 3 => "fit, last three levels".to_string(),
        n => format!("fit, last {n} levels (all of them)"),
    };
    let _ = write!(out, "| {last} | | |");
    for r in rates {
        let _ = write!(out, " {} | |", fmt_fit(r.fit_last_three));
    }
    let _ = writeln!(out, "\n");
    out
}

/// A user's words (a series' label, a code's name, a contact treatment in its own words) as the
/// text of a markdown table cell or heading: each `|` escaped and every control character (a
/// newline among them) shown as a space, so that no text given on the command line can end its
/// cell or its row and forge another.
pub fn table_text(words: &str) -> String {
    words
        .chars()
        .map(|c| if c.is_control() { ' ' } else { c })
        .collect::<String>()
        .replace('|', "\\|")
}
