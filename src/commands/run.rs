//! `signorini run`: one run of a scene, bar or box, with its summary on the terminal and,
//! with `--out`, its result and histories as files.

use std::path::{Path, PathBuf};

use clap::Args;

use super::failure::{write_output, Failure};
use super::limits::LimitArgs;
use super::options::{
    parse_contact, parse_mass, parse_scheme, warn_schemes, ConventionArgs, LinearSolverArgs,
};
use crate::harness::budget;
use crate::harness::elastic::run_box;
use crate::harness::output_dir::{Replace, StagedDir};
use crate::harness::problem::ContactTreatment;
use crate::harness::problem::MassVariant;
use crate::harness::problem::Scheme;
use crate::harness::problem::{BoxProblem, Problem};
use crate::harness::run::energy_balance::{self, BALANCE_TOLERANCE};
use crate::harness::run::{run, Observables, RunConfig};
use crate::harness::run_files::{box_history_csv, history_csv, RUN_JSON};
use crate::harness::scene::Scene;

/// The arguments of `signorini run`.
#[derive(Debug, Args)]
pub struct RunArgs {
    /// The scene file (see scenes/).
    pub scene: PathBuf,
    /// Scheme: a preset name (see `signorini list`) or newmark(beta=B,gamma=G),
    /// theta(theta=T), paoli-schatzman(beta=B,e=E).
    #[arg(long, value_parser = parse_scheme)]
    pub scheme: Scheme,
    /// Mass matrix: standard, redistributed, lumped, redistributed-conserving or
    /// singular-dynamic (see `signorini list`).
    #[arg(long, value_parser = parse_mass)]
    pub mass: MassVariant,
    /// Number of elements NX (>= 1; along the bar for a 2D/3D box). Default: the scene's
    /// finest level.
    #[arg(long)]
    pub nx: Option<usize>,
    /// Δx/Δt (default: the scene's).
    #[arg(long, allow_hyphen_values = true)]
    pub ratio: Option<f64>,
    /// Output directory for run.json and the histories (CSV, VTK for a box), written whole or
    /// not at all; an existing one is replaced when it holds only such files.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Contact treatment: multiplier, penalty(gamma0=G), nitsche(theta=T,gamma0=G) (1D
    /// only). Default: the scene's, else multiplier.
    #[arg(long, value_parser = parse_contact)]
    pub contact: Option<ContactTreatment>,
    /// Print the largest per-step residual of the scheme's discrete energy balance (1D paper
    /// eqs. 33, 35, 37, on a bar or a box) relative to its scale (also in run.json with --out).
    /// Every run checks it: one above 1e-9 ends solver-inaccurate, with exit code 1.
    #[arg(long)]
    pub check_balance: bool,
    /// The schemes' implementation choices.
    #[command(flatten)]
    pub conventions: ConventionArgs,
    /// The step solver of a box scene.
    #[command(flatten)]
    pub solver: LinearSolverArgs,
    /// The resource limits.
    #[command(flatten)]
    pub limits: LimitArgs,
}

/// One run of a scene: the requested error norms on the terminal; with --out, run.json
/// plus the histories the scene asks for ([`history_csv`], [`box_history_csv`] and the box's
/// VTK snapshots), staged and moved into place whole at the end.
pub fn run_scene(args: RunArgs) -> Result<(), Failure> {
    let RunArgs {
        scene,
        scheme,
        mass,
        nx,
        ratio,
        out,
        contact,
        check_balance,
        conventions,
        solver,
        limits,
    } = args;
    let scene = Scene::load(&scene)?;
    warn_schemes(&[scheme]);
    let Some(nx) = nx.or(scene.discretisation.levels.last().copied()) else {
        return Err(Failure::usage(format!(
            "scene {}: no --nx and no discretisation.levels to take the finest from",
            scene.name
        )));
    };
    let mut problem = match scene.problem() {
        Problem::Box(mut problem) => {
            problem.contact = contact.unwrap_or(problem.contact);
            problem.conventions = conventions.over(problem.conventions);
            problem.linear_solver = solver.linear_solver;
            let snapshots = out
                .as_ref()
                .map_or(0, |_| scene.observables.fields_at.len());
            let ratio_used = ratio.unwrap_or(scene.discretisation.ratio);
            limits.check(budget::box_run(
                &problem,
                nx,
                ratio_used,
                snapshots,
                out.is_some(),
            ))?;
            return run_box_scene(
                &scene,
                &problem,
                (scheme, mass),
                nx,
                ratio,
                out,
                check_balance,
            );
        }
        Problem::Bar(problem) => problem,
    };
    problem.contact = contact.unwrap_or(problem.contact);
    problem.conventions = conventions.over(problem.conventions);
    let mut observables = scene.observables();
    observables.energy_balance = check_balance;
    if out.is_none() {
        observables.contact_history = false;
        observables.energy_history = false;
        observables.points.clear();
        observables.fields_at.clear();
    }
    let config = RunConfig {
        nx,
        ratio: ratio.unwrap_or(scene.discretisation.ratio),
        scheme,
        mass,
        observables,
    };
    limits.check(budget::bar_run(&problem, &config, out.is_some()))?;
    let staged = stage(out.as_deref())?;
    let result = run(&problem, &config)?.completed()?;
    out!(
        "{} — {} / {} / {}: NX = {}, Δt = {:.4e}, {} steps, {} dofs, {} contact solves, {:.3} s",
        scene.name,
        scheme,
        mass,
        result.contact_treatment,
        nx,
        result.dt,
        result.steps,
        result.dofs,
        result.contact_solves,
        result.timings.total()
    );
    for (norm, e) in &result.errors {
        out!("  {:12} {:.6e}   {}", norm.key(), e, norm.label());
    }
    if check_balance {
        balance_line(scheme, result.max_balance_residual);
    }
    if let (Some(dir), Some(staged)) = (out, staged) {
        let json = serde_json::to_string_pretty(&result).map_err(Failure::runtime)?;
        write_output(&staged.path().join(RUN_JSON), json.as_bytes())?;
        for (name, text) in history_csv(&result) {
            write_output(&staged.path().join(&name), text.as_bytes())?;
        }
        staged.commit()?;
        out!("wrote {}", dir.display());
    }
    Ok(())
}

/// The `--check-balance` line of a completed run: its largest per-step balance residual
/// (every run checks it against [`BALANCE_TOLERANCE`]; one above it ends solver-inaccurate).
fn balance_line(scheme: Scheme, residual: Option<f64>) {
    let equation = energy_balance::equation(scheme);
    match residual {
        Some(r) => out!(
            "  energy balance eq. {equation}: largest per-step residual {r:.3e} of its scale \
             (the energy, or the size of the products it sums; tolerance {BALANCE_TOLERANCE:e})"
        ),
        None => out!(
            "  energy balance eq. {equation}: not checked (the run's conventions change the \
             scheme's equations; see docs/src/schemes-and-balances.md)"
        ),
    }
}

/// `signorini run` on a 2D/3D box scene: a summary, and with `--out` run.json, energy.csv,
/// contact.csv and the VTK snapshots at the scene's `fields_at` times.
fn run_box_scene(
    scene: &Scene,
    problem: &BoxProblem,
    (scheme, mass): (Scheme, MassVariant),
    n_axis: usize,
    ratio: Option<f64>,
    out: Option<PathBuf>,
    check_balance: bool,
) -> Result<(), Failure> {
    let staged = stage(out.as_deref())?;
    let config = RunConfig {
        nx: n_axis,
        ratio: ratio.unwrap_or(scene.discretisation.ratio),
        scheme,
        mass,
        observables: Observables {
            fields_at: if out.is_some() {
                scene.observables.fields_at.clone()
            } else {
                Vec::new()
            },
            fields_dir: staged.as_ref().map(|s| s.path().to_path_buf()),
            ..Observables::default()
        },
    };
    if out.is_none() && !scene.observables.fields_at.is_empty() {
        out!(
            "(the scene asks for fields at {:?}: pass --out DIR to write them as VTK)",
            scene.observables.fields_at
        );
    }
    let mut r = run_box(problem, &config)?.completed()?;
    let (e0, e_end) = (r.energy[0].1, r.energy[r.energy.len() - 1].1);
    let max_force = r.contact.total_force.iter().fold(0.0_f64, |m, f| m.max(-f));
    out!(
        "{} — {} / {} / {}: elements {:?}, {} dofs, {} contact nodes, Δt = {:.4e}, {} steps",
        scene.name,
        scheme,
        mass,
        r.contact_treatment,
        r.elements,
        r.dofs,
        r.contact_nodes,
        r.dt,
        r.steps
    );
    out!(
        "  time: setup {:.3} s, stepping {:.3} s, contact {:.3} s, observers {:.3} s; {} contact solves",
        r.timings.setup, r.timings.stepping, r.timings.contact, r.timings.observe, r.contact_solves
    );
    let counts = r.step_solves;
    if counts.solves > 0 && counts.iterations > 0 {
        out!(
            "  step solver {}: {} solves, {:.1} CG iterations per solve",
            r.linear_solver,
            counts.solves,
            counts.iterations as f64 / counts.solves as f64
        );
    } else {
        out!("  step solver {}", r.linear_solver);
    }
    out!(
        "  energy {e0:.6e} → {e_end:.6e}; largest total contact force {max_force:.4e}; complementarity {:.1e}",
        r.complementarity_violation
    );
    if check_balance {
        balance_line(scheme, r.max_balance_residual);
    }
    if let Some(slab) = r.contact_slab {
        out!(
            "  local contact operator: {} layers, {} slab dofs{}, truncation ratio {:.1e}",
            slab.layers,
            slab.slab_dofs,
            if slab.whole {
                " (the whole system)"
            } else {
                ""
            },
            slab.ratio
        );
    }
    if let (Some(dir), Some(staged)) = (out, staged) {
        r.vtk_files = r.vtk_files.iter().map(|f| staged.final_path(f)).collect();
        let json = serde_json::to_string_pretty(&r).map_err(Failure::runtime)?;
        write_output(&staged.path().join(RUN_JSON), json.as_bytes())?;
        for (name, text) in box_history_csv(&r) {
            write_output(&staged.path().join(&name), text.as_bytes())?;
        }
        staged.commit()?;
        for f in &r.vtk_files {
            out!("wrote {}", f.display());
        }
        out!("wrote {}", dir.display());
    }
    Ok(())
}

/// The staged `--out` directory of a run: refused when it holds files the harness did not
/// write, its old files replaced by the run's at the end.
fn stage(out: Option<&Path>) -> Result<Option<StagedDir>, Failure> {
    Ok(out
        .map(|dir| StagedDir::begin("--out", dir, Replace::Whole))
        .transpose()?)
}
