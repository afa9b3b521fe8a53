//! Time integrators of the 1D paper (§3.2) and their rivals, written against [`Model`], each
//! equation in the file named after it:
//!
//! | file | what | paper |
//! |---|---|---|
//! | [`newmark`] | Newmark(β, γ): its coefficients, the explicit member β = 0 ([`ExplicitNewmark`]) and the start ([`initial_state`], `A^0` from eq. 32c) | eq. (32) |
//! | [`theta`] | the θ-method's coefficients | eq. (34) |
//! | [`one_step`] | the common form of (32) with β > 0 and (34), contact at `t_{n+1}` ([`OneStepScheme`]) | eqs. (32), (34) |
//! | [`paoli_schatzman`] | the two-step scheme with the contact on `(u^{n+1} + e u^{n−1})/(1 + e)` ([`PaoliSchatzman`]) | eq. (36) |
//! | [`generalised_alpha`] | generalised-α and HHT-α, a rival ([`GeneralisedAlpha`]) | Chung–Hulbert 1993: (GA-a–d) |
//! | [`moreau_jean`] | Moreau–Jean, the θ-method on velocities with Newton's impact law, a rival ([`MoreauJean`]) | Jean 1999: (MJ-a–d) |
//! | [`contact_stabilised_newmark`] | Crank–Nicolson after an `M`-projection of the predictor, both velocity updates, a rival ([`ContactStabilisedNewmark`]) | Deuflhard–Krause–Ertel 2008: (CSN-a–c) |
//! | [`laursen_chawla`] | the energy-conserving persistency scheme, Moreau–Jean (½, e = 1) with the trial's active set, a rival | Laursen–Chawla 1997: (LC-a–d) |
//! | [`energy_balance`] | the discrete energy balances, as per-step residuals | eqs. (33), (35), (37), (GA-E), (MJ-E), (CSN-E) |
//! | [`massless`] | the quasi-static equation of the massless dofs | §3.2 |
//! | [`cfl`] | the stability bound of explicit Newmark | — |
//! | [`scheme`] | [`Scheme`]: names, parameters, validation | Tables 1–2 |
//! | [`statistics`] | [`StepStatistics`]: what the steps cost (step and contact solves, their seconds) and the largest complementarity violation | — |
//! | [`factory`] | [`integrator`]: the integrator of a [`Scheme`] on a model | — |
//! | [`conventions`] | [`Conventions`]: the start, the Nitsche acceleration, Paoli–Schatzman's massless rows and first step and the one-step predictor's form, the harness's or GetFEM demo's | — |
//!
//! Every scheme but contact-stabilised Newmark stays well defined with a singular mass matrix
//! (see [`newmark`], the start); that one refuses it.

pub mod cfl;
pub mod contact_stabilised_newmark;
pub mod conventions;
pub mod energy_balance;
pub mod factory;
pub mod generalised_alpha;
pub mod laursen_chawla;
pub mod massless;
pub mod moreau_jean;
pub mod newmark;
pub mod one_step;
pub mod paoli_schatzman;
pub mod scheme;
pub mod statistics;
pub mod theta;

pub use contact_stabilised_newmark::{ContactStabilisedNewmark, PredictorVelocity};
pub use conventions::Conventions;
pub use factory::integrator;
pub use generalised_alpha::{AlphaParameters, GeneralisedAlpha};
pub use moreau_jean::MoreauJean;
pub use newmark::{initial_state, ExplicitNewmark};
#[doc(hidden)]
pub use one_step::{OneStepScheme, StepCoefficients};
pub use paoli_schatzman::PaoliSchatzman;
pub use scheme::{Scheme, SCHEME_NAMES};
pub use statistics::StepStatistics;

use crate::engine::contact::ContactStep;
use crate::engine::error::SolveError;
use crate::engine::fem::SymmetricMatrix;
use crate::engine::linalg::StepSolver;
use crate::engine::model::Model;

/// The step system `k` of an implicit scheme on `model` (named `name` in errors), solved as
/// the model's solver plan says, and the contact step on it when the model has an obstacle: what
/// the scheme factors once before its steps.
fn step_system(
    model: &Model,
    k: SymmetricMatrix,
    name: &'static str,
) -> Result<(StepSolver, Option<ContactStep>), SolveError> {
    let plan = model.solver_plan();
    let system = StepSolver::new(k, plan.step, name)?;
    let contact = model
        .contact()
        .map(|c| {
            let rows = model.contact_law().rows(c);
            ContactStep::new(c, &rows, &system, model.n_dofs(), plan.contact)
        })
        .transpose()?;
    Ok((system, contact))
}

/// A value with the time it approximates.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Timed<T> {
    /// The time.
    pub time: f64,
    /// The value.
    pub value: T,
}

/// `(U^0, V^0, A^0, λ^0)` consistent with the model's equations at `t = 0`, the state every
/// integrator starts from ([`initial_state`]).
#[derive(Debug, Clone, PartialEq)]
pub struct InitialState {
    /// Displacement (massless dofs in static equilibrium).
    pub displacement: Vec<f64>,
    /// Velocity as given.
    pub velocity: Vec<f64>,
    /// Acceleration from eq. (32c) at `t = 0`.
    pub acceleration: Vec<f64>,
    /// Contact multipliers `λ^0 ≤ 0`.
    pub multiplier: Vec<f64>,
}

/// `R(U) = S U − F` (the internal minus the external force), written into `out`.
pub fn residual_force(model: &Model, u: &[f64], out: &mut [f64]) {
    model.stiffness().mul_into(u, out);
    if let Some(f) = model.load() {
        out.iter_mut().zip(f).for_each(|(o, fi)| *o -= fi);
    }
}

/// The state an integrator updates at every step: the step index `n` with the step `Δt`, and
/// `U^n`, `V^n` and `λ^n`, the multipliers of the scheme's own equations. The accessors of
/// [`TimeIntegrator`] read it, so a scheme writes only its method.
#[derive(Debug, Clone, PartialEq)]
pub struct SchemeState {
    /// `n`.
    pub step: usize,
    /// `Δt`.
    pub dt: f64,
    /// `U^n`.
    pub u: Vec<f64>,
    /// The velocity the scheme carries (see [`TimeIntegrator::velocity`]).
    pub v: Vec<f64>,
    /// The multipliers of the scheme's equations (see [`TimeIntegrator::scheme_multiplier`]).
    pub lambda: Vec<f64>,
}

impl SchemeState {
    /// Step 0 with step `dt`, from `U^0`, `V^0` and `λ^0`.
    pub fn start(dt: f64, u: Vec<f64>, v: Vec<f64>, lambda: Vec<f64>) -> Self {
        Self {
            step: 0,
            dt,
            u,
            v,
            lambda,
        }
    }

    /// A staggered energy `E^{n−½}` at `t_{n−½}`, `half_step()` computing it; `at_start`
    /// (`E_h(U^0, V^0)`) at `t = 0` before the first step.
    pub fn staggered_energy(&self, at_start: f64, half_step: impl FnOnce() -> f64) -> Timed<f64> {
        if self.step == 0 {
            return Timed {
                time: 0.0,
                value: at_start,
            };
        }
        Timed {
            time: (self.step as f64 - 0.5) * self.dt,
            value: half_step(),
        }
    }
}

/// A time integrator holding its state `(U^n, V^n, λ^n)`.
pub trait TimeIntegrator {
    /// Advances from `t_n` to `t_{n+1}`.
    fn advance(&mut self) -> Result<(), SolveError>;
    /// The current state.
    fn state(&self) -> &SchemeState;
    /// The index `n` of the current state.
    fn step_index(&self) -> usize {
        self.state().step
    }
    /// `t_n = n Δt`.
    fn time(&self) -> f64 {
        self.step_index() as f64 * self.dt()
    }
    /// The time step `Δt`.
    fn dt(&self) -> f64 {
        self.state().dt
    }
    /// `U^n`.
    fn displacement(&self) -> &[f64] {
        &self.state().u
    }
    /// The velocity the scheme carries (`V^n`; `(U^n − U^{n−1})/Δt` at `t_{n−½}` for
    /// Paoli–Schatzman).
    fn velocity(&self) -> &[f64] {
        &self.state().v
    }
    /// The contact multipliers (`λ ≤ 0`, one per contact dof) with the time they approximate:
    /// the [scheme's](Self::scheme_multiplier) at `t_n`, unless the scheme reports others.
    fn multiplier(&self) -> Timed<&[f64]> {
        Timed {
            time: self.time(),
            value: &self.state().lambda,
        }
    }
    /// The multipliers as the scheme's equations carry them, the ones its energy balance
    /// ([`energy_balance`]) uses: `λ^{n−1}` of eq. (36), which produced `U^n`, for
    /// Paoli–Schatzman (before the rescaling by `1/β` of a massless contact node); the
    /// reported [`multiplier`](Self::multiplier) `λ^n` for the other schemes.
    fn scheme_multiplier(&self) -> &[f64] {
        &self.state().lambda
    }
    /// `A^n`, where the scheme carries an acceleration that its energy balance needs
    /// (generalised-α, (GA-E)); `None` for the others.
    fn acceleration(&self) -> Option<&[f64]> {
        None
    }
    /// `U^pred` of the last step, where the scheme projects a predictor that its energy balance
    /// needs (contact-stabilised Newmark, (CSN-E)); `None` for the others.
    fn projected_predictor(&self) -> Option<&[f64]> {
        None
    }
    /// The scheme's discrete energy with the time it approximates (computed on demand).
    fn energy(&self) -> Timed<f64>;
    /// What the steps so far cost (step and contact solves) and how well they kept the
    /// contact condition.
    fn statistics(&self) -> StepStatistics;

    /// Whether the scheme's discrete energy balance (1D paper eqs. 33, 35, 37;
    /// [`energy_balance`]) is an identity of the last step: false for a step of explicit
    /// Newmark that stopped a contact dof with mass by a Taylor–Flanagan impulse, which takes
    /// kinetic energy outside the balance.
    fn balance_holds(&self) -> bool {
        true
    }

    /// The balance of the last step where the integrator computes it itself (a distributed
    /// run, whose state no one process holds whole): `Some(None)` before its first step,
    /// `Some(Some(b))` after a step; `None` when the [`energy_balance::BalanceMonitor`] is
    /// to compute it from the states.
    fn own_balance(&self) -> Option<Option<energy_balance::StepBalance>> {
        None
    }

    /// Hands `perturb` every vector of the state that the last step computed and the next
    /// step reads (a round-off ensemble member's per-step perturbation,
    /// [`crate::engine::problem::StepPerturbation`]), then recomputes what the scheme derives
    /// from them, so that the state stays consistent. A state no step computes (another
    /// code's run replayed) carries nothing: the default does nothing.
    fn perturb_carried(&mut self, _perturb: &mut dyn FnMut(&mut [f64])) {}
}
