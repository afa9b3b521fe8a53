//! `signorini getfem`: the report of GetFEM's runs solved again, and the runs exported as
//! external-run files that `signorini verify` reads like any other code's.

use crate::common;

#[test]
fn getfem_writes_its_report_and_exports_runs_that_verify() {
    let dir = std::env::temp_dir().join(format!("signorini-getfem-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let runs = dir.join("runs");
    let out = common::signorini(&[
        "getfem",
        "--out",
        dir.to_str().unwrap(),
        "--export",
        runs.to_str().unwrap(),
    ]);
    let stdout = common::success_stdout(&out);
    assert!(stdout.contains("wrote 51 external-run files"), "{stdout}");
    assert!(
        stdout.contains("every run is within its class (52 runs)"),
        "{stdout}"
    );
    let report = std::fs::read_to_string(dir.join("getfem.md")).unwrap();
    let rows: Vec<&str> = report
        .lines()
        .filter(|l| l.starts_with("| `getfem_v"))
        .collect();
    // The per-norm rows of the chaotic runs against the ensemble: the ensemble's ranges
    // `[min, max]`, the last cell how far outside the range with the per-step members GetFEM's
    // norm lies (`—`: inside).
    let per_norm: Vec<&&str> = rows.iter().filter(|l| l.contains(" | [")).collect();
    assert!(
        !per_norm.is_empty(),
        "the chaotic runs' norms against the ensemble"
    );
    for l in &per_norm {
        let cells: Vec<&str> = l.trim_end_matches(" |").rsplit(" | ").take(2).collect();
        assert_eq!(
            cells[1] == "yes",
            cells[0] == "—",
            "a norm inside the ensemble's range, or how far outside it: {l}"
        );
    }
    assert_eq!(
        rows.len() - per_norm.len(),
        2 * 52 + 26 + 8,
        "the two tables of the 52 runs, the norms of the 26 configurations, the 8 chaotic runs"
    );
    let judged = rows
        .iter()
        .filter(|l| l.ends_with("| agrees |") || l.ends_with("| undecided |"));
    assert_eq!(
        judged.count(),
        8,
        "no chaotic run disagrees with the ensemble"
    );
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("getfem.json")).unwrap()).unwrap();
    assert_eq!(json["outside_class"], 0);
    assert_eq!(json["runs"].as_array().unwrap().len(), 52);
    // The blown-up Nitsche run has no finite trace to export.
    assert!(!runs
        .join("getfem_v3_b0.25_g0.5_gN10_tN1_m1_nx40.csv")
        .exists());
    let series = ["nx20", "nx40"].map(|nx| {
        runs.join(format!("getfem_v0_b0.5_g1_m1_{nx}.csv"))
            .to_string_lossy()
            .into_owned()
    });
    let verified_dir = dir.join("verified");
    let verified = common::signorini(&[
        "verify",
        "scenes/bar1d-dirichlet.json",
        &series[0],
        &series[1],
        "--out",
        verified_dir.to_str().unwrap(),
    ]);
    let stdout = common::success_stdout(&verified);
    assert!(stdout.contains("getfem_v0_b0.5_g1_m1"), "{stdout}");
    assert!(
        stdout.contains("not computed"),
        "a contact trace has no field: {stdout}"
    );
    // Version 2: the demo's configuration declared as the harness names it, no stress at
    // t = 0, the demo's energy beside the norms.
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(verified_dir.join("verify.json")).unwrap())
            .unwrap();
    let s = &json["series"][0];
    assert_eq!(
        s["declared"],
        serde_json::json!({
            "scheme": "newmark-1",
            "mass": "getfem-redistributed",
            "contact": "multiplier",
        })
    );
    let notes = s["notes"].as_array().unwrap();
    assert!(
        notes.len() == 2
            && notes
                .iter()
                .all(|n| n.as_str().unwrap().contains("(t = 0)")),
        "{notes:?}"
    );
    let energies = s["reported_energy"].as_array().unwrap();
    assert_eq!(energies.len(), 2);
    assert!(energies
        .iter()
        .all(|e| e["definition"] == "total-at-sample" && e["linf"].as_f64().unwrap() > 0.0));
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A run outside its class is flagged: a round-off reproducible run (Newmark (½, 1) with the
/// demo's redistributed mass at NX = 20) whose stored contact displacement is moved on purpose
/// by 1e-6 at one step, a hundred times the class's threshold, is outside its class in
/// `getfem.md`, in `getfem.json` and in what the command says; the file as GetFEM wrote it is
/// within.
#[test]
fn getfem_flags_a_run_outside_its_class() {
    let dir = std::env::temp_dir().join(format!("signorini-getfem-class-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let runs = dir.join("runs");
    std::fs::create_dir_all(&runs).unwrap();
    let name = "getfem_v0_b0.5_g1_m1_nx20.json.gz";
    let mut text = String::new();
    std::io::Read::read_to_string(
        &mut flate2::read::GzDecoder::new(
            std::fs::File::open(std::path::Path::new("tests/data/getfem").join(name)).unwrap(),
        ),
        &mut text,
    )
    .unwrap();
    let original: serde_json::Value = serde_json::from_str(&text).unwrap();
    let write = |value: &serde_json::Value| {
        let file = std::fs::File::create(runs.join(name)).unwrap();
        let mut gz = flate2::write::GzEncoder::new(file, flate2::Compression::fast());
        std::io::Write::write_all(&mut gz, value.to_string().as_bytes()).unwrap();
        gz.finish().unwrap();
    };
    let getfem = |out: &std::path::Path| {
        let run = common::signorini(&[
            "getfem",
            "--runs",
            runs.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ]);
        let stdout = common::success_stdout(&run);
        let json: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(out.join("getfem.json")).unwrap())
                .unwrap();
        let report = std::fs::read_to_string(out.join("getfem.md")).unwrap();
        (stdout, json, report)
    };
    write(&original);
    let (stdout, json, report) = getfem(&dir.join("as-written"));
    assert!(
        stdout.contains("every run is within its class (1 runs)"),
        "{stdout}"
    );
    assert_eq!(json["runs"][0]["within_class"], true, "{json}");
    assert!(report.contains("All 1 runs are within their class."));
    let mut forged = original.clone();
    let u0 = &mut forged["arrays"]["store_u0"][300];
    *u0 = serde_json::json!(u0.as_f64().unwrap() + 1e-6);
    write(&forged);
    let (stdout, json, report) = getfem(&dir.join("forged"));
    assert!(
        stdout.contains("1 of 1 runs are outside their class")
            && stdout.contains(&format!("{name} (round-off): Δu 1.0e-6 > 1.0e-8")),
        "{stdout}"
    );
    assert_eq!(json["outside_class"], 1);
    let record = &json["runs"][0];
    assert_eq!(record["within_class"], false);
    assert_eq!(record["class"], "round-off");
    assert_eq!(record["misses"], serde_json::json!(["Δu 1.0e-6 > 1.0e-8"]));
    assert!(
        report.contains("**1 of 1 runs are outside their class**")
            && report.contains("| **outside**: Δu 1.0e-6 > 1.0e-8 |"),
        "{report}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}
