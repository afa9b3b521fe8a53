//! `signorini verify`: another code's runs of a scene, read from JSON or CSV run files,
//! measured with the harness's norms, fitted into rates per label and printed as Tables 1–2;
//! optionally gated against a golden file, written as one, and saved as JSON and markdown.

use std::path::PathBuf;

use clap::Args;

use super::failure::{write_output, Failure};
use super::limits::LimitArgs;
use crate::harness::external::format::MAX_VALUES;
use crate::harness::external::report::render;
use crate::harness::external::{compare, verify, ExternalError, VerifyGolden};
use crate::harness::files::artifacts::{read_json, writable, write_json};
use crate::harness::files::input::GOLDEN_FILE;
use crate::harness::files::output_dir::{Replace, StagedDir};
use crate::harness::study::budget::{self, Estimate};
use crate::harness::study::golden::{check_values, render_drifts};
use crate::harness::study::scene::Scene;

/// `verify.json` under `--out`: the [`crate::harness::external::Verification`].
pub const VERIFY_JSON: &str = "verify.json";

/// `verify.md` under `--out`: the tables.
pub const VERIFY_MD: &str = "verify.md";

/// The arguments of `signorini verify`.
#[derive(Debug, Args)]
pub struct VerifyArgs {
    /// The scene file the runs solve (a bar1d scene with an exact solution).
    pub scene: PathBuf,
    /// Run files of another code (`.json` or `.csv`, see docs/src/external-runs.md); files
    /// with one label form one refinement series.
    #[arg(required = true)]
    pub runs: Vec<PathBuf>,
    /// Gate the rates and errors against this golden file (exit code 1 on a drift).
    #[arg(long, conflicts_with = "write_golden")]
    pub golden: Option<PathBuf>,
    /// Write the rates and errors as a golden file for later `--golden` checks.
    #[arg(long)]
    pub write_golden: Option<PathBuf>,
    /// Write verify.json (norms and rates) and verify.md (the tables) into this directory.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// The resource limits (the run files are all held in memory while they are verified).
    #[command(flatten)]
    pub limits: LimitArgs,
}

/// What reading and verifying the run files `runs` costs: each is held in memory at no more
/// than its reader's bound (four bytes per byte of text, the arrays as `f64`, and never past
/// three times [`MAX_VALUES`] numbers), one exact-solution evaluation per number.
fn reading_cost(runs: &[PathBuf]) -> Estimate {
    let cap = 3.0 * 8.0 * MAX_VALUES as f64;
    let held: f64 = budget::file_sizes(runs)
        .iter()
        .map(|b| (4.0 * b).min(cap))
        .sum();
    budget::reading(held, 1.0)
}

impl From<ExternalError> for Failure {
    fn from(e: ExternalError) -> Self {
        match e {
            ExternalError::Harness(e) => e.into(),
            e => Self::usage(e),
        }
    }
}

/// Verifies another code's runs of a scene: prints Tables 1–2 of their series, then gates or
/// writes the golden file and writes the outputs asked for.
pub fn verify_runs(args: VerifyArgs) -> Result<(), Failure> {
    let VerifyArgs {
        scene,
        runs,
        golden,
        write_golden,
        out,
        limits,
    } = args;
    let scene = Scene::load(&scene)?;
    let files = [(out.is_some(), 2.0), (write_golden.is_some(), 1.0)]
        .iter()
        .filter(|(given, _)| *given)
        .map(|(_, n)| n)
        .sum();
    limits.check(reading_cost(&runs).writing(files))?;
    if let Some(path) = &write_golden {
        writable(path)?;
    }
    let staged = out
        .as_deref()
        .map(|dir| StagedDir::begin("--out", dir, Replace::Whole))
        .transpose()?;
    let verification = verify(&scene, &runs)?;
    let markdown = render(&verification);
    out!("{}", markdown.trim_end());
    if let (Some(dir), Some(staged)) = (&out, staged) {
        write_json(&staged.path().join(VERIFY_JSON), &verification).map_err(Failure::from)?;
        write_output(&staged.path().join(VERIFY_MD), markdown.as_bytes())?;
        staged.commit()?;
        out!(
            "wrote {} and {}",
            dir.join(VERIFY_JSON).display(),
            dir.join(VERIFY_MD).display()
        );
    }
    if let Some(path) = write_golden {
        let golden = VerifyGolden::from_verification(&verification)?;
        write_json(&path, &golden).map_err(Failure::from)?;
        out!("wrote the golden file {}", path.display());
    }
    if let Some(path) = golden {
        let golden: VerifyGolden = read_json(&path, GOLDEN_FILE).map_err(Failure::usage)?;
        let series = golden.series.iter().map(|s| (s.case.as_str(), &s.norms));
        check_values(&path, &golden.tolerances, series)?;
        let drifts = compare(&golden, &verification);
        if !drifts.is_empty() {
            return Err(Failure::runtime(format!(
                "the verified runs drifted from the golden file {}\n{}",
                path.display(),
                render_drifts(&drifts).trim_end()
            )));
        }
        out!(
            "golden gate passed: every rate and error within its tolerance of {}",
            path.display()
        );
    }
    Ok(())
}
