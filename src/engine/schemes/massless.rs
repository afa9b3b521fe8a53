//! The quasi-static equation of the massless dofs.
//!
//! On the dofs `Z` where `M` has zero rows (`ker M`, see [`Model::massless_dofs`]) the equation
//! `M A + S U = F − Bᵀλ` reduces to the static one
//! `S_ZZ U_Z = (F − S_ZR U_R)_Z − (Bᵀλ)_Z`, `0 ≤ U_c + g_c ⟂ λ_c ≤ 0` for the contact dofs
//! `c ∈ Z` (1D paper §3.2: "the node at the contact boundary evolves in a quasi-static way").
//! Given the dofs with mass `U_R`, this is a small complementarity problem on the Delassus
//! operator of `S_ZZ`, solved with the crate's contact solvers. With a penalty or Nitsche
//! treatment ([`crate::engine::contact::law`]) each constraint `m_iᵀU + g_i`, force `f_i`, is split
//! into its `Z` part and the fixed `R` part `Σ_{d∈R} m_{i,d} U_d`, which joins the gap. It is used for consistent
//! initial data ([`super::initial_state`]) and at every step of the explicit scheme
//! ([`super::ExplicitNewmark`]).

use super::{residual_force, StepStatistics};
use crate::engine::contact::law::{ConstraintRow, SparseVector};
use crate::engine::contact::ContactStep;
use crate::engine::error::SolveError;
use crate::engine::linalg::{SolveCounts, StepSolver};
use crate::engine::model::{ContactSet, Model};

/// `S_ZZ` factorised, with the contact correction of the contact dofs in `Z`.
#[derive(Debug)]
pub struct QuasiStatic {
    massless: Vec<usize>,
    solver: StepSolver,
    /// The contact constraints whose force acts on `Z`: their index in the model's set.
    local: Vec<usize>,
    /// The part of each local constraint's measure on the dofs with mass.
    fixed: Vec<SparseVector>,
    contact: Option<ContactStep>,
    without_z: Vec<f64>,
    residual: Vec<f64>,
    u_z: Vec<f64>,
    guess_z: Vec<f64>,
    lambda_z: Vec<f64>,
}

impl QuasiStatic {
    /// Factorises `S_ZZ` and prepares its Delassus operator; `None` when `M` has no zero row.
    pub fn new(model: &Model) -> Result<Option<Self>, SolveError> {
        let massless = model.massless_dofs().to_vec();
        if massless.is_empty() {
            return Ok(None);
        }
        let s_zz = model.stiffness().principal_submatrix(&massless);
        let solver = StepSolver::new(
            s_zz,
            model.solver_plan().step,
            "stiffness on the massless dofs",
        )?;
        let on_z = |v: &[(usize, f64)]| -> SparseVector {
            v.iter()
                .filter_map(|&(k, c)| massless.binary_search(&k).ok().map(|z| (z, c)))
                .collect()
        };
        let mut local = Vec::new();
        let mut fixed = Vec::new();
        let mut set = ContactSet {
            dofs: Vec::new(),
            gaps: Vec::new(),
        };
        let mut rows = Vec::new();
        if let Some(c) = model.contact() {
            for (k, row) in model.contact_law().rows(c).into_iter().enumerate() {
                let force = on_z(&row.force);
                let Some(&(z, _)) = force.first() else {
                    continue;
                };
                local.push(k);
                fixed.push(
                    row.measure
                        .iter()
                        .filter(|(d, _)| massless.binary_search(d).is_err())
                        .copied()
                        .collect(),
                );
                set.dofs.push(z);
                set.gaps.push(c.gaps[k]);
                rows.push(ConstraintRow {
                    measure: on_z(&row.measure),
                    force,
                    compliance: row.compliance,
                });
            }
        }
        let contact = if local.is_empty() {
            None
        } else {
            Some(ContactStep::new(
                &set,
                &rows,
                &solver,
                massless.len(),
                model.solver_plan().contact,
            )?)
        };
        let n = model.n_dofs();
        Ok(Some(Self {
            solver,
            contact,
            without_z: vec![0.0; n],
            residual: vec![0.0; n],
            u_z: vec![0.0; massless.len()],
            guess_z: vec![0.0; massless.len()],
            lambda_z: vec![0.0; local.len()],
            local,
            fixed,
            massless,
        }))
    }

    /// Replaces `U_Z` by the solution of the static contact problem with `U_R` as given, and
    /// writes the multipliers of the contact dofs in `Z` into `lambda` (the others untouched).
    pub fn solve(
        &mut self,
        model: &Model,
        step: usize,
        u: &mut [f64],
        lambda: &mut [f64],
    ) -> Result<(), SolveError> {
        self.without_z.copy_from_slice(u);
        for &z in &self.massless {
            self.without_z[z] = 0.0;
        }
        residual_force(model, &self.without_z, &mut self.residual);
        for ((uz, gz), &z) in self
            .u_z
            .iter_mut()
            .zip(&mut self.guess_z)
            .zip(&self.massless)
        {
            *uz = -self.residual[z];
            *gz = u[z];
        }
        self.solver.solve(&mut self.u_z, &self.guess_z)?;
        if let Some(contact) = self.contact.as_mut() {
            let fixed: Vec<f64> = self
                .fixed
                .iter()
                .map(|part| part.iter().map(|&(d, c)| c * u[d]).sum())
                .collect();
            contact.enforce(step, &mut self.u_z, |i, g| g + fixed[i], &mut self.lambda_z)?;
            for (&k, &l) in self.local.iter().zip(&self.lambda_z) {
                lambda[k] = l;
            }
        }
        for (&z, &v) in self.massless.iter().zip(&self.u_z) {
            u[z] = v;
        }
        Ok(())
    }

    /// The static contact solves so far and their largest violation (no step solves: `S_ZZ`'s
    /// are not counted).
    pub fn statistics(&self) -> StepStatistics {
        StepStatistics::of(SolveCounts::default(), &self.contact)
    }
}
