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
    residual_force, step_system, InitialState, OneStepScheme, SchemeState, StepCoefficients,
    StepStatistics, TimeIntegrator, Timed,
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

/// A Paoli–Schatzman integrator.
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
    /// `λ` is `λ^{n−1}` of eq. (36), which produced `U^n` ([`TimeIntegrator::scheme_multiplier`]).
    state: SchemeState,
    u_prev: Vec<f64>,
    mid: Vec<f64>,
    lambda_reported: Vec<f64>,
    lambda_time: f64,
    energy_at_start: f64,
    work: Vec<f64>,
    force: Vec<f64>,
    next: Vec<f64>,
    pending_start: Option<InitialState>,
}

impl<'m> PaoliSchatzman<'m> {
    /// Factorises `M/Δt² + βS` and prepares the contact correction, with the treatment of the
    /// massless rows and of the first step that `conventions` ask for.
    pub fn new(
        model: &'m Model,
        beta: f64,
        restitution: f64,
        dt: f64,
        start: InitialState,
        conventions: &Conventions,
    ) -> Result<Self, SolveError> {
        let k = model
            .mass()
            .linear_combination(1.0 / (dt * dt), model.stiffness(), beta);
        let (system, contact) = step_system(model, k, "Paoli–Schatzman system M/Δt² + βS")?;
        let n = model.n_dofs();
        let energy_at_start = model.energy(&start.displacement, &start.velocity);
        let three_level = conventions.paoli_schatzman_massless_rows == MasslessRows::ThreeLevel;
        let three_level_start = three_level.then(|| {
            let massless = model.massless_dofs();
            let mut start_force = Vec::new();
            if let Some(c) = model.contact() {
                for (&d, &l) in c.dofs.iter().zip(&start.multiplier) {
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
            state: SchemeState::start(
                dt,
                start.displacement.clone(),
                start.velocity.clone(),
                start.multiplier.clone(),
            ),
            u_prev: start.displacement.clone(),
            mid: start.displacement.clone(),
            lambda_reported: start.multiplier.clone(),
            lambda_time: 0.0,
            energy_at_start,
            work: vec![0.0; n],
            force: vec![0.0; n],
            next: vec![0.0; n],
            pending_start: Some(start),
        })
    }

    /// `U^{n−1}`.
    pub fn previous_displacement(&self) -> &[f64] {
        &self.u_prev
    }

    /// β.
    pub fn beta(&self) -> f64 {
        self.beta
    }

    fn start_step(&mut self, start: InitialState) -> Result<(), SolveError> {
        let mut first = OneStepScheme::new(
            self.model,
            StepCoefficients::newmark(self.beta, 0.5),
            self.state.dt,
            start,
            NitscheAcceleration::Consistent,
        )?
        .with_predictor(self.predictor);
        match (self.first_step, self.model.contact()) {
            (FirstStepContact::PreviousEqualsInitial, Some(set)) => {
                let (e, u0) = (self.restitution, &self.state.u);
                first.advance_with_gap(|i, g| e * u0[set.dofs[i]] + (1.0 + e) * g)?;
            }
            _ => first.advance()?,
        }
        self.start_statistics = first.statistics();
        self.u_prev.copy_from_slice(&self.state.u);
        self.state.u.copy_from_slice(first.displacement());
        self.state.lambda.copy_from_slice(first.multiplier().value);
        // A massless contact node reports the force at t_1 that the Newmark start step imposed;
        // a node with mass keeps reporting λ^0 at t_0 until eq. (36) yields λ^1.
        if self.massless_contact {
            self.lambda_reported
                .copy_from_slice(first.multiplier().value);
            self.lambda_time = self.state.dt;
        }
        Ok(())
    }

    fn two_step(&mut self) -> Result<(), SolveError> {
        let (beta, e, dt) = (self.beta, self.restitution, self.state.dt);
        let levels = || self.state.u.iter().zip(&self.u_prev);
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
            Some(start_force) if self.state.step == 1 => {
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
            let u_prev = &self.u_prev;
            contact.enforce(
                self.state.step + 1,
                &mut self.next,
                |i, g| e * u_prev[set.dofs[i]] + (1.0 + e) * g,
                &mut self.state.lambda,
            )?;
        }
        std::mem::swap(&mut self.u_prev, &mut self.state.u);
        std::mem::swap(&mut self.state.u, &mut self.next);
        if self.massless_contact {
            for (r, l) in self.lambda_reported.iter_mut().zip(&self.state.lambda) {
                *r = l / beta;
            }
            self.lambda_time = (self.state.step + 1) as f64 * dt;
        } else {
            self.lambda_reported.copy_from_slice(&self.state.lambda);
            self.lambda_time = self.state.step as f64 * dt;
        }
        Ok(())
    }
}

impl PaoliSchatzman<'_> {
    /// The half-step velocity and mean from the two levels `U^{n−1}`, `U^n` ([`half_step`]).
    fn update_half_step(&mut self) {
        half_step(
            self.state.dt,
            &self.u_prev,
            &self.state.u,
            &mut self.state.v,
            &mut self.mid,
        );
    }
}

impl TimeIntegrator for PaoliSchatzman<'_> {
    fn advance(&mut self) -> Result<(), SolveError> {
        match self.pending_start.take() {
            Some(start) => self.start_step(start)?,
            None => self.two_step()?,
        }
        self.update_half_step();
        self.state.step += 1;
        Ok(())
    }

    /// `U^{n+1}`, the one level the step computed (`U^n`, the other level the next step
    /// reads, was perturbed when it was computed); the half-step velocity and mean are
    /// recomputed from the perturbed level.
    fn perturb_carried(&mut self, perturb: &mut dyn FnMut(&mut [f64])) {
        perturb(&mut self.state.u);
        self.update_half_step();
    }

    fn state(&self) -> &SchemeState {
        &self.state
    }

    fn multiplier(&self) -> Timed<&[f64]> {
        Timed {
            time: self.lambda_time,
            value: &self.lambda_reported,
        }
    }

    fn energy(&self) -> Timed<f64> {
        let (model, beta, dt) = (self.model, self.beta, self.state.dt);
        self.state.staggered_energy(self.energy_at_start, || {
            energy_of_half_step(model, beta, dt, &self.mid, &self.state.v)
        })
    }

    /// The start step's contact solves and violation with the two-step's own (its step solves
    /// and slab are the two-step's alone).
    fn statistics(&self) -> StepStatistics {
        StepStatistics::of(self.system.counts(), &self.contact)
            .after_contact_of(&self.start_statistics)
    }
}
