//! The energy balance of a distributed step (1D paper eqs. 33 and 35) computed on the ranks'
//! slabs ([`SlabForms`]), so that no rank needs the whole state to check it.
//!
//! Every product `c xᵀAy` of a balance is each rank's rows' part `Σ_{i ∈ slab} x_i (A y)_i`
//! (the product reading one layer of each neighbour), with its bound's weighted squares
//! `Σ r_i x_i²`, `Σ r_i y_i²` (`r` the row sums of `|A|`), each summed in rank order; the
//! contact works are rank 0's, which holds `Γ_Sig` and the multipliers, summed so that every
//! rank has them. Every rank therefore computes the same sides, which
//! [`crate::engine::schemes::energy_balance::newmark_sides`] and `theta_sides` assemble as for
//! one process. The sums differ from one process's by their order only.

use super::{Ranks, SlabOperator};
use crate::engine::contact::law::{sparse_dot, ConstraintRow};
use crate::engine::fem::sparse::{weighted_squares, WeightedForm};
use crate::engine::linalg::dot;
use crate::engine::schemes::energy_balance::{BalanceForms, Term};

/// The row sums of `|M|` and `|S|` on a slab's rows, and its contact constraints.
pub struct SlabBalanceData {
    pub(super) mass_rows: Vec<f64>,
    pub(super) stiffness_rows: Vec<f64>,
    /// The contact constraints (rank 0's; none elsewhere).
    pub(super) contact: Vec<ConstraintRow>,
}

impl SlabBalanceData {
    /// The row sums of `mass` and `stiffness` on this rank's rows, with its `contact` rows.
    pub fn new<R: Ranks + ?Sized>(
        mass: &SlabOperator<'_, R>,
        stiffness: &SlabOperator<'_, R>,
        contact: Vec<ConstraintRow>,
    ) -> Self {
        Self {
            mass_rows: mass.rows().abs_row_sums(),
            stiffness_rows: stiffness.rows().abs_row_sums(),
            contact,
        }
    }
}

/// A slab's [`BalanceForms`], summed over the ranks (every rank together).
pub struct SlabForms<'a, 'r, R: Ranks + ?Sized> {
    pub(super) ranks: &'r R,
    pub(super) mass: &'a SlabOperator<'r, R>,
    pub(super) stiffness: &'a SlabOperator<'r, R>,
    pub(super) data: &'a SlabBalanceData,
    /// `A y` on this rank's rows.
    pub(super) product: &'a mut Vec<f64>,
}

impl<R: Ranks + ?Sized> SlabForms<'_, '_, R> {
    /// The term `c xᵀAy` of `a` with row sums `rows`: not evaluated when `c = 0`, as one
    /// process does not (the same on every rank).
    fn term(&mut self, mass: bool, c: f64, x: &[f64], y: &[f64]) -> Term {
        if c == 0.0 {
            return Term::default();
        }
        let (a, rows) = if mass {
            (self.mass, &self.data.mass_rows)
        } else {
            (self.stiffness, &self.data.stiffness_rows)
        };
        a.mul_dot(y, self.product);
        let value = dot(x, self.product);
        let (x_squares, y_squares) = weighted_squares(rows, x, y);
        Term::of(
            c,
            WeightedForm {
                value: self.ranks.sum(value),
                x_squares: self.ranks.sum(x_squares),
                y_squares: self.ranks.sum(y_squares),
            },
        )
    }
}

impl<R: Ranks + ?Sized> BalanceForms for SlabForms<'_, '_, R> {
    fn mass(&mut self, c: f64, x: &[f64], y: &[f64]) -> Term {
        self.term(true, c, x, y)
    }

    fn stiffness(&mut self, c: f64, x: &[f64], y: &[f64]) -> Term {
        self.term(false, c, x, y)
    }

    /// Rank 0's constraints on its part `x` (it holds every contact dof), summed.
    fn contact_work(&mut self, x: &[f64], weights: &dyn Fn(usize) -> f64) -> f64 {
        let own: f64 = (self.data.contact.iter().enumerate())
            .map(|(i, row)| sparse_dot(&row.force, x) * weights(i))
            .sum();
        self.ranks.sum(own)
    }

    /// A distributed run has no load.
    fn load(&mut self, _x: &[f64]) -> (f64, f64) {
        (0.0, 0.0)
    }
}
