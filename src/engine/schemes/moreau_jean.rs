//! Moreau–Jean (M. Jean, CMAME 177, 1999; V. Acary and B. Brogliato, *Numerical Methods for
//! Nonsmooth Dynamical Systems*, Springer 2008, §10.1), as Siconos's `MoreauJeanOSI` runs it: the
//! θ-method on velocities, with the contact as an impulse and Newton's impact law on the
//! velocities of the constraints active at the start of the step:
//! ```text
//! M (V^{n+1} − V^n) = Δt (F − S U^{n+θ}) − Δt Bᵀλ^{n+1}                        (MJ-a)
//! U^{n+1} = U^n + Δt V^{n+θ}                                                    (MJ-b)
//! I^n = { i : (B U^n + g)_i + ½ Δt (B V^n)_i ≤ 0 }                               (MJ-c)
//! i ∈ I^n: 0 ≤ (B V^{n+1})_i + e (B V^n)_i ⟂ λ_i^{n+1} ≤ 0;   i ∉ I^n: λ_i^{n+1} = 0  (MJ-d)
//! ```
//! with `X^{n+θ} = (1 − θ) X^n + θ X^{n+1}`. `Δt λ^{n+1}` is the contact impulse of the step,
//! reported as the force `λ^{n+1}` at `t_{n+1}`; (MJ-c) is `MoreauJeanOSI`'s default activation
//! (its γ = ½). θ ∈ [½, 1] is stable; e ∈ [0, 1] the restitution coefficient. Without contact
//! (MJ-a–b) is the θ-method, eq. (34), written on velocities: both give
//! `M ΔV = Δt (F − S U^{n+θ})` with `ΔU = Δt V^{n+θ}`. The contact is imposed on velocities,
//! not on positions: a constraint can be violated by `O(Δt)` during a step, and a penalty or
//! Nitsche force, which is a function of the position, has no place in (MJ-d).
//!
//! **The step.** Substituting (MJ-b) into `U^{n+θ}` and dividing by `θ²Δt²`,
//! `(M / (θ²Δt²) + S) V^{n+1} = M V^n / (θ²Δt²) + (F − S (U^n + θ(1 − θ) Δt V^n)) / (θ²Δt) − Bᵀν`
//! with `ν = λ^{n+1} / (θ²Δt)`: the step matrix of the θ-method, and the complementarity
//! problem (MJ-d) on `V^{n+1}` solved by the same contact step
//! ([`crate::engine::contact::ContactStep`]), whose offset `e (B V^n)_i` imposes Newton's law
//! and whose offset `+∞` leaves a constraint outside `I^n` free.
//!
//! **The energy balance (MJ-E).** Multiplying (MJ-a) by `V^{n+θ} = ΔU/Δt` (Acary, INRIA research
//! report 8602, 2014, §3) gives, for `E = E_h(U, V)` (eq. 31),
//! ```text
//! ΔE = (½ − θ) (ΔVᵀMΔV + ΔUᵀSΔU) − ΔUᵀBᵀλ^{n+1}                                  (MJ-E)
//! ```
//! the θ-method's eq. (35) with the whole impulse at `t_{n+1}`
//! ([`super::energy_balance::moreau_jean`]). With θ = ½ and (MJ-d), where
//! `λ_i^{n+1} (B V^{n+1})_i = −e λ_i^{n+1} (B V^n)_i`, the last term is
//! `−½ Δt (1 − e) Σ_i λ_i^{n+1} (B V^n)_i`, which is ≤ 0 when the constraints that push were
//! approaching, `(B V^n)_i ≤ 0`, as at an impact: energy is lost there unless e = 1.

use super::{step_system, SchemeState, StepStatistics, TimeIntegrator, Timed};
use crate::engine::contact::law::{sparse_dot, ConstraintRow};
use crate::engine::contact::ContactStep;
use crate::engine::error::SolveError;
use crate::engine::linalg::StepSolver;
use crate::engine::model::Model;

/// Which constraints a step's impact law (MJ-d) applies to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Activation {
    /// (MJ-c): `(B U^n + g)_i + ½ Δt (B V^n)_i ≤ 0`, Siconos's `MoreauJeanOSI` default.
    HalfStepPrediction,
    /// The gap of the step without contact: `(B Ũ^{n+1} + g)_i ≤ 0` with
    /// `Ũ^{n+1} = U^n + Δt ((1 − θ) V^n + θ Ṽ^{n+1})`, `Ṽ^{n+1}` the unconstrained solve (the
    /// trial of Laursen and Chawla, [`super::laursen_chawla`]).
    FreeStep,
}

/// A Moreau–Jean integrator: its factorised step matrix and contact step. The state it advances
/// carries `(U^n, V^n)` and no acceleration: the scheme works on velocities.
#[derive(Debug)]
pub struct MoreauJean<'m> {
    model: &'m Model,
    theta: f64,
    restitution: f64,
    activation: Activation,
    system: StepSolver,
    contact: Option<ContactStep>,
    /// The contact constraints (none without an obstacle).
    rows: Vec<ConstraintRow>,
    /// `(B U^n)_i` and `(B V^n)_i` of the constraints, for (MJ-c–d).
    positions: Vec<f64>,
    velocities: Vec<f64>,
    /// `(B Ũ^{n+1})_i` of [`Activation::FreeStep`].
    trial: Vec<f64>,
    /// `ν` of the step's complementarity problem.
    nu: Vec<f64>,
    rhs: Vec<f64>,
    scratch: Vec<f64>,
}

impl<'m> MoreauJean<'m> {
    /// Factorises `M / (θ²Δt²) + S` and prepares the contact step.
    pub fn new(
        model: &'m Model,
        theta: f64,
        restitution: f64,
        dt: f64,
    ) -> Result<Self, SolveError> {
        let scale = 1.0 / (theta * theta * dt * dt);
        let k = model
            .mass()
            .linear_combination(scale, model.stiffness(), 1.0);
        let (system, contact) = step_system(model, k, "Moreau–Jean system M/(θ²Δt²) + S")?;
        let rows = model
            .contact()
            .map_or_else(Vec::new, |set| model.contact_law().rows(set));
        let n = model.n_dofs();
        let constraints = rows.len();
        Ok(Self {
            model,
            theta,
            restitution,
            activation: Activation::HalfStepPrediction,
            system,
            contact,
            rows,
            positions: vec![0.0; constraints],
            velocities: vec![0.0; constraints],
            trial: vec![0.0; constraints],
            nu: vec![0.0; constraints],
            rhs: vec![0.0; n],
            scratch: vec![0.0; n],
        })
    }

    /// Applies the impact law to the constraints `activation` selects (the default is (MJ-c)).
    pub fn with_activation(mut self, activation: Activation) -> Self {
        self.activation = activation;
        self
    }
}

impl TimeIntegrator for MoreauJean<'_> {
    fn advance(&mut self, state: &mut SchemeState) -> Result<(), SolveError> {
        let (dt, theta, e) = (state.dt, self.theta, self.restitution);
        let theta2_dt = theta * theta * dt;
        // The right-hand side `M V^n / (θ²Δt²) + (F − S W) / (θ²Δt)`, `W = U^n + θ(1 − θ)Δt V^n`.
        for ((w, u), v) in self.scratch.iter_mut().zip(&state.u).zip(&state.v) {
            *w = u + theta * (1.0 - theta) * dt * v;
        }
        self.model
            .stiffness()
            .mul_into(&self.scratch, &mut self.rhs);
        self.model.mass().mul_into(&state.v, &mut self.scratch);
        let load = self.model.load();
        for (k, (r, mv)) in self.rhs.iter_mut().zip(&self.scratch).enumerate() {
            let f = load.map_or(0.0, |f| f[k]);
            *r = mv / (theta2_dt * dt) + (f - *r) / theta2_dt;
        }
        self.system.solve(&mut self.rhs, &state.v)?;
        for (i, row) in self.rows.iter().enumerate() {
            self.positions[i] = sparse_dot(&row.measure, &state.u);
            self.velocities[i] = sparse_dot(&row.measure, &state.v);
            let free = sparse_dot(&row.measure, &self.rhs);
            self.trial[i] =
                self.positions[i] + dt * ((1.0 - theta) * self.velocities[i] + theta * free);
        }
        if let Some(contact) = self.contact.as_mut() {
            let (positions, velocities, trial) = (&self.positions, &self.velocities, &self.trial);
            let activation = self.activation;
            contact.enforce(
                state.step + 1,
                &mut self.rhs,
                |i, g| {
                    let active = match activation {
                        Activation::HalfStepPrediction => {
                            positions[i] + g + 0.5 * dt * velocities[i] <= 0.0
                        }
                        Activation::FreeStep => trial[i] + g <= 0.0,
                    };
                    if active {
                        e * velocities[i]
                    } else {
                        f64::INFINITY
                    }
                },
                &mut self.nu,
            )?;
            for (l, nu) in state.lambda.iter_mut().zip(&self.nu) {
                *l = theta2_dt * nu;
            }
        }
        let updates = state.u.iter_mut().zip(state.v.iter_mut());
        for ((u, v), v_new) in updates.zip(&self.rhs) {
            *u += dt * ((1.0 - theta) * *v + theta * v_new);
            *v = *v_new;
        }
        state.next_step();
        Ok(())
    }

    /// `U^{n+1}` and `V^{n+1}`: the next step reads both.
    fn perturb_carried(&self, state: &mut SchemeState, perturb: &mut dyn FnMut(&mut [f64])) {
        state.perturb_levels(perturb);
    }

    fn energy(&self, state: &SchemeState) -> Timed<f64> {
        state.mechanical_energy(self.model)
    }

    /// The violation is the largest of Newton's law (MJ-d) on the velocities, over the steps.
    fn statistics(&self) -> StepStatistics {
        StepStatistics::of(self.system.counts(), &self.contact)
    }
}
