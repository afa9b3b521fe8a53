//! Every run of GetFEM's demo in `tests/data/getfem/` solved again with the demo's conventions
//! ([`signorini::studies::getfem`]): the contact node's displacement, the demo's energy and the
//! contact stress agree step by step wherever the two codes solve the same discrete problem, up
//! to the first impact where that problem is round-off chaotic (and after its predictability
//! horizon within the spread of the harness's round-off ensemble), and up to the first impact for
//! the one the demo itself integrates inconsistently (Nitsche θ ≠ 0 with its mass type 1; with
//! θ = 1 the demo blows up and the harness's energy stays bounded). The expectation of each
//! configuration, with its reason, is [`Expectation::of`].

use std::path::Path;

use signorini::harness::getfem::{list_runs, read_run};
use signorini::studies::getfem::{
    ensemble_agreement, reproduce, Expectation, Judgement, GETFEM_ENSEMBLE, GETFEM_RUNS,
};

/// The displacement and the energy at every step.
const STATE_TOL: f64 = 1e-8;
/// The contact stress, relative to its largest magnitude (a residual divided by βΔt²: GetFEM's
/// two linear solvers differ by up to 3e-8 in it).
const STRESS_TOL: f64 = 1e-7;

#[test]
fn every_getfem_run_is_reproduced_where_the_discrete_problems_agree() {
    let runs = list_runs(Path::new(GETFEM_RUNS)).unwrap();
    assert_eq!(runs.len(), 52, "the 52 configurations of tests/data/getfem");
    let mut failures = Vec::new();
    for file in &runs {
        let run = read_run(&file.path).unwrap();
        let r = reproduce(Path::new("."), &file.path, &run).unwrap();
        let name = file.path.file_name().unwrap().to_string_lossy();
        let ok = r.status.is_completed()
            && match r.expectation {
                Expectation::RoundOff => {
                    r.displacement.max <= STATE_TOL
                        && r.energy.max <= STATE_TOL
                        && r.stress.max <= STRESS_TOL
                }
                Expectation::UndampedStressRoundOff => {
                    r.displacement.max <= STATE_TOL
                        && r.energy.max <= STATE_TOL
                        && r.stress_before_impact.max <= STRESS_TOL
                }
                Expectation::RoundOffChaotic => {
                    let ensemble =
                        ensemble_agreement(Path::new("."), &run, GETFEM_ENSEMBLE).unwrap();
                    r.parting.is_some_and(|n| n > r.first_impact)
                        && ensemble.judgement() != Judgement::Disagrees
                }
                // θ = −1: the same steps while the contact end is at rest; θ = 1: the demo
                // blows up, the harness's energy stays at E₀ = 1/8.
                Expectation::DemoMasslessNitsche if r.config.theta_n < 0.0 => {
                    r.parting.is_some_and(|n| n >= r.first_impact)
                }
                Expectation::DemoMasslessNitsche => {
                    r.demo_peak_energy > 1e6 && r.harness_peak_energy < 0.126
                }
            };
        if !ok {
            failures.push(format!("{name}: {r:?}"));
        }
    }
    assert!(failures.is_empty(), "not reproduced: {failures:?}");
}

/// Crank–Nicolson with the standard mass at NX = 20, round-off chaotic (issue 33, item 4):
/// GetFEM's run lies inside the range of the harness's ensemble with its per-step members in
/// every demo norm, and those members widen the range of the ensemble of initial-data members.
#[test]
fn the_chaotic_crank_nicolson_run_lies_inside_the_ensemble_with_per_step_members() {
    let path = Path::new(GETFEM_RUNS).join("getfem_v0_b0.25_g0.5_m0_nx20.json.gz");
    let run = read_run(&path).unwrap();
    let e = ensemble_agreement(Path::new("."), &run, GETFEM_ENSEMBLE).unwrap();
    assert_eq!(e.norms.len(), 7, "every demo norm is reported alike");
    let outside: Vec<_> = e.norms.iter().filter(|n| !n.inside()).collect();
    assert!(outside.is_empty(), "outside the ensemble: {outside:?}");
    assert_eq!(e.judgement(), Judgement::Agrees);
    assert!(
        e.norms
            .iter()
            .any(|n| n.spread.range() > n.initial_data.range()),
        "the per-step members widen no norm's range: {:?}",
        e.norms
    );
}
