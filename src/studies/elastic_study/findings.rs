//! The note's statements (§3.1, §3.1.1) as verdicts computed from a study, so that a report
//! says whether they hold rather than repeating them.
//!
//! The criteria are the words of [`crate::harness::vocabulary`], fixed before looking at any
//! particular study, and every one that rests on a rate is decided by its 95 % interval widened
//! by the reference's rate-bias bound of the norm ([`crate::harness::study::decision`]: holds,
//! fails or undecided):
//! * a norm **converges** when its rate's widened interval lies entirely above
//!   [`CONVERGES_ABOVE`](vocabulary::CONVERGES_ABOVE) = 0 (the error decreases as `h` does: the note's "converges to 0"
//!   against "unfortunately not the case", read from curves), and **does not converge** when it
//!   lies entirely at or below it;
//! * two cases **behave alike** in a norm when both converge or both do not, and the interval of
//!   the difference of their rates (half-widths and bias bounds added) lies within
//!   ±[`ALIKE_RATE_GAP`];
//! * a case **oscillates** when its indicator `TV(Σλ_h) / TV(Σλ_ref)` on the finest level is at
//!   least [`verdicts::OSCILLATES_FROM`] (the 1D tables' boundary between "No" and "Small"). The
//!   indicator has no interval: this comparison is decided as measured, holds or fails.
//!
//! A finding combines its decisions: it holds when all are made and satisfied, fails when one
//! is made and contradicted, and is undecided otherwise, with what would decide it.

use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};

use crate::harness::problem::{MassVariant, Scheme};
use crate::harness::run::norms::Norm;
use crate::harness::run::physics::Physics;
use crate::harness::study::decision::{all_of, any_of, Decision, Estimate, Verdict};
use crate::harness::study::{verdicts, Case, CaseStudy, Study};
use crate::harness::vocabulary::{self, ALIKE_RATE_GAP};

/// One statement of the note and whether the study supports it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Finding {
    /// The statement.
    pub claim: String,
    /// Where the note makes it.
    pub source: String,
    /// Whether it holds, fails or is undecided in this study.
    pub verdict: Verdict,
    /// What decided it, or, undecided, the intervals it has and what would decide it.
    pub reason: String,
    /// The numbers it was decided on.
    pub evidence: String,
}

impl Finding {
    fn new(claim: impl Into<String>, source: &str, decision: Decision, evidence: String) -> Self {
        Self {
            claim: claim.into(),
            source: source.to_string(),
            verdict: decision.verdict,
            reason: decision.reason,
            evidence,
        }
    }
}

fn case(cases: &[CaseStudy], scheme: Scheme, mass: MassVariant) -> Option<&CaseStudy> {
    let wanted = Case { scheme, mass };
    cases.iter().find(|c| c.case == wanted)
}

/// A case of a finding with its label (`STD`, `MOD`).
#[derive(Clone, Copy)]
struct Labelled<'c> {
    label: &'static str,
    case: &'c CaseStudy,
}

/// The rate decisions, every rate's interval widened by the rate-bias bound of its case and
/// norm (`None`: unbounded, that rate is not decided).
struct Judge<'b> {
    rate_bias: &'b RateBias<'b>,
}

/// The rate-bias bound of a case's rate in a norm: how far the reference's own error could move
/// it (`None`: no bound can be formed). Zero against an exact solution.
pub type RateBias<'b> = dyn Fn(&CaseStudy, Norm) -> Option<f64> + 'b;

/// The rate of `norm` in `case` as the findings decide it, named `what`: the unperturbed run's
/// fit with its 95 % interval and the rate-bias bound `bias` (`None`: unbounded).
fn rate_estimate(what: String, case: &CaseStudy, norm: Norm, bias: Option<f64>) -> Estimate {
    Estimate::rate(what, case.norm(norm).and_then(|r| r.fit), bias)
}

/// Whether the rate of `norm` in `case` converges, decided as the findings decide it (its 95 %
/// interval widened by `bias`, [`vocabulary::converges`]).
pub fn convergence(case: &CaseStudy, norm: Norm, bias: Option<f64>) -> Decision {
    vocabulary::converges(&rate_estimate(
        format!("{} rate", norm.key()),
        case,
        norm,
        bias,
    ))
}

impl Judge<'_> {
    fn estimate(&self, c: Labelled<'_>, norm: Norm) -> Estimate {
        rate_estimate(
            format!("{} {} rate", c.label, norm.key()),
            c.case,
            norm,
            (self.rate_bias)(c.case, norm),
        )
    }

    fn converges(&self, c: Labelled<'_>, norm: Norm) -> Decision {
        vocabulary::converges(&self.estimate(c, norm))
    }

    fn does_not_converge(&self, c: Labelled<'_>, norm: Norm) -> Decision {
        self.converges(c, norm).negated()
    }

    /// Both converge or neither does, and the difference of the rates lies within
    /// ±[`ALIKE_RATE_GAP`].
    fn alike(&self, a: Labelled<'_>, b: Labelled<'_>, norm: Norm) -> Decision {
        let same = any_of(vec![
            all_of(vec![self.converges(a, norm), self.converges(b, norm)]),
            all_of(vec![
                self.does_not_converge(a, norm),
                self.does_not_converge(b, norm),
            ]),
        ]);
        let gap = Estimate::difference(
            format!("{} − {} {} rate", a.label, b.label, norm.key()),
            &self.estimate(a, norm),
            &self.estimate(b, norm),
        );
        all_of(vec![same, vocabulary::within_alike_gap(&gap)])
    }
}

fn oscillates(c: &CaseStudy) -> bool {
    c.oscillation_indicator().is_some_and(verdicts::oscillates)
}

/// Whether `c` oscillates as `expected`, decided as measured (an indicator has no interval);
/// undecided without an indicator (a series without the contact force: no multiplier, or a
/// code's own mesh).
fn oscillation(c: Labelled<'_>, expected: bool) -> Decision {
    let Some(indicator) = c.case.oscillation_indicator().filter(|i| i.is_finite()) else {
        return Decision {
            verdict: Verdict::Undecided,
            reason: format!(
                "{}: no oscillation indicator (the contact force is not measured)",
                c.label
            ),
        };
    };
    let (word, relation) = if oscillates(c.case) {
        ("oscillates", "≥")
    } else {
        ("does not oscillate", "<")
    };
    Decision {
        verdict: Verdict::of(oscillates(c.case) == expected),
        reason: format!(
            "{} {word}: indicator {indicator:.1} {relation} {} (no interval: as measured)",
            c.label,
            verdicts::OSCILLATES_FROM
        ),
    }
}

/// `label: norm rate ± half-width, …` (the rate alone without an interval, `not computed`
/// without a fit).
fn rates_text(c: Labelled<'_>, norms: &[Norm]) -> String {
    let list: Vec<String> = norms
        .iter()
        .map(|&n| {
            let Some(fit) = c.case.norm(n).and_then(|r| r.fit) else {
                return format!("{} not computed", n.key());
            };
            match fit.ci_low.zip(fit.ci_high) {
                Some((low, high)) => {
                    format!("{} {:.2} ± {:.2}", n.key(), fit.rate, 0.5 * (high - low))
                }
                None => format!("{} {:.2}", n.key(), fit.rate),
            }
        })
        .collect();
    format!("{}: {}", c.label, list.join(", "))
}

/// `label indicator I`, or `label indicator not measured` without one.
fn indicator_text(c: Labelled<'_>) -> String {
    match c.case.oscillation_indicator().filter(|i| i.is_finite()) {
        Some(i) => format!("{} indicator {i:.1}", c.label),
        None => format!("{} indicator not measured", c.label),
    }
}

/// The note's findings for Crank–Nicolson and backward Euler with both masses, every rate
/// decided by its interval widened by `rate_bias` of its case and norm (`None`: unbounded); a
/// finding whose cases are not in the study is undecided, with the reason.
///
/// The evidence of a finding whose cases have a run the time loop flagged (a penetration beyond
/// 1 % of the face's displacement scale, an energy gain beyond 5 %, a pulling force:
/// [`Physics::flags`]) ends with those runs and their figures, so that no finding rests on such
/// a run unmarked.
pub fn note_findings(study: &Study, rate_bias: &RateBias<'_>) -> Vec<Finding> {
    marked_findings(&study.cases, rate_bias, &study.physics)
}

/// [`note_findings`] on the cases `cases` (a study's, or the series of other codes' runs that
/// declare their scheme and mass), whose runs' physics is not known here.
pub fn findings_of_cases(cases: &[CaseStudy], rate_bias: &RateBias<'_>) -> Vec<Finding> {
    marked_findings(cases, rate_bias, &BTreeMap::new())
}

/// `; physics: STD NX = 10: gains energy: …` for every level of the cases `pair` whose run
/// `physics` (by case id, one per level) flags; empty when none does.
fn physics_marks(pair: [Labelled<'_>; 2], physics: &BTreeMap<String, Vec<Physics>>) -> String {
    let marks: Vec<String> = pair
        .iter()
        .flat_map(|c| {
            let levels = physics.get(&c.case.case.id());
            c.case
                .levels
                .iter()
                .zip(levels.into_iter().flatten())
                .filter_map(move |(level, p)| {
                    p.flags()
                        .map(|f| format!("{} NX = {}: {f}", c.label, level.nx))
                })
        })
        .collect();
    if marks.is_empty() {
        String::new()
    } else {
        format!("; physics: {}", marks.join("; "))
    }
}

/// The findings of `cases`, their evidence marked by `physics` ([`note_findings`]).
fn marked_findings(
    cases: &[CaseStudy],
    rate_bias: &RateBias<'_>,
    physics: &BTreeMap<String, Vec<Physics>>,
) -> Vec<Finding> {
    let judge = Judge { rate_bias };
    let cn = Scheme::CRANK_NICOLSON;
    let be = Scheme::BACKWARD_EULER;
    let (std, modified) = (MassVariant::Standard, MassVariant::Redistributed);
    let labelled = |scheme| {
        let s = case(cases, scheme, std)?;
        let m = case(cases, scheme, modified)?;
        Some((
            Labelled {
                label: "STD",
                case: s,
            },
            Labelled {
                label: "MOD",
                case: m,
            },
        ))
    };
    let missing = |claim: &str, source: &str| {
        Finding::new(
            claim,
            source,
            Decision::undecided("not tested: a case is missing from the study"),
            String::new(),
        )
    };
    let energy = [Norm::EnergyLinf, Norm::EnergyL2];
    let mut out = Vec::new();
    match labelled(cn) {
        Some((s, m)) => {
            let marks = physics_marks([s, m], physics);
            let first = out.len();
            out.push(Finding::new(
                "Crank–Nicolson: the redistributed mass removes the contact oscillations that \
                 the standard mass shows",
                "§3.1, Figure 1",
                all_of(vec![oscillation(s, true), oscillation(m, false)]),
                format!("{}; {}", indicator_text(s), indicator_text(m)),
            ));
            out.push(Finding::new(
                "Crank–Nicolson: with the redistributed mass the energy error converges",
                "§3.1, Figures 2, 3e–f",
                all_of(energy.iter().map(|&n| judge.converges(m, n)).collect()),
                rates_text(m, &energy),
            ));
            out.push(Finding::new(
                "Crank–Nicolson: with the standard mass the energy error does not converge",
                "§3.1, Figures 2, 3e–f",
                all_of(
                    energy
                        .iter()
                        .map(|&n| judge.does_not_converge(s, n))
                        .collect(),
                ),
                rates_text(s, &energy),
            ));
            let vl = [Norm::DisplacementL2V, Norm::MultiplierL2];
            out.push(Finding::new(
                "Crank–Nicolson: u in L²(0,T;V) and the contact force in L²(0,T) converge with \
                 the redistributed mass and not with the standard one",
                "§3.1, Figure 3c–d",
                all_of(
                    vl.iter()
                        .flat_map(|&n| [judge.converges(m, n), judge.does_not_converge(s, n)])
                        .collect(),
                ),
                format!("{}; {}", rates_text(m, &vl), rates_text(s, &vl)),
            ));
            let h = [Norm::DisplacementLinfH, Norm::DisplacementL2H];
            out.push(Finding::new(
                "Crank–Nicolson: u in L∞(0,T;H) and L²(0,T;H) converges with both masses",
                "§3.1, Figure 3a–b",
                all_of(
                    h.iter()
                        .flat_map(|&n| [judge.converges(m, n), judge.converges(s, n)])
                        .collect(),
                ),
                format!("{}; {}", rates_text(m, &h), rates_text(s, &h)),
            ));
            for f in &mut out[first..] {
                f.evidence.push_str(&marks);
            }
        }
        None => out.push(missing("Crank–Nicolson findings", "§3.1")),
    }
    match labelled(be) {
        Some((s, m)) => {
            let mut decisions: Vec<Decision> =
                Norm::ALL.iter().map(|&n| judge.alike(s, m, n)).collect();
            decisions.push(oscillation(s, false));
            decisions.push(oscillation(m, false));
            out.push(Finding::new(
                format!(
                    "Backward Euler: both masses behave alike (in every norm both converge or \
                     neither does, with rates within {ALIKE_RATE_GAP}) and neither oscillates"
                ),
                "§3.1.1, Figures 6–8",
                all_of(decisions),
                format!(
                    "{}; {}; {}; {}{}",
                    rates_text(s, &Norm::ALL),
                    rates_text(m, &Norm::ALL),
                    indicator_text(s),
                    indicator_text(m),
                    physics_marks([s, m], physics)
                ),
            ));
        }
        None => out.push(missing("Backward Euler findings", "§3.1.1")),
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
            physics: Default::default(),
        }
    }

    fn verdicts(findings: &[Finding]) -> Vec<Verdict> {
        findings.iter().map(|f| f.verdict).collect()
    }

    #[test]
    fn every_finding_holds_on_the_notes_picture_with_a_small_bias() {
        let findings = note_findings(&note_like(1.0), &|_, _| Some(0.01));
        assert_eq!(findings.len(), 6);
        for f in &findings {
            assert_eq!(f.verdict, Verdict::Holds, "{f:?}");
        }
    }

    /// A run of CN-STD whose energy rose 74 % above its start (the box's CN-STD at level 10
    /// does) marks the evidence of every Crank–Nicolson finding with its level and figures; the
    /// backward-Euler finding, whose runs are not flagged, is not marked; the verdicts stay
    /// the rates'.
    #[test]
    fn a_flagged_run_marks_the_evidence_of_the_findings_that_rest_on_it() {
        let calm = Physics {
            penetration: 0.0,
            penetration_time: 0.0,
            face_displacement_scale: 0.2,
            relative_penetration: Some(0.0),
            energy_start: 1.0,
            energy_max: 1.0,
            energy_max_time: 0.0,
            energy_ratio: Some(1.0),
            external_work: None,
            wrong_sign_force: 0.0,
            max_force: 1.0,
        };
        let gaining = Physics {
            energy_max: 1.74,
            energy_max_time: 1.25,
            energy_ratio: Some(1.74),
            ..calm
        };
        let mut study = note_like(1.0);
        for c in &study.cases {
            let mut levels = vec![calm; c.levels.len()];
            if c.case.scheme == Scheme::CRANK_NICOLSON && c.case.mass == MassVariant::Standard {
                levels[0] = gaining;
            }
            study.physics.insert(c.case.id(), levels);
        }
        let findings = note_findings(&study, &|_, _| Some(0.01));
        for f in &findings[..5] {
            assert!(
                f.evidence
                    .ends_with("; physics: STD NX = 10: gains energy: E_max/E_0 = 1.7400 (E_0 = 1.0000e0, E_max = 1.7400e0) at t = 1.2500"),
                "{}",
                f.evidence
            );
            assert_eq!(f.verdict, Verdict::Holds, "{f:?}");
        }
        assert!(
            !findings[5].evidence.contains("physics"),
            "{}",
            findings[5].evidence
        );
    }

    #[test]
    fn an_oscillating_redistributed_case_fails_the_first_finding_only() {
        let findings = note_findings(&note_like(10.0), &|_, _| Some(0.0));
        assert_eq!(findings[0].verdict, Verdict::Fails, "{:?}", findings[0]);
        assert!(findings[0].reason.contains("no interval"));
        assert!(findings[1..].iter().all(|f| f.verdict == Verdict::Holds));
    }

    /// A series without the contact force (no multiplier, or a code's own mesh) has no
    /// oscillation indicator: the first finding is undecided, saying so, never failed as if it
    /// did not oscillate.
    #[test]
    fn a_case_without_an_indicator_leaves_the_oscillation_finding_undecided() {
        let findings = note_findings(&note_like(f64::NAN), &|_, _| Some(0.0));
        assert_eq!(findings[0].verdict, Verdict::Undecided, "{:?}", findings[0]);
        assert!(
            findings[0].reason.contains("no oscillation indicator"),
            "{}",
            findings[0].reason
        );
        assert!(
            findings[0].evidence.contains("MOD indicator not measured"),
            "{}",
            findings[0].evidence
        );
    }

    #[test]
    fn a_finding_flips_from_holds_to_undecided_when_its_bias_grows() {
        let small = note_findings(&note_like(1.0), &|_, _| Some(0.05));
        assert!(verdicts(&small).iter().all(|&v| v == Verdict::Holds));
        let large = note_findings(&note_like(1.0), &|_, _| Some(1.0));
        assert_eq!(
            large[0].verdict,
            Verdict::Holds,
            "the indicator has no rate"
        );
        for f in &large[1..] {
            assert_eq!(f.verdict, Verdict::Undecided, "{f:?}");
            assert!(f.reason.contains("finer reference"), "{}", f.reason);
        }
        let unbounded = note_findings(&note_like(1.0), &|_, n| {
            (n != Norm::EnergyLinf).then_some(0.0)
        });
        assert_eq!(unbounded[1].verdict, Verdict::Undecided);
        assert!(
            unbounded[1].reason.contains("unbounded"),
            "{}",
            unbounded[1].reason
        );
    }

    #[test]
    fn each_rate_is_widened_by_its_own_case_bound() {
        // A rival beside the note's cases whose rates have no bound (its errors as small as the
        // reference's) leaves the note's findings as they are; the same unbounded bound on a
        // note case leaves its findings undecided.
        let mut study = note_like(1.0);
        let rival = synthetic(
            Scheme::LaursenChawla {},
            MassVariant::Standard,
            &|_| 1.5,
            1.0,
        );
        study.cases.push(rival);
        let own =
            |c: &CaseStudy, _: Norm| (c.case.scheme != Scheme::LaursenChawla {}).then_some(0.01);
        assert!(verdicts(&note_findings(&study, &own))
            .iter()
            .all(|&v| v == Verdict::Holds));
        let cn_mod_unbounded = |c: &CaseStudy, _: Norm| {
            (c.case
                != Case {
                    scheme: Scheme::CRANK_NICOLSON,
                    mass: MassVariant::Redistributed,
                })
            .then_some(0.01)
        };
        let findings = note_findings(&study, &cn_mod_unbounded);
        assert_eq!(findings[1].verdict, Verdict::Undecided, "{:?}", findings[1]);
    }

    #[test]
    fn a_missing_case_leaves_its_findings_undecided() {
        let mut study = note_like(1.0);
        study.cases.truncate(2);
        let findings = note_findings(&study, &|_, _| Some(0.0));
        let last = findings.last().unwrap();
        assert_eq!(last.verdict, Verdict::Undecided);
        assert!(last.reason.contains("not tested"));
    }

    #[test]
    fn the_verdict_is_written_as_a_word() {
        let f = &note_findings(&note_like(1.0), &|_, _| Some(0.0))[0];
        let json = serde_json::to_value(f).unwrap();
        assert_eq!(json["verdict"], "holds");
        assert!(json.get("holds").is_none() && json.get("robust").is_none());
    }
}
