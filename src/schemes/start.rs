//! Consistent initial data for a possibly singular mass matrix.
//!
//! With the redistributed mass the contact node carries no inertia: its equation is the static
//! one, `(S U − F + Bᵀλ)_Z = 0` on the massless dofs `Z`, with the contact condition. Given
//! data need not satisfy it (the Dirichlet benchmark starts with `u_0 = ½` but a strained first
//! element), so the massless dofs of `U^0` are replaced by the solution of that static contact
//! problem with the other dofs fixed, which also yields `λ^0`. The initial acceleration solves
//! `M_RR A_R = (F − S U^0 − Bᵀλ^0)_R` on the dofs `R` that carry mass (eq. 32c at `t = 0`);
//! `A_Z = 0` (it never enters `M A`).
//!
//! For the standard mass `Z` is empty, `U^0` is the given data and `λ^0 = 0`.
//!
//! A penalty or Nitsche treatment ([`crate::contact::law`]) makes the force a function of the
//! displacement: the static problem on `Z` is solved with it, and `λ^0` is that force at `U^0`
//! (enters eq. 32c with its force vectors `f_i`).

use super::massless::QuasiStatic;
use crate::error::SolveError;
use crate::linalg::SpdSolver;
use crate::model::{ContactSet, Model};

/// `(U^0, V^0, A^0, λ^0)` consistent with the model's equations at `t = 0`.
#[derive(Debug, Clone, PartialEq)]
pub struct InitialState {
    /// Displacement (massless dofs in static equilibrium).
    pub displacement: Vec<f64>,
    /// Velocity as given.
    pub velocity: Vec<f64>,
    /// Acceleration from eq. (32c) at `t = 0`.
    pub acceleration: Vec<f64>,
    /// Contact multipliers `λ^0 ≤ 0`.
    pub multiplier: Vec<f64>,
}

/// `S U − F` (the internal minus the external force).
pub fn residual_force(model: &Model, u: &[f64], out: &mut [f64]) {
    model.stiffness().mul_into(u, out);
    if let Some(f) = model.load() {
        out.iter_mut().zip(f).for_each(|(o, fi)| *o -= fi);
    }
}

/// Builds the consistent initial state from the given displacement and velocity dofs.
pub fn initial_state(model: &Model, u0: &[f64], v0: &[f64]) -> Result<InitialState, SolveError> {
    let n = model.n_dofs();
    let mut u = u0.to_vec();
    let n_contact = model.contact().map_or(0, ContactSet::len);
    let mut lambda = vec![0.0; n_contact];
    if let Some(mut statics) = QuasiStatic::new(model)? {
        statics.solve(model, 0, &mut u, &mut lambda)?;
    }
    let massless = model.massless_dofs();
    if let Some(c) = model.contact() {
        if let Some(forces) = model.contact_law().forces(c, &u) {
            lambda = forces;
        }
    }

    let mut rhs = vec![0.0; n];
    residual_force(model, &u, &mut rhs);
    rhs.iter_mut().for_each(|r| *r = -*r);
    if let Some(c) = model.contact() {
        for (row, &l) in model.contact_law().rows(c).iter().zip(&lambda) {
            for &(k, coef) in &row.force {
                rhs[k] -= coef * l;
            }
        }
    }
    let with_mass: Vec<usize> = (0..n)
        .filter(|i| massless.binary_search(i).is_err())
        .collect();
    let mut acceleration = vec![0.0; n];
    if !with_mass.is_empty() {
        let m_rr = model.mass().principal_submatrix(&with_mass);
        let solver = SpdSolver::factor(&m_rr, "mass (dofs with inertia)")?;
        let mut a_r: Vec<f64> = with_mass.iter().map(|&i| rhs[i]).collect();
        solver.solve_in_place(&mut a_r);
        for (&i, a) in with_mass.iter().zip(a_r) {
            acceleration[i] = a;
        }
    }
    Ok(InitialState {
        displacement: u,
        velocity: v0.to_vec(),
        acceleration,
        multiplier: lambda,
    })
}
