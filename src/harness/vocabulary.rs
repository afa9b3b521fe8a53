//! The verdict words the harness prints, each defined once: the quantity it is said of, the
//! threshold that quantity is compared with (a constant here, which the deciding code uses), and
//! the interval that decides it. `docs/src/vocabulary.md` carries [`table`] (a test holds the two
//! equal), and every report that prints one of these words means what [`words`] says.
//!
//! One rule decides them all ([`crate::harness::study::decision`]): a word is said of a quantity
//! when the interval of that quantity lies entirely on its side of the threshold; the opposite
//! word when it lies entirely on the other side; and the quantity is **undecided** when the
//! interval straddles the threshold, with what would decide it. The intervals are of three
//! kinds:
//! * a fitted rate's 95 % interval (Student t over the levels), widened by the reference's
//!   rate-bias bound ([`Estimate`]; a round-off chaotic case: its ensemble's `[min, max]`): more
//!   levels or a finer reference decide an undecided rate;
//! * a measured figure's range over the runs that measure the same thing ([`Interval`]): the
//!   unperturbed run and the members of its round-off ensemble, or repeated timings; members or
//!   repeats that all fall on one side would decide it;
//! * a single run's figure (a run without an ensemble): its interval is the point itself, so it
//!   is decided as measured, and the report says so.

use std::fmt::Write as _;

pub use crate::harness::study::decision::wholly_above;
use crate::harness::study::decision::{all_of, Decision, Estimate, Verdict};

pub use crate::harness::run::physics::{
    ENERGY_GAIN_TOLERANCE, FACE_SCALE_FLOOR, FORCE_SIGN_TOLERANCE, PENETRATION_TOLERANCE,
};
pub use crate::harness::study::verdicts::{
    OSCILLATES_FROM, OSCILLATION_BIG_FROM, OSCILLATION_YES_FROM,
};

/// A rate converges when its interval lies above this: the error decreases as `h` does.
pub const CONVERGES_ABOVE: f64 = 0.0;

/// An error that does not converge is *bounded* when its rate's interval lies within
/// `±BOUNDED_RATE_WITHIN` (it neither decreases nor grows markedly), and *grows* when its
/// interval lies at or below `−BOUNDED_RATE_WITHIN`.
pub const BOUNDED_RATE_WITHIN: f64 = 0.25;

/// A rate agrees with another source's value (the paper's) when its interval lies within
/// `±AGREES_WITHIN` of that value, and differs when it lies entirely outside.
pub const AGREES_WITHIN: f64 = 0.1;

/// Two cases behave alike in a norm when the interval of the difference of their rates lies
/// within `±ALIKE_RATE_GAP` (and both converge or neither does).
pub const ALIKE_RATE_GAP: f64 = 0.25;

/// A run is dissipative when its energy ends more than this fraction of `E_0` below `E_0`.
pub const DISSIPATIVE_LOSS_FROM: f64 = 0.01;

/// A run has diverged when a value is not finite or `E_max / E_0` exceeds this.
pub const DIVERGED_ENERGY_RATIO: f64 = 1e6;

/// Where the exact contact force is constant (its total variation 0) the oscillation indicator
/// is the discrete force's total variation, and oscillates spuriously above this.
pub const CONSTANT_FORCE_VARIATION: f64 = 1e-9;

/// A figure measured by several runs of the same thing: the unperturbed run's `value` and the
/// range `[low, high]` of it and the members of its round-off ensemble (or of repeated
/// timings); a single run's figure is the point `[value, value]`.
#[derive(Debug, Clone, PartialEq)]
pub struct Interval {
    /// What it is, as a reason names it (`E_max/E_0 − 1`).
    pub what: String,
    /// The unperturbed run's (or the median repeat's) figure.
    pub value: f64,
    /// The smallest of the runs.
    pub low: f64,
    /// The largest of the runs.
    pub high: f64,
    /// How many runs measured it.
    pub runs: usize,
}

impl Interval {
    /// One run's figure: decided as measured.
    pub fn point(what: impl Into<String>, value: f64) -> Self {
        Self {
            what: what.into(),
            value,
            low: value,
            high: value,
            runs: 1,
        }
    }

    /// `value` and the figures of the other runs of the same thing (`others`).
    pub fn of_runs(what: impl Into<String>, value: f64, others: &[f64]) -> Self {
        let nan = |a: f64, b: f64| a.is_nan() || b.is_nan();
        let (low, high) = others.iter().fold((value, value), |(l, h), &x| {
            if nan(l, x) {
                (f64::NAN, f64::NAN)
            } else {
                (l.min(x), h.max(x))
            }
        });
        Self {
            what: what.into(),
            value,
            low,
            high,
            runs: 1 + others.len(),
        }
    }

    /// `E_max/E_0 − 1 5.00e-2 [4.90e-2, 5.10e-2] (5 runs)`, or the point and `(one run: as
    /// measured)`.
    fn head(&self) -> String {
        if self.runs > 1 {
            format!(
                "{} {:.3e} [{:.3e}, {:.3e}] ({} runs)",
                self.what, self.value, self.low, self.high, self.runs
            )
        } else {
            format!("{} {:.3e} (one run: as measured)", self.what, self.value)
        }
    }

    /// "The figure is above `threshold`" (`strict`) or "at least `threshold`" (not `strict`):
    /// holds when every run's figure is, fails when none is, undecided when they split or a
    /// figure is not finite.
    pub fn beyond(&self, threshold: f64, strict: bool) -> Decision {
        let head = self.head();
        let (rel, not) = if strict { (">", "≤") } else { ("≥", "<") };
        let past = |x: f64| {
            if strict {
                x > threshold
            } else {
                x >= threshold
            }
        };
        if !(self.low.is_finite() && self.high.is_finite()) {
            return Decision::undecided(format!(
                "{head} is not finite: a run that completes would decide it"
            ));
        }
        if past(self.low) {
            Decision {
                verdict: Verdict::Holds,
                reason: format!("{head} {rel} {threshold:e}"),
            }
        } else if !past(self.high) {
            Decision {
                verdict: Verdict::Fails,
                reason: format!("{head} {not} {threshold:e}"),
            }
        } else {
            Decision::undecided(format!(
                "{head} straddles {threshold:e}: runs that all fall on one side (a smaller \
                 perturbation, or repeats under less load) would decide it"
            ))
        }
    }
}

/// "The rate converges": its interval lies above [`CONVERGES_ABOVE`]; fails ("does not
/// converge") when it lies at or below it.
pub fn converges(rate: &Estimate) -> Decision {
    rate.above(CONVERGES_ABOVE)
}

/// The word of a convergence decision: `converges`, `does not converge` or `undecided`.
pub fn convergence_word(verdict: Verdict) -> &'static str {
    match verdict {
        Verdict::Holds => "converges",
        Verdict::Fails => "does not converge",
        Verdict::Undecided => "undecided",
    }
}

/// "The error is bounded": its rate's interval lies within `±`[`BOUNDED_RATE_WITHIN`].
pub fn bounded(rate: &Estimate) -> Decision {
    rate.within(-BOUNDED_RATE_WITHIN, BOUNDED_RATE_WITHIN)
}

/// "The error grows": its rate's interval lies at or below `−`[`BOUNDED_RATE_WITHIN`].
pub fn grows(rate: &Estimate) -> Decision {
    rate.above(-BOUNDED_RATE_WITHIN).negated()
}

/// "The rate agrees with `value`": its interval lies within `±`[`AGREES_WITHIN`] of it; fails
/// ("differs") when it lies entirely outside.
pub fn agrees(rate: &Estimate, value: f64) -> Decision {
    rate.within(value - AGREES_WITHIN, value + AGREES_WITHIN)
}

/// The word of an agreement decision: `agrees`, `differs` or `undecided`.
pub fn agreement_word(verdict: Verdict) -> &'static str {
    match verdict {
        Verdict::Holds => "agrees",
        Verdict::Fails => "differs",
        Verdict::Undecided => "undecided",
    }
}

/// "The two rates are within [`ALIKE_RATE_GAP`]": the interval of their difference lies within
/// `±ALIKE_RATE_GAP`.
pub fn within_alike_gap(difference: &Estimate) -> Decision {
    difference.within(-ALIKE_RATE_GAP, ALIKE_RATE_GAP)
}

/// "The measured figure is within its target" (`ok`): the interval of the repeats lies at or
/// below `target`; fails (`missed`) when it lies wholly above; undecided when it straddles.
pub fn within_target(measured: &Interval, target: f64) -> Decision {
    measured.beyond(target, true).negated()
}

/// The word of a target decision: `ok`, `missed` or `undecided`.
pub fn target_word(verdict: Verdict) -> &'static str {
    match verdict {
        Verdict::Holds => "ok",
        Verdict::Fails => "missed",
        Verdict::Undecided => "undecided",
    }
}

/// "The run penetrates": its judged penetration `p / max(D, D_min)` lies above
/// [`PENETRATION_TOLERANCE`].
pub fn penetrating(judged_penetration: &Interval) -> Decision {
    judged_penetration.beyond(PENETRATION_TOLERANCE, true)
}

/// "The run gains energy": `(E_max − E_0) / |E_0|` lies above [`ENERGY_GAIN_TOLERANCE`].
pub fn gains_energy(gain: &Interval) -> Decision {
    gain.beyond(ENERGY_GAIN_TOLERANCE, true)
}

/// "The run is dissipative": the energy lost by the end, `(E_0 − E(T)) / |E_0|`, lies above
/// [`DISSIPATIVE_LOSS_FROM`].
pub fn dissipative(loss: &Interval) -> Decision {
    loss.beyond(DISSIPATIVE_LOSS_FROM, true)
}

/// "The contact force oscillates": the indicator `TV(λ_h)/TV(λ)` is at least
/// [`OSCILLATES_FROM`] (the tables' Small, Yes or Big).
pub fn oscillates(indicator: &Interval) -> Decision {
    indicator.beyond(OSCILLATES_FROM, false)
}

/// "The contact force oscillates spuriously": the indicator is at least
/// [`OSCILLATION_YES_FROM`] (the tables' Yes or Big).
pub fn oscillates_spuriously(indicator: &Interval) -> Decision {
    indicator.beyond(OSCILLATION_YES_FROM, false)
}

/// "The run is stable": it neither gains energy, penetrates, oscillates spuriously nor
/// dissipates (each of the four fails).
pub fn stable(
    gain: &Interval,
    penetration: &Interval,
    indicator: &Interval,
    loss: &Interval,
) -> Decision {
    all_of(vec![
        gains_energy(gain).negated(),
        penetrating(penetration).negated(),
        oscillates_spuriously(indicator).negated(),
        dissipative(loss).negated(),
    ])
}

/// One verdict word: what it is said of, against what, decided how, and where it is printed.
#[derive(Debug, Clone, PartialEq)]
pub struct Word {
    /// The word as the reports print it.
    pub word: &'static str,
    /// The quantity it is said of.
    pub quantity: &'static str,
    /// The threshold, with the constant's value.
    pub threshold: String,
    /// The interval that decides it and how.
    pub decided_by: &'static str,
    /// The reports that print it.
    pub printed_in: &'static str,
}

/// The interval of a fitted rate, as [`words`] names it.
const RATE_INTERVAL: &str = "the rate's 95 % interval (Student t over the levels), widened on \
    both sides by the reference's rate-bias bound (a round-off chaotic case: the ensemble's \
    [min, max])";

/// The range of a figure over a run and its round-off ensemble, as [`words`] names it.
const RUN_INTERVAL: &str = "the figure's range over the unperturbed run and the members of its \
    round-off ensemble (a run without an ensemble: the figure itself, as measured)";

/// Every verdict word, in the order of `docs/src/vocabulary.md`.
pub fn words() -> Vec<Word> {
    vec![
        Word {
            word: "converges",
            quantity: "the least-squares rate of an error against the mesh size h",
            threshold: format!("rate > {CONVERGES_ABOVE} (`CONVERGES_ABOVE`)"),
            decided_by: RATE_INTERVAL,
            printed_in: "the 2D/3D reports, extended.md, league.md, the findings",
        },
        Word {
            word: "does not converge",
            quantity: "the least-squares rate of an error against h",
            threshold: format!("rate ≤ {CONVERGES_ABOVE} (`CONVERGES_ABOVE`)"),
            decided_by: RATE_INTERVAL,
            printed_in: "the 2D/3D reports, extended.md, league.md, the findings",
        },
        Word {
            word: "bounded",
            quantity: "the rate of an error that does not converge, printed with the error's \
                size (an energy error as a multiple of E₀): bounded is not small",
            threshold: format!(
                "−{BOUNDED_RATE_WITHIN} ≤ rate ≤ {BOUNDED_RATE_WITHIN} (`BOUNDED_RATE_WITHIN`)"
            ),
            decided_by: RATE_INTERVAL,
            printed_in: "extended.md",
        },
        Word {
            word: "grows",
            quantity: "the rate of an error that does not converge (or a finest error that is \
                not finite)",
            threshold: format!("rate ≤ −{BOUNDED_RATE_WITHIN} (`BOUNDED_RATE_WITHIN`)"),
            decided_by: RATE_INTERVAL,
            printed_in: "extended.md",
        },
        Word {
            word: "agrees",
            quantity: "a rate beside another source's value (the paper's)",
            threshold: format!("|rate − value| ≤ {AGREES_WITHIN} (`AGREES_WITHIN`)"),
            decided_by: RATE_INTERVAL,
            printed_in: "tables.md",
        },
        Word {
            word: "differs",
            quantity: "a rate beside another source's value (the paper's)",
            threshold: format!("|rate − value| > {AGREES_WITHIN} (`AGREES_WITHIN`)"),
            decided_by: RATE_INTERVAL,
            printed_in: "tables.md",
        },
        Word {
            word: "alike",
            quantity: "two cases' rates in one norm: both converge or neither does, and their \
                difference",
            threshold: format!("|difference| ≤ {ALIKE_RATE_GAP} (`ALIKE_RATE_GAP`)"),
            decided_by: "the difference's interval: the two rates' half-widths and bias bounds \
                added",
            printed_in: "the findings of the 2D/3D reports and league.md",
        },
        Word {
            word: "holds",
            quantity: "a finding: a statement made of the decisions above",
            threshold: "every decision it needs holds (a decision that fails makes it fail)"
                .to_string(),
            decided_by: "its decisions in three-valued logic: holds when all are made and \
                satisfied, fails when one is made and contradicted, undecided otherwise",
            printed_in: "the 2D/3D reports, league.md, reports/README.md",
        },
        Word {
            word: "fails",
            quantity: "a finding",
            threshold: "a decision it needs is made and contradicted".to_string(),
            decided_by: "its decisions in three-valued logic",
            printed_in: "the 2D/3D reports, league.md, reports/README.md",
        },
        Word {
            word: "oscillates",
            quantity: "the oscillation indicator TV(λ_h)/TV(λ) on the finest level (grades: No \
                below the threshold, Small, Yes, Big)",
            threshold: format!(
                "indicator ≥ {OSCILLATES_FROM} (`OSCILLATES_FROM`; Yes from \
                 {OSCILLATION_YES_FROM}, Big from {OSCILLATION_BIG_FROM})"
            ),
            decided_by: "the indicator has no fitted interval: one run's, as measured (the \
                reports say so)",
            printed_in: "the tables, extended.md, league.md, the 2D/3D reports",
        },
        Word {
            word: "oscillates spuriously",
            quantity: "the oscillation indicator TV(λ_h)/TV(λ) (TV(λ_h) where the exact force is \
                constant)",
            threshold: format!(
                "indicator ≥ {OSCILLATION_YES_FROM} (`OSCILLATION_YES_FROM`, the tables' Yes); \
                 TV(λ_h) > {CONSTANT_FORCE_VARIATION:e} (`CONSTANT_FORCE_VARIATION`)"
            ),
            decided_by: RUN_INTERVAL,
            printed_in: "stability.md, schemes.md",
        },
        Word {
            word: "penetrating",
            quantity: "the largest penetration p relative to the contact face's displacement \
                scale: p / max(D, D_min); or a pulling contact force",
            threshold: format!(
                "p / max(D, {FACE_SCALE_FLOOR:e}) > {PENETRATION_TOLERANCE} \
                 (`PENETRATION_TOLERANCE`, `FACE_SCALE_FLOOR`); a force λ > \
                 {FORCE_SIGN_TOLERANCE:e} max|λ| (`FORCE_SIGN_TOLERANCE`)"
            ),
            decided_by: RUN_INTERVAL,
            printed_in: "run, stability.md, schemes.md, the findings' evidence",
        },
        Word {
            word: "gains energy",
            quantity: "the largest energy above the start, (E_max − E₀)/|E₀| (with a load, \
                energy and its work)",
            threshold: format!("> {ENERGY_GAIN_TOLERANCE} (`ENERGY_GAIN_TOLERANCE`)"),
            decided_by: RUN_INTERVAL,
            printed_in: "run, stability.md, schemes.md",
        },
        Word {
            word: "dissipative",
            quantity: "the energy lost by the end of the run, (E₀ − E(T))/|E₀|, of a run that \
                does not gain energy",
            threshold: format!("> {DISSIPATIVE_LOSS_FROM} (`DISSIPATIVE_LOSS_FROM`)"),
            decided_by: RUN_INTERVAL,
            printed_in: "stability.md, schemes.md",
        },
        Word {
            word: "stable",
            quantity: "a run: none of gains energy, penetrating, oscillates spuriously, \
                dissipative, diverged",
            threshold: format!(
                "E_max/E₀ − 1 ≤ {ENERGY_GAIN_TOLERANCE}, energy lost ≤ \
                 {DISSIPATIVE_LOSS_FROM}, indicator < {OSCILLATION_YES_FROM}, p / max(D, D_min) \
                 ≤ {PENETRATION_TOLERANCE}"
            ),
            decided_by: RUN_INTERVAL,
            printed_in: "stability.md, schemes.md, reports/README.md",
        },
        Word {
            word: "diverged",
            quantity: "a run: a value that is not finite, or E_max/E₀",
            threshold: format!("E_max/E₀ > {DIVERGED_ENERGY_RATIO:e} (`DIVERGED_ENERGY_RATIO`)"),
            decided_by: RUN_INTERVAL,
            printed_in: "stability.md, schemes.md",
        },
        Word {
            word: "faster",
            quantity: "two cases' rates in one norm",
            threshold: "A's interval wholly above B's".to_string(),
            decided_by: RATE_INTERVAL,
            printed_in: "schemes.md",
        },
        Word {
            word: "cheaper",
            quantity: "two cases' costs to reach a target error (dof-steps, or seconds)",
            threshold: "A's interval wholly below B's".to_string(),
            decided_by: "the cost's bracket between the two levels around the target's \
                crossing (seconds: over repeated timings)",
            printed_in: "schemes.md, work-precision.md",
        },
        Word {
            word: "ok",
            quantity: "a measured time or memory beside its target",
            threshold: "the target of the line (bench.md)".to_string(),
            decided_by: "the range of the repeated measurements: ok when it lies at or below \
                the target",
            printed_in: "bench.md",
        },
        Word {
            word: "missed",
            quantity: "a measured time or memory beside its target",
            threshold: "the target of the line (bench.md)".to_string(),
            decided_by: "the range of the repeated measurements: missed when it lies wholly \
                above the target",
            printed_in: "bench.md",
        },
        Word {
            word: "undecided",
            quantity: "any of the above",
            threshold: "its word's".to_string(),
            decided_by: "the interval straddles the threshold (or there is none): the report \
                names the interval and what would decide it (more levels, a finer reference, \
                runs or repeats that fall on one side)",
            printed_in: "every report",
        },
    ]
}

/// `text` as a markdown table cell: its `|` escaped.
pub fn table_cell(text: &str) -> String {
    text.replace('|', "\\|")
}

/// The words of [`words`] as the markdown table `docs/src/vocabulary.md` carries.
pub fn table() -> String {
    let mut md = String::from(
        "| word | measured quantity | threshold | decided by | printed in |\n|---|---|---|---|---|\n",
    );
    for w in words() {
        let _ = writeln!(
            md,
            "| **{}** | {} | {} | {} | {} |",
            w.word,
            table_cell(w.quantity),
            table_cell(&w.threshold),
            table_cell(w.decided_by),
            w.printed_in
        );
    }
    md
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A rate `value ± half` fitted on four levels against an exact reference.
    fn rate(value: f64, half: f64) -> Estimate {
        Estimate {
            what: "rate".into(),
            value,
            interval: Some((value - half, value + half)),
            bias: Some(0.0),
            levels: 4,
        }
    }

    /// Runs measuring `value` with the others spread to `low` and `high`.
    fn runs(value: f64, low: f64, high: f64) -> Interval {
        Interval::of_runs("figure", value, &[low, high])
    }

    fn verdicts(decide: impl Fn(f64) -> Decision, above: f64, below: f64, astride: f64) {
        let (a, b, s) = (decide(above), decide(below), decide(astride));
        assert_eq!(a.verdict, Verdict::Holds, "{}", a.reason);
        assert_eq!(b.verdict, Verdict::Fails, "{}", b.reason);
        assert_eq!(s.verdict, Verdict::Undecided, "{}", s.reason);
        assert!(s.reason.contains("would decide it"), "{}", s.reason);
    }

    #[test]
    fn converges_and_does_not_converge_by_the_interval_about_zero() {
        verdicts(|v| converges(&rate(v, 0.2)), 0.5, -0.5, 0.1);
        assert_eq!(
            convergence_word(converges(&rate(0.5, 0.2)).verdict),
            "converges"
        );
        assert_eq!(
            convergence_word(converges(&rate(-0.5, 0.2)).verdict),
            "does not converge"
        );
        assert_eq!(
            convergence_word(converges(&rate(0.1, 0.2)).verdict),
            "undecided"
        );
        let extended_old_threshold = converges(&rate(0.2, 0.1));
        assert_eq!(extended_old_threshold.verdict, Verdict::Holds);
    }

    #[test]
    fn bounded_and_grows_by_the_interval_about_the_quarter() {
        verdicts(|v| bounded(&rate(v, 0.05)), 0.0, 0.8, 0.24);
        verdicts(|v| grows(&rate(v, 0.05)), -0.5, 0.0, -0.26);
    }

    #[test]
    fn agrees_and_differs_by_the_interval_about_the_value() {
        verdicts(|v| agrees(&rate(v, 0.02), 1.0), 1.05, 1.3, 1.09);
        assert_eq!(agreement_word(Verdict::Fails), "differs");
    }

    #[test]
    fn alike_by_the_interval_of_the_difference() {
        let b = rate(1.0, 0.05);
        verdicts(
            |v| within_alike_gap(&Estimate::difference("gap", &rate(v, 0.05), &b)),
            1.1,
            1.5,
            1.24,
        );
    }

    #[test]
    fn holds_and_fails_combine_their_decisions() {
        let d = |v: f64| all_of(vec![converges(&rate(v, 0.2)), converges(&rate(1.0, 0.2))]);
        verdicts(d, 0.5, -0.5, 0.1);
    }

    #[test]
    fn ok_and_missed_by_the_repeats_about_the_target() {
        verdicts(
            |v| within_target(&runs(v, v - 5.0, v + 5.0), 60.0),
            40.0,
            80.0,
            57.0,
        );
        assert_eq!(target_word(Verdict::Holds), "ok");
        assert_eq!(target_word(Verdict::Fails), "missed");
        let one = within_target(&Interval::point("wall", 49.3), 60.0);
        assert!(one.reason.contains("as measured"), "{}", one.reason);
    }

    #[test]
    fn the_physics_words_by_the_runs_about_their_tolerances() {
        verdicts(
            |v| penetrating(&runs(v, v * 0.9, v * 1.1)),
            0.5,
            1e-3,
            0.0095,
        );
        verdicts(
            |v| gains_energy(&runs(v, v * 0.9, v * 1.1)),
            0.5,
            1e-3,
            0.048,
        );
        verdicts(
            |v| dissipative(&runs(v, v * 0.9, v * 1.1)),
            0.16,
            1e-3,
            0.0099,
        );
    }

    #[test]
    fn oscillates_and_oscillates_spuriously_by_the_runs_about_their_grades() {
        verdicts(|v| oscillates(&runs(v, v * 0.9, v * 1.1)), 30.0, 1.0, 5.2);
        verdicts(
            |v| oscillates_spuriously(&runs(v, v * 0.99, v * 1.01)),
            578.0,
            10.0,
            100.348,
        );
        let at = oscillates_spuriously(&Interval::point("indicator", 100.348));
        assert_eq!(at.verdict, Verdict::Holds);
        assert!(at.reason.contains("as measured"), "{}", at.reason);
    }

    #[test]
    fn stable_is_none_of_the_four() {
        let calm = Interval::point("figure", 0.0);
        let indicator = Interval::point("indicator", 8.5);
        verdicts(
            |loss| {
                stable(
                    &calm,
                    &calm,
                    &indicator,
                    &runs(loss, loss * 0.9, loss * 1.1),
                )
                .negated()
            },
            0.16,
            1e-3,
            0.0099,
        );
    }

    #[test]
    fn a_figure_that_is_not_finite_is_undecided() {
        let d = gains_energy(&Interval::of_runs("gain", 0.1, &[f64::NAN]));
        assert_eq!(d.verdict, Verdict::Undecided);
        let d = gains_energy(&Interval::point("gain", f64::INFINITY));
        assert_eq!(d.verdict, Verdict::Undecided);
    }

    #[test]
    fn the_table_names_every_word_and_threshold_once() {
        let t = table();
        for line in t.lines() {
            assert_eq!(line.replace("\\|", "").matches('|').count(), 6, "{line}");
        }
        for w in words() {
            assert_eq!(
                t.matches(&format!("| **{}** |", w.word)).count(),
                1,
                "{}",
                w.word
            );
            assert!(t.contains(&table_cell(&w.threshold)), "{}", w.word);
        }
    }
}
