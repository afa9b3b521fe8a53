//! The note's statements (§3.1, §3.1.1) as verdicts computed from a study, so that a report
//! says whether they hold rather than repeating them.
//!
//! The criteria are fixed here, once, before looking at any particular study:
//! * a norm **converges** when its least-squares rate over all levels is above
//!   [`CONVERGENCE_RATE`] = 0: the error decreases as `h` does (the note's "converges to 0"
//!   against "unfortunately not the case", read from curves; how fast is the rate itself);
//! * a case **oscillates** when its indicator `TV(Σλ_h) / TV(Σλ_ref)` on the finest level is at
//!   least [`OSCILLATION_RATIO`] (the 1D tables' boundary between "No" and "Small");
//! * two cases **behave alike** in a norm when both converge or both do not, and their rates
//!   differ by at most [`ALIKE_RATE_GAP`].

use serde::{Deserialize, Serialize};

use crate::fem::MassVariant;
use crate::norms::Norm;
use crate::schemes::Scheme;
use crate::study::{Case, CaseStudy, Study};

/// The rate above which a norm counts as converging.
pub const CONVERGENCE_RATE: f64 = 0.0;

/// Smallest oscillation indicator that counts as oscillating.
pub const OSCILLATION_RATIO: f64 = 5.0;

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

fn converges(c: &CaseStudy, norm: Norm) -> bool {
    rate(c, norm) > CONVERGENCE_RATE
}

fn oscillates(c: &CaseStudy) -> bool {
    c.oscillation_indicator()
        .is_some_and(|r| r >= OSCILLATION_RATIO)
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

/// The note's findings for Crank–Nicolson and backward Euler with both masses; a finding
/// whose cases are not in the study is reported as not holding, with the reason.
pub fn note_findings(study: &Study) -> Vec<Finding> {
    let cn = Scheme::CRANK_NICOLSON;
    let be = Scheme::BACKWARD_EULER;
    let (std, modified) = (MassVariant::Standard, MassVariant::Redistributed);
    let missing = |claim: &str, source: &str| Finding {
        claim: claim.to_string(),
        source: source.to_string(),
        holds: false,
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
                evidence: format!("{}; {}", indicator_text("STD", s), indicator_text("MOD", m)),
            });
            out.push(Finding {
                claim: "Crank–Nicolson: with the redistributed mass the energy error converges"
                    .into(),
                source: "§3.1, Figures 2, 3e–f".into(),
                holds: energy.iter().all(|&n| converges(m, n)),
                evidence: rates_text("MOD", m, &energy),
            });
            out.push(Finding {
                claim: "Crank–Nicolson: with the standard mass the energy error does not converge"
                    .into(),
                source: "§3.1, Figures 2, 3e–f".into(),
                holds: energy.iter().all(|&n| !converges(s, n)),
                evidence: rates_text("STD", s, &energy),
            });
            let vl = [Norm::DisplacementL2V, Norm::MultiplierL2];
            out.push(Finding {
                claim: "Crank–Nicolson: u in L²(0,T;V) and the contact force in L²(0,T) converge \
                        with the redistributed mass and not with the standard one"
                    .into(),
                source: "§3.1, Figure 3c–d".into(),
                holds: vl.iter().all(|&n| converges(m, n) && !converges(s, n)),
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
                holds: h.iter().all(|&n| converges(m, n) && converges(s, n)),
                evidence: format!("{}; {}", rates_text("MOD", m, &h), rates_text("STD", s, &h)),
            });
        }
        _ => out.push(missing("Crank–Nicolson findings", "§3.1")),
    }
    match (case(study, be, std), case(study, be, modified)) {
        (Some(s), Some(m)) => {
            let alike: Vec<Norm> = Norm::ALL
                .into_iter()
                .filter(|&n| {
                    converges(s, n) == converges(m, n)
                        && (rate(s, n) - rate(m, n)).abs() <= ALIKE_RATE_GAP
                })
                .collect();
            out.push(Finding {
                claim: format!(
                    "Backward Euler: both masses behave alike (in every norm both converge or \
                     neither does, with rates within {ALIKE_RATE_GAP}) and neither oscillates"
                ),
                source: "§3.1.1, Figures 6–8".into(),
                holds: alike.len() == Norm::ALL.len() && !oscillates(s) && !oscillates(m),
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
