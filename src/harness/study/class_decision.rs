//! How sure a round-off class is: the rules of [`super::sensitivity`] applied as three-valued
//! decisions ([`super::decision`]), so that a class the ensemble cannot decide says so.
//!
//! A class rests on each level's separations (whether a member parts, the largest separation,
//! the median fitted growth of the separation) and, in a refinement study, on the ensemble
//! ranges of the rates; all of them are fields of the sensitivity files, so a class written
//! before this rule is judged by it too.
//! * *reproducible* is decided when no member parts at any level;
//! * otherwise the class is *chaotic* when both tests below hold and *event-sensitive* when one
//!   fails ([`super::decision::all_of`]):
//!   - **runs away**: holds when at some level the largest separation reaches
//!     [`RUNAWAY`] and that level's median growth is finite (an exponential growth fitted over
//!     at least [`MIN_GROWTH_DECADES`] decades); fails when no level reaches [`RUNAWAY`];
//!     undecided otherwise: the separation reaches [`RUNAWAY`] with no finite growth (its
//!     decades crossed within one step), a jump that tells neither exponential growth nor a
//!     bounded event;
//!   - **rates vary** (a refinement study; at one mesh there is no rate and the separation
//!     alone decides): holds when some rate's ensemble range exceeds [`CHAOTIC_RATE_RANGE`],
//!     fails when rates were fitted and none does, undecided when none was (fewer than two
//!     levels).
//!
//! The class's decision holds when these decide it and is undecided, with the test that could
//! not be made and what would make it, otherwise. The class itself is the rule's as before
//! ([`super::sensitivity::SensitivityClass`]): an undecided one is the class the gates and
//! tables use, stated with the doubt.

use std::collections::BTreeMap;

use super::decision::{all_of, Decision, Verdict};
use super::sensitivity::{
    CaseSensitivity, RunSensitivity, Spread, CHAOTIC_RATE_RANGE, MIN_GROWTH_DECADES, PARTING,
    RUNAWAY,
};

/// One level's separations, as a class reads them.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LevelSeparation {
    /// `NX` of the level; `None` for a single run (the stability suite's).
    pub nx: Option<usize>,
    /// Whether some member parts (by more than [`PARTING`]).
    pub parted: bool,
    /// The median fitted growth of the separation (per unit time), if any was fitted.
    pub growth: Option<f64>,
    /// The largest separation of any member.
    pub largest: f64,
}

impl LevelSeparation {
    /// `at NX = n ` or nothing for a single run.
    fn at(&self) -> String {
        self.nx.map_or(String::new(), |nx| format!("at NX = {nx} "))
    }
}

impl CaseSensitivity {
    /// Whether the class is decided by the ensemble ([`class_decision`] over its levels).
    pub fn class_decision(&self) -> Decision {
        let levels: Vec<LevelSeparation> = self
            .levels
            .iter()
            .enumerate()
            .map(|(k, &nx)| LevelSeparation {
                nx: Some(nx),
                parted: self
                    .predictability_steps
                    .get(k)
                    .copied()
                    .flatten()
                    .is_some(),
                growth: self.separation_growth.get(k).copied().flatten(),
                largest: self.largest_separation.get(k).copied().unwrap_or(0.0),
            })
            .collect();
        class_decision(&levels, Some(&self.rates))
    }
}

impl RunSensitivity {
    /// Whether the class is decided by the members' separations alone ([`class_decision`] at
    /// one mesh).
    pub fn class_decision(&self) -> Decision {
        let level = LevelSeparation {
            nx: None,
            parted: self.predictability_step.is_some(),
            growth: self.separation_growth,
            largest: self.largest_separation,
        };
        class_decision(&[level], None)
    }
}

/// Whether the class of `levels` (and, for a refinement study, of the ensemble `rates`: norm
/// key → spread of its rate; `None` at one mesh) is decided (see the module): `holds` with the
/// evidence that decides it, or `undecided` with what it lacks.
pub fn class_decision(
    levels: &[LevelSeparation],
    rates: Option<&BTreeMap<String, Spread>>,
) -> Decision {
    if !levels.iter().any(|l| l.parted) {
        let largest = levels.iter().fold(0.0_f64, |m, l| m.max(l.largest));
        return Decision {
            verdict: Verdict::Holds,
            reason: format!(
                "reproducible: no member parts by more than {PARTING:e} (largest separation \
                 {largest:.1e})"
            ),
        };
    }
    let mut tests = vec![runs_away(levels)];
    tests.extend(rates.map(rates_vary));
    let chaotic = all_of(tests);
    let verdict = match chaotic.verdict {
        Verdict::Holds | Verdict::Fails => Verdict::Holds,
        Verdict::Undecided => Verdict::Undecided,
    };
    let class = match chaotic.verdict {
        Verdict::Holds => "chaotic: ",
        Verdict::Fails => "event-sensitive: ",
        Verdict::Undecided => "chaotic or event-sensitive: ",
    };
    Decision {
        verdict,
        reason: format!("{class}{}", chaotic.reason),
    }
}

/// "Some member's separation runs away exponentially" (see the module).
fn runs_away(levels: &[LevelSeparation]) -> Decision {
    let reached: Vec<&LevelSeparation> = levels.iter().filter(|l| l.largest >= RUNAWAY).collect();
    if let Some(l) = reached
        .iter()
        .find(|l| l.growth.is_some_and(f64::is_finite))
    {
        return Decision {
            verdict: Verdict::Holds,
            reason: format!(
                "{}a separation grows exponentially (median growth {:.1} per unit time) to \
                 {:.1e} ≥ {RUNAWAY:e}",
                l.at(),
                l.growth.unwrap_or(f64::NAN),
                l.largest
            ),
        };
    }
    match reached.first() {
        Some(l) => Decision::undecided(format!(
            "{}a separation reaches {:.1e} ≥ {RUNAWAY:e} with no growth fitted (its decade \
             thresholds crossed within one step, or fewer than {MIN_GROWTH_DECADES}): a jump \
             tells exponential growth from a bounded event no more than it tells the reverse; \
             members whose separation crosses the decades over several steps would decide it",
            l.at(),
            l.largest
        )),
        None => {
            let largest = levels.iter().fold(0.0_f64, |m, l| m.max(l.largest));
            Decision {
                verdict: Verdict::Fails,
                reason: format!(
                    "members part, but the largest separation {largest:.1e} stays below \
                     {RUNAWAY:e}"
                ),
            }
        }
    }
}

/// "Some rate's ensemble range exceeds [`CHAOTIC_RATE_RANGE`]" (see the module).
fn rates_vary(rates: &BTreeMap<String, Spread>) -> Decision {
    let Some((norm, range)) = rates
        .iter()
        .map(|(n, s)| (n.as_str(), s.range()))
        .max_by(|a, b| a.1.total_cmp(&b.1))
    else {
        return Decision::undecided(
            "no rate was fitted over the members (fewer than two levels): more levels would \
             decide whether the rates vary",
        );
    };
    let (verdict, relation) = if range > CHAOTIC_RATE_RANGE {
        (Verdict::Holds, ">")
    } else {
        (Verdict::Fails, "≤")
    };
    Decision {
        verdict,
        reason: format!(
            "the largest ensemble range of a rate is {range:.2e} ({norm}) {relation} \
             {CHAOTIC_RATE_RANGE}"
        ),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn level(parted: bool, growth: Option<f64>, largest: f64) -> LevelSeparation {
        LevelSeparation {
            nx: Some(80),
            parted,
            growth,
            largest,
        }
    }

    fn rates(range: f64) -> BTreeMap<String, Spread> {
        BTreeMap::from([(
            "u_Linf_H".to_string(),
            Spread {
                min: 0.8,
                median: 0.8,
                max: 0.8 + range,
            },
        )])
    }

    #[test]
    fn an_ensemble_that_never_parts_decides_reproducible() {
        let d = class_decision(&[level(false, None, 3e-9)], Some(&rates(0.0)));
        assert_eq!(d.verdict, Verdict::Holds);
        assert!(d.reason.starts_with("reproducible"), "{}", d.reason);
    }

    #[test]
    fn a_fitted_runaway_with_varying_rates_decides_chaotic() {
        let d = class_decision(&[level(true, Some(140.0), 4e4)], Some(&rates(0.17)));
        assert_eq!(d.verdict, Verdict::Holds, "{}", d.reason);
        assert!(d.reason.starts_with("chaotic: "), "{}", d.reason);
        assert!(d.reason.contains("0.005"), "{}", d.reason);
    }

    #[test]
    fn either_test_failing_decides_event_sensitive() {
        let bounded = class_decision(&[level(true, Some(5.0), 3e-7)], Some(&rates(0.17)));
        assert_eq!(bounded.verdict, Verdict::Holds);
        assert!(bounded.reason.contains("stays below"), "{}", bounded.reason);
        let steady = class_decision(&[level(true, Some(5.0), 1e-3)], Some(&rates(1e-5)));
        assert_eq!(steady.verdict, Verdict::Holds);
        assert!(
            steady.reason.starts_with("event-sensitive"),
            "{}",
            steady.reason
        );
    }

    #[test]
    fn a_runaway_without_a_fitted_growth_is_undecided() {
        for growth in [None, Some(f64::INFINITY)] {
            let d = class_decision(&[level(true, growth, 2e-3)], Some(&rates(0.17)));
            assert_eq!(d.verdict, Verdict::Undecided, "{}", d.reason);
            assert!(d.reason.contains("no growth fitted"), "{}", d.reason);
        }
        let one_mesh = LevelSeparation {
            nx: None,
            ..level(true, None, 2e-3)
        };
        let d = class_decision(&[one_mesh], None);
        assert_eq!(d.verdict, Verdict::Undecided);
        assert!(
            d.reason.starts_with("chaotic or event-sensitive"),
            "{}",
            d.reason
        );
    }

    #[test]
    fn a_runaway_without_fitted_rates_is_undecided_but_one_mesh_needs_none() {
        let d = class_decision(&[level(true, Some(40.0), 1e-2)], Some(&BTreeMap::new()));
        assert_eq!(d.verdict, Verdict::Undecided);
        assert!(d.reason.contains("more levels"), "{}", d.reason);
        let one_mesh = LevelSeparation {
            nx: None,
            ..level(true, Some(40.0), 1e-2)
        };
        assert_eq!(class_decision(&[one_mesh], None).verdict, Verdict::Holds);
    }
}
