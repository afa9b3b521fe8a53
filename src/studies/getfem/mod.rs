//! GetFEM's public demo `demo_dynamic_contact_1D.py` as an external witness (issue 17): each of
//! its runs (`tests/data/getfem/`, read by [`crate::harness::getfem`]) is solved again by the
//! harness with the demo's discrete problem — its mass ([`MassVariant::GETFEM`], lumped or
//! consistent), its contact treatment, its time step and [`Conventions::GETFEM_DEMO`] — and the
//! two trajectories are compared step by step: the contact node's displacement, the energy in
//! the demo's own definition ([`DemoEnergy`]), the contact stress and the final field. A
//! round-off-chaotic run is measured after its predictability horizon against the harness's
//! round-off ensemble ([`ensemble`]); GetFEM's contact traces are measured with the harness's
//! norms as another code's runs ([`trace`]); [`report`] writes `reports/getfem.md`.

mod class_check;
mod ensemble;
mod report;
mod trace;

pub use class_check::{
    beyond, Check, ClassCheck, Rule, DEMO_BLOWN_UP_ENERGY, HARNESS_ENERGY_CEILING, STATE_TOLERANCE,
    STRESS_TOLERANCE,
};
pub use ensemble::{
    ensemble_agreement, initial_data_horizon, EnsembleAgreement, Judgement, NormInEnsemble, Timing,
    AMPLITUDE_DECADES, GETFEM_ENSEMBLE,
};
pub use report::{write_getfem_report, CheckedRun, GETFEM_JSON, GETFEM_REPORT};
pub use trace::{contact_trace, export_runs, label, trace_norms, TRACE_NORMS};

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;
use std::time::Instant;

use crate::harness::files::error::{self as files, SolveError};
use crate::harness::getfem::{
    DemoConfig, DemoEnergy, DemoErrorNorms, DemoMass, DemoNorms, DemoRun, DemoVersion,
};
use crate::harness::problem::{Conventions, MassVariant, Scheme, Settings};
use crate::harness::run::exact::ErrorObservers;
use crate::harness::run::norms::Norm;
use crate::harness::run::{drive, time_grid, Integration, Observer, RunStatus};
use crate::harness::study::sensitivity::{Member, PARTING};
use crate::studies::benchmark::dirichlet;
use crate::studies::error::Error;

/// Where the demo's runs are kept, relative to the repository root.
pub const GETFEM_RUNS: &str = "tests/data/getfem";

/// What the comparison of one configuration can hold, and why.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Expectation {
    /// The same discrete problem, not round-off sensitive: agreement at every step.
    RoundOff,
    /// Newmark (½, 1) with the standard mass: the same discrete problem, but in persistent
    /// contact the scheme maps a round-off `δ` in the constrained node's `M·V` to
    /// `(1 − γ/β) δ = −δ` at every step, so the stress (a residual divided by `βΔt²`) keeps the
    /// round-off of each code undamped: the displacement and the energy agree at every step, the
    /// stress up to the first impact (`tests/unit/getfem_demo.rs` shows that a `1e-12` change
    /// of the data predicts the gap).
    UndampedStressRoundOff,
    /// The same discrete problem, round-off chaotic after the first impact
    /// (`reports/sensitivity.md`; GetFEM's own two linear solvers part on these too): agreement
    /// up to the first impact.
    RoundOffChaotic,
    /// Nitsche θ ≠ 0 with the demo's mass type 1: its bookkeeping of the massless node uses
    /// `K + K_N1` in the step and `K` in the acceleration, which no consistent scheme does
    /// (θ = 1 blows up in the demo; θ = −1 parts at the first impact): agreement while the
    /// contact end is at rest, before the first impact.
    DemoMasslessNitsche,
}

impl Expectation {
    /// The class's name in the reports: `round-off`, `undamped-stress-round-off`,
    /// `round-off-chaotic` or `demo-massless-nitsche` (a demo artefact).
    pub fn name(self) -> &'static str {
        match self {
            Expectation::RoundOff => "round-off",
            Expectation::UndampedStressRoundOff => "undamped-stress-round-off",
            Expectation::RoundOffChaotic => "round-off-chaotic",
            Expectation::DemoMasslessNitsche => "demo-massless-nitsche",
        }
    }

    /// The expectation of a configuration.
    pub fn of(config: &DemoConfig) -> Self {
        let standard = config.mass == DemoMass::Consistent;
        match config.version {
            DemoVersion::Nitsche if !standard && config.theta_n != 0.0 => {
                Expectation::DemoMasslessNitsche
            }
            DemoVersion::Signorini if standard && config.gamma == 0.5 => {
                Expectation::RoundOffChaotic
            }
            DemoVersion::Signorini if standard && !config.lumped => {
                Expectation::UndampedStressRoundOff
            }
            DemoVersion::PaoliSchatzman if standard && config.e_ps == 1.0 => {
                Expectation::RoundOffChaotic
            }
            _ => Expectation::RoundOff,
        }
    }
}

/// The largest difference of a series from the demo's, and the step (or node) where it occurs.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Difference {
    /// `max_n |harness_n − demo_n|` (`NaN` when either is not finite at some step).
    pub max: f64,
    /// The step (or node) of the maximum.
    pub step: usize,
}

impl Difference {
    /// Over the indices `from..` common to both series.
    fn between(harness: &[f64], demo: &[f64], from: usize) -> Self {
        let mut d = Difference::default();
        for (n, (a, b)) in harness.iter().zip(demo).enumerate().skip(from) {
            let e = (a - b).abs();
            if e > d.max || e.is_nan() {
                d = Difference { max: e, step: n };
                if e.is_nan() {
                    break;
                }
            }
        }
        d
    }
}

/// One configuration solved again and compared with the demo's run.
#[derive(Debug, Clone)]
pub struct Reproduction {
    /// The demo's configuration.
    pub config: DemoConfig,
    /// What the comparison can hold.
    pub expectation: Expectation,
    /// How the harness's run ended.
    pub status: RunStatus,
    /// The contact node's displacement.
    pub displacement: Difference,
    /// The energy in the demo's definition.
    pub energy: Difference,
    /// The contact stress from the first step (the demo stores 0 at `t = 0`; the harness's
    /// implicit start reports `λ⁰`), relative to the demo's largest `|s|`.
    pub stress: Difference,
    /// The same up to the first impact.
    pub stress_before_impact: Difference,
    /// The displacement field at `t = T` (the demo stores no other), node by node: the
    /// largest difference and its node.
    pub final_field: Difference,
    /// The first step where the displacements differ by more than [`PARTING`] (`1e-8`).
    pub parting: Option<usize>,
    /// The step of the first impact of the exact solution (`t = 1`).
    pub first_impact: usize,
    /// The demo's own error norms.
    pub demo_norms: DemoErrorNorms,
    /// The same norms of the harness's run, in the demo's conventions.
    pub harness_demo_norms: DemoErrorNorms,
    /// The harness's Tables 1–2 norms of its run.
    pub harness_norms: BTreeMap<Norm, f64>,
    /// The harness's [`trace::TRACE_NORMS`] of GetFEM's own contact trace; `None` for a run
    /// that is not finite or whose norms overflow (the demo's blown-up Nitsche run).
    pub getfem_trace_norms: Option<BTreeMap<Norm, f64>>,
    /// The demo's largest energy (its run blows up when this is huge or not finite).
    pub demo_peak_energy: f64,
    /// The harness's largest energy.
    pub harness_peak_energy: f64,
}

/// The harness's problem, mass, scheme and `Δx/Δt` for a demo configuration.
fn harness_setup(
    root: &Path,
    config: &DemoConfig,
) -> Result<(crate::harness::problem::Problem1d, MassVariant, Scheme, f64), Error> {
    let mut problem = dirichlet(root, config.horizon)?;
    problem.contact = config.contact()?;
    let h = 1.0 / config.nx as f64;
    Ok((
        problem,
        config.mass_variant(),
        config.scheme(),
        h / config.dt,
    ))
}

/// The harness's run of a demo configuration, as the comparisons read it.
struct HarnessTrace {
    /// How the run ended.
    status: RunStatus,
    /// `max |U⁰|` of the unperturbed data (the scale of an ensemble member's perturbation).
    initial_scale: f64,
    /// The contact node's displacement at every step.
    u0: Vec<f64>,
    /// The energy in the demo's definition at every step.
    energy: Vec<f64>,
    /// The contact stress at every step, stored as the demo stores it.
    stress: Vec<f64>,
    /// The demo's seven norms of the run ([`DemoNorms`]).
    demo_norms: DemoErrorNorms,
    /// The harness's Tables 1–2 norms of the run.
    norms: BTreeMap<Norm, f64>,
    /// The displacement dofs at the last step.
    final_displacement: Vec<f64>,
}

/// Solves `config` with the harness under GetFEM's demo conventions
/// ([`Conventions::GETFEM_DEMO`]; `member`: an ensemble member with the absolute amplitude of
/// its initial-displacement noise, [`Member::perturb`]), recording what the comparisons read.
fn solve(
    root: &Path,
    config: &DemoConfig,
    member: Option<(Member, f64)>,
) -> Result<HarnessTrace, Error> {
    let (problem, mass, scheme, ratio) = harness_setup(root, config)?;
    let demo = Settings {
        conventions: Conventions::GETFEM_DEMO,
        ..Settings::default()
    };
    let settings = member.map_or(demo, |(m, amplitude)| m.perturb(demo, amplitude));
    let discretisation = problem.discretise(config.nx, mass, &settings)?;
    let initial_scale = discretisation
        .displacement
        .iter()
        .fold(0.0_f64, |m, x| m.max(x.abs()));
    let mut energy = DemoEnergy::new(config, &discretisation)?;
    let mut demo_norms = DemoNorms::new(&discretisation.mesh)?;
    let all: BTreeSet<Norm> = Norm::ALL.into_iter().collect();
    let mut errors = ErrorObservers::new(&discretisation.mesh, problem.exact.as_ref(), &all, false);
    let (steps, _) = time_grid(problem.horizon, discretisation.mesh.h(), ratio);
    let (mut u0, mut e, mut s, mut last) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    let paoli_schatzman = config.version == DemoVersion::PaoliSchatzman;
    let mut record = |state: &Integration<'_>| -> Result<(), files::Error> {
        // Paoli–Schatzman's λ^n produced U^{n+1}: the demo stores it with U^{n+1}.
        let stress = if paoli_schatzman {
            state.scheme_multiplier()[0]
        } else {
            state.multiplier().value[0]
        };
        u0.push(state.displacement()[0]);
        e.push(energy.energy(state, stress));
        s.push(stress);
        if state.step_index() == steps {
            last = state.displacement().to_vec();
        }
        Ok(())
    };
    let mut observers: Vec<&mut dyn Observer> = vec![&mut record, &mut demo_norms];
    observers.extend(errors.observers());
    let stepped = drive(
        &discretisation,
        problem.horizon,
        ratio,
        scheme,
        &mut observers,
        Instant::now(),
    )?;
    drop(observers);
    Ok(HarnessTrace {
        status: stepped.status,
        initial_scale,
        u0,
        energy: e,
        stress: s,
        demo_norms: demo_norms.norms(),
        norms: errors.norms(&all),
        final_displacement: last,
    })
}

/// Solves `run`'s configuration with the harness and compares it with the demo's arrays; the
/// harness's Tables 1–2 norms of GetFEM's contact trace come from its replay
/// ([`trace::trace_norms`], as `signorini verify` computes them).
pub fn reproduce(root: &Path, path: &Path, run: &DemoRun) -> Result<Reproduction, Error> {
    let config = &run.config;
    let trace = solve(root, config, None)?;
    let series = &run.series;
    let stress_scale = series.s0.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    let first_impact = (1.0 / config.dt).round() as usize;
    let mut stress = Difference::between(&trace.stress, &series.s0, 1);
    stress.max /= stress_scale;
    let before_impact = &trace.stress[..trace.stress.len().min(first_impact + 1)];
    let mut stress_before_impact = Difference::between(before_impact, &series.s0, 1);
    stress_before_impact.max /= stress_scale;
    let getfem_trace_norms = match contact_trace(path, run).map(|t| trace_norms(root, &t)) {
        Some(Ok(norms)) => Some(norms),
        // The demo's blown-up run: not finite, or finite with an energy error that overflows.
        None => None,
        Some(Err(e)) if matches!(e.as_solve(), Some(SolveError::NonFinite { .. })) => None,
        Some(Err(e)) => return Err(e),
    };
    Ok(Reproduction {
        config: config.clone(),
        expectation: Expectation::of(config),
        status: trace.status,
        displacement: Difference::between(&trace.u0, &series.u0, 0),
        energy: Difference::between(&trace.energy, &run.energy, 0),
        stress,
        stress_before_impact,
        final_field: Difference::between(&trace.final_displacement, &run.final_state.u, 0),
        parting: parting(&trace.u0, &series.u0),
        first_impact,
        demo_norms: run.norms,
        harness_demo_norms: trace.demo_norms,
        harness_norms: trace.norms,
        getfem_trace_norms,
        demo_peak_energy: peak(&run.energy),
        harness_peak_energy: peak(&trace.energy),
    })
}

/// The first step where two contact-node displacement histories differ by more than
/// [`PARTING`] (or one is not finite).
fn parting(a: &[f64], b: &[f64]) -> Option<usize> {
    a.iter().zip(b).position(|(x, y)| {
        let gap = (x - y).abs();
        gap > PARTING || gap.is_nan()
    })
}

/// The largest value of a series; infinite when one is not finite.
fn peak(v: &[f64]) -> f64 {
    v.iter().fold(0.0_f64, |m, &x| {
        if x.is_finite() {
            m.max(x)
        } else {
            f64::INFINITY
        }
    })
}
