//! Another code's run replayed as a time integrator ([`Replay`]): each sample of the file is a
//! state that the harness's own observers (`crate::harness::run::exact`) take in exactly as
//! they take in a scheme's, so the norms of a file are computed by the code that computes the
//! harness's runs, over the file's own sample times. A sample without `λ` (version 2) is left
//! out of the multiplier's observer; a file with fields at some samples only has its
//! displacement errors at those samples measured one by one.

use std::collections::{BTreeMap, BTreeSet};
use std::time::Instant;

use serde::{Deserialize, Serialize};

use super::format::ExternalRun;
use crate::engine::error::{SolveError, StateField};
use crate::engine::exact::ExactSolution;
use crate::engine::fem::Bar1d;
use crate::engine::model::Model;
use crate::engine::schemes::{Integration, SchemeState, StepStatistics, TimeIntegrator, Timed};
use crate::harness::files::error::Error;
use crate::harness::run::exact::ErrorObservers;
use crate::harness::run::nested_comparison::error_series::DisplacementError;
use crate::harness::run::norms::{Norm, SpaceErrorIntegrator, TimeSeriesNorm};
use crate::harness::run::{finite, MultiplierVariation, Observer};

/// Where a replay's energy, the one the energy norms measure, comes from.
#[derive(Debug, Clone, Copy)]
pub enum EnergySource<'a> {
    /// The file's `energy` at its `energy_time` (version 1, and GetFEM's contact traces).
    Reported,
    /// The harness's `E_h(Uⁿ, Vⁿ) = ½ VⁿᵀM Vⁿ + ½ UⁿᵀS Uⁿ − FᵀUⁿ` (plus the contact term of a
    /// penalty or Nitsche treatment; 1D paper eq. 31, [`Model::energy`]) of the file's fields
    /// at the sample's time, with the model of the mass the file declares (version 2).
    Fields(&'a Model),
    /// None: no energy norm is asked for (version 2 without a mass, or without both fields at
    /// every sample).
    Absent,
}

/// The samples of a run file as the states of a time integrator on the scene's bar: sample `n`
/// is state `n` at the file's time `t_n`; the fields are the file's nodal values (without a
/// clamped end's node, as the bar's dofs), the multiplier and the energy are the file's with
/// the times they approximate. The replay reads the file; the state it moves from sample to
/// sample is the caller's ([`Replay::start`]).
pub struct Replay<'a> {
    run: &'a ExternalRun,
    /// The bar's dofs: the nodes less a clamped end.
    dofs: usize,
    /// What [`TimeIntegrator::energy`] reports.
    energy: EnergySource<'a>,
}

impl<'a> Replay<'a> {
    /// The replay of `run` on `bar` (the scene's bar with the file's `NX`), its energy from
    /// `energy`.
    pub fn new(run: &'a ExternalRun, bar: &Bar1d, energy: EnergySource<'a>) -> Self {
        Self {
            run,
            dofs: bar.n_dofs(),
            energy,
        }
    }

    /// The state at the file's first sample.
    pub fn start(&self) -> SchemeState {
        let mut state = SchemeState::sample(0, 0.0, 0.0, (Vec::new(), Vec::new()));
        self.load(0, &mut state);
        state
    }

    /// Copies sample `n` of the file into `state`: its index and time, the spacing to the
    /// previous sample (to the next one at the first sample), the file's nodal displacements
    /// and velocities (empty when the file has none), its multiplier (none when the file has
    /// none) with the file's `lambda_time` when it gives one.
    fn load(&self, n: usize, state: &mut SchemeState) {
        let (run, dofs) = (self.run, self.dofs);
        let row = |field| {
            run.row(field, n)
                .map_or_else(Vec::new, |r| r[..dofs].to_vec())
        };
        state.u = row(&run.displacement);
        state.v = row(&run.velocity);
        state.lambda = run.lambda_at(n).into_iter().collect();
        let (t, k) = (&run.time, n.max(1));
        state.dt = t[k] - t[k - 1];
        state.set_clock(n, t[n]);
        state.reported = run.lambda_time.as_ref().map(|times| Timed {
            time: times[n],
            value: state.lambda.clone(),
        });
    }

    /// The sample of `state`'s entry of `times` (`lambda_time`, `energy_time`) when the file
    /// gives them, else the sample's time.
    fn reported_time(&self, times: &Option<Vec<f64>>, state: &SchemeState) -> f64 {
        times
            .as_ref()
            .map_or(state.time(), |t| t[state.step_index()])
    }
}

impl TimeIntegrator for Replay<'_> {
    /// Moves to the next sample; the last sample stays (a file holds nothing after its horizon).
    fn advance(&mut self, state: &mut SchemeState) -> Result<(), SolveError> {
        let next = state.step_index() + 1;
        if next < self.run.samples() {
            self.load(next, state);
        }
        Ok(())
    }

    /// The energy of the [`EnergySource`]: the file's at `energy_time` (default: the sample's
    /// time), or the harness's of the sample's fields at its time; NaN when there is none,
    /// which no observer is then built to read.
    fn energy(&self, state: &SchemeState) -> Timed<f64> {
        match self.energy {
            EnergySource::Fields(model) => state.mechanical_energy(model),
            EnergySource::Reported | EnergySource::Absent => Timed {
                time: self.reported_time(&self.run.energy_time, state),
                value: match (self.energy, &self.run.energy) {
                    (EnergySource::Reported, Some(e)) => e[state.step_index()],
                    _ => f64::NAN,
                },
            },
        }
    }

    /// None: a replay solves nothing; its complementarity violation is unknown (NaN).
    fn statistics(&self) -> StepStatistics {
        StepStatistics {
            complementarity_violation: f64::NAN,
            ..StepStatistics::default()
        }
    }
}

/// `L∞(0, T)` and `L²(0, T)` of a sampled error.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct TimeNorms {
    /// The largest absolute value.
    pub linf: f64,
    /// The trapezoidal rule over the sample times.
    pub l2: f64,
}

/// What a replay measured.
#[derive(Debug, Clone, PartialEq)]
pub struct Replayed {
    /// The norms asked for.
    pub errors: BTreeMap<Norm, f64>,
    /// The total variations of `λ_h` and `λ`, when the multiplier's norm was asked for.
    pub multiplier_variation: Option<MultiplierVariation>,
    /// `u_h(0, t) − u(0, t)` over the samples, when the file has the contact node's
    /// displacement (given, or the fields') at every sample and its norms are finite.
    pub contact_displacement_error: Option<TimeNorms>,
    /// The displacement's errors in `H` (`L²` in space) and `V` (`H¹`) at each sample that has
    /// the field, when some sample lacks it.
    pub displacement_at_samples: Vec<DisplacementError>,
    /// The file's own energy's error `E_code − E` over its samples, when it reports one and the
    /// energy norms measure the harness's ([`EnergySource::Fields`] or
    /// [`EnergySource::Absent`]).
    pub reported_energy_error: Option<TimeNorms>,
    /// Wall-clock seconds of the observers.
    pub seconds: f64,
}

/// `L∞` and `L²` of `norm`; `None` when either overflows (a diagnostic that is not a number is
/// left out, never written as `null` or `inf`).
fn time_norms(norm: &TimeSeriesNorm) -> Option<TimeNorms> {
    let (linf, l2) = (norm.linf(), norm.l2());
    (linf.is_finite() && l2.is_finite()).then_some(TimeNorms { linf, l2 })
}

/// Replays `run` on `bar` against `exact` and computes the norms `norms` (which the file must
/// have the data of: the multiplier's over the samples that have `λ`) with the harness's
/// observers, as [`crate::harness::run::run`] does for a scheme, the energy from `energy`.
pub fn replay(
    run: &ExternalRun,
    bar: &Bar1d,
    exact: &dyn ExactSolution,
    norms: &BTreeSet<Norm>,
    energy: EnergySource<'_>,
) -> Result<Replayed, Error> {
    let clock = Instant::now();
    let mut errors = ErrorObservers::new(bar, exact, norms, false);
    let samples = run.samples();
    let mut contact = (0..samples)
        .all(|k| run.contact_displacement_at(k).is_some())
        .then(TimeSeriesNorm::default);
    let partial = run.displacement.as_ref().filter(|u| !u.is_complete());
    let mut space = partial.map(|_| SpaceErrorIntegrator::new());
    let mut displacement_at_samples = Vec::new();
    let mut reported = match (energy, &run.energy) {
        (EnergySource::Reported, _) | (_, None) => None,
        (_, Some(_)) => Some(TimeSeriesNorm::default()),
    };
    let mut replayed = Replay::new(run, bar, energy);
    let mut sample = replayed.start();
    for k in 0..samples {
        if k > 0 {
            replayed.advance(&mut sample)?;
        }
        let state = Integration {
            scheme: &replayed,
            state: &sample,
        };
        if let Some(o) = errors.displacement.as_mut() {
            o.observe(&state)?;
        }
        if let (Some(o), Some(_)) = (errors.multiplier.as_mut(), run.lambda_at(k)) {
            o.observe(&state)?;
        }
        if let Some(o) = errors.energy.as_mut() {
            o.observe(&state)?;
        }
        let t = state.time();
        if let (Some(space), Some(u)) = (space.as_mut(), run.row(&run.displacement, k)) {
            let e = space.errors(bar, &u[..bar.n_dofs()], exact, t);
            let quantity = StateField::DisplacementError;
            displacement_at_samples.push(DisplacementError {
                time: t,
                h: finite(&state, quantity, e.l2)?,
                v: finite(&state, quantity, e.h1)?,
            });
        }
        if let (Some(c), Some(u0)) = (contact.as_mut(), run.contact_displacement_at(k)) {
            c.push(t, u0 - exact.eval(0.0, t).u);
        }
        if let (Some(r), Some(e)) = (reported.as_mut(), &run.energy) {
            let te = replayed.reported_time(&run.energy_time, &sample);
            r.push(
                te,
                finite(&state, StateField::Energy, e[k])? - exact.energy(te),
            );
        }
    }
    Ok(Replayed {
        errors: errors.norms(norms),
        multiplier_variation: errors.multiplier.as_ref().and_then(|m| m.variation()),
        contact_displacement_error: contact.as_ref().and_then(time_norms),
        displacement_at_samples,
        reported_energy_error: reported.as_ref().and_then(time_norms),
        seconds: clock.elapsed().as_secs_f64(),
    })
}
