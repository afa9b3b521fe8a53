//! The time series of a run's errors against the reference, in every norm of a 2D/3D study (the
//! displacement's `H` and `V` norms of [`super::norm_matrices::NormMatrices`], the total contact
//! force, the energy), and their `L∞(0, T)` and `L²(0, T)` norms.
//!
//! A sample may lack a quantity (another code's file that holds its fields at some times only,
//! or no energy): the norms of a quantity some sample lacks are then not computed, since a time
//! norm over part of the samples is not the norm the study fits.

use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};

use crate::harness::run::norms::{Norm, TimeSeriesNorm};

/// The displacement's error at one sample, in both norms.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct DisplacementError {
    /// `t_n`.
    pub time: f64,
    /// `‖e‖_H`.
    pub h: f64,
    /// `‖e‖_V`.
    pub v: f64,
}

/// The quantities of a series, each with the samples that lacked it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum Quantity {
    /// The displacement field (the four `u` norms).
    Displacement,
    /// The total contact force (`lambda_L2`).
    Force,
    /// The energy (`energy_Linf`, `energy_L2`).
    Energy,
}

impl Quantity {
    /// The quantity whose error `norm` measures.
    pub fn of(norm: Norm) -> Self {
        match norm {
            Norm::MultiplierL2 => Quantity::Force,
            Norm::EnergyLinf | Norm::EnergyL2 => Quantity::Energy,
            _ => Quantity::Displacement,
        }
    }
}

/// The time series of a run's errors in every norm.
#[derive(Debug, Clone, Default)]
pub struct ErrorSeries {
    u_h: TimeSeriesNorm,
    u_v: TimeSeriesNorm,
    force: TimeSeriesNorm,
    energy: TimeSeriesNorm,
    /// Per quantity, the samples that lacked it.
    lacking: BTreeMap<Quantity, usize>,
    /// The displacement errors sample by sample: what is reported when some sample lacks the
    /// displacement (its time norms are then not computed).
    displacement_at: Vec<DisplacementError>,
}

impl ErrorSeries {
    /// Adds the sample at `time`: the squared displacement errors `h2`, `v2` and the errors of
    /// the total contact force and of the energy.
    pub fn push(&mut self, time: f64, squared: (f64, f64), force: f64, energy: f64) {
        self.push_partial(time, Some(squared), Some(force), Some(energy));
    }

    /// [`Self::push`] of a sample that may lack some quantities.
    pub fn push_partial(
        &mut self,
        time: f64,
        squared: Option<(f64, f64)>,
        force: Option<f64>,
        energy: Option<f64>,
    ) {
        match squared {
            Some((h2, v2)) => {
                let (h, v) = (h2.max(0.0).sqrt(), v2.max(0.0).sqrt());
                self.u_h.push(time, h);
                self.u_v.push(time, v);
                self.displacement_at.push(DisplacementError { time, h, v });
            }
            None => self.lack(Quantity::Displacement),
        }
        match force {
            Some(f) => self.force.push(time, f),
            None => self.lack(Quantity::Force),
        }
        match energy {
            Some(e) => self.energy.push(time, e),
            None => self.lack(Quantity::Energy),
        }
    }

    fn lack(&mut self, quantity: Quantity) {
        *self.lacking.entry(quantity).or_default() += 1;
    }

    /// How many samples lacked `quantity`.
    pub fn lacking(&self, quantity: Quantity) -> usize {
        self.lacking.get(&quantity).copied().unwrap_or(0)
    }

    /// The displacement errors at the samples that had the field.
    pub fn displacement_errors(&self) -> &[DisplacementError] {
        &self.displacement_at
    }

    /// The error in every norm whose quantity every sample had, by norm.
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
        .into_iter()
        .filter(|(n, _)| self.lacking(Quantity::of(*n)) == 0)
        .collect()
    }
}
