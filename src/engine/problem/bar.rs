//! The 1D bar of the paper: its obstacle and load, the exact solution that supplies the initial
//! data and the reference, and the horizon.

use std::sync::Arc;

use super::{Discretisation, InitialData, Settings};
use crate::engine::contact::{ContactLaw, ContactTreatment};
use crate::engine::error::ParameterError;
use crate::engine::exact::ExactSolution;
use crate::engine::fem::{Bar1d, EndCondition, MassVariant};
use crate::engine::model::Model;
use crate::engine::solver_plan::SolverPlan;

/// A 1D benchmark: the bar, its obstacle and load, the exact solution that supplies the
/// initial data and the reference, and the horizon.
#[derive(Debug, Clone)]
pub struct Problem1d {
    /// Bar length `L`.
    pub length: f64,
    /// Density `ρ`.
    pub density: f64,
    /// Wave speed `c`.
    pub wave_speed: f64,
    /// Condition at `x = L`.
    pub far_end: EndCondition,
    /// Gap to the obstacle at `x = 0`; `None`: no obstacle.
    pub obstacle_gap: Option<f64>,
    /// Constant body force density; `None`: no load.
    pub body_force: Option<f64>,
    /// The exact solution (the reference of every error norm).
    pub exact: Arc<dyn ExactSolution>,
    /// The initial displacement and velocity.
    pub initial: InitialData,
    /// Horizon `T`.
    pub horizon: f64,
    /// How the contact condition is discretised (default: the multiplier).
    pub contact: ContactTreatment,
}

impl Problem1d {
    /// The problem's bar meshed with `nx` elements.
    pub fn bar(&self, nx: usize) -> Result<Bar1d, ParameterError> {
        Bar1d::new(self.length, nx, self.density, self.wave_speed, self.far_end)
    }

    /// The mesh with `nx` elements and the model assembled from what the problem declares:
    /// a contact set (with the problem's contact treatment) only with an obstacle, a load
    /// vector only with a body force. A treatment other than the multiplier needs an obstacle.
    pub fn model(&self, nx: usize, mass: MassVariant) -> Result<(Bar1d, Model), ParameterError> {
        let bar = self.bar(nx)?;
        bar.check_mass(mass)?;
        let mut model = Model::bar1d(&bar, mass, self.obstacle_gap, self.body_force);
        if self.contact != ContactTreatment::Multiplier {
            if self.obstacle_gap.is_none() {
                return Err(ParameterError::new(
                    "contact",
                    self.contact,
                    "multiplier for a problem without obstacle",
                ));
            }
            model = model.with_contact_law(ContactLaw::bar1d(self.contact, &bar)?);
        }
        Ok((bar, model))
    }

    /// The discretisation with `nx` elements and the mass matrix `mass`, solved with
    /// `settings`: the mesh, the model ([`Problem1d::model`]) with its solver plan
    /// ([`SolverPlan::for_bar`]) and the initial dofs
    /// ([`Problem1d::initial_dofs`]), with the settings' round-off perturbation (if any) added
    /// to every displacement dof except the contact dofs, after the declared one.
    pub fn discretise(
        &self,
        nx: usize,
        mass: MassVariant,
        settings: &Settings,
    ) -> Result<Discretisation<Bar1d>, ParameterError> {
        settings.validate()?;
        let plan = SolverPlan::for_bar(settings.linear_solver)?;
        let (bar, model) = self.model(nx, mass)?;
        let model = model.with_solver_plan(plan);
        let (mut displacement, velocity) = self.initial_dofs(&bar, &model);
        if let Some(p) = &settings.round_off {
            p.apply(&mut displacement, contact_dofs(&model));
        }
        Ok(Discretisation {
            mesh: bar,
            model,
            displacement,
            velocity,
            conventions: settings.conventions,
            step_perturbation: settings.step_round_off,
        })
    }

    /// The initial displacement and velocity of the problem as stated, as dof vectors: the
    /// nodal interpolants of the declared profiles, then the declared seeded perturbation (if
    /// any) added to every displacement dof except the contact dofs of `model`.
    pub fn initial_dofs(&self, bar: &Bar1d, model: &Model) -> (Vec<f64>, Vec<f64>) {
        let exact = self.exact.as_ref();
        let mut u0 = self.initial.displacement.interpolate(bar, exact, |p| p.u);
        let v0 = self.initial.velocity.interpolate(bar, exact, |p| p.ut);
        if let Some(p) = &self.initial.perturbation {
            p.apply(&mut u0, contact_dofs(model));
        }
        (u0, v0)
    }
}

/// The contact dofs of `model` (none without an obstacle): the displacement perturbations
/// leave them untouched, so perturbed data stay admissible.
fn contact_dofs(model: &Model) -> &[usize] {
    model.contact().map_or(&[][..], |c| &c.dofs[..])
}
