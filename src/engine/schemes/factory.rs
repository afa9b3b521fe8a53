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
    OneStepScheme, PaoliSchatzman, Scheme, SchemeState, StepCoefficients, TimeIntegrator,
};
use crate::engine::contact::ContactTreatment;
use crate::engine::error::{Error, ParameterError};
use crate::engine::model::Model;

/// A scheme on a model with the state it starts from: the method the time loop calls and the
/// state `t_0` the loop holds and hands to it.
pub type Integrator<'m> = (Box<dyn TimeIntegrator + 'm>, SchemeState);

/// Builds the integrator of `scheme` on `model` with step `dt` and its state at `t = 0`, from
/// the displacement and velocity dofs `u0`, `v0`, under the implementation `conventions`. Paoli–Schatzman,
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
) -> Result<Integrator<'m>, Error> {
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
    let state = SchemeState::start(dt, initial_state(model, u0, v0, conventions)?);
    let one_step = |coefficients| -> Result<Box<dyn TimeIntegrator + 'm>, Error> {
        let scheme = OneStepScheme::new(model, coefficients, dt, conventions.nitsche_acceleration)?;
        Ok(Box::new(scheme.with_predictor(conventions.predictor)))
    };
    Ok(match scheme {
        Scheme::Newmark { gamma, .. } if scheme.is_explicit() => {
            (Box::new(ExplicitNewmark::new(model, gamma, dt)?), state)
        }
        Scheme::PaoliSchatzman { beta, restitution } => {
            let method =
                PaoliSchatzman::new(model, (beta, restitution), dt, &state.lambda, conventions)?;
            (Box::new(method), state)
        }
        Scheme::GeneralisedAlpha(parameters) => {
            let method = GeneralisedAlpha::new(model, parameters, dt)?;
            (
                Box::new(method.with_predictor(conventions.predictor)),
                state,
            )
        }
        Scheme::MoreauJean { theta, restitution } => (
            Box::new(MoreauJean::new(model, theta, restitution, dt)?),
            state.without_acceleration(),
        ),
        Scheme::LaursenChawla {} => (
            Box::new(laursen_chawla(model, dt)?),
            state.without_acceleration(),
        ),
        Scheme::ContactStabilisedNewmark { velocity } => (
            Box::new(ContactStabilisedNewmark::new(model, velocity, dt)?),
            state.without_acceleration(),
        ),
        Scheme::Newmark { beta, gamma } => {
            (one_step(StepCoefficients::newmark(beta, gamma))?, state)
        }
        Scheme::Theta { theta } => (one_step(StepCoefficients::theta(theta))?, state),
    })
}
