//! One run: a problem, a mesh level, a scheme and a mass variant, time stepped to the horizon
//! while observers accumulate only the requested error norms and histories.

use std::collections::{BTreeMap, BTreeSet};
use std::time::Instant;

use serde::{Deserialize, Serialize};

use crate::engine::contact::ContactTreatment;
use crate::engine::error::{require_positive, ParameterError, SolveError};
use crate::engine::exact::ExactSolution;
use crate::engine::fem::{Bar1d, MassVariant};
pub use crate::engine::problem::Problem1d;
use crate::engine::schemes::energy_balance::BalanceMonitor;
use crate::engine::schemes::{integrator, Scheme, TimeIntegrator};
use crate::harness::error::Error;
use crate::harness::norms::{Norm, SpaceErrorIntegrator, TimeSeriesNorm};

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
    /// Record the whole field at the steps nearest to these times.
    pub fields_at: Vec<f64>,
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

/// Everything one run measured.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RunResult {
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
    /// 37), relative to the energy scale ([`BalanceMonitor`]), when the run evaluated it
    /// ([`Observables::energy_balance`]); absent otherwise.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_balance_residual: Option<f64>,
}

fn multiplier_name() -> String {
    ContactTreatment::Multiplier.name()
}

/// The number of steps and the step that lands exactly on `horizon`.
pub fn time_grid(horizon: f64, h: f64, ratio: f64) -> (usize, f64) {
    let nominal = h / ratio;
    let steps = ((horizon / nominal) - 1e-9).ceil().max(1.0) as usize;
    (steps, horizon / steps as f64)
}

struct Observer<'a> {
    bar: &'a Bar1d,
    exact: &'a dyn ExactSolution,
    wants_space: bool,
    wants_multiplier: bool,
    wants_energy: bool,
    space: SpaceErrorIntegrator,
    u_h: TimeSeriesNorm,
    u_v: TimeSeriesNorm,
    lambda: TimeSeriesNorm,
    energy: TimeSeriesNorm,
    variation: MultiplierVariation,
    last_multiplier: Option<(f64, f64, f64)>,
    contact: Option<ContactHistory>,
    energy_history: Option<EnergyHistory>,
    points: Option<PointHistory>,
    pending_fields: Vec<f64>,
    fields: Vec<FieldSnapshot>,
}

impl<'a> Observer<'a> {
    fn new(bar: &'a Bar1d, exact: &'a dyn ExactSolution, obs: &Observables) -> Self {
        let has = |n: &[Norm]| n.iter().any(|x| obs.norms.contains(x));
        Self {
            bar,
            exact,
            wants_space: has(&[
                Norm::DisplacementLinfH,
                Norm::DisplacementL2H,
                Norm::DisplacementLinfV,
                Norm::DisplacementL2V,
            ]),
            wants_multiplier: has(&[Norm::MultiplierL2]),
            wants_energy: has(&[Norm::EnergyLinf, Norm::EnergyL2]),
            space: SpaceErrorIntegrator::new(),
            u_h: TimeSeriesNorm::default(),
            u_v: TimeSeriesNorm::default(),
            lambda: TimeSeriesNorm::default(),
            energy: TimeSeriesNorm::default(),
            variation: MultiplierVariation::default(),
            last_multiplier: None,
            contact: obs.contact_history.then(ContactHistory::default),
            energy_history: obs.energy_history.then(EnergyHistory::default),
            points: (!obs.points.is_empty()).then(|| PointHistory {
                x: obs.points.clone(),
                displacement: vec![Vec::new(); obs.points.len()],
                displacement_exact: vec![Vec::new(); obs.points.len()],
                ..PointHistory::default()
            }),
            pending_fields: {
                let mut t = obs.fields_at.clone();
                t.sort_by(|a, b| b.total_cmp(a));
                t
            },
            fields: Vec::new(),
        }
    }

    fn record_points(&mut self, scheme: &dyn TimeIntegrator) {
        let Some(p) = self.points.as_mut() else {
            return;
        };
        let t = scheme.time();
        p.time.push(t);
        for (k, &x) in p.x.iter().enumerate() {
            p.displacement[k].push(self.bar.value_at(scheme.displacement(), x));
            p.displacement_exact[k].push(self.exact.eval(x, t).u);
        }
    }

    fn record_fields(&mut self, scheme: &dyn TimeIntegrator) {
        let t = scheme.time();
        while let Some(&wanted) = self.pending_fields.last() {
            if t + 0.5 * scheme.dt() < wanted {
                break;
            }
            self.pending_fields.pop();
            let u = scheme.displacement();
            let bar = self.bar;
            let nodes: Vec<f64> = (0..=bar.nx()).map(|i| bar.node(i)).collect();
            let mids: Vec<f64> = nodes.windows(2).map(|w| 0.5 * (w[0] + w[1])).collect();
            self.fields.push(FieldSnapshot {
                requested_time: wanted,
                time: t,
                displacement: (0..=bar.nx()).map(|i| bar.nodal_value(u, i)).collect(),
                displacement_exact: nodes.iter().map(|&x| self.exact.eval(x, t).u).collect(),
                strain: (0..bar.nx())
                    .map(|e| (bar.nodal_value(u, e + 1) - bar.nodal_value(u, e)) / bar.h())
                    .collect(),
                strain_exact: mids.iter().map(|&x| self.exact.eval(x, t).ux).collect(),
                x: nodes,
                x_mid: mids,
            });
        }
    }

    fn observe(&mut self, scheme: &dyn TimeIntegrator) {
        self.record_points(scheme);
        self.record_fields(scheme);
        let t = scheme.time();
        if self.wants_space {
            let e = self
                .space
                .errors(self.bar, scheme.displacement(), self.exact, t);
            self.u_h.push(t, e.l2);
            self.u_v.push(t, e.h1);
        }
        if self.wants_multiplier || self.contact.is_some() {
            let m = scheme.multiplier();
            let lambda_h = m.value.first().copied().unwrap_or(0.0);
            let lambda = self.exact.contact_multiplier(m.time);
            self.lambda.push(m.time, lambda_h - lambda);
            match self.last_multiplier {
                Some((t0, _, _)) if m.time <= t0 => {}
                Some((_, h0, e0)) => {
                    self.variation.discrete += (lambda_h - h0).abs();
                    self.variation.exact += (lambda - e0).abs();
                    self.last_multiplier = Some((m.time, lambda_h, lambda));
                }
                None => self.last_multiplier = Some((m.time, lambda_h, lambda)),
            }
            self.variation.max_abs = self.variation.max_abs.max(lambda_h.abs());
            if let Some(c) = self.contact.as_mut() {
                c.time.push(t);
                c.displacement
                    .push(self.bar.nodal_value(scheme.displacement(), 0));
                c.displacement_exact.push(self.exact.eval(0.0, t).u);
                if c.multiplier_time.last().is_none_or(|&last| m.time > last) {
                    c.multiplier_time.push(m.time);
                    c.multiplier.push(lambda_h);
                    c.multiplier_exact.push(lambda);
                }
            }
        }
        if self.wants_energy || self.energy_history.is_some() {
            let e = scheme.energy();
            let exact = self.exact.energy(e.time);
            self.energy.push(e.time, e.value - exact);
            if let Some(h) = self.energy_history.as_mut() {
                if h.time.last().is_none_or(|&last| e.time > last) {
                    h.time.push(e.time);
                    h.energy.push(e.value);
                    h.energy_exact.push(exact);
                }
            }
        }
    }

    fn errors(&self, norms: &BTreeSet<Norm>) -> BTreeMap<Norm, f64> {
        norms
            .iter()
            .map(|&n| {
                let v = match n {
                    Norm::DisplacementLinfH => self.u_h.linf(),
                    Norm::DisplacementL2H => self.u_h.l2(),
                    Norm::DisplacementLinfV => self.u_v.linf(),
                    Norm::DisplacementL2V => self.u_v.l2(),
                    Norm::MultiplierL2 => self.lambda.l2(),
                    Norm::EnergyLinf => self.energy.linf(),
                    Norm::EnergyL2 => self.energy.l2(),
                };
                (n, v)
            })
            .collect()
    }
}

fn check_finite(scheme: &dyn TimeIntegrator) -> Result<(), SolveError> {
    let fields: [(&'static str, &[f64]); 3] = [
        ("displacement", scheme.displacement()),
        ("velocity", scheme.velocity()),
        ("multiplier", scheme.multiplier().value),
    ];
    for (quantity, values) in fields {
        if values.iter().any(|v| !v.is_finite()) {
            return Err(SolveError::NonFinite {
                step: scheme.step_index(),
                time: scheme.time(),
                quantity,
            });
        }
    }
    Ok(())
}

/// Runs one configuration of a problem to its horizon.
pub fn run(problem: &Problem1d, config: &RunConfig) -> Result<RunResult, Error> {
    let setup_clock = Instant::now();
    require_positive("ratio", config.ratio)?;
    require_positive("horizon", problem.horizon)?;
    let scheme = config.scheme.validate()?;
    if problem.obstacle_gap.is_none() && config.observables.norms.contains(&Norm::MultiplierL2) {
        return Err(ParameterError::new(
            "norm",
            Norm::MultiplierL2,
            "a norm the problem defines (lambda_L2 needs an obstacle)",
        )
        .into());
    }
    let (bar, model) = problem.model(config.nx, config.mass)?;
    let (steps, dt) = time_grid(problem.horizon, bar.h(), config.ratio);
    let exact = problem.exact.as_ref();
    let (u0, v0) = problem.initial_dofs(&bar, &model);
    let mut integ = integrator(&model, scheme, dt, &u0, &v0)?;
    let mut observer = Observer::new(&bar, exact, &config.observables);
    let mut balance = config
        .observables
        .energy_balance
        .then(|| BalanceMonitor::new(&model, scheme, dt));
    let setup = setup_clock.elapsed().as_secs_f64();

    let (mut stepping, mut observe) = (0.0, 0.0);
    let clock = Instant::now();
    observer.observe(integ.as_ref());
    if let Some(b) = balance.as_mut() {
        b.observe(integ.as_ref());
    }
    observe += clock.elapsed().as_secs_f64();
    for _ in 0..steps {
        let clock = Instant::now();
        integ.advance()?;
        check_finite(integ.as_ref())?;
        let mid = Instant::now();
        observer.observe(integ.as_ref());
        if let Some(b) = balance.as_mut() {
            b.observe(integ.as_ref());
        }
        let end = Instant::now();
        stepping += (mid - clock).as_secs_f64();
        observe += (end - mid).as_secs_f64();
    }
    Ok(RunResult {
        nx: config.nx,
        h: bar.h(),
        dt,
        steps,
        dofs: model.n_dofs(),
        dof_steps: steps * model.n_dofs(),
        errors: observer.errors(&config.observables.norms),
        contact_solves: integ.contact_solves(),
        complementarity_violation: integ.complementarity_violation(),
        timings: Timings {
            setup,
            stepping: stepping - integ.contact_seconds(),
            contact: integ.contact_seconds(),
            observe,
        },
        space_norm_evaluations: observer.space.evaluations(),
        multiplier_variation: observer.last_multiplier.map(|_| observer.variation),
        contact_history: observer.contact,
        energy_history: observer.energy_history,
        point_history: observer.points,
        fields: observer.fields,
        contact_treatment: problem.contact.name(),
        max_balance_residual: balance.map(|b| b.largest_residual()),
    })
}
