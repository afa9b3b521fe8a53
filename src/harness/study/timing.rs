//! Costs with an interval: the wall time of one piece of work (a case at a level) timed over
//! several runs of it, and the orders those intervals decide.
//!
//! A [`WallCost`] is the median of the runs' wall seconds with their `[min, max]` as its
//! interval: the runs are what the machine gave under its load while the study ran, so no
//! narrower interval is claimed. It has an interval only from [`MIN_RUNS`] runs on; a cost
//! timed fewer times is undecided against any other.
//!
//! **What decides an order.** A is *cheaper* than B when A's whole interval lies below B's
//! (A's max below B's min); B is then *dearer*; overlapping intervals leave the order
//! *undecided*. The *cheapest* of several is the one whose interval lies below
//! every other's ([`cheapest`]); a rank is the range of places the intervals allow
//! ([`rank_ranges`]): `1 + ` the number decidedly cheaper, up to the count less the number
//! decidedly dearer.
//!
//! Where the runs come from: a study's own run of each case and level, and the runs of its
//! round-off ensemble that do the same work (the unperturbed run and the initial-data
//! members, [`crate::harness::study::sensitivity::CaseSensitivity::wall_seconds`]); joined by
//! [`level_runs`].

use serde::{Deserialize, Serialize};

use crate::harness::study::decision::wholly_above;
use crate::harness::study::decision::{Decision, Verdict};
use crate::harness::study::sensitivity::Sensitivity;
use crate::harness::study::CaseStudy;

/// The fewest runs whose `[min, max]` is taken as a cost's interval.
pub const MIN_RUNS: usize = 3;

/// The wall time of one piece of work over its runs (JSON
/// `{"median": s, "min": s, "max": s, "runs": n}`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct WallCost {
    /// The median of the runs' wall seconds (the mean of the two middle ones for an even
    /// count).
    pub median: f64,
    /// The fastest run's seconds.
    pub min: f64,
    /// The slowest run's seconds.
    pub max: f64,
    /// How many runs.
    pub runs: usize,
}

impl WallCost {
    /// The cost of the runs `seconds`; `None` without a finite one (non-finite ones are left
    /// out).
    pub fn of(seconds: &[f64]) -> Option<Self> {
        let mut s: Vec<f64> = seconds.iter().copied().filter(|x| x.is_finite()).collect();
        if s.is_empty() {
            return None;
        }
        s.sort_by(f64::total_cmp);
        let n = s.len();
        let median = if n % 2 == 1 {
            s[n / 2]
        } else {
            0.5 * (s[n / 2 - 1] + s[n / 2])
        };
        Some(Self {
            median,
            min: s[0],
            max: s[n - 1],
            runs: n,
        })
    }

    /// `[min, max]` when there are at least [`MIN_RUNS`] runs.
    pub fn interval(&self) -> Option<(f64, f64)> {
        (self.runs >= MIN_RUNS).then_some((self.min, self.max))
    }

    /// `2.09e-2 s [2.05e-2, 2.13e-2] (18 runs)`, or `2.09e-2 s (1 run: no interval)`.
    pub fn text(&self) -> String {
        match self.interval() {
            Some((low, high)) => format!(
                "{:.3e} s [{low:.3e}, {high:.3e}] ({} runs)",
                self.median, self.runs
            ),
            None => format!(
                "{:.3e} s ({} run{}: no interval)",
                self.median,
                self.runs,
                if self.runs == 1 { "" } else { "s" }
            ),
        }
    }
}

/// Whether `a`'s interval lies wholly below `b`'s; `false` when either has none.
pub fn below(a: &WallCost, b: &WallCost) -> bool {
    match (a.interval(), b.interval()) {
        (Some(a), Some(b)) => wholly_above(b, a),
        _ => false,
    }
}

/// The place each of `costs` can take in the order from cheapest, as `(best, worst)`: `1 +` the
/// number of costs whose interval lies wholly below its own, up to the number of costs less
/// those whose interval lies wholly above. A cost without an interval takes any place
/// (`(1, n)`) and narrows no other's. `None` for an entry without a cost.
pub fn rank_ranges(costs: &[Option<WallCost>]) -> Vec<Option<(usize, usize)>> {
    let present: Vec<&WallCost> = costs.iter().flatten().collect();
    let n = present.len();
    costs
        .iter()
        .map(|c| {
            let c = c.as_ref()?;
            let cheaper = present.iter().filter(|o| below(o, c)).count();
            let dearer = present.iter().filter(|o| below(c, o)).count();
            Some((1 + cheaper, n - dearer))
        })
        .collect()
}

/// A place as a report prints it: `3` when the intervals decide it, `2–5` otherwise.
pub fn rank_text((best, worst): (usize, usize)) -> String {
    if best == worst {
        best.to_string()
    } else {
        format!("{best}–{worst}")
    }
}

/// "The entry of `costs` with the smallest median is the cheapest" (entries named by
/// `names`): holds when its interval lies wholly below every other's, undecided otherwise
/// (with the entries whose intervals it does not clear). The index of that entry with the
/// decision; `None` when no entry has a cost.
pub fn cheapest(names: &[&str], costs: &[Option<WallCost>]) -> Option<(usize, Decision)> {
    let (best, cost) = costs
        .iter()
        .enumerate()
        .filter_map(|(k, c)| Some((k, (*c)?)))
        .min_by(|a, b| a.1.median.total_cmp(&b.1.median))?;
    let uncleared: Vec<String> = costs
        .iter()
        .enumerate()
        .filter(|&(k, _)| k != best)
        .filter_map(|(k, c)| Some((k, (*c)?)))
        .filter(|(_, c)| !below(&cost, c))
        .map(|(k, c)| format!("{} {}", names[k], c.text()))
        .collect();
    let decision = if uncleared.is_empty() {
        Decision {
            verdict: Verdict::Holds,
            reason: format!(
                "{} {}: every other interval lies wholly above",
                names[best],
                cost.text()
            ),
        }
    } else {
        Decision::undecided(format!(
            "{} {} does not lie wholly below {}",
            names[best],
            cost.text(),
            uncleared.join(", ")
        ))
    };
    Some((best, decision))
}

/// The runs of each level of `case` that the study timed, in seconds: its study's run first
/// and, when `sensitivity` has the case at the same levels, its ensemble's runs of the same work
/// (the unperturbed run and the initial-data members).
pub fn level_runs(case: &CaseStudy, sensitivity: Option<&Sensitivity>) -> Vec<Vec<f64>> {
    let nx: Vec<usize> = case.levels.iter().map(|l| l.nx).collect();
    let repeats = sensitivity
        .and_then(|s| s.case(&case.case.id()))
        .filter(|s| s.levels == nx && s.wall_seconds.len() == nx.len())
        .map(|s| s.wall_seconds.as_slice());
    case.levels
        .iter()
        .enumerate()
        .map(|(l, level)| {
            let mut runs = vec![level.timings.total()];
            if let Some(repeats) = repeats {
                runs.extend(&repeats[l]);
            }
            runs
        })
        .collect()
}

/// The cost of each level of `case` over its runs ([`level_runs`]); a level without a finite
/// time has a cost of no run (`NaN`, no interval).
pub fn level_costs(case: &CaseStudy, sensitivity: Option<&Sensitivity>) -> Vec<WallCost> {
    level_runs(case, sensitivity)
        .iter()
        .map(|runs| {
            WallCost::of(runs).unwrap_or(WallCost {
                median: f64::NAN,
                min: f64::NAN,
                max: f64::NAN,
                runs: 0,
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `runs` wall times around `centre`, spread over `±spread` relative.
    fn runs(centre: f64, spread: f64, runs: usize) -> Vec<f64> {
        (0..runs)
            .map(|k| centre * (1.0 + spread * (2.0 * k as f64 / (runs - 1) as f64 - 1.0)))
            .collect()
    }

    #[test]
    fn a_cost_is_the_median_with_the_runs_range_from_three_runs_on() {
        let c = WallCost::of(&[3.0, 1.0, 2.0, 10.0]).unwrap();
        assert_eq!((c.median, c.min, c.max, c.runs), (2.5, 1.0, 10.0, 4));
        assert_eq!(c.interval(), Some((1.0, 10.0)));
        let two = WallCost::of(&[1.0, 2.0]).unwrap();
        assert_eq!(two.interval(), None);
        assert!(two.text().contains("no interval"), "{}", two.text());
        assert!(WallCost::of(&[f64::NAN]).is_none());
    }

    #[test]
    fn the_cheapest_is_decided_by_intervals_wholly_apart() {
        let a = WallCost::of(&runs(1.0, 0.05, 5)).unwrap();
        let b = WallCost::of(&runs(2.0, 0.05, 5)).unwrap();
        let c = WallCost::of(&runs(1.02, 0.05, 5)).unwrap();
        let (best, decided) = cheapest(&["a", "b"], &[Some(a), Some(b)]).unwrap();
        assert_eq!((best, decided.verdict), (0, Verdict::Holds));
        let (_, tied) = cheapest(&["a", "c"], &[Some(a), Some(c)]).unwrap();
        assert_eq!(tied.verdict, Verdict::Undecided);
        assert!(
            tied.reason.contains("does not lie wholly below"),
            "{}",
            tied.reason
        );
        let one = WallCost::of(&[0.1]).unwrap();
        let (best, once) = cheapest(&["one", "b"], &[Some(one), Some(b)]).unwrap();
        assert_eq!((best, once.verdict), (0, Verdict::Undecided));
    }

    #[test]
    fn ranks_are_the_places_the_intervals_allow() {
        let costs = [
            Some(WallCost::of(&runs(1.0, 0.05, 5)).unwrap()),
            Some(WallCost::of(&runs(1.02, 0.05, 5)).unwrap()),
            Some(WallCost::of(&runs(2.0, 0.05, 5)).unwrap()),
            None,
            Some(WallCost::of(&[1.5]).unwrap()),
        ];
        let ranks = rank_ranges(&costs);
        assert_eq!(
            ranks,
            vec![Some((1, 3)), Some((1, 3)), Some((3, 4)), None, Some((1, 4))]
        );
        assert_eq!(rank_text((3, 3)), "3");
        assert_eq!(rank_text((1, 2)), "1–2");
        let names = ["a", "b", "c", "d", "e"];
        let (k, d) = cheapest(&names, &costs).unwrap();
        assert_eq!((k, d.verdict), (0, Verdict::Undecided));
        assert!(d.reason.contains("b 1.020e0 s"), "{}", d.reason);
        let (k, d) = cheapest(&["a", "c"], &[costs[0], costs[2]]).unwrap();
        assert_eq!((k, d.verdict), (0, Verdict::Holds), "{}", d.reason);
    }
}
