//! The Delassus operator `W = B K⁻¹ Bᵀ` of a factorised system, shifted by the compliance of a
//! regularised treatment (`W_ij = m_iᵀK⁻¹f_j + ε_i δ_ij`, see [`super::law`]), and the contact
//! correction of one step, with the full operator ([`Delassus`]) or the local one
//! ([`LocalDelassus`]) as the model's solver plan resolved it ([`DelassusKind`]).

use super::law::{sparse_dot, ConstraintRow};
use super::local::{DelassusKind, LocalDelassus, Truncation};
use super::{default_solver, ContactSolver, ContactStatus};
use crate::engine::contact::ContactSet;
use crate::engine::error::SolveError;
use crate::engine::fem::SymmetricMatrix;
use crate::engine::linalg::StepSolver;

/// `K⁻¹f_j` (one column per constraint) and `W_ij = m_iᵀK⁻¹f_j + ε_i δ_ij` (row-major); for the
/// multiplier `W = B K⁻¹ Bᵀ`.
#[derive(Debug, Clone)]
pub struct Delassus {
    columns: Vec<Vec<f64>>,
    matrix: Vec<f64>,
}

impl Delassus {
    /// Computes `K⁻¹ f_j` for every constraint (one solve each, [`StepSolver::solve_columns`])
    /// and `W`.
    pub fn new(
        system: &StepSolver,
        n_dofs: usize,
        rows: &[ConstraintRow],
    ) -> Result<Self, SolveError> {
        let mut columns: Vec<Vec<f64>> = rows
            .iter()
            .map(|row| {
                let mut col = vec![0.0; n_dofs];
                for &(k, c) in &row.force {
                    col[k] = c;
                }
                col
            })
            .collect();
        system.solve_columns(&mut columns)?;
        let nc = columns.len();
        let mut matrix = vec![0.0; nc * nc];
        for (i, row) in rows.iter().enumerate() {
            for (j, col) in columns.iter().enumerate() {
                matrix[i * nc + j] = sparse_dot(&row.measure, col);
            }
            if row.compliance != 0.0 {
                matrix[i * nc + i] += row.compliance;
            }
        }
        Ok(Self { columns, matrix })
    }

    /// `W` row-major.
    pub fn matrix(&self) -> &[f64] {
        &self.matrix
    }

    /// `u += K⁻¹Bᵀ μ`.
    pub fn apply_correction(&self, mu: &[f64], u: &mut [f64]) {
        for (col, &m) in self.columns.iter().zip(mu) {
            if m != 0.0 {
                u.iter_mut().zip(col).for_each(|(ui, ci)| *ui += m * ci);
            }
        }
    }
}

/// The operator a contact step was prepared with.
#[derive(Debug)]
enum Operator {
    Full(Delassus),
    Local(LocalDelassus),
}

impl Operator {
    fn matrix(&self) -> &[f64] {
        match self {
            Operator::Full(d) => d.matrix(),
            Operator::Local(d) => d.matrix(),
        }
    }

    fn apply_correction(&mut self, mu: &[f64], u: &mut [f64]) -> Result<(), SolveError> {
        match self {
            Operator::Full(d) => {
                d.apply_correction(mu, u);
                Ok(())
            }
            Operator::Local(d) => d.apply_correction(mu, u),
        }
    }
}

/// Everything one scheme needs to impose the contact condition at each step.
#[derive(Debug)]
pub struct ContactStep {
    set: ContactSet,
    rows: Vec<ConstraintRow>,
    delassus: Operator,
    solver: Box<dyn ContactSolver>,
    free_gaps: Vec<f64>,
    mu: Vec<f64>,
    solves: usize,
    seconds: f64,
    max_violation: f64,
}

impl ContactStep {
    /// Prepares the contact correction of the constraints `rows` of `set` for the step matrix
    /// of `system` with the operator `kind`: the local one needs the step matrix, which the
    /// iterative solver keeps; a matrix solved directly for its form (bandwidth one or less,
    /// [`StepSolver::new`]) takes the full operator, one triangular solve pair per constraint.
    /// Fails when a diagonal entry of the (shifted) Delassus operator is not positive: the
    /// step's complementarity problem would not be well posed.
    pub fn new(
        set: &ContactSet,
        rows: &[ConstraintRow],
        system: &StepSolver,
        n_dofs: usize,
        kind: DelassusKind,
    ) -> Result<Self, SolveError> {
        let delassus = match (kind, system.matrix()) {
            (DelassusKind::Local { layers }, Some(k)) => {
                Operator::Local(LocalDelassus::new(k, rows, layers)?)
            }
            _ => Operator::Full(Delassus::new(system, n_dofs, rows)?),
        };
        Self::with_operator(set, rows, delassus)
    }

    /// [`ContactStep::new`] with the local operator of the step matrix `k`
    /// ([`LocalDelassus`]; `layers` fixed, or chosen by its truncation when `None`), without a
    /// step solver: what the rank holding `Γ_Sig` builds in a distributed run, whose step
    /// solve is shared by every rank.
    pub fn local(
        set: &ContactSet,
        rows: &[ConstraintRow],
        k: &SymmetricMatrix,
        layers: Option<usize>,
    ) -> Result<Self, SolveError> {
        let delassus = Operator::Local(LocalDelassus::new(k, rows, layers)?);
        Self::with_operator(set, rows, delassus)
    }

    /// The contact step of `rows` of `set` with the Delassus operator `delassus`, refused when
    /// one of its diagonal entries is not positive.
    fn with_operator(
        set: &ContactSet,
        rows: &[ConstraintRow],
        delassus: Operator,
    ) -> Result<Self, SolveError> {
        let n = set.len();
        let not_positive = |w: f64| w.is_nan() || w <= 0.0;
        if let Some(i) = (0..n).find(|&i| not_positive(delassus.matrix()[i * n + i])) {
            return Err(SolveError::Factorization {
                matrix: "contact (Delassus) operator",
                detail: format!(
                    "diagonal entry {i} is {:e}, not > 0",
                    delassus.matrix()[i * n + i]
                ),
            });
        }
        Ok(Self {
            delassus,
            solver: default_solver(n),
            set: set.clone(),
            rows: rows.to_vec(),
            free_gaps: vec![0.0; n],
            mu: vec![0.0; n],
            solves: 0,
            seconds: 0.0,
            max_violation: 0.0,
        })
    }

    /// Replaces the complementarity solver.
    pub fn with_solver(mut self, solver: Box<dyn ContactSolver>) -> Self {
        self.solver = solver;
        self
    }

    /// The slab of the local operator (`None` for the full one).
    pub fn truncation(&self) -> Option<Truncation> {
        match &self.delassus {
            Operator::Full(_) => None,
            Operator::Local(d) => Some(d.truncation()),
        }
    }

    /// The number of complementarity problems solved so far (steps where some constraint was
    /// violated by the free solution).
    pub fn solves(&self) -> usize {
        self.solves
    }

    /// Wall-clock seconds spent in complementarity solves and corrections.
    pub fn seconds(&self) -> f64 {
        self.seconds
    }

    /// The largest complementarity violation after a solve so far:
    /// `max(−y_i, μ_i |y_i|)` with `y_i = c_i(u) + ε_i μ_i` over constraints and steps (0 when
    /// exact).
    pub fn max_violation(&self) -> f64 {
        self.max_violation
    }

    /// Turns the unconstrained solution `u` into the constrained one, for the constraint
    /// `m_iᵀu + shift_i(gap_i) ≥ 0` (`u[d_i] + …` for the multiplier) where `shift` maps
    /// constraint `i` and its gap to the offset used this step; writes `λ = −μ ≤ 0` into
    /// `lambda`.
    pub fn enforce(
        &mut self,
        step: usize,
        u: &mut [f64],
        shift: impl Fn(usize, f64) -> f64,
        lambda: &mut [f64],
    ) -> Result<(), SolveError> {
        let mut violated = false;
        for (i, (row, &g)) in self.rows.iter().zip(&self.set.gaps).enumerate() {
            self.free_gaps[i] = sparse_dot(&row.measure, u) + shift(i, g);
            violated |= self.free_gaps[i] < 0.0;
        }
        if !violated {
            lambda.iter_mut().for_each(|l| *l = 0.0);
            return Ok(());
        }
        self.solves += 1;
        let clock = std::time::Instant::now();
        match self
            .solver
            .solve(self.delassus.matrix(), &self.free_gaps, &mut self.mu)
        {
            ContactStatus::Solved { .. } => {}
            ContactStatus::NotConverged { iterations } => {
                return Err(SolveError::ContactNotConverged { step, iterations })
            }
        }
        self.delassus.apply_correction(&self.mu, u)?;
        for (i, (row, &g)) in self.rows.iter().zip(&self.set.gaps).enumerate() {
            let gap = sparse_dot(&row.measure, u) + shift(i, g) + row.compliance * self.mu[i];
            let violation = (-gap).max(self.mu[i] * gap.abs());
            self.max_violation = self.max_violation.max(violation);
        }
        for (l, m) in lambda.iter_mut().zip(&self.mu) {
            *l = -m;
        }
        self.seconds += clock.elapsed().as_secs_f64();
        Ok(())
    }
}
