//! `reports/schemes.md` ("Which scheme to trust", `studies::schemes`) on a small tables study:
//! a row per case in every section, and the stability suite's section only when its records are
//! given, each case with its long-horizon verdict and its count of hard cases held, failed and
//! undecided, read from the records' own decisions.

use std::collections::BTreeSet;
use std::path::Path;

use signorini::engine::fem::MassVariant;
use signorini::harness::reference::exact::run_study;
use signorini::harness::run::norms::Norm;
use signorini::harness::study::decision::Verdict as Decided;
use signorini::harness::study::sensitivity::{run_sensitivity, EnsembleConfig};
use signorini::harness::study::{Case, StudyConfig};
use signorini::studies::schemes::render;
use signorini::studies::stability::{hard_cases, judge};

use crate::benchmarks;

fn case(scheme: &str, mass: MassVariant) -> Case {
    Case {
        scheme: scheme.parse().unwrap(),
        mass,
    }
}

#[test]
fn the_ranking_carries_the_stability_suite_when_its_records_are_there() {
    let cases = [
        case("crank-nicolson", MassVariant::Standard),
        case("crank-nicolson", MassVariant::Redistributed),
        case("contact-stabilised-newmark", MassVariant::Standard),
    ];
    let norms: BTreeSet<Norm> = Norm::ALL.into_iter().collect();
    let config = StudyConfig {
        levels: vec![10, 20, 40],
        ..StudyConfig::paper_default()
    };
    let study = run_study(
        &benchmarks::dirichlet(config.horizon),
        &cases,
        &norms,
        &config,
    )
    .unwrap();
    let longer_config = StudyConfig {
        horizon: 9.0,
        ..config.clone()
    };
    let longer = run_study(&benchmarks::dirichlet(9.0), &cases, &norms, &longer_config).unwrap();
    let ensemble = EnsembleConfig {
        members: 2,
        amplitude: 1e-13,
    };
    let sensitivity = run_sensitivity(
        &benchmarks::dirichlet(config.horizon),
        &cases,
        &norms,
        &config,
        ensemble,
    )
    .unwrap();

    let without = render(&study, &sensitivity, &longer, None);
    let cost = without
        .split("## Cost to reach a target error")
        .nth(1)
        .unwrap();
    for c in cases {
        let row = cost
            .lines()
            .find(|l| l.starts_with(&format!("| {} |", label_of(c))))
            .unwrap_or_else(|| panic!("a cost row for {}: {cost}", c.id()));
        assert!(row.contains("| wall [") && row.ends_with("] s |"), "{row}");
    }
    assert!(cost.contains("**Cheapest in wall time**"), "{cost}");
    assert!(!without.contains("## Over 100 periods"), "{without}");
    for section in [
        "## Convergence rates",
        "## Oscillation, energy and round-off",
        "## Cost to reach a target error",
    ] {
        assert!(without.contains(section), "{section}");
    }

    // Two hard cases of the suite, the long horizon among them; the Redistributed Crank–Nicolson
    // is left out of the records, as a suite run without it would be.
    let hard: Vec<_> = hard_cases(Path::new(env!("CARGO_MANIFEST_DIR")), false)
        .unwrap()
        .into_iter()
        .filter(|h| ["long-horizon", "ratio-0.5"].contains(&h.name))
        .collect();
    let records: Vec<_> = hard
        .iter()
        .flat_map(|h| [cases[0], cases[2]].map(|c| judge(h, c).unwrap()))
        .collect();
    let with = render(&study, &sensitivity, &longer, Some(&records));
    for md in [&without, &with] {
        let indented: Vec<&str> = md.lines().filter(|l| l.starts_with(' ')).collect();
        assert!(indented.is_empty(), "markdown lines indented: {indented:?}");
    }
    let section = with
        .split("## Over 100 periods and on the hard cases")
        .nth(1)
        .expect("the stability section")
        .split("\n## ")
        .next()
        .unwrap();
    assert!(section.contains("of the 2 hard cases"), "{section}");
    for c in [cases[0], cases[2]] {
        let mine: Vec<_> = records.iter().filter(|r| r.case == c.id()).collect();
        let long = mine.iter().find(|r| r.hard_case == "long-horizon").unwrap();
        let count = |v| {
            mine.iter()
                .filter(|r| r.stays_stable().verdict == v)
                .count()
        };
        let row = section
            .lines()
            .find(|l| l.starts_with(&format!("| {} |", label_of(c))))
            .unwrap_or_else(|| panic!("a row for {}: {section}", c.id()));
        assert!(row.contains(&long.verdict_text()), "{row}");
        assert!(
            row.ends_with(&format!(
                "| {} / {} / {} |",
                count(Decided::Holds),
                count(Decided::Fails),
                count(Decided::Undecided)
            )),
            "{row}"
        );
    }
    assert!(
        section.contains("not in the suite"),
        "the case without records says so: {section}"
    );
    // Crank–Nicolson with the standard mass diverges over 100 periods: it cannot be listed
    // among those that stay stable everywhere.
    let everywhere = section
        .lines()
        .find(|l| l.starts_with("**Stays numerically stable on every hard case**"))
        .unwrap();
    assert!(!everywhere.contains(&label_of(cases[0])), "{everywhere}");
}

/// The label `schemes.md` gives a case's row.
fn label_of(c: Case) -> String {
    format!("{} / {}", c.scheme.label(), c.mass.paper_label())
}
