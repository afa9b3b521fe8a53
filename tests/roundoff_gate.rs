//! Test (a) of issue 15: an arithmetically equivalent rewrite of a chaotic case's step (the
//! predictor `U + ΔtV + aΔt²A` evaluated as `U + Δt(V + aΔtA)`, the factored
//! `PredictorForm` of the settings' conventions) keeps the gate green, while the old 1 %
//! per-level check fails on it.

use std::collections::BTreeSet;
use std::path::Path;

use signorini::engine::fem::MassVariant;
use signorini::engine::schemes::conventions::PredictorForm;
use signorini::engine::schemes::Scheme;
use signorini::harness::problem::Settings;
use signorini::harness::reference::exact::run_study;
use signorini::harness::run::norms::Norm;
use signorini::harness::run::Problem1d;
use signorini::harness::study::golden::{compare, compare_ensemble, read_golden, render_drifts};
use signorini::harness::study::{Case, StudyConfig};
use signorini::studies::benchmark;
use signorini::studies::tables::{tables_sensitivity_under, GOLDEN_TABLES};

/// The Signorini–Dirichlet benchmark of `scenes/bar1d-dirichlet.json`, to `horizon`.
fn dirichlet(horizon: f64) -> Problem1d {
    benchmark::dirichlet(Path::new(env!("CARGO_MANIFEST_DIR")), horizon).unwrap()
}

#[test]
fn an_equivalent_rewrite_of_a_chaotic_step_passes_the_gate_and_fails_the_old_check() {
    let golden = read_golden(&Path::new(env!("CARGO_MANIFEST_DIR")).join(GOLDEN_TABLES)).unwrap();
    let case = Case {
        scheme: Scheme::CRANK_NICOLSON,
        mass: MassVariant::Standard,
    };
    let g = golden.cases.iter().find(|g| g.case == case.id()).unwrap();
    assert!(
        g.is_chaotic(),
        "crank-nicolson/standard is no longer chaotic"
    );

    let mut factored = Settings::default();
    factored.conventions.predictor = PredictorForm::Factored;
    let config = StudyConfig {
        settings: factored,
        ..StudyConfig::paper_default()
    };
    let norms: BTreeSet<Norm> = Norm::ALL.into_iter().collect();
    let rewritten = run_study(&dirichlet(config.horizon), &[case], &norms, &config).unwrap();
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let ensembles = tables_sensitivity_under(root, factored, &[case]).unwrap();

    // The rewrite changed the run: it is not the golden sample any more.
    let now = &rewritten.cases[0];
    let golden_errors = &g.norms["u_Linf_H"].errors;
    assert_ne!(
        &now.norm(Norm::DisplacementLinfH).unwrap().errors,
        golden_errors
    );

    // The new gate: the case's single run is not held, its ensemble statistics are.
    assert!(compare(&golden, &rewritten).is_empty());
    let mut this_case = golden.clone();
    this_case.cases.retain(|g| g.case == case.id());
    let drifts = compare_ensemble(&this_case, &ensembles);
    assert!(drifts.is_empty(), "{}", render_drifts(&drifts));

    // The old gate: the same golden values, 1 % per level, 0.02 per rate, on the one run.
    let mut old = golden.clone();
    for g in &mut old.cases {
        g.class = None;
    }
    let drifts = compare(&old, &rewritten);
    assert!(
        !drifts.is_empty(),
        "the old 1 % check passed the rewrite, so this test shows nothing"
    );
}
