//! `signorini verify` end to end: the committed hand-made runs and runs of the harness exported
//! in the external format verify; `--out` writes whole files; `--write-golden` then `--golden`
//! passes and a perturbed golden file fails with exit code 1; every broken file exits with code
//! 2 and a message naming its field; never a panic.

use crate::common;
use crate::external_runs::{export_run, write_csv, write_json, SCENE};

use std::path::{Path, PathBuf};

use common::{expect_error, signorini, success_stdout};
use signorini::engine::fem::MassVariant;
use signorini::engine::schemes::Scheme;
use signorini::studies::benchmark;

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("signorini-verify-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

const TRACE4: &str = "tests/data/external/contact-trace-nx4.csv";
const TRACE8: &str = "tests/data/external/contact-trace-nx8.csv";
const INTERPOLANT: &str = "tests/data/external/interpolant-nx4.json";

fn text(path: &Path) -> String {
    std::fs::read_to_string(path).unwrap()
}

#[test]
fn the_committed_hand_made_runs_verify() {
    let out = signorini(&["verify", SCENE, TRACE4, TRACE8, INTERPOLANT]);
    let stdout = success_stdout(&out);
    assert!(stdout.contains("### Table 1") && stdout.contains("### Table 2"));
    assert!(stdout.contains(
        "| backward Euler, redistributed mass (contact trace) | hand-copied 1 | not computed |"
    ));
    assert!(stdout.contains("not computed: the file tests/data/external/contact-trace-nx4.csv"));
    assert!(stdout.contains("#### exact solution's nodal interpolant, five samples — hand-made 1"));
}

/// The harness's own runs exported: tables, whole output files, and the gate on its own golden
/// file (passes) and on a perturbed one (fails with the drift named).
#[test]
fn exported_runs_verify_write_their_files_and_are_gated() {
    let dir = scratch("exported");
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let problem = benchmark::dirichlet(root, 3.0).unwrap();
    let mut files = Vec::new();
    for nx in [10, 20, 40] {
        let e = export_run(
            &problem,
            nx,
            10.0,
            Scheme::BACKWARD_EULER,
            MassVariant::Redistributed,
        );
        let json = dir.join(format!("be-nx{nx}.json"));
        write_json(&json, &e, "backward Euler, MOD (JSON)");
        let csv = dir.join(format!("be-nx{nx}.csv"));
        write_csv(&csv, &e, "backward Euler, MOD (CSV)");
        files.push(json.to_string_lossy().into_owned());
        files.push(csv.to_string_lossy().into_owned());
    }
    let out_dir = dir.join("out");
    let golden = dir.join("golden.json");
    let (out_s, golden_s) = (
        out_dir.to_string_lossy().into_owned(),
        golden.to_string_lossy().into_owned(),
    );
    let args = |extra: &[&str]| {
        let mut a = vec!["verify", SCENE];
        a.extend(files.iter().map(String::as_str));
        a.extend_from_slice(extra);
        a.iter().map(|s| s.to_string()).collect::<Vec<_>>()
    };
    let run = |a: Vec<String>| signorini(&a.iter().map(String::as_str).collect::<Vec<_>>());
    let stdout = success_stdout(&run(args(&["--out", &out_s, "--write-golden", &golden_s])));
    assert!(stdout.contains("| backward Euler, MOD (JSON) | signorini test export |"));
    let json: serde_json::Value =
        serde_json::from_str(&text(&out_dir.join("verify.json"))).unwrap();
    assert_eq!(json["scene"], "bar1d-dirichlet");
    assert_eq!(json["series"].as_array().unwrap().len(), 2);
    let rates = &json["series"][0]["rates"];
    assert_eq!(rates.as_array().unwrap().len(), 7);
    assert_eq!(rates[0]["norm"], "u_Linf_H");
    assert!(rates[0]["fit"]["rate"].as_f64().unwrap() > 0.3);
    assert_eq!(json["series"][0]["levels"][2]["nx"], 40);
    assert!(text(&out_dir.join("verify.md")).contains("## Per-level errors"));
    let leftovers = std::fs::read_dir(&out_dir)
        .unwrap()
        .filter_map(|e| e.ok())
        .filter(|e| e.file_name().to_string_lossy().contains(".tmp-"))
        .count();
    assert_eq!(leftovers, 0, "temporary files left behind");

    let stdout = success_stdout(&run(args(&["--golden", &golden_s])));
    assert!(stdout.contains("golden gate passed"));

    let mut g: serde_json::Value = serde_json::from_str(&text(&golden)).unwrap();
    let e = &mut g["series"][1]["norms"]["energy_L2"]["errors"][2];
    *e = serde_json::json!(e.as_f64().unwrap() * 1.05);
    let perturbed = dir.join("perturbed.json");
    std::fs::write(&perturbed, serde_json::to_string(&g).unwrap()).unwrap();
    let out = run(args(&["--golden", &perturbed.to_string_lossy()]));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("drifted")
            && stderr.contains("energy_L2")
            && stderr.contains("error[NX=40]")
    );
    assert!(!stderr.contains("panicked"));
}

/// `base` (a committed fixture) with `from` replaced by `to`, written as `name` into `dir`.
fn broken(dir: &Path, name: &str, base: &str, from: &str, to: &str) -> String {
    let text = text(&Path::new(env!("CARGO_MANIFEST_DIR")).join(base));
    assert!(text.contains(from), "{from:?} not in {base}");
    let path = dir.join(name);
    std::fs::write(&path, text.replacen(from, to, 1)).unwrap();
    path.to_string_lossy().into_owned()
}

#[test]
fn broken_run_files_exit_2_naming_the_field() {
    let dir = scratch("broken");
    let cases = [
        (
            broken(
                &dir,
                "length.csv",
                TRACE4,
                "\n0.25,0.2554,0,",
                "\n0.25,0.2554,",
            ),
            vec!["invalid row", "line 9", "one per header column"],
        ),
        (
            broken(&dir, "nan.csv", TRACE4, "-0.1844", "NaN"),
            vec!["invalid lambda = NaN", "line 13", "finite"],
        ),
        (
            broken(&dir, "time.csv", TRACE4, "\n1.25,", "\n0.9,"),
            vec!["invalid time = 0.9", "line 13", "strictly increasing"],
        ),
        (
            broken(&dir, "column.csv", TRACE4, "energy\n", "energie\n"),
            vec![
                "invalid columns = \"energie\"",
                "column 4",
                "contact_displacement",
            ],
        ),
        (
            broken(
                &dir,
                "scene.csv",
                TRACE4,
                "bar1d-dirichlet",
                "bar1d-gravity",
            ),
            vec!["invalid scene = \"bar1d-gravity\"", "\"bar1d-dirichlet\""],
        ),
        (
            broken(&dir, "mesh.csv", TRACE4, "0.5, 0.75", "0.55, 0.75"),
            vec!["invalid mesh.nodes = 0.55", "node 2", "uniform mesh"],
        ),
        (
            broken(
                &dir,
                "length.json",
                INTERPOLANT,
                "[0.125, 0.125, 0.125, 0.125, 0]",
                "[0.125, 0.125, 0]",
            ),
            vec![
                "invalid displacement = 3 values",
                "samples[1]",
                "one value per mesh node (5)",
            ],
        ),
        (
            broken(
                &dir,
                "field.json",
                INTERPOLANT,
                "\"energy\": 0.125 },",
                "\"energy\": 0.125, \"stress\": 1 },",
            ),
            vec!["unknown field `stress`", "line 8"],
        ),
        (
            dir.join("missing.csv").to_string_lossy().into_owned(),
            vec!["cannot read run file", "missing.csv"],
        ),
    ];
    for (file, needles) in &cases {
        expect_error(&["verify", SCENE, file], 2, needles);
    }
    expect_error(
        &["verify", "scenes/bar2d.json", TRACE4],
        2,
        &[
            "extension \"csv\"",
            ".pvd (a ParaView collection), .xdmf (XDMF with HDF5 heavy data) or .json",
        ],
    );
}

/// A diverged run's energy overflows the energy error: those norms are not computed (with the
/// sample where it overflows), the others are, and no number stands for them.
#[test]
fn a_diverged_runs_overflowing_norms_are_not_computed() {
    let dir = scratch("diverged");
    let file = broken(
        &dir,
        "diverged.csv",
        TRACE4,
        "0.75,0.01778,0,0.0372",
        "0.75,0.01778,0,1e200",
    );
    let stdout = success_stdout(&signorini(&["verify", SCENE, &file]));
    assert!(
        stdout.contains("`energy_Linf`, `energy_L2` not computed")
            && stdout.contains("no finite energy error (it overflows at sample 3"),
        "{stdout}"
    );
    let non_finite = stdout
        .split(['|', ' ', '\n'])
        .any(|cell| ["inf", "-inf", "NaN"].contains(&cell));
    assert!(!non_finite, "{stdout}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// A golden file whose error arrays were emptied, or whose norms were removed, fails the gate
/// naming each entry, with no number printed for what is missing (issue 55 item 4).
#[test]
fn a_golden_file_emptied_of_its_errors_fails_the_gate() {
    let dir = scratch("golden-emptied");
    let golden = dir.join("golden.json");
    let golden_arg = golden.to_string_lossy().into_owned();
    success_stdout(&signorini(&[
        "verify",
        SCENE,
        TRACE4,
        TRACE8,
        "--write-golden",
        &golden_arg,
    ]));
    let written: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&golden).unwrap()).unwrap();
    let mut emptied = written.clone();
    for series in emptied["series"].as_array_mut().unwrap() {
        for norm in series["norms"].as_object_mut().unwrap().values_mut() {
            norm["errors"] = serde_json::json!([]);
        }
    }
    let mut without_norms = written;
    for series in without_norms["series"].as_array_mut().unwrap() {
        series["norms"] = serde_json::json!({});
    }
    for (edited, needle) in [
        (
            emptied,
            "energy_L2 (the golden file has 0 errors for 2 levels)",
        ),
        (without_norms, "| energy_L2 | missing | — | — | — | — |"),
    ] {
        std::fs::write(&golden, edited.to_string()).unwrap();
        let out = signorini(&["verify", SCENE, TRACE4, TRACE8, "--golden", &golden_arg]);
        let text = format!(
            "{}{}",
            String::from_utf8_lossy(&out.stdout),
            String::from_utf8_lossy(&out.stderr)
        );
        assert_eq!(out.status.code(), Some(1), "{text}");
        assert!(text.contains(needle), "{needle:?} not in {text}");
        assert!(
            !text.contains("NaN") && !text.contains("gate passed"),
            "{text}"
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// A contact displacement of 1e200 overflows the contact trace's L² norm: the diagnostic is not
/// computed (`null`, as for a file without the trace), never half a number with its `l2` `null`
/// (issue 55 item 4).
#[test]
fn an_overflowing_contact_trace_is_left_out_not_written_as_null() {
    let dir = scratch("contact-overflow");
    let file = broken(
        &dir,
        "overflow.csv",
        TRACE4,
        "0.75,0.01778,0,0.0372",
        "0.75,1e200,0,0.0372",
    );
    let out = dir.join("out");
    success_stdout(&signorini(&[
        "verify",
        SCENE,
        &file,
        "--out",
        &out.to_string_lossy(),
    ]));
    let json = std::fs::read_to_string(out.join("verify.json")).unwrap();
    assert!(
        json.contains("\"contact_displacement_error\": null"),
        "{json}"
    );
    assert!(!json.contains("\"l2\": null"), "{json}");
    let _ = std::fs::remove_dir_all(&dir);
}
