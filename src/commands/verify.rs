//! `signorini verify`: another code's runs of a scene checked with the harness's norms and
//! rates ([`crate::studies::verify_run`]).

use std::path::PathBuf;

use clap::Args;

use super::failure::Failure;
use super::limits::LimitArgs;
use crate::studies::verify_run::{verify, VerifyRequest};

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

/// Verifies another code's runs of a scene: prints Tables 1–2 of their series, then gates or
/// writes the golden file and writes the outputs asked for.
pub fn verify_runs(args: VerifyArgs) -> Result<(), Failure> {
    let request = VerifyRequest {
        scene: args.scene,
        runs: args.runs,
        golden: args.golden,
        write_golden: args.write_golden,
        out: args.out,
        limits: args.limits.limits(),
    };
    Ok(verify(request, &mut |said| out!("{said}"))?)
}
