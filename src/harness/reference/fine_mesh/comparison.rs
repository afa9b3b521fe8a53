//! The distance of a coarse box run to the fine-mesh reference, accumulated step by step.
//!
//! At each coarse step `t_n` (a reference sample: the meshes and time grids are nested) the
//! error `e = P U_H(t_n) − U_ref(t_n)` of the coarse displacement, prolongated exactly into the
//! reference mesh, is measured in
//! * `H`: `‖e‖_H² = eᵀ M e`, `M` the consistent fine mass matrix (`ρ ∫ |e|²`);
//! * `V`: `‖e‖_V² = eᵀ M e + eᵀ S e`, `S` the fine stiffness (`a(e, e)`, equivalent to the H¹
//!   seminorm by Korn's inequality since `e = 0` on `Γ_Dir`), the counterpart of the 1D
//!   paper's full H¹ norm;
//! * the contact force: the total normal force `Σ_i λ_i` (a resultant, comparable across meshes
//!   and mass matrices, where the nodal multipliers are not: their size scales with the
//!   contact element);
//! * the energy (eq. 6): `E_h(t_n) − E_ref(t_n)`.
//!
//! The two displacement norms are evaluated on the coarse mesh from the reference's projections
//! on the run's level ([`crate::harness::run::nested_comparison::projection`]): the same numbers,
//! without the fine mesh.
//!
//! The time norms are `L∞(0, T)` (largest sample) and `L²(0, T)` (trapezoidal rule over the
//! coarse steps), as in the note's Figure 3.

use std::collections::BTreeMap;

use super::cache::ReferenceHistories;
use crate::harness::files::error::Error;
use crate::harness::run::nested_comparison::error_series::{ErrorSeries, Quantity};
use crate::harness::run::nested_comparison::norm_matrices::NormMatrices;
use crate::harness::run::nested_comparison::projection::LevelProjections;
use crate::harness::run::norms::Norm;
use crate::harness::run::{Integration, Observer};

/// Accumulates the errors of one coarse run against the reference.
#[derive(Debug)]
pub struct ReferenceComparison<'r> {
    histories: &'r ReferenceHistories,
    projections: &'r LevelProjections,
    norms: &'r NormMatrices,
    history_stride: usize,
    step: usize,
    series: ErrorSeries,
    force_variation: f64,
    reference_variation: f64,
    last_force: Option<(f64, f64)>,
    scratch: [Vec<f64>; 2],
}

impl<'r> ReferenceComparison<'r> {
    /// A comparison for a run on the level of `projections` (whose coarse norm matrices are
    /// `norms`), the reference's scalar `histories` being sampled `history_stride` times per
    /// step of that level.
    pub fn new(
        histories: &'r ReferenceHistories,
        projections: &'r LevelProjections,
        norms: &'r NormMatrices,
        history_stride: usize,
    ) -> Self {
        let n = projections.dofs;
        Self {
            histories,
            projections,
            norms,
            history_stride,
            step: 0,
            series: ErrorSeries::default(),
            force_variation: 0.0,
            reference_variation: 0.0,
            last_force: None,
            scratch: [vec![0.0; n], vec![0.0; n]],
        }
    }

    /// The error in every norm, by norm.
    pub fn errors(&self) -> BTreeMap<Norm, f64> {
        self.series.errors()
    }

    /// The oscillation indicator `TV(Σλ_h) / TV(Σλ_ref)` over the coarse steps (the 1D
    /// tables' indicator with the reference in place of the exact force); `None` when some
    /// step lacked the force.
    pub fn variation_ratio(&self) -> Option<f64> {
        (self.series.lacking(Quantity::Force) == 0)
            .then(|| self.force_variation / self.reference_variation)
    }
}

/// One sample of a run as the comparison takes it: each quantity may be absent (another code's
/// file), a scheme's state has them all.
#[derive(Debug, Clone, Copy)]
pub struct ComparedSample<'s> {
    /// `U^n`, the level's dofs.
    pub displacement: Option<&'s [f64]>,
    /// `Σ_i λ_i`.
    pub total_force: Option<f64>,
    /// `E_h(t_n)`.
    pub energy: Option<f64>,
}

impl ReferenceComparison<'_> {
    /// Compares the next coarse step `t_n` (called once per step, `n = 0, 1, …`); a quantity
    /// the sample lacks is left out, and its norms are then not computed
    /// ([`ErrorSeries::errors`]). The oscillation indicator needs the force at every step.
    pub fn compare(&mut self, sample: ComparedSample<'_>) {
        let n = self.step;
        self.step += 1;
        let k = n * self.history_stride;
        let h = self.histories;
        let Some(&t) = h.time.get(k) else {
            return;
        };
        let squared = match sample.displacement {
            Some(u) => match self
                .projections
                .squared_errors(n, u, self.norms, &mut self.scratch)
            {
                Some(squared) => Some(squared),
                None => return,
            },
            None => None,
        };
        self.series.push_partial(
            t,
            squared,
            sample.total_force.map(|f| f - h.total_force[k]),
            sample.energy.map(|e| e - h.energy[k]),
        );
        match sample.total_force {
            Some(force) => {
                if let Some((previous, previous_reference)) = self.last_force {
                    self.force_variation += (force - previous).abs();
                    self.reference_variation += (h.total_force[k] - previous_reference).abs();
                }
                self.last_force = Some((force, h.total_force[k]));
            }
            None => self.last_force = None,
        }
    }

    /// The series of errors compared so far.
    pub fn series(&self) -> &ErrorSeries {
        &self.series
    }
}

impl Observer for ReferenceComparison<'_> {
    /// Compares the state at the next coarse step `t_n` ([`ReferenceComparison::compare`]).
    fn observe(&mut self, state: &Integration<'_>) -> Result<(), Error> {
        self.compare(ComparedSample {
            displacement: Some(state.displacement()),
            total_force: Some(state.multiplier().value.iter().sum()),
            energy: Some(state.energy().value),
        });
        Ok(())
    }
}
