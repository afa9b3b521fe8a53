//! The golden file of `signorini verify` ([`VerifyGolden`]): another code's series with their
//! rates and per-level errors, held by the harness's own comparison
//! (`crate::harness::study::golden::compare_rates`) at the harness's tolerances.

use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};

use super::error::ExternalError;
use super::format::Code;
use super::verify::{Series, Verification};
use crate::harness::study::golden::{compare_rates, Drift, GoldenCase, GoldenNorm, Tolerances};

/// The committed values of one series.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GoldenSeries {
    /// The configuration's label.
    pub case: String,
    /// The code and version that made the runs (recorded, not compared).
    pub code: Code,
    /// `NX` of each level.
    pub levels: Vec<usize>,
    /// Norm key → values (the fields of `golden/rates-1d-dirichlet.json`'s norms).
    pub norms: BTreeMap<String, GoldenNorm>,
}

impl GoldenSeries {
    fn of(series: &Series) -> Self {
        let case = GoldenCase::from_rates(series.label.clone(), &series.rates);
        Self {
            case: case.case,
            code: series.code.clone(),
            levels: series.levels.iter().map(|l| l.nx).collect(),
            norms: case.norms,
        }
    }

    fn golden_case(&self) -> GoldenCase {
        GoldenCase {
            case: self.case.clone(),
            class: None,
            norms: self.norms.clone(),
        }
    }
}

/// A golden file of verified runs.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct VerifyGolden {
    /// What wrote it (`signorini verify --write-golden`).
    pub generated_by: String,
    /// The scene's name.
    pub scene: String,
    /// The gate's tolerances (the harness's defaults: a rate within 0.02, an error within 1 %).
    pub tolerances: Tolerances,
    /// One entry per series.
    pub series: Vec<GoldenSeries>,
}

impl VerifyGolden {
    /// The golden values of `verification`, at the default tolerances. Every computed norm of
    /// every series needs its rates (two levels or more with a positive finite error; three for
    /// `rate_last_three`): a gate cannot hold a rate that does not exist.
    pub fn from_verification<J>(verification: &Verification<J>) -> Result<Self, ExternalError> {
        for s in &verification.series {
            if let Some(r) = s
                .rates
                .iter()
                .find(|r| r.fit.is_none() || r.fit_last_three.is_none())
            {
                return Err(ExternalError::Series {
                    label: s.label.clone(),
                    problem: format!(
                        "{} has no fitted rate over all levels or the last three (levels {:?}): \
                         a golden file needs at least two levels with a positive, finite error",
                        r.norm.key(),
                        s.levels.iter().map(|l| l.nx).collect::<Vec<_>>()
                    ),
                });
            }
        }
        Ok(Self {
            generated_by: "signorini verify --write-golden".to_string(),
            scene: verification.scene.clone(),
            tolerances: Tolerances::default(),
            series: verification.series.iter().map(GoldenSeries::of).collect(),
        })
    }
}

/// Every entry of `verification` that drifted from `golden` (empty: the gate passes): each
/// series' rates and errors by [`compare_rates`]; a series or norm on one side only, other
/// levels or another scene is a drift too.
pub fn compare<J>(golden: &VerifyGolden, verification: &Verification<J>) -> Vec<Drift> {
    let mut drifts = Vec::new();
    if golden.scene != verification.scene {
        drifts.push(Drift::missing(
            "(all series)",
            &format!(
                "(scene {} differs from the golden file's {})",
                verification.scene, golden.scene
            ),
        ));
        return drifts;
    }
    for s in &verification.series {
        let Some(g) = golden.series.iter().find(|g| g.case == s.label) else {
            drifts.push(Drift::missing(&s.label, "(series not in golden file)"));
            continue;
        };
        let levels: Vec<usize> = s.levels.iter().map(|l| l.nx).collect();
        if g.levels != levels {
            drifts.push(Drift::missing(
                &s.label,
                "(levels differ from the golden file)",
            ));
            continue;
        }
        drifts.extend(compare_rates(
            &g.golden_case(),
            &golden.tolerances,
            &s.rates,
            &levels,
        ));
        for key in g.norms.keys() {
            if !s.rates.iter().any(|r| r.norm.key() == key) {
                drifts.push(Drift::missing(&s.label, &format!("{key} (not computed)")));
            }
        }
    }
    for g in &golden.series {
        if !verification.series.iter().any(|s| s.label == g.case) {
            drifts.push(Drift::missing(&g.case, "(golden series not verified)"));
        }
    }
    drifts
}
