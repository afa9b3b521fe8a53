//! The time series of a run's errors against the reference, in every norm of a 2D/3D study (the
//! displacement's `H` and `V` norms of [`super::projection::NormMatrices`], the total contact
//! force, the energy), and their `L∞(0, T)` and `L²(0, T)` norms.

use std::collections::BTreeMap;

use crate::harness::run::norms::{Norm, TimeSeriesNorm};

/// The time series of a run's errors in every norm.
#[derive(Debug, Clone, Default)]
pub struct ErrorSeries {
    u_h: TimeSeriesNorm,
    u_v: TimeSeriesNorm,
    force: TimeSeriesNorm,
    energy: TimeSeriesNorm,
}

impl ErrorSeries {
    /// Adds the sample at `time`: the squared displacement errors `h2`, `v2` and the errors of
    /// the total contact force and of the energy.
    pub fn push(&mut self, time: f64, (h2, v2): (f64, f64), force: f64, energy: f64) {
        self.u_h.push(time, h2.max(0.0).sqrt());
        self.u_v.push(time, v2.max(0.0).sqrt());
        self.force.push(time, force);
        self.energy.push(time, energy);
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
}
