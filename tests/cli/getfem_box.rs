//! GetFEM's own runs of the 2D and 3D bars (tests/data/getfem2d, getfem3d), written in the box
//! form by `signorini getfem-box`, verify to the errors of the harness's own runs of the same
//! configurations within 1e-8 relative: both codes solve the same discrete problem (their
//! states agree to about 1e-13 at every step at these levels), so every error the verification
//! measures (the force norm at every step, the displacement errors at the stored steps, the
//! distance of the reported energy to the reference's) agrees to round-off.
//!
//! The harness's runs are given exactly what GetFEM's files give: the same file with the
//! harness's displacement, velocity, multipliers and energy put at the same steps.

use std::path::{Path, PathBuf};

use serde_json::Value;

use super::verify_box::{read_json, run_case_every_step, s, scene_at_levels, scratch};
use crate::common::{expect_error, signorini, success_stdout};
use signorini::harness::external::pvd::{read_collection, read_snapshot};

/// How far an error of GetFEM's run may be from the harness's, relative.
const AGREEMENT: f64 = 1e-8;

/// The box-form files `getfem-box` writes from `tests/data/getfem<d>d/` into `out`.
fn converted(dimension: usize, out: &Path) -> Vec<PathBuf> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let runs: Vec<PathBuf> = std::fs::read_dir(root.join(format!("tests/data/getfem{dimension}d")))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.to_string_lossy().ends_with(".json.gz"))
        .collect();
    assert_eq!(runs.len(), 8, "CN and BE × two masses × levels 10, 20");
    let mut args = vec!["getfem-box"];
    args.extend(runs.iter().map(|p| s(p)));
    args.extend(["--out", s(out)]);
    let stdout = success_stdout(&signorini(&args));
    let files: Vec<PathBuf> = stdout.lines().map(PathBuf::from).collect();
    assert_eq!(files.len(), 8, "{stdout}");
    files
}

/// The GetFEM file `getfem` with the harness's run of its configuration put at the steps where
/// it has values, written into `dir` under the label `signorini <label>`.
fn harness_twin(scene: &Path, getfem: &Path, dir: &Path) -> PathBuf {
    let mut file = read_json(getfem);
    let scheme = file["scheme"].as_str().unwrap().to_string();
    let mass = file["mass"].as_str().unwrap().to_string();
    let level = file["mesh"]["elements"].as_array().unwrap().last().unwrap();
    let level = level.as_u64().unwrap() as usize;
    let stem = getfem.file_stem().unwrap().to_string_lossy().into_owned();
    let run_dir = dir.join(format!("run-{stem}"));
    let pvd = run_case_every_step(scene, &scheme, &mass, level, &run_dir);
    let energy: Vec<f64> = std::fs::read_to_string(run_dir.join("energy.csv"))
        .unwrap()
        .lines()
        .skip(1)
        .map(|l| l.split(',').nth(1).unwrap().parse().unwrap())
        .collect();
    let d = file["mesh"]["lengths"].as_array().unwrap().len();
    let entries = read_collection(&pvd).unwrap();
    let samples = file["samples"].as_array_mut().unwrap();
    assert_eq!(samples.len(), entries.len(), "{stem}: one sample per step");
    assert_eq!(samples.len(), energy.len(), "{stem}: one energy per step");
    for ((sample, entry), e) in samples.iter_mut().zip(&entries).zip(energy) {
        let snapshot = read_snapshot(&entry.file).unwrap();
        let nodal = |name: &str| -> Value {
            let values = &snapshot.array(name).unwrap().values;
            serde_json::json!(values
                .chunks(3)
                .map(|c| c[..d].to_vec())
                .collect::<Vec<_>>())
        };
        let contact = sample["multipliers"].as_array().unwrap().len();
        let multipliers = &snapshot.array("contact_multiplier").unwrap().values;
        sample["multipliers"] = serde_json::json!(multipliers[..contact]);
        sample["energy"] = serde_json::json!(e);
        for field in ["displacement", "velocity"] {
            if !sample[field].is_null() {
                sample[field] = nodal(field);
            }
        }
    }
    file["code"] = serde_json::json!({"name": "signorini", "version": "test"});
    let label = format!("signorini {scheme}, {mass}");
    file["label"] = serde_json::json!(label);
    let path = dir.join(format!("signorini-{stem}.json"));
    std::fs::write(&path, file.to_string()).unwrap();
    path
}

/// Every error of a verify.json's run `file` (by file name) as `(what, value)`: the force norm of
/// its series at its level, its displacement errors at the stored steps, its reported energy's
/// distances.
fn run_errors(verified: &Value, file: &Path) -> Vec<(String, f64)> {
    let name = file.display().to_string();
    let mut out = Vec::new();
    for series in verified["series"].as_array().unwrap() {
        let runs = series["runs"].as_array().unwrap();
        let Some(k) = runs.iter().position(|r| r["file"] == name.as_str()) else {
            continue;
        };
        for rate in series["rates"].as_array().unwrap() {
            let norm = rate["norm"].as_str().unwrap();
            out.push((norm.to_string(), rate["errors"][k].as_f64().unwrap()));
        }
        for e in runs[k]["displacement_at_samples"].as_array().unwrap() {
            let t = e["time"].as_f64().unwrap();
            out.push((format!("H at t = {t}"), e["h"].as_f64().unwrap()));
            out.push((format!("V at t = {t}"), e["v"].as_f64().unwrap()));
        }
    }
    for e in verified["reported_energy"].as_array().unwrap() {
        if e["file"] == name.as_str() {
            out.push(("reported energy L∞".into(), e["linf"].as_f64().unwrap()));
            out.push(("reported energy L²".into(), e["l2"].as_f64().unwrap()));
        }
    }
    out
}

fn getfem_runs_agree_with_the_harness(dimension: usize) {
    let dir = scratch(&format!("getfem-{dimension}d"));
    let scene = scene_at_levels(&dir, &format!("scenes/bar{dimension}d.json"), &[10, 20]);
    let getfem = converted(dimension, &dir.join("getfem"));
    let twins: Vec<PathBuf> = getfem
        .iter()
        .map(|g| harness_twin(&scene, g, &dir))
        .collect();
    let out = dir.join("verify");
    let mut args = vec!["verify", s(&scene)];
    args.extend(getfem.iter().chain(&twins).map(|p| s(p)));
    let cache = dir.join("references");
    args.extend(["--cache", s(&cache), "--out", s(&out)]);
    success_stdout(&signorini(&args));
    let verified = read_json(&out.join("verify.json"));
    for (g, h) in getfem.iter().zip(&twins) {
        let (theirs, ours) = (run_errors(&verified, g), run_errors(&verified, h));
        let whats: Vec<&str> = ours.iter().map(|(w, _)| w.as_str()).collect();
        assert!(
            whats.contains(&"lambda_L2")
                && whats.iter().any(|w| w.starts_with("H at"))
                && whats.contains(&"reported energy L∞"),
            "{}: the force norm, the stored steps' errors and the energy: {whats:?}",
            g.display()
        );
        assert_eq!(theirs.len(), ours.len(), "{}", g.display());
        for ((what, a), (what_ours, b)) in theirs.iter().zip(&ours) {
            assert_eq!(what, what_ours);
            assert!(
                (a - b).abs() <= AGREEMENT * b.abs(),
                "{} {what}: GetFEM {a:e}, the harness {b:e} (relative {:e})",
                g.display(),
                (a - b).abs() / b.abs()
            );
        }
    }
}

#[test]
fn getfem_2d_runs_verify_to_the_errors_of_the_harness_runs() {
    getfem_runs_agree_with_the_harness(2);
}

#[test]
fn getfem_3d_runs_verify_to_the_errors_of_the_harness_runs() {
    getfem_runs_agree_with_the_harness(3);
}

/// A file that is not one of GetFEM's box runs is refused with exit code 2, naming it.
#[test]
fn a_file_that_is_not_a_getfem_box_run_is_refused() {
    let dir = scratch("getfem-box-refused");
    let plain = dir.join("plain.json.gz");
    std::fs::write(&plain, b"not gzip").unwrap();
    expect_error(
        &["getfem-box", s(&plain), "--out", s(&dir.join("out"))],
        2,
        &["plain.json.gz", "gzipped JSON"],
    );
    assert!(!dir.join("out").exists(), "nothing is written");
}
