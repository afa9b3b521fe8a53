//! Another code's run replayed as a time integrator ([`Replay`]): each sample of the file is a
//! state that the harness's own observers (`crate::harness::run::exact`) take in exactly as
//! they take in a scheme's, so the norms of a file are computed by the code that computes the
//! harness's runs, over the file's own sample times.

use std::collections::{BTreeMap, BTreeSet};
use std::time::Instant;

use serde::{Deserialize, Serialize};

use super::format::ExternalRun;
use crate::engine::error::SolveError;
use crate::engine::exact::ExactSolution;
use crate::engine::fem::Bar1d;
use crate::engine::schemes::{SchemeState, TimeIntegrator, Timed};
use crate::harness::files::error::Error;
use crate::harness::run::exact::ErrorObservers;
use crate::harness::run::norms::{Norm, TimeSeriesNorm};
use crate::harness::run::{MultiplierVariation, Observer};

/// The samples of a run file as the states of a time integrator on the scene's bar: sample `n`
/// is state `n` at the file's time `t_n`; the fields are the file's nodal values (without a
/// clamped end's node, as the bar's dofs), the multiplier and the energy are the file's with
/// the times they approximate.
pub struct Replay<'a> {
    run: &'a ExternalRun,
    /// Nodes per field row.
    nodes: usize,
    /// The bar's dofs: the nodes less a clamped end.
    dofs: usize,
    /// The current sample: its index, the spacing to the previous sample (to the next one at
    /// the first sample), the file's nodal displacements and velocities (empty when the file
    /// has none) and its multiplier (none when the file has none).
    state: SchemeState,
}

impl<'a> Replay<'a> {
    /// The replay of `run` on `bar` (the scene's bar with the file's `NX`), at its first sample.
    pub fn new(run: &'a ExternalRun, bar: &Bar1d) -> Self {
        let mut replay = Self {
            run,
            nodes: run.nodes.len(),
            dofs: bar.n_dofs(),
            state: SchemeState::start(0.0, Vec::new(), Vec::new(), Vec::new()),
        };
        replay.load();
        replay
    }

    /// Copies the current sample of the file into the state.
    fn load(&mut self) {
        let (n, nodes, dofs) = (self.state.step, self.nodes, self.dofs);
        let row = |field: &Option<Vec<f64>>| -> Vec<f64> {
            field
                .as_ref()
                .map_or_else(Vec::new, |f| ExternalRun::row(f, nodes, n)[..dofs].to_vec())
        };
        self.state.u = row(&self.run.displacement);
        self.state.v = row(&self.run.velocity);
        self.state.lambda = self
            .run
            .lambda
            .as_ref()
            .map_or_else(Vec::new, |l| vec![l[n]]);
        let (t, k) = (&self.run.time, n.max(1));
        self.state.dt = t[k] - t[k - 1];
    }

    /// The current sample's entry of `times` (`lambda_time`, `energy_time`) when the file gives
    /// them, else the sample's time.
    fn reported_time(&self, times: &Option<Vec<f64>>) -> f64 {
        times.as_ref().map_or(self.time(), |t| t[self.state.step])
    }
}

impl TimeIntegrator for Replay<'_> {
    /// Moves to the next sample; the last sample stays (a file holds nothing after its horizon).
    fn advance(&mut self) -> Result<(), SolveError> {
        if self.state.step + 1 < self.run.samples() {
            self.state.step += 1;
            self.load();
        }
        Ok(())
    }

    fn state(&self) -> &SchemeState {
        &self.state
    }

    /// The file's time of the current sample.
    fn time(&self) -> f64 {
        self.run.time[self.state.step]
    }

    /// The file's multiplier at `lambda_time` (default: the sample's time); empty when the
    /// file has none.
    fn multiplier(&self) -> Timed<&[f64]> {
        Timed {
            time: self.reported_time(&self.run.lambda_time),
            value: &self.state.lambda,
        }
    }

    /// The file's energy at `energy_time` (default: the sample's time); NaN when the file has
    /// none, which no observer is then built to read.
    fn energy(&self) -> Timed<f64> {
        Timed {
            time: self.reported_time(&self.run.energy_time),
            value: self
                .run
                .energy
                .as_ref()
                .map_or(f64::NAN, |e| e[self.state.step]),
        }
    }

    /// None: a replay solves nothing.
    fn contact_solves(&self) -> usize {
        0
    }

    /// None: a replay solves nothing.
    fn contact_seconds(&self) -> f64 {
        0.0
    }

    /// Unknown for another code's run: NaN.
    fn complementarity_violation(&self) -> f64 {
        f64::NAN
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
    /// displacement (given, or the fields').
    pub contact_displacement_error: Option<TimeNorms>,
    /// Wall-clock seconds of the observers.
    pub seconds: f64,
}

/// Replays `run` on `bar` against `exact` and computes the norms `norms` (which the file must
/// have the data of) with the harness's observers, as [`crate::harness::run::run`] does for a
/// scheme.
pub fn replay(
    run: &ExternalRun,
    bar: &Bar1d,
    exact: &dyn ExactSolution,
    norms: &BTreeSet<Norm>,
) -> Result<Replayed, Error> {
    let clock = Instant::now();
    let mut errors = ErrorObservers::new(bar, exact, norms, false);
    let mut contact = run
        .contact_displacement_at(0)
        .map(|_| TimeSeriesNorm::default());
    let mut state = Replay::new(run, bar);
    {
        let mut observers: Vec<&mut dyn Observer> = errors.observers().collect();
        for k in 0..run.samples() {
            if k > 0 {
                state.advance()?;
            }
            for o in observers.iter_mut() {
                o.observe(&state)?;
            }
            if let (Some(c), Some(u0)) = (contact.as_mut(), run.contact_displacement_at(k)) {
                let t = state.time();
                c.push(t, u0 - exact.eval(0.0, t).u);
            }
        }
    }
    Ok(Replayed {
        errors: errors.norms(norms),
        multiplier_variation: errors.multiplier.as_ref().and_then(|m| m.variation()),
        contact_displacement_error: contact.map(|c| TimeNorms {
            linf: c.linf(),
            l2: c.l2(),
        }),
        seconds: clock.elapsed().as_secs_f64(),
    })
}
