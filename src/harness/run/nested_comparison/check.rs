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
//!
//! Beside a distributed reference the check run is distributed too, over the same ranks, and
//! stepped by the reference's own steps in the same thread ([`LockstepCheck`]): one check step
//! every second reference step, so that each rank's core does both runs' work in turn and no
//! thread waits for another. At each sample every rank sends its part of the check run's
//! displacement to rank 0 ([`CheckGather`]), which hands the whole sample to the comparison.

use std::cell::RefCell;
use std::collections::BTreeMap;
use std::ops::Range;
use std::sync::mpsc::{Receiver, Sender, SyncSender};

use super::error_series::ErrorSeries;
use super::norm_matrices::NormMatrices;
use super::slab_fine::{SlabFine, SlabSetup};
use crate::engine::distributed::{Ranks, Slabs};
use crate::engine::error::SolveError;
use crate::engine::fem::{BoxMesh, Prolongation};
use crate::engine::schemes::Integration;
use crate::harness::files::error::Error;
use crate::harness::run::distributed::{DistributedRun, SlabObserver, SlabState};
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
    fn observe(&mut self, state: &Integration<'_>) -> Result<(), Error> {
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

/// The check run's slab observer on every rank of its distributed run: every `stride` steps
/// (from step 0) each rank sends rank 0 its part of the displacement, and rank 0 sends the
/// whole sample into its channel, as [`CheckSender`] does (once the reference has stopped
/// listening, the run goes on without sending). The channel has no bound: the two runs are
/// stepped in one thread, so a sample is sent before the comparison that reads it.
pub struct CheckGather<'r> {
    ranks: &'r dyn Ranks,
    /// Rank 0's channel to the reference (`None` on the other ranks).
    channel: Option<Sender<CheckSample>>,
    samples: Samples,
    /// Unknowns per node layer of the check run's mesh.
    layer_dofs: usize,
    /// Every rank's range of the whole displacement, once the run has cut the box.
    parts: Vec<Range<usize>>,
}

impl<'r> CheckGather<'r> {
    /// The observer of rank `ranks.rank()` of the check run on `mesh`, sending into `channel`
    /// (rank 0's; `None` on the others) every `stride`-th step.
    pub fn new(
        ranks: &'r dyn Ranks,
        channel: Option<Sender<CheckSample>>,
        stride: usize,
        mesh: &BoxMesh,
    ) -> Self {
        let d = mesh.dim();
        let per_layer: usize = mesh.counts()[..d - 1].iter().map(|n| n + 1).product();
        Self {
            ranks,
            channel,
            samples: Samples { stride, step: 0 },
            layer_dofs: per_layer * d,
            parts: Vec::new(),
        }
    }
}

impl SlabObserver for CheckGather<'_> {
    fn start(&mut self, slabs: &Slabs) -> Result<(), Error> {
        self.parts = (0..slabs.ranks())
            .map(|r| {
                let layers = slabs.of(r);
                layers.start * self.layer_dofs..layers.end * self.layer_dofs
            })
            .collect();
        Ok(())
    }

    fn observe_slab(&mut self, state: &SlabState) {
        if !self.samples.next_is_sample() {
            return;
        }
        if self.ranks.rank() != 0 {
            self.ranks.send(0, state.u);
            return;
        }
        let mut displacement = vec![0.0; self.parts.last().map_or(0, |p| p.end)];
        displacement[self.parts[0].clone()].copy_from_slice(state.u);
        for (r, part) in self.parts.iter().enumerate().skip(1) {
            self.ranks.receive(r, &mut displacement[part.clone()]);
        }
        let sample = CheckSample {
            displacement,
            energy: state.energy,
            total_force: state.total_force,
        };
        if self
            .channel
            .as_ref()
            .is_some_and(|c| c.send(sample).is_err())
        {
            self.channel = None;
        }
    }
}

/// The check run of a distributed reference stepped by the reference's steps, on every rank:
/// a slab observer of the reference, listed before its comparison, that takes one step of the
/// check run at every second reference step (the check has half its steps), in the reference's
/// thread; the check's [`CheckGather`] sends rank 0's samples to the comparison. A failed check
/// step fails on every rank alike: the check then stops, its channel is closed (the comparison
/// compares no more), and [`LockstepCheck::finish`] returns the failure.
pub struct LockstepCheck<'r> {
    run: DistributedRun<'r, dyn Ranks + 'r>,
    gather: &'r RefCell<CheckGather<'r>>,
    /// Reference steps observed.
    observed: usize,
    failed: Option<SolveError>,
}

impl<'r> LockstepCheck<'r> {
    /// The check `run` (a [`crate::harness::run::distributed::lockstep_run`] observed by
    /// `gather`), at its start.
    pub fn new(
        run: DistributedRun<'r, dyn Ranks + 'r>,
        gather: &'r RefCell<CheckGather<'r>>,
    ) -> Self {
        Self {
            run,
            gather,
            observed: 0,
            failed: None,
        }
    }

    /// The check run's steps, or its failure.
    pub fn finish(self) -> Result<usize, SolveError> {
        match self.failed {
            Some(e) => Err(e),
            None => Ok(self.run.step_index()),
        }
    }
}

impl SlabObserver for LockstepCheck<'_> {
    /// The check run was set up on its own decomposition.
    fn start(&mut self, _: &Slabs) -> Result<(), Error> {
        Ok(())
    }

    fn observe_slab(&mut self, _: &SlabState) {
        let step = self.observed;
        self.observed += 1;
        if step == 0 || step % 2 == 1 || self.failed.is_some() {
            return;
        }
        if let Err(e) = self.run.step_together() {
            self.failed = Some(e);
            self.gather.borrow_mut().channel = None;
        }
    }
}

/// The reference run's observer: receives the check run's sample every `stride` steps and
/// measures its distance to the reference state: in one process (an [`Observer`]), or on every
/// rank of a distributed run (a [`SlabObserver`], rank 0 receiving the samples and keeping the
/// series, [`CheckComparison::distributed`]).
pub struct CheckComparison<'a> {
    channel: Option<Receiver<CheckSample>>,
    samples: Samples,
    series: ErrorSeries,
    fine: CheckFine<'a>,
}

/// The reference's side of the comparison.
enum CheckFine<'a> {
    /// The whole reference mesh, in this process.
    Whole {
        norms: &'a NormMatrices,
        prolongation: Prolongation,
        error: Vec<f64>,
        scratch: Vec<f64>,
    },
    /// A distributed run's, before the run has cut the box into slabs.
    Unstarted(SlabSetup<'a>),
    /// This rank's slab of it.
    Slab(Box<SlabFine<'a>>),
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
            samples: Samples { stride, step: 0 },
            series: ErrorSeries::default(),
            fine: CheckFine::Whole {
                norms,
                prolongation,
                error: vec![0.0; n],
                scratch: vec![0.0; n],
            },
        })
    }

    /// [`CheckComparison::new`] on the rank `ranks.rank()` of a distributed run: rank 0 is
    /// given the `channel`, the others `None`; its part is set up when the run has cut the box
    /// ([`SlabObserver::start`]).
    pub fn distributed(
        ranks: &'a dyn Ranks,
        channel: Option<Receiver<CheckSample>>,
        norms: &'a NormMatrices,
        (coarse, fine): (&BoxMesh, &'a BoxMesh),
        stride: usize,
    ) -> Self {
        Self {
            channel,
            samples: Samples { stride, step: 0 },
            series: ErrorSeries::default(),
            fine: CheckFine::Unstarted(SlabSetup {
                ranks,
                norms,
                coarse: coarse.clone(),
                fine,
            }),
        }
    }

    /// The distance in every norm over the samples both runs reached (none on a distributed
    /// run's ranks other than 0). Stops listening (the check run's sends then return at once).
    pub fn finish(mut self) -> BTreeMap<Norm, f64> {
        self.channel = None;
        self.series.errors()
    }

    /// The check run's sample, when it still sends (it stops listening otherwise).
    fn receive(&mut self) -> Option<CheckSample> {
        let sample = self.channel.as_ref()?.recv().ok();
        if sample.is_none() {
            self.channel = None;
        }
        sample
    }
}

impl Observer for CheckComparison<'_> {
    /// At a sample, waits for the check run's state at the same time and compares; once the
    /// check run has ended (its error, if any, is reported when it is joined), compares no more.
    fn observe(&mut self, state: &Integration<'_>) -> Result<(), Error> {
        if !self.samples.next_is_sample() {
            return Ok(());
        }
        let Some(sample) = self.receive() else {
            return Ok(());
        };
        let CheckFine::Whole {
            norms,
            prolongation,
            error,
            scratch,
        } = &mut self.fine
        else {
            unreachable!("a distributed comparison observes the slabs")
        };
        prolongation.apply_into(&sample.displacement, error);
        for (e, u) in error.iter_mut().zip(state.displacement()) {
            *e -= u;
        }
        let squared = norms.squared(error, scratch);
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

impl SlabObserver for CheckComparison<'_> {
    /// Cuts the reference's side into this rank's slab.
    fn start(&mut self, slabs: &Slabs) -> Result<(), Error> {
        if let CheckFine::Unstarted(setup) = &self.fine {
            self.fine = CheckFine::Slab(Box::new(setup.start(slabs)?));
        }
        Ok(())
    }

    /// At a sample, rank 0 waits for the check run's state and tells every rank whether it
    /// came; then every rank adds its part of the distance, and rank 0 keeps it.
    fn observe_slab(&mut self, state: &SlabState) {
        if !self.samples.next_is_sample() {
            return;
        }
        let CheckFine::Slab(slab) = &self.fine else {
            unreachable!("a distributed comparison is started first")
        };
        let sample = if slab.rank() == 0 {
            self.receive()
        } else {
            None
        };
        let CheckFine::Slab(slab) = &mut self.fine else {
            unreachable!("a distributed comparison is started first")
        };
        if !slab.rank_0_says(sample.is_some()) {
            return;
        }
        let squared = slab.distances(state.u, sample.as_ref().map(|s| s.displacement.as_slice()));
        if let Some(sample) = sample {
            self.series.push(
                state.time,
                squared,
                sample.total_force - state.total_force,
                sample.energy - state.energy,
            );
        }
    }
}
