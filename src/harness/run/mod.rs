//! Runs: a problem, a mesh level, a scheme and a mass variant, time stepped to the horizon
//! while observers accumulate only the requested error norms and histories; a bar's run here, a
//! box's in [`elastic`], both through the one loop [`drive`]. An [`Observer`] sees each state as
//! the engine's [`TimeIntegrator`]. What the runs produce (results, norms, their files, box runs
//! compared across nested meshes) is here too; above [`crate::harness::files`] only.
//!
//! | module | its face |
//! |---|---|
//! | this file | [`run`] (a bar), [`RunConfig`], [`Observables`], [`RunResult`] and its histories; [`drive`], [`Observer`], [`RunStatus`], [`time_grid`] |
//! | [`exact`] | the observers against an exact solution: [`exact::ErrorObservers`] and the recorders of the histories |
//! | [`norms`] | [`norms::Norm`], the seven norms; the space and time quadratures |
//! | [`elastic`] | [`elastic::run_box`] (a box), [`elastic::BoxRunResult`], VTK snapshots |
//! | [`paraview`] | a box run for ParaView: [`paraview::write_collection`], [`paraview::write_obstacle`] |
//! | [`run_files`] | the files of a run: [`run_files::RUN_JSON`], [`run_files::history_csv`], [`run_files::box_history_csv`] |
//! | [`nested_comparison`] | a box run against a finer one on nested meshes: [`nested_comparison::projection::ProjectionRecorder`], [`nested_comparison::check`], [`nested_comparison::error_series::ErrorSeries`] |

use std::collections::{BTreeMap, BTreeSet};
use std::path::PathBuf;
use std::time::Instant;

use serde::{Deserialize, Serialize};

mod driver;
pub mod elastic;
pub mod exact;
pub mod nested_comparison;
pub mod norms;
pub mod paraview;
pub mod run_files;

pub use driver::{drive, finite, time_grid, Observer, RunStatus, SnapshotTimes, Stepped, Timings};

use crate::engine::contact::ContactTreatment;
use crate::engine::error::ParameterError;
use crate::engine::fem::MassVariant;
pub use crate::engine::problem::Problem1d;
/// The discrete energy balances every run is checked against (eqs. 33/35/37), by scheme.
pub use crate::engine::schemes::{energy_balance, TimeIntegrator};

use crate::engine::problem::Settings;
use crate::engine::schemes::Scheme;
use crate::harness::files::error::Error;
use crate::harness::run::norms::Norm;
use exact::{ContactRecorder, EnergyRecorder, ErrorObservers, FieldRecorder, PointRecorder};

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

/// Everything one run measured.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RunResult {
    /// How the run ended; absent from the JSON of a completed run. A run that did not
    /// complete has no error norms, no multiplier variation and no balance residual.
    #[serde(default, skip_serializing_if = "RunStatus::is_completed")]
    pub status: RunStatus,
    /// `NX`.
    pub nx: usize,
    /// `h = L / NX`.
    pub h: f64,
    /// The time step actually used (`T / N`, `N = ⌈T ratio / h⌉`).
    pub dt: f64,
    /// Number of time steps `N`.
    pub steps: usize,
    /// Number of unknowns.
    pub dofs: usize,
    /// `steps × dofs`, the unit of cost per step.
    pub dof_steps: usize,
    /// The requested error norms.
    pub errors: BTreeMap<Norm, f64>,
    /// Steps that needed a complementarity solve.
    pub contact_solves: usize,
    /// The largest complementarity violation of any step (see
    /// [`TimeIntegrator::complementarity_violation`]).
    pub complementarity_violation: f64,
    /// Wall-clock split.
    pub timings: Timings,
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
    /// The contact treatment's name (`multiplier`, `penalty(gamma0=…)`, `nitsche(…)`).
    #[serde(default = "multiplier_name")]
    pub contact_treatment: String,
    /// The largest per-step residual of the scheme's energy balance (1D paper eqs. 33, 35,
    /// 37), relative to the energy scale
    /// ([`crate::engine::schemes::energy_balance::BalanceMonitor`]), when the run reports it
    /// ([`Observables::energy_balance`]); absent otherwise.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_balance_residual: Option<f64>,
}

impl RunResult {
    /// The result of a completed run; otherwise the failure that stopped it.
    pub fn completed(self) -> Result<Self, Error> {
        self.status.completed()?;
        Ok(self)
    }
}

fn multiplier_name() -> String {
    ContactTreatment::Multiplier.name()
}

/// Runs one configuration of a bar to its horizon: the one time loop ([`drive`]) with the
/// observers `config.observables` asks for, and nothing else evaluated.
pub fn run(problem: &Problem1d, config: &RunConfig) -> Result<RunResult, Error> {
    let started = Instant::now();
    let observables = &config.observables;
    if problem.obstacle_gap.is_none() && observables.norms.contains(&Norm::MultiplierL2) {
        return Err(ParameterError::new(
            "norm",
            Norm::MultiplierL2,
            "a norm the problem defines (lambda_L2 needs an obstacle)",
        )
        .into());
    }
    let discretisation = problem.discretise(config.nx, config.mass, &config.settings)?;
    let bar = &discretisation.mesh;
    let model = &discretisation.model;
    let exact = problem.exact.as_ref();
    let mut errors =
        ErrorObservers::new(bar, exact, &observables.norms, observables.contact_history);
    let mut contact = observables
        .contact_history
        .then(|| ContactRecorder::new(bar, exact));
    let mut energy_history = observables
        .energy_history
        .then(|| EnergyRecorder::new(exact));
    let mut points = (!observables.points.is_empty())
        .then(|| PointRecorder::new(bar, exact, &observables.points));
    let mut fields = FieldRecorder::new(bar, exact, &observables.fields_at);
    let stepped = {
        let mut observers: Vec<&mut dyn Observer> = vec![&mut fields];
        observers.extend(points.as_mut().map(|o| o as &mut dyn Observer));
        observers.extend(errors.observers());
        observers.extend(contact.as_mut().map(|o| o as &mut dyn Observer));
        observers.extend(energy_history.as_mut().map(|o| o as &mut dyn Observer));
        drive(
            &discretisation,
            problem.horizon,
            config.ratio,
            config.scheme,
            &mut observers,
            started,
        )?
    };
    let completed = stepped.status.is_completed();
    Ok(RunResult {
        status: stepped.status,
        nx: config.nx,
        h: bar.h(),
        dt: stepped.dt,
        steps: stepped.steps,
        dofs: model.n_dofs(),
        dof_steps: stepped.steps * model.n_dofs(),
        errors: if completed {
            errors.norms(&observables.norms)
        } else {
            BTreeMap::new()
        },
        contact_solves: stepped.contact_solves,
        complementarity_violation: stepped.complementarity_violation,
        timings: stepped.timings,
        space_norm_evaluations: errors.displacement.as_ref().map_or(0, |d| d.evaluations()),
        multiplier_variation: errors
            .multiplier
            .as_ref()
            .and_then(|m| m.variation())
            .filter(|_| completed),
        contact_history: contact.map(|c| c.history),
        energy_history: energy_history.map(|e| e.history),
        point_history: points.map(|p| p.history),
        fields: fields.snapshots,
        contact_treatment: problem.contact.name(),
        max_balance_residual: stepped
            .max_balance_residual
            .filter(|_| observables.energy_balance && completed),
    })
}
