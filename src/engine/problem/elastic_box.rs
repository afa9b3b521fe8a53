//! The 2D/3D bar of the note (§3): a box of Q1 elements, its face `x_d = 0` on the obstacle
//! side, its face `x_d = L_d` held fixed, starting with a uniform axial displacement and
//! velocity.

use super::{Discretisation, Settings};
use crate::engine::contact::{ContactLaw, ContactTreatment};
use crate::engine::error::ParameterError;
use crate::engine::fem::box_mesh::{BoxMesh, Elasticity};
use crate::engine::fem::MassVariant;
use crate::engine::linalg::StepSolverKind;
use crate::engine::model::Model;
use crate::engine::solver_plan::SolverPlan;

/// A 2D/3D bar problem.
#[derive(Debug, Clone, PartialEq)]
pub struct BoxProblem {
    /// Box lengths, the last along the bar's axis.
    pub lengths: Vec<f64>,
    /// Density and Lamé constants.
    pub elasticity: Elasticity,
    /// Distance from the bottom face to the obstacle; `None`: no obstacle.
    pub obstacle_gap: Option<f64>,
    /// Uniform initial displacement along the axis (measured from the initial configuration).
    pub initial_displacement: f64,
    /// Uniform initial velocity along the axis.
    pub initial_velocity: f64,
    /// Horizon `T`.
    pub horizon: f64,
    /// How the contact condition is discretised (multiplier or penalty; Nitsche is 1D only).
    pub contact: ContactTreatment,
}

/// The mesh of a run: `n_axis` elements along the axis, square elements across.
pub fn box_mesh(problem: &BoxProblem, n_axis: usize) -> Result<BoxMesh, ParameterError> {
    let d = problem.lengths.len();
    let h = problem
        .lengths
        .get(d.wrapping_sub(1))
        .copied()
        .unwrap_or(f64::NAN)
        / n_axis as f64;
    let counts: Vec<usize> = problem
        .lengths
        .iter()
        .enumerate()
        .map(|(i, l)| {
            if i + 1 == d {
                n_axis
            } else {
                ((l / h).round() as usize).max(1)
            }
        })
        .collect();
    BoxMesh::new(&problem.lengths, &counts)
}

/// The initial displacement and velocity dofs of the problem as stated on `mesh`: the nodal
/// interpolants of the uniform axial values `u⁰ = initial_displacement · e_d`,
/// `v⁰ = initial_velocity · e_d`.
pub fn initial_dofs(problem: &BoxProblem, mesh: &BoxMesh) -> (Vec<f64>, Vec<f64>) {
    let d = mesh.dim();
    let axis = |value: f64| {
        move |_: &[f64]| {
            let mut v = [0.0; 3];
            v[d - 1] = value;
            v
        }
    };
    let u0 = mesh.interpolate(axis(problem.initial_displacement));
    let v0 = mesh.interpolate(axis(problem.initial_velocity));
    (u0, v0)
}

impl BoxProblem {
    /// The discretisation with `n_axis` elements along the axis and the mass matrix `mass`,
    /// solved with `settings`: the mesh and the model ([`BoxProblem::model`]), and the initial
    /// dofs ([`initial_dofs`]) with the settings' round-off perturbation (if any) added to every
    /// velocity dof (the contact face's included).
    pub fn discretise(
        &self,
        n_axis: usize,
        mass: MassVariant,
        settings: &Settings,
    ) -> Result<Discretisation<BoxMesh>, ParameterError> {
        let (mesh, model) = self.model(n_axis, mass, settings)?;
        let (displacement, mut velocity) = initial_dofs(self, &mesh);
        if let Some(p) = &settings.round_off {
            p.apply(&mut velocity, &[]);
        }
        Ok(Discretisation {
            mesh,
            model,
            displacement,
            velocity,
            conventions: settings.conventions,
            step_perturbation: settings.step_round_off,
        })
    }

    /// The mesh with `n_axis` elements along the axis ([`box_mesh`]) and the model on it with
    /// the mass matrix `mass`, the problem's contact treatment, and the solver plan of
    /// `settings`' step solver and contact operator on this box ([`SolverPlan::for_box`]): no vector of the box's size when the model is matrix-free
    /// ([`Model::of_box_matrix_free`], what a rank of a distributed run builds), which it is
    /// when its step solver is `cg` and the mass has a matrix-free form; assembled
    /// ([`Model::of_box`]) otherwise: the direct solver needs the entries.
    pub fn model(
        &self,
        n_axis: usize,
        mass: MassVariant,
        settings: &Settings,
    ) -> Result<(BoxMesh, Model), ParameterError> {
        settings.validate()?;
        let mesh = box_mesh(self, n_axis)?;
        self.elasticity.validate(mesh.dim())?;
        mesh.check_mass(mass)?;
        let law = ContactLaw::boxed(self.contact, &mesh, &self.elasticity)?;
        let plan = SolverPlan::for_box(
            settings.linear_solver,
            settings.contact_operator,
            mesh.n_dofs(),
        )?;
        let matrix_free = (plan.step == StepSolverKind::Cg)
            .then(|| Model::of_box_matrix_free(&mesh, &self.elasticity, mass, self.obstacle_gap))
            .flatten();
        let model = matrix_free
            .unwrap_or_else(|| Model::of_box(&mesh, &self.elasticity, mass, self.obstacle_gap))
            .with_contact_law(law)
            .with_solver_plan(plan);
        Ok((mesh, model))
    }
}
