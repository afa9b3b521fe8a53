//! The Newmark family, 1D paper eq. (32), with its start and its explicit member β = 0:
//! ```text
//! U^{n+1} = U^n + Δt V^n + Δt² ((½ − β) A^n + β A^{n+1})            (32a)
//! V^{n+1} = V^n + Δt ((1 − γ) A^n + γ A^{n+1})                       (32b)
//! M A^{n+1} + S U^{n+1} = F − Bᵀλ^{n+1}                              (32c)
//! 0 ≤ B U^{n+1} + g ⟂ λ^{n+1} ≤ 0                                     (32d)
//! ```
//!
//! * **β > 0** is implicit: the coefficients `(a, b, c, d) = (½ − β, β, 1 − γ, γ)` of the common
//!   one-step form ([`StepCoefficients::newmark`]) drive [`super::OneStepScheme`], shared with the
//!   θ-method ([`super::theta`], eq. 34).
//! * **β = 0** is explicit ([`ExplicitNewmark`], central differences for γ = ½), with its CFL
//!   bound ([`super::cfl`]) checked before the run.
//! * **The start** ([`initial_state`]): `U^0`, `V^0` are given and `A^0` follows from (32c) at
//!   `t = 0` ("`U_{h,tt}^0` is evaluated by using (32c)"; the same for the θ-method's 34c); it is
//!   the initial state of every scheme.
//!
//! The energy balance of (32) is eq. (33) ([`super::energy_balance::newmark`]).
//!
//! # The start with a singular mass
//!
//! With the redistributed mass the contact node carries no inertia: its equation is the static
//! one, `(S U − F + Bᵀλ)_Z = 0` on the massless dofs `Z`, with the contact condition. Given
//! data need not satisfy it (the Dirichlet benchmark starts with `u_0 = ½` but a strained first
//! element). Two starts are offered ([`Start`]):
//!
//! * [`Start::Static`] (the default): the massless dofs of `U^0` are replaced by the solution of
//!   that static contact problem with the other dofs fixed ([`QuasiStatic`]), which also yields
//!   `λ^0`;
//! * [`Start::ImplicitMultiplier`] (the paper's and GetFEM's): `U^0` is kept and the rows `Z` of
//!   (32c) are not imposed at `t = 0`; a massless contact dof reports the multiplier they imply,
//!   `λ^0 = −(S U^0 − F)_c`. The first step restores the static equation.
//!
//! The initial acceleration solves `M_RR A_R = (F − S U^0 − Bᵀλ^0)_R` on the dofs `R` that
//! carry mass (eq. 32c at `t = 0`); `A_Z = 0` (it never enters `M A`).
//!
//! For the standard mass `Z` is empty, `U^0` is the given data, `λ^0 = 0`, and both starts are
//! the same.
//!
//! A penalty or Nitsche treatment ([`crate::engine::contact::law`]) makes the force a function of the
//! displacement: the static problem on `Z` is solved with it, and `λ^0` is that force at `U^0`
//! (enters eq. 32c with its force vectors `f_i`).
//!
//! # Explicit Newmark, β = 0
//!
//! Eq. (32) with β = 0, split into the dofs with mass `R` and the massless dofs `Z` (zero rows
//! of `M`):
//!
//! * `U_R^{n+1}` is explicit (32a);
//! * `U_Z^{n+1}` solves the rows `Z` of (32c), which have no inertia:
//!   `S_ZZ U_Z = (F − S_ZR U_R)_Z − (Bᵀλ)_Z` with the contact condition, a small
//!   complementarity problem ([`QuasiStatic`]);
//! * `A_R^{n+1} = M_RR⁻¹ (F − S U^{n+1})_R` (one solve with `M_RR` factorised once: a diagonal
//!   for the lumped mass, a band or sparse Cholesky for the consistent ones); `A_Z = 0` and
//!   `V_Z` is the difference quotient, as in the implicit schemes (they never enter `M A`).
//!
//! **Contact.** A massless contact dof (`redistributed`, `redistributed-conserving`,
//! `singular-dynamic`, GetFEM's two) is in the static rows: the contact force only acts there
//! and the step stays explicit on `R`. A contact dof with mass (`standard`, `lumped`) gets the
//! Taylor–Flanagan step ([`TaylorFlanagan`]; GetFEM demo's version 4): when the predictor
//! penetrates while approaching, `B_A U^{n+1} + g_A < 0` and `B_A Ṽ < 0` on the set `A`, the
//! impulse `s` that stops those dofs,
//! `(B_A M⁻¹ B_Aᵀ) s = B_A Ṽ / Δt` with `Ṽ = V^n + Δt(1 − γ)A^n`, is applied to the velocity and
//! the displacement, `Ṽ ← Ṽ − Δt M⁻¹B_Aᵀ s`, `U^{n+1} ← U^{n+1} − Δt² M⁻¹B_Aᵀ s` (so `B_A Ṽ = 0`),
//! and `λ_A = s`. It is not the Signorini condition at `t_{n+1}` (the node may stay below the
//! obstacle by `O(Δt²)` until it leaves) and dissipates the kinetic energy of the stopped
//! dofs, so the explicit energy balance below holds only away from those steps.
//!
//! **Stability.** The run is refused before the first step when `Δt > √(2/γ)/ω_max`
//! ([`super::cfl`]; `2/ω_max` for central differences) with [`SolveError::CflViolated`].
//!
//! **Energy.** The scheme reports the staggered energy [`staggered_energy`]
//! `E^{n+½} = ½ V^{n+½}ᵀ M V^{n+½} + ½ U^{n+1}ᵀ S U^n − ½ Fᵀ(U^{n+1} + U^n)`,
//! `V^{n+½} = (U^{n+1} − U^n)/Δt`, at `t_{n+½}`. With γ = ½ it changes by the contact work alone
//! and is conserved to round-off without contact
//! ([`super::energy_balance::central_difference`]).

use super::cfl::{largest_eigenvalue, stable_step};
use super::conventions::{Conventions, NitscheAcceleration, Start};
use super::massless::QuasiStatic;
use super::{
    residual_force, InitialState, SchemeState, StepCoefficients, StepStatistics, TimeIntegrator,
    Timed, CARRIES_ACCELERATION,
};
use crate::engine::contact::law::sparse_dot;
use crate::engine::error::SolveError;
use crate::engine::linalg::{SpdSolver, StepSolver};
use crate::engine::model::{ContactSet, Model};

impl StepCoefficients {
    /// Newmark(β, γ), eq. (32a–b): `(a, b, c, d) = (½ − β, β, 1 − γ, γ)`.
    pub fn newmark(beta: f64, gamma: f64) -> Self {
        Self {
            a: 0.5 - beta,
            b: beta,
            c: 1.0 - gamma,
            d: gamma,
        }
    }
}

/// Builds the initial state from the given displacement and velocity dofs under
/// `conventions`: the massless dofs of `U^0` in static equilibrium ([`Start::Static`]) or kept
/// with the implicit multiplier `λ⁰ = −(S U⁰ − F)_c` of a massless contact dof
/// ([`Start::ImplicitMultiplier`]), and `A^0` from eq. (32c) at `t = 0` on the dofs with mass
/// (with the elastic stiffness for [`NitscheAcceleration::ElasticStiffness`]); see the module
/// documentation.
pub fn initial_state(
    model: &Model,
    u0: &[f64],
    v0: &[f64],
    conventions: &Conventions,
) -> Result<InitialState, SolveError> {
    let n = model.n_dofs();
    let mut u = u0.to_vec();
    let n_contact = model.contact().map_or(0, ContactSet::len);
    let mut lambda = vec![0.0; n_contact];
    if conventions.start == Start::Static {
        if let Some(mut statics) = QuasiStatic::new(model)? {
            statics.solve(model, 0, &mut u, &mut lambda)?;
        }
    }
    let mut rhs = vec![0.0; n];
    residual_force(model, &u, &mut rhs);
    if let Some(c) = model.contact() {
        if conventions.start == Start::ImplicitMultiplier {
            let massless = model.massless_dofs();
            for (l, &d) in lambda.iter_mut().zip(&c.dofs) {
                if massless.binary_search(&d).is_ok() {
                    *l = -rhs[d];
                }
            }
        }
        if let Some(forces) = model.contact_law().forces(c, &u) {
            lambda = forces;
        }
    }
    rhs.iter_mut().for_each(|r| *r = -*r);
    if let Some(c) = model.contact() {
        for (row, &l) in model.contact_law().rows(c).iter().zip(&lambda) {
            for &(k, coef) in &row.force {
                rhs[k] -= coef * l;
            }
        }
    }
    if conventions.nitsche_acceleration == NitscheAcceleration::ElasticStiffness {
        if let Some((a, scale)) = model.contact_law().stiffness_update() {
            let stress = sparse_dot(a, &u);
            for &(k, ak) in a {
                rhs[k] += scale * stress * ak;
            }
        }
    }
    let with_mass = model.dofs_with_mass();
    let mut acceleration = vec![0.0; n];
    if !with_mass.is_empty() {
        let m_rr = model.mass().principal_submatrix(&with_mass);
        let mut solver =
            StepSolver::new(m_rr, model.solver_plan().step, "mass (dofs with inertia)")?;
        let mut a_r: Vec<f64> = with_mass.iter().map(|&i| rhs[i]).collect();
        solver.solve(&mut a_r, &vec![0.0; with_mass.len()])?;
        for (&i, a) in with_mass.iter().zip(a_r) {
            acceleration[i] = a;
        }
    }
    Ok(InitialState {
        displacement: u,
        velocity: v0.to_vec(),
        acceleration,
        multiplier: lambda,
    })
}

/// The staggered energy of explicit Newmark at `t_{n+½}`, from `U^n` (`earlier`) and `U^{n+1}`
/// (`later`): `E^{n+½} = ½ V^{n+½}ᵀ M V^{n+½} + ½ U^{n+1}ᵀ S U^n − ½ Fᵀ(U^{n+1} + U^n)`,
/// `V^{n+½} = (U^{n+1} − U^n)/Δt` (see the module documentation).
pub fn staggered_energy(model: &Model, dt: f64, earlier: &[f64], later: &[f64]) -> f64 {
    let inv_dt = 1.0 / dt;
    let half_step: Vec<f64> = (later.iter().zip(earlier))
        .map(|(u, up)| (u - up) * inv_dt)
        .collect();
    let kinetic = 0.5 * model.mass().quadratic_form(&half_step);
    let strain = 0.5 * model.stiffness().bilinear_form(later, earlier);
    let load = model.load().map_or(0.0, |f| {
        0.5 * (f.iter().zip(later.iter().zip(earlier)))
            .map(|(fi, (u, up))| fi * (u + up))
            .sum::<f64>()
    });
    kinetic + strain - load
}

/// The Taylor–Flanagan contact step of the contact dofs with mass (see the module
/// documentation): `(B_A M⁻¹ B_Aᵀ) s = B_A Ṽ / Δt` on the penetrating set `A`.
#[derive(Debug)]
struct TaylorFlanagan {
    /// `(contact index, dof)` of the contact dofs with mass.
    dofs: Vec<(usize, usize)>,
    /// The position of each dof among the dofs with mass `R`.
    position: Vec<usize>,
    /// The dofs with mass `R`.
    with_mass: Vec<usize>,
}

impl TaylorFlanagan {
    /// The contact dofs of `model` that carry mass; `None` when there are none.
    fn new(model: &Model, with_mass: &[usize]) -> Option<Self> {
        let c = model.contact()?;
        let (dofs, position): (Vec<_>, Vec<_>) = (c.dofs.iter().enumerate())
            .filter_map(|(k, &d)| with_mass.binary_search(&d).ok().map(|p| ((k, d), p)))
            .unzip();
        (!dofs.is_empty()).then(|| Self {
            dofs,
            position,
            with_mass: with_mass.to_vec(),
        })
    }

    /// Stops the penetrating dofs that approach the obstacle (`Ṽ < 0`: a receding dof gets no
    /// adhesive impulse; GetFEM's demo, which tests the penetration only, never met one): corrects `next` (`U^{n+1}`) and `velocity` (`Ṽ`, on the
    /// dofs with mass `R`, indexed by position) and writes their impulses into `lambda` (zero for
    /// the others).
    fn apply(
        &self,
        set: &ContactSet,
        mass: &SpdSolver,
        dt: f64,
        next: &mut [f64],
        velocity: &mut [f64],
        lambda: &mut [f64],
    ) -> Result<bool, SolveError> {
        let active: Vec<usize> = (0..self.dofs.len())
            .filter(|&i| {
                let (k, d) = self.dofs[i];
                next[d] + set.gaps[k] < 0.0 && velocity[self.position[i]] < 0.0
            })
            .collect();
        for &(k, _) in &self.dofs {
            lambda[k] = 0.0;
        }
        if active.is_empty() {
            return Ok(false);
        }
        let columns: Vec<Vec<f64>> = active
            .iter()
            .map(|&i| {
                let mut col = vec![0.0; self.with_mass.len()];
                col[self.position[i]] = 1.0;
                mass.solve_in_place(&mut col);
                col
            })
            .collect();
        let m = active.len();
        let delassus =
            nalgebra::DMatrix::from_fn(m, m, |r, c| columns[c][self.position[active[r]]]);
        let stopped = nalgebra::DVector::from_fn(m, |r, _| velocity[self.position[active[r]]] / dt);
        let impulse = delassus
            .cholesky()
            .ok_or_else(|| SolveError::Factorization {
                matrix: "Taylor–Flanagan Delassus operator B M⁻¹ Bᵀ",
                detail: "Cholesky failed".to_string(),
            })?
            .solve(&stopped);
        for (col, &s) in columns.iter().zip(impulse.iter()) {
            for ((v, &i), c) in velocity.iter_mut().zip(&self.with_mass).zip(col) {
                *v -= dt * s * c;
                next[i] -= dt * dt * s * c;
            }
        }
        for (&i, &s) in active.iter().zip(impulse.iter()) {
            lambda[self.dofs[i].0] = s;
        }
        Ok(true)
    }
}

/// Explicit Newmark(0, γ): the factorised `M_RR`, the static rows of the massless dofs and the
/// Taylor–Flanagan step. The state it advances carries `A^n` ([`SchemeState::acceleration()`]),
/// which its update reads, and `U^{n−1}` ([`SchemeState::previous`]), which its staggered
/// energy reads.
#[derive(Debug)]
pub struct ExplicitNewmark<'m> {
    model: &'m Model,
    gamma: f64,
    with_mass: Vec<usize>,
    mass_solver: Option<SpdSolver>,
    statics: Option<QuasiStatic>,
    taylor_flanagan: Option<TaylorFlanagan>,
    /// Whether the last step applied a Taylor–Flanagan impulse.
    impulse: bool,
    stable_dt: f64,
    next: Vec<f64>,
    force: Vec<f64>,
    force_r: Vec<f64>,
}

impl<'m> ExplicitNewmark<'m> {
    /// Checks the CFL bound, then factorises `M_RR` and prepares the contact steps (static
    /// for massless contact dofs, Taylor–Flanagan for the others).
    pub fn new(model: &'m Model, gamma: f64, dt: f64) -> Result<Self, SolveError> {
        let n = model.n_dofs();
        let with_mass = model.dofs_with_mass();
        let (mass_solver, stable_dt) = if with_mass.is_empty() {
            (None, f64::INFINITY)
        } else {
            let m_rr = model.mass().principal_submatrix(&with_mass);
            let s_rr = model.stiffness().principal_submatrix(&with_mass);
            let omega2 = largest_eigenvalue(&s_rr, &m_rr)?;
            let solver = SpdSolver::factor(&m_rr, "mass (dofs with inertia)")?;
            (Some(solver), stable_step(omega2, gamma))
        };
        if dt > stable_dt {
            return Err(SolveError::CflViolated {
                dt,
                bound: stable_dt,
                gamma,
            });
        }
        Ok(Self {
            model,
            gamma,
            mass_solver,
            statics: QuasiStatic::new(model)?,
            taylor_flanagan: TaylorFlanagan::new(model, &with_mass),
            impulse: false,
            stable_dt,
            next: vec![0.0; n],
            force: vec![0.0; n],
            force_r: vec![0.0; with_mass.len()],
            with_mass,
        })
    }

    /// The largest stable time step `√(2/γ)/ω_max` (infinite when no dof has mass).
    pub fn stable_dt(&self) -> f64 {
        self.stable_dt
    }
}

impl TimeIntegrator for ExplicitNewmark<'_> {
    fn advance(&mut self, state: &mut SchemeState) -> Result<(), SolveError> {
        let (dt, step) = (state.dt, state.step + 1);
        let SchemeState {
            u,
            v,
            lambda,
            acceleration,
            previous,
            ..
        } = state;
        let a = acceleration.as_mut().expect(CARRIES_ACCELERATION);
        for ((next, u), (v, a)) in self.next.iter_mut().zip(&*u).zip(v.iter().zip(&*a)) {
            *next = u + dt * v + 0.5 * dt * dt * a;
        }
        if let Some(statics) = self.statics.as_mut() {
            statics.solve(self.model, step, &mut self.next, lambda)?;
        }
        let gamma = self.gamma;
        for &i in &self.with_mass {
            v[i] += dt * (1.0 - gamma) * a[i];
        }
        if let (Some(tf), Some(m), Some(set)) = (
            &self.taylor_flanagan,
            &self.mass_solver,
            self.model.contact(),
        ) {
            for (f, &i) in self.force_r.iter_mut().zip(&self.with_mass) {
                *f = v[i];
            }
            self.impulse = tf.apply(set, m, dt, &mut self.next, &mut self.force_r, lambda)?;
            for (&i, &vi) in self.with_mass.iter().zip(&self.force_r) {
                v[i] = vi;
            }
        }
        residual_force(self.model, &self.next, &mut self.force);
        for (f, &i) in self.force_r.iter_mut().zip(&self.with_mass) {
            *f = -self.force[i];
        }
        if let Some(m) = &self.mass_solver {
            m.solve_in_place(&mut self.force_r);
        }
        for (&i, &a_new) in self.with_mass.iter().zip(&self.force_r) {
            v[i] += dt * gamma * a_new;
            a[i] = a_new;
        }
        for &z in self.model.massless_dofs() {
            v[z] = (self.next[z] - u[z]) / dt;
        }
        let previous = previous.get_or_insert_with(|| vec![0.0; u.len()]);
        std::mem::swap(previous, u);
        std::mem::swap(u, &mut self.next);
        state.next_step();
        Ok(())
    }

    /// `U^{n+1}`, `V^{n+1}` and `A^{n+1}`, which the next step's update reads (`U^n`, kept for
    /// the staggered energy, was perturbed when it was computed).
    fn perturb_carried(&self, state: &mut SchemeState, perturb: &mut dyn FnMut(&mut [f64])) {
        state.perturb_levels(perturb);
    }

    /// `E^{n−½}` at `t_{n−½}` (see the module documentation); `E_h(U^0, V^0)` before the
    /// first step.
    fn energy(&self, state: &SchemeState) -> Timed<f64> {
        let (model, dt) = (self.model, state.dt);
        state.staggered_energy(model, |previous| {
            staggered_energy(model, dt, previous, &state.u)
        })
    }

    /// The quasi-static contact solves of the massless dofs (their slab is not reported, nor
    /// are the solves of `M_RR` and `S_ZZ`).
    fn statistics(&self) -> StepStatistics {
        let statics = self.statics.as_ref().map(QuasiStatic::statistics);
        StepStatistics {
            contact_truncation: None,
            ..statics.unwrap_or_default()
        }
    }

    fn balance_holds(&self) -> bool {
        !self.impulse
    }
}
