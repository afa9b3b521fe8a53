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
//! Each figure is the median of several repetitions (9 for the kernels). The process exits with status 1 when a
//! target is missed, so `make bench` checks them.

use std::collections::BTreeSet;
use std::path::Path;
use std::process::{Command, ExitCode};
use std::time::Instant;

use signorini::fem::MassVariant;
use signorini::norms::Norm;
use signorini::run::{run, Observables, RunConfig, RunResult};
use signorini::schemes::Scheme;
use signorini::studies::benchmark::dirichlet;
use signorini::studies::tables::{tables_sensitivity, tables_study};
use signorini::study::Case;

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

fn kernel(scheme: Scheme, mass: MassVariant, norms: &BTreeSet<Norm>) -> (f64, RunResult) {
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
    };
    let mut samples = Vec::new();
    let mut last = None;
    for _ in 0..9 {
        let clock = Instant::now();
        let r = run(&problem, &config).expect("benchmark run");
        samples.push(clock.elapsed().as_secs_f64() * 1e9 / r.dof_steps as f64);
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

fn main() -> ExitCode {
    let all: BTreeSet<Norm> = Norm::ALL.into_iter().collect();
    let none = BTreeSet::new();
    let mut all_ok = true;
    println!("Step kernels, NX = 640, Δx/Δt = 10, T = 3 (19 200 steps), median of 9 runs (this 2-core VM varies ±25 % from run to run)");
    println!(
        "| scheme | mass | ns/dof-step, 7 observables | of which stepping / contact / observe | ns/dof-step, no observable | target |"
    );
    println!("|---|---|---|---|---|---|");
    for scheme in Scheme::paper_schemes() {
        for mass in MassVariant::PAPER {
            let (with, r) = kernel(scheme, mass, &all);
            let (without, _) = kernel(scheme, mass, &none);
            let per = |s: f64| s * 1e9 / r.dof_steps as f64;
            let ok = with <= NS_PER_DOF_STEP_TARGET;
            all_ok &= ok;
            println!(
                "| {} | {} | {:.1} | {:.1} / {:.1} / {:.1} | {:.1} | ≤ {} {} |",
                scheme,
                mass,
                with,
                per(r.timings.stepping),
                per(r.timings.contact),
                per(r.timings.observe),
                without,
                NS_PER_DOF_STEP_TARGET,
                verdict(ok)
            );
        }
    }

    let walls: Vec<f64> = (0..3)
        .map(|_| {
            let clock = Instant::now();
            tables_study(root()).expect("tables study");
            clock.elapsed().as_secs_f64()
        })
        .collect();
    let wall = median(walls);
    let ok = wall <= STUDY_SECONDS_TARGET;
    all_ok &= ok;
    println!(
        "\nTables 1–2 study (14 cases × 7 levels, all norms): {wall:.2} s wall, median of 3 (target ≤ {STUDY_SECONDS_TARGET} s) {}",
        verdict(ok)
    );

    let clock = Instant::now();
    tables_sensitivity(root(), &Case::paper_matrix()).expect("sensitivity study");
    let wall = clock.elapsed().as_secs_f64();
    let ok = wall <= SENSITIVITY_SECONDS_TARGET;
    all_ok &= ok;
    println!(
        "1D sensitivity study (14 cases × 7 levels × 16 members): {wall:.1} s wall (target ≤ {SENSITIVITY_SECONDS_TARGET} s) {}",
        verdict(ok)
    );

    let fine = std::env::args().any(|a| a == "--fine");
    for &(nx, seconds, megabytes) in BOX_3D_TARGETS.iter().filter(|t| fine || t.0 < 320) {
        match box_3d_run(nx) {
            Some((wall, mb)) => {
                let ok = wall <= seconds && mb <= megabytes;
                all_ok &= ok;
                println!(
                    "3D level {nx} run (CN, redistributed, T = 2, the default step solver): {wall:.1} s wall, {mb:.0} MB peak (target ≤ {seconds} s, ≤ {megabytes} MB) {}",
                    verdict(ok)
                );
            }
            None => {
                all_ok = false;
                println!("3D level {nx} run: failed, or /usr/bin/time -v unavailable");
            }
        }
    }

    match peak_memory_mb() {
        Some(mb) => {
            let ok = mb <= PEAK_MEMORY_MB_TARGET;
            all_ok &= ok;
            println!(
                "Peak memory of `signorini study scenes/bar1d-dirichlet.json`: {mb:.1} MB (target ≤ {PEAK_MEMORY_MB_TARGET} MB) {}",
                verdict(ok)
            );
        }
        None => {
            all_ok = false;
            println!("Peak memory: /usr/bin/time -v unavailable (install the `time` package)");
        }
    }
    if all_ok {
        ExitCode::SUCCESS
    } else {
        ExitCode::FAILURE
    }
}
