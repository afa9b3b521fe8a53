//! The distance of a coarse box run to the fine-mesh reference, accumulated step by step.
//!
//! At each coarse step `t_n` (a reference sample: the meshes and time grids are nested) the
//! coarse displacement is prolongated to the fine mesh and `e = P U_H(t_n) − U_ref(t_n)` is
//! measured in
//! * `H`: `‖e‖_H² = eᵀ M e`, `M` the consistent fine mass matrix (`ρ ∫ |e|²`);
//! * `V`: `‖e‖_V² = eᵀ M e + eᵀ S e`, `S` the fine stiffness (`a(e, e)`, equivalent to the H¹
//!   seminorm by Korn's inequality since `e = 0` on `Γ_Dir`), the counterpart of the 1D
//!   paper's full H¹ norm;
//! * the contact force: the total normal force `Σ_i λ_i` (a resultant, comparable across meshes
//!   and mass matrices, where the nodal multipliers are not: their size scales with the
//!   contact element);
//! * the energy (eq. 6): `E_h(t_n) − E_ref(t_n)`.
//!
//! The time norms are `L∞(0, T)` (largest sample) and `L²(0, T)` (trapezoidal rule over the
//! coarse steps), as in the note's Figure 3.

use std::collections::BTreeMap;

use super::reference::Reference;
use crate::engine::fem::{Prolongation, SymmetricMatrix};
use crate::engine::schemes::TimeIntegrator;
use crate::harness::error::Error;
use crate::harness::norms::{Norm, TimeSeriesNorm};
use crate::harness::run::Observer;

/// The fine-mesh matrices of the norms, assembled once per study.
#[derive(Debug, Clone)]
pub struct FineNorms {
    /// Consistent mass (the `H` inner product).
    pub mass: SymmetricMatrix,
    /// Stiffness (`a(·, ·)`).
    pub stiffness: SymmetricMatrix,
}

/// Accumulates the errors of one coarse run against the reference.
#[derive(Debug)]
pub struct ReferenceComparison<'r> {
    reference: &'r Reference,
    norms: &'r FineNorms,
    prolongation: &'r Prolongation,
    level: usize,
    sample_level: usize,
    step: usize,
    u_h: TimeSeriesNorm,
    u_v: TimeSeriesNorm,
    force: TimeSeriesNorm,
    energy: TimeSeriesNorm,
    force_variation: f64,
    reference_variation: f64,
    last_force: Option<(f64, f64)>,
    fine: Vec<f64>,
    scratch: Vec<f64>,
}

impl<'r> ReferenceComparison<'r> {
    /// A comparison for a run on `level` elements along the axis, the reference being sampled
    /// at the time step of the level `sample_level` (`Δt ∝ h`): step `s` of the run is sample
    /// `s · sample_level / level` when that is an integer, and is skipped otherwise (runs finer
    /// than the samples are compared at the sample times only).
    pub fn new(
        reference: &'r Reference,
        norms: &'r FineNorms,
        prolongation: &'r Prolongation,
        level: usize,
        sample_level: usize,
    ) -> Self {
        let n = reference.histories.dofs;
        Self {
            reference,
            norms,
            prolongation,
            level,
            sample_level,
            step: 0,
            u_h: TimeSeriesNorm::default(),
            u_v: TimeSeriesNorm::default(),
            force: TimeSeriesNorm::default(),
            energy: TimeSeriesNorm::default(),
            force_variation: 0.0,
            reference_variation: 0.0,
            last_force: None,
            fine: vec![0.0; n],
            scratch: vec![0.0; n],
        }
    }

    /// The error in every norm, by norm.
    pub fn errors(&self) -> BTreeMap<Norm, f64> {
        BTreeMap::from([
            (Norm::DisplacementLinfH, self.u_h.linf()),
            (Norm::DisplacementL2H, self.u_h.l2()),
            (Norm::DisplacementLinfV, self.u_v.linf()),
            (Norm::DisplacementL2V, self.u_v.l2()),
            (Norm::MultiplierL2, self.force.l2()),
            (Norm::EnergyLinf, self.energy.linf()),
            (Norm::EnergyL2, self.energy.l2()),
        ])
    }

    /// The oscillation indicator `TV(Σλ_h) / TV(Σλ_ref)` over the coarse steps (the 1D
    /// tables' indicator with the reference in place of the exact force).
    pub fn variation_ratio(&self) -> f64 {
        self.force_variation / self.reference_variation
    }
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

impl Observer for ReferenceComparison<'_> {
    /// Compares the state at the next coarse step `t_n` (called once per step,
    /// `n = 0, 1, …`).
    fn observe(&mut self, state: &dyn TimeIntegrator) -> Result<(), Error> {
        let scaled = self.step * self.sample_level;
        self.step += 1;
        if scaled % self.level != 0 {
            return Ok(());
        }
        let k = scaled / self.level;
        let Some(&t) = self.reference.histories.time.get(k) else {
            return Ok(());
        };
        self.prolongation
            .apply_into(state.displacement(), &mut self.fine);
        for (e, r) in self.fine.iter_mut().zip(self.reference.displacement_at(k)) {
            *e -= r;
        }
        self.norms.mass.mul_into(&self.fine, &mut self.scratch);
        let h2 = dot(&self.fine, &self.scratch);
        self.norms.stiffness.mul_into(&self.fine, &mut self.scratch);
        let a2 = dot(&self.fine, &self.scratch);
        self.u_h.push(t, h2.max(0.0).sqrt());
        self.u_v.push(t, (h2 + a2).max(0.0).sqrt());
        let h = &self.reference.histories;
        let force: f64 = state.multiplier().value.iter().sum();
        self.force.push(t, force - h.total_force[k]);
        self.energy.push(t, state.energy().value - h.energy[k]);
        if let Some((previous, previous_reference)) = self.last_force {
            self.force_variation += (force - previous).abs();
            self.reference_variation += (h.total_force[k] - previous_reference).abs();
        }
        self.last_force = Some((force, h.total_force[k]));
        Ok(())
    }
}
