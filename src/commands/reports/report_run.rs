//! The commands behind the make targets that write `reports/` and `golden/`, below the command
//! line: `report` (the gravity benchmark, Tables 1–2 and the extended table), `experiment`,
//! `stability`, `golden` and `figures`. Each is held to its limits before it starts, hands its
//! job lists to the executor it is given, and returns what it wrote, for the user.

use std::path::Path;

use crate::commands::command_error::CommandError;
use crate::commands::sharding::outputs::{share_of_work, Destination, Received};
use crate::harness::files::output_dir::{Replace, StagedDir};
use crate::harness::study::budget::{self, Estimate, Limits};
use crate::harness::study::executor::{computed_here, Executor};
use crate::harness::study::shard::Invocation;
use crate::harness::study::Case;
use crate::studies::error::Error;
use crate::studies::estimate;
use crate::studies::experiment::{defaults_experiment, write_defaults_experiment};
use crate::studies::extended::{extended_studies_in, write_extended_report};
use crate::studies::golden::write_golden;
use crate::studies::gravity::{gravity_benchmark, write_gravity_report};
use crate::studies::render::render_reports;
use crate::studies::report::{tables_report, write_report};
use crate::studies::reports_index::REPORTS_INDEX;
use crate::studies::stability::{hard_cases, run_suite_on, write_stability_files, Verdict};

/// `estimate` checked against `limits`.
fn within(estimate: Estimate, limits: &Limits) -> Result<(), CommandError> {
    estimate.check(limits).map_err(|e| Error::from(e).into())
}

/// `signorini report`: the gravity benchmark, Tables 1–2 beside the paper and the extended
/// table into `out`, their job lists handed to `executor` one after the other.
pub fn report(
    out: &Path,
    limits: &Limits,
    executor: &Executor,
    invocation: &Invocation,
) -> Result<String, CommandError> {
    let root = Path::new(".");
    within(share_of_work(estimate::report(root)?, executor), limits)?;
    let destination = Destination::begin(executor, out)?;
    let executed = executor.execute_lists(|batch| {
        let gravity = gravity_benchmark(root, batch)?;
        let tables = tables_report(root, batch)?;
        let extended = extended_studies_in(root, batch)?;
        Ok::<_, Error>(gravity.zip(tables).zip(extended))
    })?;
    let (((gravity, tables), extended), staged) = match destination.receive(executed, invocation)? {
        Received::Complete(value) => value,
        Received::ShardWritten(line) => return Ok(line),
    };
    write_gravity_report(&gravity, staged.path())?;
    write_report(&tables, staged.path())?;
    write_extended_report(&extended, staged.path())?;
    staged.commit()?;
    let o = out.display();
    Ok(format!(
        "wrote {o}/gravity.md and {o}/gravity/ ({} cases)\n\
         wrote {o}/tables.md and {o}/rates.json ({} cases, study {:.1} s wall)\n\
         wrote {o}/extended.md",
        gravity.study.cases.len(),
        tables.study.cases.len(),
        tables.study.wall_seconds
    ))
}

/// `signorini experiment`: how the Tables 1–2 rates move with the horizon and the level range,
/// into `out`.
pub fn experiment(
    out: &Path,
    limits: &Limits,
    executor: &Executor,
    invocation: &Invocation,
) -> Result<String, CommandError> {
    let root = Path::new(".");
    within(share_of_work(estimate::experiment(root)?, executor), limits)?;
    let destination = Destination::begin(executor, out)?;
    let executed = executor.execute_lists(|batch| defaults_experiment(root, batch))?;
    let (experiment, staged) = match destination.receive(executed, invocation)? {
        Received::Complete(value) => value,
        Received::ShardWritten(line) => return Ok(line),
    };
    let md = write_defaults_experiment(&experiment, staged.path())?;
    staged.commit()?;
    let summary: Vec<&str> = md.lines().skip(4).take(7).collect();
    Ok(format!(
        "{}\nwrote {}/defaults-experiment.md",
        summary.join("\n"),
        out.display()
    ))
}

/// `signorini stability`: every scheme × mass of the tables ([`Case::tables_matrix`]: the
/// paper's and the rivals') on the hard cases (only CI's subset with
/// `ci_subset`), with a verdict each, into `out`.
pub fn stability(
    out: &Path,
    ci_subset: bool,
    limits: &Limits,
    executor: &Executor,
    invocation: &Invocation,
) -> Result<String, CommandError> {
    let hard = hard_cases(Path::new("."), ci_subset)?;
    let suite = estimate::stability(&hard);
    // A shard runs its share of the jobs, at most the whole suite's memory; a merge runs none.
    let cases = Case::tables_matrix();
    let jobs = hard.len() * cases.len();
    let share = computed_here(&vec![1; jobs], executor).len() as f64 / jobs.max(1) as f64;
    let here = Estimate {
        dof_steps: suite.dof_steps * share,
        ..suite
    };
    within(here, limits)?;
    let destination = Destination::begin(executor, out)?;
    let executed = run_suite_on(executor, &hard, &cases)?;
    let (records, staged) = match destination.receive(executed, invocation)? {
        Received::Complete(value) => value,
        Received::ShardWritten(line) => return Ok(line),
    };
    write_stability_files(staged.path(), &hard, &records)?;
    staged.commit()?;
    let flagged = records
        .iter()
        .filter(|r| {
            !matches!(
                r.shared_verdict(),
                Some(Verdict::Stable | Verdict::Dissipative)
            )
        })
        .count();
    let o = out.display();
    Ok(format!(
        "wrote {o}/stability.md and {o}/stability.json ({} runs, {flagged} flagged)",
        records.len()
    ))
}

/// `signorini golden`: the golden rates of the gated studies under `root`, regenerated.
pub fn golden(root: &Path, limits: &Limits) -> Result<String, CommandError> {
    within(estimate::golden(root)?.writing(4.0), limits)?;
    let lines: Vec<String> = write_golden(root)?
        .iter()
        .map(|(name, golden)| format!("wrote {name} ({} cases)", golden.cases.len()))
        .collect();
    Ok(lines.join("\n"))
}

/// `signorini figures`, the render step: the pages that gather several sections' data
/// (`schemes.md`, `work-precision.md`), the figures and the README.md index built from the data
/// under `reports` ([`render_reports`]); the data read is held to `limits`' memory, the files
/// written to its number of files before any is moved into place.
pub fn figures(reports: &Path, limits: &Limits) -> Result<String, CommandError> {
    within(
        budget::reading(bytes_under(&reports.join("data")), 4.0),
        limits,
    )?;
    let staged = StagedDir::begin("--out", reports, Replace::Files)?;
    let rendered = render_reports(reports, staged.path())?;
    let files = rendered.figures.len() + rendered.pages.len() + 1;
    within(Estimate::default().writing(files as f64), limits)?;
    staged.commit()?;
    let r = reports.display();
    let mut said = format!(
        "wrote {} figures into {r}/figures and {r}/{REPORTS_INDEX}",
        rendered.figures.len()
    );
    for page in &rendered.pages {
        said.push_str(&format!("\nwrote {r}/{page}"));
    }
    for m in rendered.missing {
        said.push_str(&format!("\nskipped (input missing): {m}"));
    }
    Ok(said)
}

/// The bytes of the files under `dir`, recursively (none when it cannot be read).
fn bytes_under(dir: &Path) -> f64 {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return 0.0;
    };
    entries
        .flatten()
        .map(|e| match e.file_type() {
            Ok(t) if t.is_dir() => bytes_under(&e.path()),
            Ok(t) if t.is_file() => e.metadata().map_or(0.0, |m| m.len() as f64),
            _ => 0.0,
        })
        .sum()
}
