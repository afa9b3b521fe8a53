//! The markdown report of a 2D/3D study: the rate table beside what the note's Figures 3 and 8
//! show (a round-off chaotic case's rate as its ensemble median and range), the findings, the
//! round-off sensitivity of every case, the reference check and the per-level errors.

use std::fmt::Write as _;

use super::findings::{convergence, Finding};
use super::ElasticStudy;
use crate::harness::render::report::{chaotic_rate, chaotic_spread, convergence_tables};
use crate::harness::run::norms::Norm;
use crate::harness::study::decision::Verdict;
use crate::harness::study::sensitivity::{
    class_rules, class_table, rate_ranges, Sensitivity, SensitivityClass,
};
use crate::harness::study::verdicts::{oscillation_word, OSCILLATES_FROM};
use crate::harness::study::CaseStudy;
use crate::harness::vocabulary::{convergence_word, ALIKE_RATE_GAP, CONVERGES_ABOVE};

/// What the note's convergence figures show for a case (scheme name, mass name) and norm:
/// "converges" or "does not converge" (§3.1 for Crank–Nicolson, Figure 3; §3.1.1 for backward
/// Euler, Figure 8: "the error curves converge for both methods"). The note prints curves, not
/// rates, so this is the only comparison it allows.
pub fn note_expectation(scheme: &str, mass: &str, norm: Norm) -> Option<&'static str> {
    let converges = match (scheme, mass) {
        ("crank-nicolson", "redistributed") => true,
        ("crank-nicolson", "standard") => {
            matches!(norm, Norm::DisplacementLinfH | Norm::DisplacementL2H)
        }
        ("backward-euler", _) => true,
        _ => return None,
    };
    if norm == Norm::DisplacementLinfV {
        return None;
    }
    Some(if converges {
        "converges"
    } else {
        "does not converge"
    })
}

/// The rate of `norm` in case `c` (a chaotic case's ensemble median and range), the harness's
/// word for it (`converges`, `does not converge`, `undecided`: [`convergence`], the findings'
/// decision on the unperturbed run's interval widened by `bias`), and apart, marked as the
/// note's, what the note shows for it: `0.01 undecided (note: converges)`.
fn rate_cell(
    c: &CaseStudy,
    norm: Norm,
    sensitivity: Option<&Sensitivity>,
    bias: Option<f64>,
) -> String {
    let rate = match chaotic_spread(c, norm, sensitivity) {
        Some(spread) => chaotic_rate(&spread),
        None => match c.norm(norm).and_then(|r| r.fit) {
            Some(fit) => format!("{:.2}", fit.rate),
            None => return "—".to_string(),
        },
    };
    let word = convergence_word(convergence(c, norm, bias).verdict);
    match note_expectation(&c.case.scheme.name(), c.case.mass.name(), norm) {
        Some(note) => format!("{rate} {word} (note: {note})"),
        None => format!("{rate} {word}"),
    }
}

/// The members perturbed at every step per case and level, and their `ε`, as the ensembles
/// record them (0 in a study run before there were any).
fn step_members(s: &Sensitivity) -> (usize, f64) {
    let members = s.cases.iter().map(|c| c.step_members).max().unwrap_or(0);
    let epsilon = s.cases.iter().map(|c| c.step_epsilon).fold(0.0, f64::max);
    (members, epsilon)
}

/// The round-off sensitivity section: how the ensemble was made, each case's class with its
/// predictability step and separation growth at the finest level, and the rate ranges of the
/// chaotic cases.
fn sensitivity_section(s: &Sensitivity) -> String {
    let finest = s.config.levels.last().copied().unwrap_or(0);
    let (step_members, epsilon) = step_members(s);
    let every_step = if step_members > 0 {
        format!(
            "; and {step_members} members whose carried state (displacement, velocity, \
             acceleration) moves after every step by a seeded relative amount in ±{epsilon:.2e}, \
             the unit round-off"
        )
    } else {
        String::new()
    };
    let mut md = format!(
        "## Round-off sensitivity\n\n\
         Every case at every level also ran as {} members whose initial velocity carries seeded \
         noise of relative size {:e}: every velocity dof (the contact face's included) moves by \
         a uniform amount in ±A·max|v⁰|, the displacement is untouched{every_step}. Each member \
         is compared with the same (unperturbed) reference; its separation from the \
         unperturbed run is taken on the centre contact node's normal displacement. {} The \
         members ran inside the study's (case, level) jobs, after each job's unperturbed run: \
         {} runs, {:.1} s of run time summed over the jobs on this machine.\n\n",
        s.ensemble.members,
        s.ensemble.amplitude,
        class_rules(),
        s.cases.len() * s.config.levels.len() * (s.ensemble.members + step_members),
        s.wall_seconds
    );
    md.push_str(&class_table(s, finest));
    md.push('\n');
    for class in [
        SensitivityClass::Reproducible,
        SensitivityClass::EventSensitive,
        SensitivityClass::Chaotic,
    ] {
        let cases: Vec<String> = s
            .cases
            .iter()
            .filter(|c| c.class == class)
            .map(|c| {
                let largest = c.largest_separation.last().copied().unwrap_or(f64::NAN);
                format!(
                    "{} (largest separation {largest:.1e} at NX = {finest})",
                    c.case
                )
            })
            .collect();
        let list = if cases.is_empty() {
            "none".to_string()
        } else {
            cases.join(", ")
        };
        let _ = writeln!(md, "- *{}*: {list}.", class.name());
    }
    let chaotic: Vec<_> = s.cases.iter().filter(|c| c.chaotic).collect();
    if !chaotic.is_empty() {
        let _ = writeln!(
            md,
            "\n### Rate ranges of the chaotic cases\n\n\
             Ensemble minimum, median and maximum of the rate fitted over all levels, member by \
             member (the rate table shows the median and the range, marked †).\n\n{}",
            rate_ranges(chaotic).trim_end()
        );
    }
    md
}

/// The norms whose rate intervals the report tabulates: every norm the rate table shows, so
/// that every word beside a rate there has its interval here.
const INTERVAL_NORMS: [Norm; 7] = Norm::ALL;

/// The least-squares rates of every norm with their 95 % intervals (Student t,
/// `levels − 2` degrees of freedom) and, beside them, the reference's rate-bias bound of the
/// norm: the interval says how well the levels determine a rate, the bound how far the
/// reference's own error could move it.
fn interval_section(study: &ElasticStudy) -> String {
    let bias = &study.reference.rate_bias;
    let mut md = format!(
        "\n## Rates with their 95 % intervals\n\n\
         Every norm of the rate table: the rate ± the half-width of its 95 % confidence interval over the {} levels (Student t \
         with levels − 2 degrees of freedom; none with two levels), then the reference's \
         rate-bias bound of that rate: how far the reference's own error could move it (see *Is \
         the reference fine enough?*), by which the findings widen its interval. The first row \
         gives each norm's largest bound over the cases.\n\n| case |",
        study.study.config.levels.len()
    );
    for n in INTERVAL_NORMS {
        let _ = write!(md, " {} |", n.key());
    }
    let _ = writeln!(md, "\n|---|{}", "---|".repeat(INTERVAL_NORMS.len()));
    let _ = write!(md, "| rate-bias bound |");
    for n in INTERVAL_NORMS {
        let _ = write!(md, " {} |", bias_cell(bias.get(n.key()), "±"));
    }
    md.push('\n');
    for c in &study.study.cases {
        let _ = write!(md, "| {} |", c.case.id());
        for n in INTERVAL_NORMS {
            let own_bias = bias_cell(Some(&study.reference.case_bias(c, n)), "±");
            let cell = match c.norm(n).and_then(|r| r.fit) {
                Some(fit) => match (fit.ci_low, fit.ci_high) {
                    (Some(low), Some(high)) => {
                        format!(
                            "{:.2} ± {:.2}; bias {own_bias}",
                            fit.rate,
                            0.5 * (high - low)
                        )
                    }
                    _ => format!("{:.2}; bias {own_bias}", fit.rate),
                },
                None => "—".to_string(),
            };
            let _ = write!(md, " {cell} |");
        }
        md.push('\n');
    }
    md.push_str(&unbounded_note(&study.reference));
    md
}

/// A rate-bias bound as a table cell (after `sign`), or `none¹` where none can be formed
/// ([`unbounded_note`] says why).
fn bias_cell(bias: Option<&Option<f64>>, sign: &str) -> String {
    match bias.copied().flatten() {
        Some(b) => format!("{sign}{b:.2}"),
        None => "none¹".to_string(),
    }
}

/// The footnote of a `none¹` rate-bias bound; empty when every bound was formed.
fn unbounded_note(r: &super::ReferenceCheck) -> String {
    if !r.some_bias_unbounded() {
        return String::new();
    }
    format!(
        "\n¹ No bound: the distance of level {} to the reference is as large as an error a fit \
         uses (level {} is itself fitted, or its error is that small), so moving the errors by \
         it could make one vanish and the rate is not bounded. Fit only levels below {}, or \
         compute the reference one level finer.\n",
        r.next_coarser, r.next_coarser, r.next_coarser
    )
}

/// The findings by verdict, and what a reference one level finer would take (twice the
/// elements along the axis, `2^d` times the unknowns and twice the steps) for those undecided.
fn verdict_summary(study: &ElasticStudy) -> String {
    let r = &study.reference;
    let list = |verdict: Verdict| {
        let claims: Vec<String> = study
            .findings
            .iter()
            .filter(|f| f.verdict == verdict)
            .map(|f| format!("*{}*", f.claim))
            .collect();
        if claims.is_empty() {
            "none".to_string()
        } else {
            claims.join("; ")
        }
    };
    let finer_dofs = r.dofs as f64 * f64::from(1u32 << study.dimension);
    format!(
        "\nWith the reference on {} elements and levels {:?}: holding: {}. Failing: {}. \
         Undecided: {}. An undecided finding's reason names the interval that straddles and what \
         would decide it: more levels narrow an interval; a reference one level finer ({} \
         elements along the axis, about {:.1e} unknowns and {} steps) shrinks the rate-bias \
         bounds. That reference is one run, which `--shard` cannot split: only the study's other \
         jobs shard (docs/src/sharding-and-clusters.md, and *What a finer reference would take* \
         in docs/src/convergence-2d-3d.md).\n",
        r.level,
        study.study.config.levels,
        list(Verdict::Holds),
        list(Verdict::Fails),
        list(Verdict::Undecided),
        2 * r.level,
        finer_dofs,
        2 * r.steps
    )
}

/// The findings as a markdown table: the claim, where the note makes it, the verdict (in bold
/// unless it holds), what decided it and the evidence.
pub fn findings_table(findings: &[Finding]) -> String {
    let mut md = String::from(
        "| finding | note | verdict | decided by | evidence |\n|---|---|---|---|---|\n",
    );
    for f in findings {
        let verdict = match f.verdict {
            Verdict::Holds => "holds".to_string(),
            other => format!("**{}**", other.word()),
        };
        let _ = writeln!(
            md,
            "| {} | {} | {verdict} | {} | {} |",
            f.claim, f.source, f.reason, f.evidence
        );
    }
    md
}

/// The whole report; `command` is the command line that made it.
pub fn render(study: &ElasticStudy, command: &str) -> String {
    let s = &study.study;
    let r = &study.reference;
    let d = study.dimension;
    let mut md = String::new();
    let _ = writeln!(
        md,
        "# {d}D bar (note §3): convergence against a fine-mesh reference\n\n\
         Levels (elements along the axis): {:?}; Δx/Δt = {}; T = {}. Generated by `{command}` \
         (`make report` runs the study of `scenes/bar{d}d.json` into `reports/`, `make \
         report-fine` that of `scenes/bar{d}d-fine.json` into `reports/fine/`); study wall time \
         {:.1} s on this machine, reference run {:.1} s ({}).\n",
        s.config.levels,
        s.config.ratio,
        s.config.horizon,
        s.wall_seconds,
        r.seconds,
        if r.from_cache {
            "read from the cache"
        } else {
            "computed for this study"
        }
    );
    let _ = writeln!(
        md,
        "## Rates (least squares over all levels)\n\n\
         Each cell: our rate; the harness's word for it, decided as the findings below decide \
         (its 95 % interval, in the next section, widened by the reference's rate-bias bound: \
         *converges* above {CONVERGES_ABOVE}, *does not converge* at or below it, *undecided* \
         when it straddles or there is none; docs/src/vocabulary.md); then, apart and marked \
         `note:`, what the note's Figure 3 for Crank–Nicolson, Figure 8 for backward Euler, shows \
         for that curve (the note prints curves, not numbers: its expectation, not a verdict). The contact force is \
         the total normal force Σλᵢ on Γ_Sig; V is the energy norm (‖e‖²_H + a(e, e))^½; the \
         energy error is |E_h − E_ref|. The last column is the oscillation indicator \
         TV(Σλ_h)/TV(Σλ_ref) on the finest level.\n"
    );
    let _ = write!(md, "| case |");
    for n in Norm::ALL {
        let _ = write!(md, " {} |", n.key());
    }
    let _ = writeln!(
        md,
        " oscillation |\n|---|{}---|",
        "---|".repeat(Norm::ALL.len())
    );
    let sensitivity = study.sensitivity.as_ref();
    for c in &s.cases {
        let _ = write!(md, "| {} |", c.case.id());
        for n in Norm::ALL {
            let bias = study.reference.case_bias(c, n);
            let _ = write!(md, " {} |", rate_cell(c, n, sensitivity, bias));
        }
        let ind = c.oscillation_indicator().unwrap_or(f64::NAN);
        let _ = writeln!(md, " {ind:.1} ({}) |", oscillation_word(ind));
    }
    if let Some(sens) = sensitivity.filter(|s| s.cases.iter().any(|c| c.chaotic)) {
        let _ = writeln!(
            md,
            "\n† round-off chaotic (see *Round-off sensitivity*): the ensemble median rate of {} \
             members with relative noise {:e} on the initial velocity{}, and the ensemble [min, \
             max]; the unperturbed run's rate is one sample of that range (its per-level errors \
             are below).",
            sens.ensemble.members,
            sens.ensemble.amplitude,
            match step_members(sens) {
                (0, _) => String::new(),
                (n, _) => format!(" and {n} perturbed by the unit round-off after every step"),
            }
        );
    }

    md.push_str(&interval_section(study));
    let _ = write!(
        md,
        "\n## The note's findings, tested\n\n\
         Every rate is decided by its 95 % interval widened on both sides by the reference's \
         rate-bias bound of that rate (its case's and norm's: see the intervals above and the \
         last section; no bound: undecided). A norm \
         converges when the widened interval lies above {CONVERGES_ABOVE}, does not converge \
         when it lies at or below it, and is undecided otherwise, as is a rate fitted on fewer \
         than three levels (no interval). Two cases behave alike in a norm when both converge \
         or neither does and the interval of the difference of their rates (half-widths and \
         bounds added) lies within ±{ALIKE_RATE_GAP}. A case oscillates when its indicator is \
         at least {OSCILLATES_FROM}: an indicator has no interval, so that comparison is made \
         as measured.\n\n\
         A finding *holds* when every decision it needs is made and satisfied, *fails* when one \
         is made and contradicted, and is *undecided* otherwise.\n\n\
         {}",
        findings_table(&study.findings)
    );

    md.push_str(&verdict_summary(study));
    if let Some(sens) = sensitivity {
        let _ = write!(md, "\n{}", sensitivity_section(sens));
    }
    let _ = writeln!(
        md,
        "\n## Is the reference fine enough?\n\n\
         Reference: {} on {} elements along the axis ({:?} elements, {} unknowns, {} steps of \
         Δt = {:.3e}). The same case on {} elements is compared with it: that distance bounds \
         the reference's own error if the case converges, and it should sit well below the \
         smallest error that enters a fit. The last column is what an error of that size in the \
         reference could do to the fitted rates (the largest change over the cases when every \
         error moves by the distance, the coarse levels one way and the fine ones the other).\n\n\
         | norm | distance of level {} to the reference | smallest fitted error | ratio | rate bias bound |\n\
         |---|---|---|---|---|",
        r.case,
        r.level,
        r.elements,
        r.dofs,
        r.steps,
        r.dt,
        r.next_coarser,
        r.next_coarser
    );
    for n in Norm::ALL {
        let key = n.key();
        let _ = writeln!(
            md,
            "| {key} | {:.3e} | {:.3e} | {} | {} |",
            r.distance.get(key).copied().unwrap_or(f64::NAN),
            r.smallest_fitted_error
                .get(key)
                .copied()
                .unwrap_or(f64::NAN),
            r.margin(key)
                .filter(|m| m.is_finite())
                .map_or_else(|| "—".to_string(), |m| format!("{m:.1}")),
            bias_cell(r.rate_bias.get(key), "")
        );
    }
    md.push_str(&unbounded_note(r));
    let _ = writeln!(
        md,
        "\n## Errors per level\n\n{}",
        convergence_tables(s).trim_end()
    );
    md
}
