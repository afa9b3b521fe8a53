//! CI guards of the stability suite (the fast subset; `make stability` runs everything): the
//! schemes meant to be stable stay stable over 100 periods, and the detector does flag the
//! known energy growth of Crank–Nicolson with the standard mass.

use signorini::fem::MassVariant;
use signorini::run::Problem1d;
use signorini::schemes::Scheme;
use signorini::stability::{hard_cases, judge, HardCase, Verdict};
use signorini::study::Case;

fn long_horizon() -> HardCase {
    hard_cases(true)
        .into_iter()
        .find(|h| h.name == "long-horizon")
        .expect("the CI subset has the long horizon")
}

fn case(scheme: &str, mass: MassVariant) -> Case {
    Case {
        scheme: scheme.parse().unwrap(),
        mass,
    }
}

#[test]
fn conservative_schemes_keep_energy_bounded_with_the_redistributed_mass() {
    // γ = ½ Newmark schemes conserve energy without contact; with M^mod they lose or gain at
    // most O(h) per impact and must not drift over 100 periods.
    let hard = long_horizon();
    for scheme in ["crank-nicolson", "newmark-2"] {
        let r = judge(&hard, case(scheme, MassVariant::Redistributed)).unwrap();
        assert!(
            r.max_energy_drift < 1e-2,
            "{}: drift {:e}",
            r.case,
            r.max_energy_drift
        );
        assert!(
            r.energy_trend.abs() < 1e-2,
            "{}: trend {:e}",
            r.case,
            r.energy_trend
        );
        assert_eq!(r.verdict, Verdict::Stable, "{}", r.case);
        assert!(r.complementarity_violation < 1e-12, "{}", r.case);
    }
}

#[test]
fn dissipative_schemes_never_gain_energy() {
    let hard = long_horizon();
    for scheme in ["backward-euler", "newmark-1"] {
        for mass in MassVariant::ALL {
            let r = judge(&hard, case(scheme, mass)).unwrap();
            assert!(
                r.max_energy_step_increase <= 1e-12,
                "{}: a step gained {:e} E_0",
                r.case,
                r.max_energy_step_increase
            );
            assert_eq!(r.verdict, Verdict::Dissipative, "{}", r.case);
        }
    }
}

#[test]
fn no_redistributed_case_diverges_or_grows() {
    let hard = long_horizon();
    for scheme in Scheme::paper_schemes() {
        let r = judge(
            &hard,
            Case {
                scheme,
                mass: MassVariant::Redistributed,
            },
        )
        .unwrap();
        assert!(r.failure.is_none(), "{}: {:?}", r.case, r.failure);
        assert!(
            !matches!(r.verdict, Verdict::Diverged | Verdict::EnergyGrowth),
            "{}: {}",
            r.case,
            r.verdict.word()
        );
    }
}

#[test]
fn the_detector_flags_crank_nicolson_with_the_standard_mass() {
    // Ten periods: the energy has grown by orders of magnitude but is still finite.
    let hard = HardCase {
        name: "ten-periods",
        description: "",
        problem: Problem1d::signorini_dirichlet(30.0),
        nx: 80,
        ratio: 10.0,
    };
    let r = judge(&hard, case("crank-nicolson", MassVariant::Standard)).unwrap();
    assert_eq!(
        r.verdict,
        Verdict::EnergyGrowth,
        "drift {:e}",
        r.max_energy_drift
    );
    // One hundred periods: unbounded.
    let r = judge(
        &long_horizon(),
        case("crank-nicolson", MassVariant::Standard),
    )
    .unwrap();
    assert_eq!(
        r.verdict,
        Verdict::Diverged,
        "drift {:e}",
        r.max_energy_drift
    );
}

#[test]
fn a_non_finite_state_is_a_diverged_verdict_naming_the_step() {
    // Newmark(¼, 0.55) violates β ≥ (γ + ½)²/4 and blows up with the massless node.
    let r = judge(
        &long_horizon(),
        case("newmark(beta=0.25,gamma=0.55)", MassVariant::Redistributed),
    )
    .unwrap();
    assert_eq!(r.verdict, Verdict::Diverged);
    let failure = r.failure.expect("the run stopped");
    assert!(
        failure.contains("non-finite") && failure.contains("step"),
        "{failure}"
    );
}
