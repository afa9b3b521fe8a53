//! Another code's runs (`harness::external`): a run of the harness exported in the external
//! format and verified gives the internal run's norms and rates bit for bit, through JSON and
//! CSV; every malformed or inconsistent file is a typed error naming its field; series are
//! checked; the golden comparison passes on its own values and catches a drift.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

use crate::benchmarks;
use crate::external_runs::{export_run, write_csv, write_json, SCENE};
use signorini::engine::fem::MassVariant;
use signorini::engine::schemes::Scheme;
use signorini::harness::external::box_run::SeriesOptions;
use signorini::harness::external::load::load;
use signorini::harness::external::verify::fine_mesh::ReferenceSource;
use signorini::harness::external::{
    compare, verify as measure, ExternalError, Verification, VerifyGolden, VerifySources,
};
use signorini::harness::reference::exact::run_study;
use signorini::harness::reference::fine_mesh::cache::ReferenceCache;
use signorini::harness::run::norms::Norm;
use signorini::harness::study::budget::Limits;
use signorini::harness::study::scene::Scene;
use signorini::harness::study::{Case, StudyConfig};

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("signorini-ext-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn scene() -> Scene {
    Scene::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join(SCENE)).unwrap()
}

/// The files `files` verified against `scene` as measured (a box scene's reference is neither
/// read nor computed: its files are refused first).
fn verify(scene: &Scene, files: &[PathBuf]) -> Result<Verification, ExternalError> {
    let cache = ReferenceCache::ReadOnly(std::env::temp_dir().join("signorini-ext-no-references"));
    let sources = VerifySources {
        pvd: &SeriesOptions::default(),
        reference: ReferenceSource {
            cache: &cache,
            limits: &Limits::or_defaults(None, None, None),
        },
    };
    Ok(measure(scene, files, &sources, &mut |_| {})?.verification)
}

/// Exports `case` at `levels` as JSON (label `… json`) and CSV (label `… csv`) into `dir`, and
/// checks that verifying them gives exactly the errors, oscillation ratios and rates of the
/// harness's own study of the case.
fn exported_runs_verify_as_the_internal_study(case: Case, levels: &[usize], csv: bool) {
    let dir = scratch(&case.id().replace('/', "-"));
    let problem = benchmarks::dirichlet(3.0);
    let mut files = Vec::new();
    for &nx in levels {
        let e = export_run(&problem, nx, 10.0, case.scheme, case.mass);
        let json = dir.join(format!("nx{nx}.json"));
        write_json(&json, &e, "json");
        files.push(json);
        if csv {
            let csv = dir.join(format!("nx{nx}.csv"));
            write_csv(&csv, &e, "csv");
            files.push(csv);
        }
    }
    let scene = scene();
    let v = verify(&scene, &files).unwrap();
    assert_eq!(v.series.len(), if csv { 2 } else { 1 });
    let norms: BTreeSet<Norm> = Norm::ALL.into_iter().collect();
    let config = StudyConfig {
        levels: levels.to_vec(),
        ratio: 10.0,
        horizon: 3.0,
        settings: Default::default(),
    };
    let study = run_study(&problem, &[case], &norms, &config).unwrap();
    let internal = &study.cases[0];
    for s in &v.series {
        assert!(s.not_computed.is_empty(), "{:?}", s.not_computed);
        assert_eq!(s.rates.len(), 7);
        for (ours, theirs) in s.rates.iter().zip(&internal.rates) {
            assert_eq!(ours.norm, theirs.norm);
            let bits = |e: &[f64]| e.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            assert_eq!(
                bits(&ours.errors),
                bits(&theirs.errors),
                "{} {}: {:?} against {:?}",
                s.label,
                ours.norm,
                ours.errors,
                theirs.errors
            );
            assert_eq!(ours.fit, theirs.fit);
            assert_eq!(ours.fit_last_three, theirs.fit_last_three);
        }
        for (ours, theirs) in s.levels.iter().zip(&internal.levels) {
            assert_eq!(ours.nx, theirs.nx);
            assert_eq!(ours.h, theirs.h);
            assert_eq!(ours.steps, theirs.steps);
            assert_eq!(
                ours.multiplier_variation_ratio,
                theirs.multiplier_variation_ratio
            );
            assert!((ours.dt - theirs.dt).abs() <= 1e-12 * theirs.dt);
        }
        assert!(s
            .runs
            .iter()
            .all(|r| r.contact_displacement_error.is_some()));
    }
}

/// The single implementation: Crank–Nicolson with the standard mass at NX = 10, 20, 40,
/// exported as JSON and as CSV, verifies to the bits of the harness's own study.
#[test]
fn crank_nicolson_exported_verifies_to_the_bits_of_the_internal_study() {
    let case = Case {
        scheme: Scheme::CRANK_NICOLSON,
        mass: MassVariant::Standard,
    };
    exported_runs_verify_as_the_internal_study(case, &[10, 20, 40], true);
}

/// A scheme whose energy approximates `t_{n−½}` (Paoli–Schatzman): the file's `energy_time`
/// reaches the observers, and the norms are still the internal ones, bit for bit.
#[test]
fn paoli_schatzman_with_its_energy_times_verifies_to_the_bits() {
    let case = Case {
        scheme: "paoli-schatzman-e0.5".parse().unwrap(),
        mass: MassVariant::Standard,
    };
    exported_runs_verify_as_the_internal_study(case, &[10, 20], false);
}

const BASE_CSV: &str = "\
# format: signorini-external/1
# scene: bar1d-dirichlet
# code.name: test
# code.version: 0
# label: base
# mesh.nodes: 0, 0.5, 1
time,u0,u1,u2,lambda,contact_displacement,energy
0,0.5,0.25,0,0,0.5,0.125
1.5,0,-0.25,0,-0.5,0,0.125
3,0.5,0.25,0,0,0.5,0.125
";

const ENERGY_ONLY: &str = "\
# format: signorini-external/1
# scene: bar1d-dirichlet
# code.name: test
# code.version: 0
# label: energy only
# mesh.nodes: 0, 0.5, 1
time,energy
0,0.125
3,0.125
";

const BASE_JSON: &str = r#"{
  "format": "signorini-external/1",
  "scene": "bar1d-dirichlet",
  "code": { "name": "test", "version": "0" },
  "label": "base",
  "mesh": { "nodes": [0, 0.5, 1] },
  "samples": [
    { "time": 0, "displacement": [0.5, 0.25, 0], "lambda": 0, "energy": 0.125 },
    { "time": 1.5, "displacement": [0, -0.25, 0], "lambda": -0.5, "energy": 0.125 },
    { "time": 3, "displacement": [0.5, 0.25, 0], "lambda": 0, "energy": 0.125 }
  ]
}"#;

/// `base` with `from` replaced by `to`, written as `name` into `dir`.
fn edited(dir: &Path, name: &str, base: &str, from: &str, to: &str) -> PathBuf {
    assert!(base.contains(from), "{from:?} not in the base file");
    let path = dir.join(name);
    std::fs::write(&path, base.replacen(from, to, 1)).unwrap();
    path
}

/// Every kind of bad file is a typed error naming its field (and where it is), never a panic.
#[test]
fn malformed_or_inconsistent_files_are_errors_naming_the_field() {
    let dir = scratch("malformed");
    let scene = scene();
    let signorini::engine::problem::Problem::Bar(problem) = scene.problem() else {
        panic!("a bar scene")
    };
    let check = |path: PathBuf| load(&path, &scene.name, &problem);
    assert!(check(edited(&dir, "ok.csv", BASE_CSV, "", "")).is_ok());
    assert!(check(edited(&dir, "ok.json", BASE_JSON, "", "")).is_ok());

    let csv = |name: &str, from: &str, to: &str| check(edited(&dir, name, BASE_CSV, from, to));
    let json = |name: &str, from: &str, to: &str| check(edited(&dir, name, BASE_JSON, from, to));
    let cases: Vec<(&str, Result<_, ExternalError>, &str, Option<&str>)> = vec![
        (
            "row length",
            csv("a.csv", "1.5,0,-0.25,0,", "1.5,0,-0.25,"),
            "row",
            Some("line 9"),
        ),
        (
            "NaN",
            csv("b.csv", "-0.5,0,0.125", "NaN,0,0.125"),
            "lambda",
            Some("line 9, column 5"),
        ),
        (
            "time order",
            csv("c.csv", "\n1.5,", "\n3,"),
            "time",
            Some("line 10"),
        ),
        (
            "unknown column",
            csv("d.csv", "energy\n", "enrgy\n"),
            "columns",
            Some("line 7, column 7"),
        ),
        (
            "wrong scene",
            csv("e.csv", "scene: bar1d-dirichlet", "scene: bar1d-gravity"),
            "scene",
            None,
        ),
        (
            "non-uniform mesh",
            csv("f.csv", "0, 0.5, 1", "0, 0.6, 1"),
            "mesh.nodes",
            Some("node 1"),
        ),
        (
            "short mesh",
            csv("g.csv", "0, 0.5, 1", "0, 0.5, 0.9"),
            "mesh.nodes",
            Some("node 2"),
        ),
        (
            "missing label",
            csv("h.csv", "# label: base\n", ""),
            "label",
            None,
        ),
        (
            "unknown key",
            csv("i.csv", "# label:", "# lable:"),
            "metadata",
            Some("line 5"),
        ),
        (
            "late horizon",
            csv("j.csv", "\n3,0.5", "\n2.9,0.5"),
            "time",
            Some("line 10"),
        ),
        (
            "first time",
            csv("k.csv", "\n0,0.5", "\n0.1,0.5"),
            "time",
            Some("line 8"),
        ),
        (
            "clamped end",
            csv("l.csv", "1.5,0,-0.25,0,", "1.5,0,-0.25,0.1,"),
            "u2",
            Some("line 9"),
        ),
        (
            "contact displacement",
            csv("m.csv", "-0.5,0,0.125", "-0.5,0.1,0.125"),
            "contact_displacement",
            Some("line 9"),
        ),
        (
            "field columns",
            csv("n.csv", "u1,u2,", "u1,v2,"),
            "u2",
            Some("line 7"),
        ),
        (
            "format",
            csv("o.csv", "external/1", "external/9"),
            "format",
            None,
        ),
        (
            "extension",
            check(edited(&dir, "p.txt", BASE_CSV, "", "")),
            "file name",
            None,
        ),
        (
            "field length",
            json("q.json", "[0, -0.25, 0]", "[0, -0.25]"),
            "displacement",
            Some("samples[1]"),
        ),
        (
            "null",
            json("r.json", "\"lambda\": -0.5", "\"lambda\": null"),
            "lambda",
            Some("samples[1]"),
        ),
        (
            "missing energy",
            json(
                "s.json",
                ", \"energy\": 0.125 },\n    { \"time\": 3",
                " },\n    { \"time\": 3",
            ),
            "energy",
            Some("samples[1]"),
        ),
        (
            "energy_time without energy",
            csv("v.csv", "energy\n", "energy_time\n"),
            "energy_time",
            None,
        ),
        (
            "a field in one sample only",
            json(
                "t.json",
                "\"energy\": 0.125 }\n",
                "\"energy\": 0.125, \"energy_time\": 3 }\n",
            ),
            "energy_time",
            Some("samples[2]"),
        ),
        (
            "reported times",
            json(
                "u.json",
                "\"lambda\": -0.5,",
                "\"lambda\": -0.5, \"lambda_time\": 4,",
            ),
            "lambda_time",
            Some("samples[1]"),
        ),
        (
            "neither fields nor a contact trace",
            check(edited(&dir, "z.csv", ENERGY_ONLY, "", "")),
            "displacement",
            None,
        ),
        (
            "fields missing from samples[0] only",
            json(
                "w.json",
                "\"displacement\": [0.5, 0.25, 0], \"lambda\": 0, ",
                "",
            ),
            "displacement",
            Some("samples[1]"),
        ),
    ];
    for (what, result, field, at) in cases {
        match result {
            Err(ExternalError::Invalid {
                field: f, at: a, ..
            }) => {
                assert_eq!(f, field, "{what}");
                assert_eq!(a.as_deref(), at, "{what}");
            }
            other => panic!("{what}: expected an error on {field}, got {other:?}"),
        }
    }
    let message = |r: Result<_, ExternalError>| r.unwrap_err().to_string();
    let unknown = message(json("x.json", "\"label\"", "\"lable\""));
    assert!(
        unknown.contains("unknown field `lable`") && unknown.contains("label"),
        "{unknown}"
    );
    let missing = message(check(dir.join("absent.csv")));
    assert!(
        missing.contains("cannot read run file") && missing.contains("absent.csv"),
        "{missing}"
    );
    let lines = message(csv("y.csv", "\n1.5", "\n\n1.5"));
    assert!(lines.contains("empty line"), "{lines}");
}

/// A contact trace without fields verifies the multiplier and the energy, and says that the
/// displacement norms are not computed and why; the files of one label must be one code at
/// distinct levels; a box scene has no exact solution to verify against.
#[test]
fn series_report_what_is_not_computed_and_are_checked() {
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/external");
    let trace = [
        data.join("contact-trace-nx4.csv"),
        data.join("contact-trace-nx8.csv"),
    ];
    let scene = scene();
    let v = verify(&scene, &trace).unwrap();
    let s = &v.series[0];
    assert_eq!(s.levels.iter().map(|l| l.nx).collect::<Vec<_>>(), [4, 8]);
    let computed: Vec<Norm> = s.rates.iter().map(|r| r.norm).collect();
    assert_eq!(
        computed,
        [Norm::MultiplierL2, Norm::EnergyLinf, Norm::EnergyL2]
    );
    let reason = s.not_computed(Norm::DisplacementLinfH).unwrap();
    assert!(reason.contains("contact-trace-nx4.csv") && reason.contains("no displacement"));
    assert!(s.oscillation_indicator().is_some());

    let dir = scratch("series");
    let twice = [trace[0].clone(), trace[0].clone()];
    assert!(matches!(
        verify(&scene, &twice),
        Err(ExternalError::Series { .. })
    ));
    let other_code = edited(
        &dir,
        "other.csv",
        &std::fs::read_to_string(&trace[1]).unwrap(),
        "code.version: 1",
        "code.version: 2",
    );
    let mixed = [trace[0].clone(), other_code];
    assert!(matches!(
        verify(&scene, &mixed),
        Err(ExternalError::Series { .. })
    ));
    let bar2d =
        Scene::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/bar2d.json")).unwrap();
    assert!(matches!(
        verify(&bar2d, &trace),
        Err(ExternalError::Invalid { .. })
    ));
}

/// The golden file of a verification passes on the same runs and catches a drift, a missing
/// series and other levels; a series without fitted rates cannot be made golden.
#[test]
fn the_verify_gate_passes_on_its_own_values_and_catches_drifts() {
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/external");
    let trace = [
        data.join("contact-trace-nx4.csv"),
        data.join("contact-trace-nx8.csv"),
    ];
    let single = verify(&scene(), &[data.join("interpolant-nx4.json")]).unwrap();
    assert!(matches!(
        VerifyGolden::from_verification(&single),
        Err(ExternalError::Series { .. })
    ));
    let mut v = verify(&scene(), &trace).unwrap();
    let golden = VerifyGolden::from_verification(&v).unwrap();
    assert!(compare(&golden, &v).is_empty());
    let other = verify(&scene(), &[trace[0].clone()]).unwrap();
    assert!(!compare(&golden, &other).is_empty());

    let mut drifted = golden.clone();
    let norm = drifted.series[0].norms.get_mut("lambda_L2").unwrap();
    norm.errors[1] *= 1.02;
    let drifts = compare(&drifted, &v);
    assert!(drifts
        .iter()
        .any(|d| d.quantity == "error[NX=8]" && d.norm == "lambda_L2"));

    let mut levels = golden.clone();
    levels.series[0].levels = vec![4, 16];
    assert!(compare(&levels, &v).iter().any(|d| d.quantity == "missing"));
    v.series[0].label = "renamed".to_string();
    let renamed = compare(&golden, &v);
    assert_eq!(renamed.len(), 2, "a series on each side only: {renamed:?}");
}
