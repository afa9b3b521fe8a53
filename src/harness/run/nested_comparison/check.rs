//! Is the reference fine enough? The reference case one level coarser runs beside the reference,
//! in lockstep, and is compared with it in the fine space at the reference's samples: the
//! distance that bounds the reference's own error (for a converging reference) without storing
//! either trajectory.
//!
//! The check run is a second thread. At each sample its observer ([`CheckSender`]) sends the
//! displacement, energy and total contact force through a channel of one slot; the reference's
//! observer ([`CheckComparison`]) receives them at the same sample, prolongates the displacement
//! and measures the error in every norm of an [`ErrorSeries`]. Memory is one coarse displacement in
//! flight; the two runs advance together, the faster waiting for the slower.

use std::collections::BTreeMap;
use std::sync::mpsc::{Receiver, SyncSender};

use super::error_series::ErrorSeries;
use super::norm_matrices::NormMatrices;
use crate::engine::fem::{BoxMesh, Prolongation};
use crate::engine::schemes::TimeIntegrator;
use crate::harness::files::error::Error;
use crate::harness::run::norms::Norm;
use crate::harness::run::Observer;

/// What the check run sends at a sample.
#[derive(Debug)]
pub struct CheckSample {
    displacement: Vec<f64>,
    energy: f64,
    total_force: f64,
}

/// Counts an observer's steps and says which are samples: every `stride`-th from step 0.
#[derive(Debug)]
struct Samples {
    stride: usize,
    step: usize,
}

impl Samples {
    /// Whether the step being observed is a sample (called once per step).
    fn next_is_sample(&mut self) -> bool {
        let step = self.step;
        self.step += 1;
        step % self.stride == 0
    }
}

/// The check run's observer: sends its state every `stride` steps while the reference listens.
#[derive(Debug)]
pub struct CheckSender {
    channel: Option<SyncSender<CheckSample>>,
    samples: Samples,
}

impl CheckSender {
    /// Sends every `stride`-th step (from step 0) into `channel`.
    pub fn new(channel: SyncSender<CheckSample>, stride: usize) -> Self {
        Self {
            channel: Some(channel),
            samples: Samples { stride, step: 0 },
        }
    }
}

impl Observer for CheckSender {
    /// Sends the state at a sample; once the reference has stopped listening (it has finished,
    /// or failed and reports why), the run goes on without sending.
    fn observe(&mut self, state: &dyn TimeIntegrator) -> Result<(), Error> {
        let (true, Some(channel)) = (self.samples.next_is_sample(), &self.channel) else {
            return Ok(());
        };
        let sample = CheckSample {
            displacement: state.displacement().to_vec(),
            energy: state.energy().value,
            total_force: state.multiplier().value.iter().sum(),
        };
        if channel.send(sample).is_err() {
            self.channel = None;
        }
        Ok(())
    }
}

/// The reference run's observer: receives the check run's sample every `stride` steps and
/// measures its distance to the reference state.
pub struct CheckComparison<'a> {
    channel: Option<Receiver<CheckSample>>,
    norms: &'a NormMatrices,
    prolongation: Prolongation,
    samples: Samples,
    series: ErrorSeries,
    error: Vec<f64>,
    scratch: Vec<f64>,
}

impl<'a> CheckComparison<'a> {
    /// Receives from `channel` every `stride`-th step the state of a run on `coarse`, nested in
    /// the reference mesh `fine`, whose norm matrices are `norms`.
    pub fn new(
        channel: Receiver<CheckSample>,
        norms: &'a NormMatrices,
        coarse: &BoxMesh,
        fine: &BoxMesh,
        stride: usize,
    ) -> Result<Self, Error> {
        let prolongation = Prolongation::new(coarse, fine)?;
        let n = prolongation.fine_dofs();
        Ok(Self {
            channel: Some(channel),
            norms,
            prolongation,
            samples: Samples { stride, step: 0 },
            series: ErrorSeries::default(),
            error: vec![0.0; n],
            scratch: vec![0.0; n],
        })
    }

    /// The distance in every norm over the samples both runs reached. Stops listening (the
    /// check run's sends then return at once).
    pub fn finish(mut self) -> BTreeMap<Norm, f64> {
        self.channel = None;
        self.series.errors()
    }
}

impl Observer for CheckComparison<'_> {
    /// At a sample, waits for the check run's state at the same time and compares; once the
    /// check run has ended (its error, if any, is reported when it is joined), compares no more.
    fn observe(&mut self, state: &dyn TimeIntegrator) -> Result<(), Error> {
        let (true, Some(channel)) = (self.samples.next_is_sample(), &self.channel) else {
            return Ok(());
        };
        let Ok(sample) = channel.recv() else {
            self.channel = None;
            return Ok(());
        };
        self.prolongation
            .apply_into(&sample.displacement, &mut self.error);
        for (e, u) in self.error.iter_mut().zip(state.displacement()) {
            *e -= u;
        }
        let squared = self.norms.squared(&self.error, &mut self.scratch);
        let force: f64 = state.multiplier().value.iter().sum();
        self.series.push(
            state.time(),
            squared,
            sample.total_force - force,
            sample.energy - state.energy().value,
        );
        Ok(())
    }
}
