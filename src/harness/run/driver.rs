//! The one time loop of every run, bar or box: the problem discretised at a level is stepped
//! to its horizon by a scheme, every state `t_n`, `n = 0..=N`, is checked for non-finite
//! values, measured for penetration, energy above the start and contact-force sign
//! ([`PhysicsMonitor`]) and handed to the run's observers.

use std::sync::OnceLock;
use std::time::Instant;

use serde::{Deserialize, Serialize};

use crate::engine::contact::Truncation;
use crate::engine::error::{require_positive, ParameterError, SolveError, StateField};
use crate::engine::linalg::SolveCounts;
use crate::engine::model::Model;
use crate::engine::problem::{AxialMesh, Discretisation};
use crate::engine::schemes::energy_balance::{self, BalanceMonitor, BALANCE_TOLERANCE};
use crate::engine::schemes::{
    integrator, Conventions, Integration, Integrator, Scheme, SchemeState,
};
use crate::harness::files::error::Error;
use crate::harness::run::physics::{Physics, PhysicsMonitor};

/// What a run does with each state of the scheme: accumulate a norm, record a history, write
/// a snapshot. Observers see the state at `t_0` (the initial data) and after every step.
pub trait Observer {
    /// Takes in the state `t_n` (with the scheme that computed it).
    fn observe(&mut self, state: &Integration<'_>) -> Result<(), Error>;
}

/// A closure is an observer (a one-off probe: a test, a sampled history).
impl<F: FnMut(&Integration<'_>) -> Result<(), Error>> Observer for F {
    fn observe(&mut self, state: &Integration<'_>) -> Result<(), Error> {
        self(state)
    }
}

/// Wall-clock time of the phases of a run, in seconds.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct Timings {
    /// Assembly, factorisation, Delassus operator and initial state.
    pub setup: f64,
    /// Time stepping, contact solves excluded.
    pub stepping: f64,
    /// Complementarity solves and their corrections.
    pub contact: f64,
    /// Observers (norms and histories).
    pub observe: f64,
}

impl Timings {
    /// The whole run.
    pub fn total(&self) -> f64 {
        self.setup + self.stepping + self.contact + self.observe
    }
}

/// The number of steps and the step that lands exactly on `horizon`.
pub fn time_grid(horizon: f64, h: f64, ratio: f64) -> (usize, f64) {
    let nominal = h / ratio;
    let steps = ((horizon / nominal) - 1e-9).ceil().max(1.0) as usize;
    (steps, horizon / steps as f64)
}

/// How a run ended: an outcome of the computation, reported the way a solver reports its
/// status, not an error. A run that did not complete reports no error norm.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(tag = "status", rename_all = "kebab-case")]
pub enum RunStatus {
    /// Every step was taken.
    #[default]
    Completed,
    /// A value became NaN or infinite at `step`: the run stopped there.
    Diverged {
        /// The step.
        step: usize,
        /// Its time.
        time: f64,
        /// `displacement`, `velocity` or `multiplier`.
        quantity: StateField,
    },
    /// The contact solver did not converge at `step`: the run stopped there.
    ContactNotConverged {
        /// The step.
        step: usize,
        /// Iterations spent.
        iterations: usize,
    },
    /// The step at `step` cannot be trusted: its linear solve missed its tolerance (the true
    /// residual checked), or the scheme's discrete energy balance (1D paper eqs. 33, 35, 37)
    /// is violated beyond [`BALANCE_TOLERANCE`]. The run stopped there.
    SolverInaccurate {
        /// The step.
        step: usize,
        /// Its time.
        time: f64,
        /// What missed its bound, with the value and the bound.
        detail: String,
    },
}

impl RunStatus {
    /// Whether every step was taken.
    pub fn is_completed(&self) -> bool {
        *self == RunStatus::Completed
    }

    /// `Ok` for a completed run; otherwise the failure, for callers that need every step (a
    /// refinement study cannot fit a rate through a run that stopped).
    pub fn completed(&self) -> Result<(), SolveError> {
        match self {
            RunStatus::Completed => Ok(()),
            RunStatus::Diverged {
                step,
                time,
                quantity,
            } => Err(SolveError::NonFinite {
                step: *step,
                time: *time,
                quantity: *quantity,
            }),
            RunStatus::ContactNotConverged { step, iterations } => {
                Err(SolveError::ContactNotConverged {
                    step: *step,
                    iterations: *iterations,
                })
            }
            RunStatus::SolverInaccurate { step, time, detail } => Err(SolveError::Inaccurate {
                step: *step,
                time: *time,
                detail: detail.clone(),
            }),
        }
    }

    /// The status of a run stopped by `error` during stepping; `None` for an error that is not
    /// an outcome of the computation.
    fn of(error: &SolveError) -> Option<Self> {
        match *error {
            SolveError::NonFinite {
                step,
                time,
                quantity,
            } => Some(RunStatus::Diverged {
                step,
                time,
                quantity,
            }),
            SolveError::ContactNotConverged { step, iterations } => {
                Some(RunStatus::ContactNotConverged { step, iterations })
            }
            SolveError::Inaccurate {
                step,
                time,
                ref detail,
            } => Some(RunStatus::SolverInaccurate {
                step,
                time,
                detail: detail.clone(),
            }),
            _ => None,
        }
    }
}

/// What the time loop itself measured.
#[derive(Debug, Clone, PartialEq)]
pub struct Stepped {
    /// How the run ended.
    pub status: RunStatus,
    /// Steps `N`.
    pub steps: usize,
    /// `Δt = T / N`.
    pub dt: f64,
    /// Steps that needed a complementarity solve.
    pub contact_solves: usize,
    /// Largest complementarity violation.
    pub complementarity_violation: f64,
    /// The step matrix's solves and their CG iterations.
    pub step_solves: SolveCounts,
    /// The slab of the local contact operator, if one was used.
    pub contact_truncation: Option<Truncation>,
    /// The largest per-step residual of the scheme's energy balance relative to the energy
    /// scale ([`BalanceMonitor::largest_residual`]) over the steps taken; `None` where the
    /// balances are not identities of the run ([`energy_balance::holds_under`]).
    pub max_balance_residual: Option<f64>,
    /// Penetration, energy above the start and contact-force sign over the states that were
    /// taken ([`PhysicsMonitor`]).
    pub physics: Physics,
    /// Wall-clock split; `setup` counts from `started`.
    pub timings: Timings,
}

/// The name of a snapshot `<prefix>-t<time>.<extension>` of a run of time step `dt` and horizon
/// `horizon`: the time with as many decimals as tell its steps apart (one past the place of
/// `Δt`'s first significant digit: `field-t0.150.vtu` for `Δt = 0.05`), its integer part padded
/// with zeros to the horizon's width, so that the names sort in time order.
pub fn snapshot_name(
    prefix: &str,
    time: f64,
    (dt, horizon): (f64, f64),
    extension: &str,
) -> String {
    let decimals = (-dt.log10()).ceil().max(0.0) as usize + 1;
    let integer_digits = horizon.max(1.0).log10().floor() as usize + 1;
    let width = integer_digits + 1 + decimals;
    format!("{prefix}-t{time:0width$.decimals$}.{extension}")
}

/// Requested snapshot times, each due at the step nearest to it.
#[derive(Debug, Clone, Default)]
pub struct SnapshotTimes {
    /// From the last to the first, so that the next one due is popped.
    pending: Vec<f64>,
}

impl SnapshotTimes {
    /// The times `times`, in any order.
    pub fn new(times: &[f64]) -> Self {
        let mut pending = times.to_vec();
        pending.sort_by(|a, b| b.total_cmp(a));
        Self { pending }
    }

    /// The next requested time that the state at `t_n` is the nearest step to
    /// (`t_n + Δt/2 ≥ t`), removed from the pending ones; `None` when none is due.
    pub fn next_due(&mut self, state: &SchemeState) -> Option<f64> {
        let wanted = *self.pending.last()?;
        (state.time() + 0.5 * state.dt() >= wanted).then(|| {
            self.pending.pop();
            wanted
        })
    }
}

/// `value`, observed as `quantity` from `state`, when finite; otherwise the error that stops
/// the run at `state`'s step ([`RunStatus::Diverged`]). Observers check what they compute with
/// it, so that no non-finite value reaches a result.
pub fn finite(state: &SchemeState, quantity: StateField, value: f64) -> Result<f64, Error> {
    if value.is_finite() {
        Ok(value)
    } else {
        Err(SolveError::NonFinite {
            step: state.step_index(),
            time: state.time(),
            quantity,
        }
        .into())
    }
}

/// A step solve that missed its tolerance ([`SolveError::NotConverged`]) as the inaccurate
/// solve that stops the run at `step` (time `time`); any other error as it is.
fn inaccurate_solve(error: SolveError, step: usize, time: f64) -> SolveError {
    match error {
        SolveError::NotConverged {
            solver,
            iterations,
            residual,
        } => SolveError::Inaccurate {
            step,
            time,
            detail: format!(
                "the step solve ({solver}) reached a true relative residual of {residual:.3e} \
                 in {iterations} iterations, above its tolerance"
            ),
        },
        other => other,
    }
}

/// Takes the state into `monitor` and checks the step's energy balance (1D paper eqs. 33, 35,
/// 37): a relative residual above [`BALANCE_TOLERANCE`] (or NaN) is returned as the inaccurate
/// solve that the run ends with, unless the run diverges first (a growing unstable mode takes
/// the balance's round-off with it before the state overflows: the run is then diverged, not
/// inaccurate). A step the scheme takes outside its balance
/// ([`crate::engine::schemes::TimeIntegrator::balance_holds`]) is recorded, not checked.
fn balance_violation(
    monitor: &mut BalanceMonitor,
    state: &Integration<'_>,
    scheme: Scheme,
) -> Option<SolveError> {
    monitor.observe(state)?;
    let residual = monitor.last_residual();
    if residual <= BALANCE_TOLERANCE || !state.balance_holds() {
        return None;
    }
    Some(SolveError::Inaccurate {
        step: state.step_index(),
        time: state.time(),
        detail: format!(
            "the energy balance eq. {} is violated: its residual is {residual:.3e} of its \
             scale (the energy, or the size of the products it sums), above the round-off \
             bound {BALANCE_TOLERANCE:e}",
            energy_balance::equation(scheme)
        ),
    })
}

/// The environment variable that turns the per-step checks off: the benchmark's internal
/// switch (`scripts/bench.py`), which measures what the checks cost by running the same
/// binary with them on and off. Set to `off`, the loop skips the non-finite check, the energy
/// balance and the physics monitor: a run then reports no balance residual and zero physics
/// figures, and a non-finite state goes unnoticed. It is not a user option (no flag, no
/// documentation outside the benchmark's).
pub const CHECKS_SWITCH: &str = "SIGNORINI_BENCHMARK_CHECKS";

/// Whether the per-step checks run: unless [`CHECKS_SWITCH`] is `off` (read once per process).
fn checks_on() -> bool {
    static ON: OnceLock<bool> = OnceLock::new();
    *ON.get_or_init(|| std::env::var_os(CHECKS_SWITCH).is_none_or(|v| v != "off"))
}

/// Whether every value is finite: `0 · v` is ±0 for a finite `v` and NaN for an infinite or NaN
/// one, so their sum is 0 exactly when all are finite. Summed in independent lanes without an
/// early exit, the loop is vectorised (the per-step check costs a fraction of a pass over the
/// state).
fn all_finite(values: &[f64]) -> bool {
    const LANES: usize = 8;
    let mut lanes = [0.0; LANES];
    let blocks = values.chunks_exact(LANES);
    let rest: f64 = blocks.remainder().iter().map(|v| 0.0 * v).sum();
    for block in blocks {
        for (lane, v) in lanes.iter_mut().zip(block) {
            *lane += 0.0 * v;
        }
    }
    lanes.iter().sum::<f64>() + rest == 0.0
}

/// The first non-finite value of the state, as the error that stops the run.
fn check_finite(state: &SchemeState) -> Result<(), SolveError> {
    let fields: [(StateField, &[f64]); 3] = [
        (StateField::Displacement, state.displacement()),
        (StateField::Velocity, state.velocity()),
        (StateField::Multiplier, state.multiplier().value),
    ];
    for (quantity, values) in fields {
        if !all_finite(values) {
            return Err(SolveError::NonFinite {
                step: state.step_index(),
                time: state.time(),
                quantity,
            });
        }
    }
    Ok(())
}

/// Steps `discretisation` from its initial dofs to `horizon` with `scheme` and
/// `Δt = T / ⌈T ratio / Δx⌉` ([`time_grid`], `Δx` the element size along the axis), handing
/// every state to each of `observers` in order. With a per-step perturbation
/// ([`Discretisation::step_perturbation`], an ensemble member's), the state each step carries
/// forward is perturbed right after the step, before the checks and the observers see it
/// ([`crate::engine::schemes::TimeIntegrator::perturb_carried`]); observers only read. The first non-finite displacement, velocity
/// or multiplier (the initial state's included), a non-finite value an observer computes
/// ([`finite`]), or a contact solve that does not converge, stops the run with that
/// [`RunStatus`]. A `ratio` that makes `Δt` longer than the horizon is refused; a failure to
/// set the scheme up (a parameter, the CFL bound, a factorisation) is an error. `started` is
/// when the run's setup began (its discretisation included).
pub fn drive<M: AxialMesh>(
    discretisation: &Discretisation<M>,
    horizon: f64,
    ratio: f64,
    scheme: Scheme,
    observers: &mut [&mut dyn Observer],
    started: Instant,
) -> Result<Stepped, Error> {
    drive_by(
        discretisation,
        horizon,
        ratio,
        (scheme, None),
        observers,
        started,
    )
}

/// Builds a run's integrator and its state at `t = 0` from its model, scheme, `Δt`, initial
/// data and conventions in place of the one-process schemes ([`integrator`]): a distributed
/// run's ([`crate::harness::run::distributed`]).
pub type IntegratorFactory<'r> =
    dyn Fn(&Model, Scheme, f64, &[f64], &[f64], &Conventions) -> Result<Integrator<'r>, Error> + 'r;

/// [`drive`] with the integrator `make` builds, when given, instead of the one-process
/// scheme's.
pub fn drive_by<'r, M: AxialMesh>(
    discretisation: &Discretisation<M>,
    horizon: f64,
    ratio: f64,
    (scheme, make): (Scheme, Option<&IntegratorFactory<'r>>),
    observers: &mut [&mut dyn Observer],
    started: Instant,
) -> Result<Stepped, Error> {
    require_positive("ratio", ratio)?;
    require_positive("horizon", horizon)?;
    let scheme = scheme.validate()?;
    let h = discretisation.mesh.axial_element_size();
    let steps_per_horizon = horizon * ratio / h;
    if steps_per_horizon.is_nan() || steps_per_horizon < 1.0 - 1e-9 {
        return Err(ParameterError::new(
            "ratio",
            format!(
                "{ratio}: Δt = Δx/ratio = {:.3e} is longer than the horizon T = {horizon} \
                 (Δx = {h:.3e}; the smallest ratio is Δx/T = {:.3e})",
                h / ratio,
                h / horizon
            ),
            "Δx/Δt >= Δx/T, at least one time step",
        )
        .into());
    }
    let (steps, dt) = time_grid(horizon, h, ratio);
    let (model, u0, v0) = (
        &discretisation.model,
        &discretisation.displacement,
        &discretisation.velocity,
    );
    let conventions = &discretisation.conventions;
    let (mut integ, mut state): Integrator<'_> = match make {
        Some(make) => make(model, scheme, dt, u0, v0, conventions)?,
        None => integrator(model, scheme, dt, u0, v0, conventions)?,
    };
    let setup = started.elapsed().as_secs_f64();

    let (mut stepping, mut observe) = (0.0, 0.0);
    let mut status = RunStatus::Completed;
    let model = &discretisation.model;
    let checked = checks_on();
    let finite_if = |state: &SchemeState| match checked {
        true => check_finite(state),
        false => Ok(()),
    };
    let mut balance = (checked && energy_balance::holds_under(&discretisation.conventions, model))
        .then(|| BalanceMonitor::new(model, scheme, dt));
    let mut violation = None;
    let mut physics = PhysicsMonitor::new(model);
    let mut step_noise = discretisation.step_perturbation.map(|p| p.stream());
    'steps: for step in 0..=steps {
        let clock = Instant::now();
        let stepped = if step > 0 {
            integ
                .advance(&mut state)
                .map_err(|e| inaccurate_solve(e, step, step as f64 * dt))
                .map(|()| {
                    if let Some(noise) = step_noise.as_mut() {
                        integ.perturb_carried(&mut state, &mut |values| noise.perturb(values));
                    }
                })
                .and_then(|()| finite_if(&state))
        } else {
            finite_if(&state)
        };
        let observed = Integration {
            scheme: integ.as_ref(),
            state: &state,
        };
        if let (Ok(()), Some(monitor), None) = (&stepped, balance.as_mut(), &violation) {
            violation = balance_violation(monitor, &observed, scheme);
        }
        if checked && stepped.is_ok() {
            let balanced = balance.as_ref().and_then(|m| m.energy_of(step));
            physics.observe(&observed, balanced);
        }
        stepping += clock.elapsed().as_secs_f64();
        if let Err(e) = stepped {
            status = RunStatus::of(&e).ok_or(e)?;
            break;
        }
        let clock = Instant::now();
        for o in observers.iter_mut() {
            match o.observe(&observed) {
                Ok(()) => {}
                Err(Error::Solve(e)) => match RunStatus::of(&e) {
                    Some(stopped) => {
                        status = stopped;
                        break 'steps;
                    }
                    None => return Err(e.into()),
                },
                Err(e) => return Err(e),
            }
        }
        observe += clock.elapsed().as_secs_f64();
    }
    if let (RunStatus::Completed, Some(e)) = (&status, violation) {
        status = RunStatus::of(&e).ok_or(e)?;
    }
    let statistics = integ.statistics();
    Ok(Stepped {
        status,
        steps,
        dt,
        contact_solves: statistics.contact_solves,
        complementarity_violation: statistics.complementarity_violation,
        step_solves: statistics.step_solves,
        contact_truncation: statistics.contact_truncation,
        max_balance_residual: balance.as_ref().map(BalanceMonitor::largest_residual),
        physics: physics.physics(),
        timings: Timings {
            setup,
            stepping: stepping - statistics.contact_seconds,
            contact: statistics.contact_seconds,
            observe,
        },
    })
}
