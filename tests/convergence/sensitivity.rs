//! The round-off sensitivity study: a chaotic case and a reproducible one are told apart by the
//! module's fixed rules (the reproducible one on its screening members alone), the study is
//! bit-reproducible, and bad ensemble input is refused.

use crate::{benchmarks, common};

use std::collections::BTreeSet;

use common::expect_error;
use signorini::engine::fem::MassVariant;
use signorini::engine::schemes::Scheme;
use signorini::harness::run::norms::Norm;
use signorini::harness::study::sensitivity::{
    run_sensitivity, EnsembleConfig, SensitivityClass, PARTING, SCREEN_MEMBERS,
};
use signorini::harness::study::{Case, StudyConfig};

/// Crank–Nicolson with the paper's two masses.
fn crank_nicolson_cases() -> Vec<Case> {
    MassVariant::PAPER
        .into_iter()
        .map(|mass| Case {
            scheme: Scheme::CRANK_NICOLSON,
            mass,
        })
        .collect()
}

fn small_sensitivity() -> signorini::harness::study::sensitivity::Sensitivity {
    let config = StudyConfig {
        levels: vec![20, 40, 80],
        ratio: 10.0,
        horizon: 3.0,
        settings: Default::default(),
    };
    let cases = crank_nicolson_cases();
    let norms: BTreeSet<Norm> = [Norm::DisplacementLinfH, Norm::EnergyL2].into();
    run_sensitivity(
        &benchmarks::dirichlet(3.0),
        &cases,
        &norms,
        &config,
        EnsembleConfig {
            members: 6,
            amplitude: 1e-13,
        },
    )
    .unwrap()
}

#[test]
fn crank_nicolson_is_chaotic_with_the_standard_mass_and_reproducible_with_the_redistributed() {
    let s = small_sensitivity();
    let standard = s.case("crank-nicolson/standard").unwrap();
    assert_eq!(standard.class, SensitivityClass::Chaotic, "{standard:#?}");
    assert!(standard.chaotic);
    // The separation grows exponentially: a positive rate, parting within the run.
    assert!(standard
        .separation_growth
        .iter()
        .flatten()
        .all(|&g| g > 0.0));
    assert!(standard.predictability_steps.iter().any(Option::is_some));
    // It parted in the screen, so all six members of each set ran at every level.
    assert_eq!((standard.members, standard.step_members), (6, 6));
    assert!(standard.wall_seconds.iter().all(|l| l.len() == 1 + 6));
    let redistributed = s.case("crank-nicolson/redistributed").unwrap();
    assert_eq!(redistributed.class, SensitivityClass::Reproducible);
    // None of its screening members parted: the other two of each set were not run.
    assert_eq!(
        (redistributed.members, redistributed.step_members),
        (SCREEN_MEMBERS, SCREEN_MEMBERS)
    );
    assert!(redistributed
        .wall_seconds
        .iter()
        .all(|l| l.len() == 1 + SCREEN_MEMBERS));
    assert!(redistributed
        .predictability_steps
        .iter()
        .all(Option::is_none));
    assert!(redistributed
        .largest_separation
        .iter()
        .all(|&d| d <= PARTING));
    assert!(redistributed.separation_growth.iter().all(Option::is_none));
    // Its members agree far below the 1 % of the old gate.
    assert!(redistributed.relative_error_spread("u_Linf_H").unwrap() < 1e-6);
    // min ≤ median ≤ max everywhere.
    for c in &s.cases {
        for r in c.rates.values().chain(c.errors.values().flatten()) {
            assert!(r.min <= r.median && r.median <= r.max, "{r:?}");
        }
    }
}

#[test]
fn the_study_reproduces_bit_for_bit() {
    let measured = || {
        let mut cases = small_sensitivity().cases;
        for c in &mut cases {
            assert!(c.wall_seconds.iter().flatten().all(|s| *s > 0.0));
            c.wall_seconds.clear();
        }
        serde_json::to_string(&cases).unwrap()
    };
    assert_eq!(measured(), measured(), "every figure but the wall times");
}

#[test]
fn bad_ensemble_input_exits_2_naming_the_field() {
    let scene = "scenes/bar1d-dirichlet.json";
    expect_error(
        &["sensitivity", scene, "--members", "1"],
        2,
        &["members", "[2, 1024]"],
    );
    expect_error(
        &["sensitivity", scene, "--amplitude", "-1e-13"],
        2,
        &["amplitude", "> 0"],
    );
    expect_error(
        &["sensitivity", scene, "--amplitude", "0.5"],
        2,
        &["amplitude", "(0, 1e-3]"],
    );
    expect_error(
        &["sensitivity", "scenes/bar2d.json", "--members", "1"],
        2,
        &["members", "[2, 1024]"],
    );
}

#[test]
fn the_command_writes_its_report_and_json() {
    let dir = std::env::temp_dir().join(format!("signorini-sensitivity-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let text = std::fs::read_to_string(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/bar1d-dirichlet.json"),
    )
    .unwrap();
    let scene = dir.join("scene.json");
    std::fs::write(
        &scene,
        text.replacen("[10, 20, 40, 80, 160, 320, 640]", "[10, 20, 40]", 1),
    )
    .unwrap();
    let out = common::signorini(&[
        "sensitivity",
        &scene.to_string_lossy(),
        "--members",
        "3",
        "--out",
        &dir.to_string_lossy(),
    ]);
    let stdout = common::success_stdout(&out);
    assert!(stdout.contains("crank-nicolson/standard"), "{stdout}");
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("sensitivity.json")).unwrap())
            .unwrap();
    let cases = json["cases"].as_array().unwrap();
    assert_eq!(cases.len(), 14);
    for field in [
        "case",
        "class",
        "chaotic",
        "members",
        "amplitude",
        "rates",
        "errors",
        "predictability_steps",
        "separation_growth",
    ] {
        assert!(cases[0].get(field).is_some(), "{field} missing");
    }
    assert_eq!(cases[0]["errors"]["u_Linf_H"].as_array().unwrap().len(), 3);
    assert!(dir.join("sensitivity.md").exists());
    let _ = std::fs::remove_dir_all(&dir);
}

/// Tables 1–2 show a chaotic case's ensemble median and range, marked †, and the Agreement
/// section says whether the paper's value is inside that range; reproducible rows are unchanged.
#[test]
fn the_tables_mark_a_chaotic_case_with_its_ensemble_range() {
    use signorini::studies::tables::agreement::{disagreements, paper_tables};
    use signorini::studies::tables::paper::PaperTables;
    let s = small_sensitivity();
    let cases = crank_nicolson_cases();
    let study = signorini::harness::reference::exact::run_study(
        &benchmarks::dirichlet(3.0),
        &cases,
        &[Norm::DisplacementLinfH, Norm::EnergyL2].into(),
        &s.config,
    )
    .unwrap();
    let paper = PaperTables::load();
    let plain = paper_tables(&study, &paper, None);
    let marked = paper_tables(&study, &paper, Some(&s));
    assert!(!plain.contains('†'));
    let chaotic = s.case("crank-nicolson/standard").unwrap().rates["u_Linf_H"];
    let expected = format!(
        "{:.2}† [{:.2}, {:.2}]",
        chaotic.median, chaotic.min, chaotic.max
    );
    assert!(marked.contains(&expected), "{expected} not in {marked}");
    let row = |t: &str, mass: &str| {
        t.lines()
            .find(|l| l.starts_with("| Crank–Nicolson") && l.contains(mass))
            .map(str::to_string)
    };
    assert_eq!(row(&plain, "| MOD |"), row(&marked, "| MOD |"));
    for d in disagreements(&study, &paper, Some(&s)) {
        let words = d.diagnosis(9.0);
        if d.case == "crank-nicolson/standard" {
            let e = d
                .ensemble
                .expect("a chaotic case carries its ensemble")
                .spread;
            let inside = (e.min..=e.max).contains(&d.paper);
            assert!(
                words.contains(if inside {
                    "inside our ensemble"
                } else {
                    "outside our ensemble"
                }),
                "{words}"
            );
        } else {
            assert!(d.ensemble.is_none());
        }
    }
}
