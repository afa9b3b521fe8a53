//! `signorini cluster-plan`: the cost model of a distributed reference fitted to measured
//! references, and its prediction on a cluster ([`crate::studies::cluster_plan`]).

use std::path::PathBuf;

use clap::Args;

use super::failure::Failure;
use crate::harness::files::output_dir::{Replace, StagedDir};
use crate::harness::study::budget::parse_bytes;
use crate::harness::study::scene::Scene;
use crate::studies::cluster_plan::fit::Node;
use crate::studies::cluster_plan::plan::{Plan, PLAN_MD};
use crate::studies::cluster_plan::Measurement;

/// The arguments of `signorini cluster-plan`.
#[derive(Args, Debug, Clone)]
pub struct ClusterPlanArgs {
    /// The box scene whose reference is planned.
    pub scene: PathBuf,
    /// The reference's elements along the axis.
    #[arg(long, value_parser = clap::value_parser!(u32).range(2..=1_000_000))]
    pub level: u32,
    /// The measurements the model is fitted to (`signorini reference --measure`).
    #[arg(long, required = true, num_args = 1..)]
    pub measured: Vec<PathBuf>,
    /// The cores the measurements ran on: a run whose ranks × threads exceed them is fitted for
    /// its memory only.
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=100_000))]
    pub measured_cores: u32,
    /// The numbers of nodes to predict for.
    #[arg(long, value_delimiter = ',', default_value = "8,16,32",
          value_parser = clap::value_parser!(u32).range(1..=1_000_000))]
    pub nodes: Vec<u32>,
    /// Cores per node.
    #[arg(long, default_value_t = 64, value_parser = clap::value_parser!(u32).range(1..=100_000))]
    pub cores: u32,
    /// Memory per node (K, M, G, T suffixes).
    #[arg(long, default_value = "256G", value_parser = parse_bytes)]
    pub memory: u64,
    /// Interconnect bandwidth, bytes per second.
    #[arg(long, default_value_t = 12.5e9, value_parser = positive)]
    pub bandwidth: f64,
    /// Interconnect latency, seconds.
    #[arg(long, default_value_t = 2e-6, value_parser = positive)]
    pub latency: f64,
    /// Studies whose reference was computed here in one process (their `elastic-<d>d.json`),
    /// to check the model against.
    #[arg(long)]
    pub check: Vec<PathBuf>,
    /// Where cluster-plan.md and cluster-plan.json go.
    #[arg(long, default_value = "reports/cluster")]
    pub out: PathBuf,
}

/// A finite positive number.
fn positive(s: &str) -> Result<f64, String> {
    match s.trim().parse::<f64>() {
        Ok(v) if v.is_finite() && v > 0.0 => Ok(v),
        _ => Err(format!("{s}: allowed: a finite number above 0")),
    }
}

/// Fits the model to the measurements and writes the plan of the scene's reference on each
/// number of nodes.
pub fn cluster_plan(args: ClusterPlanArgs) -> Result<(), Failure> {
    let scene = Scene::load(&args.scene)?;
    let problem = scene.box_problem("box scenes: a cluster plan is for their reference")?;
    let measured = (args.measured.iter())
        .map(|p| Measurement::read(p))
        .collect::<Result<Vec<_>, _>>()?;
    let node = Node {
        cores: args.cores as usize,
        memory_bytes: args.memory as f64,
        bandwidth: args.bandwidth,
        latency: args.latency,
    };
    let nodes: Vec<usize> = args.nodes.iter().map(|&n| n as usize).collect();
    let checks: Vec<&std::path::Path> = args.check.iter().map(PathBuf::as_path).collect();
    let inputs: Vec<&PathBuf> = (args.measured.iter().chain(&args.check))
        .chain([&args.scene])
        .collect();
    let staged = StagedDir::begin("--out", &args.out, Replace::Files)?.reading(&inputs)?;
    let plan = Plan::new(
        (&scene.name, &problem, args.level as usize),
        (&measured, args.measured_cores as usize),
        node,
        &nodes,
        &checks,
    )?;
    plan.write(staged.path())?;
    staged.commit()?;
    out!("the plan is in {}", args.out.join(PLAN_MD).display());
    Ok(())
}
