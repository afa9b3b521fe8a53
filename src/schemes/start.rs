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

use crate::contact::law::{ConstraintRow, SparseVector};
use crate::contact::ContactStep;
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
    let massless = model.massless_dofs();
    if !massless.is_empty() {
        equilibrate_massless(model, massless, &mut u, &mut lambda)?;
    }
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

/// Solves `S_ZZ u_Z = (F − S_ZR u_R)_Z − (Σ λ_i f_i)_Z` with the contact condition of every
/// constraint whose force acts on `Z`, in place. A constraint value `m_iᵀu + g_i` is split
/// into its `Z` part and the fixed `R` part, which joins the gap.
fn equilibrate_massless(
    model: &Model,
    massless: &[usize],
    u: &mut [f64],
    lambda: &mut [f64],
) -> Result<(), SolveError> {
    let n = model.n_dofs();
    let s_zz = model.stiffness().principal_submatrix(massless);
    let solver = SpdSolver::factor(&s_zz, "stiffness on the massless dofs")?;
    let mut without_z = u.to_vec();
    for &z in massless {
        without_z[z] = 0.0;
    }
    let mut r = vec![0.0; n];
    residual_force(model, &without_z, &mut r);
    let mut u_z: Vec<f64> = massless.iter().map(|&z| -r[z]).collect();
    solver.solve_in_place(&mut u_z);

    if let Some(contact) = model.contact() {
        let local_part = |v: &[(usize, f64)]| -> SparseVector {
            v.iter()
                .filter_map(|&(k, c)| massless.binary_search(&k).ok().map(|z| (z, c)))
                .collect()
        };
        let mut local: Vec<usize> = Vec::new();
        let mut set = ContactSet {
            dofs: Vec::new(),
            gaps: Vec::new(),
        };
        let mut rows = Vec::new();
        for (k, row) in model.contact_law().rows(contact).into_iter().enumerate() {
            let force = local_part(&row.force);
            let Some(&(z, _)) = force.first() else {
                continue;
            };
            let fixed: f64 = row
                .measure
                .iter()
                .filter(|(d, _)| massless.binary_search(d).is_err())
                .map(|&(d, c)| c * u[d])
                .sum();
            local.push(k);
            set.dofs.push(z);
            set.gaps.push(if fixed == 0.0 {
                contact.gaps[k]
            } else {
                contact.gaps[k] + fixed
            });
            rows.push(ConstraintRow {
                measure: local_part(&row.measure),
                force,
                compliance: row.compliance,
            });
        }
        if !local.is_empty() {
            let mut step = ContactStep::new(&set, &rows, &solver, massless.len())?;
            let mut lambda_z = vec![0.0; set.len()];
            step.enforce(0, &mut u_z, |_, g| g, &mut lambda_z)?;
            for (&k, l) in local.iter().zip(lambda_z) {
                lambda[k] = l;
            }
        }
    }
    for (&z, v) in massless.iter().zip(u_z) {
        u[z] = v;
    }
    Ok(())
}
