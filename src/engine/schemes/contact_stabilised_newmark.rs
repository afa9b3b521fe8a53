//! The contact-stabilised Newmark method of P. Deuflhard, R. Krause and S. Ertel (IJNME 73,
//! 2008): Crank–Nicolson (Newmark ¼, ½) with the contact force taken wholly at `t_{n+1}`, after
//! an `M`-projection of the predictor `U^n + Δt V^n` onto the admissible set
//! `K = { W : B W + g ≥ 0 }`:
//! ```text
//! U^pred = argmin_{W ∈ K} ½ (W − U^n − Δt V^n)ᵀ M (W − U^n − Δt V^n)                   (CSN-a)
//! M (U^{n+1} − U^pred) = ½ Δt² (F − S Ū − Bᵀλ^{n+1}),  Ū = ½ (U^n + U^{n+1}),
//!     0 ≤ (B U^{n+1} + g)_i ⟂ λ_i^{n+1} ≤ 0                                          (CSN-b)
//! V^{n+1} = W^n + (2/Δt) (U^{n+1} − U^pred)                                          (CSN-c)
//! ```
//! with two velocities `W^n` the corrector starts from ([`PredictorVelocity`]):
//! - `W^n = V^n`, Deuflhard, Krause and Ertel's update ([`PredictorVelocity::Carried`]);
//! - `W^n = (U^pred − U^n)/Δt`, the predictor's own velocity ([`PredictorVelocity::Projected`]):
//!   the velocity the projection left, so that the impulse of (CSN-a) is kept in the velocity
//!   too. This is the variant whose energy can only decrease (CSN-E below); Klapproth, Schiela
//!   and Deuflhard (Numer. Math. 116, 2010) give an energy-dissipative improvement of the
//!   method, and this variant is the harness's reading of it (docs/src/schemes-and-balances.md
//!   says what was and was not checked against their text).
//!
//! Without an obstacle `U^pred = U^n + Δt V^n`, `W^n = V^n`, and (CSN-b–c) are Crank–Nicolson,
//! eq. (32) with (β, γ) = (¼, ½), whose `¼ Δt² (A^n + A^{n+1})` is `½ Δt² M⁻¹(F − S Ū)`. With the
//! obstacle the contact force of `t_n` no longer enters the step (`A^n` of eq. 32 carries none):
//! the persistent force of a resting contact is `λ` itself.
//!
//! **Where it is defined.** (CSN-a) is a projection in the `M`-norm: with a mass that leaves
//! dofs without mass (the redistributed masses) the minimiser is not unique on `ker M`, and the
//! constraint (on the contact dofs, massless) is not seen by the norm at all. The method is
//! defined with a definite mass (standard or lumped) and a hard constraint: the multiplier
//! treatment (a penalty or Nitsche force has no admissible set to project onto).
//!
//! **The step.** (CSN-a) is the contact step ([`ContactStep`]) of the system `M` applied to the
//! unconstrained `U^n + Δt V^n`; (CSN-b) is `(M + ¼Δt² S) U^{n+1} = M U^pred + ¼Δt² (2F − S U^n)
//! − ½Δt² Bᵀλ^{n+1}`, the contact step of the system `M + ¼Δt² S` (the Crank–Nicolson step
//! matrix), with `λ^{n+1} = −2μ/Δt²` for its correction `Bᵀμ`.
//!
//! **The energy balance (CSN-E).** With `E = E_h(U, V)` (eq. 31), `ΔU = U^{n+1} − U^n` and the
//! projection's displacement `P = U^pred − U^n − Δt V^n`, (CSN-b–c) give
//! `M (V^{n+1} − W^n) = Δt (F − S Ū − Bᵀλ^{n+1})`; multiplied by `½ (V^{n+1} + V^n)`:
//! ```text
//! Carried:    ΔE = −ΔUᵀBᵀλ^{n+1} + Pᵀ(S Ū − F + Bᵀλ^{n+1})                              (CSN-E)
//! Projected:  ΔE = −ΔUᵀBᵀλ^{n+1} + (1/Δt) PᵀM V^n + (1/(2Δt²)) PᵀM P
//! ```
//! ([`super::energy_balance::contact_stabilised_newmark`]). In the projected variant both terms
//! are ≤ 0: by (CSN-b), `−λᵀB ΔU = λᵀ(B U^n + g) ≤ 0` for an admissible `U^n`; the other is
//! `½ |W^n|²_M − ½ |V^n|²_M ≤ 0`, since the projection onto `K` does not lengthen the step from
//! `U^n ∈ K`. In the carried variant the projection's term has no sign, and no inequality on
//! the energy follows from (CSN-E).

use serde::{Deserialize, Serialize};

use super::{step_system, SchemeState, StepStatistics, TimeIntegrator, Timed};
use crate::engine::contact::ContactStep;
use crate::engine::error::{Error, ParameterError, SolveError};
use crate::engine::linalg::{SolveCounts, StepSolver};
use crate::engine::model::Model;

/// The velocity `W^n` the corrector of (CSN-c) starts from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum PredictorVelocity {
    /// `W^n = V^n`: Deuflhard, Krause and Ertel's update.
    Carried,
    /// `W^n = (U^pred − U^n)/Δt`: the predictor's velocity, energy-dissipative.
    Projected,
}

/// A contact-stabilised Newmark integrator: its two factorised systems and their contact steps.
/// The state it advances carries `(U^n, V^n)`, no acceleration, and the last step's `U^pred`
/// ([`SchemeState::predictor`]), which its energy balance (CSN-E) reads.
#[derive(Debug)]
pub struct ContactStabilisedNewmark<'m> {
    model: &'m Model,
    velocity: PredictorVelocity,
    /// `M + ¼Δt² S`, the corrector's matrix.
    system: StepSolver,
    /// The corrector's contact step (CSN-b).
    contact: Option<ContactStep>,
    /// The mass's solver, kept for its contact step.
    mass: StepSolver,
    /// The predictor's projection (CSN-a).
    projection: Option<ContactStep>,
    /// The projection's multipliers, which its contact step writes (no balance reads them).
    projection_multiplier: Vec<f64>,
    rhs: Vec<f64>,
    scratch: Vec<f64>,
}

impl<'m> ContactStabilisedNewmark<'m> {
    /// Factorises `M` and `M + ¼Δt² S` and prepares their contact steps for `constraints`
    /// contact constraints. Refuses a mass with massless dofs (field `mass`): (CSN-a) is not defined
    /// there (the factory, [`super::integrator`], refuses the treatments other than the
    /// multiplier).
    pub fn new(model: &'m Model, velocity: PredictorVelocity, dt: f64) -> Result<Self, Error> {
        let massless = model.massless_dofs().len();
        if massless > 0 {
            return Err(ParameterError::new(
                "mass",
                format!("a mass with {massless} massless dofs"),
                "a definite mass (standard or lumped) with contact-stabilised Newmark: its \
                 predictor is a projection in the M-norm, which does not see the massless \
                 contact dofs (run the redistributed masses with the other schemes)",
            )
            .into());
        }
        let k = model
            .mass()
            .linear_combination(1.0, model.stiffness(), 0.25 * dt * dt);
        let (system, contact) = step_system(model, k, "contact-stabilised Newmark M + Δt²S/4")?;
        let (mass, projection) = step_system(
            model,
            model.mass().clone(),
            "contact-stabilised Newmark projection M",
        )?;
        let n = model.n_dofs();
        let constraints = model.contact().map_or(0, |c| c.len());
        Ok(Self {
            model,
            velocity,
            system,
            contact,
            mass,
            projection,
            projection_multiplier: vec![0.0; constraints],
            rhs: vec![0.0; n],
            scratch: vec![0.0; n],
        })
    }
}

impl TimeIntegrator for ContactStabilisedNewmark<'_> {
    fn advance(&mut self, state: &mut SchemeState) -> Result<(), SolveError> {
        let (dt, step) = (state.dt, state.step + 1);
        let SchemeState {
            u,
            v,
            lambda,
            predictor,
            ..
        } = state;
        let predictor = predictor.get_or_insert_with(|| vec![0.0; u.len()]);
        // (CSN-a): `U^n + Δt V^n`, projected onto `K` in the `M`-norm.
        for ((p, u), v) in predictor.iter_mut().zip(u.iter()).zip(v.iter()) {
            *p = u + dt * v;
        }
        if let Some(projection) = self.projection.as_mut() {
            projection.enforce(step, predictor, |_, g| g, &mut self.projection_multiplier)?;
        }
        // (CSN-b): `(M + ¼Δt² S) U^{n+1} = M U^pred + ¼Δt² (2F − S U^n)`, then the contact.
        let quarter = 0.25 * dt * dt;
        self.model.stiffness().mul_into(u, &mut self.scratch);
        self.model.mass().mul_into(predictor, &mut self.rhs);
        let load = self.model.load();
        for (k, (r, su)) in self.rhs.iter_mut().zip(&self.scratch).enumerate() {
            let f = load.map_or(0.0, |f| f[k]);
            *r += quarter * (2.0 * f - su);
        }
        self.system.solve(&mut self.rhs, predictor)?;
        if let Some(contact) = self.contact.as_mut() {
            contact.enforce(step, &mut self.rhs, |_, g| g, lambda)?;
            let scale = 2.0 / (dt * dt);
            lambda.iter_mut().for_each(|l| *l *= scale);
        }
        // (CSN-c).
        let start_velocity = self.velocity;
        let levels = u.iter_mut().zip(v.iter_mut()).zip(&self.rhs);
        for (((u, v), u_new), p) in levels.zip(predictor.iter()) {
            let w = match start_velocity {
                PredictorVelocity::Carried => *v,
                PredictorVelocity::Projected => (p - *u) / dt,
            };
            *v = w + 2.0 / dt * (u_new - p);
            *u = *u_new;
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

    /// The steps that needed a complementarity solve, in the corrector or in the projection,
    /// the largest violation of (CSN-a) or (CSN-b), the solves of both matrices, and the
    /// corrector's slab.
    fn statistics(&self) -> StepStatistics {
        let (k, m) = (self.system.counts(), self.mass.counts());
        let step_solves = SolveCounts {
            solves: k.solves + m.solves,
            iterations: k.iterations + m.iterations,
        };
        StepStatistics::of(step_solves, self.contact.iter().chain(&self.projection))
    }
}
