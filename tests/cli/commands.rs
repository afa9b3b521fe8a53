//! The `signorini` binary end to end: good runs write whole files, every bad input gets a
//! one-paragraph message naming the field, exit code 2 for usage errors and 1 for failures,
//! never a panic, and no half-written output.

use crate::common;

use std::path::{Path, PathBuf};

use common::{expect_error, signorini, success_stdout};

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("signorini-cli-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

const DIRICHLET: &str = "scenes/bar1d-dirichlet.json";

/// The scene text with `from` replaced by `to`, written to a scratch file.
/// The Dirichlet scene's velocity, horizon and reference: replaced to make an `at-rest` scene.
const AT_REST_FROM: &str = "\"velocity\": \"reference\" },\n  \"horizon\": 3.0,\n  \"reference\": { \"exact\": \"signorini-dirichlet\" }";

fn edited_scene(dir: &Path, from: &str, to: &str) -> String {
    let text =
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join(DIRICHLET)).unwrap();
    assert!(text.contains(from), "the scene no longer contains {from:?}");
    let path = dir.join("scene.json");
    std::fs::write(&path, text.replacen(from, to, 1)).unwrap();
    path.to_string_lossy().into_owned()
}

fn run_args<'a>(scene: &'a str, extra: &[&'a str]) -> Vec<&'a str> {
    let mut v = vec![
        "run",
        scene,
        "--scheme",
        "crank-nicolson",
        "--mass",
        "standard",
        "--nx",
        "10",
    ];
    v.extend_from_slice(extra);
    v
}

#[test]
fn a_run_writes_its_summary_and_whole_files() {
    let dir = scratch("ok");
    let out_dir = dir.join("out");
    let out_str = out_dir.to_string_lossy().into_owned();
    let out = signorini(&run_args(DIRICHLET, &["--out", &out_str]));
    let stdout = success_stdout(&out);
    assert!(stdout.contains("u_Linf_H") && stdout.contains("energy_L2"));
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out_dir.join("run.json")).unwrap()).unwrap();
    assert_eq!(json["nx"], 10);
    assert_eq!(json["steps"], 300);
    assert!(json.get("max_balance_residual").is_none());
    assert!(!stdout.contains("energy balance"));
    for f in ["contact.csv", "multiplier.csv", "energy.csv"] {
        let text = std::fs::read_to_string(out_dir.join(f)).unwrap();
        assert_eq!(text.lines().count(), 302, "{f}: header + 301 samples");
    }
    let leftovers: Vec<_> = std::fs::read_dir(&out_dir)
        .unwrap()
        .filter_map(|e| e.ok())
        .filter(|e| e.file_name().to_string_lossy().contains(".tmp-"))
        .collect();
    assert!(leftovers.is_empty(), "temporary files left behind");
}

#[test]
fn a_study_prints_a_rate_table_and_json() {
    let out = signorini(&[
        "study",
        DIRICHLET,
        "--scheme",
        "backward-euler",
        "--mass",
        "redistributed",
        "--norm",
        "u_Linf_H",
        "--levels",
        "10,20,40",
    ]);
    let stdout = success_stdout(&out);
    assert!(stdout.contains("| 40 |") && stdout.contains("fit, all levels"));
    assert!(
        !stdout.contains("energy_L2"),
        "a norm outside the selection was computed"
    );

    let out = signorini(&[
        "study",
        "scenes/bar1d-free.json",
        "--scheme",
        "crank-nicolson",
        "--mass",
        "standard",
        "--levels",
        "10,20,40",
        "--json",
    ]);
    success_stdout(&out);
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let rate = json["cases"][0]["rates"]
        .as_array()
        .unwrap()
        .iter()
        .find(|r| r["norm"] == "u_Linf_H")
        .unwrap()["fit"]["rate"]
        .as_f64()
        .unwrap();
    assert!(
        (rate - 2.0).abs() < 0.1,
        "Crank–Nicolson without obstacle: rate {rate}"
    );
}

#[test]
fn the_gravity_scene_studies_crank_nicolson_and_the_rivals_with_both_masses() {
    let out = signorini(&["study", "scenes/bar1d-gravity.json", "--levels", "10,20,40"]);
    let stdout = success_stdout(&out);
    assert!(stdout.contains("#### Crank–Nicolson — standard"));
    assert!(stdout.contains("#### Crank–Nicolson — redistributed"));
    assert!(stdout.contains("#### Moreau–Jean θ = 1/2, e = 0 (Jean) — redistributed"));
    // Seven schemes with both masses, but contact-stabilised Newmark (two variants) with the
    // standard mass only.
    assert!(stdout.contains("12 cases × 3 levels"), "{stdout}");
    let refused = signorini(&[
        "study",
        "scenes/bar1d-gravity.json",
        "--scheme",
        "contact-stabilised-newmark",
        "--mass",
        "redistributed",
    ]);
    assert!(!refused.status.success());
    let stderr = String::from_utf8_lossy(&refused.stderr);
    assert!(
        stderr.contains("--mass") && stderr.contains("standard or lumped"),
        "{stderr}"
    );
}

#[test]
fn help_and_list_document_the_commands() {
    let out = signorini(&["--help"]);
    let text = String::from_utf8_lossy(&out.stdout);
    for needle in ["run", "study", "report", "list", "Examples:", "Exit codes"] {
        assert!(text.contains(needle), "--help lacks {needle}");
    }
    let out = signorini(&["list"]);
    let text = String::from_utf8_lossy(&out.stdout);
    for needle in [
        "crank-nicolson",
        "paoli-schatzman-e0.5",
        "Laursen–Chawla, energy-conserving [rival]",
        "redistributed",
        "lambda_L2",
        "scenes/bar1d-dirichlet.json",
    ] {
        assert!(text.contains(needle), "list lacks {needle}");
    }
    // The schemes are a table: every row's parameters start in one column.
    let rows: Vec<&str> = text
        .lines()
        .skip_while(|l| !l.starts_with("Schemes"))
        .skip(1)
        .take_while(|l| !l.starts_with("  any parameters"))
        .collect();
    let column = |row: &str| {
        let name_end = 2 + row[2..].find(' ').unwrap();
        row[..name_end].chars().count() + row[name_end..].len() - row[name_end..].trim_start().len()
    };
    assert!(rows.len() >= 14, "{rows:?}");
    assert!(
        rows.iter().all(|r| column(r) == column(rows[0])),
        "{rows:#?}"
    );
    let moreau = rows
        .iter()
        .find(|r| r.starts_with("  moreau-jean "))
        .unwrap();
    assert!(moreau.contains("Moreau–Jean θ = 0.5, e = 0"), "{moreau}");
}

#[test]
fn usage_errors_in_arguments_exit_2() {
    expect_error(
        &[
            "run", DIRICHLET, "--scheme", "leapfrog", "--mass", "standard", "--nx", "10",
        ],
        2,
        &["scheme", "crank-nicolson", "paoli-schatzman-e1"],
    );
    expect_error(
        &[
            "run",
            DIRICHLET,
            "--scheme",
            "crank-nicolson",
            "--mass",
            "heavy",
            "--nx",
            "10",
        ],
        2,
        &["mass", "standard, redistributed"],
    );
    expect_error(
        &run_args(DIRICHLET, &["--ratio", "-1"]),
        2,
        &["ratio", "> 0"],
    );
    expect_error(&run_args(DIRICHLET, &["--ratio", "0"]), 2, &["ratio"]);
    expect_error(
        &[
            "run",
            DIRICHLET,
            "--scheme",
            "crank-nicolson",
            "--mass",
            "standard",
            "--nx",
            "0",
        ],
        2,
        &["nx", ">= 1"],
    );
    expect_error(
        &[
            "run",
            DIRICHLET,
            "--scheme",
            "theta(theta=1.5)",
            "--mass",
            "standard",
            "--nx",
            "5",
        ],
        2,
        &["theta", "(0, 1]"],
    );
    expect_error(
        &[
            "run",
            DIRICHLET,
            "--scheme",
            "paoli-schatzman(beta=0.25,e=2)",
            "--mass",
            "standard",
            "--nx",
            "5",
        ],
        2,
        &["e = 2", "[0, 1]"],
    );
    expect_error(
        &["study", DIRICHLET, "--norm", "u_Linf_W"],
        2,
        &["norm", "u_Linf_H"],
    );
    expect_error(
        &["study", DIRICHLET, "--levels", "40,20"],
        2,
        &["levels", "increasing"],
    );
    expect_error(&["frobnicate"], 2, &["frobnicate"]);
}

/// `run --check-balance` prints the largest per-step residual of the scheme's balance (eq. 37
/// for Paoli–Schatzman) and writes it to run.json; it holds to round-off.
#[test]
fn check_balance_reports_the_largest_residual_in_text_and_json() {
    let dir = scratch("balance");
    let out_dir = dir.join("out");
    let out_str = out_dir.to_string_lossy().into_owned();
    let out = signorini(&[
        "run",
        DIRICHLET,
        "--scheme",
        "paoli-schatzman-e0.5",
        "--mass",
        "redistributed",
        "--nx",
        "20",
        "--check-balance",
        "--out",
        &out_str,
    ]);
    let stdout = success_stdout(&out);
    assert!(
        stdout.contains("energy balance eq. (37): largest per-step residual"),
        "{stdout}"
    );
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out_dir.join("run.json")).unwrap()).unwrap();
    let residual = json["max_balance_residual"].as_f64().expect("a number");
    assert!(
        residual > 0.0 && residual <= signorini::engine::schemes::energy_balance::BALANCE_TOLERANCE,
        "{residual:e}"
    );
    // A box run checks the same balance on the box's matrices (eq. 35 for backward Euler).
    let box_out = dir.join("box");
    let stdout = success_stdout(&signorini(&[
        "run",
        "scenes/bar2d.json",
        "--scheme",
        "backward-euler",
        "--mass",
        "redistributed",
        "--nx",
        "10",
        "--check-balance",
        "--out",
        &box_out.to_string_lossy(),
    ]));
    assert!(
        stdout.contains("energy balance eq. (35): largest per-step residual"),
        "{stdout}"
    );
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(box_out.join("run.json")).unwrap()).unwrap();
    let residual = json["max_balance_residual"].as_f64().expect("a number");
    assert!(
        residual <= signorini::engine::schemes::energy_balance::BALANCE_TOLERANCE,
        "{residual:e}"
    );
}

#[test]
fn bad_scene_files_exit_2_naming_the_problem() {
    let dir = scratch("scenes");
    let missing = dir.join("nope.json").to_string_lossy().into_owned();
    expect_error(&run_args(&missing, &[]), 2, &["nope.json", "cannot read"]);

    let broken = dir.join("broken.json");
    std::fs::write(&broken, "{\n  \"name\": \"x\",\n  \"description\": \n}").unwrap();
    expect_error(
        &run_args(&broken.to_string_lossy(), &[]),
        2,
        &["broken.json", "line 4", "column"],
    );

    // (text in the scene, replacement, what the message must say)
    let edits: [(&str, &str, &[&str]); 18] = [
        (
            "\"horizon\"",
            "\"horizn\": 1.0, \"horizon\"",
            &["unknown field `horizn`", "expected one of"],
        ),
        ("\"horizon\": 3.0,", "", &["missing field `horizon`"]),
        (
            "\"density\": 1.0",
            "\"density\": -2.0",
            &["material.density", "-2", "> 0"],
        ),
        ("\"horizon\": 3.0", "\"horizon\": 0.0", &["horizon", "> 0"]),
        ("\"gap\": 0.0", "\"gap\": -0.5", &["obstacle.gap", ">= 0"]),
        (
            "\"signorini-dirichlet\"",
            "\"bouncy\"",
            &["reference.exact", "signorini-dirichlet, clamped-free-mode"],
        ),
        (
            "\"length\": 1.0",
            "\"length\": 2.0",
            &["reference.exact", "L = 1"],
        ),
        (
            "\"clamped\"",
            "\"pinned\"",
            &["unknown variant `pinned`", "clamped", "free"],
        ),
        (
            "\"u_Linf_H\",",
            "\"u_sup\",",
            &["observables.norms", "u_sup"],
        ),
        (
            "[10, 20, 40, 80, 160, 320, 640]",
            "[20, 10]",
            &["discretisation.levels", "increasing"],
        ),
        (
            "\"ratio\": 10.0",
            "\"ratio\": \"ten\"",
            &["invalid type", "line"],
        ),
        (
            "\"observables\": {",
            "\"observables\": { \"points\": [2.0],",
            &["observables.points", "[0, L]"],
        ),
        (
            "\"velocity\": \"reference\" }",
            "\"velocity\": \"reference\", \"perturbation\": {\"amplitude\": -1.0, \"seed\": 1} }",
            &["initial.perturbation.amplitude", "-1", "(0, L]"],
        ),
        (
            "\"velocity\": \"reference\" }",
            "\"velocity\": \"reference\", \"perturbation\": {\"amplitude\": 1e308, \"seed\": 1} }",
            &["initial.perturbation.amplitude", "(0, L]"],
        ),
        // A closed-form reference solves only its own data.
        (
            "\"displacement\": \"reference\"",
            "\"displacement\": {\"constant\": 0.3}",
            &["initial.displacement", "signorini-dirichlet", "0.5 at x = 0"],
        ),
        (
            "\"displacement\": \"reference\"",
            "\"displacement\": {\"constant\": 2.0}",
            &["initial.displacement", "signorini-dirichlet"],
        ),
        (
            AT_REST_FROM,
            "\"velocity\": {\"constant\": -1.0} },\n  \"horizon\": 3.0,\n  \"reference\": { \"exact\": \"at-rest\" }",
            &["initial.velocity", "at-rest", "0 at x = 0"],
        ),
        (
            AT_REST_FROM,
            "\"velocity\": {\"constant\": 1e3} },\n  \"horizon\": 3.0,\n  \"reference\": { \"exact\": \"at-rest\" }",
            &["initial.velocity", "at-rest"],
        ),
    ];
    for (from, to, needles) in edits {
        let s = edited_scene(&dir, from, to);
        expect_error(&run_args(&s, &[]), 2, needles);
    }
}

#[test]
fn initial_data_equal_to_the_references_are_accepted_and_run_as_the_reference() {
    let dir = scratch("reference-data");
    let s = edited_scene(
        &dir,
        "\"initial\": { \"displacement\": \"reference\", \"velocity\": \"reference\" }",
        "\"initial\": { \"displacement\": {\"affine\": {\"at_start\": 0.5, \"at_end\": 0.0}}, \
         \"velocity\": {\"constant\": 0.0} }",
    );
    let given = success_stdout(&signorini(&run_args(&s, &[])));
    let reference = success_stdout(&signorini(&run_args(DIRICHLET, &[])));
    let errors = |out: &str| out.lines().skip(1).map(str::to_string).collect::<Vec<_>>();
    assert_eq!(errors(&given), errors(&reference));
}

#[test]
fn an_unwritable_output_is_a_failure_with_exit_1_and_no_file() {
    let dir = scratch("unwritable");
    let blocker = dir.join("file");
    std::fs::write(&blocker, "not a directory").unwrap();
    let out_dir = blocker.join("out").to_string_lossy().into_owned();
    expect_error(
        &run_args(DIRICHLET, &["--out", &out_dir]),
        1,
        &["cannot create", "out"],
    );
    assert!(!blocker.join("out").exists());
}

#[test]
fn a_diverging_run_is_a_failure_with_exit_1() {
    // Newmark(β = ¼, γ = 0.55) violates β ≥ (γ + ½)²/4: with the massless contact node the
    // scheme blows up (by step ~1270 whatever NX), and the run stops with a typed error
    // naming the step and the quantity.
    expect_error(
        &[
            "run",
            DIRICHLET,
            "--scheme",
            "newmark(beta=0.25,gamma=0.55)",
            "--mass",
            "redistributed",
            "--nx",
            "80",
        ],
        1,
        &["non-finite", "step"],
    );
}
