//! The Paoli–Schatzman scheme, 1D paper eq. (36), γ = ½, two steps:
//! ```text
//! M (U^{n+1} − 2U^n + U^{n−1}) / Δt² + β R(U^{n+1}) + P [(1 − 2β) R(U^n) + β R(U^{n−1})] = −Bᵀλ^n
//! 0 ≤ (B U^{n+1} + e B U^{n−1}) / (1 + e) + g ⟂ λ^n ≤ 0,          R(U) = S U − F
//! ```
//! `P` is the orthogonal projection onto `(ker M)^⊥` — the identity for the standard mass. With
//! the redistributed mass, the rows of `ker M` then read `R(U^{n+1}) = −Bᵀλ^n / β`: the massless
//! contact node is in static equilibrium at `t_{n+1}` with the contact force `λ^n / β`, which is
//! the multiplier this scheme reports (at `t_{n+1}`). Without `P` those rows would impose the
//! equilibrium on a three-level average, whose `(−1)^n` mode is undamped (the paper's reason for
//! the projection, §3.2). With the standard mass the reported multiplier is `λ^n` at `t_n`.
//!
//! With [`MasslessRows::ThreeLevel`] (GetFEM's demo) `P` is the identity: the rows of `ker M`
//! impose `β R(U^{n+1}) + (1 − 2β) R(U^n) + β R(U^{n−1}) = −Bᵀλ^n`, where the residual of `U^0`
//! is the one the start imposed, `R(U^0) + Bᵀλ^0` (zero on a massless contact dof under either
//! [`super::conventions::Start`]); `λ^n` is then reported at `t_n`, as with the standard mass.
//!
//! `U^1` comes from one Newmark(β, ½) step (the one-step scheme whose two-step form this is),
//! with the contact on `U^1` ([`FirstStepContact::AtNewStep`]) or on `(U^1 + e U^0)/(1 + e)`
//! ([`FirstStepContact::PreviousEqualsInitial`], GetFEM's `U₋₁ = U0`). The energy is the half-step quantity ([`HalfStep::energy`])
//! `E^{n−½} = ½ V^{n−½}ᵀ (M + (β − ¼)Δt² S) V^{n−½} + ½ Ūᵀ S Ū − Fᵀ Ū`, `Ū = (U^n + U^{n−1})/2`,
//! `V^{n−½} = (U^n − U^{n−1})/Δt`, at `t_{n−½}`; for β = ¼ it is the paper's. Its balance is
//! eq. (37) ([`super::energy_balance::paoli_schatzman`]).

use super::conventions::{
    Conventions, FirstStepContact, MasslessRows, NitscheAcceleration, PredictorForm,
};
use super::{
    residual_force, step_system, OneStepScheme, SchemeState, StepCoefficients, StepStatistics,
    TimeIntegrator, Timed,
};
use crate::engine::contact::ContactStep;
use crate::engine::error::SolveError;
use crate::engine::linalg::StepSolver;
use crate::engine::model::Model;

/// `V^{n−½} = (U^n − U^{n−1})/Δt` into `velocity` and `Ū = (U^n + U^{n−1})/2` into `mean`, from
/// `U^{n−1}` (`earlier`) and `U^n` (`later`).
fn half_step(dt: f64, earlier: &[f64], later: &[f64], velocity: &mut [f64], mean: &mut [f64]) {
    let levels = later.iter().zip(earlier);
    for ((v, m), (u, up)) in velocity.iter_mut().zip(mean.iter_mut()).zip(levels) {
        *v = (u - up) / dt;
        *m = 0.5 * (u + up);
    }
}

/// `E^{n−½} = ½ V^{n−½}ᵀ (M + (β − ¼)Δt² S) V^{n−½} + ½ Ūᵀ S Ū − Fᵀ Ū` from `Ū` and `V^{n−½}`.
fn energy_of_half_step(model: &Model, beta: f64, dt: f64, mean: &[f64], velocity: &[f64]) -> f64 {
    // The (β − ¼)Δt² VᵀSV term vanishes for the paper's β = ¼: skip its product.
    let correction = if beta == 0.25 {
        0.0
    } else {
        0.5 * (beta - 0.25) * dt * dt * model.stiffness().quadratic_form(velocity)
    };
    model.energy(mean, velocity) + correction
}

/// The half-step state of Paoli–Schatzman at `t_{n−½}`: `V^{n−½} = (U^n − U^{n−1})/Δt` and
/// `Ū = (U^n + U^{n−1})/2`, with the energy its balance (eq. 37) is written for.
#[derive(Debug, Clone, PartialEq)]
pub struct HalfStep {
    /// `V^{n−½}`.
    pub velocity: Vec<f64>,
    /// `Ū`.
    pub mean: Vec<f64>,
}

impl HalfStep {
    /// The half step between `U^{n−1}` (`earlier`) and `U^n` (`later`).
    pub fn between(dt: f64, earlier: &[f64], later: &[f64]) -> Self {
        let mut velocity = vec![0.0; later.len()];
        let mut mean = vec![0.0; later.len()];
        half_step(dt, earlier, later, &mut velocity, &mut mean);
        Self { velocity, mean }
    }

    /// `E^{n−½} = ½ V^{n−½}ᵀ (M + (β − ¼)Δt² S) V^{n−½} + ½ Ūᵀ S Ū − Fᵀ Ū`, the energy the
    /// integrator reports (see the module documentation).
    pub fn energy(&self, model: &Model, beta: f64, dt: f64) -> f64 {
        energy_of_half_step(model, beta, dt, &self.mean, &self.velocity)
    }
}

/// A Paoli–Schatzman integrator: its factorised step matrix and contact step, and how it treats
/// the massless rows and the first step. The state it advances carries `U^{n−1}`
/// ([`SchemeState::previous`]), which its step reads, with the half-step velocity `V^{n−½}` as
/// its velocity, `λ^{n−1}` of eq. (36) as the scheme's multipliers
/// ([`SchemeState::scheme_multiplier`]) and, with `U^{n+1}`, the multipliers it reports
/// ([`SchemeState::reported`]): `λ^n / β` at `t_{n+1}` with a massless contact node, `λ^n` at
/// `t_n` otherwise.
#[derive(Debug)]
pub struct PaoliSchatzman<'m> {
    model: &'m Model,
    beta: f64,
    restitution: f64,
    /// Whether every contact dof is massless and the rows of `ker M` are projected (decides
    /// which multiplier is reported).
    massless_contact: bool,
    first_step: FirstStepContact,
    /// How the first step's one-step scheme sums its predictor.
    predictor: PredictorForm,
    /// `β (Bᵀλ^0)_z` on the massless dofs `z` of the three-level rows, added to the force of
    /// the first two-step; `None` when the rows are projected.
    three_level_start: Option<Vec<(usize, f64)>>,
    system: StepSolver,
    contact: Option<ContactStep>,
    /// The contact work of the start step ([`OneStepScheme`]).
    start_statistics: StepStatistics,
    work: Vec<f64>,
    force: Vec<f64>,
    next: Vec<f64>,
}

impl<'m> PaoliSchatzman<'m> {
    /// Factorises `M/Δt² + βS` and prepares the contact correction, with the treatment of the
    /// massless rows and of the first step that `conventions` ask for; `initial_multiplier` is
    /// the start's `λ^0`.
    pub fn new(
        model: &'m Model,
        (beta, restitution): (f64, f64),
        dt: f64,
        initial_multiplier: &[f64],
        conventions: &Conventions,
    ) -> Result<Self, SolveError> {
        let k = model
            .mass()
            .linear_combination(1.0 / (dt * dt), model.stiffness(), beta);
        let (system, contact) = step_system(model, k, "Paoli–Schatzman system M/Δt² + βS")?;
        let n = model.n_dofs();
        let three_level = conventions.paoli_schatzman_massless_rows == MasslessRows::ThreeLevel;
        let three_level_start = three_level.then(|| {
            let massless = model.massless_dofs();
            let mut start_force = Vec::new();
            if let Some(c) = model.contact() {
                for (&d, &l) in c.dofs.iter().zip(initial_multiplier) {
                    if massless.binary_search(&d).is_ok() {
                        start_force.push((d, beta * l));
                    }
                }
            }
            start_force
        });
        Ok(Self {
            model,
            beta,
            restitution,
            massless_contact: model.contact_is_massless() && !three_level,
            first_step: conventions.paoli_schatzman_first_step,
            predictor: conventions.predictor,
            three_level_start,
            system,
            contact,
            start_statistics: StepStatistics::default(),
            work: vec![0.0; n],
            force: vec![0.0; n],
            next: vec![0.0; n],
        })
    }

    /// β.
    pub fn beta(&self) -> f64 {
        self.beta
    }

    /// `U^1` from `U^0` by one Newmark(β, ½) step, `A^0` dropped after it.
    fn start_step(&mut self, state: &mut SchemeState) -> Result<(), SolveError> {
        let mut first = OneStepScheme::new(
            self.model,
            StepCoefficients::newmark(self.beta, 0.5),
            state.dt,
            NitscheAcceleration::Consistent,
        )?
        .with_predictor(self.predictor);
        let u0 = state.u.clone();
        // A massless contact node reports the force at t_1 that the Newmark start step imposes;
        // a node with mass keeps reporting λ^0 at t_0 until eq. (36) yields λ^1.
        let lambda0 = state.lambda.clone();
        match (self.first_step, self.model.contact()) {
            (FirstStepContact::PreviousEqualsInitial, Some(set)) => {
                let e = self.restitution;
                first.advance_with_gap(state, |i, g| e * u0[set.dofs[i]] + (1.0 + e) * g)?;
            }
            _ => first.advance(state)?,
        }
        self.start_statistics = first.statistics();
        state.acceleration = None;
        state.previous = Some(u0);
        state.reported = Some(if self.massless_contact {
            Timed {
                time: state.dt,
                value: state.lambda.clone(),
            }
        } else {
            Timed {
                time: 0.0,
                value: lambda0,
            }
        });
        Ok(())
    }

    fn two_step(&mut self, state: &mut SchemeState) -> Result<(), SolveError> {
        let (beta, e, dt, step) = (self.beta, self.restitution, state.dt, state.step);
        let SchemeState {
            u,
            lambda,
            previous,
            reported,
            ..
        } = state;
        let u_prev = previous
            .as_mut()
            .expect("Paoli–Schatzman's state after its start step carries U^{n−1}");
        let levels = || u.iter().zip(u_prev.iter());
        for (w, (u, up)) in self.work.iter_mut().zip(levels()) {
            *w = (1.0 - 2.0 * beta) * u + beta * up;
        }
        // P [(1 − 2β) R(U^n) + β R(U^{n−1})], R(U) = S U − F, F constant in time.
        residual_force(self.model, &self.work, &mut self.force);
        if let Some(f) = self.model.load() {
            self.force
                .iter_mut()
                .zip(f)
                .for_each(|(r, fi)| *r += beta * fi);
        }
        match &self.three_level_start {
            None => {
                for &z in self.model.massless_dofs() {
                    self.force[z] = 0.0;
                }
            }
            Some(start_force) if step == 1 => {
                for &(z, f) in start_force {
                    self.force[z] += f;
                }
            }
            Some(_) => {}
        }
        for (w, (u, up)) in self.work.iter_mut().zip(levels()) {
            *w = (2.0 * u - up) / (dt * dt);
        }
        self.model.mass().mul_into(&self.work, &mut self.next);
        self.next
            .iter_mut()
            .zip(&self.force)
            .for_each(|(r, f)| *r -= f);
        if let Some(f) = self.model.load() {
            self.next
                .iter_mut()
                .zip(f)
                .for_each(|(r, fi)| *r += beta * fi);
        }
        // The linear extrapolation 2U^n − U^{n−1} is the iterative solver's initial guess.
        for (w, (u, up)) in self.work.iter_mut().zip(levels()) {
            *w = 2.0 * u - up;
        }
        self.system.solve(&mut self.next, &self.work)?;
        if let (Some(contact), Some(set)) = (self.contact.as_mut(), self.model.contact()) {
            let u_prev = &*u_prev;
            contact.enforce(
                step + 1,
                &mut self.next,
                |i, g| e * u_prev[set.dofs[i]] + (1.0 + e) * g,
                lambda,
            )?;
        }
        std::mem::swap(u_prev, u);
        std::mem::swap(u, &mut self.next);
        let reported = reported
            .as_mut()
            .expect("Paoli–Schatzman's state after its start step carries its report");
        if self.massless_contact {
            for (r, l) in reported.value.iter_mut().zip(lambda.iter()) {
                *r = l / beta;
            }
            reported.time = (step + 1) as f64 * dt;
        } else {
            reported.value.copy_from_slice(lambda);
            reported.time = step as f64 * dt;
        }
        state.next_step();
        Ok(())
    }
}

/// The half-step velocity `V^{n−½} = (U^n − U^{n−1})/Δt` of `state` from its two levels
/// (as [`half_step`]; the energy recomputes `Ū`).
fn update_half_step(state: &mut SchemeState) {
    let SchemeState {
        dt, u, v, previous, ..
    } = state;
    if let Some(previous) = previous {
        for ((v, u), up) in v.iter_mut().zip(u.iter()).zip(previous.iter()) {
            *v = (u - up) / *dt;
        }
    }
}

impl TimeIntegrator for PaoliSchatzman<'_> {
    fn advance(&mut self, state: &mut SchemeState) -> Result<(), SolveError> {
        if state.step == 0 {
            self.start_step(state)?;
        } else {
            self.two_step(state)?;
        }
        update_half_step(state);
        Ok(())
    }

    /// `U^{n+1}`, the one level the step computed (`U^n`, the other level the next step
    /// reads, was perturbed when it was computed); the half-step velocity is recomputed from
    /// the perturbed level.
    fn perturb_carried(&self, state: &mut SchemeState, perturb: &mut dyn FnMut(&mut [f64])) {
        perturb(&mut state.u);
        update_half_step(state);
    }

    fn energy(&self, state: &SchemeState) -> Timed<f64> {
        let (model, beta, dt) = (self.model, self.beta, state.dt);
        state.staggered_energy(model, |previous| {
            let mean: Vec<f64> = (state.u.iter().zip(previous))
                .map(|(u, up)| 0.5 * (u + up))
                .collect();
            energy_of_half_step(model, beta, dt, &mean, &state.v)
        })
    }

    /// The start step's contact solves and violation with the two-step's own (its step solves
    /// and slab are the two-step's alone).
    fn statistics(&self) -> StepStatistics {
        StepStatistics::of(self.system.counts(), &self.contact)
            .after_contact_of(&self.start_statistics)
    }
}
