//! The note's statements (§3.1, §3.1.1) as verdicts computed from a study, so that a report
//! says whether they hold rather than repeating them.
//!
//! The criteria are fixed here, once, before looking at any particular study:
//! * a norm **converges** when its least-squares rate over all levels is above
//!   [`CONVERGENCE_RATE`] = 0: the error decreases as `h` does (the note's "converges to 0"
//!   against "unfortunately not the case", read from curves; how fast is the rate itself);
//! * a case **oscillates** when its indicator `TV(Σλ_h) / TV(Σλ_ref)` on the finest level is at
//!   least [`verdicts::OSCILLATES_FROM`] (the 1D tables' boundary between "No" and "Small");
//! * two cases **behave alike** in a norm when both converge or both do not, and their rates
//!   differ by at most [`ALIKE_RATE_GAP`].

use serde::{Deserialize, Serialize};

use crate::harness::problem::{MassVariant, Scheme};
use crate::harness::run::norms::Norm;
use crate::harness::study::{verdicts, Case, CaseStudy, Study};

/// The rate above which a norm counts as converging.
pub const CONVERGENCE_RATE: f64 = 0.0;

/// Largest rate difference of two cases that behave alike.
pub const ALIKE_RATE_GAP: f64 = 0.25;

/// One statement of the note and whether the study supports it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Finding {
    /// The statement.
    pub claim: String,
    /// Where the note makes it.
    pub source: String,
    /// Whether it holds in this study.
    pub holds: bool,
    /// Whether it still holds when every rate it uses moves by the reference's rate-bias bound
    /// for that norm ([`super::ReferenceCheck::rate_bias`]): a rate decision then needs a
    /// margin, so an error in the reference of the size measured cannot flip it.
    pub robust: bool,
    /// The numbers it was decided on.
    pub evidence: String,
}

fn case(study: &Study, scheme: Scheme, mass: MassVariant) -> Option<&CaseStudy> {
    study.case(&Case { scheme, mass })
}

fn rate(c: &CaseStudy, norm: Norm) -> f64 {
    c.norm(norm)
        .and_then(|r| r.fit)
        .map_or(f64::NAN, |f| f.rate)
}

/// The rate decisions, each required to hold with a margin per norm (0: as measured).
struct Judge<'m> {
    margin: &'m dyn Fn(Norm) -> f64,
}

impl Judge<'_> {
    fn converges(&self, c: &CaseStudy, norm: Norm) -> bool {
        rate(c, norm) - (self.margin)(norm) > CONVERGENCE_RATE
    }

    fn does_not_converge(&self, c: &CaseStudy, norm: Norm) -> bool {
        rate(c, norm) + (self.margin)(norm) <= CONVERGENCE_RATE
    }

    /// Both converge or neither does, and the rates are within [`ALIKE_RATE_GAP`].
    fn alike(&self, a: &CaseStudy, b: &CaseStudy, norm: Norm) -> bool {
        let same = (self.converges(a, norm) && self.converges(b, norm))
            || (self.does_not_converge(a, norm) && self.does_not_converge(b, norm));
        same && (rate(a, norm) - rate(b, norm)).abs() + 2.0 * (self.margin)(norm) <= ALIKE_RATE_GAP
    }
}

fn oscillates(c: &CaseStudy) -> bool {
    c.oscillation_indicator().is_some_and(verdicts::oscillates)
}

fn rates_text(label: &str, c: &CaseStudy, norms: &[Norm]) -> String {
    let list: Vec<String> = norms
        .iter()
        .map(|&n| format!("{} {:.2}", n.key(), rate(c, n)))
        .collect();
    format!("{label}: {}", list.join(", "))
}

fn indicator_text(label: &str, c: &CaseStudy) -> String {
    format!(
        "{label} indicator {:.1}",
        c.oscillation_indicator().unwrap_or(f64::NAN)
    )
}

/// The note's findings for Crank–Nicolson and backward Euler with both masses, judged as
/// measured (`holds`) and with every rate allowed to move by `rate_bias` of its norm
/// (`robust`); a finding whose cases are not in the study does not hold, with the reason.
pub fn note_findings(study: &Study, rate_bias: &dyn Fn(Norm) -> f64) -> Vec<Finding> {
    let exact = Judge { margin: &|_| 0.0 };
    let strict = Judge { margin: rate_bias };
    judged(study, &exact)
        .into_iter()
        .zip(judged(study, &strict))
        .map(|(mut f, g)| {
            f.robust = f.holds && g.holds;
            f
        })
        .collect()
}

fn judged(study: &Study, judge: &Judge<'_>) -> Vec<Finding> {
    let cn = Scheme::CRANK_NICOLSON;
    let be = Scheme::BACKWARD_EULER;
    let (std, modified) = (MassVariant::Standard, MassVariant::Redistributed);
    let missing = |claim: &str, source: &str| Finding {
        claim: claim.to_string(),
        source: source.to_string(),
        holds: false,
        robust: false,
        evidence: "not tested: a case is missing from the study".to_string(),
    };
    let energy = [Norm::EnergyLinf, Norm::EnergyL2];
    let mut out = Vec::new();
    match (case(study, cn, std), case(study, cn, modified)) {
        (Some(s), Some(m)) => {
            out.push(Finding {
                claim: "Crank–Nicolson: the redistributed mass removes the contact oscillations \
                        that the standard mass shows"
                    .into(),
                source: "§3.1, Figure 1".into(),
                holds: oscillates(s) && !oscillates(m),
                robust: false,
                evidence: format!("{}; {}", indicator_text("STD", s), indicator_text("MOD", m)),
            });
            out.push(Finding {
                claim: "Crank–Nicolson: with the redistributed mass the energy error converges"
                    .into(),
                source: "§3.1, Figures 2, 3e–f".into(),
                holds: energy.iter().all(|&n| judge.converges(m, n)),
                robust: false,
                evidence: rates_text("MOD", m, &energy),
            });
            out.push(Finding {
                claim: "Crank–Nicolson: with the standard mass the energy error does not converge"
                    .into(),
                source: "§3.1, Figures 2, 3e–f".into(),
                holds: energy.iter().all(|&n| judge.does_not_converge(s, n)),
                robust: false,
                evidence: rates_text("STD", s, &energy),
            });
            let vl = [Norm::DisplacementL2V, Norm::MultiplierL2];
            out.push(Finding {
                claim: "Crank–Nicolson: u in L²(0,T;V) and the contact force in L²(0,T) converge \
                        with the redistributed mass and not with the standard one"
                    .into(),
                source: "§3.1, Figure 3c–d".into(),
                holds: vl
                    .iter()
                    .all(|&n| judge.converges(m, n) && judge.does_not_converge(s, n)),
                robust: false,
                evidence: format!(
                    "{}; {}",
                    rates_text("MOD", m, &vl),
                    rates_text("STD", s, &vl)
                ),
            });
            let h = [Norm::DisplacementLinfH, Norm::DisplacementL2H];
            out.push(Finding {
                claim: "Crank–Nicolson: u in L∞(0,T;H) and L²(0,T;H) converges with both masses"
                    .into(),
                source: "§3.1, Figure 3a–b".into(),
                holds: h
                    .iter()
                    .all(|&n| judge.converges(m, n) && judge.converges(s, n)),
                robust: false,
                evidence: format!("{}; {}", rates_text("MOD", m, &h), rates_text("STD", s, &h)),
            });
        }
        _ => out.push(missing("Crank–Nicolson findings", "§3.1")),
    }
    match (case(study, be, std), case(study, be, modified)) {
        (Some(s), Some(m)) => {
            let alike: Vec<Norm> = Norm::ALL
                .into_iter()
                .filter(|&n| judge.alike(s, m, n))
                .collect();
            out.push(Finding {
                claim: format!(
                    "Backward Euler: both masses behave alike (in every norm both converge or \
                     neither does, with rates within {ALIKE_RATE_GAP}) and neither oscillates"
                ),
                source: "§3.1.1, Figures 6–8".into(),
                holds: alike.len() == Norm::ALL.len() && !oscillates(s) && !oscillates(m),
                robust: false,
                evidence: format!(
                    "{}; {}; {}; {}",
                    rates_text("STD", s, &Norm::ALL),
                    rates_text("MOD", m, &Norm::ALL),
                    indicator_text("STD", s),
                    indicator_text("MOD", m)
                ),
            });
        }
        _ => out.push(missing("Backward Euler findings", "§3.1.1")),
    }
    out
}

#[cfg(test)]
mod tests {
    use std::collections::BTreeMap;

    use super::*;
    use crate::harness::run::Timings;
    use crate::harness::study::{LevelRecord, StudyConfig};

    /// A case whose every norm converges at `rates[norm]` (errors `h^p`), with `indicator` on
    /// every level.
    fn synthetic(
        scheme: Scheme,
        mass: MassVariant,
        rate_of: &dyn Fn(Norm) -> f64,
        indicator: f64,
    ) -> CaseStudy {
        let h = [0.1, 0.05, 0.025, 0.0125];
        let levels = h
            .iter()
            .map(|&h| LevelRecord {
                nx: (1.0 / h) as usize,
                h,
                dt: h / 2.0,
                steps: 1,
                dofs: 1,
                timings: Timings::default(),
                multiplier_variation_ratio: Some(indicator),
            })
            .collect();
        let errors: BTreeMap<Norm, Vec<f64>> = Norm::ALL
            .into_iter()
            .map(|n| (n, h.iter().map(|x: &f64| x.powf(rate_of(n))).collect()))
            .collect();
        CaseStudy::from_levels(Case { scheme, mass }, levels, errors)
    }

    /// The note's picture: CN-STD converges only in H and oscillates; the others converge.
    fn note_like(mod_indicator: f64) -> Study {
        let cn = Scheme::CRANK_NICOLSON;
        let be = Scheme::BACKWARD_EULER;
        let std_cn = |n: Norm| match n {
            Norm::DisplacementLinfH | Norm::DisplacementL2H => 0.3,
            _ => -0.5,
        };
        Study {
            config: StudyConfig {
                levels: vec![10, 20, 40, 80],
                ratio: 2.0,
                horizon: 2.0,
                settings: Default::default(),
            },
            norms: Norm::ALL.to_vec(),
            cases: vec![
                synthetic(cn, MassVariant::Standard, &std_cn, 50.0),
                synthetic(cn, MassVariant::Redistributed, &|_| 0.8, mod_indicator),
                synthetic(be, MassVariant::Standard, &|_| 0.5, 1.0),
                synthetic(be, MassVariant::Redistributed, &|_| 0.6, 1.0),
            ],
            not_run: Vec::new(),
            wall_seconds: 0.0,
        }
    }

    #[test]
    fn every_finding_holds_on_the_notes_picture_and_is_robust_to_a_small_bias() {
        let findings = note_findings(&note_like(1.0), &|_| 0.01);
        assert_eq!(findings.len(), 6);
        for f in &findings {
            assert!(f.holds && f.robust, "{f:?}");
        }
    }

    #[test]
    fn an_oscillating_redistributed_case_breaks_the_first_finding_only() {
        let findings = note_findings(&note_like(10.0), &|_| 0.0);
        assert!(!findings[0].holds, "{:?}", findings[0]);
        assert!(findings[1..].iter().all(|f| f.holds));
    }

    #[test]
    fn a_large_rate_bias_leaves_rate_findings_unproven_but_not_the_oscillation_one() {
        let findings = note_findings(&note_like(1.0), &|_| 1.0);
        assert!(findings.iter().all(|f| f.holds));
        assert!(findings[0].robust, "the indicator does not depend on rates");
        assert!(findings[1..].iter().all(|f| !f.robust));
    }

    #[test]
    fn a_missing_case_is_reported_as_not_tested() {
        let mut study = note_like(1.0);
        study.cases.truncate(2);
        let findings = note_findings(&study, &|_| 0.0);
        let last = findings.last().unwrap();
        assert!(!last.holds && last.evidence.contains("not tested"));
    }
}
