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
    let report = std::fs::read_to_string(dir.join("getfem.md")).unwrap();
    let rows: Vec<&str> = report
        .lines()
        .filter(|l| l.starts_with("| `getfem_v"))
        .collect();
    // The per-norm rows of the chaotic runs against the ensemble: the ensemble's ranges
    // `[min, max]`, the last cell whether GetFEM's norm is inside the range with the per-step
    // members.
    let per_norm: Vec<&&str> = rows.iter().filter(|l| l.contains(" | [")).collect();
    assert!(
        !per_norm.is_empty(),
        "the chaotic runs' norms against the ensemble"
    );
    assert!(
        per_norm.iter().all(|l| l.ends_with("| yes |")),
        "every chaotic run's norm inside the ensemble's range: {per_norm:?}"
    );
    assert_eq!(
        rows.len() - per_norm.len(),
        2 * 52 + 26 + 8,
        "the two tables of the 52 runs, the norms of the 26 configurations, the 8 chaotic runs"
    );
    let chaotic = rows.iter().filter(|l| l.ends_with("| agrees |"));
    assert_eq!(
        chaotic.count(),
        8,
        "every chaotic run agrees with the ensemble"
    );
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
