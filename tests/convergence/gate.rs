//! The regression gate: the Tables 1–2 study and the extended table against `golden/`, the
//! rendered tables as an insta snapshot, and proof that the gate fails when a scheme changes.

use crate::benchmarks;
use std::collections::BTreeSet;
use std::path::Path;

use signorini::engine::schemes::Scheme;
use signorini::harness::reference::exact::run_study;
use signorini::harness::run::norms::Norm;
use signorini::harness::study::golden::{
    compare, gate, read_golden, render_drifts, Golden, Tolerances,
};
use signorini::harness::study::sensitivity::{Sensitivity, SensitivityClass};
use signorini::harness::study::{Case, Study, StudyConfig};
use signorini::studies::extended::{
    extended_sensitivity, extended_studies, read_extended_golden, GOLDEN_EXTENDED, TREATMENTS,
};
use signorini::studies::gravity::{gravity_sensitivity, gravity_study, GOLDEN_GRAVITY};
use signorini::studies::tables::agreement::paper_tables;
use signorini::studies::tables::paper::PaperTables;
use signorini::studies::tables::{tables_sensitivity, tables_study, GOLDEN_TABLES};

fn golden() -> Golden {
    read_golden(&Path::new(env!("CARGO_MANIFEST_DIR")).join(GOLDEN_TABLES)).unwrap()
}

/// Holds `study` to `golden` at what each case's reproducibility allows: the non-chaotic cases
/// entry by entry, the chaotic ones by the ensemble statistics that `ensembles` measures for
/// them. Returns the chaotic cases.
fn assert_gate<E: std::fmt::Debug>(
    what: &str,
    golden: &Golden,
    study: &Study,
    ensembles: impl FnOnce(&[Case]) -> Result<Sensitivity, E>,
) -> Vec<Case> {
    assert!(
        golden.cases.iter().all(|g| g.class.is_some()),
        "{what}: make golden attaches every case's round-off class"
    );
    let drifts = gate(golden, study, ensembles).unwrap();
    assert!(drifts.is_empty(), "{what}: {}", render_drifts(&drifts));
    golden.chaotic_cases(study)
}

/// Every case is held at what its reproducibility allows: reproducible and event-sensitive
/// cases entry by entry at tolerances from their measured spread, chaotic cases by their
/// ensemble statistics. The table snapshot holds the rows whose digits are reproducible.
#[test]
fn tables_study_matches_the_golden_rates_and_errors() {
    let golden = golden();
    let study = tables_study(Path::new(env!("CARGO_MANIFEST_DIR"))).unwrap();
    let chaotic = assert_gate(GOLDEN_TABLES, &golden, &study, |cases| {
        tables_sensitivity(Path::new(env!("CARGO_MANIFEST_DIR")), cases)
    });

    let mut reproducible = study.clone();
    reproducible.cases.retain(|c| !chaotic.contains(&c.case));
    let mut settings = insta::Settings::clone_current();
    settings.set_snapshot_path(concat!(env!("CARGO_MANIFEST_DIR"), "/golden"));
    settings.set_prepend_module_to_snapshot(false);
    settings.bind(|| {
        insta::assert_snapshot!(
            "tables_1d_dirichlet",
            paper_tables(&reproducible, &PaperTables::load(), None)
        );
    });
}

/// Test (b) of issue 15: a 0.1 % change in one reproducible case's error is caught (the old 1 %
/// gate let it through), and so is a rate moved by ten times its tolerance.
#[test]
fn the_gate_catches_a_small_change_in_a_reproducible_case() {
    let golden = golden();
    let study = tables_study(Path::new(env!("CARGO_MANIFEST_DIR"))).unwrap();
    let id = "crank-nicolson/redistributed";
    let g = golden.cases.iter().find(|g| g.case == id).unwrap();
    assert_eq!(g.class, Some(SensitivityClass::Reproducible));
    let mut moved = study.clone();
    let case = moved.cases.iter_mut().find(|c| c.case.id() == id).unwrap();
    case.rates[0].errors[3] *= 1.001;
    let drifts = compare(&golden, &moved);
    assert_eq!(drifts.len(), 1, "{}", render_drifts(&drifts));
    assert_eq!(drifts[0].case, id);
    assert!(drifts[0].tolerance < 1e-4, "{}", render_drifts(&drifts));
    let mut old = golden.clone();
    for g in &mut old.cases {
        g.class = None;
        for n in g.norms.values_mut() {
            n.error_rel = None;
            n.rate_abs = None;
        }
    }
    assert!(
        compare(&old, &moved).is_empty(),
        "the old 1 % gate passed it"
    );
}

#[test]
fn gravity_study_matches_the_golden_rates_and_errors() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let study = gravity_study(root).unwrap();
    let golden = read_golden(&root.join(GOLDEN_GRAVITY)).unwrap();
    assert_gate(GOLDEN_GRAVITY, &golden, &study, |cases| {
        gravity_sensitivity(root, cases)
    });
    // Crank–Nicolson with both masses converges in H (the paper's Figure 3 a–b): the
    // redistributed mass at every level; the standard mass only from NX = 80 on (its coarse
    // levels bounce erratically, see reports/gravity.md), which is what this checks for it.
    let crank_nicolson = study
        .cases
        .iter()
        .filter(|c| c.case.scheme == Scheme::CRANK_NICOLSON);
    for c in crank_nicolson {
        let first = match c.case.mass {
            signorini::engine::fem::MassVariant::Redistributed => 0,
            // The study runs `MassVariant::PAPER`: this arm is the standard mass.
            _ => c.levels.iter().position(|l| l.nx == 80).unwrap(),
        };
        for norm in [Norm::DisplacementLinfH, Norm::DisplacementL2H] {
            let errors = &c.norm(norm).unwrap().errors[first..];
            assert!(
                errors.windows(2).all(|w| w[1] < w[0]),
                "{} {norm}: errors do not decrease: {errors:?}",
                c.case.id()
            );
        }
    }
}

/// Crank–Nicolson with γ moved from ½ to 0.55 (and β to 0.28 ≥ (γ + ½)²/4, which keeps it
/// unconditionally stable), compared under Crank–Nicolson's name: what a change to the scheme's
/// code would look like to the gate.
#[test]
fn gate_reports_a_deliberately_wrong_scheme() {
    let config = StudyConfig::paper_default();
    let wrong = Scheme::Newmark {
        beta: 0.28,
        gamma: 0.55,
    };
    let cases: Vec<Case> = signorini::engine::fem::MassVariant::PAPER
        .into_iter()
        .map(|mass| Case {
            scheme: wrong,
            mass,
        })
        .collect();
    let norms: BTreeSet<Norm> = Norm::ALL.into_iter().collect();
    let mut study = run_study(
        &benchmarks::dirichlet(config.horizon),
        &cases,
        &norms,
        &config,
    )
    .unwrap();
    for c in &mut study.cases {
        c.case.scheme = Scheme::CRANK_NICOLSON;
    }
    let drifts = compare(&golden(), &study);
    let rate_drifts = drifts.iter().filter(|d| d.quantity == "rate").count();
    assert!(
        rate_drifts >= 4,
        "the gate missed a perturbed γ: {}",
        render_drifts(&drifts)
    );
    assert!(drifts.iter().all(|d| d.case.starts_with("crank-nicolson/")));
    let table = render_drifts(&drifts);
    assert!(table.contains("| crank-nicolson/redistributed | energy_Linf | rate |"));
}

/// A small real study (two cases, three levels) to exercise the comparator.
fn small_study() -> Study {
    let config = StudyConfig {
        levels: vec![10, 20, 40],
        ratio: 10.0,
        horizon: 3.0,
        settings: Default::default(),
    };
    let cases = [Case {
        scheme: Scheme::CRANK_NICOLSON,
        mass: signorini::engine::fem::MassVariant::Redistributed,
    }];
    let norms: BTreeSet<Norm> = [Norm::DisplacementLinfH, Norm::EnergyL2].into();
    run_study(&benchmarks::dirichlet(3.0), &cases, &norms, &config).unwrap()
}

#[test]
fn comparator_passes_identical_and_catches_each_kind_of_drift() {
    let study = small_study();
    let golden = Golden::from_study(&study, Tolerances::default());
    assert!(compare(&golden, &study).is_empty());

    // An error 0.5 % off passes, 1.5 % off fails, on exactly that entry.
    let scaled = |factor: f64| {
        let mut g = golden.clone();
        g.cases[0].norms.get_mut("u_Linf_H").unwrap().errors[1] *= factor;
        g
    };
    assert!(compare(&scaled(1.005), &study).is_empty());
    let g = scaled(1.015);
    let drifts = compare(&g, &study);
    assert_eq!(drifts.len(), 1, "{}", render_drifts(&drifts));
    assert_eq!(drifts[0].quantity, "error[NX=20]");
    assert_eq!(drifts[0].norm, "u_Linf_H");

    // A rate 0.03 off fails at the default 0.02 and passes with a per-norm override of 0.05.
    let mut g = golden.clone();
    g.cases[0].norms.get_mut("energy_L2").unwrap().rate += 0.03;
    assert_eq!(compare(&g, &study).len(), 1);
    g.tolerances
        .rate_abs_per_norm
        .insert("energy_L2".to_string(), 0.05);
    assert!(compare(&g, &study).is_empty());

    // NaN now or in the golden file is a drift, never a pass.
    let mut broken = study.clone();
    broken.cases[0].rates[0].errors[2] = f64::NAN;
    assert!(!compare(&golden, &broken).is_empty());
    let mut g = golden.clone();
    g.cases[0].norms.get_mut("u_Linf_H").unwrap().rate = f64::INFINITY;
    assert!(!compare(&g, &study).is_empty());

    // Other levels than the golden file's: every case drifts.
    let mut g = golden.clone();
    g.levels = vec![10, 20, 80];
    assert_eq!(compare(&g, &study).len(), 1);

    // A case the golden file lacks.
    let mut g = golden;
    g.cases.clear();
    assert_eq!(compare(&g, &study)[0].quantity, "missing");
}

/// The extended table (issue 11): every treatment's study matches its golden values, each case
/// at what its reproducibility allows, and the golden file holds exactly the treatments of the
/// table.
#[test]
fn extended_studies_match_the_golden_rates_and_errors() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let golden = read_extended_golden(&root.join(GOLDEN_EXTENDED)).unwrap();
    let names: Vec<&str> = golden
        .treatments
        .iter()
        .map(|t| t.contact.as_str())
        .collect();
    assert_eq!(names, TREATMENTS);
    for s in extended_studies(root).unwrap() {
        let g = golden
            .treatment(&s.contact)
            .unwrap_or_else(|| panic!("{} is not in {GOLDEN_EXTENDED}", s.contact));
        assert_gate(&s.contact, g, &s.study, |cases| {
            extended_sensitivity(root, &s.contact, cases)
        });
    }
}
