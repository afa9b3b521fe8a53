//! The cost model's answer for a reference on a cluster (`signorini cluster-plan`): how many
//! ranks a node can hold, each rank's memory, the time per step and the whole run on `N`
//! nodes, and the model checked against references computed here in one process.

use std::path::Path;

use serde::Serialize;

use super::fit::{CostModel, Node};
use super::Measurement;
use crate::harness::files::artifacts::{read_json, write_atomic, write_json};
use crate::harness::files::error::ParameterError;
use crate::harness::files::input::Limit;
use crate::harness::run::elastic::BoxProblem;
use crate::harness::study::budget::{box_size, steps};
use crate::studies::error::Error;

/// The machine-readable plan's file name.
pub const PLAN_JSON: &str = "cluster-plan.json";
/// Its report's.
pub const PLAN_MD: &str = "cluster-plan.md";

/// The reference on `nodes` nodes.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Prediction {
    /// Nodes.
    pub nodes: usize,
    /// Ranks per node (rank 0's node holds as many as any).
    pub ranks_per_node: usize,
    /// All ranks.
    pub ranks: usize,
    /// Rank 0's peak bytes.
    pub rank0_bytes: f64,
    /// Every other rank's peak bytes.
    pub rank_bytes: f64,
    /// The busiest node's bytes (rank 0's).
    pub node_bytes: f64,
    /// The node layers rank 0 holds: its share, or the contact slab's when that is more.
    pub rank0_layers: usize,
    /// Seconds per step of rank 0's slab (the slowest), computing, its contact solves included.
    pub slab_seconds_per_step: f64,
    /// Seconds per step on the interconnect.
    pub network_seconds_per_step: f64,
    /// Seconds per reference step of the check run on rank 0's core: half a step of it over
    /// the same ranks, its interconnect included (added to the reference's step); or, where
    /// its contact slab leaves no layer for some rank, in one process beside rank 0 (then the
    /// floor of a step, `check_distributed` false).
    pub check_seconds_per_step: f64,
    /// Whether the check run is distributed over the ranks.
    pub check_distributed: bool,
    /// The whole run, hours.
    pub hours: f64,
}

/// The model against a reference computed here in one process.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Check {
    /// The file it was read from.
    pub source: String,
    /// Elements along the axis.
    pub level: usize,
    /// Unknowns.
    pub dofs: usize,
    /// Steps.
    pub steps: usize,
    /// Its measured seconds.
    pub measured_seconds: f64,
    /// The model's, on one process of as many threads as the measured run had (the threads'
    /// speed-up measured on one level, [`Plan::thread_speedup`]).
    pub predicted_seconds: f64,
}

/// The plan: the model, its fit, its predictions and its checks (`cluster-plan.json`).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Plan {
    /// The scene.
    pub scene: String,
    /// The reference's elements along the axis.
    pub level: usize,
    /// Its unknowns.
    pub dofs: f64,
    /// Its steps.
    pub steps: f64,
    /// The stated node.
    pub node: Node,
    /// The fitted model.
    pub model: CostModel,
    /// The speed-up of one process's threads (its pool's size here) over one thread,
    /// measured: `(threads, speed-up)`.
    pub thread_speedup: Option<(usize, f64)>,
    /// On each number of nodes asked for.
    pub predictions: Vec<Prediction>,
    /// The model against the one-process references given.
    pub checks: Vec<Check>,
}

/// What a study's JSON holds of its reference.
#[derive(Debug, serde::Deserialize)]
struct StudyReference {
    level: usize,
    dofs: usize,
    steps: usize,
    seconds: f64,
    from_cache: bool,
}

#[derive(Debug, serde::Deserialize)]
struct StudyFile {
    reference: StudyReference,
}

const STUDY_FILE: Limit = Limit {
    what: "study results",
    max_bytes: 64 * 1024 * 1024,
};

impl Plan {
    /// The plan of `problem`'s (scene `scene`) reference on `level` elements over each of
    /// `nodes` nodes of `node`, the model fitted to `measured` (made on `cores` cores) and
    /// checked against the references of the studies `checks` (their `elastic-<d>d.json`).
    pub fn new(
        (scene, problem, level): (&str, &BoxProblem, usize),
        (measured, cores): (&[Measurement], usize),
        node: Node,
        nodes: &[usize],
        checks: &[&Path],
    ) -> Result<Self, Error> {
        let model = CostModel::fit(measured, cores).map_err(|e| {
            ParameterError::new(
                "measured",
                e.0,
                "references measured on two levels at least, each on 1 and 2 ranks of one \
                 thread and on 3 ranks (make cluster-plan's)",
            )
        })?;
        let (dofs, h) = box_size(problem, level);
        let ratio = measured.first().map_or(2.0, |m| {
            let (_, h_m) = box_size(problem, m.level);
            m.steps as f64 * h_m / problem.horizon
        });
        let steps = steps(problem.horizon, h, ratio);
        let (check_dofs, _) = box_size(problem, level / 2);
        let thread_speedup = Self::thread_speedup(measured);
        let predictions = nodes
            .iter()
            .map(|&n| Self::predict(&model, &node, (level, dofs, steps, check_dofs), n))
            .collect();
        let checks = checks
            .iter()
            .map(|path| {
                let study: StudyFile = read_json(path, STUDY_FILE)?;
                let r = study.reference;
                if r.from_cache {
                    return Err(ParameterError::new(
                        "check",
                        path.display().to_string(),
                        "a study whose reference was computed in it (its seconds are a run's)",
                    )
                    .into());
                }
                let one_thread = r.steps as f64 * model.step_seconds(r.level, r.dofs as f64, 1.0)
                    + model.setup_per_dof * r.dofs as f64;
                Ok(Check {
                    source: path.display().to_string(),
                    level: r.level,
                    dofs: r.dofs,
                    steps: r.steps,
                    measured_seconds: r.seconds,
                    predicted_seconds: one_thread / thread_speedup.map_or(1.0, |(_, s)| s),
                })
            })
            .collect::<Result<Vec<Check>, Error>>()?;
        Ok(Self {
            scene: scene.to_string(),
            level,
            dofs,
            steps,
            node,
            model,
            thread_speedup,
            predictions,
            checks,
        })
    }

    /// The speed-up of the measured one-process run with the most threads over the one-thread
    /// run of the same level.
    fn thread_speedup(measured: &[Measurement]) -> Option<(usize, f64)> {
        let many = (measured.iter())
            .filter(|m| m.ranks == 1 && m.threads > 1)
            .max_by_key(|m| m.threads)?;
        let one =
            (measured.iter()).find(|m| m.ranks == 1 && m.threads == 1 && m.level == many.level)?;
        Some((
            many.threads,
            one.seconds_per_step() / many.seconds_per_step(),
        ))
    }

    /// The reference (`level`, `dofs` unknowns, `steps` steps) on `nodes` nodes: on the number
    /// of ranks whose step is the shortest (the fewest of those that tie), among those the
    /// nodes hold (a rank per core at most, rank 0's node within its memory) and the layers
    /// allow (one per two). Beyond about `ℓ/(L + 1)` ranks rank 0's contact slab bounds the
    /// step, and more ranks only add to the interconnect's time.
    fn predict(
        model: &CostModel,
        node: &Node,
        (level, dofs, steps, check_dofs): (usize, f64, f64, f64),
        nodes: usize,
    ) -> Prediction {
        let nodes = nodes.max(1);
        let most_ranks = (level / 2).max(1).min(nodes * node.cores.max(1));
        let memory = |ranks: usize| {
            let p = ranks as f64;
            let rank0 = model.rank0_memory.bytes(dofs, p);
            let rank = model.rank_memory.bytes(dofs, p);
            (
                rank0,
                rank,
                rank0 + (ranks.div_ceil(nodes) - 1) as f64 * rank,
            )
        };
        // The check run's layers give every rank one beyond rank 0's contact slab, or it runs
        // in one process beside rank 0.
        let timing = |ranks: usize| {
            let p = ranks as f64;
            let slab = model.step_seconds(level, dofs, p);
            let network = model.network_seconds(node, level, dofs, p);
            if level / 2 > model.contact_layers + ranks - 1 {
                let check = model.check_seconds(level, check_dofs, p)
                    + 0.5 * model.network_seconds(node, level / 2, check_dofs, p);
                (slab, network, check, true, slab + network + check)
            } else {
                let check = model.check_seconds(level, check_dofs, 1.0);
                (slab, network, check, false, (slab + network).max(check))
            }
        };
        let ranks = (1..=most_ranks)
            .filter(|&r| memory(r).2 <= node.memory_bytes)
            .min_by(|&a, &b| timing(a).4.total_cmp(&timing(b).4))
            .unwrap_or(1);
        let (rank0_bytes, rank_bytes, node_bytes) = memory(ranks);
        let (slab, network, check, check_distributed, step) = timing(ranks);
        Prediction {
            nodes,
            ranks_per_node: ranks.div_ceil(nodes),
            ranks,
            rank0_bytes,
            rank_bytes,
            node_bytes,
            rank0_layers: model.rank0_layers(level, ranks as f64),
            slab_seconds_per_step: slab,
            network_seconds_per_step: network,
            check_seconds_per_step: check,
            check_distributed,
            hours: (steps * step + model.setup_per_dof * dofs) / 3600.0,
        }
    }

    /// Writes `cluster-plan.json` and `cluster-plan.md` into `out` (a staged output directory).
    pub fn write(&self, out: &Path) -> Result<(), Error> {
        write_json(&out.join(PLAN_JSON), self)?;
        Ok(write_atomic(&out.join(PLAN_MD), self.render().as_bytes())?)
    }

    /// The report.
    pub fn render(&self) -> String {
        let gib = |b: f64| b / f64::from(1u32 << 30);
        let m = &self.model;
        let mut s = format!(
            "# The {} reference on {} elements across a cluster\n\n\
             Written by `signorini cluster-plan` (`make cluster-plan`) from references computed \
             here with `signorini reference --measure` on 1 to 4 ranks; the model and its \
             terms are in `docs/src/distributed-reference.md`. {:.3e} unknowns, {:.0} steps.\n\n\
             ## The node (stated)\n\n\
             {} cores, {:.0} GiB, interconnect {:.1} GB/s and {:.1} µs.\n\n\
             ## The fitted model\n\n\
             | term | value |\n|---|---|\n\
             | a: seconds per CG iteration and slab unknown | {:.3e} |\n\
             | c: seconds per step | {:.3e} |\n\
             | e: contact seconds per step and contact slab unknown | {:.3e} |\n\
             | L: the contact slab's layers (finest level measured) | {} |\n\
             | iterations per step k = k0 ℓ^p | k0 = {:.3}, p = {:.3} |\n\
             | messages per iteration (2 ranks, rank 0) | {:.2} |\n\
             | bytes per iteration and layer unknown | {:.2} |\n\
             | sums per iteration | {:.2} |\n\
             | rank 0 memory A + B n + C n/P + D P | {:.0} MiB + {:.1} B n + {:.1} B n/P + {:.2} MiB P |\n\
             | other ranks' memory | {:.0} MiB + {:.1} B n + {:.1} B n/P + {:.2} MiB P |\n\n",
            self.scene,
            self.level,
            self.dofs,
            self.steps,
            self.node.cores,
            gib(self.node.memory_bytes),
            self.node.bandwidth / 1e9,
            self.node.latency * 1e6,
            m.per_iteration_dof,
            m.per_step,
            m.contact_per_slab_dof,
            m.contact_layers,
            m.iterations.0,
            m.iterations.1,
            m.messages_per_iteration,
            m.bytes_per_iteration_layer_dof,
            m.sums_per_iteration,
            m.rank0_memory.fixed / 1048576.0,
            m.rank0_memory.per_dof,
            m.rank0_memory.per_slab_dof,
            m.rank0_memory.per_rank / 1048576.0,
            m.rank_memory.fixed / 1048576.0,
            m.rank_memory.per_dof,
            m.rank_memory.per_slab_dof,
            m.rank_memory.per_rank / 1048576.0,
        );
        s +=
            "## The fit\n\n| level | ranks | measured s/step | model s/step |\n|---|---|---|---|\n";
        for (level, ranks, measured, model) in &m.time_fit {
            s += &format!("| {level} | {ranks} | {measured:.4} | {model:.4} |\n");
        }
        s += "\n| level | ranks | rank | measured peak MiB | model MiB |\n|---|---|---|---|---|\n";
        for (level, ranks, rank, measured, model) in &m.memory_fit {
            s += &format!(
                "| {level} | {ranks} | {rank} | {:.0} | {:.0} |\n",
                measured / 1048576.0,
                model / 1048576.0
            );
        }
        s += "\n(Fitted to the runs in one process of one thread; the runs on two ranks are set \
              beside it: each of their processes runs the reference's slab and the check run's \
              on one of this machine's two cores.)\n\n\
              ## The prediction\n\nOn each number of nodes, the number of ranks whose step \
              is the shortest (the fewest of those that tie), among those the nodes' cores and \
              memory hold. A step takes rank 0's slab (the slowest: it holds the \
              contact slab's layers at least), the interconnect's time, and half a step of the \
              check run distributed over the same ranks (or, where the check's contact slab \
              leaves no layer for some rank, the longer of the reference's step and the check's \
              in one process).\n\n| nodes | ranks per node | ranks | rank 0 GiB | other ranks \
              GiB | rank 0's node GiB | rank 0's layers | slab s/step | interconnect s/step | \
              check run s/step | hours |\n|---|---|---|---|---|---|---|---|---|---|---|\n";
        for p in &self.predictions {
            s +=
                &format!(
                "| {} | {} | {} | {:.1} | {:.2} | {:.0} | {} | {:.3} | {:.3} | {:.3}{} | {:.1} |\n",
                p.nodes,
                p.ranks_per_node,
                p.ranks,
                gib(p.rank0_bytes),
                gib(p.rank_bytes),
                gib(p.node_bytes),
                p.rank0_layers,
                p.slab_seconds_per_step,
                p.network_seconds_per_step,
                p.check_seconds_per_step,
                if p.check_distributed { "" } else { " (one process)" },
                p.hours
            );
        }
        if !self.checks.is_empty() {
            let threads = self
                .thread_speedup
                .map_or("no thread speed-up measured".to_string(), |(t, s)| {
                    format!("{t} threads measured {s:.2}× one")
                });
            s += &format!(
                "\n## The model against references computed here in one process\n\n\
                 One process of the machine's threads ({threads}).\n\n\
                 | study | level | unknowns | steps | measured s | model s |\n|---|---|---|---|---|---|\n"
            );
            for c in &self.checks {
                s += &format!(
                    "| {} | {} | {} | {} | {:.0} | {:.0} |\n",
                    c.source, c.level, c.dofs, c.steps, c.measured_seconds, c.predicted_seconds
                );
            }
        }
        s
    }
}
