//! Tables 1–2 beside the paper's: the two tables in the paper's layout, the entries not shown
//! to agree with it and what the harness shows about each ([`Disagreement::diagnosis`]).
//!
//! An entry agrees with the paper when its 95 % interval lies within
//! `[paper − PAPER_AGREEMENT, paper + PAPER_AGREEMENT]` (the exact solution is the reference:
//! no bias bound), differs when it lies entirely outside, and is undecided otherwise, a rate
//! without an interval included ([`crate::harness::study::decision`]). A round-off chaotic
//! case is judged by its ensemble instead ([`EnsembleRate`]): the median, with the members'
//! `[min, max]` joined with each member's own 95 % fit interval in the interval's place (the
//! members' rates are samples of what round-off gives, and each of them is itself a fit with its
//! own uncertainty: the interval must hold both).

use std::fmt::Write as _;

use super::paper::PaperTables;
use crate::harness::render::report::{chaotic_rate, chaotic_spread, fmt_fit};
use crate::harness::run::norms::Norm;
use crate::harness::study::decision::{Decision, Estimate, Verdict};
use crate::harness::study::rates::RateFit;
use crate::harness::study::sensitivity::{Sensitivity, Spread};

/// A round-off chaotic case's rate of one norm by its ensemble: the spread of the members'
/// rates and the interval the agreement is decided on.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EnsembleRate {
    /// The members' minimum, median and maximum rate.
    pub spread: Spread,
    /// `[min, max]` joined with the members' own 95 % fit intervals
    /// ([`crate::harness::study::sensitivity::CaseSensitivity::rate_interval`]).
    pub interval: (f64, f64),
}

/// The ensemble of `c`'s rate of `norm` when `sensitivity` classes the case round-off chaotic.
fn chaotic_ensemble(
    c: &CaseStudy,
    norm: Norm,
    sensitivity: Option<&Sensitivity>,
) -> Option<EnsembleRate> {
    let spread = chaotic_spread(c, norm, sensitivity)?;
    let interval = sensitivity?.case(&c.case.id())?.rate_interval(norm.key())?;
    Some(EnsembleRate { spread, interval })
}
use crate::harness::study::verdicts::{oscillation_ratio_text, oscillation_word};
use crate::harness::study::{CaseStudy, Study};

/// The columns of Table 1 (displacement).
pub const TABLE1: [Norm; 4] = [
    Norm::DisplacementLinfH,
    Norm::DisplacementL2H,
    Norm::DisplacementLinfV,
    Norm::DisplacementL2V,
];

/// The rate columns of Table 2 (multiplier and energy; the oscillation column sits between
/// the first and the other two).
pub const TABLE2: [Norm; 3] = [Norm::MultiplierL2, Norm::EnergyLinf, Norm::EnergyL2];

/// Agreement threshold with the paper's rates: an entry agrees when its interval lies within
/// this distance of the paper's value.
pub const PAPER_AGREEMENT: f64 = 0.1;

fn rate_of(c: &CaseStudy, norm: Norm) -> Option<RateFit> {
    c.norm(norm).and_then(|r| r.fit)
}

fn cell(
    c: &CaseStudy,
    norm: Norm,
    paper: Option<f64>,
    sensitivity: Option<&Sensitivity>,
) -> String {
    if let Some(s) = chaotic_spread(c, norm, sensitivity) {
        let ours = chaotic_rate(&s);
        return match paper {
            Some(p) => format!("{ours} ({p:.2}, {:+.2})", s.median - p),
            None => ours,
        };
    }
    match (rate_of(c, norm), paper) {
        (Some(f), Some(p)) => format!("{:.2} ({:.2}, {:+.2})", f.rate, p, f.rate - p),
        (Some(f), None) => format!("{:.2}", f.rate),
        (None, _) => "—".to_string(),
    }
}

/// Tables 1 and 2 in the paper's layout: each cell is `ours (paper, ours − paper)`. With a
/// sensitivity study, a round-off chaotic case shows its ensemble median rate and range, marked
/// `†`, instead of the one sample that the unperturbed run is.
pub fn paper_tables(
    study: &Study,
    paper: &PaperTables,
    sensitivity: Option<&Sensitivity>,
) -> String {
    let mut out = String::new();
    let _ = writeln!(out, "### Table 1: convergence rates for the displacement\n");
    let _ = writeln!(
        out,
        "| Scheme | Mass | {} |",
        TABLE1.map(Norm::label).join(" | ")
    );
    let _ = writeln!(out, "|---|---|{}", "---|".repeat(TABLE1.len()));
    for c in &study.cases {
        let row = paper.row(&c.case);
        let cells: Vec<String> = TABLE1
            .iter()
            .map(|&n| cell(c, n, row.map(|r| r.rate(n)), sensitivity))
            .collect();
        let _ = writeln!(
            out,
            "| {} | {} | {} |",
            c.case.scheme.label(),
            c.case.mass.paper_label(),
            cells.join(" | ")
        );
    }
    let _ = writeln!(
        out,
        "\n### Table 2: convergence rates for the Lagrange multiplier and the energy\n"
    );
    let _ = writeln!(
        out,
        "| Scheme | Mass | {} | Oscillations (TV ratio; paper) | {} | {} |",
        TABLE2[0].label(),
        TABLE2[1].label(),
        TABLE2[2].label()
    );
    let _ = writeln!(out, "|---|---|---|---|---|---|");
    for c in &study.cases {
        let row = paper.row(&c.case);
        let osc = match c.oscillation_indicator() {
            Some(r) => format!(
                "{} ({}; {})",
                oscillation_word(r),
                oscillation_ratio_text(r),
                row.map_or("—", |r| r.oscillations.as_str())
            ),
            None => "—".to_string(),
        };
        let rates: Vec<String> = TABLE2
            .iter()
            .map(|&n| cell(c, n, row.map(|r| r.rate(n)), sensitivity))
            .collect();
        let _ = writeln!(
            out,
            "| {} | {} | {} | {} | {} | {} |",
            c.case.scheme.label(),
            c.case.mass.paper_label(),
            rates[0],
            osc,
            rates[1],
            rates[2]
        );
    }
    out
}

/// One entry not shown to agree with the paper within [`PAPER_AGREEMENT`]: it differs, or its
/// interval cannot tell.
#[derive(Debug, Clone, PartialEq)]
pub struct Disagreement {
    /// `fails` (it differs) or `undecided`, with the interval it was decided on.
    pub decision: Decision,
    /// `scheme/mass`.
    pub case: String,
    /// The norm.
    pub norm: Norm,
    /// Our rate (all levels).
    pub ours: RateFit,
    /// Our rate over the last three levels.
    pub last_three: Option<f64>,
    /// Our rate over the first three levels.
    pub first_three: Option<f64>,
    /// Our rate over all levels with a longer horizon, when it was computed.
    pub longer_horizon: Option<f64>,
    /// The paper's rate.
    pub paper: f64,
    /// Our rate by its ensemble when the case is round-off chaotic.
    pub ensemble: Option<EnsembleRate>,
}

impl Disagreement {
    /// What the harness shows about the difference, decided mechanically.
    pub fn diagnosis(&self, longer_horizon: f64) -> String {
        let near = |x: Option<f64>| x.is_some_and(|v| (v - self.paper).abs() <= PAPER_AGREEMENT);
        let mut reasons = Vec::new();
        if let Some(EnsembleRate { spread: e, .. }) = self.ensemble {
            let (verdict, place) = if (e.min..=e.max).contains(&self.paper) {
                ("round-off noise", "inside")
            } else {
                ("not round-off noise", "outside")
            };
            reasons.push(format!(
                "{verdict}: the paper's value is {place} our ensemble range [{:.2}, {:.2}] \
                 (chaotic case)",
                e.min, e.max
            ));
        }
        if let (Some(lo), Some(hi)) = (self.ours.ci_low, self.ours.ci_high) {
            if (lo..=hi).contains(&self.paper) {
                reasons.push("the paper's value is inside our 95 % interval".to_string());
            }
        }
        if near(self.first_three) {
            reasons.push("our coarse levels (first three) give the paper's slope".to_string());
        }
        if near(self.last_three) {
            reasons.push("our finest levels (last three) give the paper's slope".to_string());
        }
        if near(self.longer_horizon) {
            reasons.push(format!(
                "with T = {longer_horizon} our slope is the paper's"
            ));
        }
        if reasons.is_empty() {
            "not explained by the level range, the interval or the horizon".to_string()
        } else {
            reasons.join("; ")
        }
    }
}

/// Whether the rate of `norm` agrees with the paper's `paper` (see the module): by `fit`, or
/// by the ensemble of a chaotic case (its median, and `[min, max]` joined with the members' fit
/// intervals).
pub fn agreement(
    norm: Norm,
    fit: Option<RateFit>,
    ensemble: Option<EnsembleRate>,
    paper: f64,
) -> Decision {
    let what = format!("{} rate", norm.key());
    let estimate = match ensemble {
        Some(e) => Estimate::of_ensemble(
            format!("{what} (ensemble median, [min, max] ∪ members' 95 % intervals)"),
            e.spread.median,
            e.interval,
            fit.map_or(0, |f| f.levels),
        ),
        None => Estimate::rate(what, fit, Some(0.0)),
    };
    estimate.within(paper - PAPER_AGREEMENT, paper + PAPER_AGREEMENT)
}

/// Every entry of `study` not shown to agree with the paper ([`agreement`]); for a round-off
/// chaotic case (by `sensitivity`), by its ensemble.
pub fn disagreements(
    study: &Study,
    paper: &PaperTables,
    sensitivity: Option<&Sensitivity>,
) -> Vec<Disagreement> {
    let mut out = Vec::new();
    for c in &study.cases {
        let Some(row) = paper.row(&c.case) else {
            continue;
        };
        for r in &c.rates {
            let Some(fit) = r.fit else { continue };
            let p = row.rate(r.norm);
            let ensemble = chaotic_ensemble(c, r.norm, sensitivity);
            let decision = agreement(r.norm, Some(fit), ensemble, p);
            if decision.verdict != Verdict::Holds {
                out.push(Disagreement {
                    decision,
                    case: c.case.id(),
                    norm: r.norm,
                    ours: fit,
                    last_three: r.fit_last_three.map(|f| f.rate),
                    first_three: r.fit_first_three.map(|f| f.rate),
                    longer_horizon: None,
                    paper: p,
                    ensemble,
                });
            }
        }
    }
    out
}

/// The verdict of an entry as the agreement section names it.
fn verdict_word(verdict: Verdict) -> &'static str {
    match verdict {
        Verdict::Holds => "agrees",
        Verdict::Fails => "differs",
        Verdict::Undecided => "undecided",
    }
}

/// The "Agreement with the paper" section.
pub fn disagreement_section(list: &[Disagreement], longer_horizon: f64) -> String {
    let mut out = String::new();
    let differ = list
        .iter()
        .filter(|d| d.decision.verdict == Verdict::Fails)
        .count();
    let _ = writeln!(
        out,
        "{} entries are not shown to agree with the paper within {PAPER_AGREEMENT}: an entry \
         agrees when our 95 % interval (for a round-off chaotic case, †: the ensemble's [min, \
         max] joined with its members' own 95 % intervals) lies within the paper's value ± {PAPER_AGREEMENT}, *differs* when it lies \
         entirely outside ({differ} entries) and is *undecided* when it overlaps an end ({} \
         entries). For each: our rate over all levels with that interval (†: the ensemble \
         median), over the first and the last three levels, over all levels with T = \
         {longer_horizon} (these three of the unperturbed run), the verdict, and what these \
         show.\n",
        list.len(),
        list.len() - differ
    );
    let _ = writeln!(
        out,
        "| Case | Norm | ours | first 3 | last 3 | T = {longer_horizon} | paper | verdict | what the harness shows |"
    );
    let _ = writeln!(out, "|---|---|---|---|---|---|---|---|---|");
    let f = |x: Option<f64>| x.map_or("—".to_string(), |v| format!("{v:.2}"));
    for d in list {
        let ours = d.ensemble.map_or_else(
            || fmt_fit(Some(d.ours)),
            |EnsembleRate {
                 spread: e,
                 interval: (low, high),
             }| {
                format!(
                    "{:.2}† [{:.2}, {:.2}] ∪ fits [{low:.2}, {high:.2}]",
                    e.median, e.min, e.max
                )
            },
        );
        let _ = writeln!(
            out,
            "| {} | {} | {ours} | {} | {} | {} | {:.2} | {}: {} | {} |",
            d.case,
            d.norm.key(),
            f(d.first_three),
            f(d.last_three),
            f(d.longer_horizon),
            d.paper,
            verdict_word(d.decision.verdict),
            d.decision.reason,
            d.diagnosis(longer_horizon)
        );
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn fit(rate: f64, half: Option<f64>) -> RateFit {
        RateFit {
            rate,
            intercept: 0.0,
            ci_low: half.map(|h| rate - h),
            ci_high: half.map(|h| rate + h),
            levels: if half.is_some() { 7 } else { 2 },
        }
    }

    #[test]
    fn an_entry_agrees_differs_or_is_undecided_by_its_interval() {
        let norm = Norm::DisplacementLinfH;
        let near = agreement(norm, Some(fit(0.50, Some(0.03))), None, 0.48);
        assert_eq!(near.verdict, Verdict::Holds, "{}", near.reason);
        let far = agreement(norm, Some(fit(0.86, Some(0.05))), None, 0.47);
        assert_eq!(far.verdict, Verdict::Fails, "{}", far.reason);
        let wide = agreement(norm, Some(fit(0.60, Some(0.15))), None, 0.49);
        assert_eq!(wide.verdict, Verdict::Undecided, "{}", wide.reason);
        let close_but_no_interval = agreement(norm, Some(fit(0.49, None)), None, 0.49);
        assert_eq!(close_but_no_interval.verdict, Verdict::Undecided);
    }

    fn ensemble(median: f64, min: f64, max: f64, fits: (f64, f64)) -> EnsembleRate {
        let spread = Spread { median, min, max };
        EnsembleRate {
            spread,
            interval: (min.min(fits.0), max.max(fits.1)),
        }
    }

    #[test]
    fn a_chaotic_entry_is_judged_by_its_ensemble_range_and_its_members_intervals() {
        let norm = Norm::EnergyL2;
        let outside = agreement(
            norm,
            None,
            Some(ensemble(0.82, 0.75, 0.92, (0.7, 0.97))),
            0.48,
        );
        assert_eq!(outside.verdict, Verdict::Fails, "{}", outside.reason);
        let inside = agreement(
            norm,
            None,
            Some(ensemble(0.50, 0.45, 0.55, (0.43, 0.57))),
            0.48,
        );
        assert_eq!(inside.verdict, Verdict::Holds, "{}", inside.reason);
        let wide_members = ensemble(0.50, 0.45, 0.55, (0.30, 0.62));
        let undecided = agreement(norm, None, Some(wide_members), 0.48);
        assert_eq!(
            undecided.verdict,
            Verdict::Undecided,
            "{}",
            undecided.reason
        );
        assert!(
            undecided.reason.contains("[0.30, 0.62]"),
            "{}",
            undecided.reason
        );
    }
}
