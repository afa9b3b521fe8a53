//! The `signorini` command line: runs, refinement studies, the report and the golden files.
//!
//! Exit codes: 0 success; 2 usage errors (bad arguments, a scene file that is missing,
//! malformed or out of range); 1 failures (a run that fails, an energy balance that
//! `--check-balance` finds violated, an output that cannot be written).

use std::process::ExitCode;

use clap::{Parser, Subcommand};

use signorini::commands::{
    self, ClusterPlanArgs, CommandLine, ExperimentArgs, Failure, FiguresArgs, GetfemArgs,
    GetfemBoxArgs, GoldenArgs, LeagueArgs, ListArgs, MergeArgs, ReferenceArgs, RejudgeArgs,
    ReportArgs, RunArgs, SensitivityArgs, ShardableCommand, StabilityArgs, StudyArgs, VerifyArgs,
};

const AFTER_HELP: &str = "\
Examples:
  signorini list
  signorini run scenes/bar1d-dirichlet.json --scheme crank-nicolson --mass redistributed --nx 80
  signorini run scenes/bar1d-dirichlet.json --scheme 'newmark(beta=0.3,gamma=0.6)' --mass standard --nx 40 --out out/
  signorini run scenes/bar1d-dirichlet.json --scheme backward-euler --mass standard --contact 'penalty(gamma0=10)'
  signorini run scenes/bar1d-dirichlet.json --scheme paoli-schatzman-e0.5 --mass redistributed --check-balance
  signorini study scenes/bar1d-dirichlet.json --scheme crank-nicolson --mass standard,redistributed --norm u_Linf_H,energy_L2
  signorini study scenes/bar1d-free.json --scheme crank-nicolson --mass standard --json
  signorini verify scenes/bar1d-dirichlet.json runs/mycode-nx*.csv --out verified/
  signorini study scenes/bar1d-dirichlet.json --scheme crank-nicolson --shard 2/4 --out shard-2/
  signorini merge shard-*/shard-study-*-of-4.json
  signorini report

Exit codes: 0 success, 2 usage error (arguments or scene file), 1 failure.";

/// Verification and regression harness for dynamic contact: an elastic bar hits a rigid
/// obstacle; schemes of Dabaghi, Petrov, Pousin & Renard are run with the standard or the
/// redistributed mass matrix and compared with exact solutions.
#[derive(Parser)]
#[command(name = "signorini", version, about, after_help = AFTER_HELP)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// One run of a scene: the requested error norms on the terminal; with --out, run.json
    /// plus the histories the scene asks for (contact.csv, multiplier.csv, energy.csv,
    /// points.csv, field-t<T>.csv, strain-t<T>.csv; a box: energy.csv, contact.csv,
    /// field-t<T>.vtu, and with them obstacle.vtu, the obstacle plane, and fields.pvd, their
    /// collection for ParaView), the directory written whole or not at all.
    Run(RunArgs),
    /// A refinement study of a scene: the rate table of the selected cases and norms, as
    /// markdown or JSON. Nothing outside the selection is computed.
    Study(StudyArgs),
    /// The findings of a committed 2D/3D study judged again from its elastic-<d>d.json under
    /// --out, without running anything (`make rejudge`): its report and its findings rewritten.
    Rejudge(RejudgeArgs),
    /// Round-off sensitivity of a bar1d scene's study (`make report`): every case and level run
    /// as an ensemble of members with seeded noise of relative size A on the initial
    /// displacement; writes sensitivity.md and sensitivity.json with each case's class.
    Sensitivity(SensitivityArgs),
    /// The fine-mesh reference of a box scene (`make reference`): reuses the cache when its
    /// parameters match the scene's, says which differ otherwise, and recomputes it.
    Reference(ReferenceArgs),
    /// The cost model of a reference across MPI ranks fitted to references measured here
    /// (`reference --measure`), and its answer for the scene's reference on --level elements
    /// on N nodes of a stated size: cluster-plan.md and cluster-plan.json (`make cluster-plan`).
    ClusterPlan(ClusterPlanArgs),
    /// The 1D part of `make report`: the gravity benchmark (gravity.md, gravity/), Tables 1–2
    /// beside the paper (tables.md, rates.json) and the extended table (extended.md) into
    /// --out. `make report` also runs `experiment`, `study` on the 2D and 3D bars, `getfem` and
    /// `figures`.
    Report(ReportArgs),
    /// How the Tables 1–2 rates move with the horizon and the level range (`make experiment`).
    Experiment(ExperimentArgs),
    /// The render step (`make figures`): from the data under a reports directory (--out), the
    /// pages that gather several studies (schemes.md, work-precision.md), the figures (SVG)
    /// into its figures/ and its README.md index.
    Figures(FiguresArgs),
    /// The stability suite (`make stability`): every scheme × mass on the hard cases, with a
    /// verdict each; writes stability.md and stability.json.
    Stability(StabilityArgs),
    /// Regenerate the golden rates of the gated studies with their round-off sensitivity (`make
    /// golden`; nothing else writes them): golden/rates-1d-dirichlet.json,
    /// rates-1d-gravity.json, rates-1d-extended.json and rates-2d.json.
    Golden(GoldenArgs),
    /// Another code's runs of a scene (JSON or CSV run files): the harness's norms, the rates
    /// of each labelled series as Tables 1–2; --golden gates them, --write-golden writes such
    /// a file, --out writes verify.json and verify.md.
    Verify(VerifyArgs),
    /// GetFEM's demo runs (tests/data/getfem) solved again with its conventions and compared
    /// step by step (`make verify-getfem`); writes getfem.md.
    Getfem(GetfemArgs),
    /// GetFEM's own runs of the 2D and 3D bars (tests/data/getfem2d, getfem3d) written as run
    /// files of the external format's box form, for `signorini verify` (`make league`).
    GetfemBox(GetfemBoxArgs),
    /// The league table (`make league`): every verification under a directory
    /// (`<entry>/verify.json`, from `verify --out DIR/<entry>`) side by side in league.md and
    /// league.json.
    League(LeagueArgs),
    /// The schemes with their parameters, the mass variants, the norms and the scenes found.
    List(ListArgs),
    /// The reports of a command run as shards (`--shard k/n` on study, stability, sensitivity
    /// or reference) from the shards' partial result files: checks they are the n shards of
    /// one invocation and writes, or prints, what the unsharded command does.
    Merge(MergeArgs),
}

/// Reads the command line once (the only read of this process's arguments), parses it and runs
/// its subcommand; a command whose job lists shard runs as its typed [`ShardableCommand`], given
/// the line it was typed as.
fn main() -> ExitCode {
    let argv: Vec<std::ffi::OsString> = std::env::args_os().collect();
    let cli = Cli::parse_from(&argv);
    let line = CommandLine::new(
        argv.iter()
            .skip(1)
            .map(|a| a.to_string_lossy().into_owned())
            .collect(),
    );
    let progress = commands::show_progress(&line);
    let result: Result<(), Failure> = match cli.command {
        Command::Run(args) => commands::run_scene(args),
        Command::Study(args) => ShardableCommand::Study(args).run(&line),
        Command::Rejudge(args) => commands::rejudge(args),
        Command::Sensitivity(args) => ShardableCommand::Sensitivity(args).run(&line),
        Command::Reference(args) => ShardableCommand::Reference(args).run(&line),
        Command::ClusterPlan(args) => commands::cluster_plan(args),
        Command::Report(args) => ShardableCommand::Report(args).run(&line),
        Command::Experiment(args) => ShardableCommand::Experiment(args).run(&line),
        Command::Figures(args) => commands::figures(args),
        Command::Stability(args) => ShardableCommand::Stability(args).run(&line),
        Command::Golden(args) => commands::golden(args),
        Command::Verify(args) => commands::verify_runs(args),
        Command::Getfem(args) => commands::getfem(args),
        Command::GetfemBox(args) => commands::getfem_box(args),
        Command::League(args) => commands::league(args),
        Command::List(args) => commands::list(args),
        Command::Merge(args) => commands::merge(args),
    };
    drop(progress);
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(f) => {
            eprintln!("error: {}", f.message);
            ExitCode::from(f.code)
        }
    }
}
