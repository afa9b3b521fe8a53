//! One run of a scene as a user asks for it (`signorini run`): the scheme and mass chosen, the
//! scene's level, ratio and contact treatment unless overridden, whatever the geometry: one
//! [`run`] of the scene's [`Problem`], a bar's measuring its errors against the exact solution,
//! a box's its energy and contact face, and the summary and files of its outcome. The command
//! (`crate::commands`) parses, stages its directory and writes what comes back.

use std::path::{Path, PathBuf};

use serde::Serialize;

use crate::harness::files::error::{self as files, ParameterError};
use crate::harness::problem::{
    BoxProblem, ContactTreatment, LinearSolver, MassVariant, Problem, Scheme,
};
use crate::harness::reference::scene_study::{chosen_settings, ConventionChoice};
use crate::harness::run::elastic::BoxObservations;
use crate::harness::run::energy_balance::{self, BALANCE_TOLERANCE};
use crate::harness::run::physics::{
    Physics, ENERGY_GAIN_TOLERANCE, FACE_SCALE_FLOOR, PENETRATION_TOLERANCE,
};
use crate::harness::run::run_files::{box_history_csv, history_csv};
use crate::harness::run::{run, time_grid, Observables, Observed, RunConfig, RunResult};
use crate::harness::study::budget::{self, Estimate};
use crate::harness::study::error::Error;
use crate::harness::study::progress::StepProgress;
use crate::harness::study::scene::Scene;

/// What a user chooses for one run of a scene; each `None` keeps the scene's.
#[derive(Debug, Clone)]
pub struct RunChoices {
    /// The time integrator.
    pub scheme: Scheme,
    /// The mass matrix.
    pub mass: MassVariant,
    /// Elements (along the axis of a box); default: the scene's finest level.
    pub nx: Option<usize>,
    /// `Δx/Δt`.
    pub ratio: Option<f64>,
    /// The contact treatment.
    pub contact: Option<ContactTreatment>,
    /// The schemes' conventions.
    pub conventions: ConventionChoice,
    /// The step solver of a box.
    pub linear_solver: LinearSolver,
    /// Whether a bar run measures its energy balance's residual (a box run always does).
    pub check_balance: bool,
    /// Whether the run's files are written (the histories and fields the scene asks for are
    /// recorded only then).
    pub writes_files: bool,
    /// Whether a box's fields are written at every step `t_n` (else at the scene's
    /// `fields_at` times).
    pub fields_every_step: bool,
}

/// The most snapshots `--fields-every-step` writes: a run of more steps is refused before
/// anything is allocated.
pub const MAX_SNAPSHOTS: usize = 100_000;

/// What `--fields-every-step` allows, for its error.
const SNAPSHOTS_ALLOWED: &str =
    "at most 100000 snapshots (MAX_SNAPSHOTS): a coarser level or a larger ratio";

/// Every step's time `t_n = n Δt`, `n = 0..N`, of a run of `problem` on `nx` elements along
/// the axis with `Δx/Δt = ratio`, as the run steps ([`time_grid`]); more than
/// [`MAX_SNAPSHOTS`] is refused (an invalid `nx` or ratio is refused by the run itself).
fn every_step(problem: &BoxProblem, nx: usize, ratio: f64) -> Result<Vec<f64>, ParameterError> {
    if nx == 0 || !(ratio.is_finite() && ratio > 0.0) {
        return Ok(Vec::new());
    }
    let h = problem.lengths[problem.lengths.len() - 1] / nx as f64;
    let (steps, dt) = time_grid(problem.horizon, h, ratio);
    if steps >= MAX_SNAPSHOTS {
        return Err(ParameterError::new(
            "--fields-every-step",
            format!("{} snapshots", steps + 1),
            SNAPSHOTS_ALLOWED,
        ));
    }
    Ok((0..=steps).map(|n| n as f64 * dt).collect())
}

/// A run of a scene with the user's choices applied.
#[derive(Debug, Clone)]
pub struct SceneRun {
    /// The scene's name.
    pub scene: String,
    /// The problem.
    pub problem: Problem,
    /// Level, ratio, scheme, mass and what is recorded.
    pub config: RunConfig,
    /// The times at which the scene asks a box's fields to be written.
    fields_at: Vec<f64>,
    /// Whether the run's files are written.
    writes_files: bool,
}

/// `run.json`: the scene, scheme and mass that were run, then the result's fields beside them.
#[derive(Serialize)]
struct RunFile<'a> {
    /// The scene's name.
    scene: &'a str,
    /// The scheme's name (`signorini list`).
    scheme: String,
    /// The mass variant's name.
    mass: &'static str,
    /// The result.
    #[serde(flatten)]
    result: &'a RunResult,
}

/// What a run of a scene hands back: its result, whatever the geometry.
#[derive(Debug, Clone)]
pub struct RunOutcome(RunResult);

impl SceneRun {
    /// The run of `scene` with `choices`. Without `--nx` and without levels in the scene it is
    /// refused naming `--nx`.
    pub fn of(scene: &Scene, choices: RunChoices) -> Result<Self, Error> {
        let nx = choices
            .nx
            .or(scene.discretisation.levels.last().copied())
            .ok_or_else(|| {
                ParameterError::new(
                    "--nx",
                    "none",
                    "an element count >= 1 (the scene has no discretisation.levels to take \
                     the finest from)",
                )
            })?;
        let settings = chosen_settings(scene, choices.conventions, choices.linear_solver);
        let (problem, observables) = match scene.problem() {
            Problem::Box(mut problem) => {
                problem.contact = choices.contact.unwrap_or(problem.contact);
                let fields_at = match (choices.writes_files, choices.fields_every_step) {
                    (false, _) => Vec::new(),
                    (true, false) => scene.observables.fields_at.clone(),
                    (true, true) => every_step(
                        &problem,
                        nx,
                        choices.ratio.unwrap_or(scene.discretisation.ratio),
                    )?,
                };
                let observables = Observables {
                    fields_at,
                    ..Observables::default()
                };
                (Problem::Box(problem), observables)
            }
            Problem::Bar(mut problem) => {
                problem.contact = choices.contact.unwrap_or(problem.contact);
                let mut observables = scene.observables();
                observables.energy_balance = choices.check_balance;
                if !choices.writes_files {
                    observables.contact_history = false;
                    observables.energy_history = false;
                    observables.points.clear();
                    observables.fields_at.clear();
                }
                (Problem::Bar(problem), observables)
            }
        };
        Ok(Self {
            scene: scene.name.clone(),
            problem,
            config: RunConfig {
                nx,
                ratio: choices.ratio.unwrap_or(scene.discretisation.ratio),
                scheme: choices.scheme,
                mass: choices.mass,
                observables,
                settings,
            },
            fields_at: scene.observables.fields_at.clone(),
            writes_files: choices.writes_files,
        })
    }

    /// The estimate of the run's memory, files and work ([`budget`]).
    pub fn estimate(&self) -> Estimate {
        let writes = self.writes_files;
        match &self.problem {
            Problem::Bar(problem) => budget::bar_run(problem, &self.config, writes),
            Problem::Box(problem) => budget::box_run(
                problem,
                &self.config.settings,
                self.config.nx,
                self.config.ratio,
                self.config.observables.fields_at.len(),
                writes,
            ),
        }
    }

    /// What the user should know before the run: a box scene asks for fields that a run
    /// without a directory does not write.
    pub fn advice(&self) -> Option<String> {
        (matches!(self.problem, Problem::Box(_))
            && !self.writes_files
            && !self.fields_at.is_empty())
        .then(|| {
            format!(
                "(the scene asks for fields at {:?}: pass --out DIR to write them as VTK)",
                self.fields_at
            )
        })
    }

    /// Runs it, with a box's VTK snapshots written into `fields_dir` when given, its steps
    /// counted in the progress shown.
    pub fn run(&self, fields_dir: Option<&Path>) -> Result<RunOutcome, Error> {
        let config = RunConfig {
            observables: Observables {
                fields_dir: fields_dir.map(Path::to_path_buf),
                ..self.config.observables.clone()
            },
            ..self.config.clone()
        };
        let mut steps = StepProgress::new(
            &format!("run on {} elements", config.nx),
            self.problem.horizon(),
        );
        Ok(RunOutcome(
            run(&self.problem, &config, &mut [&mut steps])?.completed()?,
        ))
    }
}

impl RunOutcome {
    /// The summary printed after a run of `run` (`check_balance`: with the largest per-step
    /// residual of the scheme's energy balance).
    pub fn summary(&self, run: &SceneRun, check_balance: bool) -> String {
        let (c, r) = (&run.config, &self.0);
        let mut lines = Vec::new();
        match &r.observed {
            Observed::Bar(bar) => {
                lines.push(format!(
                    "{} — {} / {} / {}: NX = {}, Δt = {:.4e}, {} steps, {} dofs, {} contact solves, {:.3} s",
                    run.scene, c.scheme, c.mass, r.contact_treatment, c.nx, r.dt, r.steps,
                    r.dofs, r.contact_solves, r.timings.total()
                ));
                for (norm, e) in &bar.errors {
                    lines.push(format!("  {:12} {:.6e}   {}", norm.key(), e, norm.label()));
                }
            }
            Observed::Box(body) => box_summary(&mut lines, run, r, body),
        }
        if let Some(physics) = &r.physics {
            physics_lines(&mut lines, physics);
        }
        if check_balance {
            lines.push(balance_line(c.scheme, r.max_balance_residual));
        }
        let slab = match &r.observed {
            Observed::Box(body) => body.contact_slab,
            Observed::Bar(_) => None,
        };
        if let Some(slab) = slab {
            lines.push(format!(
                "  local contact operator: {} layers, {} slab dofs{}, truncation ratio {:.1e}",
                slab.layers,
                slab.slab_dofs,
                if slab.whole {
                    " (the whole system)"
                } else {
                    ""
                },
                slab.ratio
            ));
        }
        lines.join("\n")
    }

    /// The run's files: `run.json`'s text (what was run, [`RunFile`], then the result) and the
    /// histories as CSV (name, text), with a box's VTK files named by `final_path` (where they
    /// will be once the staging is moved).
    pub fn files(
        &mut self,
        run: &SceneRun,
        final_path: impl Fn(&Path) -> PathBuf,
    ) -> Result<(String, Vec<(String, String)>), Error> {
        let encode = files::Error::encode(Path::new("run.json"));
        let r = &mut self.0;
        if let Observed::Box(body) = &mut r.observed {
            body.vtk_files = body.vtk_files.iter().map(|f| final_path(f)).collect();
        }
        let histories = match &r.observed {
            Observed::Bar(bar) => history_csv(bar),
            Observed::Box(body) => box_history_csv(body),
        };
        let file = RunFile {
            scene: &run.scene,
            scheme: run.config.scheme.name(),
            mass: run.config.mass.name(),
            result: r,
        };
        Ok((
            serde_json::to_string_pretty(&file).map_err(encode)?,
            histories,
        ))
    }

    /// The VTK files a box run wrote (none for a bar).
    pub fn vtk_files(&self) -> &[PathBuf] {
        match &self.0.observed {
            Observed::Box(body) => &body.vtk_files,
            Observed::Bar(_) => &[],
        }
    }
}

/// The lines of a box run's summary before its balance.
fn box_summary(lines: &mut Vec<String>, run: &SceneRun, r: &RunResult, body: &BoxObservations) {
    let c = &run.config;
    let (e0, e_end) = (body.energy[0].1, body.energy[body.energy.len() - 1].1);
    let max_force = body
        .contact
        .total_force
        .iter()
        .fold(0.0_f64, |m, f| m.max(-f));
    lines.push(format!(
        "{} — {} / {} / {}: elements {:?}, {} dofs, {} contact nodes, Δt = {:.4e}, {} steps",
        run.scene,
        c.scheme,
        c.mass,
        r.contact_treatment,
        body.elements,
        r.dofs,
        body.contact_nodes,
        r.dt,
        r.steps
    ));
    lines.push(format!(
        "  time: setup {:.3} s, stepping {:.3} s, contact {:.3} s, observers {:.3} s; {} contact solves",
        r.timings.setup, r.timings.stepping, r.timings.contact, r.timings.observe, r.contact_solves
    ));
    let counts = body.step_solves;
    lines.push(if counts.solves > 0 && counts.iterations > 0 {
        format!(
            "  step solver {}: {} solves, {:.1} CG iterations per solve",
            body.linear_solver,
            counts.solves,
            counts.iterations as f64 / counts.solves as f64
        )
    } else {
        format!("  step solver {}", body.linear_solver)
    });
    if !body.solver_plan.is_empty() {
        lines.push(format!("  solver plan: {}", body.solver_plan));
    }
    lines.push(format!(
        "  energy {e0:.6e} → {e_end:.6e}; largest total contact force {max_force:.4e}; complementarity {:.1e}",
        r.complementarity_violation
    ));
}

/// The physics lines of a run's summary: its penetration, its energy above the start and its
/// contact-force sign ([`Physics`]), then what fails its tolerance, with the figures.
fn physics_lines(lines: &mut Vec<String>, p: &Physics) {
    let tolerance = format!(
        "{} % of max(D, {FACE_SCALE_FLOOR:e})",
        100.0 * PENETRATION_TOLERANCE
    );
    lines.push(format!(
        "  penetration {} (tolerance {tolerance}); energy {}; contact force: largest pulling \
         {:.3e} of largest |λ| {:.3e}",
        p.penetration_text(),
        p.energy_text(),
        p.wrong_sign_force,
        p.max_force
    ));
    lines.push(match p.flags() {
        Some(flags) => format!("  physics FLAGGED: {flags}"),
        None => format!(
            "  physics: no penetration beyond {} % of D, no energy gain beyond {} % of E_0, \
             no pulling contact force",
            100.0 * PENETRATION_TOLERANCE,
            100.0 * ENERGY_GAIN_TOLERANCE
        ),
    });
}

/// The `--check-balance` line of a completed run: its largest per-step balance residual
/// (every run checks it against [`BALANCE_TOLERANCE`]; one above it ends solver-inaccurate),
/// and what that residual covers and what it does not.
fn balance_line(scheme: Scheme, residual: Option<f64>) -> String {
    let equation = energy_balance::equation(scheme);
    match residual {
        Some(r) => format!(
            "  energy balance eq. {equation}: largest per-step residual {r:.3e} of its scale \
             (the energy, or the size of the products it sums; tolerance {BALANCE_TOLERANCE:e}). \
             It covers each step's energy change against the change the scheme's equations \
             predict (the solves' accuracy); it does not cover whether that change is physical: \
             contact work that raises the energy, or a node inside the obstacle, balance too \
             (the physics line judges them)"
        ),
        None => format!(
            "  energy balance eq. {equation}: not checked (the run's conventions change the \
             scheme's equations; see docs/src/schemes-and-balances.md)"
        ),
    }
}
