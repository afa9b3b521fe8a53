//! `signorini getfem` below the command line: GetFEM's demo runs solved again with its
//! conventions and compared step by step into `getfem.md`, and optionally exported as
//! external-run files for `signorini verify`; GetFEM's own 2D/3D runs written in the box form
//! (`signorini getfem-box`).

use std::path::{Path, PathBuf};

use crate::commands::command_error::CommandError;
use crate::harness::files::artifacts::write_json;
use crate::harness::files::output_dir::{Replace, StagedDir};
use crate::harness::getfem::anchor::convert_anchor;
use crate::harness::study::budget::Limits;
use crate::studies::getfem::{
    export_runs, write_getfem_report, Expectation, GETFEM_JSON, GETFEM_REPORT,
};

/// Reproduces every demo run under `runs` into `out`'s `getfem.md` and `getfem.json` (each
/// run's work and memory held to `limits` as it is read), after exporting them into `export`
/// when given; tells `say` what it wrote and every run outside its class, with its misses.
pub fn getfem(
    runs: &Path,
    out: &Path,
    export: Option<&Path>,
    limits: &Limits,
    say: &mut dyn FnMut(&str),
) -> Result<(), CommandError> {
    let staged_out = StagedDir::begin("--out", out, Replace::Files)?;
    if let Some(dir) = export {
        let staged = StagedDir::begin("--export", dir, Replace::Whole)?.reading(&[runs])?;
        let written = export_runs(runs, staged.path(), limits)?;
        staged.commit()?;
        let n = written.len();
        say(&format!(
            "wrote {n} external-run files to {}",
            dir.display()
        ));
    }
    let all = write_getfem_report(Path::new("."), runs, staged_out.path(), limits)?;
    staged_out.commit()?;
    let reproducible = all
        .iter()
        .filter(|r| r.reproduction.expectation == Expectation::RoundOff)
        .count();
    say(&format!(
        "wrote {0}/{GETFEM_REPORT} and {0}/{GETFEM_JSON} ({1} runs, {reproducible} expected to \
         agree at every step)",
        out.display(),
        all.len()
    ));
    let outside: Vec<_> = all.iter().filter(|r| !r.check.within()).collect();
    if outside.is_empty() {
        say(&format!(
            "every run is within its class ({} runs)",
            all.len()
        ));
    } else {
        say(&format!(
            "{} of {} runs are outside their class:",
            outside.len(),
            all.len()
        ));
        for r in outside {
            let misses: Vec<String> = r.check.misses().map(|c| c.text()).collect();
            say(&format!(
                "  {} ({}): {}",
                r.name,
                r.check.class,
                misses.join("; ")
            ));
        }
    }
    Ok(())
}

/// Writes GetFEM's 2D/3D runs `runs` ([`convert_anchor`]) into `out` as box-form run files
/// (the directory written whole or not at all); tells `say` each file written.
pub fn getfem_box(
    runs: &[PathBuf],
    out: &Path,
    say: &mut dyn FnMut(&str),
) -> Result<(), CommandError> {
    let converted = runs
        .iter()
        .map(|path| convert_anchor(path))
        .collect::<Result<Vec<_>, _>>()?;
    let staged = StagedDir::begin("--out", out, Replace::Whole)?.reading(runs)?;
    for c in &converted {
        write_json(&staged.path().join(&c.file_name), &c.run)?;
    }
    staged.commit()?;
    for c in &converted {
        say(&out.join(&c.file_name).display().to_string());
    }
    Ok(())
}
