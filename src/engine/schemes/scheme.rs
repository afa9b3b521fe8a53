//! The scheme names and parameters of the paper and of its rivals, with validation.

use std::fmt;
use std::str::FromStr;

use serde::{Deserialize, Serialize};

use super::{AlphaParameters, PredictorVelocity};
use crate::engine::error::{require_in, ParameterError};
use crate::engine::fem::MassVariant;

/// A time-stepping scheme and its parameters.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(tag = "family", rename_all = "kebab-case", deny_unknown_fields)]
pub enum Scheme {
    /// Newmark(β, γ), eq. (32); explicit for β = 0 ([`super::ExplicitNewmark`]).
    Newmark {
        /// β ≥ 0 (β = 0: explicit, then γ ≥ ½).
        beta: f64,
        /// γ ≥ 0.
        gamma: f64,
    },
    /// θ-method, eq. (34).
    Theta {
        /// θ ∈ (0, 1].
        theta: f64,
    },
    /// Paoli–Schatzman, eq. (36), with γ = ½.
    PaoliSchatzman {
        /// β > 0.
        beta: f64,
        /// Restitution coefficient e ∈ [0, 1].
        restitution: f64,
    },
    /// Generalised-α (Chung–Hulbert 1993), eqs. (GA-a–d) of [`super::generalised_alpha`]; HHT-α
    /// is `α_m = 0`, Newmark(β, γ) is `α_m = α_f = 0`. Valid: `α_m < 1`, `α_f ∈ [0, 1)`, `β > 0`,
    /// `γ ≥ 0`.
    GeneralisedAlpha(AlphaParameters),
    /// Moreau–Jean (Jean 1999), eqs. (MJ-a–d) of [`super::moreau_jean`]: the θ-method on
    /// velocities with Newton's impact law.
    MoreauJean {
        /// θ ∈ (0, 1].
        theta: f64,
        /// Restitution coefficient e ∈ [0, 1] of Newton's impact law.
        restitution: f64,
    },
    /// Laursen–Chawla's energy-conserving scheme (1997), eqs. (LC-a–d) of
    /// [`super::laursen_chawla`]: no parameter.
    LaursenChawla {},
    /// Contact-stabilised Newmark (Deuflhard–Krause–Ertel 2008), eqs. (CSN-a–c) of
    /// [`super::contact_stabilised_newmark`]: Crank–Nicolson after an `M`-projection of the
    /// predictor onto the admissible set; defined with a definite mass and the multiplier.
    ContactStabilisedNewmark {
        /// The velocity the corrector starts from.
        velocity: PredictorVelocity,
    },
}

/// Generalised-α with the spectral radius `ρ∞` at infinite frequency (Chung–Hulbert 1993,
/// eqs. 25 and 17–20): `α_m = (2ρ∞ − 1)/(ρ∞ + 1)`, `α_f = ρ∞/(ρ∞ + 1)`, `γ = ½ − α_m + α_f`,
/// `β = ¼(1 − α_m + α_f)²`. `ρ∞ = 1` is Crank–Nicolson's dissipation-free limit.
pub const fn generalised_alpha(rho_inf: f64) -> Scheme {
    let alpha_m = (2.0 * rho_inf - 1.0) / (rho_inf + 1.0);
    let alpha_f = rho_inf / (rho_inf + 1.0);
    let shift = 1.0 - alpha_m + alpha_f;
    Scheme::GeneralisedAlpha(AlphaParameters {
        alpha_m,
        alpha_f,
        beta: 0.25 * shift * shift,
        gamma: 0.5 - alpha_m + alpha_f,
    })
}

/// HHT-α (Hilber–Hughes–Taylor 1977) as generalised-α with `α_m = 0`, `α_f = α ∈ [0, ⅓]`,
/// `γ = ½ + α`, `β = ¼(1 + α)²` (the original paper's α is `−α` here).
pub const fn hht(alpha: f64) -> Scheme {
    Scheme::GeneralisedAlpha(AlphaParameters {
        alpha_m: 0.0,
        alpha_f: alpha,
        beta: 0.25 * (1.0 + alpha) * (1.0 + alpha),
        gamma: 0.5 + alpha,
    })
}

/// The named presets: (name, scheme, the paper's label); the paper's seven first, then central
/// differences and the rivals.
const PRESETS: [(&str, Scheme, &str); 14] = [
    (
        "crank-nicolson",
        Scheme::Newmark {
            beta: 0.25,
            gamma: 0.5,
        },
        "Crank–Nicolson",
    ),
    (
        "newmark-1",
        Scheme::Newmark {
            beta: 0.5,
            gamma: 1.0,
        },
        "Newmark I (β, γ) = (1/2, 1)",
    ),
    (
        "newmark-2",
        Scheme::Newmark {
            beta: 0.5,
            gamma: 0.5,
        },
        "Newmark II (β, γ) = (1/2, 1/2)",
    ),
    (
        "backward-euler",
        Scheme::Theta { theta: 1.0 },
        "Backward Euler",
    ),
    (
        "paoli-schatzman-e0",
        Scheme::PaoliSchatzman {
            beta: 0.25,
            restitution: 0.0,
        },
        "Paoli–Schatzman I e = 0",
    ),
    (
        "paoli-schatzman-e0.5",
        Scheme::PaoliSchatzman {
            beta: 0.25,
            restitution: 0.5,
        },
        "Paoli–Schatzman II e = 1/2",
    ),
    (
        "paoli-schatzman-e1",
        Scheme::PaoliSchatzman {
            beta: 0.25,
            restitution: 1.0,
        },
        "Paoli–Schatzman III e = 1",
    ),
    (
        "central-difference",
        Scheme::Newmark {
            beta: 0.0,
            gamma: 0.5,
        },
        "Central differences, Newmark (0, 1/2), explicit: Δt ≤ 2/ω_max",
    ),
    (
        "generalised-alpha",
        generalised_alpha(0.8),
        "Generalised-α ρ∞ = 0.8 (Chung–Hulbert)",
    ),
    ("hht", hht(0.05), "HHT-α α = 0.05 (Hilber–Hughes–Taylor)"),
    (
        "moreau-jean",
        Scheme::MoreauJean {
            theta: 0.5,
            restitution: 0.0,
        },
        "Moreau–Jean θ = 1/2, e = 0 (Jean)",
    ),
    (
        "laursen-chawla",
        Scheme::LaursenChawla {},
        "Laursen–Chawla, energy-conserving",
    ),
    (
        "contact-stabilised-newmark",
        Scheme::ContactStabilisedNewmark {
            velocity: PredictorVelocity::Carried,
        },
        "Contact-stabilised Newmark (Deuflhard–Krause–Ertel)",
    ),
    (
        "contact-stabilised-newmark-dissipative",
        Scheme::ContactStabilisedNewmark {
            velocity: PredictorVelocity::Projected,
        },
        "Contact-stabilised Newmark, predictor velocity, energy-dissipative",
    ),
];

/// What a scheme name may be, for error messages.
pub const SCHEME_NAMES: &str = "one of: crank-nicolson, newmark-1, newmark-2, backward-euler, \
    paoli-schatzman-e0, paoli-schatzman-e0.5, paoli-schatzman-e1, central-difference, \
    generalised-alpha, hht, moreau-jean, laursen-chawla, contact-stabilised-newmark, \
    contact-stabilised-newmark-dissipative, or a parametrised form \
    newmark(beta=B,gamma=G), theta(theta=T), paoli-schatzman(beta=B,e=E), \
    generalised-alpha(rho_inf=R), hht(alpha=A), \
    generalised-alpha(alpha_m=AM,alpha_f=AF,beta=B,gamma=G), moreau-jean(theta=T,e=E)";

impl Scheme {
    /// Crank–Nicolson, Newmark (¼, ½).
    pub const CRANK_NICOLSON: Scheme = PRESETS[0].1;

    /// Backward Euler, the θ-method with θ = 1.
    pub const BACKWARD_EULER: Scheme = Scheme::Theta { theta: 1.0 };

    /// Central differences, Newmark (0, ½).
    pub const CENTRAL_DIFFERENCE: Scheme = PRESETS[7].1;

    /// The seven schemes of the paper's Tables 1–2, in table order.
    pub fn paper_schemes() -> [Scheme; 7] {
        std::array::from_fn(|i| PRESETS[i].1)
    }

    /// The rivals of the paper's schemes with their presets (generalised-α, HHT-α, Moreau–Jean,
    /// Laursen–Chawla, contact-stabilised Newmark in both variants).
    pub fn rival_schemes() -> [Scheme; 6] {
        std::array::from_fn(|i| PRESETS[8 + i].1)
    }

    /// Whether the scheme is defined with `mass`: contact-stabilised Newmark is not with a mass
    /// that has massless dofs (its predictor is an `M`-projection); every other scheme is.
    pub fn is_defined_with(self, mass: MassVariant) -> bool {
        !(matches!(self, Scheme::ContactStabilisedNewmark { .. }) && mass.has_massless_dofs())
    }

    /// Whether this is the explicit Newmark scheme (β = 0).
    pub fn is_explicit(self) -> bool {
        matches!(self, Scheme::Newmark { beta, .. } if beta == 0.0)
    }

    /// All preset names with their schemes and the paper's labels.
    pub fn presets() -> impl Iterator<Item = (&'static str, Scheme, &'static str)> {
        PRESETS.into_iter()
    }

    /// Why the scheme, valid but with γ < ½ (implicit Newmark), is a poor choice: its energy
    /// balance, eq. (33), gains `(½ − γ)ΔUᵀSΔU ≥ 0` at every step (negative numerical
    /// dissipation), so the energy grows and the scheme is unstable. `None` otherwise.
    pub fn warning(&self) -> Option<String> {
        match *self {
            Scheme::Newmark { beta, gamma } if beta > 0.0 && gamma < 0.5 => Some(format!(
                "{self}: gamma = {gamma} < 1/2 makes implicit Newmark unstable: its energy \
                 balance, eq. (33), gains (1/2 - gamma) dU^T S dU >= 0 at every step (negative \
                 numerical dissipation), so the energy grows; use gamma >= 1/2"
            )),
            Scheme::GeneralisedAlpha(AlphaParameters {
                alpha_m,
                alpha_f,
                beta,
                gamma,
            }) if !(alpha_m <= alpha_f
                && alpha_f <= 0.5
                && (gamma - (0.5 - alpha_m + alpha_f)).abs() <= 1e-12
                && beta >= 0.25 + 0.5 * (alpha_f - alpha_m)) =>
            {
                Some(format!(
                    "{self}: unconditional stability and second order need alpha_m <= alpha_f <= \
                     1/2, gamma = 1/2 - alpha_m + alpha_f and beta >= 1/4 + (alpha_f - alpha_m)/2 \
                     (Chung and Hulbert 1993); generalised-alpha(rho_inf=R) or hht(alpha=A) \
                     satisfy them"
                ))
            }
            Scheme::MoreauJean { theta, .. } if theta < 0.5 => Some(format!(
                "{self}: theta = {theta} < 1/2 makes Moreau-Jean unstable: its energy balance \
                 (MJ-E) gains (1/2 - theta)(dV^T M dV + dU^T S dU) >= 0 at every step; use \
                 theta >= 1/2"
            )),
            _ => None,
        }
    }

    /// Checks the parameter ranges; errors name the parameter.
    pub fn validate(self) -> Result<Self, ParameterError> {
        match self {
            Scheme::Newmark { beta, gamma } => {
                if !(beta.is_finite() && beta >= 0.0) {
                    return Err(ParameterError::new(
                        "beta",
                        beta,
                        "a finite number >= 0 (0: explicit Newmark)",
                    ));
                }
                if !(gamma.is_finite() && gamma >= 0.0) {
                    return Err(ParameterError::new("gamma", gamma, "a finite number >= 0"));
                }
                if beta == 0.0 && gamma < 0.5 {
                    return Err(ParameterError::new(
                        "gamma",
                        gamma,
                        "a number >= 1/2 when beta = 0 (explicit Newmark with γ < ½ is unstable \
                         for every Δt)",
                    ));
                }
            }
            Scheme::Theta { theta } => {
                require_in("theta", theta, 0.0, 1.0, "a number in (0, 1]")?;
                if theta == 0.0 {
                    return Err(ParameterError::new(
                        "theta",
                        theta,
                        "a number in (0, 1] (θ = 0, forward Euler, cannot impose the contact \
                         condition at t_{n+1})",
                    ));
                }
            }
            Scheme::PaoliSchatzman { beta, restitution } => {
                if !(beta.is_finite() && beta > 0.0) {
                    return Err(ParameterError::new("beta", beta, "a finite number > 0"));
                }
                require_in("e", restitution, 0.0, 1.0, "a number in [0, 1]")?;
            }
            Scheme::GeneralisedAlpha(AlphaParameters {
                alpha_m,
                alpha_f,
                beta,
                gamma,
            }) => {
                if !(alpha_m.is_finite() && alpha_m < 1.0) {
                    return Err(ParameterError::new(
                        "alpha_m",
                        alpha_m,
                        "a finite number < 1 (the equation of motion weighs A^{n+1} by 1 − α_m)",
                    ));
                }
                if !(alpha_f.is_finite() && (0.0..1.0).contains(&alpha_f)) {
                    return Err(ParameterError::new(
                        "alpha_f",
                        alpha_f,
                        "a number in [0, 1) (the equation of motion weighs U^{n+1} by 1 − α_f)",
                    ));
                }
                if !(beta.is_finite() && beta > 0.0) {
                    return Err(ParameterError::new("beta", beta, "a finite number > 0"));
                }
                if !(gamma.is_finite() && gamma >= 0.0) {
                    return Err(ParameterError::new("gamma", gamma, "a finite number >= 0"));
                }
            }
            Scheme::MoreauJean { theta, restitution } => {
                require_in("theta", theta, 0.0, 1.0, "a number in (0, 1]")?;
                if theta == 0.0 {
                    return Err(ParameterError::new(
                        "theta",
                        theta,
                        "a number in (0, 1] (θ = 0 leaves the velocity step explicit, and the \
                         impact law at t_{n+1} cannot be imposed)",
                    ));
                }
                require_in("e", restitution, 0.0, 1.0, "a number in [0, 1]")?;
            }
            Scheme::LaursenChawla {} | Scheme::ContactStabilisedNewmark { .. } => {}
        }
        Ok(self)
    }

    /// The preset name if this is a preset, else the parametrised form.
    pub fn name(self) -> String {
        PRESETS
            .iter()
            .find(|p| p.1 == self)
            .map(|p| p.0.to_string())
            .unwrap_or_else(|| match self {
                Scheme::Newmark { beta, gamma } => format!("newmark(beta={beta},gamma={gamma})"),
                Scheme::Theta { theta } => format!("theta(theta={theta})"),
                Scheme::PaoliSchatzman { beta, restitution } => {
                    format!("paoli-schatzman(beta={beta},e={restitution})")
                }
                Scheme::GeneralisedAlpha(AlphaParameters {
                    alpha_m,
                    alpha_f,
                    beta,
                    gamma,
                }) => self.alpha_family_name().unwrap_or_else(|| {
                    format!(
                        "generalised-alpha(alpha_m={alpha_m},alpha_f={alpha_f},beta={beta},\
                         gamma={gamma})"
                    )
                }),
                Scheme::MoreauJean { theta, restitution } => {
                    format!("moreau-jean(theta={theta},e={restitution})")
                }
                Scheme::LaursenChawla {} => "laursen-chawla".to_string(),
                Scheme::ContactStabilisedNewmark { velocity } => match velocity {
                    PredictorVelocity::Carried => "contact-stabilised-newmark",
                    PredictorVelocity::Projected => "contact-stabilised-newmark-dissipative",
                }
                .to_string(),
            })
    }

    /// `generalised-alpha(rho_inf=R)` or `hht(alpha=A)` when the parameters are exactly those
    /// of that form, so that the name parses back to the same scheme.
    fn alpha_family_name(self) -> Option<String> {
        let Scheme::GeneralisedAlpha(AlphaParameters {
            alpha_m, alpha_f, ..
        }) = self
        else {
            return None;
        };
        // `ρ∞ = α_f / (1 − α_f)`, rounded to the shortest decimal that gives these bits back.
        let rho_inf = alpha_f / (1.0 - alpha_f);
        let shortest = (1..=17).find_map(|digits| {
            let candidate: f64 = format!("{:.*e}", digits - 1, rho_inf).parse().ok()?;
            (generalised_alpha(candidate) == self).then_some(candidate)
        });
        if let Some(rho_inf) = shortest {
            return Some(format!("generalised-alpha(rho_inf={rho_inf})"));
        }
        (alpha_m == 0.0 && hht(alpha_f) == self).then(|| format!("hht(alpha={alpha_f})"))
    }

    /// The paper's label for a preset, else the name.
    pub fn label(self) -> String {
        PRESETS
            .iter()
            .find(|p| p.1 == self)
            .map(|p| p.2.to_string())
            .unwrap_or_else(|| self.name())
    }
}

impl fmt::Display for Scheme {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.name())
    }
}

fn parse_params(name: &str, body: &str, keys: &[&str]) -> Result<Vec<f64>, ParameterError> {
    let mut values = vec![f64::NAN; keys.len()];
    for part in body.split(',').map(str::trim).filter(|p| !p.is_empty()) {
        let (k, v) = part
            .split_once('=')
            .ok_or_else(|| ParameterError::new("scheme", name, SCHEME_NAMES))?;
        let slot = keys
            .iter()
            .position(|&key| key == k.trim())
            .ok_or_else(|| ParameterError::new("scheme", name, SCHEME_NAMES))?;
        if !values[slot].is_nan() {
            return Err(ParameterError::repeated("scheme", name, keys[slot]));
        }
        values[slot] = v
            .trim()
            .parse()
            .map_err(|_| ParameterError::new("scheme", name, SCHEME_NAMES))?;
    }
    if values.iter().any(|v| v.is_nan()) {
        return Err(ParameterError::new("scheme", name, SCHEME_NAMES));
    }
    Ok(values)
}

impl FromStr for Scheme {
    type Err = ParameterError;

    /// A preset name or `newmark(beta=…,gamma=…)`, `theta(theta=…)`,
    /// `paoli-schatzman(beta=…,e=…)`, `generalised-alpha(rho_inf=…)`, `hht(alpha=…)`,
    /// `generalised-alpha(alpha_m=…,alpha_f=…,beta=…,gamma=…)`, `moreau-jean(theta=…,e=…)`;
    /// the parameters are validated.
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let s = s.trim();
        if let Some(p) = PRESETS.iter().find(|p| p.0 == s) {
            return Ok(p.1);
        }
        let (family, body) = s
            .strip_suffix(')')
            .and_then(|rest| rest.split_once('('))
            .ok_or_else(|| ParameterError::new("scheme", s, SCHEME_NAMES))?;
        let scheme = match family.trim() {
            "newmark" => {
                let v = parse_params(s, body, &["beta", "gamma"])?;
                Scheme::Newmark {
                    beta: v[0],
                    gamma: v[1],
                }
            }
            "theta" => Scheme::Theta {
                theta: parse_params(s, body, &["theta"])?[0],
            },
            "paoli-schatzman" => {
                let v = parse_params(s, body, &["beta", "e"])?;
                Scheme::PaoliSchatzman {
                    beta: v[0],
                    restitution: v[1],
                }
            }
            "generalised-alpha" if body.contains("rho_inf") => {
                let rho_inf = parse_params(s, body, &["rho_inf"])?[0];
                require_in("rho_inf", rho_inf, 0.0, 1.0, "a number in [0, 1]")?;
                generalised_alpha(rho_inf)
            }
            "generalised-alpha" => {
                let v = parse_params(s, body, &["alpha_m", "alpha_f", "beta", "gamma"])?;
                Scheme::GeneralisedAlpha(AlphaParameters {
                    alpha_m: v[0],
                    alpha_f: v[1],
                    beta: v[2],
                    gamma: v[3],
                })
            }
            "hht" => {
                let alpha = parse_params(s, body, &["alpha"])?[0];
                require_in("alpha", alpha, 0.0, 1.0 / 3.0, "a number in [0, 1/3]")?;
                hht(alpha)
            }
            "moreau-jean" => {
                let v = parse_params(s, body, &["theta", "e"])?;
                Scheme::MoreauJean {
                    theta: v[0],
                    restitution: v[1],
                }
            }
            _ => return Err(ParameterError::new("scheme", s, SCHEME_NAMES)),
        };
        scheme.validate()
    }
}
