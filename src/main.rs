//! The `signorini` command line: runs, refinement studies, the report and the golden files.

use std::collections::BTreeSet;
use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Parser, Subcommand, ValueEnum};

use signorini::fem::MassVariant;
use signorini::norms::Norm;
use signorini::output::write_atomic;
use signorini::pipeline::{write_defaults_experiment, write_golden, write_report, GOLDEN_TABLES};
use signorini::report::convergence_tables;
use signorini::run::{run, Observables, Problem1d, RunConfig};
use signorini::schemes::Scheme;
use signorini::study::{run_study, Case, StudyConfig};

/// Verification and regression harness for dynamic contact (Dabaghi, Petrov, Pousin, Renard).
#[derive(Parser)]
#[command(name = "signorini", version, about, long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

/// The built-in 1D benchmarks.
#[derive(Clone, Copy, ValueEnum)]
enum Benchmark {
    /// §5: bar clamped at x = 1, obstacle at x = 0, exact solution of period 3.
    SignoriniDirichlet,
    /// No obstacle: the clamped bar's first mode (smooth, for second-order checks).
    FreeVibration,
}

impl Benchmark {
    fn problem(self, horizon: f64) -> Problem1d {
        match self {
            Benchmark::SignoriniDirichlet => Problem1d::signorini_dirichlet(horizon),
            Benchmark::FreeVibration => Problem1d::free_vibration(horizon),
        }
    }

    fn norms(self) -> BTreeSet<Norm> {
        let mut all: BTreeSet<Norm> = Norm::ALL.into_iter().collect();
        if matches!(self, Benchmark::FreeVibration) {
            all.remove(&Norm::MultiplierL2);
        }
        all
    }
}

#[derive(Subcommand)]
enum Command {
    /// One run: print the error norms; with --out, write the contact and energy histories.
    ///
    /// Example: signorini run --scheme crank-nicolson --mass redistributed --nx 80
    Run {
        /// The benchmark.
        #[arg(long, value_enum, default_value_t = Benchmark::SignoriniDirichlet)]
        benchmark: Benchmark,
        /// Scheme name (see `signorini list`) or newmark(beta=B,gamma=G), theta(theta=T),
        /// paoli-schatzman(beta=B,e=E).
        #[arg(long, value_parser = parse_scheme)]
        scheme: Scheme,
        /// Mass matrix: standard or redistributed.
        #[arg(long, value_parser = parse_mass)]
        mass: MassVariant,
        /// Number of elements.
        #[arg(long)]
        nx: usize,
        /// Δx/Δt.
        #[arg(long, default_value_t = 10.0)]
        ratio: f64,
        /// Horizon T.
        #[arg(long, default_value_t = 3.0)]
        horizon: f64,
        /// Directory for run.json (errors, histories).
        #[arg(long)]
        out: Option<PathBuf>,
    },
    /// A refinement study: the rate table of the selected cases and norms (markdown or JSON).
    ///
    /// Example: signorini study --scheme crank-nicolson --mass redistributed --norm u_Linf_H
    Study {
        /// The benchmark.
        #[arg(long, value_enum, default_value_t = Benchmark::SignoriniDirichlet)]
        benchmark: Benchmark,
        /// Schemes to run (repeat or comma-separate); default: the paper's seven.
        #[arg(long, value_delimiter = ';', value_parser = parse_scheme)]
        scheme: Vec<Scheme>,
        /// Mass variants; default: both.
        #[arg(long, value_delimiter = ',', value_parser = parse_mass)]
        mass: Vec<MassVariant>,
        /// Norms (u_Linf_H, u_L2_H, u_Linf_V, u_L2_V, lambda_L2, energy_Linf, energy_L2);
        /// default: all the benchmark defines.
        #[arg(long, value_delimiter = ',', value_parser = parse_norm)]
        norm: Vec<Norm>,
        /// Levels (NX), increasing.
        #[arg(long, value_delimiter = ',', default_values_t = vec![10usize, 20, 40, 80, 160, 320, 640])]
        levels: Vec<usize>,
        /// Δx/Δt.
        #[arg(long, default_value_t = 10.0)]
        ratio: f64,
        /// Horizon T.
        #[arg(long, default_value_t = 3.0)]
        horizon: f64,
        /// Print JSON instead of markdown.
        #[arg(long)]
        json: bool,
    },
    /// What `make report` runs: Tables 1–2 beside the paper into reports/.
    Report {
        /// Output directory.
        #[arg(long, default_value = "reports")]
        out: PathBuf,
    },
    /// How the Tables 1–2 rates move with the horizon and the level range (what `make
    /// experiment` runs): writes defaults-experiment.md.
    Experiment {
        /// Output directory.
        #[arg(long, default_value = "reports")]
        out: PathBuf,
    },
    /// Regenerate the golden rates (what `make golden` runs; nothing else writes them).
    Golden {
        /// The golden file.
        #[arg(long, default_value = GOLDEN_TABLES)]
        path: PathBuf,
    },
    /// The schemes with their parameters, the mass variants and the norms.
    List,
}

fn parse_scheme(s: &str) -> Result<Scheme, String> {
    s.parse()
        .map_err(|e: signorini::error::ParameterError| e.to_string())
}

fn parse_mass(s: &str) -> Result<MassVariant, String> {
    s.parse()
        .map_err(|e: signorini::error::ParameterError| e.to_string())
}

fn parse_norm(s: &str) -> Result<Norm, String> {
    s.parse()
        .map_err(|e: signorini::error::ParameterError| e.to_string())
}

fn list() {
    println!("Schemes (name: family and parameters; paper label):");
    for (name, scheme, label) in Scheme::presets() {
        println!("  {name:22} {scheme:?}  [{label}]");
    }
    println!("  newmark(beta=B,gamma=G)  theta(theta=T)  paoli-schatzman(beta=B,e=E)");
    println!("Mass variants:");
    println!("  standard       consistent mass matrix M");
    println!("  redistributed  M^mod: elements touching the contact boundary removed (§3.2)");
    println!("Norms:");
    for n in Norm::ALL {
        println!("  {:12} {}", n.key(), n.label());
    }
    println!("Benchmarks: signorini-dirichlet (§5), free-vibration (no obstacle)");
}

fn execute(cli: Cli) -> Result<(), Box<dyn std::error::Error>> {
    match cli.command {
        Command::Run {
            benchmark,
            scheme,
            mass,
            nx,
            ratio,
            horizon,
            out,
        } => {
            let config = RunConfig {
                nx,
                ratio,
                scheme,
                mass,
                observables: Observables {
                    norms: benchmark.norms(),
                    contact_history: out.is_some(),
                    energy_history: out.is_some(),
                },
            };
            let result = run(&benchmark.problem(horizon), &config)?;
            println!(
                "{} / {}: NX = {}, Δt = {:.4e}, {} steps, {} dofs, {:.3} s",
                scheme,
                mass,
                nx,
                result.dt,
                result.steps,
                result.dofs,
                result.timings.setup + result.timings.stepping + result.timings.observe
            );
            for (norm, e) in &result.errors {
                println!("  {:12} {:.6e}", norm.key(), e);
            }
            if let Some(dir) = out {
                let path = dir.join("run.json");
                write_atomic(&path, serde_json::to_string_pretty(&result)?.as_bytes())?;
                println!("wrote {}", path.display());
            }
        }
        Command::Study {
            benchmark,
            scheme,
            mass,
            norm,
            levels,
            ratio,
            horizon,
            json,
        } => {
            let schemes = if scheme.is_empty() {
                Scheme::paper_schemes().to_vec()
            } else {
                scheme
            };
            let masses = if mass.is_empty() {
                MassVariant::ALL.to_vec()
            } else {
                mass
            };
            let norms: BTreeSet<Norm> = if norm.is_empty() {
                benchmark.norms()
            } else {
                norm.into_iter().collect()
            };
            let cases: Vec<Case> = schemes
                .iter()
                .flat_map(|&scheme| masses.iter().map(move |&mass| Case { scheme, mass }))
                .collect();
            let config = StudyConfig {
                levels,
                ratio,
                horizon,
            };
            let study = run_study(&benchmark.problem(horizon), &cases, &norms, &config)?;
            if json {
                println!("{}", serde_json::to_string_pretty(&study)?);
            } else {
                print!("{}", convergence_tables(&study));
                println!(
                    "({} cases, {:.2} s wall)",
                    study.cases.len(),
                    study.wall_seconds
                );
            }
        }
        Command::Report { out } => {
            let study = write_report(&out)?;
            println!(
                "wrote {}/tables.md and {}/rates.json ({} cases, study {:.1} s wall)",
                out.display(),
                out.display(),
                study.cases.len(),
                study.wall_seconds
            );
        }
        Command::Experiment { out } => {
            let md = write_defaults_experiment(&out)?;
            let summary: String = md.lines().skip(4).take(7).collect::<Vec<_>>().join("\n");
            println!("{summary}\nwrote {}/defaults-experiment.md", out.display());
        }
        Command::Golden { path } => {
            let golden = write_golden(&path)?;
            println!("wrote {} ({} cases)", path.display(), golden.cases.len());
        }
        Command::List => list(),
    }
    Ok(())
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    match execute(cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}
