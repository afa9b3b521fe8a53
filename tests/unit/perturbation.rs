//! `initial.perturbation` applies wherever initial data are built: a perturbed scene's errors
//! differ from the unperturbed ones, the same seed reproduces them bit for bit, another seed
//! does not, the contact dof is left alone, and the stability suite's `rough-data` case is rough.

use crate::benchmarks;
use std::path::Path;

use signorini::engine::fem::MassVariant;
use signorini::engine::problem::{InitialData, Perturbation, Problem};
use signorini::engine::schemes::Scheme;
use signorini::harness::run::{run, BarRun, Observables, Problem1d, RunConfig};
use signorini::harness::study::scene::Scene;
use signorini::studies::stability::hard_cases;

/// The problem of a bar1d scene.
fn bar(scene: &Scene) -> Problem1d {
    match scene.problem() {
        Problem::Bar(p) => p,
        Problem::Box(_) => panic!("{} is a box scene", scene.name),
    }
}

fn dirichlet_with(perturbation: Option<Perturbation>) -> Problem1d {
    Problem1d {
        initial: InitialData {
            perturbation,
            ..InitialData::default()
        },
        ..benchmarks::dirichlet(3.0)
    }
}

fn run_at_40(problem: &Problem1d) -> BarRun {
    run(
        problem,
        &RunConfig {
            nx: 40,
            ratio: 10.0,
            scheme: Scheme::CRANK_NICOLSON,
            mass: MassVariant::Redistributed,
            observables: Observables::all_norms(),
            settings: Default::default(),
        },
        &mut [],
    )
    .unwrap()
}

#[test]
fn a_perturbation_changes_the_errors_and_its_seed_reproduces_them() {
    let plain = run_at_40(&dirichlet_with(None));
    let seeded = |seed| {
        run_at_40(&dirichlet_with(Some(Perturbation {
            amplitude: 1e-3,
            seed,
        })))
    };
    let first = seeded(7);
    for (norm, e) in &plain.observed.errors {
        assert_ne!(
            first.observed.errors[norm], *e,
            "{norm}: the perturbation was not applied"
        );
    }
    let again = seeded(7);
    for (norm, e) in &first.observed.errors {
        assert_eq!(
            again.observed.errors[norm].to_bits(),
            e.to_bits(),
            "{norm}: the same seed must give the same bits"
        );
    }
    let other = seeded(8);
    assert!(first
        .observed
        .errors
        .iter()
        .any(|(n, e)| other.observed.errors[n] != *e));
}

#[test]
fn the_perturbation_moves_every_dof_but_the_contact_dof_within_its_amplitude() {
    let problem = dirichlet_with(Some(Perturbation {
        amplitude: 1e-2,
        seed: 3,
    }));
    let (bar, model) = problem.model(20, MassVariant::Standard).unwrap();
    let (u, v) = problem.initial_dofs(&bar, &model);
    let (u_plain, v_plain) = dirichlet_with(None).initial_dofs(&bar, &model);
    assert_eq!(v, v_plain, "the velocity is not perturbed");
    let contact = model.contact().unwrap().dofs.clone();
    for (i, (a, b)) in u.iter().zip(&u_plain).enumerate() {
        let shift = (a - b).abs();
        if contact.contains(&i) {
            assert_eq!(
                shift, 0.0,
                "contact dof {i} moved: the data must stay admissible"
            );
        } else {
            assert!(shift > 0.0 && shift <= 1e-2, "dof {i} moved by {shift}");
        }
    }
}

#[test]
fn a_scene_perturbation_reaches_the_run() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/bar1d-dirichlet.json");
    let text = std::fs::read_to_string(&path).unwrap();
    let perturbed = text.replacen(
        "\"velocity\": \"reference\" }",
        "\"velocity\": \"reference\", \"perturbation\": {\"amplitude\": 1e-3, \"seed\": 7} }",
        1,
    );
    assert_ne!(perturbed, text, "the scene's initial data changed shape");
    let scene = Scene::parse(&perturbed, &path).unwrap();
    let from_scene = run_at_40(&bar(&scene));
    let programmatic = run_at_40(&dirichlet_with(Some(Perturbation {
        amplitude: 1e-3,
        seed: 7,
    })));
    assert_eq!(from_scene.observed.errors, programmatic.observed.errors);
    let plain = run_at_40(&bar(&Scene::load(&path).unwrap()));
    assert_ne!(from_scene.observed.errors, plain.observed.errors);
}

#[test]
fn the_rough_data_hard_case_is_rough() {
    let cases = hard_cases(Path::new(env!("CARGO_MANIFEST_DIR")), false).unwrap();
    let rough = cases.iter().find(|c| c.name == "rough-data").unwrap();
    let plain = benchmarks::dirichlet(rough.problem.horizon);
    let (bar, model) = rough
        .problem
        .model(rough.nx, MassVariant::Standard)
        .unwrap();
    let (u, _) = rough.problem.initial_dofs(&bar, &model);
    let (u_plain, _) = plain.initial_dofs(&bar, &model);
    let amplitude = rough.problem.initial.perturbation.unwrap().amplitude;
    let largest = u
        .iter()
        .zip(&u_plain)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    // Uniform in ±a at 80 nodes: the largest shift is above a/2 unless every draw is small.
    assert!(
        largest > 0.5 * amplitude && largest <= amplitude,
        "{largest}"
    );
    // Neighbouring nodes move independently: the data's strain is rough at the mesh scale.
    let rough_strain = u
        .windows(2)
        .zip(u_plain.windows(2))
        .map(|(w, p)| ((w[1] - w[0]) - (p[1] - p[0])).abs())
        .fold(0.0, f64::max);
    assert!(rough_strain > 0.5 * amplitude, "{rough_strain}");
}
