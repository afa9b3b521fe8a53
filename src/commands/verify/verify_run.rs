//! `signorini verify` below the command line: another code's runs of a scene, read from its
//! files and measured by the harness against the reference the scene declares, fitted into rates
//! per label, judged by the report section ([`judged`]) and printed as Tables 1–2; optionally
//! gated against a golden file, written as one, and saved as JSON and markdown.

use std::path::{Path, PathBuf};

use crate::commands::command_error::CommandError;
use crate::commands::options::cache_dir;
use crate::harness::external::box_run::SeriesOptions;
use crate::harness::external::format::MAX_VALUES;
use crate::harness::external::verify::fine_mesh::ReferenceSource;
use crate::harness::external::{
    compare, verify as measure, ExternalError, Verification, VerifyGolden, VerifySources,
};
use crate::harness::files::artifacts::{read_json, writable, write_atomic, write_json};
use crate::harness::files::input::GOLDEN_FILE;
use crate::harness::files::output_dir::{Replace, StagedDir};
use crate::harness::reference::fine_mesh::cache::ReferenceCache;
use crate::harness::study::budget::{self, Estimate, Limits};
use crate::harness::study::golden::{check_values, render_drifts};
use crate::harness::study::scene::Scene;
use crate::studies::elastic_study::external::{judged, render};
use crate::studies::error::Error;

/// `verify.json` under `--out`: the judged [`Verification`].
pub const VERIFY_JSON: &str = "verify.json";

/// `verify.md` under `--out`: the tables.
pub const VERIFY_MD: &str = "verify.md";

/// A verification as the user asked for it.
pub struct VerifyRequest {
    /// The scene file the runs solve.
    pub scene: PathBuf,
    /// The run files.
    pub runs: Vec<PathBuf>,
    /// The golden file to gate against.
    pub golden: Option<PathBuf>,
    /// The golden file to write.
    pub write_golden: Option<PathBuf>,
    /// Where verify.json and verify.md go.
    pub out: Option<PathBuf>,
    /// The limits it is held to.
    pub limits: Limits,
    /// What a box scene's `.pvd` files are (their code, label, scheme, mass and arrays).
    pub box_options: SeriesOptions,
    /// Where a box scene's reference is read from and saved to (default: the user's cache,
    /// `cache_dir`).
    pub references: Option<PathBuf>,
}

impl From<ExternalError> for CommandError {
    fn from(e: ExternalError) -> Self {
        match e {
            ExternalError::Harness(e) => e.into(),
            e => Self::Refused(e.to_string()),
        }
    }
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

/// Verifies the runs of `request`, telling `say` the tables and each file written, then gates
/// them against the golden file (a drift is a failure).
pub fn verify(request: VerifyRequest, say: &mut dyn FnMut(&str)) -> Result<(), CommandError> {
    let VerifyRequest {
        scene,
        runs,
        golden,
        write_golden,
        out,
        limits,
        box_options,
        references,
    } = request;
    let inputs: Vec<&Path> = (runs.iter().chain([&scene]).chain(&golden))
        .map(PathBuf::as_path)
        .collect();
    let scene = Scene::load(&scene)?;
    let files = [(out.is_some(), 2.0), (write_golden.is_some(), 1.0)]
        .iter()
        .filter(|(given, _)| *given)
        .map(|(_, n)| n)
        .sum();
    reading_cost(&runs)
        .writing(files)
        .check(&limits)
        .map_err(Error::from)?;
    if let Some(path) = &write_golden {
        writable(path)?;
    }
    let staged = out
        .as_deref()
        .map(|dir| StagedDir::begin("--out", dir, Replace::Whole)?.reading(&inputs))
        .transpose()?;
    let cache = ReferenceCache::ReadWrite(cache_dir(references)?);
    let sources = VerifySources {
        pvd: &box_options,
        reference: ReferenceSource {
            cache: &cache,
            limits: &limits,
        },
    };
    let verification = judged(measure(&scene, &runs, &sources, &mut |note| say(&note))?);
    let markdown = render(&verification);
    say(markdown.trim_end());
    if let (Some(dir), Some(staged)) = (&out, staged) {
        write_json(&staged.path().join(VERIFY_JSON), &verification)?;
        write_atomic(&staged.path().join(VERIFY_MD), markdown.as_bytes())?;
        staged.commit()?;
        let (json, md) = (dir.join(VERIFY_JSON), dir.join(VERIFY_MD));
        say(&format!("wrote {} and {}", json.display(), md.display()));
    }
    if let Some(path) = write_golden {
        write_json(&path, &VerifyGolden::from_verification(&verification)?)?;
        say(&format!("wrote the golden file {}", path.display()));
    }
    if let Some(path) = golden {
        gate(&path, &verification)?;
        say(&format!(
            "golden gate passed: every rate and error within its tolerance of {}",
            path.display()
        ));
    }
    Ok(())
}

/// The verification gated against the golden file `path`: a drift is a failure.
fn gate<J>(path: &Path, verification: &Verification<J>) -> Result<(), CommandError> {
    let golden: VerifyGolden =
        read_json(path, GOLDEN_FILE).map_err(|e| CommandError::Refused(e.to_string()))?;
    let series = golden.series.iter().map(|s| (s.case.as_str(), &s.norms));
    check_values(path, &golden.tolerances, series)?;
    let drifts = compare(&golden, verification);
    match drifts.is_empty() {
        true => Ok(()),
        false => Err(CommandError::Failed(format!(
            "the verified runs drifted from the golden file {}\n{}",
            path.display(),
            render_drifts(&drifts).trim_end()
        ))),
    }
}
