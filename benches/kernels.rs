//! `make bench`: the speed targets of the harness, measured on this machine.
//!
//! * the step kernel of each scheme at NX = 640 (Δx/Δt = 10, T = 3, 19 200 steps) with all
//!   seven observables, in nanoseconds per degree of freedom per step (target ≤ 25);
//! * the whole Tables 1–2 study (14 cases, NX 10–640, all norms), wall seconds (target ≤ 15);
//! * the peak memory of that study run by the binary, from `/usr/bin/time -v` (target ≤ 200 MB);
//! * the 1D round-off sensitivity study (14 cases × 7 levels × 16 members), wall seconds, one
//!   run (target ≤ 60, issue 15);
//! * the 3D runs of `scenes/bar3d.json` (Crank–Nicolson, redistributed mass, T = 2, the
//!   default step solver) of issue 19, wall seconds and peak memory, one run each: level 80
//!   (target ≤ 2 s), level 160, the size of the 3D study's reference (target ≤ 60 s), and with
//!   `--fine` (`make bench-fine`) level 320 (target ≤ 15 min and ≤ 6 GB).
//!
//! Each figure is the median of several repetitions (9 for the kernels). The figures go to
//! `reports/bench.md` and `reports/bench.json` (format `signorini-bench/1`, fields in
//! `docs/src/outputs.md`), written even when a target is missed; the process then exits with
//! status 1, so `make bench` checks them.

use std::collections::BTreeSet;
use std::path::Path;
use std::process::{Command, ExitCode};
use std::time::Instant;

use serde::Serialize;

use signorini::engine::fem::MassVariant;
use signorini::engine::schemes::Scheme;
use signorini::harness::files::artifacts::{write_atomic, write_json};
use signorini::harness::files::output_dir::{Replace, StagedDir};
use signorini::harness::run::norms::Norm;
use signorini::harness::run::{run, BarRun, Observables, RunConfig};
use signorini::harness::study::Case;
use signorini::studies::benchmark::dirichlet;
use signorini::studies::tables::{tables_sensitivity, tables_study};

const NS_PER_DOF_STEP_TARGET: f64 = 25.0;
const STUDY_SECONDS_TARGET: f64 = 15.0;
const PEAK_MEMORY_MB_TARGET: f64 = 200.0;
const SENSITIVITY_SECONDS_TARGET: f64 = 60.0;
/// Issue 19's 3D targets: `(level, wall seconds, peak MB)`; level 320 only with `--fine`
/// (`make bench-fine`).
const BOX_3D_TARGETS: [(usize, f64, f64); 3] =
    [(80, 2.0, 1024.0), (160, 60.0, 6144.0), (320, 900.0, 6144.0)];

/// The repository root: the benchmark is its scene file.
fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn kernel(scheme: Scheme, mass: MassVariant, norms: &BTreeSet<Norm>) -> (f64, BarRun) {
    let problem = dirichlet(root(), 3.0).expect("the Dirichlet scene");
    let config = RunConfig {
        nx: 640,
        ratio: 10.0,
        scheme,
        mass,
        observables: Observables {
            norms: norms.clone(),
            ..Observables::default()
        },
        settings: Default::default(),
    };
    let mut samples = Vec::new();
    let mut last = None;
    for _ in 0..9 {
        let clock = Instant::now();
        let r = run(&problem, &config, &mut []).expect("benchmark run");
        samples.push(clock.elapsed().as_secs_f64() * 1e9 / r.observed.dof_steps as f64);
        last = Some(r);
    }
    (median(samples), last.expect("nine runs"))
}

/// One 3D run of `scenes/bar3d.json` (Crank–Nicolson, `M^mod`, T = 2, the default step
/// solver) on `nx` elements along the axis, by the binary under `/usr/bin/time -v`: wall
/// seconds and peak resident megabytes.
fn box_3d_run(nx: usize) -> Option<(f64, f64)> {
    let started = Instant::now();
    let out = Command::new("/usr/bin/time")
        .arg("-v")
        .arg(env!("CARGO_BIN_EXE_signorini"))
        .args(["run", "scenes/bar3d.json", "--scheme", "crank-nicolson"])
        .args(["--mass", "redistributed", "--nx", &nx.to_string()])
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .env("CI", "true")
        .output()
        .ok()?;
    let wall = started.elapsed().as_secs_f64();
    out.status.success().then_some(())?;
    Some((
        wall,
        max_resident_mb(&String::from_utf8_lossy(&out.stderr))?,
    ))
}

/// The peak resident size in `/usr/bin/time -v`'s report, in MB.
fn max_resident_mb(report: &str) -> Option<f64> {
    let kb: f64 = report
        .lines()
        .find(|l| l.contains("Maximum resident set size"))?
        .rsplit(':')
        .next()?
        .trim()
        .parse()
        .ok()?;
    Some(kb / 1024.0)
}

fn peak_memory_mb() -> Option<f64> {
    let out = Command::new("/usr/bin/time")
        .arg("-v")
        .arg(env!("CARGO_BIN_EXE_signorini"))
        .args(["study", "scenes/bar1d-dirichlet.json"])
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .env("CI", "true")
        .output()
        .ok()?;
    max_resident_mb(&String::from_utf8_lossy(&out.stderr))
}

fn verdict(ok: bool) -> &'static str {
    if ok {
        "ok"
    } else {
        "MISSED"
    }
}

/// One scheme's step kernel ([`kernel`]): nanoseconds per dof-step.
#[derive(Debug, Serialize)]
struct KernelFigure {
    scheme: String,
    mass: String,
    /// With the seven observables.
    ns_per_dof_step: f64,
    /// Of which the stepping (the energy-balance check included), the contact solves and the
    /// observers.
    stepping: f64,
    contact: f64,
    observe: f64,
    /// With no observable.
    ns_per_dof_step_no_observable: f64,
    target: f64,
    met: bool,
}

/// One other measured figure and its target.
#[derive(Debug, Serialize)]
struct Figure {
    what: String,
    value: f64,
    unit: &'static str,
    target: f64,
    met: bool,
    /// Its second measure and target, where it has one (a 3D run's peak memory in MB).
    peak_mb: Option<f64>,
    peak_mb_target: Option<f64>,
}

/// What `make bench` measured: `reports/bench.json` (format `signorini-bench/1`), rendered as
/// `reports/bench.md`.
#[derive(Debug, Serialize)]
struct BenchReport {
    format: &'static str,
    kernels: Vec<KernelFigure>,
    figures: Vec<Figure>,
    /// Figures that could not be measured (a failed run, `/usr/bin/time` missing).
    unmeasured: Vec<String>,
    all_met: bool,
}

impl BenchReport {
    fn markdown(&self) -> String {
        let mut md = String::from(
            "# Speed targets (`make bench`)\n\nMeasured by `make bench` on the machine that ran it \
             (this report is rewritten at each run; a 2-core VM varies ±25 % from run to run).\n\n\
             ## Step kernels\n\nNX = 640, Δx/Δt = 10, T = 3 (19 200 steps), median of 9 runs, in \
             ns per dof-step.\n\n| scheme | mass | 7 observables | of which stepping / contact / observe | no observable | target |\n\
             |---|---|---|---|---|---|\n",
        );
        for k in &self.kernels {
            md += &format!(
                "| {} | {} | {:.1} | {:.1} / {:.1} / {:.1} | {:.1} | ≤ {} {} |\n",
                k.scheme,
                k.mass,
                k.ns_per_dof_step,
                k.stepping,
                k.contact,
                k.observe,
                k.ns_per_dof_step_no_observable,
                k.target,
                verdict(k.met)
            );
        }
        md += "\n## Studies and runs\n\n| what | measured | target | |\n|---|---|---|---|\n";
        for f in &self.figures {
            let (measured, target) = match (f.peak_mb, f.peak_mb_target) {
                (Some(mb), Some(t)) => (
                    format!("{:.1} {}, {mb:.0} MB peak", f.value, f.unit),
                    format!("≤ {} {}, ≤ {t} MB", f.target, f.unit),
                ),
                _ => (
                    format!("{:.1} {}", f.value, f.unit),
                    format!("≤ {} {}", f.target, f.unit),
                ),
            };
            md += &format!(
                "| {} | {measured} | {target} | {} |\n",
                f.what,
                verdict(f.met)
            );
        }
        for what in &self.unmeasured {
            md += &format!("| {what} | not measured | | MISSED |\n");
        }
        md += &format!(
            "\n{}\n",
            if self.all_met {
                "Every target is met."
            } else {
                "At least one target is missed (`make bench` exits non-zero)."
            }
        );
        md
    }
}

fn main() -> ExitCode {
    let all: BTreeSet<Norm> = Norm::ALL.into_iter().collect();
    let none = BTreeSet::new();
    let mut kernels = Vec::new();
    for scheme in Scheme::paper_schemes() {
        for mass in MassVariant::PAPER {
            let (with, r) = kernel(scheme, mass, &all);
            let (without, _) = kernel(scheme, mass, &none);
            let per = |s: f64| s * 1e9 / r.observed.dof_steps as f64;
            let figure = KernelFigure {
                scheme: scheme.to_string(),
                mass: mass.to_string(),
                ns_per_dof_step: with,
                stepping: per(r.timings.stepping),
                contact: per(r.timings.contact),
                observe: per(r.timings.observe),
                ns_per_dof_step_no_observable: without,
                target: NS_PER_DOF_STEP_TARGET,
                met: with <= NS_PER_DOF_STEP_TARGET,
            };
            eprintln!(
                "kernel {} {}: {:.1} ns/dof-step",
                figure.scheme, figure.mass, with
            );
            kernels.push(figure);
        }
    }
    let mut figures = Vec::new();
    let mut unmeasured = Vec::new();
    let mut timed = |what: String, value: f64, unit: &'static str, target: f64| {
        eprintln!("{what}: {value:.2} {unit}");
        figures.push(Figure {
            what,
            value,
            unit,
            target,
            met: value <= target,
            peak_mb: None,
            peak_mb_target: None,
        });
    };
    let walls: Vec<f64> = (0..3)
        .map(|_| {
            let clock = Instant::now();
            tables_study(root()).expect("tables study");
            clock.elapsed().as_secs_f64()
        })
        .collect();
    timed(
        "Tables 1–2 study (14 cases × 7 levels, all norms), wall, median of 3".into(),
        median(walls),
        "s",
        STUDY_SECONDS_TARGET,
    );
    let clock = Instant::now();
    tables_sensitivity(root(), &Case::paper_matrix()).expect("sensitivity study");
    timed(
        "1D sensitivity study (14 cases × 7 levels × 16 members), wall".into(),
        clock.elapsed().as_secs_f64(),
        "s",
        SENSITIVITY_SECONDS_TARGET,
    );
    match peak_memory_mb() {
        Some(mb) => timed(
            "peak memory of `signorini study scenes/bar1d-dirichlet.json`".into(),
            mb,
            "MB",
            PEAK_MEMORY_MB_TARGET,
        ),
        None => unmeasured.push("peak memory of the 1D study (/usr/bin/time -v)".to_string()),
    }
    let fine = std::env::args().any(|a| a == "--fine");
    for &(nx, seconds, megabytes) in BOX_3D_TARGETS.iter().filter(|t| fine || t.0 < 320) {
        let what =
            format!("3D level {nx} run (CN, redistributed, T = 2, the default step solver), wall");
        match box_3d_run(nx) {
            Some((wall, mb)) => {
                eprintln!("{what}: {wall:.1} s, {mb:.0} MB");
                figures.push(Figure {
                    what,
                    value: wall,
                    unit: "s",
                    target: seconds,
                    met: wall <= seconds && mb <= megabytes,
                    peak_mb: Some(mb),
                    peak_mb_target: Some(megabytes),
                });
            }
            None => unmeasured.push(what),
        }
    }
    let all_met =
        unmeasured.is_empty() && kernels.iter().all(|k| k.met) && figures.iter().all(|f| f.met);
    let report = BenchReport {
        format: "signorini-bench/1",
        kernels,
        figures,
        unmeasured,
        all_met,
    };
    let markdown = report.markdown();
    print!("{markdown}");
    if let Err(e) = write_report(&report, &markdown) {
        eprintln!("error: {e}");
        return ExitCode::FAILURE;
    }
    println!("wrote reports/bench.md and reports/bench.json");
    if all_met {
        ExitCode::SUCCESS
    } else {
        ExitCode::FAILURE
    }
}

/// Writes `reports/bench.md` and `reports/bench.json` (beside the other reports, recorded in
/// the directory's manifest).
fn write_report(report: &BenchReport, markdown: &str) -> Result<(), Box<dyn std::error::Error>> {
    let staged = StagedDir::begin("reports", &root().join("reports"), Replace::Files)?;
    write_atomic(&staged.path().join("bench.md"), markdown.as_bytes())?;
    write_json(&staged.path().join("bench.json"), report)?;
    staged.commit()?;
    Ok(())
}
