//! Verdicts decided by intervals: the one rule every verdict that rests on a fitted rate follows.
//!
//! An [`Estimate`] is a fitted quantity (a rate, a difference of rates) with its 95 %
//! confidence interval and a bound on how far a bias of its reference could move it. Compared
//! with a threshold, the interval is first widened on both sides by the bias bound (0 for an
//! exact reference), then:
//! * the statement "above the threshold" **holds** when the widened interval lies entirely above
//!   it, **fails** when it lies entirely at or below it, and is **undecided** otherwise;
//! * an estimate without an interval (a fit over fewer than three levels) or with an unbounded
//!   bias is undecided whatever its value.
//!
//! A statement made of several such decisions combines them in three-valued logic
//! ([`all_of`], [`any_of`]): it holds when every decision it needs is made and satisfied, fails
//! when one it needs is made and contradicted, and is undecided otherwise. An undecided
//! verdict's reason names the interval it has and what would decide it, computed from the data:
//! the half-width the interval would need, the number of levels it was fitted on, or a finer
//! reference when the bias bound alone straddles the threshold.

use serde::{Deserialize, Serialize};

use super::rates::RateFit;

/// A three-valued verdict.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Verdict {
    /// Every decision it needs is made and satisfied.
    Holds,
    /// A decision it needs is made and contradicted.
    Fails,
    /// Neither: the intervals cannot tell.
    Undecided,
}

impl Verdict {
    /// The word a report prints.
    pub fn word(self) -> &'static str {
        match self {
            Verdict::Holds => "holds",
            Verdict::Fails => "fails",
            Verdict::Undecided => "undecided",
        }
    }

    /// `Holds` for `true`, `Fails` for `false`: a verdict decided without an interval.
    pub fn of(decided: bool) -> Self {
        if decided {
            Verdict::Holds
        } else {
            Verdict::Fails
        }
    }
}

/// A verdict with what decided it or, undecided, what it has and what would decide it (in
/// JSON `{"verdict": "holds" | "fails" | "undecided", "reason": "…"}`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Decision {
    /// The verdict.
    pub verdict: Verdict,
    /// Why, in a sentence computed from the data.
    pub reason: String,
}

impl Decision {
    /// The opposite statement: holds where this fails and the reverse, undecided where this is.
    pub fn negated(self) -> Self {
        let verdict = match self.verdict {
            Verdict::Holds => Verdict::Fails,
            Verdict::Fails => Verdict::Holds,
            Verdict::Undecided => Verdict::Undecided,
        };
        Self { verdict, ..self }
    }

    /// An undecided decision with `reason`.
    pub fn undecided(reason: impl Into<String>) -> Self {
        Self {
            verdict: Verdict::Undecided,
            reason: reason.into(),
        }
    }
}

/// The reasons of the decisions with `verdict`, each once, joined.
fn reasons_of(decisions: &[Decision], verdict: Verdict) -> String {
    let mut reasons: Vec<&str> = Vec::new();
    for reason in decisions
        .iter()
        .filter(|d| d.verdict == verdict)
        .flat_map(|d| d.reason.split("; "))
    {
        if !reasons.contains(&reason) {
            reasons.push(reason);
        }
    }
    reasons.join("; ")
}

/// Every one of `decisions`: fails when one fails (with the failing ones' reasons), holds when
/// all hold, undecided otherwise (with the undecided ones' reasons).
pub fn all_of(decisions: Vec<Decision>) -> Decision {
    let verdict = if decisions.iter().any(|d| d.verdict == Verdict::Fails) {
        Verdict::Fails
    } else if decisions.iter().all(|d| d.verdict == Verdict::Holds) {
        Verdict::Holds
    } else {
        Verdict::Undecided
    };
    Decision {
        verdict,
        reason: reasons_of(&decisions, verdict),
    }
}

/// One of `decisions`: holds when one holds (with the holding ones' reasons), fails when all
/// fail, undecided otherwise.
pub fn any_of(decisions: Vec<Decision>) -> Decision {
    all_of(decisions.into_iter().map(Decision::negated).collect()).negated()
}

/// A fitted quantity with its 95 % interval and its reference's bias bound.
#[derive(Debug, Clone, PartialEq)]
pub struct Estimate {
    /// What it is, as a reason names it (e.g. `MOD u_L2_H rate`).
    pub what: String,
    /// The fitted value.
    pub value: f64,
    /// The 95 % interval; `None` for a fit over fewer than three levels.
    pub interval: Option<(f64, f64)>,
    /// How far a bias of the reference can move the value; `None`: unbounded.
    pub bias: Option<f64>,
    /// The levels it was fitted on.
    pub levels: usize,
}

impl Estimate {
    /// The rate of `fit` (undecidable without one: `NaN`, no interval) with the bias bound
    /// `bias` (`Some(0.0)` for an exact reference).
    pub fn rate(what: impl Into<String>, fit: Option<RateFit>, bias: Option<f64>) -> Self {
        Self {
            what: what.into(),
            value: fit.map_or(f64::NAN, |f| f.rate),
            interval: fit.and_then(|f| Some((f.ci_low?, f.ci_high?))),
            bias,
            levels: fit.map_or(0, |f| f.levels),
        }
    }

    /// An ensemble's spread of a quantity fitted on `levels` levels: its `median`, with `range`
    /// in the interval's place and no bias. `range` holds at least the members' `[min, max]`
    /// (the samples round-off gives); a caller that has each member's own fit interval joins
    /// them in (the tables' agreement does:
    /// [`crate::harness::study::sensitivity::CaseSensitivity::rate_interval`]).
    pub fn of_ensemble(
        what: impl Into<String>,
        median: f64,
        range: (f64, f64),
        levels: usize,
    ) -> Self {
        Self {
            what: what.into(),
            value: median,
            interval: Some(range),
            bias: Some(0.0),
            levels,
        }
    }

    /// `a − b`: its interval's half-width the sum of theirs and its bias bound the sum of
    /// theirs (both bounds of the two 95 % intervals, no independence assumed), on the fewer
    /// of their levels.
    pub fn difference(what: impl Into<String>, a: &Estimate, b: &Estimate) -> Self {
        let interval = a.interval.zip(b.interval).map(|((al, ah), (bl, bh))| {
            let half = 0.5 * (ah - al) + 0.5 * (bh - bl);
            let centre = a.value - b.value;
            (centre - half, centre + half)
        });
        Self {
            what: what.into(),
            value: a.value - b.value,
            interval,
            bias: a.bias.zip(b.bias).map(|(x, y)| x + y),
            levels: a.levels.min(b.levels),
        }
    }

    /// The interval widened by the bias bound, or why there is none to decide with.
    fn widened(&self) -> Result<(f64, f64), Decision> {
        if self.levels == 0 && !self.value.is_finite() {
            return Err(Decision::undecided(format!(
                "{} is not computed on any level (the runs lack what it needs)",
                self.what
            )));
        }
        let Some((low, high)) = self.interval.filter(|_| self.value.is_finite()) else {
            return Err(Decision::undecided(format!(
                "{} {:.2} has no 95 % interval: it is fitted on {} levels and an interval needs \
                 3; more levels would decide it",
                self.what, self.value, self.levels
            )));
        };
        let Some(bias) = self.bias else {
            return Err(Decision::undecided(format!(
                "{} {:.2} [{low:.2}, {high:.2}]: the reference's rate-bias bound is unbounded; \
                 a finer reference would decide it",
                self.what, self.value
            )));
        };
        Ok((low - bias, high + bias))
    }

    /// `[low, high]` and, with a bias, `± bias → [low', high']`.
    fn interval_text(&self, (low, high): (f64, f64)) -> String {
        let (l, h) = self.interval.unwrap_or((low, high));
        let bias = self.bias.unwrap_or(0.0);
        if bias > 0.0 {
            format!("[{l:.2}, {h:.2}] widened by the bias bound {bias:.2} to [{low:.2}, {high:.2}]")
        } else {
            format!("[{l:.2}, {h:.2}]")
        }
    }

    /// What would decide a widened interval straddling `threshold`: the half-width it would
    /// need with this bias bound (and this study's levels), or a finer reference when the bias
    /// bound alone reaches the threshold.
    fn what_would_decide(&self, threshold: f64) -> String {
        let bias = self.bias.unwrap_or(0.0);
        let needed = (self.value - threshold).abs() - bias;
        let half = self.interval.map_or(f64::NAN, |(l, h)| 0.5 * (h - l));
        if needed > 0.0 {
            let finer = if bias > 0.0 {
                " or a finer reference (a smaller bias bound)"
            } else {
                ""
            };
            format!(
                "a half-width below {needed:.2} (it is {half:.2}) would decide it: more levels \
                 (this fit has {}){finer}",
                self.levels
            )
        } else {
            format!(
                "the bias bound {bias:.2} alone reaches {threshold:.2}: only a finer reference \
                 would decide it"
            )
        }
    }

    /// What is decided, its value and its widened interval `widened`, as a reason begins.
    fn head(&self, widened: (f64, f64)) -> String {
        format!(
            "{} {:.2} {}",
            self.what,
            self.value,
            self.interval_text(widened)
        )
    }

    /// "The value is above `threshold`" (see the module).
    pub fn above(&self, threshold: f64) -> Decision {
        let (low, high) = match self.widened() {
            Ok(w) => w,
            Err(undecided) => return undecided,
        };
        let head = self.head((low, high));
        if low > threshold {
            Decision {
                verdict: Verdict::Holds,
                reason: format!("{head} > {threshold}"),
            }
        } else if high <= threshold {
            Decision {
                verdict: Verdict::Fails,
                reason: format!("{head} ≤ {threshold}"),
            }
        } else {
            Decision::undecided(format!(
                "{head} contains {threshold}: {}",
                self.what_would_decide(threshold)
            ))
        }
    }

    /// "The value lies within `[low, high]`": holds when the widened interval does, fails when
    /// it lies entirely outside, undecided otherwise.
    pub fn within(&self, low: f64, high: f64) -> Decision {
        let (wl, wh) = match self.widened() {
            Ok(w) => w,
            Err(undecided) => return undecided,
        };
        let head = self.head((wl, wh));
        if wl >= low && wh <= high {
            Decision {
                verdict: Verdict::Holds,
                reason: format!("{head} ⊂ [{low:.2}, {high:.2}]"),
            }
        } else if wh < low || wl > high {
            Decision {
                verdict: Verdict::Fails,
                reason: format!("{head} outside [{low:.2}, {high:.2}]"),
            }
        } else {
            let nearer = if (self.value - low).abs() < (self.value - high).abs() {
                low
            } else {
                high
            };
            Decision::undecided(format!(
                "{head} overlaps an end of [{low:.2}, {high:.2}]: {}",
                self.what_would_decide(nearer)
            ))
        }
    }
}

/// The one order of two measured intervals every ranking uses (the vocabulary's faster and cheaper,
/// the fronts of the schemes report, the extended table's fastest row, the work-precision ranks): the interval
/// `[a_low, a_high]` lies wholly above `[b_low, b_high]`, `a_low > b_high`.
pub fn wholly_above((a_low, _): (f64, f64), (_, b_high): (f64, f64)) -> bool {
    a_low > b_high
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rate(value: f64, half: Option<f64>, bias: Option<f64>) -> Estimate {
        Estimate {
            what: "rate".into(),
            value,
            interval: half.map(|h| (value - h, value + h)),
            bias,
            levels: if half.is_some() { 4 } else { 2 },
        }
    }

    #[test]
    fn an_interval_above_zero_converges() {
        let d = rate(0.8, Some(0.3), Some(0.0)).above(0.0);
        assert_eq!(d.verdict, Verdict::Holds, "{}", d.reason);
    }

    #[test]
    fn an_interval_at_or_below_zero_does_not_converge() {
        let d = rate(-0.5, Some(0.3), Some(0.0)).above(0.0);
        assert_eq!(d.verdict, Verdict::Fails, "{}", d.reason);
        assert_eq!(d.negated().verdict, Verdict::Holds);
        let touching = rate(-0.3, Some(0.3), Some(0.0)).above(0.0);
        assert_eq!(touching.verdict, Verdict::Fails, "{}", touching.reason);
    }

    #[test]
    fn an_interval_straddling_zero_is_undecided_and_says_what_would_decide_it() {
        let d = rate(0.01, Some(4.98), Some(0.0)).above(0.0);
        assert_eq!(d.verdict, Verdict::Undecided);
        assert!(d.reason.contains("[-4.97, 4.99]"), "{}", d.reason);
        assert!(d.reason.contains("below 0.01"), "{}", d.reason);
        assert!(d.reason.contains("this fit has 4"), "{}", d.reason);
    }

    #[test]
    fn an_interval_straddling_zero_only_once_widened_by_the_bias_is_undecided() {
        let exact = rate(0.5, Some(0.2), Some(0.0)).above(0.0);
        assert_eq!(exact.verdict, Verdict::Holds);
        let biased = rate(0.5, Some(0.2), Some(0.4)).above(0.0);
        assert_eq!(biased.verdict, Verdict::Undecided, "{}", biased.reason);
        assert!(
            biased.reason.contains("a finer reference"),
            "{}",
            biased.reason
        );
        let dominated = rate(0.5, Some(0.2), Some(0.6)).above(0.0);
        assert!(dominated.reason.contains("only a finer reference"));
        let unbounded = rate(0.5, Some(0.2), None).above(0.0);
        assert_eq!(unbounded.verdict, Verdict::Undecided);
        assert!(
            unbounded.reason.contains("unbounded"),
            "{}",
            unbounded.reason
        );
    }

    #[test]
    fn a_rate_without_an_interval_is_undecided_whatever_its_value() {
        for value in [-3.0, 3.0] {
            let d = rate(value, None, Some(0.0)).above(0.0);
            assert_eq!(d.verdict, Verdict::Undecided);
            assert!(d.reason.contains("fitted on 2 levels"), "{}", d.reason);
        }
        let missing = Estimate::rate("rate", None, Some(0.0)).above(0.0);
        assert_eq!(missing.verdict, Verdict::Undecided);
    }

    #[test]
    fn a_difference_adds_the_half_widths_and_the_biases() {
        let a = rate(1.0, Some(0.05), Some(0.01));
        let b = rate(0.9, Some(0.05), Some(0.01));
        let d = Estimate::difference("gap", &a, &b);
        let (low, high) = d.interval.unwrap();
        assert!((high - low - 0.2).abs() < 1e-12 && (d.bias.unwrap() - 0.02).abs() < 1e-12);
        assert_eq!(d.within(-0.25, 0.25).verdict, Verdict::Holds);
        let far = Estimate::difference("gap", &rate(2.0, Some(0.05), Some(0.0)), &b);
        assert_eq!(far.within(-0.25, 0.25).verdict, Verdict::Fails);
        let wide = Estimate::difference("gap", &rate(1.0, Some(1.0), Some(0.0)), &b);
        assert_eq!(wide.within(-0.25, 0.25).verdict, Verdict::Undecided);
    }

    #[test]
    fn three_valued_combinations() {
        let holds = || rate(1.0, Some(0.1), Some(0.0)).above(0.0);
        let fails = || rate(-1.0, Some(0.1), Some(0.0)).above(0.0);
        let open = || rate(0.0, Some(1.0), Some(0.0)).above(0.0);
        assert_eq!(all_of(vec![holds(), holds()]).verdict, Verdict::Holds);
        assert_eq!(all_of(vec![holds(), open()]).verdict, Verdict::Undecided);
        assert_eq!(all_of(vec![open(), fails()]).verdict, Verdict::Fails);
        assert_eq!(any_of(vec![fails(), open()]).verdict, Verdict::Undecided);
        assert_eq!(any_of(vec![fails(), holds()]).verdict, Verdict::Holds);
        assert_eq!(any_of(vec![fails(), fails()]).verdict, Verdict::Fails);
    }
}
