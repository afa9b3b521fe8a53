//! The round-off ensembles of the 2D/3D studies (issue 15, item 6): a tiny box ensemble is
//! bit-reproducible, its members' errors differ from the unperturbed run's, the perturbation
//! touches the initial velocity only, and bad ensemble input is refused with a typed error
//! naming the field, before anything runs.

use std::path::{Path, PathBuf};

use crate::common::{signorini, success_stdout};
use signorini::engine::fem::MassVariant;
use signorini::engine::problem::{Perturbation, Problem, Settings};
use signorini::engine::schemes::{Integration, Scheme};
use signorini::harness::files::error as files;
use signorini::harness::reference::fine_mesh::cache::ReferenceCache;
use signorini::harness::reference::fine_mesh::ElasticStudyConfig;
use signorini::harness::run::elastic::{box_mesh, initial_dofs, BoxProblem};
use signorini::harness::run::norms::Norm;
use signorini::harness::run::{run, Observables, RunConfig};
use signorini::harness::study::error::Error;
use signorini::harness::study::scene::{Scene, SceneError};
use signorini::harness::study::sensitivity::{EnsembleConfig, SensitivityClass};
use signorini::harness::study::Case;
use signorini::studies::elastic_study::report::render;
use signorini::studies::elastic_study::{run_elastic_study, ElasticStudy};

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// The 2D scene's bar to shortly after its first impact (it falls 0.2 at speed 0.5: t = 0.4).
fn problem() -> BoxProblem {
    let scene = Scene::load(&root().join("scenes/bar2d.json")).unwrap();
    let Problem::Box(declared) = scene.problem() else {
        panic!("scenes/bar2d.json is not a box scene")
    };
    BoxProblem {
        horizon: 0.8,
        ..declared
    }
}

/// Crank–Nicolson with both masses on levels 2 and 4 against a reference on 8 elements, as an
/// ensemble of 3 members with noise 1e-6 (large enough that no member can round to the
/// unperturbed run).
fn tiny_config() -> ElasticStudyConfig {
    ElasticStudyConfig {
        levels: vec![2, 4],
        reference_level: 8,
        ratio: 2.0,
        cases: [MassVariant::Standard, MassVariant::Redistributed]
            .map(|mass| Case {
                scheme: Scheme::CRANK_NICOLSON,
                mass,
            })
            .to_vec(),
        sensitivity: Some(EnsembleConfig {
            members: 3,
            amplitude: 1e-6,
        }),
        settings: Settings::default(),
    }
}

fn cache(name: &str) -> PathBuf {
    std::env::temp_dir().join(format!(
        "signorini-box-sensitivity-{name}-{}",
        std::process::id()
    ))
}

fn study(
    problem: &BoxProblem,
    config: &ElasticStudyConfig,
    name: &str,
) -> Result<ElasticStudy, Error> {
    let dir = cache(name);
    let result = run_elastic_study(
        problem,
        config,
        &ReferenceCache::ReadWrite(dir.clone()),
        &mut |_| {},
    );
    let _ = std::fs::remove_dir_all(&dir);
    result.map(|(study, _)| study)
}

#[test]
fn a_tiny_box_ensemble_is_bit_reproducible_and_its_members_differ_from_the_unperturbed_run() {
    let (problem, config) = (problem(), tiny_config());
    let first = study(&problem, &config, "first").unwrap();
    let second = study(&problem, &config, "second").unwrap();
    let (a, b) = (
        first.sensitivity.as_ref().unwrap(),
        second.sensitivity.as_ref().unwrap(),
    );
    assert_eq!(
        serde_json::to_string(&a.cases).unwrap(),
        serde_json::to_string(&b.cases).unwrap()
    );
    assert_eq!(a.ensemble, config.sensitivity.unwrap());
    assert_eq!(a.config.levels, config.levels);
    for (case, study) in a.cases.iter().zip(&first.study.cases) {
        assert_eq!(case.case, study.case.id());
        assert_eq!(case.members, 3);
        for rates in &study.rates {
            let key = rates.norm.key();
            for (spread, &unperturbed) in case.errors[key].iter().zip(&rates.errors) {
                // Noise of relative size 1e-6 moves an error by far less than itself.
                assert!(
                    spread.range() <= 1e-2 * unperturbed.abs(),
                    "{} {key}: {spread:?} around {unperturbed}",
                    case.case
                );
            }
        }
        // The displacement errors move at every level (the contact force's need not: a coarse
        // run may not touch the obstacle at the compared times before the horizon).
        for norm in [Norm::DisplacementL2H, Norm::DisplacementL2V] {
            let unperturbed = &study.norm(norm).unwrap().errors;
            for (spread, &e) in case.errors[norm.key()].iter().zip(unperturbed) {
                assert!(
                    spread.min != e || spread.max != e,
                    "{} {norm}: every member's error equals the unperturbed {e}",
                    case.case
                );
            }
        }
        // The members part from the unperturbed run at the contact node (noise 1e-6 · 0.5 over
        // the run is far above the parting threshold 1e-8).
        assert!(
            case.predictability_steps.iter().all(Option::is_some),
            "{case:#?}"
        );
    }

    // The report has a sensitivity section, and marks a chaotic case's rates (here one made
    // chaotic by hand) with its ensemble median and range, and lists its rate ranges.
    let md = render(&first, "signorini study");
    assert!(md.contains("## Round-off sensitivity"));
    assert!(!md.contains('†'));
    let mut marked = first.clone();
    let chaotic = &mut marked.sensitivity.as_mut().unwrap().cases[0];
    chaotic.class = SensitivityClass::Chaotic;
    chaotic.chaotic = true;
    let md = render(&marked, "signorini study");
    let row = md
        .lines()
        .find(|l| l.starts_with(&format!("| {} | ", a.cases[0].case)))
        .unwrap();
    assert_eq!(row.matches('†').count(), 7, "{row}");
    assert!(md.contains("### Rate ranges of the chaotic cases"));
}

#[test]
fn the_perturbation_touches_the_initial_velocity_only() {
    let problem = problem();
    let unperturbed = Settings::default();
    let perturbed = unperturbed.with_round_off(Perturbation {
        amplitude: 1e-6,
        seed: 7,
    });
    let mesh = box_mesh(&problem, 4).unwrap();
    let (u, v) = initial_dofs(&problem, &mesh);
    let discretised = problem
        .discretise(4, MassVariant::Standard, &perturbed)
        .unwrap();
    let (u_p, v_p) = (&discretised.displacement, &discretised.velocity);
    assert_eq!(&u, u_p, "the displacement moved");
    let moved = v.iter().zip(v_p).filter(|(a, b)| a != b).count();
    assert_eq!(moved, v.len(), "every velocity dof carries noise");
    assert!(v.iter().zip(v_p).all(|(a, b)| (a - b).abs() <= 1e-6));

    // What the integrator starts from, both masses (the redistributed one sets its massless
    // dofs in static equilibrium from the same displacement).
    for mass in [MassVariant::Standard, MassVariant::Redistributed] {
        let start = |settings: Settings| {
            let config = RunConfig {
                nx: 4,
                ratio: 2.0,
                scheme: Scheme::CRANK_NICOLSON,
                mass,
                observables: Observables::default(),
                settings,
            };
            let mut state = None;
            let mut first = |integ: &Integration| -> Result<(), files::Error> {
                if state.is_none() {
                    state = Some((integ.displacement().to_vec(), integ.velocity().to_vec()));
                }
                Ok(())
            };
            run(&problem, &config, &mut [&mut first]).unwrap();
            state.unwrap()
        };
        let ((u0, v0), (u0_p, v0_p)) = (start(unperturbed), start(perturbed));
        assert_eq!(u0, u0_p, "{mass}: the initial displacement moved");
        assert_ne!(v0, v0_p, "{mass}: the initial velocity did not move");
    }
}

/// The name of the field a study refuses, or a failure naming what happened instead.
fn refused_field(problem: &BoxProblem, config: &ElasticStudyConfig) -> &'static str {
    let dir = cache("refused");
    match run_elastic_study(
        problem,
        config,
        &ReferenceCache::ReadWrite(dir.clone()),
        &mut |_| {},
    ) {
        Err(Error::Run(files::Error::Parameter(p))) => {
            assert!(
                !dir.exists(),
                "{}: refused after the reference was computed",
                p.name
            );
            p.name
        }
        other => panic!("expected a parameter error, got {:?}", other.err()),
    }
}

#[test]
fn bad_ensemble_input_is_a_typed_error_naming_the_field() {
    let (problem, config) = (problem(), tiny_config());
    let with = |members, amplitude| ElasticStudyConfig {
        sensitivity: Some(EnsembleConfig { members, amplitude }),
        ..config.clone()
    };
    assert_eq!(refused_field(&problem, &with(1, 1e-13)), "members");
    assert_eq!(refused_field(&problem, &with(3, 0.0)), "amplitude");
    assert_eq!(refused_field(&problem, &with(3, 1e-2)), "amplitude");
    let at_rest = BoxProblem {
        initial_velocity: 0.0,
        ..problem.clone()
    };
    assert_eq!(refused_field(&at_rest, &config), "initial_velocity");
    let no_obstacle = BoxProblem {
        obstacle_gap: None,
        ..problem.clone()
    };
    assert_eq!(refused_field(&no_obstacle, &config), "obstacle_gap");
    let perturbed = ElasticStudyConfig {
        settings: Settings::default().with_round_off(Perturbation {
            amplitude: 1e-6,
            seed: 1,
        }),
        ..config
    };
    assert_eq!(refused_field(&problem, &perturbed), "round_off");
}

#[test]
fn a_scene_declares_its_ensemble_and_bad_values_name_the_field() {
    let read = |name: &str| -> serde_json::Value {
        serde_json::from_str(&std::fs::read_to_string(root().join(name)).unwrap()).unwrap()
    };
    let invalid_field = |scene: &serde_json::Value| match Scene::parse(
        &scene.to_string(),
        Path::new("edited.json"),
    ) {
        Err(SceneError::Invalid { field, .. }) => field,
        other => panic!("expected an invalid field, got {other:?}"),
    };
    let mut box_scene = read("scenes/bar2d.json");
    let declared = Scene::parse(&box_scene.to_string(), Path::new("bar2d.json")).unwrap();
    assert!(ElasticStudyConfig::from_scene(&declared, None)
        .unwrap()
        .sensitivity
        .is_some());
    box_scene["discretisation"]["sensitivity"]["members"] = 1.into();
    assert_eq!(
        invalid_field(&box_scene),
        "discretisation.sensitivity.members"
    );
    let mut bar = read("scenes/bar1d-dirichlet.json");
    bar["discretisation"]["sensitivity"] = serde_json::json!({"members": 4, "amplitude": 1e-13});
    assert_eq!(invalid_field(&bar), "discretisation.sensitivity");
}

/// The 2D scene cut to Crank–Nicolson on levels 4 and 8 against a reference on 16 elements, to
/// t = 0.8, with an ensemble of 2 members: its path in `dir`.
fn tiny_box_scene(dir: &Path) -> PathBuf {
    let mut scene: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(root().join("scenes/bar2d.json")).unwrap())
            .unwrap();
    scene["horizon"] = 0.8.into();
    scene["observables"]["fields_at"] = serde_json::json!([0.4, 0.8]);
    let discretisation = &mut scene["discretisation"];
    discretisation["levels"] = serde_json::json!([4, 8]);
    discretisation["reference_level"] = 16.into();
    discretisation["schemes"] = serde_json::json!(["crank-nicolson"]);
    discretisation["sensitivity"] = serde_json::json!({"members": 2, "amplitude": 1e-13});
    let path = dir.join("tiny-box.json");
    std::fs::write(&path, scene.to_string()).unwrap();
    path
}

/// `json` without its wall-clock time.
fn without_wall_seconds(mut json: serde_json::Value) -> serde_json::Value {
    json.as_object_mut().unwrap().remove("wall_seconds");
    json
}

#[test]
fn the_sensitivity_command_on_a_box_scene_is_the_ensemble_of_its_study() {
    let dir = cache("command");
    std::fs::create_dir_all(&dir).unwrap();
    let text = |p: PathBuf| p.to_string_lossy().into_owned();
    let scene = text(tiny_box_scene(&dir));
    let (refs, study_out, out) = (
        text(dir.join("refs")),
        text(dir.join("study")),
        text(dir.join("sensitivity")),
    );
    let run = |args: &[&str]| success_stdout(&signorini(args));
    run(&["study", &scene, "--cache", &refs, "--out", &study_out]);
    let sensitivity = |extra: &[&str]| {
        let mut args = vec!["sensitivity", &scene, "--members", "2", "--cache", &refs];
        args.extend(extra);
        run(&args)
    };
    let said = sensitivity(&["--out", &out]);
    assert!(said.contains("crank-nicolson/standard"), "{said}");
    let read = |p: PathBuf| -> serde_json::Value {
        serde_json::from_str(&std::fs::read_to_string(p).unwrap()).unwrap()
    };
    let of_study = read(Path::new(&study_out).join("elastic-2d.json"))["sensitivity"].clone();
    let of_command = read(Path::new(&out).join("sensitivity.json"));
    assert_eq!(of_command["cases"].as_array().unwrap().len(), 2);
    assert_eq!(
        without_wall_seconds(of_command),
        without_wall_seconds(of_study)
    );
    let md = std::fs::read_to_string(Path::new(&out).join("sensitivity.md")).unwrap();
    assert!(md.contains("parting step at NX = 8"), "{md}");

    // Its two shards, merged, write the same classes and numbers.
    let shards: Vec<String> = (1..=2)
        .map(|k| {
            let (spec, shard_out) = (format!("{k}/2"), text(dir.join(format!("s{k}"))));
            sensitivity(&["--shard", &spec, "--out", &shard_out]);
            text(Path::new(&shard_out).join(format!("shard-sensitivity-{k}-of-2.json")))
        })
        .collect();
    let merged = text(dir.join("merged"));
    run(&["merge", "--out", &merged, &shards[0], &shards[1]]);
    assert_eq!(
        without_wall_seconds(read(Path::new(&merged).join("sensitivity.json"))),
        without_wall_seconds(read(Path::new(&out).join("sensitivity.json")))
    );
    let _ = std::fs::remove_dir_all(&dir);
}
