//! The scheme factory: the integrator of a [`Scheme`] on a model, from its consistent start.
//!
//! Newmark with β > 0 and the θ-method run in the common one-step form ([`OneStepScheme`],
//! eqs. 32 and 34), Newmark with β = 0 explicitly ([`ExplicitNewmark`], eq. 32), and
//! Paoli–Schatzman as its two-step scheme ([`PaoliSchatzman`], eq. 36); every one starts from
//! [`initial_state`] (`A^0` from eq. 32c).

use super::conventions::{Conventions, NitscheAcceleration};
use super::{
    initial_state, ExplicitNewmark, OneStepScheme, PaoliSchatzman, Scheme, StepCoefficients,
    TimeIntegrator,
};
use crate::engine::contact::ContactTreatment;
use crate::engine::error::{Error, ParameterError};
use crate::engine::model::Model;

/// Builds the integrator of `scheme` on `model` with step `dt`, from the displacement and
/// velocity dofs `u0`, `v0`, under the implementation `conventions`. Paoli–Schatzman runs with
/// the multiplier only (its energy balance with a penalty or Nitsche force is not derived):
/// other treatments are a [`ParameterError`] on `contact`. Explicit Newmark keeps the
/// consistent Nitsche acceleration: the elastic one is a [`ParameterError`] on
/// `nitsche_acceleration` there.
pub fn integrator<'m>(
    model: &'m Model,
    scheme: Scheme,
    dt: f64,
    u0: &[f64],
    v0: &[f64],
    conventions: &Conventions,
) -> Result<Box<dyn TimeIntegrator + 'm>, Error> {
    let treatment = model.contact_law().treatment();
    if matches!(scheme, Scheme::PaoliSchatzman { .. }) && treatment != ContactTreatment::Multiplier
    {
        return Err(ParameterError::new(
            "contact",
            treatment,
            "multiplier with Paoli–Schatzman (penalty and Nitsche run with the Newmark and θ \
             schemes)",
        )
        .into());
    }
    let elastic_nitsche = conventions.nitsche_acceleration == NitscheAcceleration::ElasticStiffness
        && model.contact_law().stiffness_update().is_some();
    if scheme.is_explicit() && elastic_nitsche {
        return Err(ParameterError::new(
            "nitsche_acceleration",
            "elastic-stiffness",
            "consistent with explicit Newmark (the elastic Nitsche acceleration is offered for \
             the implicit one-step schemes, as GetFEM's demo integrates them)",
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
