//! GetFEM's public demo `demo_dynamic_contact_1D.py` as an external witness (issue 17): each of
//! its runs (`tests/data/getfem/`, read by [`crate::harness::getfem`]) is solved again by the
//! harness with the demo's discrete problem — its mass ([`MassVariant::GETFEM`], lumped or
//! consistent), its contact treatment, its time step and [`Conventions::GETFEM_DEMO`] — and the
//! two trajectories are compared step by step: the contact node's displacement, the energy in
//! the demo's own definition ([`DemoEnergy`]) and the contact stress.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::Instant;

use crate::engine::contact::ContactTreatment;
use crate::engine::fem::Bar1d;
use crate::engine::fem::{MassVariant, SymmetricMatrix};
use crate::engine::linalg::SpdSolver;
use crate::engine::model::Model;
use crate::engine::problem::Discretisation;
use crate::engine::schemes::{Conventions, Scheme, TimeIntegrator};
use crate::harness::artifacts::write_atomic;
use crate::harness::error::Error;
use crate::harness::getfem::{
    list_runs, read_run, DemoConfig, DemoErrorNorms, DemoMass, DemoNorms, DemoRun, DemoVersion,
};
use crate::harness::run::{drive, RunStatus};
use crate::studies::benchmark::dirichlet;

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
    /// The same discrete problem, round-off chaotic after the first impact (issue 12; GetFEM's
    /// own two linear solvers part on these too): agreement up to the first impact.
    RoundOffChaotic,
    /// Nitsche θ ≠ 0 with the demo's mass type 1: its bookkeeping of the massless node uses
    /// `K + K_N1` in the step and `K` in the acceleration, which no consistent scheme does
    /// (θ = 1 blows up in the demo; θ = −1 parts at the first impact): agreement while the
    /// contact end is at rest, before the first impact.
    DemoMasslessNitsche,
}

impl Expectation {
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

/// The largest difference of a series from the demo's, and the step where it occurs.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Difference {
    /// `max_n |harness_n − demo_n|` (`NaN` when either is not finite at some step).
    pub max: f64,
    /// The step of the maximum.
    pub step: usize,
}

impl Difference {
    /// Over the steps `from..` common to both series.
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
    /// The first step where the displacements differ by more than `1e-8`.
    pub parting: Option<usize>,
    /// The step of the first impact of the exact solution (`t = 1`).
    pub first_impact: usize,
    /// The demo's own error norms.
    pub demo_norms: DemoErrorNorms,
    /// The same norms of the harness's run, in the demo's conventions.
    pub harness_demo_norms: DemoErrorNorms,
    /// The demo's largest energy (its run blows up when this is huge or not finite).
    pub demo_peak_energy: f64,
    /// The harness's largest energy.
    pub harness_peak_energy: f64,
}

/// The harness's problem, mass, scheme and `Δx/Δt` for a demo configuration.
pub fn harness_setup(
    root: &Path,
    config: &DemoConfig,
) -> Result<(crate::engine::problem::Problem1d, MassVariant, Scheme, f64), Error> {
    let mut problem = dirichlet(root, config.horizon)?;
    problem.contact = match config.version {
        DemoVersion::Penalty => format!("penalty(gamma0={})", config.gamma0_p).parse()?,
        DemoVersion::Nitsche => format!(
            "nitsche(theta={},gamma0={})",
            config.theta_n, config.gamma0_n
        )
        .parse()?,
        _ => ContactTreatment::Multiplier,
    };
    problem.conventions = Conventions::GETFEM_DEMO;
    let mass = match (config.mass, config.lumped) {
        (DemoMass::Consistent, false) => MassVariant::Standard,
        (DemoMass::Consistent, true) => MassVariant::Lumped,
        (DemoMass::Redistributed, _) => MassVariant::GetfemRedistributed,
        (DemoMass::SingularDynamic, _) => MassVariant::GetfemSingular,
    };
    let scheme = match config.version {
        DemoVersion::PaoliSchatzman => Scheme::PaoliSchatzman {
            beta: config.beta,
            restitution: config.e_ps,
        },
        _ => Scheme::Newmark {
            beta: config.beta,
            gamma: config.gamma,
        },
    };
    let h = 1.0 / config.nx as f64;
    Ok((problem, mass, scheme, h / config.dt))
}

/// The demo's energy evaluated on the harness's state: `½ VᵀMV + ½ UᵀKU` with the scheme's
/// mass and the elastic `K`, plus the penalty's `(γ₀/2h) [u₀]_−²`, or Nitsche's
/// `(θ/2)(h/γ₀)(s² − u_x(0)²)` from the first step on (the demo's `ux` is 0 before it).
/// The demo carries `M·V`: for Paoli–Schatzman, which does not, it is rebuilt from its one-step
/// form, `M V^n = M (U^n − U^{n−1})/Δt − Δt (β K U^{n−1} + (½ − β) K U^n)`.
struct DemoEnergy<'a> {
    config: &'a DemoConfig,
    model: &'a Model,
    elastic: SymmetricMatrix,
    with_mass: Vec<usize>,
    mass: SpdSolver,
    previous: Option<Vec<f64>>,
}

impl<'a> DemoEnergy<'a> {
    fn new(config: &'a DemoConfig, d: &'a Discretisation<Bar1d>) -> Result<Self, Error> {
        let model = &d.model;
        let with_mass = model.dofs_with_mass();
        let m_rr = model.mass().principal_submatrix(&with_mass);
        Ok(Self {
            config,
            model,
            elastic: d.mesh.stiffness(),
            mass: SpdSolver::factor(&m_rr, "mass (dofs with inertia)").map_err(Error::from)?,
            with_mass,
            previous: None,
        })
    }

    fn energy(&mut self, state: &dyn TimeIntegrator, stress: f64) -> f64 {
        let (u, n, dt) = (state.displacement(), self.model.n_dofs(), state.dt());
        let mut mv = vec![0.0; n];
        match (&self.previous, self.config.version) {
            (Some(up), DemoVersion::PaoliSchatzman) => {
                let quotient: Vec<f64> = u.iter().zip(up).map(|(a, b)| (a - b) / dt).collect();
                self.model.mass().mul_into(&quotient, &mut mv);
                let (mut k_prev, mut k_now) = (vec![0.0; n], vec![0.0; n]);
                self.elastic.mul_into(up, &mut k_prev);
                self.elastic.mul_into(u, &mut k_now);
                let beta = self.config.beta;
                for ((m, kp), kn) in mv.iter_mut().zip(&k_prev).zip(&k_now) {
                    *m -= dt * (beta * kp + (0.5 - beta) * kn);
                }
            }
            _ => self.model.mass().mul_into(state.velocity(), &mut mv),
        }
        self.previous = Some(u.to_vec());
        let mv_r: Vec<f64> = self.with_mass.iter().map(|&i| mv[i]).collect();
        let mut v_r = mv_r.clone();
        self.mass.solve_in_place(&mut v_r);
        let kinetic = 0.5 * mv_r.iter().zip(&v_r).map(|(a, b)| a * b).sum::<f64>();
        let mut energy = kinetic + 0.5 * self.elastic.quadratic_form(u);
        let h = 1.0 / self.config.nx as f64;
        match self.config.version {
            DemoVersion::Penalty => {
                energy += 0.5 * self.config.gamma0_p / h * u[0].min(0.0).powi(2);
            }
            DemoVersion::Nitsche if state.step_index() > 0 => {
                let ux = (u[1] - u[0]) / h;
                energy += 0.5
                    * self.config.theta_n
                    * (h / self.config.gamma0_n)
                    * (stress * stress - ux * ux);
            }
            _ => {}
        }
        energy
    }
}

/// Solves `run`'s configuration with the harness and compares it with the demo's arrays.
pub fn reproduce(root: &Path, run: &DemoRun) -> Result<Reproduction, Error> {
    let config = &run.config;
    let (problem, mass, scheme, ratio) = harness_setup(root, config)?;
    let discretisation = problem.discretise(config.nx, mass)?;
    let mut energy = DemoEnergy::new(config, &discretisation)?;
    let mut norms = DemoNorms::new(&discretisation.mesh)?;
    let (mut u0, mut e, mut s) = (Vec::new(), Vec::new(), Vec::new());
    let paoli_schatzman = config.version == DemoVersion::PaoliSchatzman;
    let mut record = |state: &dyn TimeIntegrator| -> Result<(), Error> {
        // Paoli–Schatzman's λ^n produced U^{n+1}: the demo stores it with U^{n+1}.
        let stress = if paoli_schatzman {
            state.scheme_multiplier()[0]
        } else {
            state.multiplier().value[0]
        };
        u0.push(state.displacement()[0]);
        e.push(energy.energy(state, stress));
        s.push(stress);
        Ok(())
    };
    let stepped = drive(
        &discretisation,
        problem.horizon,
        ratio,
        scheme,
        &mut [&mut record, &mut norms],
        Instant::now(),
    )?;
    let series = &run.series;
    let stress_scale = series.s0.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    let first_impact = (1.0 / config.dt).round() as usize;
    let mut stress = Difference::between(&s, &series.s0, 1);
    stress.max /= stress_scale;
    let mut stress_before_impact =
        Difference::between(&s[..s.len().min(first_impact + 1)], &series.s0, 1);
    stress_before_impact.max /= stress_scale;
    let peak = |v: &[f64]| {
        v.iter().fold(0.0_f64, |m, &x| {
            if x.is_finite() {
                m.max(x)
            } else {
                f64::INFINITY
            }
        })
    };
    Ok(Reproduction {
        config: config.clone(),
        expectation: Expectation::of(config),
        status: stepped.status,
        displacement: Difference::between(&u0, &series.u0, 0),
        energy: Difference::between(&e, &run.energy, 0),
        stress,
        stress_before_impact,
        parting: (0..u0.len().min(series.u0.len())).find(|&n| {
            let gap = (u0[n] - series.u0[n]).abs();
            gap > 1e-8 || gap.is_nan()
        }),
        first_impact,
        demo_norms: run.norms,
        harness_demo_norms: norms.norms(),
        demo_peak_energy: peak(&run.energy),
        harness_peak_energy: peak(&e),
    })
}

/// The report's file name.
pub const GETFEM_REPORT: &str = "getfem.md";

/// Reproduces every run of `runs` (a directory of the demo's `.json.gz` files) and writes
/// `out`/[`GETFEM_REPORT`]: per configuration, what the comparison can hold, the largest
/// differences from the demo with their steps, and the demo's own seven norms beside the same
/// norms of the harness's run computed with the demo's conventions (nodal interpolant,
/// rectangle sums). Returns the reproductions.
pub fn write_getfem_report(
    root: &Path,
    runs: &Path,
    out: &Path,
) -> Result<Vec<Reproduction>, Error> {
    let mut all = Vec::new();
    let mut md = String::from(
        "# GetFEM's demo solved again by the harness\n\n\
         Every run of `demo_dynamic_contact_1D.py` in the directory given (by default \
         `tests/data/getfem/`, see its README) solved with the demo's discrete problem: its mass \
         (`getfem-redistributed`, `getfem-singular`, `standard`, `lumped`), contact treatment and \
         time step, with `--conventions getfem-demo`. `Δu` is the largest difference of the \
         contact node's displacement over all steps, `ΔE` of the energy in the demo's definition, \
         `Δs/max|s|` of the contact stress from the first step; `parts at` is the first step \
         where the displacements differ by more than 1e-8 (`—`: never). What each expectation \
         holds is in `src/studies/getfem.rs` (`Expectation`); `tests/unit/getfem_roundoff.rs` \
         asserts it for every run. Written by `make verify-getfem`.\n\n\
         | run | expectation | Δu (step) | ΔE (step) | Δs/max\\|s\\| (step) | parts at | first impact |\n\
         |---|---|---|---|---|---|---|\n",
    );
    let files = list_runs(runs)?;
    for file in &files {
        let run = read_run(&file.path)?;
        let r = reproduce(root, &run)?;
        let name = file
            .path
            .file_name()
            .map_or_else(String::new, |n| n.to_string_lossy().into_owned());
        let _ = writeln!(
            md,
            "| `{name}` | {:?} | {:.1e} ({}) | {:.1e} ({}) | {:.1e} ({}) | {} | {} |",
            r.expectation,
            r.displacement.max,
            r.displacement.step,
            r.energy.max,
            r.energy.step,
            r.stress.max,
            r.stress.step,
            r.parting.map_or("—".to_string(), |n| n.to_string()),
            r.first_impact,
        );
        all.push((name, r));
    }
    md.push_str(
        "\n## The demo's norms and the same norms of the harness's run\n\n\
         The demo's seven relative error norms as it prints them, and the harness's run measured \
         the same way (`DemoNorms`). Where the runs agree, the displacement norms agree to the \
         printed digits. Three reporting conventions, not the solutions, separate the others: \
         (1) the velocity of a massless contact node (masses 1, 2 with the implicit schemes), \
         which the dynamics leave undefined: the demo reports `(U¹₀ − U⁰₀)/Δt`, the harness the \
         value of Newmark's recurrences, so `LinfL2v` and `L2L2v` differ; (2) Paoli–Schatzman's \
         velocity, which the harness reports at `t_{n−½}` (`(Uⁿ − Uⁿ⁻¹)/Δt`) and the demo at \
         `t_n`; (3) the stress at `t = 0`, which the demo stores as 0 while the harness's implicit \
         start reports `λ⁰ = −½` (the exact `u_x(0, 0)`), so `L2sn` differs with masses 1 and 2. \
         Where the runs part (round-off chaos, the demo's massless Nitsche) the norms differ as \
         the runs do.\n\n| run |",
    );
    for name in DemoErrorNorms::NAMES {
        let _ = write!(md, " {name} demo / harness |");
    }
    md.push_str("\n|---|");
    md.push_str(&"---|".repeat(DemoErrorNorms::NAMES.len()));
    md.push('\n');
    for (name, r) in &all {
        let _ = write!(md, "| `{name}` |");
        for ((_, d), (_, h)) in r
            .demo_norms
            .named()
            .into_iter()
            .zip(r.harness_demo_norms.named())
        {
            let _ = write!(md, " {d:.6e} / {h:.6e} |");
        }
        md.push('\n');
    }
    write_atomic(&out.join(GETFEM_REPORT), md.as_bytes())?;
    Ok(all.into_iter().map(|(_, r)| r).collect())
}

/// Writes each run of `runs` whose series are finite as a contact-trace file of the external-run
/// format (`signorini-external/1`, CSV; README, "Verifying another code's runs") into `dir`:
/// the demo's time points, its contact displacement `store_u0`, stress `store_s0` (as `lambda`,
/// at the same times, as the demo stores it) and energy `store_E`, on the Dirichlet scene; runs
/// of one configuration at several NX share a label (the file name without `_nx…`), so that
/// `signorini verify` fits their rates. A run with a non-finite value (the demo's blown-up
/// Nitsche run) is skipped: the format refuses it. Returns the files written.
pub fn export_runs(runs: &Path, dir: &Path) -> Result<Vec<PathBuf>, Error> {
    let mut written = Vec::new();
    for file in list_runs(runs)? {
        let run = read_run(&file.path)?;
        let series = &run.series;
        let columns = [&series.u0, &series.s0, &run.energy];
        if columns.iter().any(|c| c.iter().any(|v| !v.is_finite())) {
            continue;
        }
        let stem = file
            .path
            .file_name()
            .map_or_else(String::new, |n| n.to_string_lossy().into_owned());
        let stem = stem.trim_end_matches(".json.gz");
        let label = stem
            .split('_')
            .filter(|part| !part.starts_with("nx"))
            .collect::<Vec<_>>()
            .join("_");
        let nx = run.config.nx;
        let nodes: Vec<String> = (0..=nx)
            .map(|i| format!("{:?}", i as f64 / nx as f64))
            .collect();
        let mut csv = format!(
            "# format: signorini-external/1\n# scene: bar1d-dirichlet\n\
             # code.name: GetFEM demo_dynamic_contact_1D.py\n# code.version: 5.4.2\n\
             # label: {label}\n# mesh.nodes: {}\ntime,contact_displacement,lambda,energy\n",
            nodes.join(", ")
        );
        for (n, t) in series.time.iter().enumerate() {
            let _ = writeln!(
                csv,
                "{t:?},{:?},{:?},{:?}",
                series.u0[n], series.s0[n], run.energy[n]
            );
        }
        let path = dir.join(format!("{stem}.csv"));
        write_atomic(&path, csv.as_bytes())?;
        written.push(path);
    }
    Ok(written)
}
