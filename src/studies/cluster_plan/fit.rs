//! The cost model of a distributed reference, fitted to [`Measurement`]s made here, and its
//! prediction for a reference on `N` nodes of a stated size ([`Node`]).
//!
//! **Time per step.** Every rank waits for the slowest at each CG iteration, and the slowest is
//! rank 0: it holds `ℓ₀ = max(⌈ℓ/P⌉, L + 1)` of the `ℓ` node layers (the local contact
//! operator's slab of `L` layers and the next, [`crate::harness::run::distributed`]) and solves
//! the contact. With `n` unknowns, `P` ranks of one thread each and `k` CG iterations per step,
//! a run's step on rank 0 takes
//! ```text
//! t(ℓ, n, P) = a · k n ℓ₀/ℓ + e · n (L + 1)/ℓ + c + t_net(P)
//! ```
//! `a`: the work per iteration and unknown (products, preconditioner, the share of the
//! projections, the check comparison and the balance); `e`: the contact solves' per step and
//! unknown of their slab; `c`: per step whatever the size. `e` is the measured contact seconds
//! of the runs in one process of one thread, `a` and `c` a least-squares fit to the rest of
//! their seconds (`k` from their iterations). The check run one level coarser is distributed
//! over the same ranks, in a second thread of each, and takes half as many steps: a reference
//! step costs `t(ℓ, n, P) + t(ℓ/2, n_c, P) / 2` on rank 0's core (`n_c` its unknowns). Where
//! the check's contact slab leaves no layer for some rank it runs in one process beside rank 0
//! instead, and a step waits for the slower: `max(t(ℓ, n, P), t(ℓ/2, n_c, 1) / 2)`. The runs
//! on two ranks are set beside the model, which they were not fitted to. Messages between
//! processes here go through shared memory; on a cluster the interconnect's are added from the
//! counted traffic and the node's stated latency `α` and bandwidth `β`:
//! ```text
//! t_net = 2 (m α + s / β)  +  2 k (P − 1) α  +  q · 2 ⌈log₂ P⌉ α
//! ```
//! `m`, `s`: messages and bytes rank 0 sent per step on 2 ranks (one neighbour; an inner rank has
//! two), scaled by `k` and the layer's unknowns; the pipeline of the preconditioner's sweeps
//! crossing `P − 1` ranks twice per iteration; and `q` sums per step, each an all-gather. `k` is
//! fitted as `k₀ ℓ^p` over the levels `ℓ` measured.
//!
//! **Memory per rank**: `A + B n + C n / P + D P`, fitted separately to rank 0's peaks and to
//! the others' over the runs on 2, 3 and 4 ranks: `B n` is what a rank holds of the whole box
//! (rank 0: what one process holds of a reference but the slabs; the others: the operators'
//! node classes), `C n / P` its slabs of the reference and of the check run, and `D P` the MPI
//! library's buffers for its peers (measured here: 17.8 MB before the run on 2 ranks, 21.1 MB
//! on 3).

use nalgebra::{DMatrix, DVector};
use serde::Serialize;

use super::Measurement;

/// A cluster node, as stated by the user (nothing here measures it).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Node {
    /// Cores (one rank of one thread each, at most).
    pub cores: usize,
    /// Memory for the ranks, bytes.
    pub memory_bytes: f64,
    /// Interconnect bandwidth, bytes per second.
    pub bandwidth: f64,
    /// Interconnect latency, seconds.
    pub latency: f64,
}

/// `A + B n + C n / P + D P` bytes.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct MemoryModel {
    /// `A`, bytes.
    pub fixed: f64,
    /// `B`, bytes per unknown of the whole mesh.
    pub per_dof: f64,
    /// `C`, bytes per unknown of the rank's slab.
    pub per_slab_dof: f64,
    /// `D`, bytes per rank of the run.
    pub per_rank: f64,
}

impl MemoryModel {
    /// Bytes for `n` unknowns over `ranks`.
    pub fn bytes(&self, n: f64, ranks: f64) -> f64 {
        self.fixed + self.per_dof * n + self.per_slab_dof * n / ranks + self.per_rank * ranks
    }
}

/// The fitted model.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CostModel {
    /// `a`, seconds per CG iteration and slab unknown.
    pub per_iteration_dof: f64,
    /// `c`, seconds per step.
    pub per_step: f64,
    /// `e`, contact seconds per step and unknown of the contact slab.
    pub contact_per_slab_dof: f64,
    /// `L`, the contact slab's layers of the finest level measured, taken for every level.
    pub contact_layers: usize,
    /// `k₀` and `p` of the iterations per step `k₀ ℓ^p`.
    pub iterations: (f64, f64),
    /// Messages rank 0 sent per step and iteration on 2 ranks.
    pub messages_per_iteration: f64,
    /// Bytes rank 0 sent per step, iteration and unknown of a layer, on 2 ranks.
    pub bytes_per_iteration_layer_dof: f64,
    /// Sums per step and iteration.
    pub sums_per_iteration: f64,
    /// Set-up seconds per unknown (rank 0's, the largest measurement's).
    pub setup_per_dof: f64,
    /// Rank 0's memory.
    pub rank0_memory: MemoryModel,
    /// Every other rank's.
    pub rank_memory: MemoryModel,
    /// Each timed measurement against the model: (level, ranks, measured, modelled) seconds
    /// per step.
    pub time_fit: Vec<(usize, usize, f64, f64)>,
    /// Each rank's peak against the model: (level, ranks, rank, measured, modelled) bytes.
    pub memory_fit: Vec<(usize, usize, usize, f64, f64)>,
}

/// Why the model cannot be fitted.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{0}")]
pub struct FitError(pub String);

/// Least squares `X β ≈ y`; `None` when `X` has fewer rows than columns.
fn least_squares(rows: &[Vec<f64>], y: &[f64]) -> Option<Vec<f64>> {
    let columns = rows.first()?.len();
    if rows.len() < columns {
        return None;
    }
    let x = DMatrix::from_fn(rows.len(), columns, |i, j| rows[i][j]);
    let y = DVector::from_column_slice(y);
    let solved = x.svd(true, true).solve(&y, 1e-300).ok()?;
    Some(solved.iter().copied().collect())
}

/// Each column scaled to unit size before the fit (unknowns of 1e4–1e6 beside a constant), the
/// coefficients scaled back.
fn scaled_least_squares(rows: &[Vec<f64>], y: &[f64]) -> Option<Vec<f64>> {
    let columns = rows.first()?.len();
    let scale: Vec<f64> = (0..columns)
        .map(|j| {
            rows.iter()
                .map(|r| r[j].abs())
                .fold(0.0, f64::max)
                .max(1e-300)
        })
        .collect();
    let scaled: Vec<Vec<f64>> = rows
        .iter()
        .map(|r| r.iter().zip(&scale).map(|(v, s)| v / s).collect())
        .collect();
    let beta = least_squares(&scaled, y)?;
    Some(beta.iter().zip(&scale).map(|(b, s)| b / s).collect())
}

/// The unknowns of a layer of a measured run (the box's unknowns over its layers).
fn layer_dofs(m: &Measurement) -> f64 {
    m.dofs as f64 / m.level as f64
}

impl CostModel {
    /// Fits the model to `measured`, whose timed runs used at most `cores` cores.
    pub fn fit(measured: &[Measurement], cores: usize) -> Result<Self, FitError> {
        let one_thread: Vec<&Measurement> = (measured.iter())
            .filter(|m| m.ranks == 1 && m.threads == 1)
            .collect();
        let rows: Vec<Vec<f64>> = (one_thread.iter())
            .map(|m| vec![m.iterations_per_step() * m.dofs as f64, 1.0])
            .collect();
        let seconds: Vec<f64> = (one_thread.iter())
            .map(|m| m.seconds_per_step() - m.contact_seconds / m.steps.max(1) as f64)
            .collect();
        let finest = one_thread.iter().max_by_key(|m| m.level);
        let contact_layers = finest.and_then(|m| m.contact_layers).unwrap_or(0);
        let contact_per_slab_dof = finest.map_or(0.0, |m| {
            m.contact_seconds
                / m.steps.max(1) as f64
                / (layer_dofs(m) * (contact_layers + 1) as f64)
        });
        let mut levels: Vec<usize> = one_thread.iter().map(|m| m.level).collect();
        levels.sort_unstable();
        levels.dedup();
        let [a, c] = scaled_least_squares(&rows, &seconds)
            .and_then(|v| <[f64; 2]>::try_from(v).ok())
            .filter(|_| levels.len() >= 2)
            .ok_or_else(|| {
                FitError(format!(
                    "one-process one-thread runs on {} level(s); the time model needs two",
                    levels.len()
                ))
            })?;
        let iterations = Self::fit_iterations(measured)?;
        let on_two: Vec<(&Measurement, _)> = (measured.iter())
            .filter(|m| m.ranks == 2)
            .filter_map(|m| m.traffic.map(|t| (m, t)))
            .collect();
        let largest = on_two
            .iter()
            .max_by_key(|(m, _)| m.dofs)
            .ok_or_else(|| FitError("no run on 2 ranks with its traffic".into()))?;
        let (m2, t2) = *largest;
        let per_iteration = m2.steps as f64 * m2.iterations_per_step();
        let largest_run = measured.iter().max_by_key(|m| m.dofs).expect("some");
        let (rank0_memory, rank_memory, memory_fit) = Self::fit_memory(measured)?;
        let mut model = Self {
            per_iteration_dof: a,
            per_step: c,
            contact_per_slab_dof,
            contact_layers,
            iterations,
            messages_per_iteration: t2.messages as f64 / per_iteration,
            bytes_per_iteration_layer_dof: t2.bytes_sent as f64 / per_iteration / layer_dofs(m2),
            sums_per_iteration: t2.sums as f64 / per_iteration,
            setup_per_dof: largest_run.setup_seconds / largest_run.dofs as f64,
            rank0_memory,
            rank_memory,
            time_fit: Vec::new(),
            memory_fit,
        };
        model.time_fit = (measured.iter())
            .filter(|m| m.threads == 1 && m.ranks * m.threads <= cores)
            .map(|m| {
                let ranks = m.ranks as f64;
                let fine = model.step_seconds(m.level, m.dofs as f64, ranks);
                let check = if m.ranks > 1 && m.check_ranks == m.ranks {
                    model.check_seconds(m.level, m.check_dofs as f64, ranks)
                } else {
                    0.0
                };
                (m.level, m.ranks, m.seconds_per_step(), fine + check)
            })
            .collect();
        Ok(model)
    }

    /// `k₀ ℓ^p` through the iterations per step of the measured levels (a log-log fit).
    fn fit_iterations(measured: &[Measurement]) -> Result<(f64, f64), FitError> {
        let mut levels: Vec<usize> = measured.iter().map(|m| m.level).collect();
        levels.sort_unstable();
        levels.dedup();
        let rows: Vec<Vec<f64>> = levels.iter().map(|&l| vec![(l as f64).ln(), 1.0]).collect();
        let y: Vec<f64> = (levels.iter())
            .map(|&l| {
                let at: Vec<f64> = (measured.iter())
                    .filter(|m| m.level == l)
                    .map(Measurement::iterations_per_step)
                    .collect();
                (at.iter().sum::<f64>() / at.len() as f64).ln()
            })
            .collect();
        let [p, ln_k0] = least_squares(&rows, &y)
            .and_then(|v| <[f64; 2]>::try_from(v).ok())
            .filter(|_| levels.len() >= 2)
            .ok_or_else(|| FitError("the iterations need runs on two levels at least".into()))?;
        Ok((ln_k0.exp(), p))
    }

    /// Rank 0's and the other ranks' memory models, and each peak against them.
    #[allow(clippy::type_complexity)]
    fn fit_memory(
        measured: &[Measurement],
    ) -> Result<
        (
            MemoryModel,
            MemoryModel,
            Vec<(usize, usize, usize, f64, f64)>,
        ),
        FitError,
    > {
        let mut zero = (Vec::new(), Vec::new(), Vec::new());
        let mut other = (Vec::new(), Vec::new(), Vec::new());
        for m in measured.iter().filter(|m| m.ranks >= 2) {
            let n = m.dofs as f64;
            for (rank, &peak) in m.peak_bytes.iter().enumerate().filter(|(_, &p)| p > 0) {
                let into = if rank == 0 { &mut zero } else { &mut other };
                into.0
                    .push(vec![1.0, n, n / m.ranks as f64, m.ranks as f64]);
                into.1.push(peak as f64);
                into.2.push((m.level, m.ranks, rank));
            }
        }
        let model = |(rows, y, _): &(Vec<Vec<f64>>, Vec<f64>, _), whose: &str| {
            scaled_least_squares(rows, y)
                .and_then(|v| <[f64; 4]>::try_from(v).ok())
                .filter(|_| {
                    let mut ranks: Vec<u64> = rows.iter().map(|r| r[3] as u64).collect();
                    ranks.sort_unstable();
                    ranks.dedup();
                    ranks.len() >= 3
                })
                .map(|[fixed, per_dof, per_slab_dof, per_rank]| MemoryModel {
                    fixed,
                    per_dof,
                    per_slab_dof,
                    per_rank,
                })
                .ok_or_else(|| {
                    FitError(format!(
                        "{} peaks of {whose}; the memory model needs runs on three numbers of \
                         ranks (2, 3 and 4)",
                        rows.len()
                    ))
                })
        };
        let rank0 = model(&zero, "rank 0")?;
        let rank = model(&other, "the other ranks")?;
        let mut fit = Vec::new();
        for (set, model) in [(&zero, rank0), (&other, rank)] {
            for ((row, &y), &(level, ranks, r)) in set.0.iter().zip(&set.1).zip(&set.2) {
                fit.push((level, ranks, r, y, model.bytes(row[1], ranks as f64)));
            }
        }
        Ok((rank0, rank, fit))
    }

    /// CG iterations per step at `level`.
    pub fn iterations_at(&self, level: usize) -> f64 {
        self.iterations.0 * (level as f64).powf(self.iterations.1)
    }

    /// The node layers rank 0 holds of a run on `level` over `ranks` ranks: its share, or the
    /// contact slab's `L + 1` when that is more ([`crate::harness::run::distributed`]).
    pub fn rank0_layers(&self, level: usize, ranks: f64) -> usize {
        let share = (level as f64 / ranks.max(1.0)).ceil() as usize;
        share.max(self.contact_layers + 1).min(level)
    }

    /// Seconds per step of rank 0 of a run on `level` with `n` unknowns over `ranks`
    /// one-thread ranks, computing here (no interconnect): its layers' CG work, the contact
    /// solves on its slab, and the per-step cost.
    pub fn step_seconds(&self, level: usize, n: f64, ranks: f64) -> f64 {
        let layer = n / level as f64;
        self.per_iteration_dof
            * self.iterations_at(level)
            * layer
            * self.rank0_layers(level, ranks) as f64
            + self.contact_per_slab_dof * layer * (self.contact_layers + 1).min(level) as f64
            + self.per_step
    }

    /// Seconds per reference step of the check run on `level / 2` with `n_check` unknowns
    /// over `ranks` ranks (1: in one process beside rank 0): half of its step.
    pub fn check_seconds(&self, level: usize, n_check: f64, ranks: f64) -> f64 {
        0.5 * self.step_seconds(level / 2, n_check, ranks)
    }

    /// Seconds per step the interconnect of `node` adds to a run on `level` with `n` unknowns
    /// over `ranks` ranks.
    pub fn network_seconds(&self, node: &Node, level: usize, n: f64, ranks: f64) -> f64 {
        if ranks <= 1.0 {
            return 0.0;
        }
        let k = self.iterations_at(level);
        let layer = n / level as f64;
        let halo = 2.0
            * (self.messages_per_iteration * k * node.latency
                + self.bytes_per_iteration_layer_dof * k * layer / node.bandwidth);
        let pipeline = 2.0 * k * (ranks - 1.0) * node.latency;
        let sums = self.sums_per_iteration * k * 2.0 * ranks.log2().ceil() * node.latency;
        halo + pipeline + sums
    }
}
