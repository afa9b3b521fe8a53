//! The rivals of the paper's schemes (`engine::schemes::generalised_alpha`, `moreau_jean`):
//! each reduces to the scheme it generalises where it should (generalised-α with
//! `α_m = α_f = 0` is Newmark(β, γ) bit for bit; Moreau–Jean without an obstacle is the
//! θ-method to round-off, though one solves for velocities and the other for displacements, on
//! every displacement and on the velocities that enter the dynamics),
//! each satisfies its energy balance, (GA-E) or (MJ-E), at every step of a run with contact to
//! round-off (and a balance with a wrong parameter does not); Laursen–Chawla conserves the
//! energy exactly; and what is not defined is refused naming the field.

use crate::stepper::Stepper;
use signorini::engine::contact::{ContactLaw, ContactTreatment};
use signorini::engine::exact::{ExactSolution, SignoriniDirichlet};
use signorini::engine::fem::box_mesh::{BoxMesh, Elasticity};
use signorini::engine::fem::{Bar1d, EndCondition, MassVariant};
use signorini::engine::model::Model;
use signorini::engine::schemes::conventions::NitscheAcceleration;
use signorini::engine::schemes::energy_balance::{self, BalanceMonitor, Level, BALANCE_TOLERANCE};
use signorini::engine::schemes::scheme::{generalised_alpha, hht};
use signorini::engine::schemes::{integrator, AlphaParameters, Conventions, Integration, Scheme};

pub(crate) const NX: usize = 20;
const RATIO: f64 = 10.0;
const HORIZON: f64 = 6.0;

/// The Dirichlet benchmark's bar at NX = 20, with the obstacle or without, and its exact data.
pub(crate) fn dirichlet(mass: MassVariant, obstacle: bool) -> (Model, Vec<f64>, Vec<f64>) {
    let bar = Bar1d::unit(NX, EndCondition::Clamped).unwrap();
    let model = Model::bar1d(&bar, mass, obstacle.then_some(0.0), None);
    let exact = SignoriniDirichlet;
    let u0 = bar.interpolate(|x| exact.eval(x, 0.0).u);
    let v0 = bar.interpolate(|x| exact.eval(x, 0.0).ut);
    (model, u0, v0)
}

pub(crate) fn dt() -> f64 {
    1.0 / (NX as f64 * RATIO)
}

pub(crate) fn steps() -> usize {
    (HORIZON / dt()).round() as usize
}

/// `(U^n, V^n, λ^n)` after every step of `scheme` on `model`.
pub(crate) fn history(model: &Model, scheme: Scheme, u0: &[f64], v0: &[f64]) -> Vec<[Vec<f64>; 3]> {
    let mut s = Stepper::harness(model, scheme, dt(), u0, v0);
    (0..steps())
        .map(|_| {
            s.advance().unwrap();
            [
                s.displacement().to_vec(),
                s.velocity().to_vec(),
                s.multiplier().value.to_vec(),
            ]
        })
        .collect()
}

#[test]
fn generalised_alpha_without_alpha_is_newmark_bit_for_bit() {
    for (beta, gamma) in [(0.25, 0.5), (0.5, 1.0), (0.3, 0.6)] {
        let alpha_free = Scheme::GeneralisedAlpha(AlphaParameters {
            alpha_m: 0.0,
            alpha_f: 0.0,
            beta,
            gamma,
        });
        for mass in MassVariant::PAPER {
            let (model, u0, v0) = dirichlet(mass, true);
            let newmark = history(&model, Scheme::Newmark { beta, gamma }, &u0, &v0);
            let alpha = history(&model, alpha_free, &u0, &v0);
            assert!(newmark.iter().any(|l| l[2][0] < 0.0), "no contact");
            assert_eq!(newmark, alpha, "β = {beta}, γ = {gamma}, {mass}");
        }
    }
}

#[test]
fn moreau_jean_without_contact_is_the_theta_method() {
    for theta in [0.5, 0.75, 1.0] {
        for mass in MassVariant::PAPER {
            let (model, u0, v0) = dirichlet(mass, false);
            // The θ-method recovers `A^{n+1}` from `U^{n+1}` dividing by `θ²Δt²`, so each step
            // leaves up to `ε |U| / (θ Δt)` in `V`; the bound is that, summed over the steps.
            let largest = u0.iter().chain(&v0).fold(0.0_f64, |m, x| m.max(x.abs()));
            let scale = steps() as f64 * f64::EPSILON * largest / (theta * dt());
            let theta_method = history(&model, Scheme::Theta { theta }, &u0, &v0);
            let moreau_jean = history(
                &model,
                Scheme::MoreauJean {
                    theta,
                    restitution: 0.0,
                },
                &u0,
                &v0,
            );
            // `V` on a massless dof (`M^mod`'s contact node) is a difference quotient outside
            // the dynamics (only `M V` enters them): with θ = ½ the round-off of the recovered
            // acceleration there is not damped, so it is not held to this bound.
            let with_mass = model.dofs_with_mass();
            let worst = largest_difference_where(&theta_method, &moreau_jean, |i| {
                with_mass.binary_search(&i).is_ok()
            });
            assert!(
                worst <= scale,
                "θ = {theta}, {mass}: the two differ by {worst:e} (round-off bound {scale:e})"
            );
        }
    }
}

/// The largest difference of a displacement or velocity dof between two histories.
pub(crate) fn largest_difference(a: &[[Vec<f64>; 3]], b: &[[Vec<f64>; 3]]) -> f64 {
    largest_difference_where(a, b, |_| true)
}

/// The largest difference between two histories of a displacement dof, or of a velocity dof `i`
/// with `velocity(i)`.
fn largest_difference_where(
    a: &[[Vec<f64>; 3]],
    b: &[[Vec<f64>; 3]],
    velocity: impl Fn(usize) -> bool,
) -> f64 {
    let velocity = &velocity;
    a.iter()
        .zip(b)
        .flat_map(|(a, b)| {
            let displacements = a[0].iter().zip(&b[0]).map(|(x, y)| (x - y).abs());
            let velocities = (a[1].iter().zip(&b[1]).enumerate())
                .filter(move |(i, _)| velocity(*i))
                .map(|(_, (x, y))| (x - y).abs());
            displacements.chain(velocities)
        })
        .fold(0.0_f64, f64::max)
}

/// The note's bar `mesh` with `mass`, at rest and moving at −0.5 along its axis towards the
/// obstacle 0.2 away, with `Δt = h/2` along the axis: `(model, U⁰, V⁰, Δt)`.
pub(crate) fn falling_box(mesh: &BoxMesh, mass: MassVariant) -> (Model, Vec<f64>, Vec<f64>, f64) {
    let d = mesh.dim();
    let model = Model::of_box(mesh, &Elasticity::NOTE, mass, Some(0.2));
    let u0 = vec![0.0; model.n_dofs()];
    let v0 = mesh.interpolate(|_| {
        let mut v = [0.0; 3];
        v[d - 1] = -0.5;
        v
    });
    let dt = mesh.element_sizes()[d - 1] / 2.0;
    (model, u0, v0, dt)
}

/// The rivals' runs checked by [`BalanceMonitor`]: the largest relative residual and whether
/// any step had contact.
pub(crate) fn monitored(
    model: &Model,
    scheme: Scheme,
    u0: &[f64],
    v0: &[f64],
    dt: f64,
    n: usize,
) -> f64 {
    let mut s = Stepper::harness(model, scheme, dt, u0, v0);
    let mut monitor = BalanceMonitor::new(model, scheme, dt);
    monitor.observe(&s.observed());
    let mut touched = false;
    for _ in 0..n {
        s.advance().unwrap();
        touched |= s.multiplier().value.iter().any(|&l| l < 0.0);
        monitor.observe(&s.observed()).expect("one step further");
    }
    assert!(touched, "{scheme}: no contact");
    assert_eq!(monitor.balanced_steps(), n, "{scheme}");
    monitor.largest_residual()
}

const RIVALS: [Scheme; 7] = [
    generalised_alpha(0.8),
    generalised_alpha(0.0),
    hht(0.05),
    Scheme::GeneralisedAlpha(AlphaParameters {
        alpha_m: 0.1,
        alpha_f: 0.3,
        beta: 0.4,
        gamma: 0.8,
    }),
    Scheme::MoreauJean {
        theta: 0.5,
        restitution: 0.0,
    },
    Scheme::MoreauJean {
        theta: 0.8,
        restitution: 0.5,
    },
    Scheme::LaursenChawla {},
];

#[test]
fn rival_balances_hold_every_step_in_1d_with_every_mass() {
    for scheme in RIVALS {
        for mass in MassVariant::PAPER {
            let (model, u0, v0) = dirichlet(mass, true);
            let worst = monitored(&model, scheme, &u0, &v0, dt(), steps());
            assert!(worst < 1e-13, "{scheme}, {mass}: residual {worst:e}");
        }
    }
}

#[test]
fn generalised_alpha_balance_holds_with_penalty_and_nitsche() {
    let bar = Bar1d::unit(NX, EndCondition::Clamped).unwrap();
    for treatment in [
        ContactTreatment::Penalty { gamma0: 10.0 },
        ContactTreatment::Nitsche {
            theta: 1.0,
            gamma0: 10.0,
        },
        ContactTreatment::Nitsche {
            theta: -1.0,
            gamma0: 10.0,
        },
    ] {
        for mass in MassVariant::PAPER {
            let (model, u0, v0) = dirichlet(mass, true);
            let model = model.with_contact_law(ContactLaw::bar1d(treatment, &bar).unwrap());
            for scheme in [generalised_alpha(0.8), hht(0.1)] {
                let worst = monitored(&model, scheme, &u0, &v0, dt(), steps());
                assert!(worst < 1e-12, "{scheme}, {treatment}, {mass}: {worst:e}");
            }
        }
    }
}

#[test]
fn rival_balances_hold_on_the_2d_and_3d_bars() {
    for mesh in [
        BoxMesh::note_2d(2, 16).unwrap(),
        BoxMesh::note_3d(2, 2, 8).unwrap(),
    ] {
        let d = mesh.dim();
        for mass in MassVariant::ON_EVERY_MESH {
            let (model, u0, v0, dt) = falling_box(&mesh, mass);
            for scheme in [RIVALS[0], RIVALS[2], RIVALS[4], RIVALS[6]] {
                let worst = monitored(&model, scheme, &u0, &v0, dt, (1.5 / dt).round() as usize);
                assert!(worst < 1e-12, "{d}D {scheme}, {mass}: residual {worst:e}");
            }
        }
    }
}

/// A balance evaluated with a parameter other than the run's leaves a residual above the
/// tolerance of `--check-balance`: the identities check the schemes' equations, they do not
/// restate them.
#[test]
fn a_balance_with_a_wrong_parameter_does_not_hold() {
    let (model, u0, v0) = dirichlet(MassVariant::Standard, true);
    let run = AlphaParameters {
        alpha_m: 0.1,
        alpha_f: 0.3,
        beta: 0.4,
        gamma: 0.8,
    };
    let scheme = Scheme::GeneralisedAlpha(run);
    let mut s = Stepper::harness(&model, scheme, dt(), &u0, &v0);
    for _ in 0..5 {
        s.advance().unwrap();
    }
    let before = snapshot_plain(&s.observed());
    let a0 = s.acceleration().unwrap().to_vec();
    s.advance().unwrap();
    let after = snapshot_plain(&s.observed());
    let a1 = s.acceleration().unwrap().to_vec();
    let relative = |p: AlphaParameters| {
        let b = energy_balance::generalised_alpha(
            &model,
            p,
            dt(),
            (&plain(&before), &plain(&after)),
            (&a0, &a1),
        );
        b.residual().abs() / b.magnitude
    };
    assert!(relative(run) < 1e-14, "{:e}", relative(run));
    for wrong in [
        AlphaParameters { gamma: 0.7, ..run },
        AlphaParameters { beta: 0.35, ..run },
        AlphaParameters {
            alpha_m: 0.0,
            ..run
        },
        AlphaParameters {
            alpha_f: 0.25,
            ..run
        },
    ] {
        assert!(
            relative(wrong) > BALANCE_TOLERANCE,
            "{wrong:?}: {:e}",
            relative(wrong)
        );
    }
    let (model, u0, v0) = dirichlet(MassVariant::Standard, true);
    let mj = Scheme::MoreauJean {
        theta: 0.5,
        restitution: 0.0,
    };
    let mut s = Stepper::harness(&model, mj, dt(), &u0, &v0);
    let (mut worst_as_theta, mut worst): (f64, f64) = (0.0, 0.0);
    for _ in 0..steps() {
        let before = snapshot_plain(&s.observed());
        s.advance().unwrap();
        let after = snapshot_plain(&s.observed());
        let b = energy_balance::theta(&model, 0.5, &plain(&before), &plain(&after));
        worst_as_theta = worst_as_theta.max(b.residual().abs() / b.magnitude);
        let b = energy_balance::moreau_jean(&model, 0.5, &plain(&before), &plain(&after));
        worst = worst.max(b.residual().abs() / b.magnitude);
    }
    assert!(worst < 1e-14, "(MJ-E): {worst:e}");
    assert!(
        worst_as_theta > BALANCE_TOLERANCE,
        "Moreau–Jean's impulse read as the θ-method's Λ_θ: {worst_as_theta:e}"
    );
}

pub(crate) type Plain = (Vec<f64>, Vec<f64>, Vec<f64>);

pub(crate) fn snapshot_plain(s: &Integration) -> Plain {
    (
        s.displacement().to_vec(),
        s.velocity().to_vec(),
        s.multiplier().value.to_vec(),
    )
}

pub(crate) fn plain(x: &Plain) -> Level<'_> {
    Level {
        displacement: &x.0,
        velocity: &x.1,
        multiplier: &x.2,
    }
}

#[test]
fn moreau_jean_keeps_newtons_law_and_loses_energy_only_at_impacts() {
    for mass in MassVariant::PAPER {
        let (model, u0, v0) = dirichlet(mass, true);
        let c = model.contact().unwrap().dofs[0];
        for restitution in [0.0, 0.5] {
            let scheme = Scheme::MoreauJean {
                theta: 0.5,
                restitution,
            };
            let mut s = Stepper::harness(&model, scheme, dt(), &u0, &v0);
            let e0 = s.energy().value;
            let mut impacts = 0;
            for n in 0..steps() {
                let (v_before, e_before) = (s.velocity()[c], s.energy().value);
                s.advance().unwrap();
                let (lambda, v_after) = (s.multiplier().value[0], s.velocity()[c]);
                assert!(
                    lambda <= 0.0,
                    "{mass} e = {restitution} step {n}: λ = {lambda}"
                );
                if lambda < 0.0 {
                    impacts += 1;
                    let law = v_after + restitution * v_before;
                    assert!(law.abs() <= 1e-12, "{mass} step {n}: v⁺ + e v⁻ = {law:e}");
                } else {
                    let change = s.energy().value - e_before;
                    assert!(
                        change.abs() <= 1e-12 * e0,
                        "{mass} step {n}: ΔE = {change:e}"
                    );
                }
            }
            assert!(impacts > 0, "{mass}: no impact");
        }
    }
}

/// Laursen–Chawla's persistency makes every product `λ_i (BΔU)_i` of (MJ-E) vanish: the energy
/// is conserved at every step, impacts included, and the gap never closes past the obstacle.
#[test]
fn laursen_chawla_conserves_the_energy_at_every_step_and_never_penetrates() {
    for mass in MassVariant::PAPER {
        let (model, u0, v0) = dirichlet(mass, true);
        let c = model.contact().unwrap().dofs[0];
        let scheme = Scheme::LaursenChawla {};
        let mut s = Stepper::harness(&model, scheme, dt(), &u0, &v0);
        let e0 = s.energy().value;
        let mut pushed = 0;
        for n in 0..steps() {
            s.advance().unwrap();
            let drift = s.energy().value - e0;
            assert!(
                drift.abs() <= 1e-12 * e0,
                "{mass} step {n}: E − E⁰ = {drift:e}"
            );
            assert!(
                s.displacement()[c] >= -1e-14,
                "{mass} step {n}: penetration"
            );
            pushed += usize::from(s.multiplier().value[0] < 0.0);
        }
        assert!(pushed > 0, "{mass}: no contact");
        if mass != MassVariant::Standard {
            // A massless contact node carries no kinetic energy for e = 0 to take.
            continue;
        }
        let mj = Scheme::MoreauJean {
            theta: 0.5,
            restitution: 0.0,
        };
        let mut dissipative = Stepper::harness(&model, mj, dt(), &u0, &v0);
        for _ in 0..steps() {
            dissipative.advance().unwrap();
        }
        assert!(
            dissipative.energy().value < (1.0 - 1e-6) * e0,
            "Moreau–Jean e = 0 loses energy where Laursen–Chawla keeps it"
        );
    }
}

#[test]
fn undefined_combinations_and_parameters_are_refused_naming_the_field() {
    let bar = Bar1d::unit(NX, EndCondition::Clamped).unwrap();
    let (model, u0, v0) = dirichlet(MassVariant::Standard, true);
    let penalty = model.clone().with_contact_law(
        ContactLaw::bar1d(ContactTreatment::Penalty { gamma0: 10.0 }, &bar).unwrap(),
    );
    let mj = Scheme::MoreauJean {
        theta: 0.5,
        restitution: 0.0,
    };
    for scheme in [mj, Scheme::LaursenChawla {}] {
        let e = integrator(&penalty, scheme, dt(), &u0, &v0, &Conventions::HARNESS)
            .err()
            .unwrap()
            .to_string();
        assert!(e.contains("contact") && e.contains("Moreau–Jean"), "{e}");
    }
    let nitsche = model.with_contact_law(
        ContactLaw::bar1d(
            ContactTreatment::Nitsche {
                theta: 1.0,
                gamma0: 10.0,
            },
            &bar,
        )
        .unwrap(),
    );
    let elastic = Conventions {
        nitsche_acceleration: NitscheAcceleration::ElasticStiffness,
        ..Conventions::HARNESS
    };
    let e = integrator(&nitsche, generalised_alpha(0.8), dt(), &u0, &v0, &elastic)
        .err()
        .unwrap()
        .to_string();
    assert!(e.contains("nitsche_acceleration"), "{e}");
    for (text, field) in [
        ("hht(alpha=0.5)", "alpha"),
        ("generalised-alpha(rho_inf=1.5)", "rho_inf"),
        (
            "generalised-alpha(alpha_m=1,alpha_f=0,beta=0.25,gamma=0.5)",
            "alpha_m",
        ),
        (
            "generalised-alpha(alpha_m=0,alpha_f=1,beta=0.25,gamma=0.5)",
            "alpha_f",
        ),
        (
            "generalised-alpha(alpha_m=0,alpha_f=0,beta=0,gamma=0.5)",
            "beta",
        ),
        ("moreau-jean(theta=0,e=0)", "theta"),
        ("moreau-jean(theta=0.5,e=2)", "e"),
        ("moreau-jean(theta=0.5)", "scheme"),
    ] {
        let e = text.parse::<Scheme>().unwrap_err();
        assert_eq!(e.name, field, "{text}: {e}");
    }
}

#[test]
fn rival_names_parse_back_to_the_same_scheme() {
    let forms = [
        "generalised-alpha",
        "hht",
        "moreau-jean",
        "generalised-alpha(rho_inf=0.5)",
        "generalised-alpha(rho_inf=0.9)",
        "hht(alpha=0.3)",
        "generalised-alpha(alpha_m=0.1,alpha_f=0.3,beta=0.4,gamma=0.8)",
        "moreau-jean(theta=1,e=0.5)",
        "laursen-chawla",
        "contact-stabilised-newmark",
        "contact-stabilised-newmark-dissipative",
    ];
    for text in forms {
        let scheme: Scheme = text.parse().unwrap();
        assert_eq!(scheme.name().parse::<Scheme>().unwrap(), scheme, "{text}");
        let json = serde_json::to_string(&scheme).unwrap();
        assert_eq!(serde_json::from_str::<Scheme>(&json).unwrap(), scheme);
    }
    assert_eq!(
        "generalised-alpha(rho_inf=0.5)"
            .parse::<Scheme>()
            .unwrap()
            .name(),
        "generalised-alpha(rho_inf=0.5)"
    );
    assert!(generalised_alpha(0.8).warning().is_none());
    assert!(hht(0.05).warning().is_none());
    let unstable = "moreau-jean(theta=0.4,e=0)".parse::<Scheme>().unwrap();
    assert!(unstable.warning().unwrap().contains("theta"));
}
