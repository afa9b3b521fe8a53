//! `signorini list`: the schemes, mass variants, contact treatments, norms and scenes
//! ([`catalogue`]).

use std::path::PathBuf;

use clap::Args;

use super::failure::Failure;
use catalogue::catalogue;

mod catalogue;

/// The arguments of `signorini list`.
#[derive(Debug, Args)]
pub struct ListArgs {
    /// Where to look for scene files (a directory read).
    #[arg(long, default_value = "scenes")]
    pub scenes: PathBuf,
}

/// The schemes with their parameters, the mass variants, the norms and the scenes found.
pub fn list(args: ListArgs) -> Result<(), Failure> {
    out!("{}", catalogue(&args.scenes));
    Ok(())
}
