//! The common form of the implicit one-step schemes, with the contact condition at `t_{n+1}`:
//! Newmark with β > 0 (1D paper eq. 32, [`super::newmark`]) and the θ-method (eq. 34,
//! [`super::theta`]).
//!
//! Both are instances of
//! ```text
//! U^{n+1} = U^n + Δt V^n + Δt² (a A^n + b A^{n+1})
//! V^{n+1} = V^n + Δt (c A^n + d A^{n+1})
//! M A^{n+1} + S U^{n+1} = F − Bᵀλ^{n+1},   0 ≤ B U^{n+1} + g ⟂ λ^{n+1} ≤ 0
//! ```
//! with `(a, b, c, d) = (½ − β, β, 1 − γ, γ)` for Newmark(β, γ) ([`StepCoefficients::newmark`])
//! and `(θ(1 − θ), θ², 1 − θ, θ)` for the θ-method ([`StepCoefficients::theta`]).
//! Substituting the first line into the third gives the step system
//! `(M / (bΔt²) + S) U^{n+1} = M P / (bΔt²) + F − Bᵀλ^{n+1}`, `P = U^n + ΔtV^n + aΔt²A^n`.
//! `A^{n+1}` and `V^{n+1}` then follow from the first two lines for every dof; only `M A` and
//! `M V` enter the dynamics, so the values on massless dofs are a consistent difference
//! quotient that never needs `M⁻¹`.
//!
//! A penalty or Nitsche treatment ([`crate::engine::contact::law`]) replaces `Bᵀλ^{n+1}` by
//! `Σ λ_i^{n+1} f_i` with `λ^{n+1}` the force at `U^{n+1}` (implicit), solved through the
//! shifted Delassus operator; for Nitsche `S` is the model's modified stiffness. With
//! [`NitscheAcceleration::ElasticStiffness`] the acceleration kept is instead the one of the
//! elastic stiffness, `A^{n+1} − M⁻¹ (θ/γ) a (aᵀU^{n+1})` ([`ElasticAcceleration`]).

use super::conventions::{NitscheAcceleration, PredictorForm};
use super::{step_system, SchemeState, StepStatistics, TimeIntegrator, Timed};
use crate::engine::contact::law::sparse_dot;
use crate::engine::contact::ContactStep;
use crate::engine::error::SolveError;
use crate::engine::linalg::{SpdSolver, StepSolver};
use crate::engine::model::Model;

/// The coefficients `(a, b, c, d)` of the one-step form; Newmark's (eq. 32) are built in
/// [`super::newmark`], the θ-method's (eq. 34) in [`super::theta`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StepCoefficients {
    /// Weight of `A^n` in the displacement update.
    pub a: f64,
    /// Weight of `A^{n+1}` in the displacement update (> 0).
    pub b: f64,
    /// Weight of `A^n` in the velocity update.
    pub c: f64,
    /// Weight of `A^{n+1}` in the velocity update.
    pub d: f64,
}

/// The change from the acceleration of the Nitsche stiffness `S_θ = S + scale a aᵀ`
/// (`scale = −θ/γ`) to the one of the elastic `S` ([`NitscheAcceleration::ElasticStiffness`]):
/// `M (A_S − A_θ) = scale a (aᵀU)`, so `A_S = A_θ + scale (aᵀU) w` with `w = M_RR⁻¹ a_R` on
/// the dofs with mass (zero on massless dofs, whose acceleration never enters `M A`).
#[derive(Debug)]
struct ElasticAcceleration {
    stress: Vec<(usize, f64)>,
    scale: f64,
    w: Vec<f64>,
}

impl ElasticAcceleration {
    /// `None` unless the model has a Nitsche stiffness and the convention asks for it.
    fn new(model: &Model, convention: NitscheAcceleration) -> Result<Option<Self>, SolveError> {
        let Some((a, scale)) = model.contact_law().stiffness_update() else {
            return Ok(None);
        };
        if convention == NitscheAcceleration::Consistent || scale == 0.0 {
            return Ok(None);
        }
        let with_mass = model.dofs_with_mass();
        let m_rr = model.mass().principal_submatrix(&with_mass);
        let solver = SpdSolver::factor(&m_rr, "mass (dofs with inertia)")?;
        let mut w = vec![0.0; model.n_dofs()];
        for &(k, ak) in a {
            w[k] = ak;
        }
        let mut w_r: Vec<f64> = with_mass.iter().map(|&i| w[i]).collect();
        solver.solve_in_place(&mut w_r);
        w.fill(0.0);
        for (&i, wi) in with_mass.iter().zip(w_r) {
            w[i] = wi;
        }
        Ok(Some(Self {
            stress: a.to_vec(),
            scale,
            w,
        }))
    }

    /// `A ← A + scale (aᵀu) w`.
    fn apply(&self, u: &[f64], acceleration: &mut [f64]) {
        let shift = self.scale * sparse_dot(&self.stress, u);
        for (acc, wi) in acceleration.iter_mut().zip(&self.w) {
            *acc += shift * wi;
        }
    }
}

/// A Newmark or θ-method integrator: its factorised step matrix and contact step. The state
/// it advances carries `A^n` ([`SchemeState::acceleration()`]), which its predictor reads.
#[derive(Debug)]
pub struct OneStepScheme<'m> {
    model: &'m Model,
    coef: StepCoefficients,
    system: StepSolver,
    contact: Option<ContactStep>,
    elastic_acceleration: Option<ElasticAcceleration>,
    predictor: Vec<f64>,
    /// How `predictor` is summed.
    predictor_form: PredictorForm,
    scratch: Vec<f64>,
    guess: Vec<f64>,
}

impl StepCoefficients {
    /// The predictor `P = U^n + ΔtV^n + aΔt²A^n` (eq. 32a without its `A^{n+1}` term) of
    /// `(U^n, V^n, A^n)` into `predictor`, summed in `form`.
    pub fn predict(
        &self,
        form: PredictorForm,
        dt: f64,
        (u, v, acc): (&[f64], &[f64], &[f64]),
        predictor: &mut [f64],
    ) {
        let a = self.a;
        let factored = form == PredictorForm::Factored;
        for (((p, u), v), acc) in predictor.iter_mut().zip(u).zip(v).zip(acc) {
            *p = if factored {
                u + dt * (v + a * dt * acc)
            } else {
                u + dt * v + a * dt * dt * acc
            };
        }
    }

    /// The iterative solver's initial guess `P + bΔt²A^n`, the displacement of an unchanged
    /// acceleration, into `guess`.
    pub fn warm_start(&self, dt: f64, predictor: &[f64], acc: &[f64], guess: &mut [f64]) {
        let b_dt2 = self.b * dt * dt;
        for ((g, p), acc) in guess.iter_mut().zip(predictor).zip(acc) {
            *g = p + b_dt2 * acc;
        }
    }

    /// `A^{n+1} = (U^{n+1} − P)/(bΔt²)` and `V^{n+1} = V^n + Δt(cA^n + dA^{n+1})` (eq. 32a–b),
    /// in place of `A^n` and `V^n`, from `U^{n+1}` and the predictor `P`.
    pub fn update(
        &self,
        dt: f64,
        (u_new, predictor): (&[f64], &[f64]),
        v: &mut [f64],
        acc: &mut [f64],
    ) {
        let (c, d) = (self.c, self.d);
        let inv_bdt2 = 1.0 / (self.b * dt * dt);
        let updates = u_new.iter().zip(predictor);
        for ((v, acc), (u_new, p)) in v.iter_mut().zip(acc.iter_mut()).zip(updates) {
            let a_new = (u_new - p) * inv_bdt2;
            *v += dt * (c * *acc + d * a_new);
            *acc = a_new;
        }
    }
}

impl<'m> OneStepScheme<'m> {
    /// Factorises `M / (bΔt²) + S` and prepares the contact correction; `nitsche` says which
    /// acceleration a Nitsche run keeps (see the module documentation).
    pub fn new(
        model: &'m Model,
        coef: StepCoefficients,
        dt: f64,
        nitsche: NitscheAcceleration,
    ) -> Result<Self, SolveError> {
        let k = model
            .mass()
            .linear_combination(1.0 / (coef.b * dt * dt), model.stiffness(), 1.0);
        let (system, contact) = step_system(model, k, "one-step scheme system M/(bΔt²) + S")?;
        let n = model.n_dofs();
        Ok(Self {
            model,
            coef,
            system,
            contact,
            elastic_acceleration: ElasticAcceleration::new(model, nitsche)?,
            predictor: vec![0.0; n],
            predictor_form: PredictorForm::Expanded,
            scratch: vec![0.0; n],
            guess: vec![0.0; n],
        })
    }

    /// Sums the predictor in `form` ([`PredictorForm`]; the expanded form by default).
    pub fn with_predictor(mut self, form: PredictorForm) -> Self {
        self.predictor_form = form;
        self
    }

    /// Replaces the complementarity solver (e.g. by the clarabel cross-check).
    pub fn with_contact_solver(
        mut self,
        solver: Box<dyn crate::engine::contact::ContactSolver>,
    ) -> Self {
        self.contact = self.contact.map(|c| c.with_solver(solver));
        self
    }
}

impl OneStepScheme<'_> {
    /// One step of `state` with the contact condition `B U^{n+1} + shift(i, g_i) ≥ 0` instead
    /// of `B U^{n+1} + g ≥ 0` (Paoli–Schatzman's first step,
    /// [`super::conventions::FirstStepContact`]).
    pub fn advance_with_gap(
        &mut self,
        state: &mut SchemeState,
        shift: impl Fn(usize, f64) -> f64,
    ) -> Result<(), SolveError> {
        let (dt, step) = (state.dt, state.step + 1);
        let StepCoefficients { b, c, d, .. } = self.coef;
        let inv_bdt2 = 1.0 / (b * dt * dt);
        let SchemeState {
            u,
            v,
            lambda,
            acceleration,
            ..
        } = state;
        let acc = acceleration.as_mut().expect(super::CARRIES_ACCELERATION);
        self.coef
            .predict(self.predictor_form, dt, (u, v, acc), &mut self.predictor);
        self.model
            .mass()
            .mul_into(&self.predictor, &mut self.scratch);
        self.scratch.iter_mut().for_each(|r| *r *= inv_bdt2);
        if let Some(f) = self.model.load() {
            self.scratch.iter_mut().zip(f).for_each(|(r, fi)| *r += fi);
        }
        if self.system.reads_guess() {
            self.coef
                .warm_start(dt, &self.predictor, acc, &mut self.guess);
        }
        self.system.solve(&mut self.scratch, &self.guess)?;
        if let Some(contact) = self.contact.as_mut() {
            contact.enforce(step, &mut self.scratch, shift, lambda)?;
        }
        match &self.elastic_acceleration {
            None => self
                .coef
                .update(dt, (&self.scratch, &self.predictor), v, acc),
            Some(elastic) => {
                // A^{n+1} needs the whole of U^{n+1} before the velocity update: the predictor
                // buffer takes it.
                for (p, u_new) in self.predictor.iter_mut().zip(&self.scratch) {
                    *p = (u_new - *p) * inv_bdt2;
                }
                elastic.apply(&self.scratch, &mut self.predictor);
                let updates = v.iter_mut().zip(acc.iter_mut());
                for ((v, acc), &a_new) in updates.zip(&self.predictor) {
                    *v += dt * (c * *acc + d * a_new);
                    *acc = a_new;
                }
            }
        }
        std::mem::swap(u, &mut self.scratch);
        state.next_step();
        Ok(())
    }
}

impl TimeIntegrator for OneStepScheme<'_> {
    fn advance(&mut self, state: &mut SchemeState) -> Result<(), SolveError> {
        self.advance_with_gap(state, |_, g| g)
    }

    /// `U^{n+1}`, `V^{n+1}` and `A^{n+1}`: the predictor of the next step reads all three.
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
