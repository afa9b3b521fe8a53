//! A box run on several ranks seen from rank 0 as a one-process run ([`GatheredRun`]): the
//! steps are distributed ([`SlabOneStep`]), and after each one the ranks' parts of `U` and
//! `V` are gathered on rank 0, where the run's observers (its histories, a reference's
//! projections and check) see the whole state through the one time loop
//! ([`super::drive_by`]) as they see a one-process run's.
//!
//! Every rank makes the same collective calls in the same order. Rank 0's time loop decides
//! when the run ends (completed, stopped by an observer, or failed), so each step starts with
//! a sum in which rank 0 says whether to go on ([`Follow`]): 0 at each step, 1 when its
//! integrator is dropped, whatever ended the loop. The other ranks follow those sums
//! ([`follow`]) and end with it.
//!
//! What needs the fine field without needing it whole, a reference's projections on its
//! coarse levels, is a [`SlabObserver`]: every rank computes it from its own part of `U` after
//! each step, inside the run, rank 0 holding the result.

use std::cell::RefCell;

use super::{time_grid, IntegratorFactory, RunConfig};
use crate::engine::contact::Truncation;
#[cfg(feature = "mpi")]
pub use crate::engine::distributed::MpiRanks;
pub use crate::engine::distributed::{CountedRanks, Ranks, Traffic};
use crate::engine::distributed::{SlabOneStep, SlabRunError, Slabs};
use crate::engine::error::{ParameterError, SolveError};
use crate::engine::linalg::SolveCounts;
use crate::engine::model::Model;
use crate::engine::problem::{AxialMesh, BoxProblem};
use crate::engine::schemes::{
    initial_state, Conventions, Scheme, SchemeState, StepCoefficients, TimeIntegrator, Timed,
};
use crate::harness::files::error::Error;

/// What rank 0 says at the start of each step.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Follow {
    /// Take the step.
    Step,
    /// The run has ended.
    End,
}

impl Follow {
    /// Rank 0's word, told to every rank (the others say nothing).
    fn agreed(self, ranks: &(impl Ranks + ?Sized)) -> Follow {
        let said = if ranks.rank() == 0 && self == Follow::End {
            1.0
        } else {
            0.0
        };
        if ranks.sum(said) > 0.0 {
            Follow::End
        } else {
            Follow::Step
        }
    }
}

/// What every rank of a distributed run computes from its part of the state after each step,
/// all ranks together (its collective calls in the same order on every rank).
pub trait SlabObserver {
    /// Sets up on the run's decomposition, before the first observation.
    fn start(&mut self, slabs: &Slabs) -> Result<(), Error>;

    /// This rank's part of `U^n`, after step `n` (from `n = 0`, every step in turn).
    fn observe_slab(&mut self, u: &[f64]);
}

/// The slab observers of a distributed run, each borrowed by the run while it steps.
pub type SlabObservers<'r> = [&'r RefCell<dyn SlabObserver + 'r>];

/// A distributed run's integrator on rank 0: the distributed steps, and the whole state
/// gathered after each ([`GatheredRun::advance`]).
pub struct GatheredRun<'r, R: Ranks + ?Sized> {
    ranks: &'r R,
    run: SlabOneStep<'r, R>,
    observers: &'r SlabObservers<'r>,
    /// The whole `U^n`, `V^n`, `λ^n` on rank 0 (empty vectors elsewhere).
    state: SchemeState,
    energy: f64,
}

impl<'r, R: Ranks + ?Sized> GatheredRun<'r, R> {
    /// The distributed run of `model` with `scheme` (an implicit Newmark or θ-method one)
    /// and `Δt = dt` from `u0`, `v0` with `conventions`, its initial state gathered and
    /// observed by `observers` (started on the run's decomposition first).
    pub fn new(
        (ranks, observers): (&'r R, &'r SlabObservers<'r>),
        model: &Model,
        (scheme, dt): (Scheme, f64),
        (u0, v0): (&[f64], &[f64]),
        conventions: &Conventions,
    ) -> Result<Self, Error> {
        let coefficients = match scheme {
            Scheme::Newmark { beta, gamma } if beta > 0.0 => StepCoefficients::newmark(beta, gamma),
            Scheme::Theta { theta } => StepCoefficients::theta(theta),
            other => {
                return Err(ParameterError::new(
                    "scheme",
                    other.name(),
                    "an implicit Newmark scheme (crank-nicolson among them) or a θ-method for \
                     a distributed run",
                )
                .into())
            }
        };
        let start = initial_state(model, u0, v0, conventions)?;
        let run = SlabOneStep::new(
            ranks,
            model,
            coefficients,
            dt,
            &start,
            conventions.predictor,
        )
        .map_err(|e| match e {
            SlabRunError::Decomposition(d) => Error::from(d),
            SlabRunError::Solve(s) => Error::from(s),
        })?;
        for o in observers {
            o.borrow_mut().start(run.slabs())?;
        }
        let whole = if ranks.rank() == 0 { u0.len() } else { 0 };
        let mut gathered = Self {
            ranks,
            observers,
            state: SchemeState::start(dt, vec![0.0; whole], vec![0.0; whole], Vec::new()),
            run,
            energy: 0.0,
        };
        gathered.observe();
        Ok(gathered)
    }

    /// The energy, the slab observers and the gathered state after a step (every rank
    /// together).
    fn observe(&mut self) {
        for o in self.observers {
            o.borrow_mut().observe_slab(self.run.displacement());
        }
        self.energy = self.run.energy();
        gather(
            self.ranks,
            &self.run,
            self.run.displacement(),
            &mut self.state.u,
        );
        gather(
            self.ranks,
            &self.run,
            self.run.velocity(),
            &mut self.state.v,
        );
        self.state.lambda = self.run.multipliers().to_vec();
        self.state.step = self.run.step();
    }
}

/// Every rank's part of a vector (`part`) into `whole` on rank 0, in rank order.
fn gather<R: Ranks + ?Sized>(ranks: &R, run: &SlabOneStep<'_, R>, part: &[f64], whole: &mut [f64]) {
    if ranks.rank() != 0 {
        ranks.send(0, part);
        return;
    }
    whole[run.own_dofs()].copy_from_slice(part);
    for r in 1..ranks.size() {
        ranks.receive(r, &mut whole[run.dofs_of(r)]);
    }
}

impl<R: Ranks + ?Sized> TimeIntegrator for GatheredRun<'_, R> {
    fn advance(&mut self) -> Result<(), SolveError> {
        Follow::Step.agreed(self.ranks);
        self.run.advance()?;
        self.observe();
        Ok(())
    }

    fn state(&self) -> &SchemeState {
        &self.state
    }

    fn energy(&self) -> Timed<f64> {
        Timed {
            time: self.run.time(),
            value: self.energy,
        }
    }

    fn contact_solves(&self) -> usize {
        self.run.contact_solves()
    }

    fn contact_seconds(&self) -> f64 {
        self.run.contact_seconds()
    }

    fn complementarity_violation(&self) -> f64 {
        self.run.complementarity_violation()
    }

    fn step_solves(&self) -> SolveCounts {
        self.run.step_solves()
    }

    fn contact_truncation(&self) -> Option<Truncation> {
        self.run.contact_truncation()
    }
}

impl<R: Ranks + ?Sized> Drop for GatheredRun<'_, R> {
    /// Rank 0's time loop is over, however it ended: every rank is told.
    fn drop(&mut self) {
        if self.ranks.rank() == 0 {
            Follow::End.agreed(self.ranks);
        }
    }
}

/// A rank other than 0 of a distributed run: its steps, as long as rank 0 says to go on,
/// with the gathers of each. Returns the error of a step that failed (rank 0's loop fails
/// with it too), after rank 0 has ended the run.
pub fn follow<R: Ranks + ?Sized>(run: &mut GatheredRun<'_, R>) -> Result<(), SolveError> {
    let mut failed = None;
    while Follow::Step.agreed(run.ranks) == Follow::Step {
        match run.run.advance() {
            Ok(()) => run.observe(),
            Err(e) => failed = Some(e),
        }
    }
    failed.map_or(Ok(()), Err)
}

/// The factory of [`GatheredRun`]s on `ranks` observed by `observers` that rank 0's time loop
/// builds its integrator with ([`super::elastic::run_box`]).
pub fn gathered<'r>(
    ranks: &'r dyn Ranks,
    observers: &'r SlabObservers<'r>,
) -> Box<IntegratorFactory<'r>> {
    Box::new(move |model, scheme, dt, u0, v0, conventions| {
        let run = GatheredRun::new(
            (ranks, observers),
            model,
            (scheme, dt),
            (u0, v0),
            conventions,
        )?;
        Ok(Box::new(run) as Box<dyn TimeIntegrator + '_>)
    })
}

/// A rank other than 0 of the distributed run of `problem` with `config`, observed by
/// `observers`: the same discretisation, scheme and `Δt` as rank 0's time loop
/// ([`super::drive_by`]), then its steps as rank 0 says ([`follow`]). The whole discretisation
/// is dropped once the run holds this rank's slab.
pub fn follow_run<'r>(
    problem: &BoxProblem,
    config: &RunConfig,
    (ranks, observers): (&'r dyn Ranks, &'r SlabObservers<'r>),
) -> Result<(), Error> {
    let discretisation = problem.discretise(config.nx, config.mass, &config.settings)?;
    let scheme = config.scheme.validate()?;
    let h = discretisation.mesh.axial_element_size();
    let (_, dt) = time_grid(problem.horizon, h, config.ratio);
    let mut run = GatheredRun::new(
        (ranks, observers),
        &discretisation.model,
        (scheme, dt),
        (&discretisation.displacement, &discretisation.velocity),
        &discretisation.conventions,
    )?;
    drop(discretisation);
    Ok(follow(&mut run)?)
}
