//! `signorini getfem`: GetFEM's demo runs solved again with its conventions
//! (`make verify-getfem`).

use std::path::{Path, PathBuf};

use clap::Args;

use super::failure::Failure;
use super::limits::LimitArgs;
use super::options::REPORTS;
use crate::harness::files::output_dir::{Replace, StagedDir};
use crate::studies::getfem::{
    export_runs, write_getfem_report, Expectation, GETFEM_REPORT, GETFEM_RUNS,
};

/// The arguments of `signorini getfem`.
#[derive(Debug, Args)]
pub struct GetfemArgs {
    /// The directory of the demo's runs (`getfem_*.json.gz`).
    #[arg(long, default_value = GETFEM_RUNS)]
    pub runs: PathBuf,
    /// Output directory.
    #[arg(long, default_value = REPORTS)]
    pub out: PathBuf,
    /// Also write every finite run as a contact-trace file of the external-run format into
    /// this directory, for `signorini verify`.
    #[arg(long)]
    pub export: Option<PathBuf>,
    /// The resource limits (each run's work and memory, checked as it is read).
    #[command(flatten)]
    pub limits: LimitArgs,
}

/// Reproduces every run and writes getfem.md.
pub fn getfem(args: GetfemArgs) -> Result<(), Failure> {
    let GetfemArgs {
        runs,
        out,
        export,
        limits,
    } = args;
    let limits = limits.limits();
    let staged_out = StagedDir::begin("--out", &out, Replace::Files)?;
    if let Some(dir) = export {
        let staged = StagedDir::begin("--export", &dir, Replace::Whole)?;
        let written = export_runs(&runs, staged.path(), &limits)?;
        staged.commit()?;
        out!(
            "wrote {} external-run files to {}",
            written.len(),
            dir.display()
        );
    }
    let all = write_getfem_report(Path::new("."), &runs, staged_out.path(), &limits)?;
    staged_out.commit()?;
    let reproducible = all
        .iter()
        .filter(|r| r.expectation == Expectation::RoundOff)
        .count();
    out!(
        "wrote {}/{GETFEM_REPORT} ({} runs, {reproducible} expected to agree at every step)",
        out.display(),
        all.len()
    );
    Ok(())
}
