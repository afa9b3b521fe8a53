//! A box run on several ranks seen from rank 0's time loop as a one-process run
//! ([`DistributedRun`]): the steps are distributed ([`SlabOneStep`]), and so is everything a
//! reference observes of the fine field: after each step every rank's [`SlabObserver`]s (the
//! projections on the coarse levels, the comparison with the check run) and the step's energy
//! balance are computed on the slabs, summed across the ranks. No rank holds the whole state:
//! rank 0's time loop sees rank 0's part of it, which holds `Γ_Sig` (the contact dofs its
//! histories read) and the multipliers.
//!
//! Every rank makes the same collective calls in the same order. Rank 0's time loop decides
//! when the run ends (completed, stopped by an observer, or failed), so each step starts with
//! a sum in which rank 0 says whether to go on ([`Follow`]): 0 at each step, 1 when its
//! integrator is dropped, whatever ended the loop. The other ranks follow those sums
//! ([`follow`]) and end with it.

use std::cell::RefCell;

use super::{time_grid, IntegratorFactory, RunConfig};
#[cfg(feature = "mpi")]
pub use crate::engine::distributed::MpiRanks;
pub use crate::engine::distributed::{CountedRanks, DecompositionError, Ranks, Traffic};
use crate::engine::distributed::{SlabOneStep, SlabRunError, Slabs};
use crate::engine::error::{ParameterError, SolveError, StateField};
use crate::engine::model::Model;
use crate::engine::problem::{initial_dofs, AxialMesh, BoxProblem};
use crate::engine::schemes::energy_balance::{newmark_sides, theta_sides, StepBalance};
use crate::engine::schemes::{
    initial_state, Conventions, Scheme, SchemeState, StepCoefficients, StepStatistics,
    TimeIntegrator, Timed,
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

    /// This rank's part of the state after step `n` (from `n = 0`, every step in turn).
    fn observe_slab(&mut self, state: &SlabState);
}

/// What a rank of a distributed run holds of the state after a step.
#[derive(Debug, Clone, Copy)]
pub struct SlabState<'s> {
    /// This rank's part of `U^n`.
    pub u: &'s [f64],
    /// `t_n`.
    pub time: f64,
    /// The energy `E_h(U^n, V^n)` (summed over the ranks).
    pub energy: f64,
    /// `Σ λ^n` (rank 0's; 0 on the others).
    pub total_force: f64,
}

/// The slab observers of a distributed run, each borrowed by the run while it steps.
pub type SlabObservers<'r> = [&'r RefCell<dyn SlabObserver + 'r>];

/// A distributed run's integrator on each rank: the distributed steps, and after each the
/// finite check, the energy, the balance and the slab observers ([`DistributedRun::advance`]).
/// The steps' state is the slabs' ([`SlabOneStep`]); the [`SchemeState`] it writes after each
/// step is this rank's part of it (rank 0's time loop reads rank 0's).
pub struct DistributedRun<'r, R: Ranks + ?Sized> {
    ranks: &'r R,
    run: SlabOneStep<'r, R>,
    observers: &'r SlabObservers<'r>,
    energy: f64,
    /// The scheme's balance law: Newmark's `(β, γ)` (eq. 33), or the θ-method's `θ` (eq. 35).
    law: BalanceLaw,
    dt: f64,
    /// The last step's balance, computed on the slabs (none before the first step).
    balance: Option<StepBalance>,
    /// Whether rank 0's drop tells the other ranks the run has ended ([`Follow`]): once the
    /// start was observed, for a run rank 0's time loop drives (a start that failed failed on
    /// every rank together); never for a run every rank steps together ([`lockstep_run`]).
    tells_end: bool,
}

/// The balance law of a distributed run's scheme.
#[derive(Debug, Clone, Copy)]
enum BalanceLaw {
    Newmark { beta: f64, gamma: f64 },
    Theta { theta: f64 },
}

impl<'r, R: Ranks + ?Sized> DistributedRun<'r, R> {
    /// The distributed run of `model` with `scheme` (an implicit Newmark or θ-method one)
    /// and `Δt = dt` from `initial` (`U⁰`, `V⁰`, given on rank 0 only: the other ranks pass
    /// `None` and receive their parts of the start) with `conventions`, its initial state
    /// observed by `observers` (started on the run's decomposition first).
    pub fn new(
        (ranks, observers): (&'r R, &'r SlabObservers<'r>),
        model: &Model,
        (scheme, dt): (Scheme, f64),
        initial: Option<(&[f64], &[f64])>,
        conventions: &Conventions,
    ) -> Result<Self, Error> {
        let (coefficients, law) = match scheme {
            Scheme::Newmark { beta, gamma } if beta > 0.0 => (
                StepCoefficients::newmark(beta, gamma),
                BalanceLaw::Newmark { beta, gamma },
            ),
            Scheme::Theta { theta } => {
                (StepCoefficients::theta(theta), BalanceLaw::Theta { theta })
            }
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
        // Rank 0 alone computes the whole start, and tells the others whether it could.
        let start = (ranks.rank() == 0).then(|| {
            let (u0, v0) = initial.expect("rank 0 is given the initial values");
            initial_state(model, u0, v0, conventions)
        });
        let failed = ranks.sum(f64::from(u8::from(matches!(start, Some(Err(_))))));
        let start = start.transpose()?;
        if failed > 0.0 {
            return Err(DecompositionError::RankZeroFailed.into());
        }
        let run = SlabOneStep::new(
            ranks,
            model,
            coefficients,
            dt,
            start.as_ref(),
            conventions.predictor,
        )
        .map_err(|e| match e {
            SlabRunError::Decomposition(d) => Error::from(d),
            SlabRunError::Solve(s) => Error::from(s),
        })?;
        for o in observers {
            o.borrow_mut().start(run.slabs())?;
        }
        let mut distributed = Self {
            ranks,
            observers,
            run,
            energy: 0.0,
            law,
            dt,
            balance: None,
            tells_end: false,
        };
        distributed.observe()?;
        distributed.tells_end = true;
        Ok(distributed)
    }

    /// One step and its observations, every rank together, without rank 0's word on whether
    /// to go on: each rank's loop decides alike ([`follow`], [`lockstep_run`]).
    pub fn step_together(&mut self) -> Result<(), SolveError> {
        self.run.advance()?;
        self.observe()
    }

    /// The state after a step (every rank together): a non-finite value on any rank ends
    /// the run on every rank; then the energy, the step's balance and the slab observers.
    fn observe(&mut self) -> Result<(), SolveError> {
        let non_finite = |v: &[f64]| f64::from(u8::from(v.iter().any(|x| !x.is_finite())));
        let displacement = self.ranks.sum(non_finite(self.run.displacement()));
        let velocity = self.ranks.sum(non_finite(self.run.velocity()));
        let quantity = if displacement > 0.0 {
            Some(StateField::Displacement)
        } else if velocity > 0.0 {
            Some(StateField::Velocity)
        } else {
            None
        };
        if let Some(quantity) = quantity {
            return Err(SolveError::NonFinite {
                step: self.run.step(),
                time: self.run.time(),
                quantity,
            });
        }
        let energy_before = self.energy;
        self.energy = self.run.energy();
        let state = SlabState {
            u: self.run.displacement(),
            time: self.run.time(),
            energy: self.energy,
            total_force: self.run.multipliers().iter().sum(),
        };
        for o in self.observers {
            o.borrow_mut().observe_slab(&state);
        }
        if self.run.step() > 0 {
            let (law, dt) = (self.law, self.dt);
            let sides = self.run.balance(|forms, vectors| match law {
                BalanceLaw::Newmark { beta, gamma } => {
                    newmark_sides(forms, (beta, gamma), dt, vectors)
                }
                BalanceLaw::Theta { theta } => theta_sides(forms, (theta, theta), vectors),
            });
            self.balance = Some(sides.with_energies(energy_before, energy_before + sides.change));
        }
        Ok(())
    }

    /// The steps taken.
    pub fn step_index(&self) -> usize {
        self.run.step()
    }

    /// This rank's part of the state: `U^n`, `V^n` and `λ^n` (rank 0's) at step `n`.
    pub fn state(&self) -> SchemeState {
        let mut state = SchemeState::sample(0, 0.0, self.dt, (Vec::new(), Vec::new()));
        self.copy_state(&mut state);
        state
    }

    /// This rank's part of the state, written into `state`.
    fn copy_state(&self, state: &mut SchemeState) {
        for (to, from) in [
            (&mut state.u, self.run.displacement()),
            (&mut state.v, self.run.velocity()),
            (&mut state.lambda, self.run.multipliers()),
        ] {
            to.clear();
            to.extend_from_slice(from);
        }
        state.set_clock(self.run.step(), self.run.time());
    }
}

impl<R: Ranks + ?Sized> TimeIntegrator for DistributedRun<'_, R> {
    fn advance(&mut self, state: &mut SchemeState) -> Result<(), SolveError> {
        Follow::Step.agreed(self.ranks);
        self.run.advance()?;
        self.observe()?;
        self.copy_state(state);
        Ok(())
    }

    fn energy(&self, _state: &SchemeState) -> Timed<f64> {
        Timed {
            time: self.run.time(),
            value: self.energy,
        }
    }

    fn statistics(&self) -> StepStatistics {
        self.run.statistics()
    }

    /// Computed on the slabs after each step.
    fn own_balance(&self) -> Option<Option<StepBalance>> {
        Some(self.balance)
    }
}

impl<R: Ranks + ?Sized> Drop for DistributedRun<'_, R> {
    /// Rank 0's time loop is over, however it ended: every rank is told.
    fn drop(&mut self) {
        if self.ranks.rank() == 0 && self.tells_end {
            Follow::End.agreed(self.ranks);
        }
    }
}

/// A rank other than 0 of a distributed run: its steps, as long as rank 0 says to go on,
/// with the observations of each. Returns the error of a step that failed (rank 0's loop fails
/// with it too), after rank 0 has ended the run.
pub fn follow<R: Ranks + ?Sized>(run: &mut DistributedRun<'_, R>) -> Result<(), SolveError> {
    let mut failed = None;
    while Follow::Step.agreed(run.ranks) == Follow::Step {
        if let Err(e) = run.step_together() {
            failed = Some(e);
        }
    }
    failed.map_or(Ok(()), Err)
}

/// The factory of [`DistributedRun`]s on `ranks` observed by `observers` that rank 0's time loop
/// builds its integrator with ([`super::elastic::run_box`]).
pub fn distributed_run<'r>(
    ranks: &'r dyn Ranks,
    observers: &'r SlabObservers<'r>,
) -> Box<IntegratorFactory<'r>> {
    Box::new(move |model, scheme, dt, u0, v0, conventions| {
        let run = DistributedRun::new(
            (ranks, observers),
            model,
            (scheme, dt),
            Some((u0, v0)),
            conventions,
        )?;
        let state = run.state();
        Ok((Box::new(run) as Box<dyn TimeIntegrator + '_>, state))
    })
}

/// This rank's share of the distributed run of `problem` with `config`, observed by
/// `observers`, outside rank 0's time loop: the same model, scheme and `Δt` as that loop's
/// ([`super::drive_by`]), rank 0 computing the start with the initial values. Nothing of the
/// whole box's size is built on the other ranks: the model is matrix-free, the mesh is its
/// counts, and rank 0 sends each rank its part of the start. Every rank steps it together
/// ([`DistributedRun::step_together`]: a reference's check run, stepped by the reference's
/// steps), or a rank other than 0 follows rank 0's loop with it ([`follow_run`]); its drop
/// tells no rank anything.
pub fn lockstep_run<'r>(
    problem: &BoxProblem,
    config: &RunConfig,
    (ranks, observers): (&'r dyn Ranks, &'r SlabObservers<'r>),
) -> Result<DistributedRun<'r, dyn Ranks + 'r>, Error> {
    let (mesh, model) = problem.model(config.nx, config.mass, &config.settings)?;
    let scheme = config.scheme.validate()?;
    let (_, dt) = time_grid(problem.horizon, mesh.axial_element_size(), config.ratio);
    let initial = (ranks.rank() == 0).then(|| initial_dofs(problem, &mesh));
    let mut run = DistributedRun::new(
        (ranks, observers),
        &model,
        (scheme, dt),
        initial.as_ref().map(|(u0, v0)| (&u0[..], &v0[..])),
        &config.settings.conventions,
    )?;
    run.tells_end = false;
    Ok(run)
}

/// A rank other than 0 of the distributed run of `problem` with `config`, observed by
/// `observers`: its share of the run ([`lockstep_run`]), then its steps as rank 0 says
/// ([`follow`]).
pub fn follow_run<'r>(
    problem: &BoxProblem,
    config: &RunConfig,
    (ranks, observers): (&'r dyn Ranks, &'r SlabObservers<'r>),
) -> Result<(), Error> {
    let mut run = lockstep_run(problem, config, (ranks, observers))?;
    Ok(follow(&mut run)?)
}
