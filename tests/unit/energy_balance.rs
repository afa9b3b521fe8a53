//! The discrete energy balances of the Appendix (eqs. 33, 35, 37, derived for every parameter
//! value, with a constant load and the singular mass; `schemes::energy_balance`) hold at every
//! step of a run with contact, to round-off, for every scheme × mass pair of Tables 1–2; with
//! the penalty and Nitsche forces; for explicit Newmark (central differences) with and without
//! contact; and on the 2D/3D boxes of the note with many contact nodes.
//!
//! One family of balance checks lives elsewhere: Crank–Nicolson and backward Euler with the
//! penalty and Nitsche treatments (in 1D, and the penalty on the 2D box) are checked through the
//! total energy `E + Φ` in `contact_treatments.rs`, whose run helper also gives the treatments'
//! other energy properties (conserved off crossings, never gained by backward Euler). A balance
//! residual is also read, not derived, by the stability suite (`max_balance_residual`,
//! `tests/convergence/stability.rs`) and by `run --check-balance` (`tests/cli/commands.rs`).

use crate::benchmarks;
use crate::stepper::Stepper;
use signorini::engine::exact::{ExactSolution, SignoriniDirichlet};
use signorini::engine::fem::box_mesh::{BoxMesh, Elasticity};
use signorini::engine::fem::{Bar1d, EndCondition, MassVariant};
use signorini::engine::model::Model;
use signorini::engine::schemes::energy_balance::{
    self, BalanceMonitor, Level, StepBalance, ThreeLevels,
};
use signorini::engine::schemes::{
    initial_state, Conventions, Integration, PaoliSchatzman, Scheme, SchemeState,
};
use signorini::harness::run::time_grid;

const NX: usize = 20;
const RATIO: f64 = 10.0;
const HORIZON: f64 = 6.0;

fn diff(a: &[f64], b: &[f64]) -> Vec<f64> {
    a.iter().zip(b).map(|(x, y)| x - y).collect()
}

/// `B v` for the single contact dof.
fn contact_component(model: &Model, v: &[f64]) -> f64 {
    v[model.contact().expect("obstacle").dofs[0]]
}

/// No load, and a constant body force pushing the bar onto the obstacle (the balances carry
/// over with the energy `½VᵀMV + ½UᵀSU − FᵀU`).
const LOADS: [Option<f64>; 2] = [None, Some(-0.3)];

fn setup(mass: MassVariant, load: Option<f64>) -> (Bar1d, Model, Vec<f64>, Vec<f64>) {
    let bar = Bar1d::unit(NX, EndCondition::Clamped).unwrap();
    let model = Model::bar1d(&bar, mass, Some(0.0), load);
    let exact = SignoriniDirichlet;
    let u0 = bar.interpolate(|x| exact.eval(x, 0.0).u);
    let v0 = bar.interpolate(|x| exact.eval(x, 0.0).ut);
    (bar, model, u0, v0)
}

fn steps(dt: f64) -> usize {
    (HORIZON / dt).round() as usize
}

struct Snapshot {
    u: Vec<f64>,
    v: Vec<f64>,
    lambda: Vec<f64>,
}

impl Snapshot {
    fn of(s: &Integration) -> Self {
        Self {
            u: s.displacement().to_vec(),
            v: s.velocity().to_vec(),
            lambda: s.multiplier().value.to_vec(),
        }
    }

    fn level(&self) -> Level<'_> {
        Level {
            displacement: &self.u,
            velocity: &self.v,
            multiplier: &self.lambda,
        }
    }
}

/// The largest `|residual| / E_0` of `balance` over the steps of a run of a one-step scheme,
/// with no load and with the load; the balance's energies are the integrator's.
fn one_step_balance(
    scheme: Scheme,
    mass: MassVariant,
    balance: impl Fn(&Model, f64, &Level, &Level) -> StepBalance,
) -> f64 {
    LOADS
        .into_iter()
        .map(|load| one_step_balance_with_load(scheme, mass, load, &balance))
        .fold(0.0, f64::max)
}

fn one_step_balance_with_load(
    scheme: Scheme,
    mass: MassVariant,
    load: Option<f64>,
    balance: &impl Fn(&Model, f64, &Level, &Level) -> StepBalance,
) -> f64 {
    let (bar, model, u0, v0) = setup(mass, load);
    let dt = bar.h() / RATIO;
    let mut s = Stepper::harness(&model, scheme, dt, &u0, &v0);
    let mut before = Snapshot::of(&s.observed());
    let e0 = s.energy().value;
    let mut worst: f64 = 0.0;
    let mut contact_steps = 0;
    for _ in 0..steps(dt) {
        s.advance().unwrap();
        let after = Snapshot::of(&s.observed());
        if after.lambda[0] != 0.0 {
            contact_steps += 1;
        }
        let b = balance(&model, dt, &before.level(), &after.level());
        assert_eq!(b.energy_after, s.energy().value, "{scheme} {mass}");
        worst = worst.max(b.residual().abs() / e0);
        before = after;
    }
    assert!(contact_steps > 0, "the run must include contact");
    worst
}

/// Newmark(β, γ), the Appendix's identity behind eq. (33) ([`energy_balance::newmark`]).
fn newmark(beta: f64, gamma: f64) -> impl Fn(&Model, f64, &Level, &Level) -> StepBalance {
    move |model, dt, b, a| energy_balance::newmark(model, beta, gamma, dt, b, a)
}

/// θ-method, eq. (35) ([`energy_balance::theta`]).
fn theta_method(theta: f64) -> impl Fn(&Model, f64, &Level, &Level) -> StepBalance {
    move |model, _dt, b, a| energy_balance::theta(model, theta, b, a)
}

/// Eq. (33) exactly as printed, `ΔE = −ΔUᵀ Λ_γ e_0` with γ = ½, as the prediction.
fn printed_eq_33(model: &Model, dt: f64, b: &Level, a: &Level) -> StepBalance {
    StepBalance {
        predicted_change: -(contact_component(model, a.displacement)
            - contact_component(model, b.displacement))
            * 0.5
            * (a.multiplier[0] + b.multiplier[0]),
        ..energy_balance::newmark(model, 0.25, 0.5, dt, b, a)
    }
}

const TOL: f64 = 1e-12;

#[test]
fn newmark_family_balance_holds_every_step() {
    for (beta, gamma) in [(0.25, 0.5), (0.5, 1.0), (0.5, 0.5), (0.3, 0.6)] {
        for mass in MassVariant::ALL {
            let scheme = Scheme::Newmark { beta, gamma };
            let worst = one_step_balance(scheme, mass, newmark(beta, gamma));
            assert!(
                worst < TOL,
                "{scheme} {mass}: energy balance residual {worst:e}"
            );
        }
    }
}

#[test]
fn printed_sign_of_the_newmark_appendix_identity_does_not_hold() {
    // The last display of the Appendix's Newmark derivation prints −Δt(β − γ/2)ΔVᵀSΔU: its
    // prediction is the balance's minus 2Δt(β − γ/2)ΔVᵀSΔU. For β ≠ γ/2 that version leaves a
    // residual far above round-off: the sign is an erratum.
    let (beta, gamma) = (0.5, 0.5);
    let worst = one_step_balance(
        Scheme::Newmark { beta, gamma },
        MassVariant::Standard,
        |model, dt, b, a| {
            let balance = energy_balance::newmark(model, beta, gamma, dt, b, a);
            let du = diff(a.displacement, b.displacement);
            let dv = diff(a.velocity, b.velocity);
            let flipped =
                2.0 * dt * (beta - 0.5 * gamma) * model.stiffness().bilinear_form(&dv, &du);
            StepBalance {
                predicted_change: balance.predicted_change - flipped,
                ..balance
            }
        },
    );
    assert!(
        worst > 1e-6,
        "printed sign unexpectedly balances: {worst:e}"
    );
}

#[test]
fn crank_nicolson_balance_is_eq_33() {
    // Eq. (33) exactly as printed, and the library's Newmark balance at (¼, ½).
    for mass in MassVariant::ALL {
        let worst = one_step_balance(Scheme::CRANK_NICOLSON, mass, printed_eq_33);
        assert!(worst < TOL, "crank-nicolson {mass}: residual {worst:e}");
        let worst = one_step_balance(Scheme::CRANK_NICOLSON, mass, newmark(0.25, 0.5));
        assert!(worst < TOL, "crank-nicolson {mass}: residual {worst:e}");
    }
}

#[test]
fn theta_method_balance_is_eq_35() {
    for theta in [1.0, 0.5, 0.75] {
        for mass in MassVariant::ALL {
            let worst = one_step_balance(Scheme::Theta { theta }, mass, theta_method(theta));
            assert!(worst < TOL, "theta {theta} {mass}: residual {worst:e}");
        }
    }
}

#[test]
fn dissipative_schemes_never_gain_energy() {
    // Eq. (35) with θ = 1 and Newmark with γ = 1: every term of ΔE is ≤ 0 under
    // complementarity (−Δu_0 λ^{n+1} = u_0^n λ^{n+1} ≤ 0).
    for scheme in [
        Scheme::Theta { theta: 1.0 },
        Scheme::Newmark {
            beta: 0.5,
            gamma: 1.0,
        },
    ] {
        for mass in MassVariant::ALL {
            let (bar, model, u0, v0) = setup(mass, None);
            let dt = bar.h() / RATIO;
            let mut s = Stepper::harness(&model, scheme, dt, &u0, &v0);
            let mut e = s.energy().value;
            let e0 = e;
            for _ in 0..steps(dt) {
                s.advance().unwrap();
                let next = s.energy().value;
                assert!(
                    next - e <= TOL * e0,
                    "{scheme} {mass} gained {:e}",
                    next - e
                );
                e = next;
            }
        }
    }
}

/// The largest `|residual| / E^{½}` over a Paoli–Schatzman(β, e) run from its second step on
/// (the first is its Newmark start), the balance's prediction replaced by `predicted(balance,
/// λ^n, U^{n−1})`; the balance's energies are the integrator's.
fn paoli_schatzman_balance(
    beta: f64,
    e: f64,
    mass: MassVariant,
    load: Option<f64>,
    predicted: impl Fn(&StepBalance, f64, &[f64]) -> f64,
) -> f64 {
    let (bar, model, u0, v0) = setup(mass, load);
    let dt = bar.h() / RATIO;
    let start = initial_state(&model, &u0, &v0, &Conventions::HARNESS).unwrap();
    let method = PaoliSchatzman::new(
        &model,
        (beta, e),
        dt,
        &start.multiplier,
        &Conventions::HARNESS,
    )
    .unwrap();
    let mut s = Stepper::new(method, SchemeState::start(dt, start));
    s.advance().unwrap();
    let e0 = s.energy().value;
    let mut worst: f64 = 0.0;
    let mut contact_steps = 0;
    for _ in 1..steps(dt) {
        let (u_prev, u_now) = (
            s.previous_displacement().unwrap().to_vec(),
            s.displacement().to_vec(),
        );
        let e_before = s.energy().value;
        s.advance().unwrap();
        let lambda = s.scheme_multiplier()[0];
        if lambda != 0.0 {
            contact_steps += 1;
        }
        let levels = ThreeLevels {
            earlier: &u_prev,
            current: &u_now,
            later: s.displacement(),
            multiplier: s.scheme_multiplier(),
        };
        let b = energy_balance::paoli_schatzman(&model, beta, dt, &levels);
        assert_eq!(b.energy_before, e_before);
        assert_eq!(b.energy_after, s.energy().value);
        worst = worst.max((b.change - predicted(&b, lambda, &u_prev)).abs() / e0);
    }
    assert!(contact_steps > 0, "the run must include contact");
    worst
}

/// Paoli–Schatzman (eq. 36 with the projection `P` off `ker M`), [`energy_balance::paoli_schatzman`]:
/// `E^{n+½} − E^{n−½} = ½ (U^{n+1} − U^{n−1})ᵀ [−Bᵀλ^n + Q((1 − 2β) R(U^n) + β R(U^{n−1}))]`,
/// `Q = I − P`, `R(U) = SU − F`; for the standard mass `Q = 0` and this is eq. (37) before the
/// complementarity substitution.
#[test]
fn paoli_schatzman_balance_holds_every_step() {
    for beta in [0.25, 0.4] {
        for e in [0.0, 0.5, 1.0] {
            for (mass, load) in MassVariant::ALL
                .into_iter()
                .flat_map(|m| LOADS.map(|l| (m, l)))
            {
                let worst =
                    paoli_schatzman_balance(beta, e, mass, load, |b, _, _| b.predicted_change);
                assert!(
                    worst < TOL,
                    "PS β={beta} e={e} {mass} load {load:?}: residual {worst:e}"
                );
            }
        }
    }
}

/// Eq. (37) exactly as printed, `ΔE = ½(1 + e) λ^n u_0^{n−1}` (β = ¼, standard mass, gap 0):
/// the balance after the complementarity substitution `λ^n (u_0^{n+1} + e u_0^{n−1}) = 0`.
#[test]
fn paoli_schatzman_balance_is_eq_37_with_the_standard_mass() {
    for e in [0.0, 0.5, 1.0] {
        for load in LOADS {
            let worst = paoli_schatzman_balance(0.25, e, MassVariant::Standard, load, |_, l, u| {
                0.5 * (1.0 + e) * l * u[0]
            });
            assert!(worst < TOL, "PS e={e} load {load:?}: residual {worst:e}");
        }
    }
}

#[test]
fn paper_schemes_are_covered() {
    // Every scheme of Tables 1–2 is a Newmark, θ or Paoli–Schatzman instance tested above.
    for s in Scheme::paper_schemes() {
        assert!(matches!(
            s,
            Scheme::Newmark {
                beta: 0.25 | 0.5,
                gamma: 0.5 | 1.0
            } | Scheme::Theta { theta: 1.0 }
                | Scheme::PaoliSchatzman { beta: 0.25, .. }
        ));
    }
}

#[test]
fn printed_load_term_of_eq_31_is_not_conserved() {
    // Without contact Crank–Nicolson conserves ½VᵀMV + ½UᵀSU − FᵀU to round-off; the printed
    // eq. (31), ½(VᵀMV + UᵀSU − VᵀF), drifts: its load term is an erratum.
    let bar = Bar1d::unit(NX, EndCondition::Clamped).unwrap();
    let model = Model::bar1d(&bar, MassVariant::Standard, None, Some(-0.3));
    let exact = SignoriniDirichlet;
    let u0 = bar.interpolate(|x| exact.eval(x, 0.0).u);
    let v0 = bar.interpolate(|x| exact.eval(x, 0.0).ut);
    let dt = bar.h() / RATIO;
    let load = model.load().unwrap().to_vec();
    let printed = |u: &[f64], v: &[f64]| {
        let vf: f64 = v.iter().zip(&load).map(|(a, b)| a * b).sum();
        0.5 * (model.mass().quadratic_form(v) + model.stiffness().quadratic_form(u) - vf)
    };
    let mut s = Stepper::harness(&model, Scheme::CRANK_NICOLSON, dt, &u0, &v0);
    let (e0, p0) = (s.energy().value, printed(s.displacement(), s.velocity()));
    let (mut previous, mut ours, mut theirs): (f64, f64, f64) = (e0, 0.0, 0.0);
    for _ in 0..steps(dt) {
        s.advance().unwrap();
        let e = s.energy().value;
        ours = ours.max((e - previous).abs() / e0);
        previous = e;
        theirs = theirs.max((printed(s.displacement(), s.velocity()) - p0).abs() / p0.abs());
    }
    assert!(ours < TOL, "−FᵀU energy changed in one step by {ours:e}");
    assert!(
        theirs > 1e-3,
        "printed energy unexpectedly conserved: {theirs:e}"
    );
}

/// The Newmark identity (Appendix, after eq. 46; [`energy_balance::newmark`]) with `Bᵀλ`
/// replaced by the penalty or Nitsche force `Σ λ_i f_i` and `S` by the integrated (for Nitsche,
/// modified) stiffness: `ΔE = (½ − γ)ΔUᵀSΔU − ΔUᵀfΛ_γ + Δt(β − γ/2)ΔVᵀSΔU + Δt(β − γ/2)ΔVᵀfΔλ`,
/// with `E = ½VᵀMV + ½UᵀSU − FᵀU` the energy without the contact term.
#[test]
fn newmark_family_balance_holds_with_penalty_and_nitsche_forces() {
    use signorini::engine::contact::ContactLaw;
    for contact in [
        "penalty(gamma0=10)",
        "nitsche(theta=-1,gamma0=10)",
        "nitsche(theta=0,gamma0=10)",
        "nitsche(theta=1,gamma0=10)",
    ] {
        for (beta, gamma) in [(0.5, 1.0), (0.5, 0.5), (0.3, 0.6)] {
            for mass in MassVariant::ALL {
                let (bar, model, u0, v0) = setup(mass, Some(-0.3));
                let law = ContactLaw::bar1d(contact.parse().unwrap(), &bar).unwrap();
                let model = model.with_contact_law(law);
                let dt = bar.h() / RATIO;
                let scheme = Scheme::Newmark { beta, gamma };
                let mut s = Stepper::harness(&model, scheme, dt, &u0, &v0);
                let mechanical =
                    |s: &Integration| s.energy().value - model.contact_energy(s.displacement());
                let mut before = Snapshot::of(&s.observed());
                let e0 = mechanical(&s.observed());
                let (mut worst, mut contact_steps): (f64, usize) = (0.0, 0);
                for _ in 0..steps(dt) {
                    s.advance().unwrap();
                    let after = Snapshot::of(&s.observed());
                    contact_steps += usize::from(after.lambda[0] != 0.0);
                    let b = energy_balance::newmark(
                        &model,
                        beta,
                        gamma,
                        dt,
                        &before.level(),
                        &after.level(),
                    );
                    assert_eq!(b.energy_after, mechanical(&s.observed()));
                    worst = worst.max(b.residual().abs() / e0.abs());
                    before = after;
                }
                assert!(contact_steps > 0, "{contact} {scheme} {mass}");
                assert!(worst < TOL, "{contact} {scheme} {mass}: residual {worst:e}");
            }
        }
    }
}

/// The variants beyond the paper (issue 11), named explicitly so that the check does not depend
/// on what `MassVariant::ALL` lists.
const NEW_MASSES: [MassVariant; 3] = [
    MassVariant::Lumped,
    MassVariant::RedistributedConserving,
    MassVariant::SingularDynamic,
];

/// Eq. (33) for Crank–Nicolson with each new mass matrix, with contact, with and without load.
#[test]
fn crank_nicolson_balance_holds_for_the_new_mass_variants() {
    for mass in NEW_MASSES {
        let worst = one_step_balance(Scheme::CRANK_NICOLSON, mass, printed_eq_33);
        assert!(worst < TOL, "crank-nicolson {mass}: residual {worst:e}");
    }
}

/// Eq. (35) for backward Euler (θ = 1) with each new mass matrix, with contact.
#[test]
fn backward_euler_balance_holds_for_the_new_mass_variants() {
    for mass in NEW_MASSES {
        let worst = one_step_balance(Scheme::Theta { theta: 1.0 }, mass, theta_method(1.0));
        assert!(worst < TOL, "backward-euler {mass}: residual {worst:e}");
    }
}

// ---------------------------------------------------------------------------------------------
// Explicit Newmark (central differences).
// ---------------------------------------------------------------------------------------------

/// The masses whose contact dof is massless: the only ones explicit contact accepts.
const MASSLESS_CONTACT: [MassVariant; 3] = [
    MassVariant::Redistributed,
    MassVariant::RedistributedConserving,
    MassVariant::SingularDynamic,
];

/// Without contact the staggered energy `E^{n+½}` is constant to round-off, for every mass
/// (with a load too), including the singular ones whose contact node is static.
#[test]
fn central_differences_conserve_the_staggered_energy_without_contact() {
    for mass in MassVariant::ALL {
        for load in [None, Some(-0.3)] {
            let bar = Bar1d::unit(40, EndCondition::Clamped).unwrap();
            let model = Model::bar1d(&bar, mass, None, load);
            let u0 = bar.interpolate(|x| (std::f64::consts::FRAC_PI_2 * x).cos());
            let v0 = bar.interpolate(|x| 0.3 * x * (1.0 - x));
            let dt = 0.5 * bar.h();
            let mut s = Stepper::harness(&model, Scheme::CENTRAL_DIFFERENCE, dt, &u0, &v0);
            s.advance().unwrap();
            let e_half = s.energy().value;
            let (mut previous, mut per_step, mut drift): (f64, f64, f64) = (e_half, 0.0, 0.0);
            for _ in 0..2000 {
                s.advance().unwrap();
                let e = s.energy().value;
                per_step = per_step.max((e - previous).abs() / e_half.abs());
                drift = drift.max((e - e_half).abs() / e_half.abs());
                previous = e;
            }
            // Round-off: ½UᵀSU sums entries of size E/h² down to E (1/h = 40 here).
            assert!(
                per_step < 1e-11,
                "{mass} load {load:?}: step change {per_step:e}"
            );
            assert!(drift < 1e-10, "{mass} load {load:?}: drift {drift:e}");
            assert_eq!(s.energy().time, (s.step_index() as f64 - 0.5) * dt);
        }
    }
    // The check can fail: γ = 0.6 damps, and the same energy then moves far above round-off.
    let bar = Bar1d::unit(40, EndCondition::Clamped).unwrap();
    let model = Model::bar1d(&bar, MassVariant::Standard, None, None);
    let u0 = bar.interpolate(|x| (std::f64::consts::FRAC_PI_2 * x).cos());
    let damped = Scheme::Newmark {
        beta: 0.0,
        gamma: 0.6,
    };
    let mut s = Stepper::harness(&model, damped, 0.5 * bar.h(), &u0, &vec![0.0; u0.len()]);
    s.advance().unwrap();
    let e_half = s.energy().value;
    for _ in 0..200 {
        s.advance().unwrap();
    }
    assert!((s.energy().value - e_half).abs() / e_half > 1e-6);
}

/// With contact: `E^{n+½} − E^{n−½} = −½ λ^n (u_c^{n+1} − u_c^{n−1})` at every step
/// (`energy_balance::central_difference`) for the staggered energy the scheme reports, and
/// `0 ≤ u_c ⟂ λ ≤ 0` at every step, on the Dirichlet benchmark.
#[test]
fn explicit_contact_balance_and_complementarity_every_step() {
    for mass in MASSLESS_CONTACT {
        let problem = benchmarks::dirichlet(3.0);
        let (bar, model) = problem.model(40, mass).unwrap();
        let exact = SignoriniDirichlet;
        let u0 = bar.interpolate(|x| exact.eval(x, 0.0).u);
        let v0 = bar.interpolate(|x| exact.eval(x, 0.0).ut);
        let (steps, dt) = time_grid(3.0, bar.h(), 10.0);
        let mut s = Stepper::harness(&model, Scheme::CENTRAL_DIFFERENCE, dt, &u0, &v0);
        let mut u_prev = s.displacement().to_vec();
        s.advance().unwrap();
        let e0 = s.energy().value;
        let (mut worst, mut contact_steps): (f64, usize) = (0.0, 0);
        for n in 1..steps {
            let (u_now, lambda_now) = (s.displacement().to_vec(), s.multiplier().value.to_vec());
            let (gap, lambda) = (u_now[0], lambda_now[0]);
            assert!(gap >= -1e-14, "{mass} step {n}: gap {gap:e}");
            assert!(lambda <= 0.0, "{mass} step {n}: λ {lambda:e}");
            assert!((gap * lambda).abs() <= 1e-14, "{mass} step {n}");
            if lambda != 0.0 {
                contact_steps += 1;
            }
            let e_before = s.energy().value;
            s.advance().unwrap();
            let levels = ThreeLevels {
                earlier: &u_prev,
                current: &u_now,
                later: s.displacement(),
                multiplier: &lambda_now,
            };
            let b = energy_balance::central_difference(&model, dt, &levels);
            assert_eq!(b.energy_before, e_before, "{mass} step {n}");
            assert_eq!(b.energy_after, s.energy().value, "{mass} step {n}");
            worst = worst.max(b.residual().abs() / e0);
            u_prev = u_now;
        }
        assert!(contact_steps > 100, "{mass}: {contact_steps} contact steps");
        // Round-off, as without contact (NX = 40: entries of S of size 40).
        assert!(worst < 1e-11, "{mass}: balance residual {worst:e}");
        assert!(s.statistics().complementarity_violation < 1e-12, "{mass}");
    }
}

// ---------------------------------------------------------------------------------------------
// The 2D/3D bars of the note, many contact nodes.
// ---------------------------------------------------------------------------------------------

/// The note's §3 set-up at a coarse level, run by the 1D engine: Crank–Nicolson, gap 0.2,
/// `v⁰ = −0.5 e_d` off `Γ_Dir`, `Δt = h/2` to `t = 1`. Contact happens, complementarity holds
/// after every step, and every step's energy change is the Crank–Nicolson balance
/// `ΔE = −½ Σ_i (U^{n+1} − U^n)_{c_i} (λ_i^n + λ_i^{n+1})` (1D paper eq. 33, the note's §2.2
/// identity; `energy_balance::newmark`) to 1e-10 E₀, with either mass.
fn dynamic_smoke(mesh: &BoxMesh) {
    let d = mesh.dim();
    let gap = 0.2;
    let h = mesh.element_sizes()[d - 1];
    let dt = h / 2.0;
    let steps = (1.0 / dt).round() as usize;
    let u0 = vec![0.0; mesh.n_dofs()];
    let v0 = mesh.interpolate(|_| {
        let mut v = [0.0; 3];
        v[d - 1] = -0.5;
        v
    });
    for variant in MassVariant::ON_EVERY_MESH {
        let model = Model::of_box(mesh, &Elasticity::NOTE, variant, Some(gap));
        let contact = model.contact().unwrap().clone();
        let mut integ = Stepper::harness(&model, Scheme::CRANK_NICOLSON, dt, &u0, &v0);
        let e0 = model.energy(integ.displacement(), integ.velocity());
        assert!(e0 > 0.0);
        let mut touched = false;
        let mut monitor = BalanceMonitor::new(&model, Scheme::CRANK_NICOLSON, dt);
        monitor.observe(&integ.observed());
        for n in 0..steps {
            integ.advance().unwrap();
            let balance = monitor
                .observe(&integ.observed())
                .expect("one step further");
            let u = integ.displacement();
            let lambda = integ.multiplier().value;
            for (i, &c) in contact.dofs.iter().enumerate() {
                let value = u[c] + contact.gaps[i];
                assert!(value >= -1e-10, "{variant} step {n}: penetration {value}");
                assert!(lambda[i] <= 0.0, "{variant} step {n}: λ = {}", lambda[i]);
                assert!(
                    (lambda[i] * value).abs() <= 1e-10 * lambda[i].abs().max(1.0),
                    "{variant} step {n}: λ (u + g) = {}",
                    lambda[i] * value
                );
                touched |= lambda[i] < 0.0;
            }
            assert!(
                balance.residual().abs() <= 1e-10 * e0,
                "{variant} step {n}: ΔE = {}, balance {}, E₀ = {e0}",
                balance.change,
                balance.predicted_change
            );
        }
        assert!(touched, "{variant}: the bar never touched the obstacle");
        assert!((integ.time() - 1.0).abs() < 1e-12);
    }
}

/// The dynamic smoke test on the note's 2D bar, 2 × 10 elements.
#[test]
fn crank_nicolson_runs_on_the_2d_bar_with_the_energy_balance() {
    dynamic_smoke(&BoxMesh::note_2d(2, 10).unwrap());
}

/// The same on the note's 3D bar, 2 × 2 × 4 elements.
#[test]
fn crank_nicolson_runs_on_the_3d_bar_with_the_energy_balance() {
    dynamic_smoke(&BoxMesh::note_3d(2, 2, 4).unwrap());
}

/// Backward Euler on the note's 2D and 3D bars, with either mass, to 1e-12 E₀.
#[test]
fn backward_euler_balance_holds_every_step_in_2d_and_3d() {
    // Eq. (35) with θ = 1 (`energy_balance::theta`):
    // ΔE = −½ΔVᵀMΔV − ½ΔUᵀSΔU − Σ_i Δu_{c_i} λ_i^{n+1}.
    for mesh in [
        BoxMesh::note_2d(2, 16).unwrap(),
        BoxMesh::note_3d(2, 2, 8).unwrap(),
    ] {
        for mass in MassVariant::ON_EVERY_MESH {
            let model = Model::of_box(&mesh, &Elasticity::NOTE, mass, Some(0.2));
            let d = mesh.dim();
            let u0 = vec![0.0; model.n_dofs()];
            let v0 = mesh.interpolate(|_| {
                let mut v = [0.0; 3];
                v[d - 1] = -0.5;
                v
            });
            let dt = mesh.element_sizes()[d - 1] / 2.0;
            let scheme = Scheme::Theta { theta: 1.0 };
            let mut s = Stepper::harness(&model, scheme, dt, &u0, &v0);
            let mut monitor = BalanceMonitor::new(&model, scheme, dt);
            monitor.observe(&s.observed());
            let e0 = s.energy().value;
            let mut worst: f64 = 0.0;
            let mut touched = false;
            for _ in 0..((1.5 / dt).round() as usize) {
                s.advance().unwrap();
                touched |= s.multiplier().value.iter().any(|&l| l < 0.0);
                let balance = monitor.observe(&s.observed()).expect("one step further");
                worst = worst.max(balance.residual().abs() / e0);
            }
            assert!(touched, "{d}D {mass}: no contact");
            assert!(worst < 1e-12, "{d}D {mass}: residual {worst:e}");
        }
    }
}
