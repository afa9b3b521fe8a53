//! Generalised-α (J. Chung and G. M. Hulbert, J. Appl. Mech. 60, 1993, eqs. 2–4), with the
//! contact condition at `t_{n+1}` as for Newmark (eq. 32):
//! ```text
//! U^{n+1} = U^n + Δt V^n + Δt² ((½ − β) A^n + β A^{n+1})                    (GA-a)
//! V^{n+1} = V^n + Δt ((1 − γ) A^n + γ A^{n+1})                               (GA-b)
//! M A^{n+1−α_m} + S U^{n+1−α_f} = F − Bᵀλ^{n+1−α_f}                          (GA-c)
//! 0 ≤ B U^{n+1} + g ⟂ λ^{n+1} ≤ 0                                             (GA-d)
//! ```
//! with `X^{n+1−α} = (1 − α) X^{n+1} + α X^n`. The contact force is weighted as the internal
//! force, so that `λ` is a force at the same time levels as `U`. With `α_m = α_f = 0` the scheme
//! is Newmark(β, γ), eq. (32); with `α_m = 0` it is HHT-α (Hilber, Hughes and Taylor, Earthq.
//! Eng. Struct. Dyn. 5, 1977), α = α_f. The parameters from the high-frequency spectral radius
//! `ρ∞ ∈ [0, 1]` ([`super::scheme::generalised_alpha`]) make the scheme second order and
//! unconditionally stable without contact, dissipating the highest frequencies by the factor
//! `ρ∞` per step; `ρ∞ = 1` dissipates nothing.
//!
//! **The step.** Dividing (GA-c) by `1 − α_f` and substituting (GA-a),
//! `(c M + S) U^{n+1} = c M P + (F − α_m M A^n − α_f (S U^n + Bᵀλ^n)) / (1 − α_f) − Bᵀλ^{n+1}`
//! with `P = U^n + Δt V^n + (½ − β) Δt² A^n` and `c = (1 − α_m) / ((1 − α_f) β Δt²)`: the
//! multiplier of the step's complementarity problem is `λ^{n+1}` itself, so the contact step
//! of the Newmark schemes ([`crate::engine::contact::ContactStep`]) solves it with every
//! contact treatment (a penalty or Nitsche force replaces `Bᵀλ` by `Σ λ_i f_i` at both levels,
//! with Nitsche's stiffness as `S`). `A^{n+1}` and `V^{n+1}` then follow from (GA-a–b) as in
//! [`super::OneStepScheme`]; `A^0` comes from (GA-c) at `t = 0` with `α = 0`
//! ([`super::initial_state`]).
//!
//! **The energy balance (GA-E).** With `ΔX = X^{n+1} − X^n` and `E = E_h(U, V)` (eq. 31),
//! multiplying (GA-c) by `ΔU` and eliminating `V̄ = (V^{n+1} + V^n)/2` by (GA-a–b),
//! `ΔU − Δt V̄ = Δt² (β − γ/2) ΔA`, gives
//! ```text
//! ΔE = −ΔUᵀBᵀΛ_f + (α_f − ½) ΔUᵀSΔU + (γ − 1 + α_m) ΔAᵀMΔU − Δt (β − γ/2) ΔAᵀMΔV     (GA-E)
//! ```
//! with `Λ_f = (1 − α_f) λ^{n+1} + α_f λ^n` ([`super::energy_balance::generalised_alpha`]).
//! With `α_m = α_f = 0`, where `M ΔA = −S ΔU − Bᵀ Δλ`, it is Newmark's eq. (33). Unlike the
//! paper's schemes the identity needs the accelerations: the scheme's state is
//! `(U^n, V^n, A^n, λ^n)`, and `M A^n + S U^n = F − Bᵀλ^n` does not hold when `α ≠ 0`.

use serde::{Deserialize, Serialize};

use super::conventions::PredictorForm;
use super::{
    step_system, SchemeState, StepStatistics, TimeIntegrator, Timed, CARRIES_ACCELERATION,
};
use crate::engine::contact::law::ConstraintRow;
use crate::engine::contact::ContactStep;
use crate::engine::error::SolveError;
use crate::engine::linalg::StepSolver;
use crate::engine::model::Model;

/// The parameters `(α_m, α_f, β, γ)` of (GA-a–c).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AlphaParameters {
    /// `α_m`, the weight of `A^n` in (GA-c).
    pub alpha_m: f64,
    /// `α_f`, the weight of `U^n` and `λ^n` in (GA-c).
    pub alpha_f: f64,
    /// `β` of (GA-a).
    pub beta: f64,
    /// `γ` of (GA-b).
    pub gamma: f64,
}

/// A generalised-α integrator: its factorised step matrix and contact step. The state it
/// advances carries `A^n` ([`SchemeState::acceleration()`]), which (GA-a–c) and the balance
/// (GA-E) read.
#[derive(Debug)]
pub struct GeneralisedAlpha<'m> {
    model: &'m Model,
    parameters: AlphaParameters,
    system: StepSolver,
    contact: Option<ContactStep>,
    /// The force vectors `f_i` of the contact constraints (none without an obstacle).
    rows: Vec<ConstraintRow>,
    predictor: Vec<f64>,
    predictor_form: PredictorForm,
    scratch: Vec<f64>,
    history: Vec<f64>,
    guess: Vec<f64>,
}

impl<'m> GeneralisedAlpha<'m> {
    /// Factorises `c M + S` (see the module documentation) and prepares the contact step.
    pub fn new(model: &'m Model, parameters: AlphaParameters, dt: f64) -> Result<Self, SolveError> {
        let AlphaParameters {
            alpha_m,
            alpha_f,
            beta,
            ..
        } = parameters;
        let c = (1.0 - alpha_m) / ((1.0 - alpha_f) * beta * dt * dt);
        let k = model.mass().linear_combination(c, model.stiffness(), 1.0);
        let (system, contact) = step_system(model, k, "generalised-α system c M + S")?;
        let rows = model
            .contact()
            .map_or_else(Vec::new, |set| model.contact_law().rows(set));
        let n = model.n_dofs();
        Ok(Self {
            model,
            parameters,
            system,
            contact,
            rows,
            predictor: vec![0.0; n],
            predictor_form: PredictorForm::Expanded,
            scratch: vec![0.0; n],
            history: vec![0.0; n],
            guess: vec![0.0; n],
        })
    }

    /// Sums the predictor `P` in `form` ([`PredictorForm`]), as the Newmark schemes do.
    pub fn with_predictor(mut self, form: PredictorForm) -> Self {
        self.predictor_form = form;
        self
    }

    /// `α_m M A^n + α_f (S U^n + Σ λ_i^n f_i)` of `(U^n, λ^n)` and `a` (`A^n`) into
    /// `history`: what (GA-c) keeps of level `n` (nothing for Newmark, α_m = α_f = 0).
    fn level_n_forces(&mut self, (u, lambda): (&[f64], &[f64]), a: &[f64]) {
        let AlphaParameters {
            alpha_m, alpha_f, ..
        } = self.parameters;
        self.history.fill(0.0);
        if alpha_f != 0.0 {
            self.model.stiffness().mul_into(u, &mut self.history);
            for (row, &l) in self.rows.iter().zip(lambda) {
                for &(k, f) in &row.force {
                    self.history[k] += l * f;
                }
            }
            self.history.iter_mut().for_each(|h| *h *= alpha_f);
        }
        if alpha_m != 0.0 {
            self.model.mass().mul_into(a, &mut self.scratch);
            for (h, ma) in self.history.iter_mut().zip(&self.scratch) {
                *h += alpha_m * ma;
            }
        }
    }
}

impl TimeIntegrator for GeneralisedAlpha<'_> {
    fn advance(&mut self, state: &mut SchemeState) -> Result<(), SolveError> {
        let (dt, step) = (state.dt, state.step + 1);
        let AlphaParameters {
            alpha_m,
            alpha_f,
            beta,
            gamma,
        } = self.parameters;
        let inv_bdt2 = 1.0 / (beta * dt * dt);
        let c = (1.0 - alpha_m) / ((1.0 - alpha_f) * beta * dt * dt);
        let a = 0.5 - beta;
        let factored = self.predictor_form == PredictorForm::Factored;
        let SchemeState {
            u,
            v,
            lambda,
            acceleration,
            ..
        } = state;
        let acceleration = acceleration.as_mut().expect(CARRIES_ACCELERATION);
        let levels = self.predictor.iter_mut().zip(u.iter()).zip(v.iter());
        for (((p, u), v), acc) in levels.zip(acceleration.iter()) {
            *p = if factored {
                u + dt * (v + a * dt * acc)
            } else {
                u + dt * v + a * dt * dt * acc
            };
        }
        self.level_n_forces((u, lambda), acceleration);
        self.model
            .mass()
            .mul_into(&self.predictor, &mut self.scratch);
        let load = self.model.load();
        for (k, (r, h)) in self.scratch.iter_mut().zip(&self.history).enumerate() {
            let f = load.map_or(0.0, |f| f[k]);
            *r = *r * c + (f - h) / (1.0 - alpha_f);
        }
        let b_dt2 = beta * dt * dt;
        let guesses = self.guess.iter_mut().zip(&self.predictor);
        for ((g, p), acc) in guesses.zip(acceleration.iter()) {
            *g = p + b_dt2 * acc;
        }
        self.system.solve(&mut self.scratch, &self.guess)?;
        if let Some(contact) = self.contact.as_mut() {
            contact.enforce(step, &mut self.scratch, |_, g| g, lambda)?;
        }
        let updates = self.scratch.iter().zip(&self.predictor);
        for ((v, acc), (u_new, p)) in v.iter_mut().zip(acceleration.iter_mut()).zip(updates) {
            let a_new = (u_new - p) * inv_bdt2;
            *v += dt * ((1.0 - gamma) * *acc + gamma * a_new);
            *acc = a_new;
        }
        std::mem::swap(u, &mut self.scratch);
        state.next_step();
        Ok(())
    }

    /// `U^{n+1}`, `V^{n+1}` and `A^{n+1}`: the next step reads all three.
    fn perturb_carried(&self, state: &mut SchemeState, perturb: &mut dyn FnMut(&mut [f64])) {
        state.perturb_levels(perturb);
    }

    fn energy(&self, state: &SchemeState) -> Timed<f64> {
        state.mechanical_energy(self.model)
    }

    fn statistics(&self) -> StepStatistics {
        StepStatistics::of(self.system.counts(), &self.contact)
    }
}
