//! CI guards of the stability suite (the fast subset; `make stability` runs everything): the
//! schemes meant to be stable stay stable over 100 periods, the rivals keep their energy claims
//! there, and the detector does flag the known energy growth of Crank–Nicolson with the
//! standard mass.

use crate::benchmarks;
use crate::report_shards::three_shards;
use std::path::Path;

use signorini::engine::fem::MassVariant;
use signorini::engine::schemes::energy_balance::BALANCE_TOLERANCE;
use signorini::engine::schemes::Scheme;
use signorini::harness::study::decision::Verdict as Decided;
use signorini::harness::study::executor::{Executed, Executor};
use signorini::harness::study::sensitivity::SensitivityClass;
use signorini::harness::study::Case;
use signorini::studies::stability::{
    hard_cases, judge, render, run_suite, run_suite_on, HardCase, Verdict, STABILITY_ENSEMBLE,
};

fn long_horizon() -> HardCase {
    hard_cases(Path::new(env!("CARGO_MANIFEST_DIR")), true)
        .unwrap()
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
    for scheme in Scheme::paper_schemes()
        .into_iter()
        .chain(Scheme::rival_schemes())
        .filter(|s| s.is_defined_with(MassVariant::Redistributed))
    {
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
        let balance = r.max_balance_residual.expect("measured");
        assert!(balance <= BALANCE_TOLERANCE, "{}: {balance:e}", r.case);
    }
}

/// Issue 35, the rivals over 100 periods: Laursen–Chawla conserves the energy with either mass,
/// its drift over all 240 000 steps below the round-off the balance check accepts in one, and
/// contact-stabilised Newmark stays numerically stable with the standard mass in both velocity
/// updates, losing energy, where Crank–Nicolson, its scheme without the projection, diverges.
#[test]
fn the_rivals_keep_their_energy_claims_over_100_periods() {
    let hard = long_horizon();
    for mass in MassVariant::PAPER {
        let r = judge(&hard, case("laursen-chawla", mass)).unwrap();
        assert!(
            r.max_energy_drift < BALANCE_TOLERANCE,
            "{}: drift {:e}",
            r.case,
            r.max_energy_drift
        );
        assert_eq!(
            r.sensitivity.expect("measured").class,
            SensitivityClass::Reproducible
        );
    }
    for scheme in [
        "contact-stabilised-newmark",
        "contact-stabilised-newmark-dissipative",
    ] {
        let r = judge(&hard, case(scheme, MassVariant::Standard)).unwrap();
        let stays = r.stays_stable();
        assert_eq!(
            stays.verdict,
            Decided::Holds,
            "{}: {}",
            r.case,
            stays.reason
        );
        assert!(
            r.energy_trend < 0.0,
            "{}: trend {:e}",
            r.case,
            r.energy_trend
        );
        let balance = r.max_balance_residual.expect("measured");
        assert!(balance <= BALANCE_TOLERANCE, "{}: {balance:e}", r.case);
    }
}

#[test]
fn the_detector_flags_crank_nicolson_with_the_standard_mass() {
    // Ten periods: the energy has grown by orders of magnitude but is still finite.
    let hard = HardCase {
        name: "ten-periods",
        description: "",
        problem: benchmarks::dirichlet(30.0),
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
    // The scheme still solves its equations: the growth is the contact work of eq. (33).
    let balance = r.max_balance_residual.expect("measured");
    assert!(balance <= BALANCE_TOLERANCE, "{balance:e}");
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

/// Issue 15, item 5: every run reports its round-off sensitivity, and "stays numerically stable"
/// needs it. Over 100 periods Crank–Nicolson with the redistributed mass is reproducible; with
/// the standard mass the members follow the unperturbed run until the first impact (t = 1) and
/// part exponentially after it.
#[test]
fn every_run_reports_its_round_off_sensitivity() {
    let hard = long_horizon();
    let calm = judge(&hard, case("crank-nicolson", MassVariant::Redistributed)).unwrap();
    let s = calm.sensitivity.expect("measured");
    assert_eq!(s.class, SensitivityClass::Reproducible);
    assert_eq!(s.members, STABILITY_ENSEMBLE.members);
    assert_eq!(s.predictability_step, None);
    assert!(s.largest_separation <= 1e-8, "{:e}", s.largest_separation);
    assert_eq!(calm.member_verdicts, vec![Verdict::Stable; s.members]);
    assert_eq!(calm.stays_stable().verdict, Decided::Holds);

    let chaotic = judge(&hard, case("newmark-2", MassVariant::Standard)).unwrap();
    let s = chaotic.sensitivity.expect("measured");
    assert_eq!(s.class, SensitivityClass::Chaotic);
    let t = s.predictability_time.expect("the members part");
    assert!(t > 1.0 && t < 3.0, "parts at t = {t}");
    assert!(s.separation_growth.is_some_and(|g| g > 0.0));
    let stays = chaotic.stays_stable();
    assert_eq!(stays.verdict, Decided::Fails);
    assert!(
        stays
            .reason
            .contains("round-off chaotic (predictable to t = "),
        "{}",
        stays.reason
    );
}

/// A stable verdict with a chaotic ensemble does not stay numerically stable; one whose
/// perturbed members are judged otherwise, or whose sensitivity was not measured, cannot be
/// decided.
#[test]
fn stays_stable_needs_every_member_and_no_chaos() {
    let hard = long_horizon();
    let calm = judge(&hard, case("crank-nicolson", MassVariant::Redistributed)).unwrap();
    let mut chaotic = calm.clone();
    if let Some(s) = chaotic.sensitivity.as_mut() {
        s.class = SensitivityClass::Chaotic;
    }
    assert_eq!(chaotic.stays_stable().verdict, Decided::Fails);
    let mut split = calm.clone();
    split.member_verdicts[1] = Verdict::Oscillating;
    let stays = split.stays_stable();
    assert_eq!(stays.verdict, Decided::Undecided);
    assert!(
        stays
            .reason
            .contains("members: 3 stable, 1 oscillates spuriously"),
        "{}",
        stays.reason
    );
    assert_eq!(split.other_member_verdicts(), vec!["oscillates spuriously"]);
    let mut unmeasured = calm;
    unmeasured.sensitivity = None;
    assert_eq!(unmeasured.stays_stable().verdict, Decided::Undecided);
}

#[test]
fn the_merge_of_three_shards_of_the_suite_equals_the_unsharded_suite() {
    // Two fast hard cases (few, large steps) × the 14 cases, as `stability --shard k/3` and
    // `merge` run them: the records equal bit for bit, so do stability.md and stability.json.
    let hard: Vec<HardCase> = hard_cases(Path::new(env!("CARGO_MANIFEST_DIR")), false)
        .unwrap()
        .into_iter()
        .filter(|h| ["ratio-0.5", "ratio-1"].contains(&h.name))
        .collect();
    assert_eq!(hard.len(), 2);
    let cases = Case::paper_matrix();
    let full = run_suite(&hard, &cases).unwrap();
    let merged = three_shards(&|executor| run_suite_on(executor, &hard, &cases).unwrap());
    let Executed::Complete(records) =
        run_suite_on(&Executor::Merge(merged), &hard, &cases).unwrap()
    else {
        panic!("a merge hands back every record");
    };
    assert_eq!(format!("{records:?}"), format!("{full:?}"));
    assert_eq!(render(&hard, &records), render(&hard, &full));
    assert_eq!(
        serde_json::to_string_pretty(&records).unwrap(),
        serde_json::to_string_pretty(&full).unwrap()
    );
}
