//! The scheme factory: the integrator of a [`Scheme`] on a model, from its consistent start.
//!
//! Newmark with β > 0 and the θ-method run in the common one-step form ([`OneStepScheme`],
//! eqs. 32 and 34), Newmark with β = 0 explicitly ([`ExplicitNewmark`], eq. 32),
//! Paoli–Schatzman as its two-step scheme ([`PaoliSchatzman`], eq. 36), and the rivals as
//! theirs ([`GeneralisedAlpha`], [`MoreauJean`], [`ContactStabilisedNewmark`]); every one
//! starts from [`initial_state`]
//! (`A^0` from eq. 32c).

use super::conventions::{Conventions, NitscheAcceleration};
use super::laursen_chawla::laursen_chawla;
use super::{
    initial_state, ContactStabilisedNewmark, ExplicitNewmark, GeneralisedAlpha, MoreauJean,
    OneStepScheme, PaoliSchatzman, Scheme, StepCoefficients, TimeIntegrator,
};
use crate::engine::contact::ContactTreatment;
use crate::engine::error::{Error, ParameterError};
use crate::engine::model::Model;

/// Builds the integrator of `scheme` on `model` with step `dt`, from the displacement and
/// velocity dofs `u0`, `v0`, under the implementation `conventions`. Paoli–Schatzman,
/// Moreau–Jean and contact-stabilised Newmark run with the multiplier only (the first's energy
/// balance with a penalty or Nitsche force is not derived; the second constrains velocities;
/// the third projects onto the admissible set): other treatments are a [`ParameterError`] on
/// `contact`. Contact-stabilised Newmark refuses a mass with massless dofs (on `mass`). Explicit Newmark and the rivals keep the consistent
/// Nitsche acceleration: the elastic one is a [`ParameterError`] on `nitsche_acceleration`
/// there.
pub fn integrator<'m>(
    model: &'m Model,
    scheme: Scheme,
    dt: f64,
    u0: &[f64],
    v0: &[f64],
    conventions: &Conventions,
) -> Result<Box<dyn TimeIntegrator + 'm>, Error> {
    let treatment = model.contact_law().treatment();
    if treatment != ContactTreatment::Multiplier {
        let only_multiplier = match scheme {
            Scheme::PaoliSchatzman { .. } => Some(
                "multiplier with Paoli–Schatzman (its energy balance with a penalty or Nitsche \
                 force is not derived; penalty and Nitsche run with the Newmark, θ and \
                 generalised-α schemes)",
            ),
            Scheme::ContactStabilisedNewmark { .. } => Some(
                "multiplier with contact-stabilised Newmark (its predictor is projected onto \
                 the admissible set, which a penalty or Nitsche force does not define)",
            ),
            Scheme::MoreauJean { .. } | Scheme::LaursenChawla {} => Some(
                "multiplier with Moreau–Jean and Laursen–Chawla (their impact or persistency \
                 law constrains the step's motion; a penalty or Nitsche force is a function of \
                 the position, run it with the θ-method)",
            ),
            _ => None,
        };
        if let Some(allowed) = only_multiplier {
            return Err(ParameterError::new("contact", treatment, allowed).into());
        }
    }
    let elastic_nitsche = conventions.nitsche_acceleration == NitscheAcceleration::ElasticStiffness
        && model.contact_law().stiffness_update().is_some();
    let one_step = matches!(scheme, Scheme::Newmark { .. } | Scheme::Theta { .. });
    if elastic_nitsche && (scheme.is_explicit() || !one_step) {
        return Err(ParameterError::new(
            "nitsche_acceleration",
            "elastic-stiffness",
            "consistent with this scheme (the elastic Nitsche acceleration is offered for \
             implicit Newmark and the θ-method, as GetFEM's demo integrates them)",
        )
        .into());
    }
    let start = initial_state(model, u0, v0, conventions)?;
    let coefficients = match scheme {
        Scheme::Newmark { gamma, .. } if scheme.is_explicit() => {
            return Ok(Box::new(ExplicitNewmark::new(model, gamma, dt, start)?));
        }
        Scheme::PaoliSchatzman { beta, restitution } => {
            return Ok(Box::new(PaoliSchatzman::new(
                model,
                beta,
                restitution,
                dt,
                start,
                conventions,
            )?));
        }
        Scheme::GeneralisedAlpha(parameters) => {
            return Ok(Box::new(
                GeneralisedAlpha::new(model, parameters, dt, start)?
                    .with_predictor(conventions.predictor),
            ));
        }
        Scheme::MoreauJean { theta, restitution } => {
            return Ok(Box::new(MoreauJean::new(
                model,
                theta,
                restitution,
                dt,
                start,
            )?));
        }
        Scheme::LaursenChawla {} => {
            return Ok(Box::new(laursen_chawla(model, dt, start)?));
        }
        Scheme::ContactStabilisedNewmark { velocity } => {
            return Ok(Box::new(ContactStabilisedNewmark::new(
                model, velocity, dt, start,
            )?));
        }
        Scheme::Newmark { beta, gamma } => StepCoefficients::newmark(beta, gamma),
        Scheme::Theta { theta } => StepCoefficients::theta(theta),
    };
    Ok(Box::new(
        OneStepScheme::new(
            model,
            coefficients,
            dt,
            start,
            conventions.nitsche_acceleration,
        )?
        .with_predictor(conventions.predictor),
    ))
}
