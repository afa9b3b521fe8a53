//! The regression gate: committed rates and per-level errors (`golden/*.json`) and the
//! tolerance comparison that reports every entry that drifted.
//!
//! A rate may move by at most an absolute tolerance (default 0.02, settable per norm), an error
//! by a relative one (default 1 %). NaN or infinity on either side is a drift, never a pass.

use std::collections::BTreeMap;
use std::fmt::Write as _;

use serde::{Deserialize, Serialize};

use crate::study::Study;

/// Tolerances of the gate, stored with the golden values.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Tolerances {
    /// Largest allowed `|rate − golden|` (default 0.02).
    pub rate_abs: f64,
    /// Per-norm overrides of `rate_abs`, keyed by norm key (`u_Linf_H`, …).
    #[serde(default)]
    pub rate_abs_per_norm: BTreeMap<String, f64>,
    /// Largest allowed `|e − golden| / |golden|` per level (default 0.01).
    pub error_rel: f64,
}

impl Default for Tolerances {
    fn default() -> Self {
        Self {
            rate_abs: 0.02,
            rate_abs_per_norm: BTreeMap::new(),
            error_rel: 0.01,
        }
    }
}

impl Tolerances {
    /// The rate tolerance of the norm with key `norm`.
    pub fn rate_tolerance(&self, norm: &str) -> f64 {
        self.rate_abs_per_norm
            .get(norm)
            .copied()
            .unwrap_or(self.rate_abs)
    }
}

/// The committed values of one norm of one case.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GoldenNorm {
    /// Least-squares rate over all levels.
    pub rate: f64,
    /// Least-squares rate over the last three levels.
    pub rate_last_three: f64,
    /// Error per level.
    pub errors: Vec<f64>,
}

/// The committed values of one case, keyed by norm.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GoldenCase {
    /// `scheme/mass`.
    pub case: String,
    /// Norm key → values.
    pub norms: BTreeMap<String, GoldenNorm>,
}

/// A golden file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Golden {
    /// What produced it (`make golden`).
    pub generated_by: String,
    /// The study's levels.
    pub levels: Vec<usize>,
    /// The study's `Δx/Δt`.
    pub ratio: f64,
    /// The study's horizon.
    pub horizon: f64,
    /// The gate's tolerances.
    pub tolerances: Tolerances,
    /// One entry per case.
    pub cases: Vec<GoldenCase>,
}

fn nan_to_inf(x: Option<f64>) -> f64 {
    x.unwrap_or(f64::NAN)
}

impl Golden {
    /// The golden values of a study, with the given tolerances.
    pub fn from_study(study: &Study, tolerances: Tolerances) -> Self {
        Self {
            generated_by: "make golden".to_string(),
            levels: study.config.levels.clone(),
            ratio: study.config.ratio,
            horizon: study.config.horizon,
            tolerances,
            cases: study
                .cases
                .iter()
                .map(|c| GoldenCase {
                    case: c.case.id(),
                    norms: c
                        .rates
                        .iter()
                        .map(|r| {
                            (
                                r.norm.key().to_string(),
                                GoldenNorm {
                                    rate: nan_to_inf(r.fit.map(|f| f.rate)),
                                    rate_last_three: nan_to_inf(r.fit_last_three.map(|f| f.rate)),
                                    errors: r.errors.clone(),
                                },
                            )
                        })
                        .collect(),
                })
                .collect(),
        }
    }
}

/// One entry outside its tolerance.
#[derive(Debug, Clone, PartialEq)]
pub struct Drift {
    /// `scheme/mass`.
    pub case: String,
    /// Norm key.
    pub norm: String,
    /// `rate`, `rate_last_three`, `error[NX=…]`, or `missing`.
    pub quantity: String,
    /// The golden value.
    pub golden: f64,
    /// The value now.
    pub now: f64,
    /// `now − golden` (absolute for rates, relative for errors).
    pub difference: f64,
    /// The tolerance it exceeded.
    pub tolerance: f64,
}

/// Compares a study with the golden values; returns every drifted entry (empty: the gate passes).
/// A study with other levels, ratio or horizon than the golden file is one drift per case.
pub fn compare(golden: &Golden, study: &Study) -> Vec<Drift> {
    let mut drifts = Vec::new();
    let tol = &golden.tolerances;
    let same_setup = golden.levels == study.config.levels
        && golden.ratio == study.config.ratio
        && golden.horizon == study.config.horizon;
    for c in &study.cases {
        let id = c.case.id();
        let missing = |norm: &str| Drift {
            case: id.clone(),
            norm: norm.to_string(),
            quantity: "missing".to_string(),
            golden: f64::NAN,
            now: f64::NAN,
            difference: f64::NAN,
            tolerance: 0.0,
        };
        let Some(g) = golden.cases.iter().find(|g| g.case == id) else {
            drifts.push(missing("(case not in golden file)"));
            continue;
        };
        if !same_setup {
            drifts.push(missing(
                "(levels, ratio or horizon differ from the golden file)",
            ));
            continue;
        }
        for r in &c.rates {
            let key = r.norm.key();
            let Some(gn) = g.norms.get(key) else {
                drifts.push(missing(key));
                continue;
            };
            let rate_tol = tol.rate_tolerance(key);
            for (quantity, golden_value, now) in [
                ("rate", gn.rate, nan_to_inf(r.fit.map(|f| f.rate))),
                (
                    "rate_last_three",
                    gn.rate_last_three,
                    nan_to_inf(r.fit_last_three.map(|f| f.rate)),
                ),
            ] {
                let diff = now - golden_value;
                if !diff.is_finite() || diff.abs() > rate_tol {
                    drifts.push(Drift {
                        case: id.clone(),
                        norm: key.to_string(),
                        quantity: quantity.to_string(),
                        golden: golden_value,
                        now,
                        difference: diff,
                        tolerance: rate_tol,
                    });
                }
            }
            for (k, (&ge, &e)) in gn.errors.iter().zip(&r.errors).enumerate() {
                let rel = (e - ge) / ge.abs();
                let both_zero = e == 0.0 && ge == 0.0;
                if !both_zero && (!rel.is_finite() || rel.abs() > tol.error_rel) {
                    drifts.push(Drift {
                        case: id.clone(),
                        norm: key.to_string(),
                        quantity: format!("error[NX={}]", study.config.levels[k]),
                        golden: ge,
                        now: e,
                        difference: rel,
                        tolerance: tol.error_rel,
                    });
                }
            }
        }
    }
    drifts
}

/// One row per drifted entry: case, norm, quantity, golden, now, difference, tolerance.
pub fn render_drifts(drifts: &[Drift]) -> String {
    let mut out = String::new();
    let _ = writeln!(
        out,
        "{} entries drifted from the golden values:\n\n| case | norm | quantity | golden | now | difference | tolerance |\n|---|---|---|---|---|---|---|",
        drifts.len()
    );
    for d in drifts {
        let _ = writeln!(
            out,
            "| {} | {} | {} | {:.6e} | {:.6e} | {:+.3e} | {:.3e} |",
            d.case, d.norm, d.quantity, d.golden, d.now, d.difference, d.tolerance
        );
    }
    out
}
