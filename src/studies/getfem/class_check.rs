//! Every GetFEM run checked against its class ([`Expectation`]) with thresholds fixed before
//! the results they judge (docs/src/getfem.md gives each with its reason): a run that misses
//! one is flagged in `getfem.md`, in `getfem.json` and by the command.
//!
//! - round-off reproducible ([`Expectation::RoundOff`], [`Expectation::UndampedStressRoundOff`]):
//!   the contact node's displacement, the energy and the final field within
//!   [`STATE_TOLERANCE`] at every step, the stress within [`STRESS_TOLERANCE`] of its largest
//!   magnitude (up to the first impact only for the undamped stress);
//! - round-off chaotic ([`Expectation::RoundOffChaotic`]): the same steps up to the first
//!   impact (it parts, if at all, after it) and, where GetFEM parts no earlier than its
//!   ensemble's first member (the ensemble is then GetFEM's distribution), no norm unlike any
//!   member ([`NormInEnsemble::within`]); where it parts earlier, how far the ensemble does not
//!   cover it is reported, not checked ([`super::Judgement::Undecided`]);
//! - demo artefact ([`Expectation::DemoMasslessNitsche`]): θ < 0 the same steps up to the first
//!   impact; θ > 0 the demo's energy above [`DEMO_BLOWN_UP_ENERGY`] and the harness's at most
//!   [`HARNESS_ENERGY_CEILING`].
//!
//! Every class also needs the harness's run to complete.

use serde::Serialize;

use super::{EnsembleAgreement, Expectation, NormInEnsemble, Reproduction, Timing};
use crate::harness::study::sensitivity::PARTING;

/// The largest difference of the contact node's displacement, of the energy and of the final
/// field a round-off reproducible run may show at any step: the harness's own parting threshold
/// ([`PARTING`]), below which two runs are the same run in every round-off class.
pub const STATE_TOLERANCE: f64 = PARTING;

/// The largest difference of the contact stress, relative to its largest magnitude, a round-off
/// reproducible run may show: fixed on the NX = 20, 40 runs (three times the 3e-8 by which
/// GetFEM's own two linear solvers differ in it: the stress is a residual divided by `βΔt²`,
/// which magnifies the state's round-off) before any finer run was compared.
pub const STRESS_TOLERANCE: f64 = 1e-7;

/// The demo's largest energy above which its massless Nitsche θ > 0 run has blown up: 8e6 times
/// the exact energy ⅛.
pub const DEMO_BLOWN_UP_ENERGY: f64 = 1e6;

/// The harness's largest energy on that run: the exact energy ⅛ and 0.8 % (a consistent scheme
/// with a conserving contact treatment does not gain energy).
pub const HARNESS_ENERGY_CEILING: f64 = 0.126;

/// How a measured quantity must compare with its bound.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Rule {
    /// `measured ≤ bound`.
    AtMost,
    /// `measured > bound`.
    Above,
    /// `measured ≥ bound`.
    AtLeast,
}

/// One check of a run against its class.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Check {
    /// What is measured, as the report names it.
    pub what: String,
    /// The measured value (a step as a number; `∞`, JSON `null`, for a run that never parts).
    pub measured: f64,
    /// How it must compare with `bound`.
    pub rule: Rule,
    /// The threshold.
    pub bound: f64,
    /// Whether it does.
    pub holds: bool,
}

impl Check {
    fn new(what: impl Into<String>, measured: f64, rule: Rule, bound: f64) -> Self {
        let holds = match rule {
            Rule::AtMost => measured <= bound,
            Rule::Above => measured > bound,
            Rule::AtLeast => measured >= bound,
        };
        Self {
            what: what.into(),
            measured,
            rule,
            bound,
            holds,
        }
    }

    /// `what measured ≤ bound` with the relation that holds (`>` for a missed `≤`).
    pub fn text(&self) -> String {
        let relation = match (self.rule, self.holds) {
            (Rule::AtMost, true) | (Rule::Above, false) => "≤",
            (Rule::AtMost, false) | (Rule::Above, true) => ">",
            (Rule::AtLeast, true) => "≥",
            (Rule::AtLeast, false) => "<",
        };
        format!(
            "{} {} {relation} {}",
            self.what,
            number(self.measured),
            number(self.bound)
        )
    }
}

/// A value as the checks print it: a step as an integer, a difference in `e` notation.
fn number(x: f64) -> String {
    if x.is_infinite() {
        "never".to_string()
    } else if x.fract() == 0.0 && x.abs() >= 1.0 && x.abs() < 1e6 {
        format!("{x:.0}")
    } else {
        format!("{x:.1e}")
    }
}

/// A run checked against its class.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ClassCheck {
    /// The class ([`Expectation::name`]).
    pub class: &'static str,
    /// Every check its class needs.
    pub checks: Vec<Check>,
}

impl ClassCheck {
    /// `r` checked against its expectation; a chaotic run's norms against `ensemble` when it
    /// was run.
    pub fn of(r: &Reproduction, ensemble: Option<&EnsembleAgreement>) -> Self {
        let completed = if r.status.is_completed() { 1.0 } else { 0.0 };
        let mut checks = vec![Check::new(
            "harness run completed (1: yes)",
            completed,
            Rule::AtLeast,
            1.0,
        )];
        let state = |what: &str, value: f64| Check::new(what, value, Rule::AtMost, STATE_TOLERANCE);
        let parting = r.parting.map_or(f64::INFINITY, |n| n as f64);
        let impact = r.first_impact as f64;
        match r.expectation {
            Expectation::RoundOff | Expectation::UndampedStressRoundOff => {
                checks.push(state("Δu", r.displacement.max));
                checks.push(state("ΔE", r.energy.max));
                checks.push(state("ΔU(T)", r.final_field.max));
                checks.push(if r.expectation == Expectation::RoundOff {
                    Check::new("Δs/max|s|", r.stress.max, Rule::AtMost, STRESS_TOLERANCE)
                } else {
                    let before = r.stress_before_impact.max;
                    Check::new(
                        "Δs/max|s| to the impact",
                        before,
                        Rule::AtMost,
                        STRESS_TOLERANCE,
                    )
                });
            }
            Expectation::RoundOffChaotic => {
                checks.push(Check::new("parts at step", parting, Rule::Above, impact));
                let in_time = ensemble.filter(|e| e.in_time() == Timing::InTime);
                for n in in_time.map_or(&[][..], |e| &e.norms) {
                    checks.push(Check::new(
                        format!("{} |GetFEM − median|", n.name),
                        (n.getfem - n.spread.median).abs(),
                        Rule::AtMost,
                        n.spread.range(),
                    ));
                }
            }
            Expectation::DemoMasslessNitsche if r.config.theta_n < 0.0 => {
                checks.push(Check::new("parts at step", parting, Rule::AtLeast, impact));
            }
            Expectation::DemoMasslessNitsche => {
                checks.push(Check::new(
                    "demo's largest energy",
                    r.demo_peak_energy,
                    Rule::Above,
                    DEMO_BLOWN_UP_ENERGY,
                ));
                checks.push(Check::new(
                    "harness's largest energy",
                    r.harness_peak_energy,
                    Rule::AtMost,
                    HARNESS_ENERGY_CEILING,
                ));
            }
        }
        Self {
            class: r.expectation.name(),
            checks,
        }
    }

    /// The checks it misses.
    pub fn misses(&self) -> impl Iterator<Item = &Check> {
        self.checks.iter().filter(|c| !c.holds)
    }

    /// Whether it holds every check.
    pub fn within(&self) -> bool {
        self.misses().next().is_none()
    }

    /// `within`, or `**outside**:` and every miss.
    pub fn text(&self) -> String {
        if self.within() {
            "within".to_string()
        } else {
            let misses: Vec<String> = self.misses().map(Check::text).collect();
            format!("**outside**: {}", misses.join("; "))
        }
    }
}

/// How far GetFEM's value of `n` lies outside the whole ensemble's `[min, max]` (0 inside),
/// and that distance in widths of the range.
pub fn beyond(n: &NormInEnsemble) -> (f64, f64) {
    let s = &n.spread;
    let d = (s.min - n.getfem).max(n.getfem - s.max).max(0.0);
    (d, d / s.range())
}
