//! The gravity benchmark (1D paper §4, `make report`): the rate table of its scene's study, the
//! round-off sensitivity of its cases, and the data of the paper's Figures 2–4. Its files, under
//! a reports directory: `gravity.md`, and in `gravity/` the study ([`STUDY_JSON`]), the
//! sensitivity ([`SENSITIVITY_JSON`]), and per mass the NX = 160 run ([`run_file`]), the
//! displacement at points ([`points_file`]) and the strain fields ([`strain_file`]) as CSV.

use std::path::Path;

use crate::harness::files::artifacts::{write_atomic, write_json};
use crate::harness::problem::MassVariant;
use crate::harness::reference::exact::{run_study, ExactSolution};
use crate::harness::render::report::convergence_tables;
use crate::harness::run::run_files::{points_csv, strain_csv, strain_csv_name};
use crate::harness::run::{run, BarRun, RunConfig};
use crate::harness::study::executor::{Batch, Jobs};
use crate::harness::study::scene::Scene;
use crate::harness::study::sensitivity::{
    class_table, rate_ranges, run_sensitivity, EnsembleConfig, Sensitivity, SensitivityJobs,
};
use crate::harness::study::{Case, Study};
use crate::studies::benchmark::bar_scene;
use crate::studies::error::Error;

/// The golden file of the gravity benchmark's study, relative to the repository root.
pub const GOLDEN_GRAVITY: &str = "golden/rates-1d-gravity.json";

/// The gravity benchmark's scene, relative to the repository root.
pub const GRAVITY_SCENE: &str = "scenes/bar1d-gravity.json";

/// The rate table and the sensitivity classes, under a reports directory.
pub const GRAVITY_MD: &str = "gravity.md";

/// The directory of the benchmark's data, under a reports directory.
pub const GRAVITY_DIR: &str = "gravity";

/// The study ([`Study`]), under [`GRAVITY_DIR`].
pub const STUDY_JSON: &str = "study.json";

/// The round-off sensitivity ([`Sensitivity`]), under [`GRAVITY_DIR`].
pub const SENSITIVITY_JSON: &str = "sensitivity.json";

/// The level of the figure data.
pub const FIGURE_LEVEL: usize = 160;

/// The digits after the point of every number in the benchmark's CSV files.
const CSV_DIGITS: usize = 10;

/// The run of `mass` at [`FIGURE_LEVEL`] (a `BarRun`), under [`GRAVITY_DIR`].
pub fn run_file(mass: MassVariant) -> String {
    format!("run-{}.json", mass.name())
}

/// The displacement at the scene's points (Figure 2) of the run of `mass`, under
/// [`GRAVITY_DIR`].
pub fn points_file(mass: MassVariant) -> String {
    format!("points-{}.csv", mass.name())
}

/// The strain field (Figure 4) of the run of `mass` at `requested_time`, under [`GRAVITY_DIR`].
pub fn strain_file(mass: MassVariant, requested_time: f64) -> String {
    strain_csv_name(&format!("strain-{}", mass.name()), requested_time)
}

/// The cases of the gravity benchmark: its scene's schemes (Crank–Nicolson, then the rivals)
/// with both masses where they are defined.
fn gravity_cases(scene: &Scene) -> Vec<Case> {
    Case::matrix(&scene.default_schemes(), &MassVariant::PAPER)
}

/// The gravity benchmark's study (§4): the scene's schemes (Crank–Nicolson and the rivals) with
/// both masses, its levels, ratio and norms. `root` is the repository root.
pub fn gravity_study(root: &Path) -> Result<Study, Error> {
    let (scene, problem) = bar_scene(root, GRAVITY_SCENE)?;
    Ok(run_study(
        &problem,
        &gravity_cases(&scene),
        &scene.observables.norms,
        &scene.study_config(),
    )?)
}

/// The level whose predictability horizon and separation growth `gravity.md` shows.
const GRAVITY_SENSITIVITY_SHOWN_LEVEL: usize = 160;

/// The round-off sensitivity (default ensemble) of `cases` on the gravity benchmark's study
/// (its scene's problem, levels, ratio and norms): what `gravity.md` reports and what the gate
/// holds its chaotic cases to. `root` is the repository root.
pub fn gravity_sensitivity(root: &Path, cases: &[Case]) -> Result<Sensitivity, Error> {
    let (scene, problem) = bar_scene(root, GRAVITY_SCENE)?;
    Ok(run_sensitivity(
        &problem,
        cases,
        &scene.observables.norms,
        &scene.study_config(),
        EnsembleConfig::default(),
    )?)
}

/// The gravity benchmark as `signorini report` writes it: its study, the round-off sensitivity
/// of the cases the study ran, and their runs at [`FIGURE_LEVEL`].
pub struct GravityBenchmark {
    /// The benchmark's scene.
    scene: Scene,
    /// The study.
    pub study: Study,
    /// The round-off sensitivity of the study's cases.
    sensitivity: Sensitivity,
    /// The runs of the figures at [`FIGURE_LEVEL`], one per mass.
    figure_runs: Vec<(MassVariant, BarRun)>,
}

/// Hands the gravity benchmark's job lists to `batch` — the study, the round-off ensembles
/// and the [`FIGURE_LEVEL`] runs of the paper's figures (the scene's first scheme,
/// Crank–Nicolson, with both masses) — and returns the benchmark made of their
/// results (`None` for a shard). The ensembles and runs of a case the study could not run are
/// dropped, as if they had not run. `root` is the repository root.
pub fn gravity_benchmark(
    root: &Path,
    batch: &mut Batch<'_>,
) -> Result<Option<GravityBenchmark>, Error> {
    let (scene, problem) = bar_scene(root, GRAVITY_SCENE)?;
    let cases = gravity_cases(&scene);
    let config = scene.study_config();
    let norms = &scene.observables.norms;
    let study = ExactSolution::jobs(&problem, &cases, norms, &config)?;
    let ensembles =
        SensitivityJobs::new(&problem, &cases, norms, &config, EnsembleConfig::default())?;
    let figure_run = |case: &Case| {
        let config = RunConfig {
            nx: FIGURE_LEVEL,
            ratio: scene.discretisation.ratio,
            scheme: case.scheme,
            mass: case.mass,
            observables: scene.observables(),
            settings: scene.settings(),
        };
        run(&problem, &config, &mut [])
    };
    let figure_scheme = scene.default_schemes()[0];
    let figure_cases: Vec<Case> = cases
        .iter()
        .copied()
        .filter(|c| c.scheme == figure_scheme)
        .collect();
    let figures = Jobs {
        items: &figure_cases,
        size: &|_| FIGURE_LEVEL,
        run: &figure_run,
    };
    let ran = (
        batch.execute(&study.list())?,
        batch.execute(&ensembles.list())?,
        batch.execute(&figures)?,
    );
    let (Some(runs), Some(members), Some(figure_runs)) = ran else {
        return Ok(None);
    };
    let study = study.reduce(runs, &cases);
    let kept: Vec<Case> = study.cases.iter().map(|c| c.case).collect();
    let sensitivity = ensembles.reduce(members, &kept)?;
    let figure_runs = figure_cases
        .iter()
        .zip(figure_runs.results)
        .filter(|(case, _)| kept.contains(case))
        .map(|(case, r)| r.completed().map(|run| (case.mass, run)))
        .collect::<Result<_, _>>()?;
    Ok(Some(GravityBenchmark {
        scene,
        study,
        sensitivity,
        figure_runs,
    }))
}

/// Writes `gravity.md` and the data of the paper's Figures 2–4 (`gravity/`) of `benchmark` into
/// `out_dir`: the rate table of the gravity benchmark and, for both masses at NX = 160, the
/// displacement at x = 0, ½, 1 over time and the strain field at the scene's `fields_at` times,
/// as CSV.
pub fn write_gravity_report(benchmark: &GravityBenchmark, out_dir: &Path) -> Result<(), Error> {
    let GravityBenchmark {
        scene,
        study,
        sensitivity,
        figure_runs,
    } = benchmark;
    let mut md = format!(
        "# The gravity benchmark (1D paper §4)\n\n{}. Levels NX = {:?}, Δx/Δt = {}, T = {}; \
         errors against the closed-form solution (`BouncingBar`, exact: no truncated series). \
         Generated by `make report`.\n\n",
        scene.description, study.config.levels, study.config.ratio, study.config.horizon
    );
    md.push_str(&convergence_tables(study));
    md.push_str(&format!(
        "\n## Round-off sensitivity\n\nEvery case at every level run as {} (the rules of \
         `sensitivity.md`); a chaotic case's rates above are one sample of the ranges below. \
         The ensembles took {:.1} s wall (`gravity/sensitivity.json`).\n\n",
        sensitivity.ensemble.describe(),
        sensitivity.wall_seconds
    ));
    md.push_str(&class_table(sensitivity, GRAVITY_SENSITIVITY_SHOWN_LEVEL));
    md.push('\n');
    md.push_str(&rate_ranges(&sensitivity.cases));
    let data = out_dir.join(GRAVITY_DIR);
    write_json(&data.join(SENSITIVITY_JSON), sensitivity)?;
    for (mass, r) in figure_runs {
        let mass = *mass;
        if let Some(p) = &r.observed.point_history {
            write_atomic(
                &data.join(points_file(mass)),
                points_csv(p, CSV_DIGITS).as_bytes(),
            )?;
        }
        for f in &r.observed.fields {
            write_atomic(
                &data.join(strain_file(mass, f.requested_time)),
                strain_csv(f, CSV_DIGITS).as_bytes(),
            )?;
        }
        write_json(&data.join(run_file(mass)), r)?;
    }
    md.push_str(
        "\nFigure data (NX = 160): `gravity/points-<mass>.csv` (Figure 2: u at x = 0, ½, 1), \
         `gravity/strain-<mass>-t<T>.csv` (Figure 4: ∂x u computed and exact), \
         `gravity/run-<mass>.json` (histories of the contact node and the energy).\n",
    );
    write_atomic(&out_dir.join(GRAVITY_MD), md.as_bytes())?;
    write_json(&data.join(STUDY_JSON), study)?;
    Ok(())
}
