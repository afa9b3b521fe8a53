//! What a run or a study will cost, estimated from the problem and the options before anything
//! is allocated, and the limits it is held to: memory (the machine's available memory unless
//! `--max-memory` says otherwise), files written (`--max-files`) and work (`--max-dof-steps`).
//!
//! Every count is computed in `f64`, so that no input (a box `1e308` long, `--nx 1e9`, a horizon
//! of `1e12`) can overflow an integer here. The memory model is an upper bound measured on this
//! crate's runs (Crank–Nicolson, peak resident size):
//!
//! - a bar: [`BAR_BYTES_PER_DOF`] per unknown (measured 423–444 at NX = 10⁶ and 4·10⁶);
//! - a 2D box: `300 log₂(dofs)` bytes per unknown (the Cholesky factor's fill grows like
//!   `log n`; measured 2.4 kB at 83 200 unknowns on a 64 × 640 bar, 4.3 kB at 180 600 on a
//!   300 × 300 square, against 4.9 kB and 5.2 kB here);
//! - a 3D box: `600 dofs^⅓` bytes per unknown (fill like `n^⅓` per unknown: measured 16.4 kB at
//!   26 460 unknowns on a 20³ cube, 10 kB at 19 440 on an 8 × 8 × 80 bar, against 17.9 and
//!   16.2 kB here), plus the dense Delassus operator of the contact face; with the `cg` step
//!   solver (matrix-free, the `auto` choice from 10 000 unknowns) [`CG_BOX_FIXED_BYTES`] and
//!   [`CG_BOX_BYTES_PER_DOF`] per unknown instead (measured 0.25 kB per unknown at 1 M);
//! - every value a run stores per step or per snapshot (histories, fields), [`BYTES_PER_STORED_VALUE`]
//!   for the value and the text it becomes in `run.json` and the CSV files;
//! - a study: as many runs at once as rayon has threads, each the size of its largest run; a box
//!   study also holds its fine-mesh reference, the reference's samples and, for the projections
//!   on each fitted level, two Cholesky factors of that level's size.
//!
//! Work is counted in dof-steps (unknowns × time steps, summed over the runs; a box's contact
//! set-up counts one solve per contact node as a step).

use crate::engine::fem::MassVariant;
use crate::engine::linalg::{LinearSolver, StepSolverKind};
use crate::engine::problem::{BoxProblem, Problem1d, Settings};
use crate::engine::schemes::Scheme;
use crate::engine::solver_plan::box_step_solver;
use crate::harness::run::RunConfig;
pub use crate::harness::study::error::BudgetError;
use crate::harness::study::executor::{computed_here, Executor};

/// Peak bytes per unknown of a bar run (an upper bound of the measured 423–444).
pub const BAR_BYTES_PER_DOF: f64 = 600.0;
/// Bytes per value a run stores and writes (8 in memory, its text in JSON and CSV).
pub const BYTES_PER_STORED_VALUE: f64 = 56.0;
/// The memory every run needs whatever its size (the binary, its libraries, its threads).
pub const BASE_BYTES: f64 = 16.0 * 1024.0 * 1024.0;
/// The memory assumed available where `/proc/meminfo` cannot be read (not Linux): 4 GiB.
pub const FALLBACK_MEMORY_BYTES: u64 = 4 << 30;
/// Most files one command writes unless `--max-files` says otherwise.
pub const DEFAULT_MAX_FILES: u64 = 1000;
/// Largest work one command takes on unless `--max-dof-steps` says otherwise: 10¹², about seven
/// hours of a bar run at the measured 4·10⁷ dof-steps per second.
pub const DEFAULT_MAX_DOF_STEPS: f64 = 1e12;

/// The limits a command is held to.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Limits {
    /// Bytes of memory.
    pub memory_bytes: f64,
    /// Where the memory limit comes from (`--max-memory`, or the machine's available memory).
    pub memory_source: &'static str,
    /// Files written.
    pub files: f64,
    /// Dof-steps of work.
    pub dof_steps: f64,
}

impl Limits {
    /// The limits given, the defaults for the others: the machine's available memory
    /// ([`available_memory`]), [`DEFAULT_MAX_FILES`], [`DEFAULT_MAX_DOF_STEPS`].
    pub fn or_defaults(memory: Option<u64>, files: Option<u64>, dof_steps: Option<f64>) -> Self {
        Self {
            memory_bytes: memory.unwrap_or_else(available_memory) as f64,
            memory_source: if memory.is_some() {
                "--max-memory"
            } else {
                "the machine's available memory"
            },
            files: files.unwrap_or(DEFAULT_MAX_FILES) as f64,
            dof_steps: dof_steps.unwrap_or(DEFAULT_MAX_DOF_STEPS),
        }
    }
}

/// The memory available to a new process: `MemAvailable` of `/proc/meminfo`, or
/// [`FALLBACK_MEMORY_BYTES`] where that cannot be read.
pub fn available_memory() -> u64 {
    std::fs::read_to_string("/proc/meminfo")
        .ok()
        .and_then(|text| {
            text.lines()
                .find_map(|line| line.strip_prefix("MemAvailable:"))
                .and_then(|rest| rest.trim().strip_suffix("kB"))
                .and_then(|kb| kb.trim().parse::<u64>().ok())
        })
        .map_or(FALLBACK_MEMORY_BYTES, |kb| kb.saturating_mul(1024))
}

/// This process's peak resident memory so far: `VmHWM` of `/proc/self/status`, `None` where
/// that cannot be read.
pub fn peak_resident_bytes() -> Option<u64> {
    std::fs::read_to_string("/proc/self/status")
        .ok()?
        .lines()
        .find_map(|line| line.strip_prefix("VmHWM:"))
        .and_then(|rest| rest.trim().strip_suffix("kB"))
        .and_then(|kb| kb.trim().parse::<u64>().ok())
        .map(|kb| kb.saturating_mul(1024))
}

/// What a run or a study is estimated to cost.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Estimate {
    /// Peak bytes of memory.
    pub memory_bytes: f64,
    /// Files written.
    pub files: f64,
    /// Dof-steps of work.
    pub dof_steps: f64,
}

/// `bytes` for a person: `3.2 GiB`.
pub fn human_bytes(bytes: f64) -> String {
    const UNITS: [&str; 6] = ["B", "KiB", "MiB", "GiB", "TiB", "PiB"];
    let mut value = bytes;
    let mut unit = 0;
    while value >= 1024.0 && unit + 1 < UNITS.len() {
        value /= 1024.0;
        unit += 1;
    }
    match UNITS.get(unit) {
        Some(name) if value < 1e6 => format!("{value:.1} {name}"),
        _ => format!("{bytes:.3e} B"),
    }
}

impl Estimate {
    /// Running `self`, then `next`: the larger memory, the files and the work of both.
    pub fn then(self, next: Estimate) -> Estimate {
        Estimate {
            memory_bytes: self.memory_bytes.max(next.memory_bytes),
            files: self.files + next.files,
            dof_steps: self.dof_steps + next.dof_steps,
        }
    }

    /// The same estimate with `files` files written.
    pub fn writing(self, files: f64) -> Estimate {
        Estimate { files, ..self }
    }
}

/// The size of each regular file of `paths` (0 for anything else, which its reader refuses):
/// what a command that reads them all is estimated from before it reads any.
pub fn file_sizes(paths: &[std::path::PathBuf]) -> Vec<f64> {
    paths
        .iter()
        .map(|p| {
            std::fs::metadata(p)
                .ok()
                .filter(std::fs::Metadata::is_file)
                .map_or(0.0, |m| m.len() as f64)
        })
        .collect()
}

/// Reading input files of `bytes` bytes in all, each kept in memory at up to `per_byte` bytes
/// per byte of file (its reader's stated bound), one unit of work per byte.
pub fn reading(bytes: f64, per_byte: f64) -> Estimate {
    Estimate {
        memory_bytes: BASE_BYTES + per_byte * bytes,
        files: 0.0,
        dof_steps: bytes,
    }
}

/// `count` bar runs of `problem` on `nx` elements with `Δx/Δt = ratio` (norms only), run as
/// one job list with the others of `runs` ([`study_of`]).
pub fn bar_runs<'p>(runs: impl Iterator<Item = (&'p Problem1d, usize, f64, f64)>) -> Estimate {
    study_of(runs.map(|(problem, nx, ratio, count)| {
        (bar_run(problem, &norms_only(nx, ratio), false), count)
    }))
}

/// A bar run of `dofs` unknowns and `steps` steps keeping `stored_per_step` values of history
/// per step (GetFEM's demo runs, reproduced with their histories).
pub fn bar_run_with_histories(dofs: f64, steps: f64, stored_per_step: f64) -> Estimate {
    Estimate {
        memory_bytes: BASE_BYTES
            + BAR_BYTES_PER_DOF * dofs
            + BYTES_PER_STORED_VALUE * stored_per_step * (steps + 1.0),
        files: 0.0,
        dof_steps: dofs * steps,
    }
}

/// `estimate` at most `limit`; a NaN estimate is not.
fn within(estimate: f64, limit: f64) -> bool {
    estimate <= limit
}

impl Estimate {
    /// `Ok` when every part is within `limits`; otherwise the first part over its limit.
    pub fn check(&self, limits: &Limits) -> Result<(), BudgetError> {
        let parts = [
            (
                "memory",
                self.memory_bytes,
                limits.memory_bytes,
                "--max-memory",
                human_bytes(self.memory_bytes),
                format!(
                    "{} ({})",
                    human_bytes(limits.memory_bytes),
                    limits.memory_source
                ),
            ),
            (
                "number of files written",
                self.files,
                limits.files,
                "--max-files",
                format!("{:.0} files", self.files),
                format!("{:.0} files", limits.files),
            ),
            (
                "work",
                self.dof_steps,
                limits.dof_steps,
                "--max-dof-steps",
                format!("{:.3e} dof-steps (unknowns × time steps)", self.dof_steps),
                format!("{:.3e} dof-steps", limits.dof_steps),
            ),
        ];
        for (resource, value, bound, option, estimate, limit) in parts {
            if !within(value, bound) {
                return Err(BudgetError::OverLimit {
                    resource,
                    estimate,
                    limit,
                    option,
                });
            }
        }
        Ok(())
    }
}

/// The number of time steps of a run over `horizon` with element size `h` and `Δx/Δt = ratio`
/// ([`crate::harness::run::time_grid`] in `f64`: no cast can overflow).
pub fn steps(horizon: f64, h: f64, ratio: f64) -> f64 {
    (horizon * ratio / h - 1e-9).ceil().max(1.0)
}

/// A bar run of `config` on `problem`; `writes_files`: the run writes `run.json` and its
/// histories (`run --out`), which it then also keeps in memory.
pub fn bar_run(problem: &Problem1d, config: &RunConfig, writes_files: bool) -> Estimate {
    let nx = (config.nx as f64).max(1.0);
    let dofs = nx + 1.0;
    let steps = steps(problem.horizon, problem.length / nx, config.ratio);
    let o = &config.observables;
    let mut files = 0.0;
    let mut stored = 0.0;
    if writes_files {
        files = 1.0;
        if o.contact_history && problem.obstacle_gap.is_some() {
            stored += 6.0 * (steps + 1.0);
            files += 2.0;
        }
        if o.energy_history {
            stored += 3.0 * (steps + 1.0);
            files += 1.0;
        }
        if !o.points.is_empty() {
            stored += (1.0 + 2.0 * o.points.len() as f64) * (steps + 1.0);
            files += 1.0;
        }
        let snapshots = o.fields_at.len() as f64;
        stored += 6.0 * dofs * snapshots;
        files += 2.0 * snapshots;
    }
    Estimate {
        memory_bytes: BASE_BYTES + BAR_BYTES_PER_DOF * dofs + BYTES_PER_STORED_VALUE * stored,
        files,
        dof_steps: dofs * steps,
    }
}

/// The shape of a box mesh with `n_axis` elements along the axis, as [`crate::engine::problem::box_mesh`]
/// builds it: unknowns, contact nodes, element size along the axis.
struct BoxShape {
    dofs: f64,
    contact_nodes: f64,
    h: f64,
    nodes: f64,
}

/// The unknowns and the element size along the axis of `problem`'s mesh on `n_axis`
/// elements along it (as the estimates count them).
pub fn box_size(problem: &BoxProblem, n_axis: usize) -> (f64, f64) {
    let shape = box_shape(problem, n_axis);
    (shape.dofs, shape.h)
}

fn box_shape(problem: &BoxProblem, n_axis: usize) -> BoxShape {
    let d = problem.lengths.len().max(1);
    let n_axis = (n_axis as f64).max(1.0);
    let h = problem.lengths.last().copied().unwrap_or(1.0) / n_axis;
    let lateral: f64 = problem
        .lengths
        .iter()
        .take(d - 1)
        .map(|l| (l / h).round().max(1.0) + 1.0)
        .product();
    let nodes = lateral * (n_axis + 1.0);
    BoxShape {
        dofs: d as f64 * nodes,
        contact_nodes: lateral,
        h,
        nodes,
    }
}

/// Peak bytes per unknown of a box run whose step solver is `cg` (matrix-free, local contact
/// operator solved by CG on its slab, the mass's dofs with inertia kept matrix-free): with
/// [`CG_BOX_FIXED_BYTES`] and [`BASE_BYTES`], an upper bound of the measured peaks of the 3D
/// bar (CN `M^mod`, `run`): 55.6 MB at level 80 (19 440 unknowns), 89.5 MB at level 160
/// (138 720), 273 MB at level 320 (1.05 M), against 72, 119 and 495 MB estimated. Before the
/// slab's CG and the matrix-free start they were 66 MB, 333 MB and 1.93 GB.
const CG_BOX_BYTES_PER_DOF: f64 = 400.0;

/// The memory a `cg` box run needs beyond [`BASE_BYTES`] whatever its size (its threads' work
/// vectors, the slab's and the plane's small factors): the level-80 run's 55.6 MB are mostly
/// this.
const CG_BOX_FIXED_BYTES: f64 = 48.0 * 1024.0 * 1024.0;

/// Peak bytes of the matrices and factor of a box run of `problem` with `dofs` unknowns and
/// `contact_nodes` contact constraints: the step solver the box's solver plan resolves
/// `linear_solver` to ([`box_step_solver`], as the run's plan does) decides between the
/// matrix-free model and the Cholesky fill's.
fn box_matrix_bytes(
    problem: &BoxProblem,
    linear_solver: LinearSolver,
    dofs: f64,
    contact_nodes: f64,
) -> f64 {
    let dim = problem.lengths.len();
    let unknowns = if dofs < 1e15 {
        dofs as usize
    } else {
        usize::MAX
    };
    let matrices = match box_step_solver(linear_solver, unknowns).0 {
        StepSolverKind::Cg => CG_BOX_FIXED_BYTES + CG_BOX_BYTES_PER_DOF * dofs,
        StepSolverKind::Direct => cholesky_bytes(dim, dofs),
    };
    matrices + 3.0 * 8.0 * contact_nodes * contact_nodes
}

/// Bytes of a sparse Cholesky factor of a box matrix on `dofs` unknowns in dimension `dim`
/// (nested-dissection fill): `600 n^{4/3}` in 3D, `300 n log₂ n` in 2D, upper bounds of the
/// measured peaks of `direct` box runs, whose step matrix has every box matrix's pattern.
fn cholesky_bytes(dim: usize, dofs: f64) -> f64 {
    if dim == 3 {
        600.0 * dofs.cbrt() * dofs
    } else {
        300.0 * dofs.max(2.0).log2() * dofs
    }
}

/// A box run of `problem` solved with `settings` with `n_axis` elements along the axis and
/// `Δx/Δt = ratio`; `writes_files`: the run writes `run.json`, its CSV histories and
/// `snapshots` VTK files, with, when there are snapshots, their collection `fields.pvd` and the
/// obstacle's `obstacle.vtu` (`run --out`).
pub fn box_run(
    problem: &BoxProblem,
    settings: &Settings,
    n_axis: usize,
    ratio: f64,
    snapshots: usize,
    writes_files: bool,
) -> Estimate {
    let shape = box_shape(problem, n_axis);
    let steps = steps(problem.horizon, shape.h, ratio);
    let per_step = 2.0
        + if problem.obstacle_gap.is_some() {
            5.0
        } else {
            0.0
        };
    let snapshots = snapshots as f64;
    let paraview = if problem.obstacle_gap.is_some() {
        2.0
    } else {
        1.0
    };
    let (files, snapshot_bytes) = if writes_files && snapshots > 0.0 {
        (
            3.0 + snapshots + paraview,
            10.0 * shape.nodes * BYTES_PER_STORED_VALUE,
        )
    } else if writes_files {
        (3.0, 0.0)
    } else {
        (0.0, 0.0)
    };
    Estimate {
        memory_bytes: BASE_BYTES
            + box_matrix_bytes(
                problem,
                settings.linear_solver,
                shape.dofs,
                shape.contact_nodes,
            )
            + BYTES_PER_STORED_VALUE * per_step * (steps + 1.0)
            + snapshot_bytes,
        files,
        dof_steps: shape.dofs * (steps + shape.contact_nodes),
    }
}

/// Peak bytes of a rank other than 0 of a distributed reference per unknown of the whole box:
/// the operators' node classes (the mesh, the model and the start are not built whole there).
/// With [`RANK_BYTES_PER_SLAB_UNKNOWN`] and [`RANK_BYTES_PER_RANK`], an upper bound of the
/// measured peaks of ranks 1 to 3 of the 3D bar's references on 80 and 160 elements over 2, 3
/// and 4 ranks (`make cluster-plan`, reports/cluster/cluster-plan.md: 24–56 MiB, fitted
/// 25 bytes per unknown, 494 per slab unknown and 1.0 MiB per rank).
const RANK_BYTES_PER_UNKNOWN: f64 = 40.0;

/// Peak bytes of such a rank per unknown of its slab of the reference (its parts of the state,
/// its rows of the operators, the CG's and the projections' work vectors, and its slab of the
/// check run).
const RANK_BYTES_PER_SLAB_UNKNOWN: f64 = 560.0;

/// Peak bytes of such a rank per rank of the run: the MPI library's buffers for its peers.
const RANK_BYTES_PER_RANK: f64 = 2.0 * 1024.0 * 1024.0;

/// The memory of a rank other than 0 of `problem`'s reference on `n_axis` elements along the
/// axis over `ranks` ranks (rank 0 holds what one process holds of a reference, and is held
/// to [`box_study`]'s estimate).
pub fn reference_rank(problem: &BoxProblem, n_axis: usize, ranks: usize) -> Estimate {
    let dofs = box_shape(problem, n_axis).dofs;
    let ranks = ranks.max(1) as f64;
    Estimate {
        memory_bytes: BASE_BYTES
            + RANK_BYTES_PER_UNKNOWN * dofs
            + RANK_BYTES_PER_SLAB_UNKNOWN * dofs / ranks
            + RANK_BYTES_PER_RANK * ranks,
        files: 0.0,
        dof_steps: 0.0,
    }
}

/// Runs at once in a study: rayon's threads, at most `runs`.
fn concurrent(runs: f64) -> f64 {
    (rayon::current_num_threads() as f64).min(runs).max(1.0)
}

/// How many of a study's case × level jobs each of `levels` holds that `executor` computes:
/// `cases` each for the whole study; under `--shard`, the jobs of that level in the shard's
/// share of the largest-first order ([`computed_here`]; the jobs listed case by case, as the
/// studies list them), so that a shard is held to its own work, not the study's; none under a
/// merge, which reads them.
pub fn jobs_per_level(levels: &[usize], cases: usize, executor: &Executor) -> Vec<f64> {
    let sizes: Vec<usize> = (0..cases).flat_map(|_| levels.iter().copied()).collect();
    let mut counts = vec![0.0; levels.len()];
    for k in computed_here(&sizes, executor) {
        counts[k % levels.len()] += 1.0;
    }
    counts
}

/// A study over `levels` of a bar with `jobs[l]` runs at level `l` ([`jobs_per_level`]; norms
/// only, nothing written): as many runs at once as rayon has threads, the work of every run.
pub fn bar_study(problem: &Problem1d, levels: &[usize], ratio: f64, jobs: &[f64]) -> Estimate {
    let runs = |nx: usize| bar_run(problem, &norms_only(nx, ratio), false);
    study_of(levels.iter().map(|&nx| runs(nx)).zip(jobs.iter().copied()))
}

/// A bar run on `nx` elements with `Δx/Δt = ratio` measuring norms only, as an estimate sees
/// it (its cost does not depend on the scheme and the mass).
fn norms_only(nx: usize, ratio: f64) -> RunConfig {
    RunConfig {
        nx,
        ratio,
        scheme: Scheme::CRANK_NICOLSON,
        mass: MassVariant::Standard,
        observables: Default::default(),
        settings: Settings::default(),
    }
}

/// A box study solved with `settings`: `jobs[l]` case × level jobs at level `l` of `levels` ([`jobs_per_level`]; none
/// for the reference alone, `signorini reference`), each of `runs_per_job` runs (the
/// unperturbed run and the ensemble's members), and its fine-mesh reference at `reference_level`
/// (counted as computed): the reference run, the check run one level coarser beside it, the
/// reference's projections on every level (`2 (dofs_ℓ + 1)` values per step of level ℓ) with
/// the two Cholesky factors per level they solve with (the level's `M` and `M + S`), the
/// finest level's prolongation into the reference mesh (at most `2^d` weights and indices per
/// fine unknown) and the five fine work vectors of the projections and the check.
pub fn box_study(
    problem: &BoxProblem,
    settings: &Settings,
    levels: &[usize],
    reference_level: usize,
    ratio: f64,
    jobs: &[f64],
    runs_per_job: usize,
) -> Estimate {
    let levels_estimate = study_of(
        levels
            .iter()
            .map(|&nx| box_run(problem, settings, nx, ratio, 0, false))
            .zip(jobs.iter().map(|&j| j * runs_per_job as f64)),
    );
    let reference = box_run(problem, settings, reference_level, ratio, 0, false);
    let check = box_run(problem, settings, reference_level / 2, ratio, 0, false);
    let fine = box_shape(problem, reference_level);
    let projections: f64 = levels
        .iter()
        .map(|&nx| {
            let level = box_shape(problem, nx);
            16.0 * (level.dofs + 1.0) * (steps(problem.horizon, level.h, ratio) + 1.0)
                + 2.0 * cholesky_bytes(problem.lengths.len(), level.dofs)
        })
        .sum();
    let corners = f64::from(1u32 << problem.lengths.len().min(3));
    Estimate {
        memory_bytes: levels_estimate.memory_bytes
            + reference.memory_bytes
            + check.memory_bytes
            + projections
            + (16.0 * corners + 40.0) * fine.dofs,
        files: 0.0,
        dof_steps: levels_estimate.dof_steps + reference.dof_steps + check.dof_steps,
    }
}

/// Runs at each level, given as (one run's estimate, how many): memory for as many at once as
/// rayon has threads (each the size of the largest that runs; none for no run), the work of all.
fn study_of(levels: impl Iterator<Item = (Estimate, f64)>) -> Estimate {
    let mut largest = 0.0_f64;
    let mut work = 0.0;
    let mut count = 0.0;
    for (e, runs) in levels.filter(|&(_, runs)| runs > 0.0) {
        largest = largest.max(e.memory_bytes);
        work += runs * e.dof_steps;
        count += runs;
    }
    Estimate {
        memory_bytes: if count > 0.0 {
            concurrent(count) * largest
        } else {
            0.0
        },
        files: 0.0,
        dof_steps: work,
    }
}

/// Bytes: an integer with an optional suffix K, M, G or T (powers of 1024).
pub fn parse_bytes(s: &str) -> Result<u64, String> {
    let t = s.trim();
    let (digits, shift) = match t.char_indices().last() {
        Some((i, c)) if c.eq_ignore_ascii_case(&'k') => (&t[..i], 10),
        Some((i, c)) if c.eq_ignore_ascii_case(&'m') => (&t[..i], 20),
        Some((i, c)) if c.eq_ignore_ascii_case(&'g') => (&t[..i], 30),
        Some((i, c)) if c.eq_ignore_ascii_case(&'t') => (&t[..i], 40),
        _ => (t, 0),
    };
    digits
        .trim()
        .parse::<u64>()
        .ok()
        .and_then(|n| n.checked_mul(1_u64 << shift))
        .ok_or_else(|| {
            format!("{s:?}: allowed: a number of bytes, optionally with K, M, G or T (e.g. 512M)")
        })
}

/// Dof-steps: a finite number > 0.
pub fn parse_dof_steps(s: &str) -> Result<f64, String> {
    s.trim()
        .parse::<f64>()
        .ok()
        .filter(|v| v.is_finite() && *v > 0.0)
        .ok_or_else(|| format!("{s:?}: allowed: a finite number of dof-steps > 0 (e.g. 1e9)"))
}
