//! The last hostile inputs of issue 55, each tried on the binary as a user would hand it over:
//! a box run file of 150 MB (refused at its limit in bounded memory), a forged shard without one
//! of its norms, a cached reference history cut short, and `rejudge` on a study whose errors are
//! shorter than its levels or whose oscillation indicator is negative. Each exits non-zero naming
//! the file, the field and the value, never panics, and leaves the user's files as they were.

use std::fs;
use std::io::Write as _;
use std::path::{Path, PathBuf};

use serde_json::Value;
use sha2::{Digest, Sha256};
use signorini::harness::study::shard::{codec, ShardFile};

use crate::watched::{scratch, watched};

/// The slowest any of these runs may take.
const SECONDS: u64 = 20;

/// Every file under `dir` (recursively) with its bytes.
fn contents(dir: &Path) -> Vec<(PathBuf, Vec<u8>)> {
    let mut files = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(at) = stack.pop() {
        for entry in fs::read_dir(&at).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                stack.push(path);
            } else {
                let bytes = fs::read(&path).unwrap();
                files.push((path, bytes));
            }
        }
    }
    files.sort();
    files
}

/// `args` run from the repository root, watched under `peak_kb`: exits `code` with every needle
/// in its stderr, and every file under `dir` as it was. Its stderr.
fn refused(dir: &Path, args: &[&str], peak_kb: u64, code: i32, needles: &[&str]) -> String {
    let before = contents(dir);
    let out = watched(args, None, SECONDS, peak_kb);
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    assert_eq!(out.status.code(), Some(code), "{args:?}: {stderr}");
    for needle in needles {
        assert!(stderr.contains(needle), "{needle:?} not in {stderr}");
    }
    assert!(
        contents(dir) == before,
        "{args:?} changed the files under {dir:?}"
    );
    stderr
}

/// `p` as a command-line argument.
fn arg(p: &Path) -> String {
    p.to_string_lossy().into_owned()
}

#[test]
fn a_box_run_file_of_150_mb_is_refused_at_its_limit_in_bounded_memory() {
    let dir = scratch("round4", "box150");
    let head = r#"{"format":"signorini-external/2","scene":"bar2d","code":{"name":"x","version":"1"},"label":"x","mesh":{"lengths":[0.1,1.0],"elements":[1,10],"node_order":"x1-fastest"},"samples":[{"time":0.0,"displacement":["#;
    // Rows of two, of one and of none: 25, 37 and 50 M rows, counted before they are held.
    for row in ["[0,0],", "[0],", "[],"] {
        let path = dir.join("run.json");
        let mut file = std::io::BufWriter::new(fs::File::create(&path).unwrap());
        file.write_all(head.as_bytes()).unwrap();
        let chunk = row.repeat(100_000);
        for _ in 0..150_000_000 / chunk.len() {
            file.write_all(chunk.as_bytes()).unwrap();
        }
        file.write_all(b"[0,0]]}]}").unwrap();
        drop(file);
        refused(
            &dir,
            &["verify", "scenes/bar2d.json", &arg(&path)],
            768 * 1024,
            2,
            &[
                "run.json",
                "more than 16777216 numbers",
                "the most a run file may hold",
            ],
        );
    }
    fs::remove_dir_all(dir).unwrap();
}

/// The one shard of a 1/1-sharded small study, written under `dir`: its file.
fn one_shard(dir: &Path) -> PathBuf {
    let out = dir.join("s");
    let status = watched(
        &[
            "study",
            "scenes/bar1d-dirichlet.json",
            "--levels",
            "10,20",
            "--shard",
            "1/1",
            "--out",
            &arg(&out),
        ],
        None,
        SECONDS,
        u64::MAX,
    );
    assert!(status.status.success());
    out.join("shard-study-1-of-1.json")
}

/// `value` less every field named `name`, at any depth.
fn without(value: &mut Value, name: &str) {
    match value {
        Value::Object(map) => {
            map.remove(name);
            map.values_mut().for_each(|v| without(v, name));
        }
        Value::Array(items) => items.iter_mut().for_each(|v| without(v, name)),
        _ => {}
    }
}

/// The shard of `dir` with `u_Linf_H` taken out of the results of its first `jobs` jobs, sealed
/// with a checksum that matches (a forgery the checksum cannot catch).
fn forge_shard(dir: &Path, jobs: usize) -> PathBuf {
    let path = one_shard(dir);
    let mut file: ShardFile = serde_json::from_str(&fs::read_to_string(&path).unwrap()).unwrap();
    let count = file.results.len();
    for job in &mut file.results[..jobs.min(count)] {
        let mut result: Value = codec::read(&job.result).unwrap();
        without(&mut result, "u_Linf_H");
        job.result = codec::encode(&result).unwrap();
    }
    fs::write(&path, serde_json::to_string(&file.sealed()).unwrap()).unwrap();
    path
}

/// A shard without `u_Linf_H` in one result panicked in the fit (`rates.rs`); without it in
/// every result, the merge printed the study with that column gone and exit 0.
#[test]
fn a_forged_shard_without_a_norm_is_refused_naming_it() {
    for (name, jobs) in [("one", 1), ("every", usize::MAX)] {
        let dir = scratch("round4", &format!("shard-{name}"));
        let path = forge_shard(&dir, jobs);
        refused(
            &dir,
            &["merge", &arg(&path)],
            256 * 1024,
            2,
            &[
                "result of crank-nicolson/standard at level 10",
                "holds errors = [u_L2_H, u_Linf_V",
                "the norms the study asks for, [u_Linf_H, u_L2_H",
            ],
        );
        fs::remove_dir_all(dir).unwrap();
    }
}

/// A shard whose level-10 result says `nx = 20` (its checksum matching) was tabulated as level
/// 20 twice; the merge refuses it naming both levels.
#[test]
fn a_forged_shard_result_of_another_level_is_refused() {
    let dir = scratch("round4", "shard-level");
    let path = one_shard(&dir);
    let mut file: ShardFile = serde_json::from_str(&fs::read_to_string(&path).unwrap()).unwrap();
    let mut result: Value = codec::read(&file.results[0].result).unwrap();
    assert_eq!(result["outcome"]["record"]["nx"], 10);
    result["outcome"]["record"]["nx"] = 20.into();
    file.results[0].result = codec::encode(&result).unwrap();
    fs::write(&path, serde_json::to_string(&file.sealed()).unwrap()).unwrap();
    refused(
        &dir,
        &["merge", &arg(&path)],
        256 * 1024,
        2,
        &["job 0", "a result of level 20 where the job's level is 10"],
    );
    fs::remove_dir_all(dir).unwrap();
}

/// `rejudge` of the committed 2D study whose oscillation indicators (the finest level's
/// multiplier variation ratio) were made negative, its manifest forged to match so that the
/// manifest's check lets it through: refused naming the field and the value (it turned a
/// finding into "fails" with exit 0), the study and its manifest kept.
#[test]
fn rejudge_refuses_a_negative_oscillation_indicator() {
    let dir = scratch("round4", "rejudge");
    let mut study: Value =
        serde_json::from_str(&fs::read_to_string("reports/elastic-2d.json").unwrap()).unwrap();
    let mut first = None;
    for case in study["study"]["cases"].as_array_mut().unwrap() {
        let last = case["levels"].as_array_mut().unwrap().last_mut().unwrap();
        let ratio = last["multiplier_variation_ratio"].as_f64().unwrap();
        first.get_or_insert(ratio);
        last["multiplier_variation_ratio"] = (-ratio).into();
    }
    let text = study.to_string();
    fs::write(dir.join("elastic-2d.json"), &text).unwrap();
    let manifest = serde_json::json!({
        "format": "signorini-manifest/1",
        "files": { "elastic-2d.json": format!("{:x}", Sha256::digest(text.as_bytes())) },
    });
    fs::write(dir.join(".signorini-manifest.json"), manifest.to_string()).unwrap();
    let value = format!("{}", -first.unwrap());
    refused(
        &dir,
        &["rejudge", "scenes/bar2d.json", "--out", &arg(&dir)],
        256 * 1024,
        2,
        &[
            "elastic-2d.json",
            "study.cases[0].levels[3].multiplier_variation_ratio",
            &value,
            "not negative",
        ],
    );
    fs::remove_dir_all(dir).unwrap();
}

/// `study` of the 2D bar on levels 1 and 2 against a reference on 8 elements cached in `cache`:
/// its stdout and stderr.
fn small_box_study(cache: &Path) -> (String, String) {
    let out = watched(
        &[
            "study",
            "scenes/bar2d.json",
            "--levels",
            "1,2",
            "--reference-level",
            "8",
            "--cache",
            &arg(cache),
        ],
        None,
        SECONDS,
        u64::MAX,
    );
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(out.status.success(), "{stderr}");
    (String::from_utf8_lossy(&out.stdout).into_owned(), stderr)
}

/// A cached reference whose histories were cut to three samples that still run evenly from 0 to
/// the horizon (the first, the middle and the last), with a valid checksum (written through the
/// cache's own `save`): stale, recomputed and said. It was read as the whole run, each step of
/// the study's levels compared with the reference's sample of the same index.
#[test]
fn a_cached_history_cut_to_three_samples_spanning_the_horizon_is_stale() {
    use signorini::harness::reference::fine_mesh::cache::{load, save, CacheLookup};
    let dir = scratch("round4", "cache");
    let cache = dir.join("cache");
    let tables = |s: &str| {
        s.lines()
            .filter(|l| l.starts_with('|'))
            .collect::<Vec<_>>()
            .join("\n")
    };
    let (fresh, _) = small_box_study(&cache);
    let stem = fs::read_dir(&cache)
        .unwrap()
        .map(|e| e.unwrap().path())
        .find(|p| p.extension().is_some_and(|e| e == "json"))
        .and_then(|p| p.file_stem().map(|s| s.to_string_lossy().into_owned()))
        .unwrap();
    let json: Value =
        serde_json::from_str(&fs::read_to_string(cache.join(format!("{stem}.json"))).unwrap())
            .unwrap();
    let key = serde_json::from_value(json["key"].clone()).unwrap();
    let CacheLookup::Hit(mut cached) = load(&cache, &stem, &key).unwrap() else {
        panic!("the fresh cache is not found");
    };
    let h = &mut cached.histories;
    let n = h.time.len();
    assert!(n > 3 && n % 2 == 1, "{n} samples");
    for series in [
        &mut h.time,
        &mut h.energy,
        &mut h.total_force,
        &mut h.centre_displacement,
        &mut h.centre_multiplier,
    ] {
        *series = vec![series[0], series[n / 2], series[n - 1]];
    }
    save((&cached.histories, &cached.projections), &cache, &stem).unwrap();
    let (again, stderr) = small_box_study(&cache);
    let said = format!(
        "time has 3 samples where level 2, the finest projected, has {} steps",
        n - 1
    );
    assert!(
        stderr.contains("is stale") && stderr.contains(&said),
        "{stderr}"
    );
    assert_eq!(tables(&again), tables(&fresh), "recomputed alike");
    fs::remove_dir_all(dir).unwrap();
}

/// A displacement of 1e308 at one interior node of a ParaView snapshot, 2D and 3D: every error
/// was `inf` with exit 0 (NaN was refused, 1e308 is finite); refused naming the file, the
/// point and the value, beyond the stated largest magnitude.
#[test]
fn a_displacement_of_1e308_at_one_node_is_refused_in_2d_and_3d() {
    use base64::Engine as _;
    let b64 = base64::engine::general_purpose::STANDARD;
    for scene in ["bar2d", "bar3d"] {
        let dir = scratch("round4", &format!("huge-{scene}"));
        let scene_path =
            crate::verify_box::scene_at_levels(&dir, &format!("scenes/{scene}.json"), &[5, 10]);
        let run = dir.join("run");
        let ran = watched(
            &[
                "run",
                &arg(&scene_path),
                "--scheme",
                "crank-nicolson",
                "--mass",
                "standard",
                "--nx",
                "5",
                "--out",
                &arg(&run),
                "--fields-every-step",
            ],
            None,
            SECONDS,
            u64::MAX,
        );
        assert!(ran.status.success());
        let field = run.join("field-t0.00.vtu");
        let text = fs::read_to_string(&field).unwrap();
        let name = text.find("Name=\"displacement\"").unwrap();
        let start = name + text[name..].find('>').unwrap() + 1;
        let end = start + text[start..].find('<').unwrap();
        let mut bytes = b64.decode(&text[start..end]).unwrap();
        // The UInt64 header, then Float64 values: value 31 is a component of an interior node.
        bytes[8 + 31 * 8..8 + 32 * 8].copy_from_slice(&1e308f64.to_le_bytes());
        let edited = format!("{}{}{}", &text[..start], b64.encode(&bytes), &text[end..]);
        fs::write(&field, edited).unwrap();
        refused(
            &dir,
            &[
                "verify",
                &arg(&scene_path),
                &arg(&run.join("fields.pvd")),
                "--code",
                "hostile",
                "--code-version",
                "0",
                "--cache",
                &arg(&dir.join("cache")),
            ],
            256 * 1024,
            2,
            &[
                "field-t0.00.vtu",
                "PointData \"displacement\" = 1e308",
                "magnitude at most 1e100",
            ],
        );
        fs::remove_dir_all(dir).unwrap();
    }
}

/// The box JSON form holds the same bound: GetFEM's level-10 run of the 2D bar as `getfem-box`
/// writes it, one sample's energy made 1e300, is refused naming the sample and the value.
#[test]
fn a_box_json_value_beyond_1e100_is_refused_naming_the_sample() {
    let dir = scratch("round4", "huge-json");
    let converted = dir.join("runs");
    let ran = watched(
        &[
            "getfem-box",
            "--out",
            &arg(&converted),
            "tests/data/getfem2d/getfem2d_crank-nicolson_standard_nx10.json.gz",
        ],
        None,
        SECONDS,
        u64::MAX,
    );
    assert!(ran.status.success());
    let path = fs::read_dir(&converted)
        .unwrap()
        .map(|e| e.unwrap().path())
        .find(|p| p.extension().is_some_and(|e| e == "json"))
        .unwrap();
    let mut run: Value = serde_json::from_str(&fs::read_to_string(&path).unwrap()).unwrap();
    run["samples"][2]["energy"] = 1e300.into();
    fs::write(&path, run.to_string()).unwrap();
    refused(
        &dir,
        &["verify", "scenes/bar2d.json", &arg(&path)],
        256 * 1024,
        2,
        &[
            "invalid samples",
            "samples[2]",
            "1e300",
            "magnitude at most 1e100",
        ],
    );
    fs::remove_dir_all(dir).unwrap();
}
