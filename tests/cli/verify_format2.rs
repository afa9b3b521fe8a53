//! `signorini verify` on the bar's files in version 2 of the external format
//! (`signorini-external/2`): the same run written in versions 1 and 2 verifies the same; λ
//! null at a sample is left out of its norm with a note; fields at the final sample only give
//! "not computed" u norms and the error at that sample; the energy the harness computes from
//! the fields is its own energy norm; a reported energy without its definition and an unknown
//! mass are refused naming the allowed values. Every expected number comes from the harness.

use crate::common;
use crate::external_runs::{
    export_run, export_run_with, write_csv, write_json, Export, SCENE, SCENE_NAME,
};

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

use common::{expect_error, signorini, success_stdout};
use serde_json::{json, Map, Value};
use signorini::engine::fem::MassVariant;
use signorini::engine::problem::{Problem1d, Settings};
use signorini::engine::schemes::conventions::{Conventions, Start};
use signorini::engine::schemes::Scheme;
use signorini::harness::reference::exact::run_study;
use signorini::harness::run::norms::{Norm, SpaceErrorIntegrator, TimeSeriesNorm};
use signorini::harness::study::{Case, StudyConfig};
use signorini::studies::benchmark;

/// The levels of every series here, at the Dirichlet scene's Δx/Δt = 10.
const LEVELS: [usize; 2] = [10, 20];

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("signorini-v2-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn problem() -> Problem1d {
    benchmark::dirichlet(Path::new(env!("CARGO_MANIFEST_DIR")), 3.0).unwrap()
}

/// The harness's run of `case` at each of [`LEVELS`].
fn exports(case: Case) -> Vec<Export> {
    let problem = problem();
    LEVELS
        .iter()
        .map(|&nx| export_run(&problem, nx, 10.0, case.scheme, case.mass))
        .collect()
}

/// `e` as a version 2 JSON file at `path`: the fields, λ and its times at every sample, the
/// top-level fields `head` added, each sample then edited by `edit(k, sample)`.
fn write_v2(
    path: &Path,
    e: &Export,
    label: &str,
    head: Value,
    edit: impl Fn(usize, &mut Map<String, Value>),
) {
    let samples: Vec<Value> = (0..e.time.len())
        .map(|k| {
            let mut sample = Map::new();
            sample.insert("time".into(), json!(e.time[k]));
            sample.insert("displacement".into(), json!(e.displacement[k]));
            sample.insert("velocity".into(), json!(e.velocity[k]));
            sample.insert("lambda".into(), json!(e.lambda[k].1));
            sample.insert("lambda_time".into(), json!(e.lambda[k].0));
            edit(k, &mut sample);
            Value::Object(sample)
        })
        .collect();
    let mut file = json!({
        "format": "signorini-external/2",
        "scene": SCENE_NAME,
        "code": {"name": "signorini", "version": "test export"},
        "label": label,
        "mesh": {"nodes": e.nodes},
        "samples": samples,
    });
    if let (Some(file), Value::Object(head)) = (file.as_object_mut(), head) {
        file.extend(head);
    }
    std::fs::write(path, serde_json::to_string(&file).unwrap()).unwrap();
}

/// `signorini verify` of `files` with `--out DIR`: its stdout and `verify.json`.
fn verify(dir: &Path, files: &[PathBuf]) -> (String, Value) {
    let out = dir.join("out");
    let mut args = vec!["verify".to_string(), SCENE.to_string()];
    args.extend(files.iter().map(|f| f.to_string_lossy().into_owned()));
    args.extend(["--out".to_string(), out.to_string_lossy().into_owned()]);
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    let stdout = success_stdout(&signorini(&args));
    let json = serde_json::from_str(&std::fs::read_to_string(out.join("verify.json")).unwrap());
    (stdout, json.unwrap())
}

/// The series labelled `label` of `verify.json`.
fn series<'v>(json: &'v Value, label: &str) -> &'v Value {
    let all = json["series"].as_array().unwrap();
    all.iter().find(|s| s["label"] == label).unwrap()
}

/// The errors per level of `norm` in `series`, as bits; `None` when not computed.
fn errors(series: &Value, norm: Norm) -> Option<Vec<u64>> {
    let rates = series["rates"].as_array().unwrap();
    let rate = rates.iter().find(|r| r["norm"] == norm.key())?;
    let errors = rate["errors"].as_array().unwrap();
    Some(
        errors
            .iter()
            .map(|e| e.as_f64().unwrap().to_bits())
            .collect(),
    )
}

fn bits(values: &[f64]) -> Vec<u64> {
    values.iter().map(|x| x.to_bits()).collect()
}

/// Crank–Nicolson with the standard mass written in version 1 (JSON), and in version 2 (JSON
/// and CSV) with its mass and its energy declared `total-at-sample`: the seven norms agree to
/// the bit (version 2's energy norms are the harness's energy of the fields, version 1's the
/// file's, and the run's energy is that same `E_h(Uⁿ, Vⁿ)`), and the reported energy's
/// distances shown beside are those norms again.
#[test]
fn a_run_in_version_1_and_in_version_2_verifies_the_same() {
    let dir = scratch("same");
    let case = Case {
        scheme: Scheme::CRANK_NICOLSON,
        mass: MassVariant::Standard,
    };
    let mut files = Vec::new();
    for (e, nx) in exports(case).iter().zip(LEVELS) {
        let v1 = dir.join(format!("v1-nx{nx}.json"));
        write_json(&v1, e, "v1");
        let v2 = dir.join(format!("v2-nx{nx}.json"));
        let head = json!({"mass": "standard", "energy_definition": "total-at-sample"});
        write_v2(&v2, e, "v2 json", head, |k, s| {
            s.insert("energy".into(), json!(e.energy[k].1));
        });
        let csv = dir.join(format!("v2-nx{nx}.csv"));
        write_csv(&csv, e, "v2 csv");
        let text = std::fs::read_to_string(&csv).unwrap().replace(
            "# format: signorini-external/1\n",
            "# format: signorini-external/2\n# mass: standard\n\
             # energy_definition: total-at-sample\n",
        );
        std::fs::write(&csv, text).unwrap();
        files.extend([v1, v2, csv]);
    }
    let (_, json) = verify(&dir, &files);
    let v1 = series(&json, "v1");
    assert!(
        v1["reported_energy"].is_null(),
        "version 1 reports no energy beside"
    );
    for label in ["v2 json", "v2 csv"] {
        let v2 = series(&json, label);
        for norm in Norm::ALL {
            assert!(errors(v1, norm).is_some(), "{norm}");
            assert_eq!(errors(v2, norm), errors(v1, norm), "{label} {norm}");
        }
        assert_eq!(v2["not_computed"], json!([]), "{label}");
        let reported = v2["reported_energy"].as_array().unwrap();
        assert_eq!(reported.len(), LEVELS.len(), "{label}");
        for (norm, key) in [(Norm::EnergyLinf, "linf"), (Norm::EnergyL2, "l2")] {
            let beside: Vec<f64> = reported.iter().map(|r| r[key].as_f64().unwrap()).collect();
            assert_eq!(Some(bits(&beside)), errors(v1, norm), "{label} {key}");
        }
        assert!(reported
            .iter()
            .all(|r| r["definition"] == "total-at-sample"));
    }
}

/// λ null at t = 0 (a code that did not compute λ⁰): its norm is the harness's `L²(0, T)` over
/// the other samples, computed here from the run's λ with the exact solution, and the outputs
/// say how many samples were left out. The run starts as the 1D paper and GetFEM do, with the
/// redistributed mass's implicit `λ⁰ = −½` where the exact `λ(0)` is 0, so that leaving the
/// sample out changes the norm.
#[test]
fn lambda_null_at_the_start_is_left_out_of_its_norm_with_a_note() {
    let dir = scratch("lambda");
    let problem = problem();
    let settings = Settings {
        conventions: Conventions {
            start: Start::ImplicitMultiplier,
            ..Conventions::HARNESS
        },
        ..Settings::default()
    };
    let case = (Scheme::BACKWARD_EULER, MassVariant::Redistributed);
    let runs: Vec<Export> = LEVELS
        .iter()
        .map(|&nx| export_run_with(&problem, nx, 10.0, case, &settings))
        .collect();
    let exact = &problem.exact;
    let mut files = Vec::new();
    let mut expected = Vec::new();
    let mut with_start = Vec::new();
    for (e, nx) in runs.iter().zip(LEVELS) {
        let path = dir.join(format!("nx{nx}.json"));
        write_v2(&path, e, "λ⁰ null", json!({}), |k, s| {
            if k == 0 {
                s.insert("lambda".into(), Value::Null);
            }
        });
        files.push(path);
        let [mut over_rest, mut over_all] = [TimeSeriesNorm::default(), TimeSeriesNorm::default()];
        for (k, &(t, lambda)) in e.lambda.iter().enumerate() {
            let error = lambda - exact.contact_multiplier(t);
            over_all.push(t, error);
            if k > 0 {
                over_rest.push(t, error);
            }
        }
        expected.push(over_rest.l2());
        with_start.push(over_all.l2());
    }
    assert_ne!(expected, with_start, "the t = 0 sample weighs in the norm");
    let (stdout, json) = verify(&dir, &files);
    let s = series(&json, "λ⁰ null");
    assert_eq!(errors(s, Norm::MultiplierL2), Some(bits(&expected)));
    let notes = s["notes"].as_array().unwrap();
    assert_eq!(notes.len(), LEVELS.len());
    for (note, e) in notes.iter().zip(&runs) {
        let n = e.time.len();
        let note = note.as_str().unwrap();
        assert!(
            note.contains(&format!("at 1 of its {n} samples (t = 0)"))
                && note.contains(&format!("over the other {} samples", n - 1)),
            "{note}"
        );
    }
    assert!(stdout.contains("### Notes") && stdout.contains("λ is null (not computed)"));
}

/// Fields at the final sample only: the u norms (and the energy, which needs the fields) are
/// not computed, naming how many samples lack them, and the error at T is the one the
/// harness's space norm gives the full run's final state.
#[test]
fn fields_at_the_final_sample_only_give_the_error_there() {
    let dir = scratch("final");
    let case = Case {
        scheme: Scheme::BACKWARD_EULER,
        mass: MassVariant::Redistributed,
    };
    let problem = problem();
    let mut files = Vec::new();
    let mut expected = Vec::new();
    for (e, nx) in exports(case).iter().zip(LEVELS) {
        let path = dir.join(format!("nx{nx}.json"));
        let last = e.time.len() - 1;
        write_v2(
            &path,
            e,
            "final fields",
            json!({"mass": "redistributed"}),
            |k, s| {
                if k < last {
                    s.remove("displacement");
                    s.insert("velocity".into(), Value::Null);
                }
            },
        );
        files.push(path);
        let bar = problem.bar(nx).unwrap();
        let u = &e.displacement[last][..bar.n_dofs()];
        let error =
            SpaceErrorIntegrator::new().errors(&bar, u, problem.exact.as_ref(), e.time[last]);
        expected.push((e.time[last], error.l2, error.h1, last));
    }
    let (stdout, json) = verify(&dir, &files);
    let s = series(&json, "final fields");
    let not_computed: BTreeSet<&str> = s["not_computed"]
        .as_array()
        .unwrap()
        .iter()
        .map(|n| n["norm"].as_str().unwrap())
        .collect();
    let lacking: BTreeSet<&str> = Norm::ALL
        .into_iter()
        .filter(|&n| n != Norm::MultiplierL2)
        .map(Norm::key)
        .collect();
    assert_eq!(not_computed, lacking);
    let reason = s["not_computed"][0]["reason"].as_str().unwrap();
    let (_, _, _, last) = expected[0];
    assert!(
        reason.contains(&format!("{last} of {} samples have none", last + 1)),
        "{reason}"
    );
    assert!(errors(s, Norm::MultiplierL2).is_some());
    for (run, (t, h, v, _)) in s["runs"].as_array().unwrap().iter().zip(&expected) {
        let at = run["displacement_at_samples"].as_array().unwrap();
        assert_eq!(at.len(), 1);
        assert_eq!(at[0]["time"].as_f64(), Some(*t));
        assert_eq!(at[0]["h"].as_f64().map(f64::to_bits), Some(h.to_bits()));
        assert_eq!(at[0]["v"].as_f64().map(f64::to_bits), Some(v.to_bits()));
    }
    assert!(stdout.contains("## Displacement errors at the samples with fields"));
    assert!(stdout.contains("samples have none): the errors at the samples that have them"));
}

/// The energy the harness computes from an exported run's fields, with the declared mass, is
/// the harness's own energy norm to the bit, not only to round-off: a one-step scheme's energy
/// is `E_h(Uⁿ, Vⁿ)` of its model at `t_n`, the file carries `Uⁿ`, `Vⁿ` to the bit (shortest
/// round-trip decimals), and the verify builds the same model for the declared mass, so both
/// evaluate one function on the same numbers. With the redistributed mass, whose contact row is
/// zero, too.
#[test]
fn the_energy_computed_from_the_fields_is_the_harness_own_energy_norm() {
    let dir = scratch("energy");
    let problem = problem();
    let cases = [
        (Scheme::CRANK_NICOLSON, MassVariant::Standard, "standard"),
        (
            Scheme::BACKWARD_EULER,
            MassVariant::Redistributed,
            "redistributed",
        ),
    ];
    let mut files = Vec::new();
    for (scheme, mass, name) in cases {
        for (e, nx) in exports(Case { scheme, mass }).iter().zip(LEVELS) {
            let path = dir.join(format!("{name}-nx{nx}.json"));
            write_v2(&path, e, name, json!({"mass": name}), |_, _| {});
            files.push(path);
        }
    }
    let (_, json) = verify(&dir, &files);
    let norms: BTreeSet<Norm> = [Norm::EnergyLinf, Norm::EnergyL2].into_iter().collect();
    let config = StudyConfig {
        levels: LEVELS.to_vec(),
        ratio: 10.0,
        horizon: 3.0,
        settings: Default::default(),
    };
    for (scheme, mass, name) in cases {
        let study = run_study(&problem, &[Case { scheme, mass }], &norms, &config).unwrap();
        let s = series(&json, name);
        for internal in &study.cases[0].rates {
            assert_eq!(
                errors(s, internal.norm),
                Some(bits(&internal.errors)),
                "{name} {}",
                internal.norm
            );
        }
    }
}

/// A reported energy without its definition, an unknown definition, an unknown mass, and
/// version 2's declarations in a version 1 file are refused naming the field and what is
/// allowed.
#[test]
fn version_2_declarations_are_checked() {
    let dir = scratch("refused");
    let case = Case {
        scheme: Scheme::CRANK_NICOLSON,
        mass: MassVariant::Standard,
    };
    let e = &exports(case)[0];
    let energy = |k: usize, s: &mut Map<String, Value>| {
        s.insert("energy".into(), json!(e.energy[k].1));
    };
    let file = |name: &str, head: Value, with_energy: bool| {
        let path = dir.join(name);
        write_v2(&path, e, "refused", head, |k, s| {
            if with_energy {
                energy(k, s)
            }
        });
        path.to_string_lossy().into_owned()
    };
    let cases = [
        (
            file("undefined.json", json!({"mass": "standard"}), true),
            vec![
                "invalid energy_definition = missing",
                "total-at-sample, staggered, total-with-contact-term",
            ],
        ),
        (
            file(
                "unknown.json",
                json!({"energy_definition": "kinetic"}),
                true,
            ),
            vec![
                "invalid energy_definition = \"kinetic\"",
                "total-at-sample, staggered, total-with-contact-term",
            ],
        ),
        (
            file("mass.json", json!({"mass": "heavy"}), false),
            vec![
                "invalid mass = \"heavy\"",
                "one of: standard, redistributed, lumped",
            ],
        ),
        (
            file(
                "alone.json",
                json!({"energy_definition": "staggered"}),
                false,
            ),
            vec!["invalid energy_definition = given", "only with energy"],
        ),
        (
            file("scheme.json", json!({"scheme": "leapfrog"}), false),
            vec!["invalid scheme = \"leapfrog\"", "crank-nicolson"],
        ),
        (
            file("contact.json", json!({"contact": " "}), false),
            vec!["invalid contact", "a non-empty text"],
        ),
    ];
    for (path, needles) in &cases {
        expect_error(&["verify", SCENE, path], 2, needles);
    }
    let v1 = dir.join("v1.json");
    write_json(&v1, e, "v1");
    let text = std::fs::read_to_string(&v1).unwrap().replacen(
        "\"label\":",
        "\"mass\":\"standard\",\"label\":",
        1,
    );
    std::fs::write(&v1, text).unwrap();
    expect_error(
        &["verify", SCENE, &v1.to_string_lossy()],
        2,
        &["invalid mass = given", "signorini-external/2"],
    );
    let text = std::fs::read_to_string(&v1).unwrap().replacen(
        "\"mass\":\"standard\"",
        "\"scheme\":\"crank-nicolson\"",
        1,
    );
    std::fs::write(&v1, text).unwrap();
    expect_error(
        &["verify", SCENE, &v1.to_string_lossy()],
        2,
        &["invalid scheme = given", "signorini-external/2"],
    );
}

/// A version 2 file's `scheme`, `mass` and `contact` are the series' declarations in
/// `verify.json`, for the league table.
#[test]
fn version_2_declarations_are_the_series_declarations() {
    let dir = scratch("declared");
    let case = Case {
        scheme: Scheme::CRANK_NICOLSON,
        mass: MassVariant::Redistributed,
    };
    let head = json!({
        "scheme": "newmark(beta=0.25,gamma=0.5)",
        "mass": "redistributed",
        "contact": "multiplier, exact",
    });
    let files: Vec<PathBuf> = exports(case)
        .iter()
        .map(|e| {
            let path = dir.join(format!("declared-{}.json", e.nodes.len() - 1));
            write_v2(&path, e, "declared", head.clone(), |_, _| {});
            path
        })
        .collect();
    let (_, json) = verify(&dir, &files);
    assert_eq!(
        series(&json, "declared")["declared"],
        json!({
            "scheme": "crank-nicolson",
            "mass": "redistributed",
            "contact": "multiplier, exact",
        })
    );
}

/// The harness reruns what a file with fields declares and compares it sample by sample: its own
/// runs (Moreau–Jean, Crank–Nicolson with the singular mass, Paoli–Schatzman with its `λ` at
/// `t_{n−1}`) come back to round-off; the same fields declared as another scheme differ at
/// the size of a discretisation error; a declared contact treatment other than the scene's is
/// not rerun, with a note.
#[test]
fn a_declared_scheme_and_mass_are_rerun_by_the_harness_and_compared() {
    let dir = scratch("rerun");
    let cases = [
        (
            Scheme::MoreauJean {
                theta: 0.5,
                restitution: 0.0,
            },
            MassVariant::Standard,
        ),
        (Scheme::CRANK_NICOLSON, MassVariant::Redistributed),
        (
            Scheme::PaoliSchatzman {
                beta: 0.25,
                restitution: 0.0,
            },
            MassVariant::Standard,
        ),
    ];
    let mut files = Vec::new();
    for (scheme, mass) in cases {
        for (declared, contact, tag) in [
            (scheme, "multiplier", "own"),
            (Scheme::BACKWARD_EULER, "multiplier", "other"),
            (scheme, "penalty(gamma0=10)", "penalty"),
        ] {
            let head = json!({
                "scheme": declared.name(),
                "mass": mass.name(),
                "contact": contact,
            });
            let label = format!("{}-{}-{tag}", scheme.name(), mass.name());
            for e in exports(Case { scheme, mass }) {
                let path = dir.join(format!("{label}-{}.json", e.nodes.len() - 1));
                write_v2(&path, &e, &label, head.clone(), |_, _| {});
                files.push(path);
            }
        }
    }
    let (_, json) = verify(&dir, &files);
    for (scheme, mass) in cases {
        let id = format!("{}-{}", scheme.name(), mass.name());
        let own = &series(&json, &format!("{id}-own"))["step_differences"];
        assert_eq!(own.as_array().unwrap().len(), LEVELS.len(), "{id}");
        for d in own.as_array().unwrap() {
            for field in ["displacement", "velocity", "multiplier"] {
                let x = d[field].as_f64().unwrap();
                assert!(x <= 1e-12, "{id} {field}: {x:e}");
            }
        }
        let other = &series(&json, &format!("{id}-other"))["step_differences"];
        for d in other.as_array().unwrap() {
            let x = d["displacement"].as_f64().unwrap();
            assert!(x > 1e-3, "{id} declared backward Euler: {x:e}");
        }
        let penalty = series(&json, &format!("{id}-penalty"));
        assert!(penalty.get("step_differences").is_none(), "{id}");
        let notes = penalty["notes"].as_array().unwrap();
        assert!(
            notes.iter().any(|n| n
                .as_str()
                .unwrap()
                .contains("declares the contact treatment penalty(gamma0=10)")),
            "{id}: {notes:?}"
        );
    }
}
