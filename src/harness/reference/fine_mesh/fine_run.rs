//! The fine run of a reference: one run on the finest nested mesh, in one process or shared by
//! the ranks of a distributed run, with the check run one level coarser beside it.
//!
//! The run keeps, every `sample_every` fine steps, the energy (eq. 6), the total normal contact
//! force `Σ λ_i` and the contact-face centre node's displacement and multiplier; for each fitted
//! level, at each of that level's steps, the reference's projections on the level
//! ([`crate::harness::run::nested_comparison::projection`]), which is all a coarse run's
//! displacement errors need; and the distance to it of the reference case one level coarser, run
//! beside it ([`crate::harness::run::nested_comparison::check`]). Its trajectory is never stored:
//! memory is the run's own and the projections (about 100 MB for the 3D levels 10–80).
//!
//! One function sets the run up for every process ([`fine_run`]): alone, as rank 0 of a
//! distributed run (which keeps the histories, the projections and the check), or as another
//! rank (its share of the steps, [`FineReference::follow`]). Beside a distributed reference the
//! check run is distributed too and stepped by the reference's steps, unless it cannot be cut
//! into the ranks' slabs, when rank 0 runs it in one process beside the reference, as a reference
//! in one process does.

use std::cell::RefCell;
use std::sync::mpsc::{channel, sync_channel};
use std::time::Instant;

use super::cache::{
    self, closest_other, CacheLookup, CachedReference, CheckOutcome, ProjectionLayout,
    ReferenceCache, ReferenceHistories, ReferenceKey,
};
use crate::harness::files::error::{self as files, ParameterError};
use crate::harness::problem::Settings;
use crate::harness::run::distributed::{
    distributed_run, follow_run, lockstep_run, DecompositionError, Ranks, SlabObserver,
    SlabObservers,
};
use crate::harness::run::elastic::{box_mesh, run_box, BoxMesh, BoxProblem};
use crate::harness::run::nested_comparison::check::{
    CheckComparison, CheckGather, CheckSender, LockstepCheck,
};
use crate::harness::run::nested_comparison::norm_matrices::NormMatrices;
use crate::harness::run::nested_comparison::projection::{LevelProjections, ProjectionRecorder};
use crate::harness::run::{run, BoxRun, Observables, RunConfig, Timings};
use crate::harness::study::error::Error;
use crate::harness::study::progress::StepProgress;

/// A reference: the histories and the projections on the fitted levels, with its mesh.
#[derive(Debug, Clone)]
pub struct FineReference {
    /// The scalar histories, the key and the check.
    pub histories: ReferenceHistories,
    /// The projections on each fitted level, coarsest first.
    pub projections: Vec<LevelProjections>,
    /// The fine mesh.
    pub mesh: BoxMesh,
    /// Whether it was read from the cache.
    pub from_cache: bool,
    /// What the fine run cost, when it was computed now.
    pub cost: Option<FineRunCost>,
}

/// What a reference's fine run cost.
#[derive(Debug, Clone, Copy)]
pub struct FineRunCost {
    /// How its time was spent (rank 0's, for a distributed run).
    pub timings: Timings,
    /// Step systems solved.
    pub solves: usize,
    /// CG iterations over all of them.
    pub iterations: usize,
    /// The ranks the check run was shared by (1: in one process, [`lockstep_check`]).
    pub check_ranks: usize,
    /// `L`, the layers of the local contact operator's slab (rank 0's), when it has one.
    pub contact_layers: Option<usize>,
}

/// The part a process takes in a fine run.
#[derive(Clone, Copy)]
enum Part<'r> {
    /// The whole run, in this process.
    Alone,
    /// Rank 0 of a distributed run: it keeps the histories, the projections and the check.
    Leader(&'r dyn Ranks),
    /// Another rank of a distributed run: its share of the steps, nothing kept.
    Follower(&'r dyn Ranks),
}

impl<'r> Part<'r> {
    /// The part of a process with `ranks` (rank 0's) or without (alone).
    fn leading(ranks: Option<&'r dyn Ranks>) -> Self {
        ranks.map_or(Part::Alone, Part::Leader)
    }

    /// The ranks of a distributed run.
    fn ranks(self) -> Option<&'r dyn Ranks> {
        match self {
            Part::Alone => None,
            Part::Leader(ranks) | Part::Follower(ranks) => Some(ranks),
        }
    }
}

impl FineReference {
    /// Runs the reference, projecting it on `key.levels` as it goes, with the check run one
    /// level coarser beside it, and keeps the scalar histories every `key.sample_every`-th step;
    /// with `ranks`, as rank 0 of a distributed run, whose steps the other ranks share
    /// ([`FineReference::follow`]; the projections and the check are computed on every rank's
    /// slab, rank 0 keeping them, [`crate::harness::run::distributed`]).
    pub fn compute(
        problem: &BoxProblem,
        settings: &Settings,
        key: ReferenceKey,
        ranks: Option<&dyn Ranks>,
    ) -> Result<Self, Error> {
        fine_run(problem, settings, key, Part::leading(ranks))
            .map(|kept| kept.expect("rank 0 and a process alone keep the reference"))
    }

    /// A rank other than 0 of the distributed reference of `key` (rank 0 runs
    /// [`FineReference::obtain`] with the same arguments): when rank 0 computes it, this rank's
    /// share of the fine run's steps and of the check run's ([`fine_run`]); nothing when rank
    /// 0 found it cached.
    pub fn follow(
        problem: &BoxProblem,
        settings: &Settings,
        key: &ReferenceKey,
        ranks: &dyn Ranks,
    ) -> Result<(), Error> {
        if ranks.sum(0.0) == 0.0 {
            return Ok(());
        }
        fine_run(problem, settings, key.clone(), Part::Follower(ranks)).map(|_| ())
    }

    /// Number of samples of the scalar histories.
    pub fn samples(&self) -> usize {
        self.histories.time.len()
    }

    /// The projections on the level of `n_axis` elements along the axis.
    pub fn projections_on(&self, n_axis: usize) -> Option<&LevelProjections> {
        self.projections.iter().find(|p| p.level == n_axis)
    }

    /// The cached reference of `key` in `cache` when there is one, otherwise a new run, saved
    /// when `cache` may be written. `note` is told why a cache was not used: no file for the
    /// key (with the closest other reference of the same dimension and the fields it differs
    /// in), or a file whose content does not match. The run is solved with `settings`; settings
    /// with a round-off perturbation are refused: the key cannot tell it from the problem as
    /// stated. `afford` is asked before a run is started (a caller's budget check: its error
    /// is returned and nothing is run).
    ///
    /// With `ranks`, this is rank 0 of a distributed run: it tells the other ranks whether it
    /// computes the reference ([`FineReference::follow`]) once the cache is looked up and the
    /// budget checked.
    pub fn obtain(
        problem: &BoxProblem,
        settings: &Settings,
        (cache, key): (&ReferenceCache, ReferenceKey),
        note: &mut dyn FnMut(String),
        afford: &dyn Fn() -> Result<(), Error>,
        ranks: Option<&dyn Ranks>,
    ) -> Result<Self, Error> {
        if settings.round_off.is_some() {
            return Err(ParameterError::new(
                "round_off",
                "given",
                "absent for a reference (its key and cache describe the problem as stated)",
            )
            .into());
        }
        let (dir, stem) = (cache.dir(), key.stem());
        match cache::load(dir, &stem, &key)? {
            CacheLookup::Hit(cached) => {
                if let Some(ranks) = ranks {
                    ranks.sum(0.0);
                }
                let CachedReference {
                    histories,
                    projections,
                } = *cached;
                note(format!("read the reference from {}", dir.display()));
                return Ok(Self {
                    mesh: box_mesh(problem, histories.key.n_axis)?,
                    histories,
                    projections,
                    from_cache: true,
                    cost: None,
                });
            }
            CacheLookup::Missing => note(
                format!(
                    "no cached reference for these parameters in {}{}",
                    dir.display(),
                    closest_other(dir, &key)
                        .map(|(name, fields)| format!(
                            " (the closest, {name}, differs in {})",
                            fields.join("; ")
                        ))
                        .unwrap_or_default()
                ) + "; computing it",
            ),
            CacheLookup::Stale(why) => note(format!(
                "cached reference {stem} is stale ({}); computing it",
                why.join("; ")
            )),
        }
        afford()?;
        if let Some(ranks) = ranks {
            ranks.sum(1.0);
        }
        let reference = Self::compute(problem, settings, key, ranks)?;
        if let ReferenceCache::ReadWrite(dir) = cache {
            cache::save((&reference.histories, &reference.projections), dir, &stem)?;
            note(format!("kept the reference in {}", dir.display()));
        } else {
            note(format!(
                "the reference is not kept (the cache {} is read only)",
                dir.display()
            ));
        }
        Ok(reference)
    }
}

/// The fine run of `key` as `part` takes it: the reference with its projections, its check and
/// its histories in one process or on rank 0 (`Some`), this rank's share of the steps on the
/// others (`None`). Every rank sets up the same parts in the same order: the projections, the
/// check run's gathering and, where its box can be cut into the ranks' slabs, its lockstep run,
/// then the comparison with the check.
fn fine_run(
    problem: &BoxProblem,
    settings: &Settings,
    key: ReferenceKey,
    part: Part<'_>,
) -> Result<Option<FineReference>, Error> {
    let clock = Instant::now();
    let ranks = part.ranks();
    let settings = match ranks {
        Some(_) => settings.distributed()?,
        None => *settings,
    };
    let config = fine_config(&key, settings)?;
    let every = key.sample_every.max(1);
    let mesh = box_mesh(problem, key.n_axis)?;
    let fine_norms = NormMatrices::of(&mesh, &problem.elasticity);
    let mesh_of = |n| box_mesh(problem, n).map_err(files::Error::from);
    let recorder = RefCell::new(ProjectionRecorder::new(
        (&key.levels, &mesh_of),
        (&mesh, &fine_norms),
        &problem.elasticity,
        ranks,
    )?);
    let check_config = RunConfig {
        nx: key.n_axis / 2,
        ..config.clone()
    };
    // The check run's steps per sample: it has half the reference's steps.
    let check_stride = (every / 2).max(1);
    let check_mesh = box_mesh(problem, check_config.nx)?;
    // Beside a distributed reference, every rank together: the check run distributed too,
    // stepped by the reference's steps, unless it cannot be cut into the ranks' slabs.
    let (lockstep_to, lockstep_from) = channel();
    let gather = ranks.map(|r| {
        let to = matches!(part, Part::Leader(_)).then_some(lockstep_to);
        RefCell::new(CheckGather::new(r, to, check_stride, &check_mesh))
    });
    let gather_observers: Vec<&RefCell<dyn SlabObserver>> = (gather.iter())
        .map(|g| g as &RefCell<dyn SlabObserver>)
        .collect();
    let lockstep = match (ranks, &gather) {
        (Some(r), Some(g)) => lockstep_check(problem, &check_config, (r, &gather_observers, g))?,
        _ => None,
    };
    let (sender, receiver) = sync_channel(1);
    let receiver = if lockstep.is_some() {
        lockstep_from
    } else {
        receiver
    };
    let comparison = RefCell::new(match part {
        Part::Alone => CheckComparison::new(receiver, &fine_norms, &check_mesh, &mesh, every)?,
        Part::Leader(ranks) => CheckComparison::distributed(
            ranks,
            Some(receiver),
            &fine_norms,
            (&check_mesh, &mesh),
            every,
        ),
        Part::Follower(ranks) => {
            CheckComparison::distributed(ranks, None, &fine_norms, (&check_mesh, &mesh), every)
        }
    });
    if let Part::Follower(ranks) = part {
        let slab_observers = fine_observers(&recorder, lockstep.as_ref(), &comparison);
        follow_run(problem, &config, (ranks, &slab_observers))?;
        if let Some(lockstep) = lockstep {
            lockstep.into_inner().finish()?;
        }
        return Ok(None);
    }
    let (run, distance, in_one_process) = std::thread::scope(|scope| {
        let check = lockstep.is_none().then(|| {
            scope.spawn(|| {
                let mut send = CheckSender::new(sender, check_stride);
                run(problem, &check_config, &mut [&mut send])
            })
        });
        let mut steps = StepProgress::new(
            &format!("reference on {} elements", key.n_axis),
            problem.horizon,
        );
        let slab_observers = fine_observers(&recorder, lockstep.as_ref(), &comparison);
        let run = match ranks {
            None => run_box(
                problem,
                (&config, None),
                &mut [
                    &mut *recorder.borrow_mut(),
                    &mut *comparison.borrow_mut(),
                    &mut steps,
                ],
            ),
            Some(ranks) => run_box(
                problem,
                (&config, Some(&*distributed_run(ranks, &slab_observers))),
                &mut [&mut steps],
            ),
        };
        let distance = comparison.into_inner().finish();
        let in_one_process = check.map(|c| {
            c.join()
                .unwrap_or_else(|panic| std::panic::resume_unwind(panic))
        });
        (run, distance, in_one_process)
    });
    let run = run?.completed()?;
    let (check_dofs, check_steps, check_ranks) = match (in_one_process, lockstep) {
        (Some(check), _) => {
            let check = check?.completed()?;
            (check.dofs, check.steps, 1)
        }
        (None, Some(lockstep)) => (
            check_mesh.n_dofs(),
            lockstep.into_inner().finish()?,
            ranks.map_or(1, |r| r.size()),
        ),
        (None, None) => unreachable!("the check ran in one process or in lockstep"),
    };
    let cost = FineRunCost {
        timings: run.timings,
        solves: run.observed.step_solves.solves,
        iterations: run.observed.step_solves.iterations,
        check_ranks,
        contact_layers: run.observed.contact_slab.map(|t| t.layers),
    };
    let projections = recorder.into_inner().finish();
    let check = CheckOutcome {
        level: check_config.nx,
        dofs: check_dofs,
        steps: check_steps,
        distance: distance
            .into_iter()
            .map(|(norm, d)| (norm.key().to_string(), d))
            .collect(),
    };
    let seconds = clock.elapsed().as_secs_f64();
    let histories = sampled_histories(problem, key, (&run, &projections), check, seconds);
    Ok(Some(FineReference {
        mesh,
        histories,
        projections,
        from_cache: false,
        cost: Some(cost),
    }))
}

/// The scalar histories the reference keeps of its fine run `run`, every `key.sample_every`-th
/// step, with the layout of its `projections`, its `check` and the run's wall time `seconds`.
fn sampled_histories(
    problem: &BoxProblem,
    key: ReferenceKey,
    (run, projections): (&BoxRun, &[LevelProjections]),
    check: CheckOutcome,
    seconds: f64,
) -> ReferenceHistories {
    let every = key.sample_every.max(1);
    let gap = problem.obstacle_gap.unwrap_or(0.0);
    let pick = |v: &[f64]| v.iter().step_by(every).copied().collect::<Vec<f64>>();
    let centre_displacement: Vec<f64> = run
        .observed
        .contact
        .centre_gap
        .iter()
        .map(|g| g - gap)
        .collect();
    let energy: Vec<f64> = run.observed.energy.iter().map(|&(_, e)| e).collect();
    ReferenceHistories {
        dofs: run.dofs,
        steps: run.steps,
        dt: run.dt,
        seconds,
        time: run
            .observed
            .energy
            .iter()
            .step_by(every)
            .map(|&(t, _)| t)
            .collect(),
        energy: pick(&energy),
        total_force: pick(&run.observed.contact.total_force),
        centre_displacement: pick(&centre_displacement),
        centre_multiplier: pick(&run.observed.contact.centre_multiplier),
        projections: projections
            .iter()
            .map(|p| ProjectionLayout {
                level: p.level,
                dofs: p.dofs,
                samples: p.samples(),
            })
            .collect(),
        check,
        key,
        checksum: String::new(),
    }
}

/// The reference run's configuration of `key`, solved with `settings`.
fn fine_config(key: &ReferenceKey, settings: Settings) -> Result<RunConfig, Error> {
    Ok(RunConfig {
        nx: key.n_axis,
        ratio: key.ratio,
        scheme: key.scheme.parse()?,
        mass: key.mass.parse()?,
        observables: Observables::default(),
        settings,
    })
}

/// A distributed reference's slab observers on every rank, in their order: the projections,
/// the check run's steps when it is stepped by the reference's (before the comparison that
/// reads their samples), and the comparison.
fn fine_observers<'o, 'a: 'o, 'b: 'o, 'c: 'o>(
    recorder: &'o RefCell<ProjectionRecorder<'a>>,
    lockstep: Option<&'o RefCell<LockstepCheck<'b>>>,
    comparison: &'o RefCell<CheckComparison<'c>>,
) -> Vec<&'o RefCell<dyn SlabObserver + 'o>> {
    let mut observers: Vec<&'o RefCell<dyn SlabObserver + 'o>> = vec![recorder];
    if let Some(lockstep) = lockstep {
        observers.push(lockstep);
    }
    observers.push(comparison);
    observers
}

/// Every rank's check run (`config`) beside a distributed reference on `ranks`, observed by
/// `observers` (its `gather`), stepped by the reference's steps ([`LockstepCheck`]); `None`
/// when its box cannot be cut into the ranks' slabs (its contact slab leaves no layer for some
/// rank: every rank learns it together, before any step), in which case rank 0 runs it in one
/// process beside the reference, as a reference in one process does.
fn lockstep_check<'r>(
    problem: &BoxProblem,
    config: &RunConfig,
    (ranks, observers, gather): (
        &'r dyn Ranks,
        &'r SlabObservers<'r>,
        &'r RefCell<CheckGather<'r>>,
    ),
) -> Result<Option<RefCell<LockstepCheck<'r>>>, Error> {
    match lockstep_run(problem, config, (ranks, observers)) {
        Ok(run) => Ok(Some(RefCell::new(LockstepCheck::new(run, gather)))),
        Err(files::Error::Distributed(DecompositionError::TooManyRanks { .. })) => Ok(None),
        Err(e) => Err(e.into()),
    }
}
