//! The `signorini` command line: runs, refinement studies, the report and the golden files.
//!
//! Exit codes: 0 success; 2 usage errors (bad arguments, a scene file that is missing,
//! malformed or out of range); 1 failures (a run that fails, an energy balance that
//! `--check-balance` finds violated, an output that cannot be written).

use std::collections::BTreeSet;
use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::{Parser, Subcommand};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

use signorini::contact::{ContactTreatment, TREATMENT_LIST};
use signorini::elastic::{run_box, BoxProblem, BoxRunConfig};
use signorini::elastic_study::{obtain_reference, run_elastic_study, ElasticStudyConfig};
use signorini::error::{Error as EngineError, ParameterError};
use signorini::fem::MassVariant;
use signorini::harness::report::convergence_tables;
use signorini::harness::run_files::{box_history_csv, history_csv, RUN_JSON};
use signorini::norms::Norm;
use signorini::output::write_atomic;
use signorini::run::{run, RunConfig};
use signorini::scene::{scene_files, Scene, SceneError};
use signorini::schemes::energy_balance::{self, BALANCE_TOLERANCE};
use signorini::schemes::Scheme;
use signorini::sensitivity::{run_sensitivity, EnsembleConfig};
use signorini::studies::elastic_study::files::write_elastic_report;
use signorini::studies::experiment::write_defaults_experiment;
use signorini::studies::extended::write_extended_report;
use signorini::studies::figures::from_reports::{reports_index, write_figures, REPORTS_INDEX};
use signorini::studies::golden::write_golden;
use signorini::studies::gravity::write_gravity_report;
use signorini::studies::report::write_report;
use signorini::studies::stability::write_stability;
use signorini::studies::tables::write_sensitivity_files;
use signorini::study::{run_study_with_progress, study_size, Case};

/// `println!` that ignores a closed stdout (`signorini list | head` must not panic).
macro_rules! out {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        let _ = writeln!(std::io::stdout(), $($arg)*);
    }};
}

const AFTER_HELP: &str = "\
Examples:
  signorini list
  signorini run scenes/bar1d-dirichlet.json --scheme crank-nicolson --mass redistributed --nx 80
  signorini run scenes/bar1d-dirichlet.json --scheme 'newmark(beta=0.3,gamma=0.6)' --mass standard --nx 40 --out out/
  signorini run scenes/bar1d-dirichlet.json --scheme backward-euler --mass standard --contact 'penalty(gamma0=10)'
  signorini run scenes/bar1d-dirichlet.json --scheme paoli-schatzman-e0.5 --mass redistributed --check-balance
  signorini study scenes/bar1d-dirichlet.json --scheme crank-nicolson --mass standard,redistributed --norm u_Linf_H,energy_L2
  signorini study scenes/bar1d-free.json --scheme crank-nicolson --mass standard --json
  signorini report

Exit codes: 0 success, 2 usage error (arguments or scene file), 1 failure.";

/// Verification and regression harness for dynamic contact: an elastic bar hits a rigid
/// obstacle; schemes of Dabaghi, Petrov, Pousin & Renard are run with the standard or the
/// redistributed mass matrix and compared with exact solutions.
#[derive(Parser)]
#[command(name = "signorini", version, about, after_help = AFTER_HELP)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// One run of a scene: the requested error norms on the terminal; with --out, run.json
    /// plus the histories the scene asks for (contact.csv, multiplier.csv, energy.csv).
    Run {
        /// The scene file (see scenes/).
        scene: PathBuf,
        /// Scheme: a preset name (see `signorini list`) or newmark(beta=B,gamma=G),
        /// theta(theta=T), paoli-schatzman(beta=B,e=E).
        #[arg(long, value_parser = parse_scheme)]
        scheme: Scheme,
        /// Mass matrix: standard, redistributed, lumped, redistributed-conserving or
        /// singular-dynamic (see `signorini list`).
        #[arg(long, value_parser = parse_mass)]
        mass: MassVariant,
        /// Number of elements NX (>= 1; along the bar for a 2D/3D box). Default: the scene's
        /// finest level.
        #[arg(long)]
        nx: Option<usize>,
        /// Δx/Δt (default: the scene's).
        #[arg(long, allow_hyphen_values = true)]
        ratio: Option<f64>,
        /// Output directory for run.json and the CSV histories.
        #[arg(long)]
        out: Option<PathBuf>,
        /// Contact treatment: multiplier, penalty(gamma0=G), nitsche(theta=T,gamma0=G) (1D
        /// only). Default: the scene's, else multiplier.
        #[arg(long, value_parser = parse_contact)]
        contact: Option<ContactTreatment>,
        /// Evaluate the scheme's discrete energy balance (1D paper eqs. 33, 35, 37) after every
        /// step: print the largest per-step residual relative to the energy (also in run.json
        /// with --out) and fail with exit code 1 when it exceeds 1e-9. 1D scenes only.
        #[arg(long)]
        check_balance: bool,
    },
    /// A refinement study of a scene: the rate table of the selected cases and norms, as
    /// markdown or JSON. Nothing outside the selection is computed.
    Study {
        /// The scene file.
        scene: PathBuf,
        /// Schemes (repeat the option for several); default: the paper's seven.
        #[arg(long, value_parser = parse_scheme)]
        scheme: Vec<Scheme>,
        /// Mass variants, comma-separated; default: the paper's two (standard, redistributed).
        #[arg(long, value_delimiter = ',', value_parser = parse_mass)]
        mass: Vec<MassVariant>,
        /// Norms, comma-separated; default: the scene's.
        #[arg(long, value_delimiter = ',', value_parser = parse_norm)]
        norm: Vec<Norm>,
        /// Levels NX, comma-separated and increasing; default: the scene's.
        #[arg(long, value_delimiter = ',')]
        levels: Vec<usize>,
        /// Δx/Δt (default: the scene's).
        #[arg(long, allow_hyphen_values = true)]
        ratio: Option<f64>,
        /// Print JSON instead of markdown.
        #[arg(long)]
        json: bool,
        /// Box scenes: elements along the axis of the fine-mesh reference (default: the
        /// scene's `discretisation.reference_level`).
        #[arg(long)]
        reference_level: Option<usize>,
        /// Box scenes: write elastic-<d>d.md, elastic-<d>d.json and the figure data into this
        /// reports directory instead of printing.
        #[arg(long)]
        out: Option<PathBuf>,
        /// Box scenes: where the fine-mesh reference is cached.
        #[arg(long, default_value = "reports/data/references")]
        cache: PathBuf,
        /// Contact treatment of every case: multiplier, penalty(gamma0=G),
        /// nitsche(theta=T,gamma0=G) (1D only). Default: the scene's, else multiplier.
        #[arg(long, value_parser = parse_contact)]
        contact: Option<ContactTreatment>,
    },
    /// Round-off sensitivity of a bar1d scene's study (`make report`): every case and level run
    /// as an ensemble of members with seeded noise of relative size A on the initial
    /// displacement; writes sensitivity.md and sensitivity.json with each case's class.
    Sensitivity {
        /// The scene file (a bar1d scene with an obstacle).
        scene: PathBuf,
        /// Perturbed members per case and level (2 to 1024).
        #[arg(long, default_value_t = 16)]
        members: usize,
        /// Relative noise amplitude, in (0, 1e-3].
        #[arg(long, default_value_t = 1e-13, allow_hyphen_values = true)]
        amplitude: f64,
        /// Output directory.
        #[arg(long, default_value = "reports")]
        out: PathBuf,
    },
    /// The fine-mesh reference of a box scene (`make reference`): reuses the cache when its
    /// parameters match the scene's, says which differ otherwise, and recomputes it.
    Reference {
        /// Box scene files.
        #[arg(required = true)]
        scenes: Vec<PathBuf>,
        /// Where the references are cached.
        #[arg(long, default_value = "reports/data/references")]
        cache: PathBuf,
    },
    /// What `make report` runs: Tables 1–2 beside the paper into reports/.
    Report {
        /// Output directory.
        #[arg(long, default_value = "reports")]
        out: PathBuf,
    },
    /// How the Tables 1–2 rates move with the horizon and the level range (`make experiment`).
    Experiment {
        /// Output directory.
        #[arg(long, default_value = "reports")]
        out: PathBuf,
    },
    /// Draw the figures (SVG) from the data under a reports directory into its figures/
    /// (`make figures`), and write its README.md index.
    Figures {
        /// The reports directory.
        #[arg(long, default_value = "reports")]
        reports: PathBuf,
    },
    /// The stability suite (`make stability`): every scheme × mass on the hard cases, with a
    /// verdict each; writes stability.md and stability.json.
    Stability {
        /// Output directory.
        #[arg(long, default_value = "reports")]
        out: PathBuf,
        /// Only the fast subset that CI guards.
        #[arg(long)]
        ci_subset: bool,
    },
    /// Regenerate the golden rates of the gated studies with their round-off sensitivity (`make
    /// golden`; nothing else writes them): golden/rates-1d-dirichlet.json,
    /// rates-1d-gravity.json, rates-1d-extended.json and rates-2d.json.
    Golden {
        /// The repository root (scenes/ and golden/ are under it).
        #[arg(long, default_value = ".")]
        root: PathBuf,
    },
    /// The schemes with their parameters, the mass variants, the norms and the scenes found.
    List {
        /// Where to look for scene files.
        #[arg(long, default_value = "scenes")]
        scenes: PathBuf,
    },
}

fn parse_scheme(s: &str) -> Result<Scheme, String> {
    s.parse().map_err(|e: ParameterError| e.to_string())
}

fn parse_contact(s: &str) -> Result<ContactTreatment, String> {
    s.parse().map_err(|e: ParameterError| e.to_string())
}

fn parse_mass(s: &str) -> Result<MassVariant, String> {
    s.parse().map_err(|e: ParameterError| e.to_string())
}

fn parse_norm(s: &str) -> Result<Norm, String> {
    s.parse().map_err(|e: ParameterError| e.to_string())
}

/// A failure with its exit code.
struct Failure {
    code: u8,
    message: String,
}

impl Failure {
    fn usage(e: impl std::fmt::Display) -> Self {
        Self {
            code: 2,
            message: e.to_string(),
        }
    }

    fn runtime(e: impl std::fmt::Display) -> Self {
        Self {
            code: 1,
            message: e.to_string(),
        }
    }
}

impl From<SceneError> for Failure {
    fn from(e: SceneError) -> Self {
        Self::usage(e)
    }
}

impl From<EngineError> for Failure {
    fn from(e: EngineError) -> Self {
        match e {
            EngineError::Parameter(p) => Self::usage(p),
            EngineError::Solve(s) if s.is_usage() => Self::usage(s),
            EngineError::Solve(s) => Self::runtime(s),
            EngineError::Io(m) => Self::runtime(m),
        }
    }
}

/// `signorini study` of a box scene: the report printed (markdown or JSON) or written to `out`.
fn elastic_study(
    problem: &BoxProblem,
    config: &ElasticStudyConfig,
    out: Option<PathBuf>,
    cache: &Path,
    json: bool,
) -> Result<(), Failure> {
    let mut note = |why: String| eprintln!("{why}; computing the reference");
    if let Some(dir) = out {
        let study = write_elastic_report(problem, config, &dir, cache, &mut note)
            .map_err(Failure::runtime)?;
        out!(
            "wrote {dir}/elastic-{d}d.md, {dir}/elastic-{d}d.json and \
             {dir}/data/elastic-{d}d-histories.json ({} cases, study {:.1} s wall)",
            study.study.cases.len(),
            study.study.wall_seconds,
            dir = dir.display(),
            d = study.dimension
        );
        if let Some(s) = &study.sensitivity {
            for c in &s.cases {
                out!("  {:36} {}", c.case, c.class.name());
            }
            out!(
                "round-off ensemble: {} members per case and level, {:.1} s wall",
                s.ensemble.members,
                s.wall_seconds
            );
        }
        return Ok(());
    }
    let (study, _) = run_elastic_study(problem, config, cache, &mut note)?;
    if json {
        out!(
            "{}",
            serde_json::to_string_pretty(&study).map_err(Failure::runtime)?
        );
    } else {
        out!(
            "{}",
            signorini::elastic_study::report::render(&study).trim_end()
        );
    }
    Ok(())
}

fn write_output(path: &Path, contents: &[u8]) -> Result<(), Failure> {
    write_atomic(path, contents)
        .map_err(|e| Failure::runtime(format!("cannot write {}: {e}", path.display())))
}

fn list(dir: &Path) {
    out!("Schemes (preset name, parameters, the paper's name):");
    for (name, scheme, label) in Scheme::presets() {
        let params = match scheme {
            Scheme::Newmark { beta, gamma } => format!("Newmark β = {beta}, γ = {gamma}"),
            Scheme::Theta { theta } => format!("θ-method θ = {theta}"),
            Scheme::PaoliSchatzman { beta, restitution } => {
                format!("Paoli–Schatzman β = {beta}, e = {restitution}")
            }
        };
        out!("  {name:22} {params:34} {label}");
    }
    out!("  any parameters: newmark(beta=B,gamma=G), theta(theta=T), paoli-schatzman(beta=B,e=E)");
    out!("\nMass variants:");
    for m in MassVariant::ALL {
        out!(
            "  {:25} {:5} {}",
            m.name(),
            m.paper_label(),
            m.description()
        );
    }
    out!("\nContact treatments (E the Young modulus, ρc² for a bar; h the mesh size at the contact):");
    for (name, params, description) in TREATMENT_LIST {
        out!("  {name:27} {params:22} {description}");
    }
    out!("\nNorms:");
    for n in Norm::ALL {
        out!("  {:12} {}", n.key(), n.label());
    }
    out!("\nScenes in {}:", dir.display());
    let files = scene_files(dir);
    if files.is_empty() {
        out!("  (none)");
    }
    for f in files {
        match Scene::load(&f) {
            Ok(s) => out!("  {:40} {}", f.display(), s.description),
            Err(e) => out!("  {:40} INVALID: {e}", f.display()),
        }
    }
}

/// `signorini run` on a 2D/3D box scene: a summary, and with `--out` run.json, energy.csv,
/// contact.csv and the VTK snapshots at the scene's `fields_at` times.
fn run_box_scene(
    scene: &Scene,
    problem: &BoxProblem,
    scheme: Scheme,
    mass: MassVariant,
    n_axis: usize,
    ratio: Option<f64>,
    out: Option<PathBuf>,
) -> Result<(), Failure> {
    if let Some(dir) = &out {
        std::fs::create_dir_all(dir)
            .map_err(|e| Failure::runtime(format!("cannot create {}: {e}", dir.display())))?;
    }
    let config = BoxRunConfig {
        n_axis,
        ratio: ratio.unwrap_or(scene.discretisation.ratio),
        scheme,
        mass,
        vtk_at: if out.is_some() {
            scene.observables.fields_at.clone()
        } else {
            Vec::new()
        },
        vtk_dir: out.clone(),
    };
    if out.is_none() && !scene.observables.fields_at.is_empty() {
        out!(
            "(the scene asks for fields at {:?}: pass --out DIR to write them as VTK)",
            scene.observables.fields_at
        );
    }
    let r = run_box(problem, &config)?;
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
    out!(
        "  energy {e0:.6e} → {e_end:.6e}; largest total contact force {max_force:.4e}; complementarity {:.1e}",
        r.complementarity_violation
    );
    if let Some(dir) = out {
        let json = serde_json::to_string_pretty(&r).map_err(Failure::runtime)?;
        write_output(&dir.join(RUN_JSON), json.as_bytes())?;
        for (name, text) in box_history_csv(&r) {
            write_output(&dir.join(&name), text.as_bytes())?;
        }
        for f in &r.vtk_files {
            out!("wrote {}", f.display());
        }
        out!("wrote {}", dir.display());
    }
    Ok(())
}

fn progress_bar(len: usize) -> ProgressBar {
    let visible = std::io::stderr().is_terminal() && std::env::var_os("CI").is_none();
    let bar = ProgressBar::with_draw_target(
        Some(len as u64),
        if visible {
            ProgressDrawTarget::stderr()
        } else {
            ProgressDrawTarget::hidden()
        },
    );
    bar.set_style(
        ProgressStyle::with_template("{bar:40} {pos}/{len} runs, {elapsed} elapsed, ETA {eta}")
            .expect("valid template"),
    );
    bar
}

fn execute(cli: Cli) -> Result<(), Failure> {
    match cli.command {
        Command::Run {
            scene,
            scheme,
            mass,
            nx,
            ratio,
            out,
            contact,
            check_balance,
        } => {
            let scene = Scene::load(&scene)?;
            let nx = nx.unwrap_or_else(|| {
                *scene
                    .discretisation
                    .levels
                    .last()
                    .expect("validated: at least one level")
            });
            if let Some(mut problem) = scene.box_problem() {
                if check_balance {
                    return Err(Failure::usage(
                        "--check-balance: 1D scenes only (the 2D/3D run does not evaluate the \
                         energy balance)",
                    ));
                }
                problem.contact = contact.unwrap_or(problem.contact);
                return run_box_scene(&scene, &problem, scheme, mass, nx, ratio, out);
            }
            let mut problem = scene.problem();
            problem.contact = contact.unwrap_or(problem.contact);
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
            if let Some(dir) = &out {
                std::fs::create_dir_all(dir).map_err(|e| {
                    Failure::runtime(format!("cannot create {}: {e}", dir.display()))
                })?;
            }
            let result = run(&problem, &config)?;
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
            let equation = energy_balance::equation(scheme);
            if let Some(residual) = result.max_balance_residual {
                out!(
                    "  energy balance eq. {equation}: largest per-step residual {residual:.3e} \
                     of the energy (tolerance {BALANCE_TOLERANCE:e})"
                );
            }
            if let Some(dir) = out {
                let json = serde_json::to_string_pretty(&result).map_err(Failure::runtime)?;
                write_output(&dir.join(RUN_JSON), json.as_bytes())?;
                for (name, text) in history_csv(&result) {
                    write_output(&dir.join(&name), text.as_bytes())?;
                }
                out!("wrote {}", dir.display());
            }
            if let Some(residual) = result
                .max_balance_residual
                .filter(|r| r.is_nan() || *r > BALANCE_TOLERANCE)
            {
                return Err(Failure::runtime(format!(
                    "energy balance eq. {equation} violated: largest per-step residual \
                     {residual:.3e} of the energy exceeds {BALANCE_TOLERANCE:e}"
                )));
            }
        }
        Command::Study {
            scene,
            scheme,
            mass,
            norm,
            levels,
            ratio,
            json,
            reference_level,
            out,
            cache,
            contact,
        } => {
            let scene = Scene::load(&scene)?;
            if let Some(mut problem) = scene.box_problem() {
                problem.contact = contact.unwrap_or(problem.contact);
                let mut config = ElasticStudyConfig::from_scene(&scene, reference_level)
                    .map_err(EngineError::from)?;
                if !levels.is_empty() {
                    config.levels = levels;
                }
                if let Some(r) = ratio {
                    config.ratio = r;
                }
                if !scheme.is_empty() || !mass.is_empty() {
                    let schemes = if scheme.is_empty() {
                        scene.default_schemes()
                    } else {
                        scheme
                    };
                    let masses = if mass.is_empty() {
                        vec![MassVariant::Standard, MassVariant::Redistributed]
                    } else {
                        mass
                    };
                    config.cases = Case::matrix(&schemes, &masses);
                }
                return elastic_study(&problem, &config, out, &cache, json);
            }
            if reference_level.is_some() || out.is_some() {
                return Err(Failure::usage(format!(
                    "scene {}: --reference-level and --out are for box scenes (a bar1d study \
                     compares with the exact solution and prints its tables)",
                    scene.name
                )));
            }
            let schemes = if scheme.is_empty() {
                scene.default_schemes()
            } else {
                scheme
            };
            let masses = if mass.is_empty() {
                MassVariant::PAPER.to_vec()
            } else {
                mass
            };
            let norms: BTreeSet<Norm> = if norm.is_empty() {
                scene.norms()
            } else {
                norm.into_iter().collect()
            };
            let cases = Case::matrix(&schemes, &masses);
            let mut config = scene.study_config();
            if !levels.is_empty() {
                config.levels = levels;
            }
            if let Some(r) = ratio {
                config.ratio = r;
            }
            let bar = progress_bar(study_size(&cases, &config));
            let mut problem = scene.problem();
            problem.contact = contact.unwrap_or(problem.contact);
            let study = run_study_with_progress(&problem, &cases, &norms, &config, &|| bar.inc(1))?;
            bar.finish_and_clear();
            if json {
                out!(
                    "{}",
                    serde_json::to_string_pretty(&study).map_err(Failure::runtime)?
                );
            } else {
                out!("{}\n", convergence_tables(&study).trim_end());
                out!(
                    "{}: {} cases × {} levels, {:.2} s wall",
                    scene.name,
                    study.cases.len(),
                    study.config.levels.len(),
                    study.wall_seconds
                );
            }
        }
        Command::Report { out } => {
            let gravity = write_gravity_report(Path::new("."), &out).map_err(Failure::runtime)?;
            out!(
                "wrote {}/gravity.md and {}/gravity/ ({} cases)",
                out.display(),
                out.display(),
                gravity.cases.len()
            );
            let study = write_report(&out).map_err(Failure::runtime)?;
            out!(
                "wrote {}/tables.md and {}/rates.json ({} cases, study {:.1} s wall)",
                out.display(),
                out.display(),
                study.cases.len(),
                study.wall_seconds
            );
            write_extended_report(&out).map_err(Failure::runtime)?;
            out!("wrote {}/extended.md", out.display());
        }
        Command::Experiment { out } => {
            let md = write_defaults_experiment(&out).map_err(Failure::runtime)?;
            let summary: Vec<&str> = md.lines().skip(4).take(7).collect();
            out!(
                "{}\nwrote {}/defaults-experiment.md",
                summary.join("\n"),
                out.display()
            );
        }
        Command::Figures { reports } => {
            let (names, missing) = write_figures(&reports).map_err(Failure::runtime)?;
            let index = reports_index(&names);
            write_output(&reports.join(REPORTS_INDEX), index.as_bytes())?;
            out!(
                "wrote {} figures into {}/figures and {}/README.md",
                names.len(),
                reports.display(),
                reports.display()
            );
            for m in missing {
                out!("skipped (input missing): {m}");
            }
        }
        Command::Stability { out, ci_subset } => {
            let records = write_stability(&out, ci_subset).map_err(Failure::runtime)?;
            let flagged = records
                .iter()
                .filter(|r| {
                    !matches!(
                        r.verdict,
                        signorini::stability::Verdict::Stable
                            | signorini::stability::Verdict::Dissipative
                    )
                })
                .count();
            out!(
                "wrote {}/stability.md ({} runs, {} flagged)",
                out.display(),
                records.len(),
                flagged
            );
        }
        Command::Reference { scenes, cache } => {
            for path in scenes {
                let scene = Scene::load(&path)?;
                let problem = scene.box_problem().ok_or_else(|| {
                    Failure::usage(format!(
                        "scene {}: a reference is for box scenes (a bar1d has an exact solution)",
                        scene.name
                    ))
                })?;
                let config =
                    ElasticStudyConfig::from_scene(&scene, None).map_err(EngineError::from)?;
                let mut computed = false;
                let reference = obtain_reference(&problem, &config, &cache, &mut |why| {
                    computed = true;
                    eprintln!("{why}; computing it");
                })?;
                out!(
                    "{}: reference {} on {:?} elements, {} unknowns, {} samples: {} ({:.1} s)",
                    scene.name,
                    reference.histories.key.scheme,
                    reference.mesh.counts(),
                    reference.histories.dofs,
                    reference.samples(),
                    if computed {
                        "computed and cached"
                    } else {
                        "the cache matches the scene's parameters"
                    },
                    reference.histories.seconds
                );
            }
        }
        Command::Sensitivity {
            scene,
            members,
            amplitude,
            out,
        } => {
            let scene = Scene::load(&scene)?;
            if scene.is_box() {
                return Err(Failure::usage(format!(
                    "scene {}: the sensitivity command is for bar1d scenes (a box scene's \
                     ensemble is its discretisation.sensitivity, run by `signorini study`)",
                    scene.name
                )));
            }
            let cases = Case::matrix(&scene.default_schemes(), &MassVariant::PAPER);
            let ensemble = EnsembleConfig { members, amplitude };
            let s = run_sensitivity(
                &scene.problem(),
                &cases,
                &scene.norms(),
                &scene.study_config(),
                ensemble,
            )?;
            write_sensitivity_files(&s, &out).map_err(|e| {
                Failure::runtime(format!("cannot write into {}: {e}", out.display()))
            })?;
            for c in &s.cases {
                out!("  {:36} {}", c.case, c.class.name());
            }
            out!(
                "wrote {}/sensitivity.md and {}/sensitivity.json ({} cases × {} levels × {} members, {:.1} s wall)",
                out.display(),
                out.display(),
                s.cases.len(),
                s.config.levels.len(),
                members,
                s.wall_seconds
            );
        }
        Command::Golden { root } => {
            for (name, golden) in write_golden(&root).map_err(Failure::runtime)? {
                out!("wrote {name} ({} cases)", golden.cases.len());
            }
        }
        Command::List { scenes } => list(&scenes),
    }
    Ok(())
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    match execute(cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(f) => {
            eprintln!("error: {}", f.message);
            ExitCode::from(f.code)
        }
    }
}
