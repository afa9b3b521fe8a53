//! The regression gate: committed rates and per-level errors (`golden/*.json`) and the
//! tolerance comparison that reports every entry that drifted.
//!
//! A rate may move by at most an absolute tolerance (default 0.02, settable per norm), an error
//! by a relative one (default 1 %). NaN or infinity on either side is a drift, never a pass.
//!
//! With a sensitivity study (`crate::harness::study::sensitivity`) each case is held at what its
//! reproducibility allows ([`Golden::with_sensitivity`]): a reproducible or event-sensitive case's
//! norms carry their own tolerances, [`SPREAD_SAFETY`] times the measured ensemble spread (at least
//! [`ERROR_REL_FLOOR`] and [`RATE_ABS_FLOOR`]); a chaotic case carries its ensemble envelope and
//! is gated by [`compare_ensemble`] on ensemble statistics, never on the bits of one run.

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::Path;

use serde::{Deserialize, Serialize};

use crate::harness::files::artifacts::read_json;
use crate::harness::files::error::Error;
use crate::harness::files::input::GOLDEN_FILE;
use crate::harness::study::sensitivity::{Sensitivity, SensitivityClass, Spread};
use crate::harness::study::{Case, NormRates, Study};

/// A case's tolerance is this many times its measured ensemble spread.
pub const SPREAD_SAFETY: f64 = 10.0;

/// The smallest relative error tolerance derived from a spread.
pub const ERROR_REL_FLOOR: f64 = 1e-9;

/// The smallest rate tolerance derived from a spread.
pub const RATE_ABS_FLOOR: f64 = 1e-4;

/// A chaotic case's statistic may leave its golden `[min, max]` by this fraction of the range.
pub const ENVELOPE_MARGIN: f64 = 0.25;

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
    /// This norm's relative error tolerance, derived from the measured spread (overrides
    /// `tolerances.error_rel`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub error_rel: Option<f64>,
    /// This norm's rate tolerance, derived from the measured spread (overrides the file's).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rate_abs: Option<f64>,
    /// A chaotic case's ensemble envelope: what [`compare_ensemble`] holds.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ensemble: Option<EnsembleEnvelope>,
}

/// The ensemble statistics of one norm of a chaotic case.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EnsembleEnvelope {
    /// The spread of the member-by-member rate.
    pub rate: Spread,
    /// The spread of the error at each level.
    pub errors: Vec<Spread>,
}

/// The committed values of one case, keyed by norm.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GoldenCase {
    /// `scheme/mass`.
    pub case: String,
    /// The case's round-off class, when a sensitivity study was attached.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub class: Option<SensitivityClass>,
    /// Norm key → values.
    pub norms: BTreeMap<String, GoldenNorm>,
}

impl GoldenCase {
    /// The golden values of the series `case` (a study's `scheme/mass`, another code's label):
    /// each norm's rates and errors, without class or tolerances of its own.
    pub fn from_rates(case: String, rates: &[NormRates]) -> Self {
        Self {
            case,
            class: None,
            norms: rates
                .iter()
                .map(|r| {
                    (
                        r.norm.key().to_string(),
                        GoldenNorm {
                            rate: rate_or_nan(r.fit.map(|f| f.rate)),
                            rate_last_three: rate_or_nan(r.fit_last_three.map(|f| f.rate)),
                            errors: r.errors.clone(),
                            error_rel: None,
                            rate_abs: None,
                            ensemble: None,
                        },
                    )
                })
                .collect(),
        }
    }

    /// Whether the case is round-off chaotic (gated by [`compare_ensemble`] only).
    pub fn is_chaotic(&self) -> bool {
        self.class == Some(SensitivityClass::Chaotic)
    }
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

/// Reads a golden file, every tolerance and value in its range ([`check_values`]).
pub fn read_golden(path: &Path) -> Result<Golden, Error> {
    let golden: Golden = read_json(path, GOLDEN_FILE)?;
    let cases = golden.cases.iter().map(|c| (c.case.as_str(), &c.norms));
    check_values(path, &golden.tolerances, cases)?;
    Ok(golden)
}

/// Refuses a golden file `path` whose tolerances are not finite numbers ≥ 0, or one of whose
/// series (`(name, norms)`) has a rate that is not finite, or an error or tolerance that is not
/// a finite number ≥ 0: such a file would gate nothing, or everything, and is not one the
/// harness wrote.
pub fn check_values<'a>(
    path: &Path,
    tolerances: &Tolerances,
    series: impl Iterator<Item = (&'a str, &'a BTreeMap<String, GoldenNorm>)>,
) -> Result<(), Error> {
    const AT_LEAST_ZERO: &str = "a finite number >= 0";
    let out = |field: String, value: f64, allowed| {
        Err(Error::OutOfRange {
            path: path.to_path_buf(),
            field,
            value,
            allowed,
        })
    };
    let non_negative = |x: f64| x.is_finite() && x >= 0.0;
    if !non_negative(tolerances.rate_abs) {
        return out(
            "tolerances.rate_abs".into(),
            tolerances.rate_abs,
            AT_LEAST_ZERO,
        );
    }
    if !non_negative(tolerances.error_rel) {
        return out(
            "tolerances.error_rel".into(),
            tolerances.error_rel,
            AT_LEAST_ZERO,
        );
    }
    for (norm, &t) in &tolerances.rate_abs_per_norm {
        if !non_negative(t) {
            return out(
                format!("tolerances.rate_abs_per_norm.{norm}"),
                t,
                AT_LEAST_ZERO,
            );
        }
    }
    for (name, norms) in series {
        for (norm, g) in norms {
            let at = |field: &str| format!("{name}.{norm}.{field}");
            for (field, rate) in [("rate", g.rate), ("rate_last_three", g.rate_last_three)] {
                if !rate.is_finite() {
                    return out(at(field), rate, "a finite number");
                }
            }
            if let Some(k) = g.errors.iter().position(|&e| !non_negative(e)) {
                return out(at(&format!("errors[{k}]")), g.errors[k], AT_LEAST_ZERO);
            }
            for (field, t) in [("error_rel", g.error_rel), ("rate_abs", g.rate_abs)] {
                if let Some(t) = t.filter(|&t| !non_negative(t)) {
                    return out(at(field), t, AT_LEAST_ZERO);
                }
            }
        }
    }
    Ok(())
}

/// A fitted rate, or NaN when the study could not fit one: no value, as in [`Drift::missing`].
/// [`compare`] reports a NaN rate as a drift (its difference is not finite), and serde_json
/// writes it, like any non-finite `f64`, as `null`, which a golden file cannot be read back
/// with: a missing rate fails loudly, never gates against a made-up number.
fn rate_or_nan(x: Option<f64>) -> f64 {
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
                .map(|c| GoldenCase::from_rates(c.case.id(), &c.rates))
                .collect(),
        }
    }

    /// The cases of `study` that this file marks chaotic, in the study's order.
    pub fn chaotic_cases(&self, study: &Study) -> Vec<Case> {
        study
            .cases
            .iter()
            .map(|c| c.case)
            .filter(|c| {
                let id = c.id();
                self.cases.iter().any(|g| g.case == id && g.is_chaotic())
            })
            .collect()
    }

    /// Holds each case at what its reproducibility allows (see the module): per-norm tolerances
    /// from the measured spread for reproducible and event-sensitive cases, the ensemble
    /// envelope for chaotic ones. Cases the study did not measure keep the file's tolerances.
    pub fn with_sensitivity(mut self, sensitivity: &Sensitivity) -> Self {
        for g in &mut self.cases {
            let Some(s) = sensitivity.case(&g.case) else {
                continue;
            };
            g.class = Some(s.class);
            for (key, gn) in &mut g.norms {
                let (Some(rate), Some(errors)) = (s.rates.get(key), s.errors.get(key)) else {
                    continue;
                };
                if s.chaotic {
                    gn.ensemble = Some(EnsembleEnvelope {
                        rate: *rate,
                        errors: errors.clone(),
                    });
                } else {
                    let spread = s.relative_error_spread(key).unwrap_or(0.0);
                    gn.error_rel = Some((SPREAD_SAFETY * spread).max(ERROR_REL_FLOOR));
                    gn.rate_abs = Some((SPREAD_SAFETY * rate.range()).max(RATE_ABS_FLOOR));
                }
            }
        }
        self
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

impl Drift {
    /// An entry the comparison could not make (`quantity` = `missing`); `norm` says what is
    /// missing.
    pub fn missing(case: &str, norm: &str) -> Self {
        Self {
            case: case.to_string(),
            norm: norm.to_string(),
            quantity: "missing".to_string(),
            golden: f64::NAN,
            now: f64::NAN,
            difference: f64::NAN,
            tolerance: 0.0,
        }
    }
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
        let missing = |norm: &str| Drift::missing(&id, norm);
        let Some(g) = golden.cases.iter().find(|g| g.case == id) else {
            drifts.push(missing("(case not in golden file)"));
            continue;
        };
        if g.is_chaotic() {
            // One run of a chaotic case is one sample: `compare_ensemble` gates it.
            continue;
        }
        if !same_setup {
            drifts.push(missing(
                "(levels, ratio or horizon differ from the golden file)",
            ));
            continue;
        }
        drifts.extend(compare_rates(g, tol, &c.rates, &study.config.levels));
    }
    drifts
}

/// Compares the rates and per-level errors of one series (`rates` at the levels `levels`) with
/// its golden values `g`, each norm at its own tolerance or else the file's `tol`; returns every
/// drifted entry. A norm of `rates` that `g` lacks is a drift.
pub fn compare_rates(
    g: &GoldenCase,
    tol: &Tolerances,
    rates: &[NormRates],
    levels: &[usize],
) -> Vec<Drift> {
    let mut drifts = Vec::new();
    let id = &g.case;
    for r in rates {
        let key = r.norm.key();
        let Some(gn) = g.norms.get(key) else {
            drifts.push(Drift::missing(id, key));
            continue;
        };
        let rate_tol = gn.rate_abs.unwrap_or_else(|| tol.rate_tolerance(key));
        let error_tol = gn.error_rel.unwrap_or(tol.error_rel);
        for (quantity, golden_value, now) in [
            ("rate", gn.rate, rate_or_nan(r.fit.map(|f| f.rate))),
            (
                "rate_last_three",
                gn.rate_last_three,
                rate_or_nan(r.fit_last_three.map(|f| f.rate)),
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
        if gn.errors.len() != r.errors.len() {
            drifts.push(Drift::missing(
                id,
                &format!(
                    "{key} (the golden file has {} errors for {} levels)",
                    gn.errors.len(),
                    r.errors.len()
                ),
            ));
            continue;
        }
        for (k, (&ge, &e)) in gn.errors.iter().zip(&r.errors).enumerate() {
            let rel = (e - ge) / ge.abs();
            let both_zero = e == 0.0 && ge == 0.0;
            if !both_zero && (!rel.is_finite() || rel.abs() > error_tol) {
                drifts.push(Drift {
                    case: id.clone(),
                    norm: key.to_string(),
                    quantity: format!("error[NX={}]", levels[k]),
                    golden: ge,
                    now: e,
                    difference: rel,
                    tolerance: error_tol,
                });
            }
        }
    }
    drifts
}

/// Gates the chaotic cases of `golden` on the ensemble statistics of `sensitivity`: per norm,
/// the median rate must lie in the golden `[min, max]` widened by [`ENVELOPE_MARGIN`] of its
/// range, and the median error at every level likewise in its golden envelope. A chaotic case
/// that `sensitivity` did not measure is a drift.
pub fn compare_ensemble(golden: &Golden, sensitivity: &Sensitivity) -> Vec<Drift> {
    let mut drifts = Vec::new();
    let within = |band: &Spread, x: f64| {
        let m = ENVELOPE_MARGIN * band.range();
        x.is_finite() && x >= band.min - m && x <= band.max + m
    };
    for g in golden.cases.iter().filter(|g| g.is_chaotic()) {
        let Some(s) = sensitivity.case(&g.case) else {
            drifts.push(Drift::missing(&g.case, "(chaotic case without ensemble)"));
            continue;
        };
        for (key, gn) in &g.norms {
            let Some(envelope) = &gn.ensemble else {
                continue;
            };
            let drift = |quantity: String, band: &Spread, now: f64| Drift {
                case: g.case.clone(),
                norm: key.clone(),
                quantity,
                golden: band.median,
                now,
                difference: now - band.median,
                tolerance: ENVELOPE_MARGIN * band.range(),
            };
            let now_rate = s.rates.get(key).map_or(f64::NAN, |r| r.median);
            if !within(&envelope.rate, now_rate) {
                drifts.push(drift("median rate".to_string(), &envelope.rate, now_rate));
            }
            let now_errors = s.errors.get(key);
            for (k, band) in envelope.errors.iter().enumerate() {
                let now = now_errors
                    .and_then(|e| e.get(k))
                    .map_or(f64::NAN, |e| e.median);
                if !within(band, now) {
                    let nx = golden.levels.get(k).copied().unwrap_or(0);
                    drifts.push(drift(format!("median error[NX={nx}]"), band, now));
                }
            }
        }
    }
    drifts
}

/// The whole gate on `study`: [`compare`] for every case, then [`compare_ensemble`] on the
/// ensembles that `ensembles` measures for the chaotic cases ([`Golden::chaotic_cases`]; not
/// called when there are none).
pub fn gate<E>(
    golden: &Golden,
    study: &Study,
    ensembles: impl FnOnce(&[Case]) -> Result<Sensitivity, E>,
) -> Result<Vec<Drift>, E> {
    let mut drifts = compare(golden, study);
    let chaotic = golden.chaotic_cases(study);
    if !chaotic.is_empty() {
        drifts.extend(compare_ensemble(golden, &ensembles(&chaotic)?));
    }
    Ok(drifts)
}

/// One row per drifted entry: case, norm, quantity, golden, now, difference, tolerance (`—`
/// where an entry is missing and has no number).
pub fn render_drifts(drifts: &[Drift]) -> String {
    let mut out = String::new();
    let _ = writeln!(
        out,
        "{} entries drifted from the golden values:\n\n| case | norm | quantity | golden | now | difference | tolerance |\n|---|---|---|---|---|---|---|",
        drifts.len()
    );
    let value = |v: f64, text: String| if v.is_nan() { "—".to_string() } else { text };
    for d in drifts {
        let _ = writeln!(
            out,
            "| {} | {} | {} | {} | {} | {} | {} |",
            d.case,
            d.norm,
            d.quantity,
            value(d.golden, format!("{:.6e}", d.golden)),
            value(d.now, format!("{:.6e}", d.now)),
            value(d.difference, format!("{:+.3e}", d.difference)),
            value(d.golden, format!("{:.3e}", d.tolerance)),
        );
    }
    out
}
