//! `signorini run`: one run of a scene, bar or box, with its summary on the terminal and,
//! with `--out`, its result and histories as files.

use std::path::{Path, PathBuf};

use clap::Args;

use super::failure::Failure;
use super::limits::LimitArgs;
use super::options::{parsed, ConventionArgs, LinearSolverArgs};
use crate::commands::command_error::CommandError;
use crate::harness::files::artifacts::write_atomic;
use crate::harness::files::output_dir::{Replace, StagedDir};
use crate::harness::problem::{ContactTreatment, MassVariant, Scheme};
use crate::harness::reference::scene_run::{RunChoices, SceneRun};
use crate::harness::run::run_files::RUN_JSON;
use crate::harness::study::budget::Limits;
use crate::harness::study::progress;
use crate::harness::study::scene::Scene;
use crate::studies::error::Error;

/// The arguments of `signorini run`.
#[derive(Debug, Args)]
pub struct RunArgs {
    /// The scene file (see scenes/).
    pub scene: PathBuf,
    /// Scheme: a preset name (see `signorini list`) or newmark(beta=B,gamma=G),
    /// theta(theta=T), paoli-schatzman(beta=B,e=E).
    #[arg(long, value_parser = parsed::<Scheme>)]
    pub scheme: Scheme,
    /// Mass matrix: standard, redistributed, lumped, redistributed-conserving,
    /// singular-dynamic, getfem-redistributed or getfem-singular (see `signorini list`).
    #[arg(long, value_parser = parsed::<MassVariant>)]
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
    #[arg(long, value_parser = parsed::<ContactTreatment>)]
    pub contact: Option<ContactTreatment>,
    /// Print the largest per-step residual of the scheme's discrete energy balance (1D paper
    /// eqs. 33, 35, 37, on a bar or a box) relative to its scale (also in run.json with --out).
    /// Every run checks it: one above 1e-9 ends solver-inaccurate, with exit code 1.
    #[arg(long)]
    pub check_balance: bool,
    /// Write a box's fields at every step (not only at the scene's `fields_at` times), with
    /// --out: the ParaView collection `fields.pvd` then holds the whole run, as `signorini
    /// verify` reads another code's.
    #[arg(long, requires = "out")]
    pub fields_every_step: bool,
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
    let choices = RunChoices {
        scheme: args.scheme,
        mass: args.mass,
        nx: args.nx,
        ratio: args.ratio,
        contact: args.contact,
        conventions: args.conventions.choice(),
        linear_solver: args.solver.linear_solver,
        check_balance: args.check_balance,
        writes_files: args.out.is_some(),
        fields_every_step: args.fields_every_step,
    };
    let (out, limits) = (args.out.as_deref(), args.limits.limits());
    Ok(run_scene_of(
        &args.scene,
        choices,
        out,
        &limits,
        &mut |said| out!("{said}"),
    )?)
}

/// `signorini run` below the command line: the run of `choices` on the scene file `scene`,
/// held to `limits`, its summary told to `say`; with `out`, its files written there whole or
/// not at all, and each named.
fn run_scene_of(
    scene: &Path,
    choices: RunChoices,
    out: Option<&Path>,
    limits: &Limits,
    say: &mut dyn FnMut(&str),
) -> Result<(), CommandError> {
    let scene_file = scene;
    let scene = Scene::load(scene)?;
    if let Some(w) = choices.scheme.warning() {
        progress::note(&format!("warning: {w}"));
    }
    let check_balance = choices.check_balance;
    let run = SceneRun::of(&scene, choices)?;
    run.estimate().check(limits).map_err(Error::from)?;
    let staged = out
        .map(|dir| StagedDir::begin("--out", dir, Replace::Whole)?.reading(&[scene_file]))
        .transpose()?;
    if let Some(advice) = run.advice() {
        say(&advice);
    }
    let mut outcome = run.run(staged.as_ref().map(StagedDir::path))?;
    say(&outcome.summary(&run, check_balance));
    let (Some(dir), Some(staged)) = (out, staged) else {
        return Ok(());
    };
    let (json, histories) = outcome.files(&run, |f| staged.final_path(f))?;
    write_atomic(&staged.path().join(RUN_JSON), json.as_bytes())?;
    let mut written = vec![dir.join(RUN_JSON)];
    for (name, text) in histories {
        write_atomic(&staged.path().join(&name), text.as_bytes())?;
        written.push(dir.join(name));
    }
    staged.commit()?;
    written.extend(outcome.vtk_files().iter().cloned());
    say(&wrote(dir, &written));
    Ok(())
}

/// What a run wrote into `dir`, in one line: how many files, and their names, the field
/// snapshots (`field-t<T>.vtu`) as their count with the first and the last.
fn wrote(dir: &Path, files: &[PathBuf]) -> String {
    let name = |f: &PathBuf| {
        f.file_name()
            .map_or(String::new(), |n| n.to_string_lossy().into_owned())
    };
    let is_snapshot = |n: &str| n.starts_with("field-t") && n.ends_with(".vtu");
    let snapshots: Vec<String> = files.iter().map(name).filter(|n| is_snapshot(n)).collect();
    let mut named: Vec<String> = files.iter().map(name).filter(|n| !is_snapshot(n)).collect();
    match snapshots.as_slice() {
        [] => {}
        [only] => named.push(only.clone()),
        [first, .., last] => named.push(format!(
            "{} field snapshots ({first} … {last})",
            snapshots.len()
        )),
    }
    format!(
        "wrote {} files into {}: {}",
        files.len(),
        dir.display(),
        named.join(", ")
    )
}
