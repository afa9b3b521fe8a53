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
//! | [`factory`] | [`integrator`]: the integrator of a [`Scheme`] on a model with its [`SchemeState`] at `t = 0` | — |
//! | [`conventions`] | [`Conventions`]: the start, the Nitsche acceleration, Paoli–Schatzman's massless rows and first step and the one-step predictor's form, the harness's or GetFEM demo's | — |
//!
//! A scheme is a method ([`TimeIntegrator`]: its operators, factorisations and scratch); the
//! state it advances ([`SchemeState`]) is a value the time loop holds and hands to it at every
//! step, and to the loop's observers with the scheme that computed it ([`Integration`]).
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
pub use factory::{integrator, Integrator};
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

/// Why a method that carries `A^n` may expect it in its state: [`SchemeState::start`] gives
/// `A^0` and the method keeps `A^n` ([`SchemeState::acceleration()`]).
const CARRIES_ACCELERATION: &str =
    "a state handed to a method that carries A^n has it (SchemeState::start gives A^0)";

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

/// The state the time loop holds and hands to its scheme at every step: the step index `n`
/// with `t_n` and the step `Δt`, `U^n`, `V^n` and `λ^n` (the multipliers of the scheme's own
/// equations), and what a method carries beyond them. A scheme ([`TimeIntegrator`]) is the
/// method alone: its operators, their factorisations and its scratch; it reads and writes the
/// state it is handed.
///
/// A vector a method needs beyond `(U^n, V^n, λ^n)` lives here when it is a value of the state
/// `t_n` that something outside the step reads — the next step (`A^n`, `U^{n−1}`), the energy
/// ([`TimeIntegrator::energy`]), the energy balance ([`energy_balance`]), a per-step
/// perturbation ([`TimeIntegrator::perturb_carried`]) or an observer (the reported multiplier).
/// A vector only the step itself reads (a right-hand side, an initial guess, the contact step's
/// multipliers) is the scheme's scratch.
#[derive(Debug, Clone, PartialEq)]
pub struct SchemeState {
    /// `n`.
    step: usize,
    /// `t_n` (`n Δt` for a scheme; another code's sample time for a run replayed).
    time: f64,
    /// `Δt`.
    pub dt: f64,
    /// `U^n`.
    pub u: Vec<f64>,
    /// The velocity the scheme carries (see [`SchemeState::velocity`]).
    pub v: Vec<f64>,
    /// The multipliers of the scheme's equations (see [`SchemeState::scheme_multiplier`]).
    pub lambda: Vec<f64>,
    /// `A^n`, where the method carries an acceleration from one step to the next: the Newmark
    /// family and the θ-method (their predictor, eq. 32a), explicit Newmark, generalised-α
    /// ((GA-a); its balance (GA-E) reads it too). Paoli–Schatzman carries `A^0` to its Newmark
    /// start step only; Moreau–Jean, Laursen–Chawla and contact-stabilised Newmark carry none.
    pub acceleration: Option<Vec<f64>>,
    /// `U^{n−1}`, where the method reads two levels: Paoli–Schatzman's step (eq. 36), its
    /// half-step velocity and energy; explicit Newmark's staggered energy. `None` before the
    /// first step and for the other schemes.
    pub previous: Option<Vec<f64>>,
    /// `U^pred` of the last step, where the method projects a predictor that its energy balance
    /// reads (contact-stabilised Newmark, (CSN-E)); `None` for the others.
    pub predictor: Option<Vec<f64>>,
    /// The multipliers the scheme reports, with the time they approximate, where they are not
    /// `λ^n` at `t_n` (see [`SchemeState::multiplier`]).
    pub reported: Option<Timed<Vec<f64>>>,
}

impl SchemeState {
    /// Step 0 of a run with step `dt`, from its consistent start: `U^0`, `V^0`, `λ^0` and `A^0`
    /// (eq. 32c; [`SchemeState::acceleration()`]).
    pub fn start(dt: f64, initial: InitialState) -> Self {
        Self {
            acceleration: Some(initial.acceleration),
            ..Self::sample(0, 0.0, dt, (initial.displacement, initial.velocity))
                .with_multiplier(initial.multiplier)
        }
    }

    /// The state at step `step`, time `time`, with step `dt`, displacement and velocity
    /// `(u, v)`, no multiplier and nothing carried beyond them: a state that no scheme computed
    /// (another code's sample, a distributed run's part).
    pub fn sample(step: usize, time: f64, dt: f64, (u, v): (Vec<f64>, Vec<f64>)) -> Self {
        Self {
            step,
            time,
            dt,
            u,
            v,
            lambda: Vec::new(),
            acceleration: None,
            previous: None,
            predictor: None,
            reported: None,
        }
    }

    /// This state with the multipliers `λ^n`.
    pub fn with_multiplier(self, lambda: Vec<f64>) -> Self {
        Self { lambda, ..self }
    }

    /// This state without its acceleration, for a method that carries none.
    pub fn without_acceleration(self) -> Self {
        Self {
            acceleration: None,
            ..self
        }
    }

    /// Moves the clock to step `step` at time `time` (a state read from elsewhere).
    pub fn set_clock(&mut self, step: usize, time: f64) {
        self.step = step;
        self.time = time;
    }

    /// Moves the clock one step on: `n + 1`, `t_{n+1} = (n + 1) Δt`.
    fn next_step(&mut self) {
        self.step += 1;
        self.time = self.step as f64 * self.dt;
    }

    /// The index `n` of the state.
    pub fn step_index(&self) -> usize {
        self.step
    }

    /// `t_n`.
    pub fn time(&self) -> f64 {
        self.time
    }

    /// The time step `Δt`.
    pub fn dt(&self) -> f64 {
        self.dt
    }

    /// `U^n`.
    pub fn displacement(&self) -> &[f64] {
        &self.u
    }

    /// The velocity the scheme carries (`V^n`; `(U^n − U^{n−1})/Δt` at `t_{n−½}` for
    /// Paoli–Schatzman).
    pub fn velocity(&self) -> &[f64] {
        &self.v
    }

    /// The contact multipliers (`λ ≤ 0`, one per contact dof) with the time they approximate:
    /// the [scheme's](Self::scheme_multiplier) at `t_n`, unless the scheme reports others
    /// (Paoli–Schatzman's, see [`paoli_schatzman`]; another code's at its own times).
    pub fn multiplier(&self) -> Timed<&[f64]> {
        match &self.reported {
            Some(reported) => Timed {
                time: reported.time,
                value: &reported.value,
            },
            None => Timed {
                time: self.time,
                value: &self.lambda,
            },
        }
    }

    /// The multipliers as the scheme's equations carry them, the ones its energy balance
    /// ([`energy_balance`]) uses: `λ^{n−1}` of eq. (36), which produced `U^n`, for
    /// Paoli–Schatzman (before the rescaling by `1/β` of a massless contact node); the
    /// reported [`multiplier`](Self::multiplier) `λ^n` for the other schemes.
    pub fn scheme_multiplier(&self) -> &[f64] {
        &self.lambda
    }

    /// `A^n`, where the method carries it (the field `acceleration`).
    pub fn acceleration(&self) -> Option<&[f64]> {
        self.acceleration.as_deref()
    }

    /// `U^{n−1}`, where the method carries it ([`SchemeState::previous`]).
    pub fn previous_displacement(&self) -> Option<&[f64]> {
        self.previous.as_deref()
    }

    /// `U^pred` of the last step, where the method projects a predictor
    /// ([`SchemeState::predictor`]).
    pub fn projected_predictor(&self) -> Option<&[f64]> {
        self.predictor.as_deref()
    }

    /// `E_h(U^n, V^n)` (eq. 31, [`Model::energy`]) at `t_n`: the energy of the schemes whose
    /// velocity is `V^n`.
    pub fn mechanical_energy(&self, model: &Model) -> Timed<f64> {
        Timed {
            time: self.time,
            value: model.energy(&self.u, &self.v),
        }
    }

    /// The `U^n`, `V^n` and, where the method carries it, `A^n` of this state, each handed to
    /// `perturb`: the vectors the next step of a one-step method reads.
    fn perturb_levels(&mut self, perturb: &mut dyn FnMut(&mut [f64])) {
        perturb(&mut self.u);
        perturb(&mut self.v);
        if let Some(acceleration) = self.acceleration.as_mut() {
            perturb(acceleration);
        }
    }

    /// A staggered energy `E^{n−½}` at `t_{n−½}`, `half_step(U^{n−1})` computing it from the
    /// previous level; `E_h(U^0, V^0)` at `t = 0` before the first step.
    fn staggered_energy(&self, model: &Model, half_step: impl FnOnce(&[f64]) -> f64) -> Timed<f64> {
        match (self.step, &self.previous) {
            (1.., Some(previous)) => Timed {
                time: (self.step as f64 - 0.5) * self.dt,
                value: half_step(previous),
            },
            _ => self.mechanical_energy(model),
        }
    }
}

/// A time integrator: the method that advances a [`SchemeState`] from `t_n` to `t_{n+1}`,
/// with what only the method knows of a state (its discrete energy) and of its steps (their
/// cost, whether its energy balance holds).
pub trait TimeIntegrator {
    /// Advances `state` from `t_n` to `t_{n+1}`.
    fn advance(&mut self, state: &mut SchemeState) -> Result<(), SolveError>;

    /// The scheme's discrete energy of `state` with the time it approximates (computed on
    /// demand).
    fn energy(&self, state: &SchemeState) -> Timed<f64>;

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

    /// Hands `perturb` every vector of `state` that the last step computed and the next
    /// step reads (a round-off ensemble member's per-step perturbation,
    /// [`crate::engine::problem::StepPerturbation`]), then recomputes what the method derives
    /// from them, so that the state stays consistent. A state no step computes (another
    /// code's run replayed) carries nothing: the default does nothing.
    fn perturb_carried(&self, _state: &mut SchemeState, _perturb: &mut dyn FnMut(&mut [f64])) {}
}

/// A state of the time loop with the scheme that computed it, as the loop hands it to its
/// observers: the state's values (it dereferences to the [`SchemeState`]) and what only the
/// method knows of it.
#[derive(Clone, Copy)]
pub struct Integration<'a> {
    /// The method.
    pub scheme: &'a dyn TimeIntegrator,
    /// The state `t_n`.
    pub state: &'a SchemeState,
}

impl std::ops::Deref for Integration<'_> {
    type Target = SchemeState;

    fn deref(&self) -> &SchemeState {
        self.state
    }
}

impl Integration<'_> {
    /// The scheme's discrete energy of the state ([`TimeIntegrator::energy`]).
    pub fn energy(&self) -> Timed<f64> {
        self.scheme.energy(self.state)
    }

    /// What the scheme's steps so far cost ([`TimeIntegrator::statistics`]).
    pub fn statistics(&self) -> StepStatistics {
        self.scheme.statistics()
    }

    /// Whether the last step's energy balance is an identity ([`TimeIntegrator::balance_holds`]).
    pub fn balance_holds(&self) -> bool {
        self.scheme.balance_holds()
    }

    /// The balance the scheme computed itself ([`TimeIntegrator::own_balance`]).
    pub fn own_balance(&self) -> Option<Option<energy_balance::StepBalance>> {
        self.scheme.own_balance()
    }
}
