//! The observers of a run against an exact solution (the 1D bars): the error norms of the
//! paper (§5), the multiplier's total variation, and the histories and snapshots the figures
//! draw. Each does one thing and is built only when a run asks for it.

use std::collections::{BTreeMap, BTreeSet};

use super::{ContactHistory, EnergyHistory, FieldSnapshot, MultiplierVariation, PointHistory};
use crate::engine::error::StateField;
use crate::engine::exact::ExactSolution;
use crate::engine::fem::Bar1d;
use crate::engine::schemes::Integration;
use crate::harness::files::error::Error;
use crate::harness::run::driver::{finite, Observer, SnapshotTimes};
use crate::harness::run::norms::{Norm, SpaceErrorIntegrator, TimeSeriesNorm};

/// Adds the sample `value` of `state` to `norm`, both the sample and the norm so far finite
/// ([`finite`]): a norm that overflows stops the run as `quantity` instead of being reported.
fn push_finite(
    norm: &mut TimeSeriesNorm,
    state: &Integration<'_>,
    quantity: StateField,
    time: f64,
    value: f64,
) -> Result<(), Error> {
    norm.push(time, finite(state, quantity, value)?);
    finite(state, quantity, norm.l2()).map(|_| ())
}

/// The space norms of the displacement error `u_h(t_n) − u(t_n)` (L² and H¹ in space),
/// accumulated in time as the `u_*_H` and `u_*_V` norms.
pub struct DisplacementErrors<'a> {
    bar: &'a Bar1d,
    exact: &'a dyn ExactSolution,
    space: SpaceErrorIntegrator,
    l2: TimeSeriesNorm,
    h1: TimeSeriesNorm,
}

impl<'a> DisplacementErrors<'a> {
    /// The observer of `bar`'s displacement against `exact`.
    pub fn new(bar: &'a Bar1d, exact: &'a dyn ExactSolution) -> Self {
        Self {
            bar,
            exact,
            space: SpaceErrorIntegrator::new(),
            l2: TimeSeriesNorm::default(),
            h1: TimeSeriesNorm::default(),
        }
    }

    /// Space-norm evaluations so far.
    pub fn evaluations(&self) -> usize {
        self.space.evaluations()
    }
}

impl Observer for DisplacementErrors<'_> {
    fn observe(&mut self, state: &Integration<'_>) -> Result<(), Error> {
        let t = state.time();
        let e = self
            .space
            .errors(self.bar, state.displacement(), self.exact, t);
        push_finite(&mut self.l2, state, StateField::DisplacementError, t, e.l2)?;
        push_finite(&mut self.h1, state, StateField::DisplacementError, t, e.h1)
    }
}

/// The contact multiplier's error `λ_h − λ` in time and the total variations of `λ_h` and `λ`
/// (the oscillation indicator of the tables).
pub struct MultiplierErrors<'a> {
    exact: &'a dyn ExactSolution,
    error: TimeSeriesNorm,
    variation: MultiplierVariation,
    last: Option<(f64, f64, f64)>,
}

impl<'a> MultiplierErrors<'a> {
    /// The observer of the first multiplier against `exact`'s.
    pub fn new(exact: &'a dyn ExactSolution) -> Self {
        Self {
            exact,
            error: TimeSeriesNorm::default(),
            variation: MultiplierVariation::default(),
            last: None,
        }
    }

    /// The total variations, once a state was observed.
    pub fn variation(&self) -> Option<MultiplierVariation> {
        self.last.map(|_| self.variation)
    }
}

impl Observer for MultiplierErrors<'_> {
    fn observe(&mut self, state: &Integration<'_>) -> Result<(), Error> {
        let m = state.multiplier();
        let lambda_h = m.value.first().copied().unwrap_or(0.0);
        let lambda = self.exact.contact_multiplier(m.time);
        let error = lambda_h - lambda;
        push_finite(
            &mut self.error,
            state,
            StateField::MultiplierError,
            m.time,
            error,
        )?;
        match self.last {
            Some((t0, _, _)) if m.time <= t0 => {}
            Some((_, h0, e0)) => {
                self.variation.discrete += (lambda_h - h0).abs();
                self.variation.exact += (lambda - e0).abs();
                self.last = Some((m.time, lambda_h, lambda));
            }
            None => self.last = Some((m.time, lambda_h, lambda)),
        }
        self.variation.max_abs = self.variation.max_abs.max(lambda_h.abs());
        finite(state, StateField::Multiplier, self.variation.discrete).map(|_| ())
    }
}

/// The energy error `E_h − E` in time.
pub struct EnergyErrors<'a> {
    exact: &'a dyn ExactSolution,
    error: TimeSeriesNorm,
}

impl<'a> EnergyErrors<'a> {
    /// The observer of the discrete energy against `exact`'s.
    pub fn new(exact: &'a dyn ExactSolution) -> Self {
        Self {
            exact,
            error: TimeSeriesNorm::default(),
        }
    }
}

impl Observer for EnergyErrors<'_> {
    fn observe(&mut self, state: &Integration<'_>) -> Result<(), Error> {
        let e = state.energy();
        let value = finite(state, StateField::Energy, e.value)?;
        let error = value - self.exact.energy(e.time);
        push_finite(
            &mut self.error,
            state,
            StateField::EnergyError,
            e.time,
            error,
        )
    }
}

/// The error observers a set of norms needs, built only when a requested norm (or, for the
/// multiplier, its variation) reads them: the one choice of every run, internal or replayed.
pub struct ErrorObservers<'a> {
    /// The displacement norms' observer.
    pub displacement: Option<DisplacementErrors<'a>>,
    /// The multiplier norm's observer (also the oscillation measure).
    pub multiplier: Option<MultiplierErrors<'a>>,
    /// The energy norms' observer.
    pub energy: Option<EnergyErrors<'a>>,
}

impl<'a> ErrorObservers<'a> {
    /// The observers of `norms`; the multiplier's also when `multiplier_anyway` (a run that
    /// records the contact history reports the multiplier's variation).
    pub fn new(
        bar: &'a Bar1d,
        exact: &'a dyn ExactSolution,
        norms: &BTreeSet<Norm>,
        multiplier_anyway: bool,
    ) -> Self {
        let has = |n: &[Norm]| n.iter().any(|x| norms.contains(x));
        Self {
            displacement: has(&[
                Norm::DisplacementLinfH,
                Norm::DisplacementL2H,
                Norm::DisplacementLinfV,
                Norm::DisplacementL2V,
            ])
            .then(|| DisplacementErrors::new(bar, exact)),
            multiplier: (has(&[Norm::MultiplierL2]) || multiplier_anyway)
                .then(|| MultiplierErrors::new(exact)),
            energy: has(&[Norm::EnergyLinf, Norm::EnergyL2]).then(|| EnergyErrors::new(exact)),
        }
    }

    /// The observers built, to hand to a run.
    pub fn observers(&mut self) -> impl Iterator<Item = &mut dyn Observer> + use<'_, 'a> {
        let d = self.displacement.as_mut().map(|o| o as &mut dyn Observer);
        let m = self.multiplier.as_mut().map(|o| o as &mut dyn Observer);
        let e = self.energy.as_mut().map(|o| o as &mut dyn Observer);
        d.into_iter().chain(m).chain(e)
    }

    /// The norms `norms` from what the observers accumulated; a norm whose observer was not
    /// built is absent from `norms` by construction.
    pub fn norms(&self, norms: &BTreeSet<Norm>) -> BTreeMap<Norm, f64> {
        let zero = TimeSeriesNorm::default();
        let (l2, h1) = self
            .displacement
            .as_ref()
            .map_or((&zero, &zero), |d| (&d.l2, &d.h1));
        let lambda = self.multiplier.as_ref().map_or(&zero, |m| &m.error);
        let e = self.energy.as_ref().map_or(&zero, |e| &e.error);
        norms
            .iter()
            .map(|&n| {
                let v = match n {
                    Norm::DisplacementLinfH => l2.linf(),
                    Norm::DisplacementL2H => l2.l2(),
                    Norm::DisplacementLinfV => h1.linf(),
                    Norm::DisplacementL2V => h1.l2(),
                    Norm::MultiplierL2 => lambda.l2(),
                    Norm::EnergyLinf => e.linf(),
                    Norm::EnergyL2 => e.l2(),
                };
                (n, v)
            })
            .collect()
    }
}

/// The contact node's displacement and multiplier with the exact ones.
pub struct ContactRecorder<'a> {
    bar: &'a Bar1d,
    exact: &'a dyn ExactSolution,
    /// The history so far.
    pub history: ContactHistory,
}

impl<'a> ContactRecorder<'a> {
    /// An empty history of `bar`'s contact node.
    pub fn new(bar: &'a Bar1d, exact: &'a dyn ExactSolution) -> Self {
        Self {
            bar,
            exact,
            history: ContactHistory::default(),
        }
    }
}

impl Observer for ContactRecorder<'_> {
    fn observe(&mut self, state: &Integration<'_>) -> Result<(), Error> {
        let t = state.time();
        let m = state.multiplier();
        let c = &mut self.history;
        c.time.push(t);
        c.displacement
            .push(self.bar.nodal_value(state.displacement(), 0));
        c.displacement_exact.push(self.exact.eval(0.0, t).u);
        if c.multiplier_time.last().is_none_or(|&last| m.time > last) {
            c.multiplier_time.push(m.time);
            c.multiplier.push(m.value.first().copied().unwrap_or(0.0));
            c.multiplier_exact
                .push(self.exact.contact_multiplier(m.time));
        }
        Ok(())
    }
}

/// The discrete energy with the exact one, once per energy time.
pub struct EnergyRecorder<'a> {
    exact: &'a dyn ExactSolution,
    /// The history so far.
    pub history: EnergyHistory,
}

impl<'a> EnergyRecorder<'a> {
    /// An empty energy history.
    pub fn new(exact: &'a dyn ExactSolution) -> Self {
        Self {
            exact,
            history: EnergyHistory::default(),
        }
    }
}

impl Observer for EnergyRecorder<'_> {
    fn observe(&mut self, state: &Integration<'_>) -> Result<(), Error> {
        let e = state.energy();
        let h = &mut self.history;
        if h.time.last().is_none_or(|&last| e.time > last) {
            h.time.push(e.time);
            h.energy.push(finite(state, StateField::Energy, e.value)?);
            h.energy_exact.push(self.exact.energy(e.time));
        }
        Ok(())
    }
}

/// The displacement at fixed positions with the exact one.
pub struct PointRecorder<'a> {
    bar: &'a Bar1d,
    exact: &'a dyn ExactSolution,
    /// The history so far.
    pub history: PointHistory,
}

impl<'a> PointRecorder<'a> {
    /// An empty history at the positions `x`.
    pub fn new(bar: &'a Bar1d, exact: &'a dyn ExactSolution, x: &[f64]) -> Self {
        Self {
            bar,
            exact,
            history: PointHistory {
                x: x.to_vec(),
                displacement: vec![Vec::new(); x.len()],
                displacement_exact: vec![Vec::new(); x.len()],
                ..PointHistory::default()
            },
        }
    }
}

impl Observer for PointRecorder<'_> {
    fn observe(&mut self, state: &Integration<'_>) -> Result<(), Error> {
        let t = state.time();
        let p = &mut self.history;
        p.time.push(t);
        for (k, &x) in p.x.iter().enumerate() {
            let u = self.bar.value_at(state.displacement(), x);
            p.displacement[k].push(finite(state, StateField::Displacement, u)?);
            p.displacement_exact[k].push(self.exact.eval(x, t).u);
        }
        Ok(())
    }
}

/// The whole displacement and strain fields at the steps nearest to requested times.
pub struct FieldRecorder<'a> {
    bar: &'a Bar1d,
    exact: &'a dyn ExactSolution,
    pending: SnapshotTimes,
    /// The snapshots so far, in time order.
    pub snapshots: Vec<FieldSnapshot>,
}

impl<'a> FieldRecorder<'a> {
    /// Snapshots at the steps nearest to each of `times`.
    pub fn new(bar: &'a Bar1d, exact: &'a dyn ExactSolution, times: &[f64]) -> Self {
        Self {
            bar,
            exact,
            pending: SnapshotTimes::new(times),
            snapshots: Vec::new(),
        }
    }
}

impl Observer for FieldRecorder<'_> {
    fn observe(&mut self, state: &Integration<'_>) -> Result<(), Error> {
        let t = state.time();
        while let Some(wanted) = self.pending.next_due(state) {
            let u = state.displacement();
            let bar = self.bar;
            let nodes: Vec<f64> = (0..=bar.nx()).map(|i| bar.node(i)).collect();
            let mids: Vec<f64> = nodes.windows(2).map(|w| 0.5 * (w[0] + w[1])).collect();
            let strain: Vec<f64> = (0..bar.nx())
                .map(|e| (bar.nodal_value(u, e + 1) - bar.nodal_value(u, e)) / bar.h())
                .collect();
            if let Some(&bad) = strain.iter().find(|v| !v.is_finite()) {
                finite(state, StateField::Strain, bad)?;
            }
            self.snapshots.push(FieldSnapshot {
                requested_time: wanted,
                time: t,
                displacement: (0..=bar.nx()).map(|i| bar.nodal_value(u, i)).collect(),
                displacement_exact: nodes.iter().map(|&x| self.exact.eval(x, t).u).collect(),
                strain,
                strain_exact: mids.iter().map(|&x| self.exact.eval(x, t).ux).collect(),
                x: nodes,
                x_mid: mids,
            });
        }
        Ok(())
    }
}
