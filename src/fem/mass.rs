//! Mass-matrix variants.
//!
//! * `standard`: the consistent P1/Q1 mass matrix, `M_ij = ∫_Ω ρ φ_i φ_j`.
//! * `redistributed`: the paper's `M^mod` (1D paper §3.2; 2D/3D note §2.1),
//!   `M^mod_ij = ∫_{Ω^mod} ρ φ_i φ_j` with `Ω^mod` the union of the elements that do **not**
//!   touch the contact boundary. Every dof of a node on the contact boundary then has a zero row
//!   and column: the node carries no inertia and evolves quasi-statically. The mass of the
//!   removed elements is removed, not moved (the total mass drops by that of one element layer).

use std::fmt;
use std::str::FromStr;

use serde::{Deserialize, Serialize};

use crate::error::ParameterError;

/// Which mass matrix the semi-discrete problem uses.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum MassVariant {
    /// Consistent mass matrix `M`.
    Standard,
    /// The paper's `M^mod`: elements touching the contact boundary removed from the integral.
    Redistributed,
}

impl MassVariant {
    /// Every variant, in table order.
    pub const ALL: [MassVariant; 2] = [MassVariant::Standard, MassVariant::Redistributed];

    /// The name used in scene files, on the command line and in reports.
    pub fn name(self) -> &'static str {
        match self {
            MassVariant::Standard => "standard",
            MassVariant::Redistributed => "redistributed",
        }
    }

    /// The paper's short label (`STD`, `MOD`).
    pub fn paper_label(self) -> &'static str {
        match self {
            MassVariant::Standard => "STD",
            MassVariant::Redistributed => "MOD",
        }
    }

    /// Whether an element contributes to the mass integral.
    pub fn includes_element(self, touches_contact_boundary: bool) -> bool {
        match self {
            MassVariant::Standard => true,
            MassVariant::Redistributed => !touches_contact_boundary,
        }
    }
}

impl fmt::Display for MassVariant {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for MassVariant {
    type Err = ParameterError;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Self::ALL
            .into_iter()
            .find(|m| m.name() == s)
            .ok_or_else(|| ParameterError::new("mass", s, "one of: standard, redistributed"))
    }
}
