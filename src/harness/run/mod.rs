//! Runs: a problem, a mesh level, a scheme and a mass variant, time stepped to the horizon
//! while observers accumulate only the requested error norms and histories: one [`run`] of a
//! bar, a box or either ([`RunProblem`]), one [`RunResult`] whose geometry's observations are
//! one field, all through the one loop [`drive`], which holds the [`SchemeState`] and hands it to
//! the engine's [`TimeIntegrator`]. An [`Observer`] sees each state with its scheme
//! ([`Integration`]). What the runs produce (results, norms, their files, box runs
//! compared across nested meshes) is here too; above [`crate::harness::files`] only.
//!
//! | module | its face |
//! |---|---|
//! | this file | [`run`], [`RunProblem`], [`RunConfig`], [`Observables`], [`RunResult`], [`Observed`], [`BarObservations`] and a bar's histories; [`drive`], [`Observer`], [`RunStatus`], [`time_grid`] |
//! | [`exact`] | the observers against an exact solution: [`exact::ErrorObservers`] and the recorders of the histories |
//! | [`norms`] | [`norms::Norm`], the seven norms; the space and time quadratures |
//! | `bar` | a bar's run against its exact solution |
//! | [`elastic`] | a box's run and what it observes, [`elastic::BoxObservations`]; VTK snapshots |
//! | [`physics`] | what the loop measures of every run's physics: [`physics::Physics`] (penetration, energy above the start, contact-force sign) |
//! | [`paraview`] | a box run for ParaView: [`paraview::write_collection`], [`paraview::write_obstacle`] |
//! | [`run_files`] | the files of a run: [`run_files::RUN_JSON`], [`run_files::history_csv`], [`run_files::box_history_csv`] |
//! | [`nested_comparison`] | a box run against a finer one on nested meshes: [`nested_comparison::projection::ProjectionRecorder`], [`nested_comparison::check`], [`nested_comparison::error_series::ErrorSeries`] |

use std::collections::{BTreeMap, BTreeSet};
use std::path::PathBuf;
use std::time::Instant;

use serde::{Deserialize, Serialize};

mod bar;
pub mod distributed;
mod driver;
pub mod elastic;
pub mod exact;
pub mod nested_comparison;
pub mod norms;
pub mod paraview;
pub mod physics;
pub mod run_files;

pub use driver::{
    drive, drive_by, finite, snapshot_name, time_grid, IntegratorFactory, Observer, RunStatus,
    SnapshotTimes, Stepped, Timings,
};

use crate::engine::contact::ContactTreatment;
use crate::engine::fem::MassVariant;
use crate::engine::problem::{AxialMesh, Discretisation};
pub use crate::engine::problem::{Problem, Problem1d};
/// The discrete energy balances every run is checked against (eqs. 33/35/37), by scheme.
pub use crate::engine::schemes::{energy_balance, Integration, SchemeState, TimeIntegrator};

use crate::engine::problem::Settings;
use crate::engine::schemes::Scheme;
use crate::harness::files::error::Error;
use crate::harness::run::norms::Norm;

/// What a run records besides the requested norms.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Observables {
    /// The error norms to compute; nothing else is evaluated.
    pub norms: BTreeSet<Norm>,
    /// Record the contact node's displacement and multiplier with the exact ones.
    pub contact_history: bool,
    /// Record the energy with the exact one.
    pub energy_history: bool,
    /// Record the displacement history at these positions.
    pub points: Vec<f64>,
    /// Record the whole field at the steps nearest to these times: in the result for a bar,
    /// as VTK files in `fields_dir` for a box.
    pub fields_at: Vec<f64>,
    /// Where a box's field snapshots go (the working directory when absent).
    pub fields_dir: Option<PathBuf>,
    /// Evaluate the scheme's energy balance ([`crate::engine::schemes::energy_balance`]) after every
    /// step and report its largest residual (`signorini run --check-balance`, the stability
    /// suite).
    pub energy_balance: bool,
}

impl Observables {
    /// All seven norms, no history.
    pub fn all_norms() -> Self {
        Self {
            norms: Norm::ALL.into_iter().collect(),
            ..Self::default()
        }
    }
}

/// One level of a study.
#[derive(Debug, Clone, PartialEq)]
pub struct RunConfig {
    /// Number of elements `NX`.
    pub nx: usize,
    /// `Δx / Δt` (the paper: 10 for §5, 1 for §4).
    pub ratio: f64,
    /// The time integrator.
    pub scheme: Scheme,
    /// The mass matrix.
    pub mass: MassVariant,
    /// What to record.
    pub observables: Observables,
    /// How the run is solved: conventions, step solver, contact operator, round-off
    /// perturbation ([`Settings::default`]: the harness's).
    pub settings: Settings,
}

/// The contact node's history.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct ContactHistory {
    /// `t_n` of the displacement samples.
    pub time: Vec<f64>,
    /// `u_h(0, t_n)`.
    pub displacement: Vec<f64>,
    /// `u(0, t_n)`.
    pub displacement_exact: Vec<f64>,
    /// The times of the multiplier samples (they differ from `time` for Paoli–Schatzman).
    pub multiplier_time: Vec<f64>,
    /// `λ_h`.
    pub multiplier: Vec<f64>,
    /// `λ` at `multiplier_time`.
    pub multiplier_exact: Vec<f64>,
}

/// The displacement history at fixed positions.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct PointHistory {
    /// The positions.
    pub x: Vec<f64>,
    /// `t_n`.
    pub time: Vec<f64>,
    /// `u_h(x_p, t_n)`, one series per position.
    pub displacement: Vec<Vec<f64>>,
    /// `u(x_p, t_n)`.
    pub displacement_exact: Vec<Vec<f64>>,
}

/// The whole field at one step.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct FieldSnapshot {
    /// The time asked for.
    pub requested_time: f64,
    /// The time of the step recorded (the nearest).
    pub time: f64,
    /// Node positions.
    pub x: Vec<f64>,
    /// `u_h` at the nodes.
    pub displacement: Vec<f64>,
    /// `u` at the nodes.
    pub displacement_exact: Vec<f64>,
    /// Element midpoints.
    pub x_mid: Vec<f64>,
    /// `∂x u_h` on each element.
    pub strain: Vec<f64>,
    /// `∂x u` at the element midpoints.
    pub strain_exact: Vec<f64>,
}

/// Total variations `Σ |λ^{k+1} − λ^k|` over the run, and the largest `|λ_h|`.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct MultiplierVariation {
    /// Of the computed multiplier `λ_h`.
    pub discrete: f64,
    /// Of the exact multiplier sampled at the same times.
    pub exact: f64,
    /// `max |λ_h|`.
    pub max_abs: f64,
}

impl MultiplierVariation {
    /// `TV(λ_h) / TV(λ)`: 1 for a multiplier that moves as much as the exact one; large for an
    /// oscillating one. `None` when the exact multiplier does not vary.
    pub fn ratio(&self) -> Option<f64> {
        (self.exact > 0.0).then(|| self.discrete / self.exact)
    }
}

/// The energy history.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct EnergyHistory {
    /// Sample times (`t_{n−½}` for Paoli–Schatzman).
    pub time: Vec<f64>,
    /// `E_h`.
    pub energy: Vec<f64>,
    /// `E`.
    pub energy_exact: Vec<f64>,
}

/// Everything one run measured: what every run has, and what its geometry observes (`O`:
/// [`BarObservations`] for a bar's run, [`elastic::BoxObservations`] for a box's, [`Observed`]
/// for a run of either), written beside the rest.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RunResult<O = Observed> {
    /// How the run ended; absent from the JSON of a completed run. A run that did not
    /// complete has no error norms, no multiplier variation and no balance residual.
    #[serde(default, skip_serializing_if = "RunStatus::is_completed")]
    pub status: RunStatus,
    /// The time step actually used (`T / N`, `N = ⌈T ratio / h⌉`, `h` along the axis).
    pub dt: f64,
    /// Number of time steps `N`.
    pub steps: usize,
    /// Number of unknowns.
    pub dofs: usize,
    /// Steps that needed a complementarity solve.
    pub contact_solves: usize,
    /// The largest complementarity violation of any step (see
    /// [`crate::engine::schemes::StepStatistics::complementarity_violation`]).
    pub complementarity_violation: f64,
    /// Wall-clock split (setup includes assembly, factorisation and the Delassus operator).
    pub timings: Timings,
    /// The contact treatment's name (`multiplier`, `penalty(gamma0=…)`, `nitsche(…)`).
    #[serde(default = "multiplier_name")]
    pub contact_treatment: String,
    /// The largest per-step residual of the scheme's energy balance (1D paper eqs. 33, 35,
    /// 37), relative to the energy scale
    /// ([`crate::engine::schemes::energy_balance::BalanceMonitor`]): a bar's when
    /// [`Observables::energy_balance`] asks for it, a box's always, where the balances are
    /// identities of the run's conventions; absent otherwise.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_balance_residual: Option<f64>,
    /// Penetration, energy above the start and contact-force sign, measured by the time loop
    /// on every state it took ([`physics::Physics`]); absent only from a file written before
    /// the loop measured them.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub physics: Option<physics::Physics>,
    /// What the run's geometry observes.
    #[serde(flatten)]
    pub observed: O,
}

/// A bar's run.
pub type BarRun = RunResult<BarObservations>;

/// A box's run.
pub type BoxRun = RunResult<elastic::BoxObservations>;

/// What a run of either geometry observes: a bar's error norms against its exact solution
/// and its histories, or a box's energy, contact face and VTK files. Written untagged: a
/// run's JSON has its geometry's fields beside the common ones.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
#[allow(clippy::large_enum_variant)] // one per run, moved whole
pub enum Observed {
    /// A 1D bar ([`Problem1d`]).
    Bar(BarObservations),
    /// A 2D/3D box ([`elastic::BoxProblem`]).
    Box(elastic::BoxObservations),
}

/// What a bar run observes against its exact solution.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct BarObservations {
    /// `NX`.
    pub nx: usize,
    /// `h = L / NX`.
    pub h: f64,
    /// `steps × dofs`, the unit of cost per step.
    pub dof_steps: usize,
    /// The requested error norms.
    pub errors: BTreeMap<Norm, f64>,
    /// Space-norm evaluations (one per step when a displacement norm is requested).
    pub space_norm_evaluations: usize,
    /// Total variation of the computed and of the exact multiplier, when the multiplier is
    /// observed (the oscillation indicator's ingredients).
    pub multiplier_variation: Option<MultiplierVariation>,
    /// Contact node history, when requested.
    pub contact_history: Option<ContactHistory>,
    /// Energy history, when requested.
    pub energy_history: Option<EnergyHistory>,
    /// Displacement histories at the requested positions.
    pub point_history: Option<PointHistory>,
    /// Fields at the requested times.
    pub fields: Vec<FieldSnapshot>,
}

impl<O> RunResult<O> {
    /// The result of a completed run; otherwise the failure that stopped it.
    pub fn completed(self) -> Result<Self, Error> {
        self.status.completed()?;
        Ok(self)
    }

    /// The result of a run of `dofs` unknowns that `stepped` describes, with its contact
    /// treatment's name, its balance residual when it reports one, and its geometry's
    /// observations.
    fn of(
        stepped: &Stepped,
        dofs: usize,
        contact_treatment: String,
        max_balance_residual: Option<f64>,
        observed: O,
    ) -> Self {
        RunResult {
            status: stepped.status.clone(),
            dt: stepped.dt,
            steps: stepped.steps,
            dofs,
            contact_solves: stepped.contact_solves,
            complementarity_violation: stepped.complementarity_violation,
            timings: stepped.timings,
            contact_treatment,
            max_balance_residual,
            physics: Some(stepped.physics),
            observed,
        }
    }

    /// The same result with its observations mapped by `f`.
    fn map_observed<Q>(self, f: impl FnOnce(O) -> Q) -> RunResult<Q> {
        RunResult {
            status: self.status,
            dt: self.dt,
            steps: self.steps,
            dofs: self.dofs,
            contact_solves: self.contact_solves,
            complementarity_violation: self.complementarity_violation,
            timings: self.timings,
            contact_treatment: self.contact_treatment,
            max_balance_residual: self.max_balance_residual,
            physics: self.physics,
            observed: f(self.observed),
        }
    }
}

/// Drives `discretisation` to `horizon` as `config` asks through the one loop ([`drive`]), its
/// run's own observers `own` followed by the caller's `extra`.
fn drive_with<'a, 'r, M: AxialMesh>(
    discretisation: &Discretisation<M>,
    horizon: f64,
    (config, make): (&RunConfig, Option<&IntegratorFactory<'r>>),
    mut own: Vec<&'a mut dyn Observer>,
    extra: &'a mut [&mut dyn Observer],
    started: Instant,
) -> Result<Stepped, Error> {
    for o in extra.iter_mut() {
        own.push(&mut **o);
    }
    drive_by(
        discretisation,
        horizon,
        config.ratio,
        (config.scheme, make),
        &mut own,
        started,
    )
}

/// A problem a run takes, and what its run observes: a bar ([`Problem1d`]), a box
/// ([`elastic::BoxProblem`]) or either ([`Problem`]).
pub trait RunProblem {
    /// What a run of it observes besides what every run has.
    type Observations;

    /// Its run of `config` with `observers` after its own: see [`run`].
    fn run_observed(
        &self,
        config: &RunConfig,
        observers: &mut [&mut dyn Observer],
    ) -> Result<RunResult<Self::Observations>, Error>;
}

impl RunProblem for Problem1d {
    type Observations = BarObservations;

    fn run_observed(
        &self,
        config: &RunConfig,
        observers: &mut [&mut dyn Observer],
    ) -> Result<RunResult<BarObservations>, Error> {
        bar::run_bar(self, config, observers)
    }
}

impl RunProblem for elastic::BoxProblem {
    type Observations = elastic::BoxObservations;

    fn run_observed(
        &self,
        config: &RunConfig,
        observers: &mut [&mut dyn Observer],
    ) -> Result<RunResult<elastic::BoxObservations>, Error> {
        elastic::run_box(self, (config, None), observers)
    }
}

impl RunProblem for Problem {
    type Observations = Observed;

    fn run_observed(
        &self,
        config: &RunConfig,
        observers: &mut [&mut dyn Observer],
    ) -> Result<RunResult, Error> {
        Ok(match self {
            Problem::Bar(bar) => run(bar, config, observers)?.map_observed(Observed::Bar),
            Problem::Box(body) => run(body, config, observers)?.map_observed(Observed::Box),
        })
    }
}

fn multiplier_name() -> String {
    ContactTreatment::Multiplier.name()
}

/// Runs one configuration of `problem` to its horizon: the one time loop ([`drive`]) with the
/// observers `config.observables` asks for (a bar's against its exact solution, a box's
/// energy, contact face and VTK snapshots, [`elastic`]) followed by `observers`, whose time
/// counts as observation. Nothing else is evaluated.
pub fn run<P: RunProblem + ?Sized>(
    problem: &P,
    config: &RunConfig,
    observers: &mut [&mut dyn Observer],
) -> Result<RunResult<P::Observations>, Error> {
    problem.run_observed(config, observers)
}
