//! Every run of GetFEM's demo in `tests/data/getfem/` solved again with the demo's conventions
//! ([`signorini::studies::getfem`]) and checked against its class ([`ClassCheck`], with the
//! thresholds of `src/studies/getfem/class_check.rs`): the contact node's displacement, the
//! demo's energy and the contact stress agree step by step wherever the two codes solve the same
//! discrete problem, up to the first impact where that problem is round-off chaotic, and up to
//! the first impact for the one the demo itself integrates inconsistently (Nitsche θ ≠ 0 with
//! its mass type 1; with θ = 1 the demo blows up and the harness's energy stays bounded). The
//! expectation of each configuration, with its reason, is [`Expectation::of`].

use std::path::Path;

use signorini::harness::getfem::{list_runs, read_run};
use signorini::harness::study::sensitivity::EnsembleConfig;
use signorini::studies::getfem::{
    ensemble_agreement, reproduce, ClassCheck, Expectation, Judgement, Timing, GETFEM_ENSEMBLE,
    GETFEM_RUNS,
};

#[test]
fn every_getfem_run_is_within_its_class() {
    let runs = list_runs(Path::new(GETFEM_RUNS)).unwrap();
    assert_eq!(runs.len(), 52, "the 52 configurations of tests/data/getfem");
    let mut failures = Vec::new();
    for file in &runs {
        let run = read_run(&file.path).unwrap();
        let r = reproduce(Path::new("."), &file.path, &run).unwrap();
        let ensemble = (r.expectation == Expectation::RoundOffChaotic)
            .then(|| ensemble_agreement(Path::new("."), &run, GETFEM_ENSEMBLE).unwrap());
        let check = ClassCheck::of(&r, ensemble.as_ref());
        if !check.within() {
            let name = file.path.file_name().unwrap().to_string_lossy();
            failures.push(format!("{name}: {}", check.text()));
        }
    }
    assert!(failures.is_empty(), "outside their class: {failures:?}");
}

/// The ensemble GetFEM's chaotic runs are judged against is `signorini sensitivity`'s, fixed
/// before the comparison (issue 53, item 5).
#[test]
fn the_getfem_ensemble_is_the_sensitivity_studys() {
    assert_eq!(GETFEM_ENSEMBLE, EnsembleConfig::default());
}

/// Crank–Nicolson with the standard mass at NX = 20, round-off chaotic (issue 33, item 4):
/// GetFEM's run lies inside the range of the harness's ensemble with its per-step members in
/// every demo norm, and those members are in the ensemble's statistics: its range holds the
/// initial-data members' and its medians move with them (whether they also widen the range is
/// the sample's, not the code's); it parts before the ensemble's first member, so the ensemble
/// does not cover its timing and the run is undecided.
#[test]
fn the_chaotic_crank_nicolson_run_lies_inside_the_ensemble_with_per_step_members() {
    let path = Path::new(GETFEM_RUNS).join("getfem_v0_b0.25_g0.5_m0_nx20.json.gz");
    let run = read_run(&path).unwrap();
    let e = ensemble_agreement(Path::new("."), &run, GETFEM_ENSEMBLE).unwrap();
    assert_eq!(e.norms.len(), 7, "every demo norm is reported alike");
    let outside: Vec<_> = e.norms.iter().filter(|n| !n.inside()).collect();
    assert!(outside.is_empty(), "outside the ensemble: {outside:?}");
    assert!(e.parts_after_impact(), "{e:?}");
    assert!(matches!(e.in_time(), Timing::Early(_)), "{e:?}");
    assert_eq!(e.judgement(), Judgement::Undecided);
    for n in &e.norms {
        let (all, initial) = (&n.spread, &n.initial_data);
        assert!(
            all.min <= initial.min && initial.max <= all.max,
            "{}: the whole range does not hold the initial-data members': {n:?}",
            n.name
        );
    }
    assert!(
        e.norms
            .iter()
            .any(|n| n.spread.median != n.initial_data.median),
        "the per-step members move no norm's median: {:?}",
        e.norms
    );
}
