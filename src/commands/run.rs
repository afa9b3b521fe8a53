//! `signorini run`: one run of a scene, bar or box, with its summary on the terminal and,
//! with `--out`, its result and histories as files.

use std::path::{Path, PathBuf};

use clap::Args;

use super::failure::{write_output, Failure};
use super::limits::LimitArgs;
use super::options::{
    parse_contact, parse_mass, parse_scheme, warn_schemes, ConventionArgs, LinearSolverArgs,
};
use crate::harness::files::output_dir::{Replace, StagedDir};
use crate::harness::problem::{ContactTreatment, MassVariant, Scheme};
use crate::harness::run::run_files::RUN_JSON;
use crate::harness::study::scene::Scene;
use crate::studies::scene_run::{RunChoices, SceneRun};

/// The arguments of `signorini run`.
#[derive(Debug, Args)]
pub struct RunArgs {
    /// The scene file (see scenes/).
    pub scene: PathBuf,
    /// Scheme: a preset name (see `signorini list`) or newmark(beta=B,gamma=G),
    /// theta(theta=T), paoli-schatzman(beta=B,e=E).
    #[arg(long, value_parser = parse_scheme)]
    pub scheme: Scheme,
    /// Mass matrix: standard, redistributed, lumped, redistributed-conserving,
    /// singular-dynamic, getfem-redistributed or getfem-singular (see `signorini list`).
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
/// plus the histories the scene asks for (CSV, and a box's VTK snapshots), staged and moved
/// into place whole at the end.
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
    let run = SceneRun::of(
        &scene,
        RunChoices {
            scheme,
            mass,
            nx,
            ratio,
            contact,
            conventions: conventions.choice(),
            linear_solver: solver.linear_solver,
            check_balance,
            writes_files: out.is_some(),
        },
    )?;
    limits.check(run.estimate())?;
    let staged = stage(out.as_deref())?;
    if let Some(advice) = run.advice() {
        out!("{advice}");
    }
    let mut outcome = run.run(staged.as_ref().map(StagedDir::path))?;
    out!("{}", outcome.summary(&run, check_balance));
    if let (Some(dir), Some(staged)) = (out, staged) {
        let (json, histories) = outcome.files(|f| staged.final_path(f))?;
        write_output(&staged.path().join(RUN_JSON), json.as_bytes())?;
        for (name, text) in histories {
            write_output(&staged.path().join(&name), text.as_bytes())?;
        }
        staged.commit()?;
        for f in outcome.vtk_files() {
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
