//! A commit that cannot be left half-done (issue 55 item 2), tried by fault injection at every
//! file operation of a command's commit (`SIGNORINI_COMMIT_FAULT`, see
//! `src/harness/files/fault.rs`): the process aborted there as SIGKILL would end it, or
//! the operation failed with "no space left on device". Three directories: a per-run one the
//! harness created (swapped whole), a per-run one the user made (written in place, its old run
//! files removed), and a shared one holding a file of the user's. After an abort, the directory
//! holds the old outputs whole or, once the next command into it has completed the journalled
//! commit, the new ones whole; after a full disk it holds one or the other at once; the user's
//! file is never touched, and the next run into the directory is never refused.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use signorini::harness::files::commit_journal::complete;
use signorini::harness::files::manifest::sha256_of;

use crate::watched::scratch;

/// The binary run with `args`, the fault injected at operation `fault` (`n:kill` or
/// `n:enospc`) when given.
fn signorini_with(args: &[&str], fault: Option<&str>) -> Output {
    let mut command = Command::new(env!("CARGO_BIN_EXE_signorini"));
    command
        .args(args)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .env("CI", "true");
    if let Some(fault) = fault {
        command.env("SIGNORINI_COMMIT_FAULT", fault);
    }
    command.output().unwrap()
}

/// Every file of `dir` (the manifest and the user's `notes.txt` left out) with its SHA-256.
fn files(dir: &Path) -> BTreeMap<String, String> {
    let mut found = BTreeMap::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for entry in std::fs::read_dir(&d).unwrap() {
            let path = entry.unwrap().path();
            let rel = path
                .strip_prefix(dir)
                .unwrap()
                .to_string_lossy()
                .into_owned();
            if path.is_dir() {
                stack.push(path);
            } else if rel != ".signorini-manifest.json" && rel != "notes.txt" {
                found.insert(rel, sha256_of(&path).unwrap());
            }
        }
    }
    found
}

/// The run files `dir`'s manifest lists with their SHA-256.
fn listed(dir: &Path) -> BTreeMap<String, String> {
    let text = std::fs::read_to_string(dir.join(".signorini-manifest.json")).unwrap();
    let manifest: serde_json::Value = serde_json::from_str(&text).unwrap();
    manifest["files"]
        .as_object()
        .unwrap()
        .iter()
        .map(|(k, v)| (k.clone(), v.as_str().unwrap().to_string()))
        .collect()
}

/// Asserts `dir` holds the old outputs `old` whole, or a whole set of outputs named as `new`'s
/// (a run's files carry its wall times, so the new bytes are the manifest's): every file listed
/// with its content, nothing unlisted, and the user's note as it was.
fn assert_whole(
    dir: &Path,
    old: &BTreeMap<String, String>,
    new: &BTreeMap<String, String>,
    at: &str,
) {
    let found = files(dir);
    let manifest = listed(dir);
    assert_eq!(found, manifest, "{at}: files and manifest differ");
    let names = |m: &BTreeMap<String, String>| m.keys().cloned().collect::<Vec<_>>();
    assert!(
        found == *old || names(&found) == names(new),
        "{at}: neither the old outputs {:?} nor the new {:?}: {:?}",
        names(old),
        names(new),
        names(&found)
    );
    if dir.join("notes.txt").exists() {
        assert_eq!(
            std::fs::read_to_string(dir.join("notes.txt")).unwrap(),
            "mine\n"
        );
    }
}

/// A scenario: how the directory is prepared with its old outputs, and the command that writes
/// the new ones.
struct Scenario {
    name: &'static str,
    prepare: fn(&Path),
    new: fn(&Path) -> Vec<String>,
}

fn run_args(dir: &Path, scheme: &str) -> Vec<String> {
    [
        "run",
        "scenes/bar1d-dirichlet.json",
        "--scheme",
        scheme,
        "--mass",
        "standard",
        "--nx",
        "10",
        "--out",
        &dir.to_string_lossy(),
    ]
    .map(str::to_string)
    .to_vec()
}

fn getfem_args(dir: &Path, run: &str) -> Vec<String> {
    let runs = dir.with_extension(format!("runs-{run}"));
    let _ = std::fs::create_dir_all(&runs);
    let source = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/getfem")
        .join(run);
    let _ = std::fs::copy(source, runs.join(run));
    [
        "getfem",
        "--runs",
        &runs.to_string_lossy(),
        "--out",
        &dir.to_string_lossy(),
    ]
    .map(str::to_string)
    .to_vec()
}

const OLD_DEMO: &str = "getfem_v0_b0.5_g0.5_m1_nx20.json.gz";
const NEW_DEMO: &str = "getfem_v1_b0.25_g0.5_e0_m1_nx20.json.gz";

fn ok(args: Vec<String>) {
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    let out = signorini_with(&args, None);
    assert!(
        out.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
}

const SCENARIOS: [Scenario; 3] = [
    Scenario {
        name: "swapped",
        prepare: |dir| ok(run_args(dir, "crank-nicolson")),
        new: |dir| run_args(dir, "backward-euler"),
    },
    Scenario {
        name: "in-place",
        prepare: |dir| {
            std::fs::create_dir_all(dir).unwrap();
            ok(run_args(dir, "crank-nicolson"));
        },
        new: |dir| run_args(dir, "backward-euler"),
    },
    Scenario {
        name: "shared",
        prepare: |dir| {
            std::fs::create_dir_all(dir).unwrap();
            std::fs::write(dir.join("notes.txt"), "mine\n").unwrap();
            ok(getfem_args(dir, OLD_DEMO));
        },
        new: |dir| getfem_args(dir, NEW_DEMO),
    },
];

/// `dir` afresh with the scenario's old outputs; their files.
fn fresh(scenario: &Scenario, dir: &Path) -> BTreeMap<String, String> {
    let _ = std::fs::remove_dir_all(dir);
    (scenario.prepare)(dir);
    files(dir)
}

/// The commit completed by the next command into `dir`, as its start does.
fn recover(dir: &Path) {
    let parent = dir.parent().unwrap();
    complete(parent, &dir.file_name().unwrap().to_os_string(), dir).unwrap();
}

#[test]
fn a_commit_cut_at_any_file_operation_leaves_old_or_new_outputs_whole() {
    let root = scratch("commit-faults", "all");
    for scenario in &SCENARIOS {
        let dir: PathBuf = root.join(scenario.name);
        let reference = root.join(format!("{}-reference", scenario.name));
        fresh(scenario, &reference);
        let args = (scenario.new)(&reference);
        ok(args);
        let new = files(&reference);
        let mut operations = 0;
        for n in 1.. {
            let old = fresh(scenario, &dir);
            let args = (scenario.new)(&dir);
            let args: Vec<&str> = args.iter().map(String::as_str).collect();
            let out = signorini_with(&args, Some(&format!("{n}:kill")));
            let at = format!("{}: killed at operation {n}", scenario.name);
            if out.status.success() {
                assert_eq!(
                    files(&dir).keys().collect::<Vec<_>>(),
                    new.keys().collect::<Vec<_>>(),
                    "{at}"
                );
                operations = n - 1;
                break;
            }
            assert_eq!(
                out.status.code(),
                None,
                "{at}: {}",
                String::from_utf8_lossy(&out.stderr)
            );
            recover(&dir);
            assert_whole(&dir, &old, &new, &at);
            let again = signorini_with(&args, None);
            assert!(
                again.status.success(),
                "{at}: the next run is refused: {}",
                String::from_utf8_lossy(&again.stderr)
            );
            assert_whole(
                &dir,
                &BTreeMap::new(),
                &new,
                &format!("{at}, then run again"),
            );
        }
        assert!(
            operations >= 6,
            "{}: {operations} operations",
            scenario.name
        );
        println!("{}: {operations} file operations, each cut", scenario.name);
        for n in 1..=operations {
            let old = fresh(scenario, &dir);
            let args = (scenario.new)(&dir);
            let args: Vec<&str> = args.iter().map(String::as_str).collect();
            let out = signorini_with(&args, Some(&format!("{n}:enospc")));
            let at = format!("{}: no space at operation {n}", scenario.name);
            assert_whole(&dir, &old, &new, &at);
            if !out.status.success() {
                assert!(
                    String::from_utf8_lossy(&out.stderr).contains("No space left on device"),
                    "{at}"
                );
            }
            let again = signorini_with(&args, None);
            assert!(
                again.status.success(),
                "{at}: the next run is refused: {}",
                String::from_utf8_lossy(&again.stderr)
            );
        }
    }
    let _ = std::fs::remove_dir_all(&root);
}
