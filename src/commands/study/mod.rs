//! `signorini study`, `sensitivity` and `reference`: refinement studies of a scene, their
//! round-off ensembles and the fine-mesh references of box scenes.

use std::path::PathBuf;

use clap::Args;
use serde::{Deserialize, Serialize};

use super::failure::Failure;
use super::limits::LimitArgs;
use super::options::{parsed, ConventionArgs, LinearSolverArgs, REPORTS};
use super::sharding::command_line::CommandLine;
use super::sharding::sharded::Sharded;
use super::sharding::{EnsembleShardArgs, ReferenceShardArgs, ShardArgs};
use crate::harness::problem::{ContactTreatment, MassVariant, Scheme};
use crate::harness::reference::scene_study::StudyChoices;
use crate::harness::run::distributed::Ranks;
#[cfg(feature = "mpi")]
use crate::harness::run::distributed::{CountedRanks, MpiRanks, Traffic};
use crate::harness::run::norms::Norm;
use crate::harness::study::executor::Executor;
use crate::harness::study::sensitivity::EnsembleConfig;
use crate::harness::study::shard::Invocation;
use reference_run::{references, ReferenceRequest};
use study_run::{SensitivityRequest, StudyRequest};

pub(crate) mod reference_run;
mod study_run;

/// The arguments of `signorini study`.
#[derive(Debug, Clone, Args, Serialize, Deserialize)]
pub struct StudyArgs {
    /// The scene file.
    pub scene: PathBuf,
    /// Schemes (repeat the option for several): a preset (see `signorini list`) or
    /// newmark(beta=B,gamma=G), theta(theta=T), paoli-schatzman(beta=B,e=E); default: the
    /// scene's `discretisation.schemes`, else the paper's seven.
    #[arg(long, value_parser = parsed::<Scheme>)]
    pub scheme: Vec<Scheme>,
    /// Mass variants, comma-separated, of standard, redistributed, lumped,
    /// redistributed-conserving, singular-dynamic, getfem-redistributed, getfem-singular;
    /// default: the paper's two (standard, redistributed).
    #[arg(long, value_delimiter = ',', value_parser = parsed::<MassVariant>)]
    pub mass: Vec<MassVariant>,
    /// Norms, comma-separated, of u_Linf_H, u_L2_H, u_Linf_V, u_L2_V, lambda_L2, energy_Linf,
    /// energy_L2; default: the scene's.
    #[arg(long, value_delimiter = ',', value_parser = parsed::<Norm>)]
    pub norm: Vec<Norm>,
    /// Levels NX, comma-separated and increasing; default: the scene's.
    #[arg(long, value_delimiter = ',')]
    pub levels: Vec<usize>,
    /// Δx/Δt (default: the scene's).
    #[arg(long, allow_hyphen_values = true)]
    pub ratio: Option<f64>,
    /// Print JSON instead of markdown.
    #[arg(long)]
    pub json: bool,
    /// Box scenes: elements along the axis of the fine-mesh reference (default: the
    /// scene's `discretisation.reference_level`).
    #[arg(long)]
    pub reference_level: Option<usize>,
    /// Box scenes: write `elastic-<d>d.md`, `elastic-<d>d.json` and the figure data into this
    /// reports directory instead of printing.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Box scenes: where the fine-mesh reference is looked up and kept (default: the user's
    /// cache, shared by every command: $SIGNORINI_CACHE, else ~/.cache/signorini/references).
    #[arg(long)]
    pub cache: Option<PathBuf>,
    /// Contact treatment of every case: multiplier, penalty(gamma0=G),
    /// nitsche(theta=T,gamma0=G) (1D only). Default: the scene's, else multiplier.
    #[arg(long, value_parser = parsed::<ContactTreatment>)]
    pub contact: Option<ContactTreatment>,
    /// The schemes' implementation choices.
    #[command(flatten)]
    pub conventions: ConventionArgs,
    /// The step solver of a box scene.
    #[command(flatten)]
    pub solver: LinearSolverArgs,
    /// The resource limits.
    #[command(flatten)]
    pub limits: LimitArgs,
    /// Run one shard of the study's jobs (with --out: where its partial result file goes).
    #[command(flatten)]
    pub shard: ShardArgs,
}

/// `values` without repetitions, in their order; each repeated one is named on stderr
/// (`--mass standard,standard` runs the case once).
fn distinct<T: PartialEq + std::fmt::Display>(option: &str, values: Vec<T>) -> Vec<T> {
    let mut kept: Vec<T> = Vec::with_capacity(values.len());
    for v in values {
        if kept.contains(&v) {
            eprintln!("note: {option} {v} is given more than once; its cases run once");
        } else {
            kept.push(v);
        }
    }
    kept
}

/// A refinement study of a scene: the rate table of the selected cases and norms, as
/// markdown or JSON. Nothing outside the selection is computed; a box study's report says it was
/// made by the command line it is given.
impl Sharded for StudyArgs {
    fn recorded(&self, out: Option<PathBuf>) -> Self {
        Self {
            out,
            shard: ShardArgs::default(),
            ..self.clone()
        }
    }

    fn inputs(&self) -> Vec<PathBuf> {
        vec![self.scene.clone()]
    }

    fn executor(&self) -> Executor {
        self.shard.executor()
    }

    fn run_with(
        self,
        executor: &Executor,
        invocation: &Invocation,
        line: &CommandLine,
    ) -> Result<(), Failure> {
        let request = StudyRequest {
            choices: StudyChoices {
                schemes: distinct("--scheme", self.scheme),
                masses: distinct("--mass", self.mass),
                norms: self.norm,
                levels: self.levels,
                ratio: self.ratio,
                reference_level: self.reference_level,
                contact: self.contact,
                conventions: self.conventions.choice(),
                linear_solver: self.solver.linear_solver,
            },
            scene: self.scene,
            json: self.json,
            out: self.out,
            cache: self.cache,
            limits: self.limits.limits(),
        };
        let said = study_run::study(request, executor, invocation, &line.typed())?;
        out!("{said}");
        Ok(())
    }
}

/// The arguments of `signorini rejudge`.
#[derive(Debug, Args)]
pub struct RejudgeArgs {
    /// The box scene whose study was written into --out.
    pub scene: PathBuf,
    /// The reports directory holding the study's elastic-<d>d.json.
    #[arg(long, default_value = REPORTS)]
    pub out: PathBuf,
}

/// The findings of a committed 2D/3D study judged again from its elastic-<d>d.json, without
/// running anything (`make rejudge`): its report and its findings rewritten.
pub fn rejudge(args: RejudgeArgs) -> Result<(), Failure> {
    out!("{}", study_run::rejudge(&args.scene, &args.out)?);
    Ok(())
}

/// The arguments of `signorini sensitivity`.
#[derive(Debug, Clone, Args, Serialize, Deserialize)]
pub struct SensitivityArgs {
    /// The scene file (a bar1d or box scene with an obstacle).
    pub scene: PathBuf,
    /// Perturbed members of each set per case and level (2 to 1024).
    #[arg(long, default_value_t = 16)]
    pub members: usize,
    /// Relative noise amplitude, in (0, 1e-3].
    #[arg(long, default_value = "1e-13", allow_hyphen_values = true)]
    pub amplitude: f64,
    /// Output directory.
    #[arg(long, default_value = REPORTS)]
    pub out: PathBuf,
    /// Box scenes: where the fine-mesh reference is looked up and kept (default: the user's
    /// cache, as `study --cache`).
    #[arg(long)]
    pub cache: Option<PathBuf>,
    /// The shard to run.
    #[command(flatten)]
    pub shard: EnsembleShardArgs,
    /// The resource limits.
    #[command(flatten)]
    pub limits: LimitArgs,
}

/// Round-off sensitivity of a scene's study (`make report` runs it on the bar): every case and
/// level run as an ensemble of members perturbed on the initial data (a bar's displacement, a
/// box's velocity) and at every step; writes sensitivity.md and sensitivity.json with each
/// case's class.
impl Sharded for SensitivityArgs {
    fn recorded(&self, out: Option<PathBuf>) -> Self {
        Self {
            out: out.unwrap_or_else(|| PathBuf::from(REPORTS)),
            shard: EnsembleShardArgs::default(),
            ..self.clone()
        }
    }

    fn inputs(&self) -> Vec<PathBuf> {
        vec![self.scene.clone()]
    }

    fn executor(&self) -> Executor {
        self.shard.executor()
    }

    fn run_with(
        self,
        executor: &Executor,
        invocation: &Invocation,
        _line: &CommandLine,
    ) -> Result<(), Failure> {
        let request = SensitivityRequest {
            scene: self.scene,
            ensemble: EnsembleConfig {
                members: self.members,
                amplitude: self.amplitude,
            },
            out: self.out,
            cache: self.cache,
            limits: self.limits.limits(),
        };
        out!("{}", study_run::sensitivity(request, executor, invocation)?);
        Ok(())
    }
}

/// The arguments of `signorini reference`.
#[derive(Debug, Clone, Args, Serialize, Deserialize)]
pub struct ReferenceArgs {
    /// Box scene files.
    #[arg(required = true)]
    pub scenes: Vec<PathBuf>,
    /// Where the references are cached (default: the user's cache, as `study --cache`).
    #[arg(long)]
    pub cache: Option<PathBuf>,
    /// With --shard: the directory the shard's partial result file goes into (the references
    /// themselves go into --cache).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// The step solver.
    #[command(flatten)]
    pub solver: LinearSolverArgs,
    /// The resource limits.
    #[command(flatten)]
    pub limits: LimitArgs,
    /// The shard to run.
    #[command(flatten)]
    pub shard: ReferenceShardArgs,
    /// Computes the one scene's reference (the cache must not hold it) and writes what it cost
    /// into this JSON file: times, CG iterations, each rank's peak memory, rank 0's traffic
    /// (the figures `signorini cluster-plan` fits).
    #[arg(long, value_name = "FILE")]
    pub measure: Option<PathBuf>,
}

/// The fine-mesh reference of a box scene (`make reference`): reuses the cache when its
/// parameters match the scene's, says which differ otherwise, and recomputes it.
///
/// Built with the `mpi` feature and launched by `mpirun` or `srun` on more than one rank, the
/// ranks share each reference's run ([`on_mpi_ranks`]); a merge finds every reference in the
/// cache and runs in one process.
impl Sharded for ReferenceArgs {
    fn recorded(&self, _out: Option<PathBuf>) -> Self {
        Self {
            out: None,
            shard: ReferenceShardArgs::default(),
            ..self.clone()
        }
    }

    fn inputs(&self) -> Vec<PathBuf> {
        self.scenes.clone()
    }

    fn executor(&self) -> Executor {
        self.shard.executor()
    }

    fn run_with(
        self,
        executor: &Executor,
        invocation: &Invocation,
        _line: &CommandLine,
    ) -> Result<(), Failure> {
        reference_with(self, executor, invocation, None)
    }

    fn run(self, invocation: &Invocation, line: &CommandLine) -> Result<(), Failure> {
        let executor = self.executor();
        #[cfg(feature = "mpi")]
        if let Some(ranks) = launched_by_mpi().then(MpiRanks::initialise).flatten() {
            if ranks.size() > 1 {
                return on_mpi_ranks(self, &executor, invocation, &ranks);
            }
        }
        self.run_with(&executor, invocation, line)
    }
}

/// Whether this process was started by an MPI launcher (Open MPI's `mpirun`, or a PMI or
/// PMIx one such as Slurm's `srun`): its environment names the job's size or this rank.
#[cfg(feature = "mpi")]
fn launched_by_mpi() -> bool {
    ["OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK"]
        .iter()
        .any(|name| std::env::var_os(name).is_some())
}

/// `signorini reference` on this MPI rank: every rank runs it (MPI is finalised when the caller
/// drops `ranks`); a rank that fails says why, with its rank, and ends every rank with its exit
/// code (`MPI_Abort`), so that none waits forever on it.
#[cfg(feature = "mpi")]
fn on_mpi_ranks(
    args: ReferenceArgs,
    executor: &Executor,
    invocation: &Invocation,
    ranks: &MpiRanks,
) -> Result<(), Failure> {
    let counted = CountedRanks::new(ranks);
    match reference_with(args, executor, invocation, Some(&counted)) {
        Ok(()) => {
            let Traffic {
                messages,
                bytes_sent,
                bytes_received,
                sums,
            } = counted.traffic();
            if ranks.rank() == 0 {
                out!(
                    "rank 0 of {}: sent {messages} messages ({bytes_sent} bytes), received \
                     {bytes_received} bytes, took part in {sums} sums",
                    ranks.size()
                );
            }
            Ok(())
        }
        Err(failure) => {
            eprintln!(
                "error: rank {} of {}: {}",
                ranks.rank(),
                ranks.size(),
                failure.message
            );
            ranks.abort(i32::from(failure.code))
        }
    }
}

/// `signorini reference` with its scenes handed to `executor`, one at a time, its shard's file
/// recording `invocation`, this process one of `ranks` when given.
fn reference_with(
    args: ReferenceArgs,
    executor: &Executor,
    invocation: &Invocation,
    ranks: Option<&dyn Ranks>,
) -> Result<(), Failure> {
    let request = ReferenceRequest {
        scenes: args.scenes,
        cache: args.cache,
        out: args.out,
        linear_solver: args.solver.linear_solver,
        limits: args.limits.limits(),
        ranks,
        measure: args.measure,
    };
    let say = |said: &str| out!("{said}");
    let done = references(request, executor, invocation, &say)?;
    if !done.is_empty() {
        out!("{done}");
    }
    Ok(())
}
