//! Scene files: every committed scene is valid, the benchmark scenes are the problems the
//! reports use, and only the effects a scene declares are simulated (counted, not timed).

use std::path::Path;

use signorini::engine::contact::ContactTreatment;
use signorini::engine::fem::{EndCondition, MassVariant};
use signorini::engine::problem::{InitialData, Problem};
use signorini::engine::schemes::Scheme;
use signorini::harness::run::norms::Norm;
use signorini::harness::run::{run, Problem1d, RunConfig};
use signorini::harness::study::scene::{scene_files, Scene, SceneError};
use signorini::harness::study::StudyConfig;

fn scene(name: &str) -> Scene {
    Scene::load(
        &Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("scenes")
            .join(name),
    )
    .unwrap()
}

/// The problem of a bar1d scene.
fn bar(scene: &Scene) -> Problem1d {
    match scene.problem() {
        Problem::Bar(p) => p,
        Problem::Box(_) => panic!("{} is a box scene", scene.name),
    }
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
    // The studies read the benchmark from this file (`studies::benchmark::dirichlet`): it is
    // the 1D paper's §5 problem with the tables' levels, ratio, horizon and norms.
    let s = scene("bar1d-dirichlet.json");
    let p = bar(&s);
    assert_eq!(
        (p.length, p.density, p.wave_speed),
        (1.0, 1.0, 1.0),
        "L, ρ, c"
    );
    assert_eq!(p.far_end, EndCondition::Clamped);
    assert_eq!(p.obstacle_gap, Some(0.0));
    assert_eq!(p.body_force, None);
    assert_eq!(p.initial, InitialData::default());
    assert_eq!(p.horizon, 3.0);
    assert_eq!(p.exact.name(), "signorini-dirichlet");
    assert_eq!(p.contact, ContactTreatment::Multiplier);
    assert_eq!(s.study_config(), StudyConfig::paper_default());
    assert_eq!(s.observables.norms, Norm::ALL.into_iter().collect());

    // What the studies run: the same problem, to the horizon they ask for.
    let studied =
        signorini::studies::benchmark::dirichlet(Path::new(env!("CARGO_MANIFEST_DIR")), 9.0)
            .unwrap();
    assert_eq!(studied.horizon, 9.0);
    assert_eq!(studied.initial, p.initial);
    assert_eq!(studied.exact.name(), p.exact.name());
}

#[test]
fn a_scene_without_obstacle_never_solves_contact() {
    let s = scene("bar1d-free.json");
    assert!(bar(&s).obstacle_gap.is_none());
    assert!(!s.observables().contact_history);
    let r = run(
        &bar(&s),
        &RunConfig {
            nx: 20,
            ratio: 1.0,
            scheme: Scheme::CRANK_NICOLSON,
            mass: MassVariant::Standard,
            observables: s.observables(),
            settings: Default::default(),
        },
        &mut [],
    )
    .unwrap();
    assert_eq!(r.contact_solves, 0);
    assert!(r.observed.multiplier_variation.is_none());
    assert!(r.observed.contact_history.is_none());

    // The same bar with an obstacle does solve contact problems: the counter counts.
    let d = scene("bar1d-dirichlet.json");
    let r = run(
        &bar(&d),
        &RunConfig {
            nx: 20,
            ratio: 10.0,
            scheme: Scheme::CRANK_NICOLSON,
            mass: MassVariant::Standard,
            observables: d.observables(),
            settings: Default::default(),
        },
        &mut [],
    )
    .unwrap();
    assert!(r.contact_solves > 0);
}

#[test]
fn a_scene_without_body_force_assembles_no_load() {
    let s = scene("bar1d-dirichlet.json");
    let (_, model) = bar(&s).model(10, MassVariant::Standard).unwrap();
    assert!(model.load().is_none());
    assert!(model.contact().is_some());

    // Declaring a body force is what makes the model carry a load vector.
    let loaded = Problem1d {
        body_force: Some(-0.1),
        ..bar(&s)
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
        &bar(&s),
        &RunConfig {
            nx: 20,
            ratio: 10.0,
            scheme: Scheme::CRANK_NICOLSON,
            mass: MassVariant::Redistributed,
            observables,
            settings: Default::default(),
        },
        &mut [],
    )
    .unwrap();
    assert_eq!(r.observed.space_norm_evaluations, 0);
    assert_eq!(
        r.observed.errors.keys().copied().collect::<Vec<_>>(),
        vec![Norm::EnergyLinf]
    );
}

#[test]
fn a_box_scene_is_a_box_problem_and_its_scheme_names_are_checked_at_load() {
    let s = scene("bar2d.json");
    let Problem::Box(p) = s.problem() else {
        panic!("bar2d.json is a box scene")
    };
    assert_eq!(p.lengths, vec![0.1, 1.0]);
    assert_eq!((p.initial_displacement, p.initial_velocity), (0.0, -0.5));
    assert_eq!(p.obstacle_gap, Some(0.2));
    // The note's two schemes, then the rivals (issue 35).
    let mut schemes = vec![Scheme::CRANK_NICOLSON, Scheme::BACKWARD_EULER];
    schemes.extend(Scheme::rival_schemes());
    assert_eq!(s.default_schemes(), schemes);
    assert!(s.observables.norms.is_empty());

    // Scheme names are parsed when the file is read, in a box scene as in a bar1d one.
    let text =
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/bar2d.json"))
            .unwrap();
    let edited = text.replace("\"backward-euler\"", "\"backward-eulr\"");
    assert_ne!(edited, text);
    match Scene::parse(&edited, Path::new("misspelt.json")) {
        Err(e @ SceneError::Invalid { .. }) => {
            let message = e.to_string();
            for needle in [
                "misspelt.json",
                "discretisation.schemes",
                "backward-eulr",
                "crank-nicolson",
            ] {
                assert!(message.contains(needle), "{needle:?} not in {message}");
            }
        }
        other => panic!("expected an invalid scheme name, got {other:?}"),
    }
}
