//! The local Delassus operator: `W` and the contact correction from a slab of dofs around the
//! contact face instead of one full solve per constraint (issue 19, item 2).
//!
//! At `Δx/Δt` fixed the step matrix `K = M/(bΔt²) + S` is mass-dominated and `K⁻¹f_j` decays
//! exponentially with the graph distance from the dofs of `f_j`. The slab `Ω_L` is the set of
//! dofs within `L` layers of the dofs the constraint rows touch (breadth-first search on the
//! sparsity graph of `K`), `E` the extension by zero from `Ω_L` and `K_L = EᵀKE` the principal
//! submatrix (zero displacement beyond the slab's cut). Then
//! ```text
//! W_ij = m_iᵀ E K_L⁻¹ Eᵀ f_j + ε_i δ_ij,      u ← u + E K_L⁻¹ Eᵀ Σ_j μ_j f_j,
//! ```
//! that is `n_c` slab solves for `W` and one per contact step for the correction, with no
//! column stored. When `Ω_L` holds every dof reachable from the constraints (the others are
//! decoupled: `K⁻¹f_j` vanishes there) this is the full operator.
//!
//! **The slab's solver** ([`SlabSolve`]). Below [`CG_SLAB_FROM_DOFS`] slab unknowns `K_L` is
//! factorised once (sparse Cholesky) and `W`'s columns are triangular solve pairs. From there
//! on the slab, which on a box is the box cut after its first `L + 1` node layers, is solved by
//! matrix-free CG with its own preconditioner ([`SymmetricMatrix::first_layers`]): the factor's
//! fill grows much faster than the slab. Measured (3D, CN `M^mod`, `L = 21`): level 160
//! (19 074 slab unknowns) set-up 2.4 → 1.6 s and contact steps 3.1 → 1.3 s; level 320
//! (71 874) set-up 29 → 20 s and contact steps 41 → 26 s (while other work shared the cores),
//! peak 1.93 → 1.44 GB; at level 640 (279 k) the factor had taken over 11 minutes and 11 GiB
//! without finishing. At level 80 (5 346) the factor is quicker (contact steps 0.11 against
//! 0.17 s). The two agree to 1e-13 of each history's scale.
//!
//! **The number of layers.** From [`INITIAL_LAYERS`], `L` grows until the largest entry on the
//! outermost layer (`dist = L`) of each representative column `K_L⁻¹f_j` (the first, middle and
//! last constraints) is at most [`TRUNCATION_TOLERANCE`] times that column's largest entry, or
//! the slab is the whole reachable system. The columns decay geometrically with the distance
//! (about 0.2 per layer at `Δx/Δt = 2`), so each slab that falls short predicts the next `L`
//! from its own ratio ([`next_layers`]). The ratio reached and `L` are kept ([`Truncation`]).
//!
//! **The selection rule** ([`ContactOperator`], resolved into a [`DelassusKind`] by the model's
//! solver plan, [`crate::engine::solver_plan`]): `auto` takes the local operator when the step
//! solver is iterative (it keeps the step matrix, [`crate::engine::linalg::StepSolver::matrix`];
//! the full operator would cost `n_c` CG solves and `n_c · n` stored values) and the full
//! operator with the direct solver (one factor, `n_c` triangular solve pairs).

use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use super::law::{sparse_dot, ConstraintRow, SparseVector};
use crate::engine::error::SolveError;
use crate::engine::fem::SymmetricMatrix;
use crate::engine::linalg::{Pcg, PcgWork, SpdSolver, DEFAULT_TOLERANCE};

/// Columns of `W` solved together (one pass over the slab's factor per block).
const BLOCK: usize = 32;

/// The slab's first number of layers.
pub const INITIAL_LAYERS: usize = 4;

/// The largest ratio of a representative column's outermost-layer entry to its largest entry
/// at which the slab stops growing.
pub const TRUNCATION_TOLERANCE: f64 = 1e-14;

/// The factor on the predicted number of layers ([`next_layers`]): the outermost layer of a
/// slab is depressed by the zero displacement beyond its cut, so a small slab's ratio
/// overstates the decay.
const LAYER_MARGIN: f64 = 1.1;

/// The number of layers after a slab of `l` layers whose truncation ratio `ratio` exceeds
/// [`TRUNCATION_TOLERANCE`]: with a geometric decay `ratio = ρ^l`, the tolerance is reached at
/// `L = l ln(tol) / ln(ratio)`, taken with [`LAYER_MARGIN`], at least `l + 1` and at most
/// `8 l` (doubling when the ratio shows no decay).
fn next_layers(l: usize, ratio: f64) -> usize {
    let l = l.max(1);
    if !(ratio > 0.0 && ratio < 1.0) {
        return 2 * l;
    }
    let predicted = LAYER_MARGIN * l as f64 * TRUNCATION_TOLERANCE.ln() / ratio.ln();
    (predicted.ceil() as usize).clamp(l + 1, 8 * l)
}

/// Which Delassus operator a contact step uses (see the module documentation).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum ContactOperator {
    /// One solve of the step matrix per constraint, every column stored
    /// ([`super::Delassus`]).
    Full,
    /// The slab operator with `L` chosen adaptively; needs the step matrix (the iterative step
    /// solver).
    Local,
    /// The slab operator with exactly this many layers, unchecked (to study the truncation).
    LocalLayers(usize),
    /// `Local` with an iterative step solver, `Full` with the direct one.
    #[default]
    Auto,
}

/// The slab a local operator was built on.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Truncation {
    /// `L`: the slab's number of graph layers around the constrained dofs.
    pub layers: usize,
    /// The largest ratio, over the representative columns, of the column's largest entry on the
    /// outermost layer to its largest entry.
    pub ratio: f64,
    /// The number of dofs in the slab.
    pub slab_dofs: usize,
    /// Whether the slab holds every dof reachable from the constraints (the operator is then
    /// the full one).
    pub whole: bool,
}

/// `W` and the correction on the slab `Ω_L` (see the module documentation).
#[derive(Debug)]
pub struct LocalDelassus {
    dofs: Vec<usize>,
    forces: Vec<SparseVector>,
    solver: SlabSolver,
    matrix: Vec<f64>,
    work: Vec<f64>,
    truncation: Truncation,
}

/// The graph distance of every dof from the dofs `rows` touch (`usize::MAX` when unreachable).
fn distances(k: &SymmetricMatrix, rows: &[ConstraintRow]) -> Vec<usize> {
    let mut dist = vec![usize::MAX; k.dim()];
    let mut front: Vec<usize> = Vec::new();
    for row in rows {
        for &(i, _) in row.measure.iter().chain(&row.force) {
            if dist[i] == usize::MAX {
                dist[i] = 0;
                front.push(i);
            }
        }
    }
    let mut layer = 0;
    while !front.is_empty() {
        layer += 1;
        let mut next = Vec::new();
        for &i in &front {
            k.for_each_in_row(i, |j, _| {
                if dist[j] == usize::MAX {
                    dist[j] = layer;
                    next.push(j);
                }
            });
        }
        front = next;
    }
    dist
}

/// `v` in the slab's numbering (`local[i]` is the slab index of dof `i`).
fn to_slab(v: &[(usize, f64)], local: &[usize]) -> SparseVector {
    v.iter().map(|&(i, c)| (local[i], c)).collect()
}

/// The slab unknowns from which `K_L` is solved by CG rather than factorised
/// ([`SlabSolver`]).
pub const CG_SLAB_FROM_DOFS: usize = 10_000;

/// What the slab's matrix is called in error messages.
const SLAB: &str = "contact slab (local Delassus operator)";

/// Which solver a local operator's slab takes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SlabSolve {
    /// CG from [`CG_SLAB_FROM_DOFS`] slab unknowns on, the factor below.
    Auto,
    /// The sparse Cholesky factor of `K_L`.
    Factor,
    /// CG on the cut box, wherever the slab is one ([`SymmetricMatrix::first_layers`]; the
    /// factor otherwise).
    Cg,
}

/// How the slab's systems `K_L x = b` are solved.
#[derive(Debug)]
enum SlabSolver {
    /// `K_L` factorised (sparse Cholesky): `W`'s columns in blocks, one pass over the factor
    /// per block.
    Factor(SpdSolver),
    /// Matrix-free CG on the cut box ([`SymmetricMatrix::first_layers`], with its own product
    /// or condensed-plane preconditioner) from [`CG_SLAB_FROM_DOFS`] unknowns, where the
    /// factor's fill outgrows the slab: at 3D level 640 (279 k slab unknowns) the factor took
    /// over 11 GiB and 11 minutes. Each column to the step solver's relative residual
    /// [`DEFAULT_TOLERANCE`], from a zero guess.
    Cg(Box<Pcg>),
}

impl SlabSolver {
    /// The solver of `K_L` on `dofs`, the dofs within `l` layers of the constraints, as
    /// `choice` asks: CG needs them to be the first `l + 1` node layers of a stencil (a prefix
    /// of its numbering); the factor is taken otherwise.
    fn of(
        k: &SymmetricMatrix,
        dofs: &[usize],
        l: usize,
        choice: SlabSolve,
    ) -> Result<Self, SolveError> {
        let prefix = dofs.last().is_some_and(|&last| last + 1 == dofs.len());
        let wanted = match choice {
            SlabSolve::Auto => dofs.len() >= CG_SLAB_FROM_DOFS,
            SlabSolve::Factor => false,
            SlabSolve::Cg => true,
        };
        let cut = (wanted && prefix)
            .then(|| k.first_layers(l + 1))
            .flatten()
            .filter(|cut| cut.dim() == dofs.len());
        match cut {
            Some(cut) => Ok(SlabSolver::Cg(Box::new(Pcg::new(
                cut,
                DEFAULT_TOLERANCE,
                SLAB,
            )?))),
            None => SpdSolver::factor(&k.principal_submatrix(dofs), SLAB).map(SlabSolver::Factor),
        }
    }

    /// Solves `K_L X = B` in place for the columns of `B`, each `ns` long, one after the other.
    fn solve_columns(&self, b: &mut [f64], ns: usize) -> Result<(), SolveError> {
        match self {
            SlabSolver::Factor(f) => {
                f.solve_columns_in_place(b, ns);
                Ok(())
            }
            SlabSolver::Cg(pcg) => {
                let (mut work, mut rhs) = (PcgWork::new(ns), vec![0.0; ns]);
                for column in b.chunks_exact_mut(ns) {
                    rhs.copy_from_slice(column);
                    column.fill(0.0);
                    pcg.solve(&rhs, column, &mut work)?;
                }
                Ok(())
            }
        }
    }
}

/// The dofs within `l` layers, `K_L`'s solver and the rows in the slab's numbering.
struct Slab {
    dofs: Vec<usize>,
    forces: Vec<SparseVector>,
    measures: Vec<SparseVector>,
    solver: SlabSolver,
    truncation: Truncation,
}

impl Slab {
    /// The slab of the `l` layers of `dist`, with the truncation of its representative columns
    /// (the first, middle and last constraints).
    fn new(
        k: &SymmetricMatrix,
        rows: &[ConstraintRow],
        dist: &[usize],
        l: usize,
        choice: SlabSolve,
    ) -> Result<Self, SolveError> {
        let dofs: Vec<usize> = (0..k.dim()).filter(|&i| dist[i] <= l).collect();
        let mut local = vec![usize::MAX; k.dim()];
        for (s, &i) in dofs.iter().enumerate() {
            local[i] = s;
        }
        let solver = SlabSolver::of(k, &dofs, l, choice)?;
        let mut slab = Self {
            truncation: Truncation {
                layers: l,
                ratio: 0.0,
                slab_dofs: dofs.len(),
                whole: dist.iter().all(|&d| d <= l || d == usize::MAX),
            },
            forces: rows.iter().map(|r| to_slab(&r.force, &local)).collect(),
            measures: rows.iter().map(|r| to_slab(&r.measure, &local)).collect(),
            dofs,
            solver,
        };
        let outer: Vec<usize> = (0..slab.dofs.len())
            .filter(|&s| dist[slab.dofs[s]] == l)
            .collect();
        let nc = rows.len();
        let mut representative = vec![0, nc / 2, nc.saturating_sub(1)];
        representative.dedup();
        let mut x = vec![0.0; slab.dofs.len()];
        for j in representative.into_iter().filter(|&j| j < nc) {
            slab.solve(j, &mut x)?;
            let largest = x.iter().fold(0.0_f64, |a, v| a.max(v.abs()));
            let edge = outer.iter().fold(0.0_f64, |a, &s| a.max(x[s].abs()));
            slab.truncation.ratio = slab.truncation.ratio.max(edge / largest);
        }
        Ok(slab)
    }

    /// `x = K_L⁻¹ Eᵀ f_j`.
    fn solve(&self, j: usize, x: &mut [f64]) -> Result<(), SolveError> {
        x.fill(0.0);
        for &(s, c) in &self.forces[j] {
            x[s] += c;
        }
        let ns = x.len();
        self.solver.solve_columns(x, ns)
    }

    /// Whether the truncation is within [`TRUNCATION_TOLERANCE`] (or there is none).
    fn accepted(&self) -> bool {
        self.truncation.whole || self.truncation.ratio <= TRUNCATION_TOLERANCE
    }
}

impl LocalDelassus {
    /// The local operator of the step matrix `k` for `rows`, with `layers` graph layers or,
    /// when `None`, the adaptive number (see the module documentation), its slab solved as
    /// [`SlabSolve::Auto`] decides. Fails when a slab's matrix is not positive definite.
    pub fn new(
        k: &SymmetricMatrix,
        rows: &[ConstraintRow],
        layers: Option<usize>,
    ) -> Result<Self, SolveError> {
        Self::with_slab_solve(k, rows, layers, SlabSolve::Auto)
    }

    /// [`LocalDelassus::new`] with the slab's solver `choice`.
    pub fn with_slab_solve(
        k: &SymmetricMatrix,
        rows: &[ConstraintRow],
        layers: Option<usize>,
        choice: SlabSolve,
    ) -> Result<Self, SolveError> {
        let dist = distances(k, rows);
        let deepest = dist
            .iter()
            .copied()
            .filter(|&d| d != usize::MAX)
            .max()
            .unwrap_or(0);
        let mut l = layers.unwrap_or(INITIAL_LAYERS).min(deepest);
        let mut slab = Slab::new(k, rows, &dist, l, choice)?;
        while layers.is_none() && !slab.accepted() {
            l = next_layers(l, slab.truncation.ratio).min(deepest);
            slab = Slab::new(k, rows, &dist, l, choice)?;
        }
        Self::on(slab, rows)
    }

    /// `W_ij = m_iᵀ E K_L⁻¹ Eᵀ f_j + ε_i δ_ij`: slab solves in blocks of [`BLOCK`] columns, the
    /// blocks in parallel.
    fn on(slab: Slab, rows: &[ConstraintRow]) -> Result<Self, SolveError> {
        let nc = rows.len();
        let ns = slab.dofs.len().max(1);
        let constraints: Vec<usize> = (0..nc).collect();
        let columns: Vec<Vec<f64>> = constraints
            .par_chunks(BLOCK)
            .map(|block| {
                let mut x = vec![0.0; ns * block.len()];
                for (column, &j) in x.chunks_exact_mut(ns).zip(block) {
                    for &(s, c) in &slab.forces[j] {
                        column[s] += c;
                    }
                }
                slab.solver.solve_columns(&mut x, ns)?;
                Ok(x.chunks_exact(ns)
                    .map(|column| {
                        slab.measures
                            .iter()
                            .map(|m| sparse_dot(m, column))
                            .collect()
                    })
                    .collect::<Vec<Vec<f64>>>())
            })
            .collect::<Result<Vec<_>, SolveError>>()?
            .into_iter()
            .flatten()
            .collect();
        let mut matrix = vec![0.0; nc * nc];
        for (j, column) in columns.into_iter().enumerate() {
            for (i, wij) in column.into_iter().enumerate() {
                matrix[i * nc + j] = wij;
            }
        }
        for (i, row) in rows.iter().enumerate() {
            matrix[i * nc + i] += row.compliance;
        }
        Ok(Self {
            work: vec![0.0; slab.dofs.len()],
            truncation: slab.truncation,
            dofs: slab.dofs,
            forces: slab.forces,
            solver: slab.solver,
            matrix,
        })
    }

    /// `W` row-major.
    pub fn matrix(&self) -> &[f64] {
        &self.matrix
    }

    /// The slab this operator was built on.
    pub fn truncation(&self) -> Truncation {
        self.truncation
    }

    /// `u += E K_L⁻¹ Eᵀ Σ_j μ_j f_j`: one slab solve (a solve pair with the factor, or CG).
    pub fn apply_correction(&mut self, mu: &[f64], u: &mut [f64]) -> Result<(), SolveError> {
        self.work.fill(0.0);
        for (f, &m) in self.forces.iter().zip(mu) {
            for &(s, c) in f {
                self.work[s] += m * c;
            }
        }
        let ns = self.work.len();
        self.solver.solve_columns(&mut self.work, ns)?;
        for (&i, &x) in self.dofs.iter().zip(&self.work) {
            u[i] += x;
        }
        Ok(())
    }
}

/// The Delassus operator a run's plan resolved its [`ContactOperator`] to: `auto` is no longer
/// one.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DelassusKind {
    /// One solve of the step matrix per constraint ([`super::Delassus`]).
    Full,
    /// The slab operator ([`LocalDelassus`]) with this many layers, or, when `None`, the
    /// adaptive number.
    Local {
        /// The fixed number of layers, `None` when adaptive.
        layers: Option<usize>,
    },
}

impl DelassusKind {
    /// The fixed number of layers of a local operator, `None` when adaptive or full.
    pub fn layers(self) -> Option<usize> {
        match self {
            DelassusKind::Local { layers } => layers,
            DelassusKind::Full => None,
        }
    }

    /// The name of the operator (`full` or `local`).
    pub fn name(self) -> &'static str {
        match self {
            DelassusKind::Full => "full",
            DelassusKind::Local { .. } => "local",
        }
    }
}
