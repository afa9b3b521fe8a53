//! The paper's Tables 1–2 (1D paper §5.2) as data, embedded in the binary.

use serde::Deserialize;

use crate::harness::problem::Scheme;
use crate::harness::run::norms::Norm;
use crate::harness::study::Case;

/// One row of the paper's tables.
#[derive(Debug, Clone, Deserialize)]
pub struct PaperRow {
    /// Scheme family or preset name.
    pub scheme: String,
    /// The scheme's parameters (`beta`, `gamma`, `theta`, `e`).
    pub params: std::collections::BTreeMap<String, f64>,
    /// `standard` or `redistributed`.
    pub mass: String,
    /// `u_Linf_H`.
    #[serde(rename = "u_Linf_H")]
    pub u_linf_h: f64,
    /// `u_L2_H`.
    #[serde(rename = "u_L2_H")]
    pub u_l2_h: f64,
    /// `u_Linf_V`.
    #[serde(rename = "u_Linf_V")]
    pub u_linf_v: f64,
    /// `u_L2_V`.
    #[serde(rename = "u_L2_V")]
    pub u_l2_v: f64,
    /// `lambda_L2`.
    #[serde(rename = "lambda_L2")]
    pub lambda_l2: f64,
    /// The paper's word: No, Small, Yes, Big.
    pub oscillations: String,
    /// `energy_Linf`.
    #[serde(rename = "energy_Linf")]
    pub energy_linf: f64,
    /// `energy_L2`.
    #[serde(rename = "energy_L2")]
    pub energy_l2: f64,
}

impl PaperRow {
    /// The paper's rate for `norm`.
    pub fn rate(&self, norm: Norm) -> f64 {
        match norm {
            Norm::DisplacementLinfH => self.u_linf_h,
            Norm::DisplacementL2H => self.u_l2_h,
            Norm::DisplacementLinfV => self.u_linf_v,
            Norm::DisplacementL2V => self.u_l2_v,
            Norm::MultiplierL2 => self.lambda_l2,
            Norm::EnergyLinf => self.energy_linf,
            Norm::EnergyL2 => self.energy_l2,
        }
    }
}

/// Tables 1–2.
#[derive(Debug, Clone, Deserialize)]
pub struct PaperTables {
    /// Where the numbers come from.
    pub source: String,
    /// The 14 rows.
    pub rows: Vec<PaperRow>,
}

impl PaperTables {
    /// The embedded tables (`paper/paper-tables.json` beside this file, a copy of the specification's data).
    pub fn load() -> Self {
        serde_json::from_str(include_str!("paper/paper-tables.json"))
            .expect("the embedded paper tables are valid JSON")
    }

    /// The row of `case`, if the paper has it.
    pub fn row(&self, case: &Case) -> Option<&PaperRow> {
        self.rows
            .iter()
            .find(|r| r.mass == case.mass.name() && r.scheme_value() == Some(case.scheme))
    }
}

impl PaperRow {
    /// The scheme this row describes: a preset name, or `paoli-schatzman` with `beta` and `e`.
    pub fn scheme_value(&self) -> Option<Scheme> {
        if let Ok(s) = self.scheme.parse() {
            return Some(s);
        }
        (self.scheme == "paoli-schatzman").then(|| Scheme::PaoliSchatzman {
            beta: self.params.get("beta").copied().unwrap_or(f64::NAN),
            restitution: self.params.get("e").copied().unwrap_or(f64::NAN),
        })
    }
}
