//! `reports/schemes.md`, "Which scheme to trust": every scheme × mass of the Tables 1–2 study
//! (the paper's and the rivals', [`Case::tables_matrix`]) on the criteria a user weighs — the
//! rate in each norm, the contact-force oscillation, the energy error over the longer horizon,
//! the round-off class, the stability suite's verdicts over 100 periods and on the hard cases
//! (when `stability.json` is there), and the cost to reach a target error — each with what
//! decides it, and for each criterion the cases no other case is decidedly better than. The page
//! gathers four sections' data, so no command writes it: the render step builds it from
//! `rates.json`, `sensitivity.json`, `rates-longer-horizon.json` and `stability.json`
//! ([`render`]).
//!
//! **What decides a comparison.** A rate is its 95 % interval (Student t over the levels), or
//! for a round-off chaotic case its ensemble's [min, max]: case A is decidedly faster than B
//! when A's lower end is above B's upper end; overlapping ranges leave the order undecided.
//! The cost to reach a target error is bracketed by the two levels around the target's crossing
//! (the work, in dof-steps, of the last level above the target and of the first at or below
//! it): A is decidedly cheaper when its bracket lies wholly below B's. The same two levels'
//! wall times bracket the cost in seconds, which prices a scheme's dof-step: each level's work
//! is timed over its runs (the study's and its round-off ensemble's runs of the same work,
//! [`crate::harness::study::timing`]), and the bracket runs from the fastest run of the level
//! above the target to the slowest of the level at or below it, so that it decides only where
//! the runs of two cases lie wholly apart. The oscillation words and round-off classes are the
//! tables' and `sensitivity.md`'s, each decided by its own rule.

use std::collections::BTreeSet;
use std::fmt::Write as _;

use crate::harness::problem::MassVariant;
use crate::harness::render::report::chaotic_spread;
use crate::harness::run::norms::Norm;
use crate::harness::run::physics::Physics;
use crate::harness::study::decision::Verdict;
use crate::harness::study::sensitivity::Sensitivity;
use crate::harness::study::timing::{level_costs, WallCost, MIN_RUNS};
use crate::harness::study::verdicts::{oscillation_ratio_text, oscillation_word};
use crate::harness::study::{CaseStudy, Study};
use crate::harness::vocabulary::wholly_above;
use crate::studies::stability::StabilityRecord;

/// The report, under a reports directory.
pub const SCHEMES_MD: &str = "schemes.md";

/// The oscillation indicator from which a contact force's oscillation counts as spurious in the
/// comparison with the literature: the tables' word Yes.
const SPURIOUS_FROM: f64 = 100.0;

/// The energy error below which a case conserves the energy to round-off over every level: its
/// rate measures the growth of round-off, not convergence, and it is not ranked by rate.
const CONSERVED_BELOW: f64 = 1e-8;

/// A range a criterion is judged by, with how it was obtained.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Range {
    low: f64,
    value: f64,
    high: f64,
}

impl Range {
    /// `self` is decidedly above `other`.
    fn above(self, other: Range) -> bool {
        wholly_above((self.low, self.high), (other.low, other.high))
    }
}

/// The rate of `norm` of `c` as a range: the ensemble's for a case `sensitivity` finds chaotic,
/// else the fit's 95 % interval; `None` without an interval (fewer than three levels, or no
/// rate).
fn rate_range(c: &CaseStudy, norm: Norm, sensitivity: Option<&Sensitivity>) -> Option<Range> {
    if let Some(s) = chaotic_spread(c, norm, sensitivity) {
        return Some(Range {
            low: s.min,
            value: s.median,
            high: s.max,
        });
    }
    let fit = c.rates.iter().find(|r| r.norm == norm)?.fit?;
    Some(Range {
        low: fit.ci_low?,
        value: fit.rate,
        high: fit.ci_high?,
    })
}

/// The indices of `ranges` that no other range is decidedly better than (`better(a, b)`: a is
/// decidedly better than b); an entry without a range is never among them.
fn front(ranges: &[Option<Range>], better: impl Fn(Range, Range) -> bool) -> Vec<usize> {
    (0..ranges.len())
        .filter(|&i| {
            ranges[i].is_some_and(|r| !ranges.iter().flatten().any(|&other| better(other, r)))
        })
        .collect()
}

/// The case's row label: the scheme's label and the mass's.
fn label(c: &CaseStudy) -> String {
    format!("{} / {}", c.case.scheme.label(), c.case.mass.paper_label())
}

fn fmt_range(r: Option<Range>) -> String {
    r.map_or("—".to_string(), |r| {
        format!("{:.2} [{:.2}, {:.2}]", r.value, r.low, r.high)
    })
}

/// The work `dofs × steps` of each level of `c`.
fn work(c: &CaseStudy) -> Vec<f64> {
    c.levels
        .iter()
        .map(|l| l.dofs as f64 * l.steps as f64)
        .collect()
}

/// The bracket of a cost `w` (one value per level of `c`) to reach `target` in `norm`: the cost
/// of the last level above it and of the first at or below it (both the first level's when it
/// already is). `None` when no level reaches it.
fn cost_bracket(c: &CaseStudy, norm: Norm, target: f64, w: &[f64]) -> Option<Range> {
    let errors = &c.rates.iter().find(|r| r.norm == norm)?.errors;
    let k = errors.iter().position(|&e| e <= target)?;
    let low = if k == 0 { w[0] } else { w[k - 1] };
    Some(Range {
        low,
        value: w[k],
        high: w[k],
    })
}

/// `schemes.md` of the tables study `study`, its round-off sensitivity, `longer`, the same
/// study over the longer horizon, and the stability suite's records when there are some.
pub fn render(
    study: &Study,
    sensitivity: &Sensitivity,
    longer: &Study,
    stability: Option<&[StabilityRecord]>,
) -> String {
    let mut md = String::from("# Which scheme to trust\n\n");
    let _ = writeln!(
        md,
        "Every scheme × mass of the Tables 1–2 study (`tables.md`: Signorini–Dirichlet \
         benchmark, levels NX = {:?}, Δx/Δt = {}, T = {}), the paper's and the rivals', on the \
         criteria a user weighs. A rate is `rate [low, high]`: its 95 % interval, or for a \
         round-off chaotic case (†) its ensemble's [min, max]. Case A is decidedly better than \
         B only when their ranges do not overlap; **best** lists, for each criterion, the cases \
         no other case is decidedly better than: the order among them is undecided at these \
         levels, and finer levels (narrower intervals) or a longer ensemble would decide it. \
         The same schemes on the note's 2D and 3D bars, against fine-mesh references, are in \
         `elastic-2d.md` and `elastic-3d.md`.\n",
        study.config.levels, study.config.ratio, study.config.horizon
    );
    rates_section(&mut md, study, sensitivity);
    behaviour_section(&mut md, study, sensitivity, longer);
    if let Some(records) = stability {
        stability_section(&mut md, study, records);
    }
    cost_section(&mut md, study, sensitivity);
    literature_section(&mut md, study);
    md
}

/// The rate of every norm, with the cases no other is decidedly faster than.
fn rates_section(md: &mut String, study: &Study, sensitivity: &Sensitivity) {
    md.push_str("## Convergence rates\n\n| Scheme / mass |");
    for norm in Norm::ALL {
        let _ = write!(md, " {} |", norm.label());
    }
    md.push_str("\n|---|");
    md.push_str(&"---|".repeat(Norm::ALL.len()));
    md.push('\n');
    for c in &study.cases {
        let chaotic = sensitivity.case(&c.case.id()).is_some_and(|s| s.chaotic);
        let _ = write!(md, "| {}{} |", label(c), if chaotic { " †" } else { "" });
        for norm in Norm::ALL {
            let _ = write!(
                md,
                " {} |",
                fmt_range(rate_range(c, norm, Some(sensitivity)))
            );
        }
        md.push('\n');
    }
    md.push_str("\n**Best rate** (no case decidedly faster):\n\n");
    for norm in Norm::ALL {
        let ranges: Vec<Option<Range>> = study
            .cases
            .iter()
            .map(|c| rate_range(c, norm, Some(sensitivity)))
            .collect();
        let best = front(&ranges, Range::above);
        let names: Vec<String> = best.iter().map(|&i| label(&study.cases[i])).collect();
        let _ = writeln!(
            md,
            "- {}: {} of {} cases: {}.",
            norm.label(),
            best.len(),
            study.cases.len(),
            names.join("; ")
        );
    }
    md.push('\n');
}

/// The oscillation word, the energy error over the longer horizon and the round-off class.
fn behaviour_section(md: &mut String, study: &Study, sensitivity: &Sensitivity, longer: &Study) {
    let finest = study.config.levels.last().copied().unwrap_or_default();
    let _ = writeln!(
        md,
        "## Oscillation, energy and round-off\n\n\
         Oscillation: `TV(λ_h)/TV(λ)` at NX = {finest} with the tables' word (No < 5 ≤ Small < \
         100 ≤ Yes < 2000 ≤ Big). Energy: `‖E_h − E‖_L∞(0,T)` at NX = {finest} over T = {} \
         (three periods of the benchmark) with its rate. Round-off: the class of \
         `sensitivity.md`. Physics: what the time loop measured of every level's run over \
         T = {}: the largest energy E_max/E₀ and the largest penetration p relative to the \
         contact face's displacement scale D (the contact node's largest distance from the \
         obstacle), over the levels; a level beyond 5 % energy gain or 1 % penetration is \
         **flagged** with its figures, and its case is not ranked by energy rate.\n\n\
         | Scheme / mass | Oscillation | Energy error, T = {} | Energy rate, T = {} | Physics, T = {} | Round-off |\n\
         |---|---|---|---|---|---|",
        longer.config.horizon,
        longer.config.horizon,
        longer.config.horizon,
        longer.config.horizon,
        longer.config.horizon
    );
    let mut flagged = Vec::new();
    let mut energy_ranges = Vec::new();
    let mut conserving = Vec::new();
    let mut calm = Vec::new();
    for c in &study.cases {
        let oscillation = c.oscillation_indicator().map_or("—".to_string(), |r| {
            format!("{} ({})", oscillation_word(r), oscillation_ratio_text(r))
        });
        if c.oscillation_indicator()
            .is_some_and(|r| oscillation_word(r) == "No")
        {
            calm.push(label(c));
        }
        let long = longer.cases.iter().find(|l| l.case == c.case);
        let errors = long
            .and_then(|l| l.rates.iter().find(|r| r.norm == Norm::EnergyLinf))
            .map(|r| r.errors.as_slice())
            .unwrap_or_default();
        let energy = errors.last().copied();
        // The ensembles ran over the tables' horizon: every case is judged by its fit here.
        let energy_rate = long.and_then(|l| rate_range(l, Norm::EnergyLinf, None));
        let conserves = !errors.is_empty() && errors.iter().all(|&e| e < CONSERVED_BELOW);
        if conserves {
            conserving.push(label(c));
        }
        let physics = longer.physics.get(&c.case.id());
        let gains = physics.is_some_and(|levels| levels.iter().any(|p| p.flagged()));
        if gains {
            flagged.push(label(c));
        }
        energy_ranges.push(energy_rate.filter(|_| !conserves && !gains));
        let class = sensitivity
            .case(&c.case.id())
            .map_or("—", |s| s.class.name());
        let _ = writeln!(
            md,
            "| {} | {oscillation} | {} | {} | {} | {class} |",
            label(c),
            energy.map_or("—".to_string(), |e| format!("{e:.3e}")),
            fmt_range(energy_rate),
            physics.map_or("—".to_string(), |levels| {
                physics_over_levels(&longer.config.levels, levels)
            })
        );
    }
    let _ = writeln!(
        md,
        "\n**No oscillation** ({} of {} cases): {}.\n",
        calm.len(),
        study.cases.len(),
        calm.join("; ")
    );
    let best = front(&energy_ranges, Range::above);
    let names: Vec<String> = best.iter().map(|&i| label(&study.cases[i])).collect();
    let _ = writeln!(
        md,
        "**Energy conserved to round-off over T = {}** (error below {CONSERVED_BELOW:e} at every \
         level; its rate measures round-off, so it is not ranked by rate): {}.\n\n\
         **Flagged by the physics check over T = {}** (a level beyond 5 % energy gain or 1 % \
         penetration; not ranked by energy rate): {}.\n\n\
         **Best energy rate over T = {}** among the others (no case decidedly faster; the \
         ensembles ran over the tables' horizon, so every case is judged by its fit here): {}.\n",
        longer.config.horizon,
        list_or_none(&conserving),
        longer.config.horizon,
        if longer.physics.is_empty() {
            "not measured (the study predates the check)".to_string()
        } else {
            list_or_none(&flagged)
        },
        longer.config.horizon,
        names.join("; ")
    );
}

/// The stability suite's judgement of every case (`stability.md`): its energy over the long
/// horizon (100 periods) and on how many hard cases it stays numerically stable, decided by
/// [`StabilityRecord::stays_stable`] (every run of the ensemble stable or dissipative, and not
/// round-off chaotic).
fn stability_section(md: &mut String, study: &Study, records: &[StabilityRecord]) {
    let hard: BTreeSet<&str> = records.iter().map(|r| r.hard_case.as_str()).collect();
    let _ = writeln!(
        md,
        "## Over 100 periods and on the hard cases\n\n\
         From `stability.json` as `make report` found it (`make stability` writes it): the \
         long-horizon run (NX = 80, Δx/Δt = 10, T = 300) with its verdict, largest energy drift \
         `max |E − E₀|/E₀` and round-off class, and on how many of the {} hard cases the case \
         stays numerically stable (every run of its round-off ensemble stable or dissipative, \
         and not chaotic), fails to, or cannot be decided. A drift is one run's: it has no \
         interval, and the verdict is given only where the ensemble's runs share it. Physics, \
         T = 300: what the time loop measured of the unperturbed run: its largest energy \
         E_max/E₀ and its largest penetration p relative to the contact face's displacement \
         scale D (the contact node's largest distance from the obstacle); **flagged** beyond \
         5 % energy gain or 1 % penetration, and then never called stable.\n\n\
         | Scheme / mass | T = 300 verdict | max abs(E − E₀)/E₀ | Physics, T = 300 | Round-off, \
         T = 300 | Stays stable: holds / fails / undecided |\n|---|---|---|---|---|---|",
        hard.len()
    );
    let mut everywhere = Vec::new();
    for c in &study.cases {
        let id = c.case.id();
        let mine: Vec<&StabilityRecord> = records.iter().filter(|r| r.case == id).collect();
        if mine.is_empty() {
            let _ = writeln!(md, "| {} | not in the suite | — | — | — | — |", label(c));
            continue;
        }
        let long = mine.iter().find(|r| r.hard_case == "long-horizon");
        let count = |v: Verdict| {
            mine.iter()
                .filter(|r| r.stays_stable().verdict == v)
                .count()
        };
        let (holds, fails, undecided) = (
            count(Verdict::Holds),
            count(Verdict::Fails),
            count(Verdict::Undecided),
        );
        if holds == mine.len() && mine.len() == hard.len() {
            everywhere.push(label(c));
        }
        let _ = writeln!(
            md,
            "| {} | {} | {} | {} | {} | {holds} / {fails} / {undecided} |",
            label(c),
            long.map_or("—".to_string(), |r| r.verdict_text()),
            long.map_or("—".to_string(), |r| format!("{:.2e}", r.max_energy_drift)),
            long.and_then(|r| r.physics)
                .map_or("—".to_string(), |p| physics_cell(&p)),
            long.and_then(|r| r.sensitivity)
                .map_or("—", |s| s.class.name()),
        );
    }
    let _ = writeln!(
        md,
        "\n**Stays numerically stable on every hard case**: {}.\n",
        list_or_none(&everywhere)
    );
}

/// The physics of a case's runs at `levels` in a cell: every flagged level with its figures
/// ([`Physics::flags`]), or the largest `E_max/E₀` and `p/D` over the levels.
fn physics_over_levels(levels: &[usize], physics: &[Physics]) -> String {
    let flagged: Vec<String> = levels
        .iter()
        .zip(physics)
        .filter_map(|(nx, p)| p.flags().map(|f| format!("NX = {nx}: {f}")))
        .collect();
    if !flagged.is_empty() {
        return format!("**flagged**: {}", flagged.join("; "));
    }
    let ratio = physics
        .iter()
        .filter_map(|p| p.energy_ratio)
        .fold(f64::NEG_INFINITY, f64::max);
    let penetration = physics
        .iter()
        .map(Physics::judged_penetration)
        .fold(0.0, f64::max);
    format!("E_max/E₀ ≤ {ratio:.4}, p/D ≤ {penetration:.1e}")
}

/// A run's physics in a cell: `E_max/E₀ 1.0000, p/D 3.5e-18`, with what fails its tolerance
/// flagged with its figures ([`Physics::flags`]).
fn physics_cell(p: &Physics) -> String {
    let ratio = p
        .energy_ratio
        .map_or("—".to_string(), |r| format!("{r:.4}"));
    let penetration = p
        .relative_penetration
        .map_or(format!("p {:.1e} (D = 0)", p.penetration), |r| {
            format!("p/D {r:.1e}")
        });
    match p.flags() {
        Some(flags) => format!("**flagged**: {flags}"),
        None => format!("E_max/E₀ {ratio}, {penetration}"),
    }
}

/// The wall time to reach `target` in `norm` of `c`, whose levels cost `costs`: from the fastest
/// run of the last level above the target to the slowest run of the first at or below it (both
/// the first level's when it already is), its value the latter's median, with the fewest runs of
/// the two levels. `None` when no level reaches it.
fn wall_bracket(
    c: &CaseStudy,
    norm: Norm,
    target: f64,
    costs: &[WallCost],
) -> Option<(Range, usize)> {
    let errors = &c.rates.iter().find(|r| r.norm == norm)?.errors;
    let k = errors.iter().position(|&e| e <= target)?;
    let above = if k == 0 { &costs[0] } else { &costs[k - 1] };
    let at = &costs[k];
    Some((
        Range {
            low: above.min,
            value: at.median,
            high: at.max,
        },
        above.runs.min(at.runs),
    ))
}

/// The work to reach a target error in `L∞(0,T;H)`: the loosest error every case reaches.
fn cost_section(md: &mut String, study: &Study, sensitivity: &Sensitivity) {
    let norm = Norm::DisplacementLinfH;
    let target = study
        .cases
        .iter()
        .filter_map(|c| c.rates.iter().find(|r| r.norm == norm))
        .filter_map(|r| r.errors.last().copied())
        .fold(0.0_f64, f64::max);
    let _ = writeln!(
        md,
        "## Cost to reach a target error\n\n\
         Target: `{}` ≤ {target:.3e}, the largest finest-level error of the cases (so that every \
         case reaches it). The work is `unknowns × steps` of the levels bracketing the \
         crossing (`[last level above, first level at or below]`), deterministic where wall \
         times are not; one level is four times the work of the one before. The wall time is \
         bracketed by the same two levels' runs (setup, stepping, contact solves and \
         observers): it prices what a dof-step costs each scheme (contact-stabilised Newmark \
         solves two contact problems a step). Each level's work is timed over its runs (the \
         study's run, then its round-off ensemble's unperturbed run and initial-data members, \
         which do the same work), and the bracket runs from the fastest run of the level above \
         the target to the slowest of the level at or below it: wall times move with the \
         machine's load, so only brackets wholly apart decide, and a level timed fewer than \
         {MIN_RUNS} times decides nothing.\n\n\
         | Scheme / mass | Work bracket (dof-steps) | Runs a level | Wall time bracket |\n|---|---|---|---|",
        norm.label()
    );
    let not_reached = || "not reached".to_string();
    let brackets: Vec<Option<Range>> = study
        .cases
        .iter()
        .map(|c| cost_bracket(c, norm, target, &work(c)))
        .collect();
    let timed: Vec<Option<(Range, usize)>> = study
        .cases
        .iter()
        .map(|c| wall_bracket(c, norm, target, &level_costs(c, Some(sensitivity))))
        .collect();
    for ((c, b), w) in study.cases.iter().zip(&brackets).zip(&timed) {
        let runs = w.map_or("—".to_string(), |(_, runs)| {
            if runs >= MIN_RUNS {
                runs.to_string()
            } else {
                format!("{runs} (no interval)")
            }
        });
        let _ = writeln!(
            md,
            "| {} | {} | {runs} | {} |",
            label(c),
            b.map_or_else(not_reached, |b| format!("[{:.3e}, {:.3e}]", b.low, b.high)),
            w.map_or_else(not_reached, |(w, _)| format!(
                "wall [{:.2e}, {:.2e}] s",
                w.low, w.high
            ))
        );
    }
    let walls: Vec<Option<Range>> = timed
        .iter()
        .map(|t| t.filter(|(_, runs)| *runs >= MIN_RUNS).map(|(w, _)| w))
        .collect();
    let untimed: Vec<String> = study
        .cases
        .iter()
        .zip(&timed)
        .filter(|(_, t)| t.is_some_and(|(_, runs)| runs < MIN_RUNS))
        .map(|(c, _)| label(c))
        .collect();
    let names = |best: Vec<usize>| -> String {
        let names: Vec<String> = best.iter().map(|&i| label(&study.cases[i])).collect();
        names.join("; ")
    };
    let in_wall_time = if untimed.is_empty() {
        names(front(&walls, |a, b| a.high < b.low))
    } else if untimed.len() == study.cases.len() {
        format!(
            "*undecided*: every case is timed fewer than {MIN_RUNS} times a level, so no \
             interval ranks them"
        )
    } else {
        format!(
            "*undecided*: {} of {} cases are timed fewer than {MIN_RUNS} times a level ({}), so \
             no interval ranks them",
            untimed.len(),
            study.cases.len(),
            untimed.join("; ")
        )
    };
    let _ = writeln!(
        md,
        "\n**Cheapest** (no case's bracket wholly below): {}.\n\n\
         **Cheapest in wall time** (no case's wall time bracket wholly below; the order among \
         them is undecided): {in_wall_time}.\n",
        names(front(&brackets, |a, b| a.high < b.low)),
    );
}

/// The comparison with Doyen, Ern and Piperno (SIAM J. Sci. Comput. 33, 2011) where it can be
/// made: their summary's claims on oscillations, checked against the oscillation indicator.
/// A case oscillates here when its indicator is at least [`SPURIOUS_FROM`] (the words Yes and
/// Big): the Small of the redistributed rows is the overshoot the exact force's jumps leave.
fn literature_section(md: &mut String, study: &Study) {
    let oscillating = |mass: MassVariant| {
        let cases: Vec<&CaseStudy> = study.cases.iter().filter(|c| c.case.mass == mass).collect();
        let moving: Vec<String> = cases
            .iter()
            .filter(|c| {
                c.oscillation_indicator()
                    .is_some_and(|r| r >= SPURIOUS_FROM)
            })
            .map(|c| c.case.scheme.label())
            .collect();
        (cases.len(), moving)
    };
    let (standard, standard_moving) = oscillating(MassVariant::Standard);
    let (redistributed, redistributed_moving) = oscillating(MassVariant::Redistributed);
    let _ = writeln!(
        md,
        "## Against Doyen, Ern and Piperno (2011)\n\n\
         Their comparison of time-integration schemes for the dynamic Signorini problem (SIAM J. \
         Sci. Comput. 33) summarises: most schemes with the standard mass show spurious \
         oscillations of the contact force or a poor long-time energy, and the modified \
         (redistributed) mass removes the oscillations. Their per-method table could not be \
         read for this harness, so only these two claims are compared, with a case counted as \
         oscillating when `TV(λ_h)/TV(λ)` ≥ {SPURIOUS_FROM} (the words Yes and Big); the \
         entry-by-entry comparison is *undecided* until their table is transcribed.\n\n\
         - Standard mass: {} of {standard} schemes oscillate: {}.\n\
         - Redistributed mass: {} of {redistributed} schemes oscillate: {}. The claim *agrees* \
         for every other scheme with the redistributed mass and *differs* for these.\n",
        standard_moving.len(),
        list_or_none(&standard_moving),
        redistributed_moving.len(),
        list_or_none(&redistributed_moving),
    );
}

fn list_or_none(names: &[String]) -> String {
    if names.is_empty() {
        "none".to_string()
    } else {
        names.join("; ")
    }
}
