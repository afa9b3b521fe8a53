//! The discrete energy balances of the 1D paper, eqs. (33), (35) and (37) (§3.2, derived in its
//! Appendix), and of the rivals, (GA-E), (MJ-E) and (CSN-E) (derived in their files): how each scheme's
//! energy changes over one step. Each function takes the states
//! of a step and returns its [`StepBalance`]: the energy at both ends, its change, and the
//! change the balance predicts; the [residual](StepBalance::residual) is zero up to round-off
//! when the scheme solved its equations.
//!
//! The change is evaluated in the difference form the Appendix starts from, eq. (43):
//! `ΔE = ½ ΔVᵀM(V^{n+1} + V^n) + ½ ΔUᵀS(U^{n+1} + U^n) − FᵀΔU` (and its analogue for the
//! two-level energies), equal to `E^{n+1} − E^n` in exact arithmetic. Subtracting the two
//! energies instead loses the digits of `½UᵀSU`, a sum of terms of size `|S| |U|² ∝ 1/h²`: on
//! the Dirichlet benchmark that round-off grows six- to eightfold per mesh halving, to 10⁻⁸ of
//! the energy at NX = 1280, where the difference form leaves the scheme's own round-off
//! (10⁻¹² there, see [`BALANCE_TOLERANCE`]).
//!
//! | scheme | energy | balance |
//! |---|---|---|
//! | Newmark(β, γ), eq. (32), β = 0 included | `E^n = E_h(U^n, V^n)` | eq. (33) for every (β, γ): [`newmark`] |
//! | θ-method, eq. (34) | `E^n = E_h(U^n, V^n)` | eq. (35): [`theta`] |
//! | Paoli–Schatzman, eq. (36) | half-step `E^{n+½}` ([`HalfStep::energy`]) | eq. (37) before the complementarity substitution: [`paoli_schatzman`] |
//! | explicit Newmark(0, ½) | staggered `E^{n+½}` ([`staggered_energy`]) | the same identity for the energy it reports: [`central_difference`] |
//! | generalised-α ([`super::generalised_alpha`]) | `E^n = E_h(U^n, V^n)` | (GA-E), with the accelerations: [`generalised_alpha`] |
//! | Moreau–Jean ([`super::moreau_jean`]) | `E^n = E_h(U^n, V^n)` | (MJ-E), eq. (35) with the impulse at `t_{n+1}`: [`moreau_jean`] |
//! | contact-stabilised Newmark ([`super::contact_stabilised_newmark`]) | `E^n = E_h(U^n, V^n)` | (CSN-E), with the projected predictor: [`contact_stabilised_newmark`] |
//!
//! `E_h(U, V) = ½ VᵀMV + ½ UᵀSU − FᵀU` is eq. (31) with the load's potential written `−FᵀU`
//! (the printed `−U_tᵀF` is an erratum, see docs/src/errata.md), without the contact energy of
//! a penalty or Nitsche treatment: with those treatments the same identities hold with `Bᵀλ` replaced by
//! `Σ_i λ_i f_i`, `f_i` the force vectors of the law's constraints ([`ConstraintRow::force`];
//! `f_i = e_{c_i}` for the multiplier) and `S` the integrated (for Nitsche, modified)
//! stiffness. Below `ΔU = U^{n+1} − U^n`, `ΔV = V^{n+1} − V^n`, `Δλ = λ^{n+1} − λ^n`.
//!
//! **Newmark, eq. (33).** The Appendix's identity for every (β, γ), from (32a–c) at both
//! levels:
//! `ΔE = (½ − γ) ΔUᵀSΔU − ΔUᵀBᵀΛ_γ + Δt(β − γ/2) ΔVᵀSΔU + Δt(β − γ/2) ΔVᵀBᵀΔλ`,
//! `Λ_γ = (1 − γ)λ^n + γλ^{n+1}`. The third term's sign follows from (46); the Appendix's last
//! display prints it negative, an erratum (`tests/energy_balance.rs` shows the printed sign
//! leaves a residual far above round-off). For Crank–Nicolson, (β, γ) = (¼, ½), only the
//! second term is left: eq. (33), `ΔE = −ΔUᵀBᵀΛ_½` (the paper's `V_h^n` is `ΔU`). With β = 0
//! the identity holds for the explicit scheme too: its massless rows satisfy (32c) statically,
//! and `M` has zero rows and columns there.
//!
//! **θ-method, eq. (35)** as printed: `ΔE = (½ − θ) ΔVᵀMΔV + (½ − θ) ΔUᵀSΔU − ΔUᵀBᵀΛ_θ`,
//! `Λ_θ = (1 − θ)λ^n + θλ^{n+1}` (the paper's `V_{h,t}^n` is `ΔV`, its `V_h^n` is `ΔU`).
//!
//! **Paoli–Schatzman, eq. (37).** Multiplying eq. (36) by `½(U^{n+1} − U^{n−1})` gives, for every
//! β > 0 and with the projection `P` off `ker M`,
//! `E^{n+½} − E^{n−½} = ½ (U^{n+1} − U^{n−1})ᵀ [−Bᵀλ^n + Q((1 − 2β) R(U^n) + β R(U^{n−1}))]`,
//! `Q = I − P`, `R(U) = SU − F`. For the standard mass `Q = 0`; with the complementarity
//! `λ^n ((u^{n+1} + e u^{n−1})/(1 + e) + g) = 0` this is eq. (37),
//! `ΔE = ½ (1 + e) λ^n (u_0^{n−1} + g)` (gap `g = 0` in the paper). The function returns the
//! identity before that substitution, which holds to round-off whatever the contact solver's
//! tolerance.
//!
//! **Explicit Newmark(0, ½).** With γ = ½ the rows with and without mass together read
//! `M (U^{n+1} − 2U^n + U^{n−1}) / Δt² + S U^n = F − Bᵀλ^n`; multiplied by `U^{n+1} − U^{n−1}`,
//! `E^{n+½} − E^{n−½} = −½ λ^nᵀ B (U^{n+1} − U^{n−1})` for the staggered energy it reports.
//!
//! [`BalanceMonitor`] evaluates the balance of a running integrator after every step (used by
//! `signorini run --check-balance` and the stability suite).

use super::newmark::staggered_energy;
use super::paoli_schatzman::HalfStep;
use super::{AlphaParameters, Integration, PredictorVelocity, Scheme, SchemeState};
use crate::engine::contact::law::{sparse_dot, ConstraintRow};
use crate::engine::contact::ContactTreatment;
use crate::engine::fem::sparse::{SymmetricMatrix, WeightedForm};
use crate::engine::model::Model;
use crate::engine::schemes::conventions::{Conventions, Start};

/// The largest relative per-step residual ([`BalanceMonitor::largest_residual`]) that
/// `signorini run --check-balance` accepts. Round-off leaves about 10⁻¹⁴ on the Dirichlet
/// benchmark at NX = 20 and grows with `1/Δt²` (the schemes recover `A^{n+1}` from `U^{n+1}`
/// by dividing by `bΔt²`): 10⁻¹² at NX = 1280 and 2·10⁻¹¹ at the stability suite's extremes
/// (NX = 5000; Δx/Δt = 1000 at NX = 40). A step that misses one term of its equations leaves
/// 10⁻⁶ of the energy or more (`tests/energy_balance.rs`).
pub const BALANCE_TOLERANCE: f64 = 1e-9;

/// One step of a balance: the discrete energy at both ends, its change, and the change the
/// balance law predicts.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StepBalance {
    /// The energy at the start of the step (`E^n`, or `E^{n−½}` for the two-level energies).
    pub energy_before: f64,
    /// The energy at the end of the step (`E^{n+1}`, or `E^{n+½}`).
    pub energy_after: f64,
    /// `E_after − E_before` in the difference form of eq. (43) (see the module documentation).
    pub change: f64,
    /// The right-hand side of the balance law.
    pub predicted_change: f64,
    /// An upper bound of the absolute products the two sides sum: over every form `c xᵀAy`
    /// they hold, `|c| (Σ r_i x_i² · Σ r_i y_i²)^½` with `r_i = Σ_j |A_ij|` (which bounds
    /// `|c| |x|ᵀ|A||y|`), plus the absolute load and contact works. Round-off leaves a residual
    /// of a modest multiple of ε times it, however much the terms cancel.
    pub magnitude: f64,
}

impl StepBalance {
    /// The change minus the predicted one.
    pub fn residual(&self) -> f64 {
        self.change - self.predicted_change
    }
}

/// One time level `(U^n, V^n, λ^n)` of a one-step scheme.
#[derive(Debug, Clone, Copy)]
pub struct Level<'a> {
    /// `U^n`.
    pub displacement: &'a [f64],
    /// `V^n`.
    pub velocity: &'a [f64],
    /// `λ^n`, one per contact constraint.
    pub multiplier: &'a [f64],
}

impl<'a> Level<'a> {
    /// The level of a state (with its [`SchemeState::scheme_multiplier`]).
    pub fn of(state: &'a SchemeState) -> Self {
        Self {
            displacement: state.displacement(),
            velocity: state.velocity(),
            multiplier: state.scheme_multiplier(),
        }
    }
}

/// The displacements `U^{n−1}`, `U^n`, `U^{n+1}` of a step of a two-step form, with the multiplier
/// `λ^n` of the middle level.
#[derive(Debug, Clone, Copy)]
pub struct ThreeLevels<'a> {
    /// `U^{n−1}`.
    pub earlier: &'a [f64],
    /// `U^n`.
    pub current: &'a [f64],
    /// `U^{n+1}`.
    pub later: &'a [f64],
    /// `λ^n`, one per contact constraint.
    pub multiplier: &'a [f64],
}

/// `E_h(U, V) = ½VᵀMV + ½UᵀSU − FᵀU`, the model's energy without its contact energy.
fn mechanical_energy(model: &Model, level: &Level) -> f64 {
    model.energy(level.displacement, level.velocity) - model.contact_energy(level.displacement)
}

/// The contact constraints of `model` (none without an obstacle).
fn constraints(model: &Model) -> Vec<ConstraintRow> {
    model
        .contact()
        .map_or_else(Vec::new, |c| model.contact_law().rows(c))
}

/// `Σ_i w_i f_iᵀ x` over the constraints, `f_i` their force vectors.
fn contact_work(rows: &[ConstraintRow], x: &[f64], weights: &dyn Fn(usize) -> f64) -> f64 {
    rows.iter()
        .enumerate()
        .map(|(i, row)| sparse_dot(&row.force, x) * weights(i))
        .sum()
}

/// `Fᵀx` (0 without a load).
fn load_work(model: &Model, x: &[f64]) -> f64 {
    model
        .load()
        .map_or(0.0, |f| f.iter().zip(x).map(|(a, b)| a * b).sum())
}

/// `Σ |F_i x_i|` (0 without a load): the products `Fᵀx` sums.
fn load_magnitude(model: &Model, x: &[f64]) -> f64 {
    model
        .load()
        .map_or(0.0, |f| f.iter().zip(x).map(|(a, b)| (a * b).abs()).sum())
}

/// A term `c xᵀAy` of a balance with the bound `|c| (Σ r_i x_i² · Σ r_i y_i²)^½` of the
/// products it sums (`r` the row sums of `|A|`, see [`StepBalance::magnitude`]).
#[derive(Debug, Clone, Copy, Default)]
pub struct Term {
    /// `c xᵀAy`.
    pub value: f64,
    /// `|c| (Σ r_i x_i² · Σ r_i y_i²)^½`.
    pub bound: f64,
}

impl Term {
    /// The term `c xᵀAy` of the weighted form `f` of `x`, `y`.
    pub fn of(c: f64, f: WeightedForm) -> Self {
        Self {
            value: c * f.value,
            bound: c.abs() * (f.x_squares * f.y_squares).sqrt(),
        }
    }

    /// `c xᵀAy` ([`SymmetricMatrix::weighted_form`]), not evaluated when `c = 0` (a term the
    /// scheme's parameters cancel, e.g. every `S`-term of Crank–Nicolson's eq. 33).
    fn form(a: &SymmetricMatrix, r: &[f64], c: f64, x: &[f64], y: &[f64]) -> Self {
        if c == 0.0 {
            return Self::default();
        }
        Self::of(c, a.weighted_form(x, y, r))
    }
}

/// The row sums of `|M|` and `|S|` of a model ([`SymmetricMatrix::abs_row_sums`]), which
/// bound the products of the balances' forms ([`StepBalance::magnitude`]).
#[derive(Debug)]
struct RowSums {
    mass: Vec<f64>,
    stiffness: Vec<f64>,
}

impl RowSums {
    fn of(model: &Model) -> Self {
        Self {
            mass: model.mass().abs_row_sums(),
            stiffness: model.stiffness().abs_row_sums(),
        }
    }

    /// The term `c xᵀMy`.
    fn mass(&self, model: &Model, c: f64, x: &[f64], y: &[f64]) -> Term {
        Term::form(model.mass(), &self.mass, c, x, y)
    }

    /// The term `c xᵀSy`.
    fn stiffness(&self, model: &Model, c: f64, x: &[f64], y: &[f64]) -> Term {
        Term::form(model.stiffness(), &self.stiffness, c, x, y)
    }
}

/// The two sides of a step's balance and the magnitude of their products
/// ([`StepBalance::magnitude`]), without the energies.
#[derive(Debug, Clone, Copy)]
pub struct Sides {
    /// [`StepBalance::change`].
    pub change: f64,
    /// [`StepBalance::predicted_change`].
    pub predicted_change: f64,
    /// [`StepBalance::magnitude`].
    pub magnitude: f64,
}

impl Sides {
    /// The step's balance with the energies at its two ends.
    pub fn with_energies(self, energy_before: f64, energy_after: f64) -> StepBalance {
        StepBalance {
            energy_before,
            energy_after,
            change: self.change,
            predicted_change: self.predicted_change,
            magnitude: self.magnitude,
        }
    }
}

/// What the balances need beyond the states, kept from step to step by [`BalanceMonitor`] so
/// that a step allocates nothing: the constraint rows and row sums (constant for a model), the
/// vectors `a − b` and `a + b` of two levels, and the entries of a sparse vector.
#[derive(Debug, Default)]
struct Workspace {
    rows: Option<Vec<ConstraintRow>>,
    sums: Option<RowSums>,
    difference: [Vec<f64>; 2],
    sum: [Vec<f64>; 2],
    entries: Vec<(usize, f64)>,
    /// `ΔA` of a generalised-α step.
    acceleration_change: Vec<f64>,
    /// `P = U^pred − U^n − Δt V^n` of a contact-stabilised Newmark step.
    projection: Vec<f64>,
}

impl Workspace {
    /// The constraint rows and the row sums of `model`, built on first use.
    fn constants(&mut self, model: &Model) {
        self.rows.get_or_insert_with(|| constraints(model));
        self.sums.get_or_insert_with(|| RowSums::of(model));
    }

    /// Prepares a one-step balance of `model` from `before` to `after`: the constants, `ΔU`,
    /// `U^{n+1} + U^n` (pair 0) and `ΔV`, `V^{n+1} + V^n` (pair 1).
    fn prepare(&mut self, model: &Model, before: &Level, after: &Level) -> Prepared<'_> {
        self.constants(model);
        for (k, (a, b)) in [
            (after.displacement, before.displacement),
            (after.velocity, before.velocity),
        ]
        .into_iter()
        .enumerate()
        {
            difference_and_sum(&mut self.difference[k], &mut self.sum[k], a, b);
        }
        self.prepared()
    }

    /// The constants and the pairs as they are.
    fn prepared(&self) -> Prepared<'_> {
        Prepared {
            rows: self.rows.as_deref().unwrap_or_default(),
            sums: self.sums.as_ref().expect("Workspace::constants ran first"),
            difference: &self.difference,
            sum: &self.sum,
        }
    }
}

/// Fills `difference` with `a − b` and `sum` with `a + b`, in one pass.
fn difference_and_sum(difference: &mut Vec<f64>, sum: &mut Vec<f64>, a: &[f64], b: &[f64]) {
    let n = a.len().min(b.len());
    difference.resize(n, 0.0);
    sum.resize(n, 0.0);
    let outputs = difference.iter_mut().zip(sum.iter_mut());
    for ((d, s), (&x, &y)) in outputs.zip(a.iter().zip(b)) {
        *d = x - y;
        *s = x + y;
    }
}

/// Fills `out` with `f(a_i, b_i)`.
fn fill(out: &mut Vec<f64>, a: &[f64], b: &[f64], f: impl Fn(f64, f64) -> f64) {
    out.clear();
    out.extend(a.iter().zip(b).map(|(&x, &y)| f(x, y)));
}

/// The vector of `f(a_i, b_i)`.
fn combined(a: &[f64], b: &[f64], f: impl Fn(f64, f64) -> f64) -> Vec<f64> {
    let mut out = Vec::with_capacity(a.len());
    fill(&mut out, a, b, f);
    out
}

impl<'w> Prepared<'w> {
    /// Its pairs with the multipliers `l0`, `l1`.
    fn vectors(&self, l0: &'w [f64], l1: &'w [f64]) -> StepVectors<'w> {
        StepVectors {
            difference: [&self.difference[0], &self.difference[1]],
            sum: [&self.sum[0], &self.sum[1]],
            multipliers: (l0, l1),
        }
    }
}

/// A balance's inputs ([`Workspace::prepare`]).
struct Prepared<'w> {
    rows: &'w [ConstraintRow],
    sums: &'w RowSums,
    /// `[ΔU, ΔV]` of a one-step balance.
    difference: &'w [Vec<f64>; 2],
    /// `[U^{n+1} + U^n, V^{n+1} + V^n]` of a one-step balance.
    sum: &'w [Vec<f64>; 2],
}

/// The products a one-step balance of the Newmark or θ family sums
/// ([`newmark_sides`], [`theta_sides`]): those of a whole model ([`WholeForms`]), or of a slab
/// of it summed over the ranks of a distributed run.
pub trait BalanceForms {
    /// The term `c xᵀMy`.
    fn mass(&mut self, c: f64, x: &[f64], y: &[f64]) -> Term;
    /// The term `c xᵀSy`.
    fn stiffness(&mut self, c: f64, x: &[f64], y: &[f64]) -> Term;
    /// `Σ_i w_i f_iᵀ x` over the contact constraints, `f_i` their force vectors.
    fn contact_work(&mut self, x: &[f64], weights: &dyn Fn(usize) -> f64) -> f64;
    /// `Fᵀx` and `Σ |F_i x_i|` (both 0 without a load).
    fn load(&mut self, x: &[f64]) -> (f64, f64);
}

/// A one-step balance's vectors: `[ΔU, ΔV]`, `[U^{n+1} + U^n, V^{n+1} + V^n]` and
/// `(λ^n, λ^{n+1})`.
#[derive(Debug, Clone, Copy)]
pub struct StepVectors<'v> {
    /// `[ΔU, ΔV]`.
    pub difference: [&'v [f64]; 2],
    /// `[U^{n+1} + U^n, V^{n+1} + V^n]`.
    pub sum: [&'v [f64]; 2],
    /// `(λ^n, λ^{n+1})`.
    pub multipliers: (&'v [f64], &'v [f64]),
}

/// The forms of a whole model.
struct WholeForms<'a> {
    model: &'a Model,
    rows: &'a [ConstraintRow],
    sums: &'a RowSums,
}

impl<'a> WholeForms<'a> {
    fn of(model: &'a Model, p: &Prepared<'a>) -> Self {
        Self {
            model,
            rows: p.rows,
            sums: p.sums,
        }
    }
}

impl BalanceForms for WholeForms<'_> {
    fn mass(&mut self, c: f64, x: &[f64], y: &[f64]) -> Term {
        self.sums.mass(self.model, c, x, y)
    }

    fn stiffness(&mut self, c: f64, x: &[f64], y: &[f64]) -> Term {
        self.sums.stiffness(self.model, c, x, y)
    }

    fn contact_work(&mut self, x: &[f64], weights: &dyn Fn(usize) -> f64) -> f64 {
        contact_work(self.rows, x, weights)
    }

    fn load(&mut self, x: &[f64]) -> (f64, f64) {
        (load_work(self.model, x), load_magnitude(self.model, x))
    }
}

/// `E_h(after) − E_h(before)` in the form of eq. (43) with the load:
/// `½ ΔVᵀM(V^{n+1} + V^n) + ½ ΔUᵀS(U^{n+1} + U^n) − FᵀΔU`, and the magnitude of its products.
fn energy_change(forms: &mut dyn BalanceForms, v: &StepVectors) -> (f64, f64) {
    let ([du, dv], [u_sum, v_sum]) = (v.difference, v.sum);
    let kinetic = forms.mass(0.5, dv, v_sum);
    let elastic = forms.stiffness(0.5, du, u_sum);
    let (load, load_magnitude) = forms.load(du);
    (
        kinetic.value + elastic.value - load,
        kinetic.bound + elastic.bound + load_magnitude,
    )
}

/// [`energy_change`] of a whole model's prepared step.
fn mechanical_energy_change(model: &Model, p: &Prepared) -> (f64, f64) {
    energy_change(&mut WholeForms::of(model, p), &p.vectors(&[], &[]))
}

/// The Newmark(β, γ) balance over one step (eq. 33 for every (β, γ), see the module
/// documentation): `ΔE` against
/// `(½ − γ) ΔUᵀSΔU − ΔUᵀBᵀΛ_γ + Δt(β − γ/2) ΔVᵀSΔU + Δt(β − γ/2) ΔVᵀBᵀΔλ`.
pub fn newmark(
    model: &Model,
    beta: f64,
    gamma: f64,
    dt: f64,
    before: &Level,
    after: &Level,
) -> StepBalance {
    newmark_in(
        &mut Workspace::default(),
        model,
        (beta, gamma),
        dt,
        (before, after),
    )
    .with_energies(
        mechanical_energy(model, before),
        mechanical_energy(model, after),
    )
}

/// [`newmark`]'s sides, in `ws`.
fn newmark_in(
    ws: &mut Workspace,
    model: &Model,
    (beta, gamma): (f64, f64),
    dt: f64,
    (before, after): (&Level, &Level),
) -> Sides {
    let p = ws.prepare(model, before, after);
    let vectors = p.vectors(before.multiplier, after.multiplier);
    newmark_sides(&mut WholeForms::of(model, &p), (beta, gamma), dt, &vectors)
}

/// The two sides of eq. (33) over one step (see [`newmark`]) with the products of `forms`.
pub fn newmark_sides(
    forms: &mut dyn BalanceForms,
    (beta, gamma): (f64, f64),
    dt: f64,
    v: &StepVectors,
) -> Sides {
    let ((l0, l1), [du, dv]) = (v.multipliers, v.difference);
    let work = forms.contact_work(du, &|i| (1.0 - gamma) * l0[i] + gamma * l1[i]);
    let impulse_change = forms.contact_work(dv, &|i| l1[i] - l0[i]);
    let skew = dt * (beta - 0.5 * gamma);
    let dissipated = forms.stiffness(0.5 - gamma, du, du);
    let skewed = forms.stiffness(skew, dv, du);
    let (change, magnitude) = energy_change(forms, v);
    Sides {
        change,
        predicted_change: dissipated.value - work + skewed.value + skew * impulse_change,
        magnitude: magnitude
            + dissipated.bound
            + skewed.bound
            + work.abs()
            + (skew * impulse_change).abs(),
    }
}

/// The θ-method balance over one step, eq. (35): `ΔE` against
/// `(½ − θ) ΔVᵀMΔV + (½ − θ) ΔUᵀSΔU − ΔUᵀBᵀΛ_θ`.
pub fn theta(model: &Model, theta: f64, before: &Level, after: &Level) -> StepBalance {
    theta_in(
        &mut Workspace::default(),
        model,
        (theta, theta),
        (before, after),
    )
    .with_energies(
        mechanical_energy(model, before),
        mechanical_energy(model, after),
    )
}

/// The Moreau–Jean balance over one step, (MJ-E) of [`super::moreau_jean`]: `ΔE` against
/// `(½ − θ) ΔVᵀMΔV + (½ − θ) ΔUᵀSΔU − ΔUᵀBᵀλ^{n+1}`, eq. (35) with the step's whole impulse
/// at `t_{n+1}`.
pub fn moreau_jean(model: &Model, theta: f64, before: &Level, after: &Level) -> StepBalance {
    theta_in(
        &mut Workspace::default(),
        model,
        (theta, 1.0),
        (before, after),
    )
    .with_energies(
        mechanical_energy(model, before),
        mechanical_energy(model, after),
    )
}

/// [`theta`]'s and [`moreau_jean`]'s sides, in `ws`: `weight` is the weight `w` of `λ^{n+1}`
/// in `Λ = (1 − w) λ^n + w λ^{n+1}` (θ for eq. 35, 1 for (MJ-E)).
fn theta_in(
    ws: &mut Workspace,
    model: &Model,
    (theta, weight): (f64, f64),
    (before, after): (&Level, &Level),
) -> Sides {
    let p = ws.prepare(model, before, after);
    let vectors = p.vectors(before.multiplier, after.multiplier);
    theta_sides(&mut WholeForms::of(model, &p), (theta, weight), &vectors)
}

/// The two sides of eq. (35) over one step (see [`theta`]; `weight` as in `theta_in`) with
/// the products of `forms`.
pub fn theta_sides(
    forms: &mut dyn BalanceForms,
    (theta, weight): (f64, f64),
    v: &StepVectors,
) -> Sides {
    let ((l0, l1), [du, dv]) = (v.multipliers, v.difference);
    let work = forms.contact_work(du, &|i| (1.0 - weight) * l0[i] + weight * l1[i]);
    let kinetic = forms.mass(0.5 - theta, dv, dv);
    let elastic = forms.stiffness(0.5 - theta, du, du);
    let (change, magnitude) = energy_change(forms, v);
    Sides {
        change,
        predicted_change: kinetic.value + elastic.value - work,
        magnitude: magnitude + kinetic.bound + elastic.bound + work.abs(),
    }
}

/// The generalised-α balance over one step, (GA-E) of [`super::generalised_alpha`]: `ΔE`
/// against `−ΔUᵀBᵀΛ_f + (α_f − ½) ΔUᵀSΔU + (γ − 1 + α_m) ΔAᵀMΔU − Δt (β − γ/2) ΔAᵀMΔV`,
/// `Λ_f = (1 − α_f) λ^{n+1} + α_f λ^n`, with the accelerations `A^n`, `A^{n+1}` of the levels.
pub fn generalised_alpha(
    model: &Model,
    parameters: AlphaParameters,
    dt: f64,
    (before, after): (&Level, &Level),
    accelerations: (&[f64], &[f64]),
) -> StepBalance {
    generalised_alpha_in(
        &mut Workspace::default(),
        model,
        parameters,
        dt,
        (before, after),
        accelerations,
    )
    .with_energies(
        mechanical_energy(model, before),
        mechanical_energy(model, after),
    )
}

/// [`generalised_alpha`]'s sides, in `ws`.
fn generalised_alpha_in(
    ws: &mut Workspace,
    model: &Model,
    parameters: AlphaParameters,
    dt: f64,
    (before, after): (&Level, &Level),
    (a0, a1): (&[f64], &[f64]),
) -> Sides {
    let AlphaParameters {
        alpha_m,
        alpha_f,
        beta,
        gamma,
    } = parameters;
    let mut da = std::mem::take(&mut ws.acceleration_change);
    fill(&mut da, a1, a0, |x, y| x - y);
    let p = ws.prepare(model, before, after);
    let (l0, l1) = (before.multiplier, after.multiplier);
    let (rows, sums, [du, dv]) = (p.rows, p.sums, p.difference);
    let work = contact_work(rows, du, &|i| alpha_f * l0[i] + (1.0 - alpha_f) * l1[i]);
    let elastic = sums.stiffness(model, alpha_f - 0.5, du, du);
    let inertial = sums.mass(model, gamma - 1.0 + alpha_m, &da, du);
    let skewed = sums.mass(model, -dt * (beta - 0.5 * gamma), &da, dv);
    let (change, magnitude) = mechanical_energy_change(model, &p);
    ws.acceleration_change = da;
    Sides {
        change,
        predicted_change: -work + elastic.value + inertial.value + skewed.value,
        magnitude: magnitude + work.abs() + elastic.bound + inertial.bound + skewed.bound,
    }
}

/// The contact-stabilised Newmark balance over one step, (CSN-E) of
/// [`super::contact_stabilised_newmark`], with `P = U^pred − U^n − Δt V^n`, `U^pred` the step's
/// projected predictor: `ΔE` against `−ΔUᵀBᵀλ^{n+1} + Pᵀ(S Ū − F + Bᵀλ^{n+1})` when the corrector
/// starts from `V^n`, `−ΔUᵀBᵀλ^{n+1} + (1/Δt) PᵀM V^n + (1/(2Δt²)) PᵀM P` when it starts from
/// the predictor's velocity.
pub fn contact_stabilised_newmark(
    model: &Model,
    velocity: PredictorVelocity,
    dt: f64,
    (before, after): (&Level, &Level),
    predictor: &[f64],
) -> StepBalance {
    contact_stabilised_newmark_in(
        &mut Workspace::default(),
        model,
        (velocity, dt),
        (before, after),
        predictor,
    )
    .with_energies(
        mechanical_energy(model, before),
        mechanical_energy(model, after),
    )
}

/// [`contact_stabilised_newmark`]'s sides, in `ws`.
fn contact_stabilised_newmark_in(
    ws: &mut Workspace,
    model: &Model,
    (velocity, dt): (PredictorVelocity, f64),
    (before, after): (&Level, &Level),
    predictor: &[f64],
) -> Sides {
    let mut p = std::mem::take(&mut ws.projection);
    p.clear();
    p.extend(
        predictor
            .iter()
            .zip(before.displacement)
            .zip(before.velocity)
            .map(|((up, u), v)| (up - u) - dt * v),
    );
    let prepared = ws.prepare(model, before, after);
    let l1 = after.multiplier;
    let (rows, sums, [du, _], [u_sum, _]) = (
        prepared.rows,
        prepared.sums,
        prepared.difference,
        prepared.sum,
    );
    let work = contact_work(rows, du, &|i| l1[i]);
    let (projected, bound) = match velocity {
        PredictorVelocity::Carried => {
            let elastic = sums.stiffness(model, 0.5, &p, u_sum);
            let load = load_work(model, &p);
            let contact = contact_work(rows, &p, &|i| l1[i]);
            (
                elastic.value - load + contact,
                elastic.bound + load_magnitude(model, &p) + contact.abs(),
            )
        }
        PredictorVelocity::Projected => {
            let cross = sums.mass(model, 1.0 / dt, &p, before.velocity);
            let square = sums.mass(model, 0.5 / (dt * dt), &p, &p);
            (cross.value + square.value, cross.bound + square.bound)
        }
    };
    let (change, magnitude) = mechanical_energy_change(model, &prepared);
    ws.projection = p;
    Sides {
        change,
        predicted_change: -work + projected,
        magnitude: magnitude + work.abs() + bound,
    }
}

/// The Paoli–Schatzman(β) balance over the step from `U^n` to `U^{n+1}`, `λ^n` the multiplier
/// of eq. (36) (eq. 37 before the complementarity substitution, see the module
/// documentation): `E^{n+½} − E^{n−½}` against
/// `½ (U^{n+1} − U^{n−1})ᵀ [−Bᵀλ^n + Q((1 − 2β) R(U^n) + β R(U^{n−1}))]`.
pub fn paoli_schatzman(model: &Model, beta: f64, dt: f64, levels: &ThreeLevels) -> StepBalance {
    let (past, next) = half_steps(dt, levels);
    paoli_schatzman_in(&mut Workspace::default(), model, beta, dt, levels)
        .with_energies(past.energy(model, beta, dt), next.energy(model, beta, dt))
}

/// The half steps `n − ½` and `n + ½` of `levels`.
fn half_steps(dt: f64, levels: &ThreeLevels) -> (HalfStep, HalfStep) {
    (
        HalfStep::between(dt, levels.earlier, levels.current),
        HalfStep::between(dt, levels.current, levels.later),
    )
}

/// [`paoli_schatzman`]'s sides, in `ws`: pair 0 holds `V^{n+½} − V^{n−½}` and
/// `V^{n+½} + V^{n−½}`, pair 1 the same of the means `Ū`; the bracket is sparse (the contact
/// forces, and the projected residuals on the massless dofs), so its entries are kept as a
/// list and its product with `U^{n+1} − U^{n−1}` summed over them.
fn paoli_schatzman_in(
    ws: &mut Workspace,
    model: &Model,
    beta: f64,
    dt: f64,
    levels: &ThreeLevels,
) -> Sides {
    ws.constants(model);
    let (earlier, current, later) = (levels.earlier, levels.current, levels.later);
    let ([dv, dm], [v_sum, m_sum]) = (&mut ws.difference, &mut ws.sum);
    let n = current.len();
    for out in [&mut *dv, &mut *dm, &mut *v_sum, &mut *m_sum] {
        out.resize(n, 0.0);
    }
    // `V^{n±½} = ±(U^{n±1} − U^n)/Δt` and `Ū^{n±½} = (U^{n±1} + U^n)/2`, combined.
    let inverse = 1.0 / dt;
    let outputs = dv
        .iter_mut()
        .zip(v_sum.iter_mut())
        .zip(dm.iter_mut().zip(m_sum.iter_mut()));
    let levels3 = earlier.iter().zip(current).zip(later);
    for (((dv, vs), (dm, ms)), ((&a, &b), &c)) in outputs.zip(levels3) {
        *dv = ((c - b) - (b - a)) * inverse;
        *vs = (c - a) * inverse;
        *dm = 0.5 * (c - a);
        *ms = 0.5 * ((c + b) + (b + a));
    }
    let entries = &mut ws.entries;
    entries.clear();
    entries.extend(model.massless_dofs().iter().map(|&z| {
        let projected = (1.0 - 2.0 * beta) * row_residual(model, current, z)
            + beta * row_residual(model, earlier, z);
        (z, projected)
    }));
    let rows = ws.rows.as_deref().unwrap_or_default();
    for (row, &l) in rows.iter().zip(levels.multiplier) {
        entries.extend(row.force.iter().map(|&(k, c)| (k, -c * l)));
    }
    let (work, absolute_work) = entries.iter().fold((0.0, 0.0), |(sum, abs), &(k, b)| {
        let product = (later[k] - earlier[k]) * b;
        (sum + product, abs + product.abs())
    });
    let p = ws.prepared();
    let ([dv, dm], [v_sum, m_sum], sums) = (p.difference, p.sum, p.sums);
    let kinetic = sums.mass(model, 0.5, dv, v_sum);
    let correction = sums.stiffness(model, 0.5 * (beta - 0.25) * dt * dt, dv, v_sum);
    let elastic = sums.stiffness(model, 0.5, dm, m_sum);
    Sides {
        change: kinetic.value + correction.value + elastic.value - load_work(model, dm),
        predicted_change: 0.5 * work,
        magnitude: kinetic.bound
            + correction.bound
            + elastic.bound
            + load_magnitude(model, dm)
            + 0.5 * absolute_work,
    }
}

/// `R(U)_z = (SU)_z − F_z`, row `z` of [`super::residual_force`].
fn row_residual(model: &Model, u: &[f64], z: usize) -> f64 {
    let mut r = -model.load().map_or(0.0, |f| f[z]);
    model.stiffness().for_each_in_row(z, |j, v| r += v * u[j]);
    r
}

/// The balance of explicit Newmark(0, ½) for the staggered energy it reports, over the step
/// from `U^n` to `U^{n+1}`: `E^{n+½} − E^{n−½}` against `−½ λ^nᵀ B (U^{n+1} − U^{n−1})` (see the
/// module documentation).
pub fn central_difference(model: &Model, dt: f64, levels: &ThreeLevels) -> StepBalance {
    let span = combined(levels.later, levels.earlier, |x, y| x - y);
    let work = contact_work(&constraints(model), &span, &|i| levels.multiplier[i]);
    let past = combined(levels.current, levels.earlier, |a, b| (a - b) / dt);
    let next = combined(levels.later, levels.current, |a, b| (a - b) / dt);
    let dv = combined(&next, &past, |x, y| x - y);
    let v_sum = combined(&next, &past, |x, y| x + y);
    let sums = RowSums::of(model);
    let kinetic = sums.mass(model, 0.5, &dv, &v_sum);
    let elastic = sums.stiffness(model, 0.5, levels.current, &span);
    StepBalance {
        energy_before: staggered_energy(model, dt, levels.earlier, levels.current),
        energy_after: staggered_energy(model, dt, levels.current, levels.later),
        change: kinetic.value + elastic.value - 0.5 * load_work(model, &span),
        predicted_change: -0.5 * work,
        magnitude: kinetic.bound
            + elastic.bound
            + 0.5 * load_magnitude(model, &span)
            + 0.5 * work.abs(),
    }
}

/// Whether the balances of this module are identities of the runs of `model` with
/// `conventions`: they are derived for the harness's conventions. GetFEM's Nitsche acceleration
/// (the elastic stiffness) and its Paoli–Schatzman rows and first step change the schemes'
/// equations, and its start gives a penalty or Nitsche run the implicit multiplier instead of
/// the law's, so those runs satisfy other identities, which are not checked.
pub fn holds_under(conventions: &Conventions, model: &Model) -> bool {
    let start_ok = conventions.start == Start::Static
        || model.contact_law().treatment() == ContactTreatment::Multiplier;
    start_ok
        && conventions.nitsche_acceleration == Conventions::HARNESS.nitsche_acceleration
        && conventions.paoli_schatzman_massless_rows
            == Conventions::HARNESS.paoli_schatzman_massless_rows
        && conventions.paoli_schatzman_first_step == Conventions::HARNESS.paoli_schatzman_first_step
}

/// The equation of `scheme`'s balance: the paper's `(33)` for Newmark (β = 0 included), `(35)`
/// for the θ-method, `(37)` for Paoli–Schatzman; `(GA-E)`, `(MJ-E)` and `(CSN-E)` of the rivals' files
/// (Laursen–Chawla's is (MJ-E) with θ = ½, where its persistency makes it `ΔE = 0`).
pub fn equation(scheme: Scheme) -> &'static str {
    match scheme {
        Scheme::Newmark { .. } => "(33)",
        Scheme::Theta { .. } => "(35)",
        Scheme::PaoliSchatzman { .. } => "(37)",
        Scheme::GeneralisedAlpha(_) => "(GA-E)",
        Scheme::MoreauJean { .. } | Scheme::LaursenChawla {} => "(MJ-E)",
        Scheme::ContactStabilisedNewmark { .. } => "(CSN-E)",
    }
}

/// Evaluates the balance of a scheme after every step of its integrator: [`newmark`] for every
/// Newmark scheme (explicit ones included, with `E_h(U^n, V^n)`), [`theta`] for the θ-method,
/// [`paoli_schatzman`] for Paoli–Schatzman from its second step on (the first is its Newmark
/// start), and the rivals' [`generalised_alpha`], [`moreau_jean`] (Laursen–Chawla's too) and
/// [`contact_stabilised_newmark`]. Each step's residual is taken relative to the scale
/// `max(|E^0|, |E_before|, |E_after|, magnitude)` (absolute where all vanish): the energies,
/// and the size of the products whose round-off the residual carries
/// ([`StepBalance::magnitude`]), which a small energy can hide (a bar translated far from its
/// rest state; a velocity on `ker M` that an unstable scheme lets grow while no energy sees it).
/// Within one run `E_after` is `E_before + ΔE` (equal up to round-off, without the products of
/// a fresh evaluation).
#[derive(Debug)]
pub struct BalanceMonitor<'m> {
    model: &'m Model,
    scheme: Scheme,
    dt: f64,
    /// The step index of the last observed state, `None` before the first observation.
    step: Option<usize>,
    /// `|E(U^0, V^0)|`.
    initial_energy: f64,
    /// `U^{n−1}` (Paoli–Schatzman); empty until two consecutive states were observed.
    earlier: Vec<f64>,
    displacement: Vec<f64>,
    velocity: Vec<f64>,
    multiplier: Vec<f64>,
    /// `A^n` of a scheme that carries it ([`SchemeState::acceleration()`]).
    acceleration: Vec<f64>,
    balanced_steps: usize,
    largest: f64,
    last: f64,
    workspace: Workspace,
    /// `E_h` of the last observed level (the next step's `E^n`), once computed.
    energy: Option<f64>,
    /// The step index of the level `energy` belongs to.
    energy_step: Option<usize>,
}

impl<'m> BalanceMonitor<'m> {
    /// A monitor for `scheme` run on `model` with step `dt`.
    pub fn new(model: &'m Model, scheme: Scheme, dt: f64) -> Self {
        Self {
            model,
            scheme,
            dt,
            step: None,
            initial_energy: 0.0,
            earlier: Vec::new(),
            displacement: Vec::new(),
            velocity: Vec::new(),
            multiplier: Vec::new(),
            acceleration: Vec::new(),
            balanced_steps: 0,
            largest: 0.0,
            last: 0.0,
            workspace: Workspace::default(),
            energy: None,
            energy_step: None,
        }
    }

    /// Records the integrator's state; when it is one step past the last recorded state,
    /// first evaluates the balance of that step, keeps its relative residual and returns it.
    /// Call it before the first step and after every step.
    pub fn observe(&mut self, integrator: &Integration<'_>) -> Option<StepBalance> {
        let step = integrator.step_index();
        let follows = self.step.is_some_and(|last| step == last + 1);
        if let Some(own) = integrator.own_balance() {
            if self.step.is_none() {
                self.initial_energy = integrator.energy().value.abs();
            }
            self.step = Some(step);
            return self.record(own.filter(|_| follows)?);
        }
        let balance = if follows {
            self.balance(integrator, step)
        } else {
            if self.step.is_none() {
                self.initial_energy = integrator.energy().value.abs();
            }
            self.energy = None;
            None
        };
        if follows {
            std::mem::swap(&mut self.earlier, &mut self.displacement);
        } else {
            self.earlier.clear();
        }
        copy_into(&mut self.displacement, integrator.displacement());
        copy_into(&mut self.velocity, integrator.velocity());
        copy_into(&mut self.multiplier, integrator.scheme_multiplier());
        if matches!(self.scheme, Scheme::GeneralisedAlpha(_)) {
            copy_into(
                &mut self.acceleration,
                integrator.acceleration().unwrap_or_default(),
            );
        }
        self.step = Some(step);
        self.record(balance?)
    }

    /// Keeps the relative residual of the step balance `b`, and returns it.
    fn record(&mut self, b: StepBalance) -> Option<StepBalance> {
        let scale = self
            .initial_energy
            .max(b.energy_before.abs())
            .max(b.energy_after.abs())
            .max(b.magnitude);
        let relative = b.residual().abs() / if scale > 0.0 { scale } else { 1.0 };
        self.balanced_steps += 1;
        self.last = relative;
        if relative > self.largest || relative.is_nan() {
            self.largest = relative;
        }
        Some(b)
    }

    fn balance(&mut self, integrator: &Integration<'_>, step: usize) -> Option<StepBalance> {
        let before = Level {
            displacement: &self.displacement,
            velocity: &self.velocity,
            multiplier: &self.multiplier,
        };
        let after = Level::of(integrator.state);
        let (model, dt, ws) = (self.model, self.dt, &mut self.workspace);
        let (sides, energy_before) = match self.scheme {
            Scheme::Newmark { beta, gamma } => (
                newmark_in(ws, model, (beta, gamma), dt, (&before, &after)),
                self.energy
                    .unwrap_or_else(|| mechanical_energy(model, &before)),
            ),
            Scheme::Theta { theta: t } => (
                theta_in(ws, model, (t, t), (&before, &after)),
                self.energy
                    .unwrap_or_else(|| mechanical_energy(model, &before)),
            ),
            Scheme::MoreauJean { theta: t, .. } => (
                theta_in(ws, model, (t, 1.0), (&before, &after)),
                self.energy
                    .unwrap_or_else(|| mechanical_energy(model, &before)),
            ),
            Scheme::LaursenChawla {} => (
                theta_in(ws, model, (0.5, 1.0), (&before, &after)),
                self.energy
                    .unwrap_or_else(|| mechanical_energy(model, &before)),
            ),
            Scheme::GeneralisedAlpha(parameters) => {
                let a1 = integrator.acceleration()?;
                (
                    generalised_alpha_in(
                        ws,
                        model,
                        parameters,
                        dt,
                        (&before, &after),
                        (&self.acceleration, a1),
                    ),
                    self.energy
                        .unwrap_or_else(|| mechanical_energy(model, &before)),
                )
            }
            Scheme::ContactStabilisedNewmark { velocity } => {
                let predictor = integrator.projected_predictor()?;
                (
                    contact_stabilised_newmark_in(
                        ws,
                        model,
                        (velocity, dt),
                        (&before, &after),
                        predictor,
                    ),
                    self.energy
                        .unwrap_or_else(|| mechanical_energy(model, &before)),
                )
            }
            Scheme::PaoliSchatzman { beta, .. } => {
                if step < 2 || self.earlier.is_empty() {
                    return None;
                }
                let levels = ThreeLevels {
                    earlier: &self.earlier,
                    current: &self.displacement,
                    later: integrator.displacement(),
                    multiplier: integrator.scheme_multiplier(),
                };
                let energy = self
                    .energy
                    .unwrap_or_else(|| half_steps(dt, &levels).0.energy(model, beta, dt));
                (paoli_schatzman_in(ws, model, beta, dt, &levels), energy)
            }
        };
        // The energies only scale the residual: `E^n + ΔE` is `E^{n+1}` up to round-off,
        // without the products that computing it afresh would take.
        let balance = sides.with_energies(energy_before, energy_before + sides.change);
        self.energy = Some(balance.energy_after);
        self.energy_step = Some(step);
        Some(balance)
    }

    /// The largest relative residual of the steps balanced so far (0 before any; NaN once a
    /// residual was NaN).
    pub fn largest_residual(&self) -> f64 {
        self.largest
    }

    /// The relative residual of the last step balanced (0 before any; NaN when it was NaN).
    pub fn last_residual(&self) -> f64 {
        self.last
    }

    /// The energy without contact energy (`½VᵀMV + ½UᵀSU − FᵀU`; the half-step energy of
    /// Paoli–Schatzman, `E_h(U^n, V^n)` for every other scheme) of the state of step `step`,
    /// when it is the state last observed and its step was balanced: `E^n + ΔE`, without the
    /// products that computing it afresh would take. `None` otherwise.
    pub fn energy_of(&self, step: usize) -> Option<f64> {
        self.energy.filter(|_| self.energy_step == Some(step))
    }

    /// How many steps were balanced.
    pub fn balanced_steps(&self) -> usize {
        self.balanced_steps
    }
}

fn copy_into(target: &mut Vec<f64>, source: &[f64]) {
    target.clear();
    target.extend_from_slice(source);
}
