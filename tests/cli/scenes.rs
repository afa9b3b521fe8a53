//! Scene files: every committed scene is valid, the benchmark scenes are the problems the
//! reports use, and only the effects a scene declares are simulated (counted, not timed).

use std::path::Path;

use signorini::fem::MassVariant;
use signorini::norms::Norm;
use signorini::run::{run, Problem1d, RunConfig};
use signorini::scene::{scene_files, Scene};
use signorini::schemes::Scheme;
use signorini::study::StudyConfig;

fn scene(name: &str) -> Scene {
    Scene::load(
        &Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("scenes")
            .join(name),
    )
    .unwrap()
}

#[test]
fn every_committed_scene_is_valid() {
    let files = scene_files(&Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes"));
    assert!(files.len() >= 2);
    for f in files {
        Scene::load(&f).unwrap_or_else(|e| panic!("{e}"));
    }
}

#[test]
fn the_dirichlet_scene_is_the_tables_problem() {
    let s = scene("bar1d-dirichlet.json");
    let from_scene = s.problem();
    let programmatic = Problem1d::signorini_dirichlet(3.0);
    assert_eq!(from_scene.length, programmatic.length);
    assert_eq!(from_scene.density, programmatic.density);
    assert_eq!(from_scene.wave_speed, programmatic.wave_speed);
    assert_eq!(from_scene.far_end, programmatic.far_end);
    assert_eq!(from_scene.obstacle_gap, programmatic.obstacle_gap);
    assert_eq!(from_scene.body_force, programmatic.body_force);
    assert_eq!(from_scene.initial, programmatic.initial);
    assert_eq!(from_scene.horizon, programmatic.horizon);
    assert_eq!(from_scene.exact.name(), programmatic.exact.name());
    assert_eq!(s.study_config(), StudyConfig::paper_default());
    assert_eq!(s.norms(), Norm::ALL.into_iter().collect());
}

#[test]
fn a_scene_without_obstacle_never_solves_contact() {
    let s = scene("bar1d-free.json");
    assert!(s.problem().obstacle_gap.is_none());
    assert!(!s.observables().contact_history);
    let r = run(
        &s.problem(),
        &RunConfig {
            nx: 20,
            ratio: 1.0,
            scheme: Scheme::CRANK_NICOLSON,
            mass: MassVariant::Standard,
            observables: s.observables(),
        },
    )
    .unwrap();
    assert_eq!(r.contact_solves, 0);
    assert!(r.multiplier_variation.is_none());
    assert!(r.contact_history.is_none());

    // The same bar with an obstacle does solve contact problems: the counter counts.
    let d = scene("bar1d-dirichlet.json");
    let r = run(
        &d.problem(),
        &RunConfig {
            nx: 20,
            ratio: 10.0,
            scheme: Scheme::CRANK_NICOLSON,
            mass: MassVariant::Standard,
            observables: d.observables(),
        },
    )
    .unwrap();
    assert!(r.contact_solves > 0);
}

#[test]
fn a_scene_without_body_force_assembles_no_load() {
    let s = scene("bar1d-dirichlet.json");
    let (_, model) = s.problem().model(10, MassVariant::Standard).unwrap();
    assert!(model.load().is_none());
    assert!(model.contact().is_some());

    // Declaring a body force is what makes the model carry a load vector.
    let loaded = Problem1d {
        body_force: Some(-0.1),
        ..s.problem()
    };
    let (_, model) = loaded.model(10, MassVariant::Standard).unwrap();
    let total: f64 = model.load().unwrap().iter().sum();
    // Clamped at x = 1: the eliminated node drops half of the last element's load.
    assert!((total - (-0.1 * (1.0 - 0.05))).abs() < 1e-14, "{total}");
}

#[test]
fn a_scene_asking_only_for_energy_evaluates_no_space_norm() {
    let text = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/bar1d-dirichlet.json"),
    )
    .unwrap();
    let start = text.find("\"norms\"").unwrap();
    let end = start + text[start..].find(']').unwrap() + 1;
    let edited = format!(
        "{}\"norms\": [\"energy_Linf\"]{}",
        &text[..start],
        &text[end..]
    );
    let s = Scene::parse(&edited, Path::new("energy-only.json")).unwrap();
    let mut observables = s.observables();
    observables.contact_history = false;
    observables.energy_history = false;
    let r = run(
        &s.problem(),
        &RunConfig {
            nx: 20,
            ratio: 10.0,
            scheme: Scheme::CRANK_NICOLSON,
            mass: MassVariant::Redistributed,
            observables,
        },
    )
    .unwrap();
    assert_eq!(r.space_norm_evaluations, 0);
    assert_eq!(
        r.errors.keys().copied().collect::<Vec<_>>(),
        vec![Norm::EnergyLinf]
    );
}
