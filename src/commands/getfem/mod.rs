//! `signorini getfem`: GetFEM's demo runs solved again with its conventions
//! (`make verify-getfem`).

use std::path::PathBuf;

use clap::Args;

use super::failure::Failure;
use super::limits::LimitArgs;
use super::options::REPORTS;
use crate::studies::getfem::GETFEM_RUNS;

mod getfem_run;

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
    let (export, limits) = (args.export.as_deref(), args.limits.limits());
    let mut say = |said: &str| out!("{said}");
    Ok(getfem_run::getfem(
        &args.runs, &args.out, export, &limits, &mut say,
    )?)
}

/// The arguments of `signorini getfem-box`.
#[derive(Debug, Args)]
pub struct GetfemBoxArgs {
    /// GetFEM's runs of the 2D and 3D bars (`signorini-getfem2d-anchor/1`, `…3d…/1`, gzipped:
    /// tests/data/getfem2d/ and getfem3d/).
    #[arg(required = true)]
    pub runs: Vec<PathBuf>,
    /// Output directory: one box-form run file per run, for `signorini verify`.
    #[arg(long)]
    pub out: PathBuf,
}

/// Writes each GetFEM 2D/3D run as a run file of the external format's box form.
pub fn getfem_box(args: GetfemBoxArgs) -> Result<(), Failure> {
    let mut say = |said: &str| out!("{said}");
    Ok(getfem_run::getfem_box(&args.runs, &args.out, &mut say)?)
}
