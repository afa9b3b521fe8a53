//! How the contact condition is discretised: a Lagrange multiplier (the papers), a penalty, or
//! Nitsche's method. Names follow the scheme names (`penalty(gamma0=G)`,
//! `nitsche(theta=T,gamma0=G)`) and are validated the same way as [`crate::engine::schemes::Scheme`].
//!
//! With `E` the Young modulus (`ρc²` for a bar) and `h` the mesh size at the contact boundary:
//! * `multiplier`: `0 ≤ B U + g ⟂ λ ≤ 0` exactly (1D paper eq. 30);
//! * `penalty(gamma0=γ₀)`: `λ = κ min(B U + g, 0)` with `κ = γ₀ E / h`;
//! * `nitsche(theta=θ,gamma0=γ₀)`: Chouly–Hild–Renard (ESAIM M2AN 49, 2015, eq. 2.5) with
//!   `γ = γ₀ E / h` and `θ ∈ {−1, 0, 1}`; 1D only (see [`super::law`]).

use std::fmt;
use std::str::FromStr;

use serde::{Deserialize, Serialize};

use crate::engine::error::ParameterError;

/// A contact treatment and its parameters.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub enum ContactTreatment {
    /// The exact complementarity condition with a Lagrange multiplier (1D paper eq. 30).
    #[default]
    Multiplier,
    /// The penalty force `λ = κ min(B U + g, 0)`, `κ = γ₀ E / h`.
    Penalty {
        /// `γ₀ > 0`.
        gamma0: f64,
    },
    /// Nitsche's method with `γ = γ₀ E / h`.
    Nitsche {
        /// `θ ∈ {−1, 0, 1}` (skew-symmetric, incomplete, symmetric).
        theta: f64,
        /// `γ₀ > 0`.
        gamma0: f64,
    },
}

/// What a contact treatment may be, for error messages.
pub const TREATMENT_NAMES: &str = "one of: multiplier, penalty(gamma0=G) with G > 0, \
    nitsche(theta=T,gamma0=G) with T in {-1, 0, 1} and G > 0";

/// The treatments `signorini list` shows: (name, parameters, description).
pub const TREATMENT_LIST: [(&str, &str, &str); 3] = [
    (
        "multiplier",
        "none",
        "Lagrange multiplier, exact complementarity (the papers; default)",
    ),
    (
        "penalty(gamma0=G)",
        "G > 0",
        "force κ min(u + g, 0), κ = G·E/h",
    ),
    (
        "nitsche(theta=T,gamma0=G)",
        "T ∈ {-1, 0, 1}, G > 0",
        "Nitsche, γ = G·E/h (1D only; T = 1 needs G > 1)",
    ),
];

impl ContactTreatment {
    /// Checks the parameters: `γ₀` finite and `> 0`, `θ ∈ {−1, 0, 1}`; errors name the field.
    pub fn validate(self) -> Result<Self, ParameterError> {
        let gamma0 = match self {
            ContactTreatment::Multiplier => return Ok(self),
            ContactTreatment::Penalty { gamma0 } => gamma0,
            ContactTreatment::Nitsche { theta, gamma0 } => {
                if ![-1.0, 0.0, 1.0].contains(&theta) {
                    return Err(ParameterError::new("theta", theta, "one of -1, 0, 1"));
                }
                gamma0
            }
        };
        if !(gamma0.is_finite() && gamma0 > 0.0) {
            return Err(ParameterError::new("gamma0", gamma0, "a finite number > 0"));
        }
        Ok(self)
    }

    /// The name as the command line and scenes write it.
    pub fn name(self) -> String {
        match self {
            ContactTreatment::Multiplier => "multiplier".to_string(),
            ContactTreatment::Penalty { gamma0 } => format!("penalty(gamma0={gamma0})"),
            ContactTreatment::Nitsche { theta, gamma0 } => {
                format!("nitsche(theta={theta},gamma0={gamma0})")
            }
        }
    }
}

impl fmt::Display for ContactTreatment {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.name())
    }
}

fn parse_params(name: &str, body: &str, keys: &[&str]) -> Result<Vec<f64>, ParameterError> {
    let bad = || ParameterError::new("contact", name, TREATMENT_NAMES);
    let mut values = vec![f64::NAN; keys.len()];
    for part in body.split(',').map(str::trim).filter(|p| !p.is_empty()) {
        let (k, v) = part.split_once('=').ok_or_else(bad)?;
        let slot = keys
            .iter()
            .position(|&key| key == k.trim())
            .ok_or_else(bad)?;
        if !values[slot].is_nan() {
            return Err(ParameterError::repeated("contact", name, keys[slot]));
        }
        values[slot] = v.trim().parse().map_err(|_| bad())?;
    }
    if values.iter().any(|v| v.is_nan()) {
        return Err(bad());
    }
    Ok(values)
}

impl FromStr for ContactTreatment {
    type Err = ParameterError;

    /// `multiplier`, `penalty(gamma0=…)` or `nitsche(theta=…,gamma0=…)`; the parameters are
    /// validated.
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let s = s.trim();
        if s == "multiplier" {
            return Ok(ContactTreatment::Multiplier);
        }
        let (family, body) = s
            .strip_suffix(')')
            .and_then(|rest| rest.split_once('('))
            .ok_or_else(|| ParameterError::new("contact", s, TREATMENT_NAMES))?;
        let treatment = match family.trim() {
            "penalty" => ContactTreatment::Penalty {
                gamma0: parse_params(s, body, &["gamma0"])?[0],
            },
            "nitsche" => {
                let v = parse_params(s, body, &["theta", "gamma0"])?;
                ContactTreatment::Nitsche {
                    theta: v[0],
                    gamma0: v[1],
                }
            }
            _ => return Err(ParameterError::new("contact", s, TREATMENT_NAMES)),
        };
        treatment.validate()
    }
}
