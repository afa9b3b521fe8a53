//! `signorini verify`: another code's runs of a scene checked with the harness's norms and
//! rates (its back-end: [`verify_run`]); `signorini league`: the verifications side by side.

mod league_run;
mod verify_run;

use std::path::PathBuf;

use clap::Args;

use super::failure::Failure;
use super::limits::LimitArgs;
use super::options::{parsed, REPORTS};
use crate::harness::external::box_run::SeriesOptions;
use crate::harness::external::format::Code;
use crate::harness::problem::{MassVariant, Scheme};
use league_run::write_league;
use verify_run::{verify, VerifyRequest};

/// The arguments of `signorini verify`.
#[derive(Debug, Args)]
pub struct VerifyArgs {
    /// The scene file the runs solve: a bar1d scene with an exact solution, or a box scene
    /// (bar2d, bar3d), verified against its fine-mesh reference.
    pub scene: PathBuf,
    /// Run files of another code (see docs/src/external-runs.md): `.json` or `.csv` for a bar,
    /// `.pvd` (ParaView collections), `.xdmf` (XDMF with HDF5) or `.json` (the box form) for a
    /// box; files with one label
    /// form one refinement series.
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
    /// A box scene's `.pvd` files: what they are and how their arrays are named.
    #[command(flatten)]
    pub pvd: SeriesArgs,
    /// Box scenes: where the fine-mesh reference is looked up and kept, as `study --cache`
    /// (default: the user's cache, shared by every command: $SIGNORINI_CACHE, else
    /// ~/.cache/signorini/references).
    #[arg(long)]
    pub cache: Option<PathBuf>,
}

/// What a `.pvd` does not say: which code wrote it, the series it belongs to, its scheme and
/// mass, and the names of its arrays.
#[derive(Debug, Args)]
pub struct SeriesArgs {
    /// The code that wrote the `.pvd` files (required with them).
    #[arg(long, requires = "code_version")]
    pub code: Option<String>,
    /// Its version.
    #[arg(long, requires = "code")]
    pub code_version: Option<String>,
    /// The series the `.pvd` files form (default: each collection's file stem).
    #[arg(long)]
    pub label: Option<String>,
    /// The scheme the code ran (a preset name, see `signorini list`): the note's findings are
    /// judged on series that declare it and their mass.
    #[arg(long, value_parser = parsed::<Scheme>)]
    pub scheme: Option<Scheme>,
    /// The mass matrix the code used: the harness computes the energy from the fields with it
    /// (standard, redistributed, lumped, …; without it the energy is not computed).
    #[arg(long, value_parser = parsed::<MassVariant>)]
    pub mass: Option<MassVariant>,
    /// How the code enforces contact, in its words (shown in verify.md and the league table).
    #[arg(long)]
    pub contact: Option<String>,
    /// The displacement's point array (default: the only vector array, else `displacement`).
    #[arg(long)]
    pub displacement: Option<String>,
    /// The velocity's point array (the energy needs it).
    #[arg(long)]
    pub velocity: Option<String>,
    /// The contact multipliers' point array (one component, λ ≤ 0 on the contact nodes; the
    /// force norm needs it).
    #[arg(long)]
    pub multiplier: Option<String>,
    /// Measure the `.pvd`/`.xdmf` fields on their own mesh (its cells located in the reference's
    /// quadrature, docs/src/external-runs.md "A code's own mesh") even when they are the scene's
    /// Q1 elements; a series with triangles or tetrahedra is always measured so.
    #[arg(long)]
    pub own_mesh: bool,
}

impl SeriesArgs {
    /// The options of the box reader.
    fn options(self) -> SeriesOptions {
        SeriesOptions {
            code: self
                .code
                .zip(self.code_version)
                .map(|(name, version)| Code { name, version }),
            label: self.label,
            scheme: self.scheme,
            mass: self.mass,
            contact: self.contact,
            displacement: self.displacement,
            velocity: self.velocity,
            multiplier: self.multiplier,
            own_mesh: self.own_mesh,
        }
    }
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
        box_options: args.pvd.options(),
        references: args.cache,
    };
    Ok(verify(request, &mut |said| out!("{said}"))?)
}

/// The arguments of `signorini league`.
#[derive(Debug, Args)]
pub struct LeagueArgs {
    /// The directory of the entries: each `<entry>/verify.json` (`signorini verify --out
    /// DIR/<entry>`) is one entry of the table.
    #[arg(default_value = "reports/league")]
    pub entries: PathBuf,
    /// Output directory: league.md and league.json.
    #[arg(long, default_value = REPORTS)]
    pub out: PathBuf,
}

/// Writes the league table of every verification under the entries' directory.
pub fn league(args: LeagueArgs) -> Result<(), Failure> {
    let mut say = |said: &str| out!("{said}");
    Ok(write_league(&args.entries, &args.out, &mut say)?)
}
