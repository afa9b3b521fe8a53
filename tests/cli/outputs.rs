//! Output directories whole or absent (`harness::files::output_dir`): an interrupted run, two runs
//! into one `--out`, a run refused after start-up, an `--out` that is a file or holds the user's
//! files, a staging directory left by a killed process, a shared directory's other files.

use std::fs;
use std::os::unix::process::ExitStatusExt;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use rustix::process::{kill_process, Pid, Signal};

use crate::common::{expect_error, signorini, success_stdout};

/// The manifest of an output directory (`harness::files::manifest::MANIFEST`).
const MANIFEST: &str = ".signorini-manifest.json";

const DIRICHLET: &str = "scenes/bar1d-dirichlet.json";

/// A fresh scratch directory.
fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("signorini-outputs-{}-{name}", std::process::id()));
    let _ = fs::remove_dir_all(&dir);
    fs::create_dir_all(&dir).unwrap();
    dir
}

/// `run` of the Dirichlet scene with Crank–Nicolson at `nx` into `out`.
fn run_args(mass: &str, nx: &str, out: &Path) -> Vec<String> {
    [
        "run",
        DIRICHLET,
        "--scheme",
        "crank-nicolson",
        "--mass",
        mass,
        "--nx",
        nx,
        "--out",
        &out.to_string_lossy(),
    ]
    .map(String::from)
    .to_vec()
}

/// Starts the binary as `common::signorini` runs it, without waiting.
fn spawn(args: &[String]) -> Child {
    Command::new(env!("CARGO_BIN_EXE_signorini"))
        .args(args)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .env("CI", "true")
        .env("SIGNORINI_CACHE", crate::common::test_cache())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the binary starts")
}

/// The names in `dir`, sorted.
fn names(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = fs::read_dir(dir)
        .map(|d| {
            d.filter_map(|e| e.ok())
                .map(|e| e.file_name().to_string_lossy().into_owned())
                .collect()
        })
        .unwrap_or_default();
    v.sort();
    v
}

/// Asserts that `out` holds exactly one run's files, each complete and agreeing with
/// `run.json`: the histories' last values are the JSON's.
fn assert_whole(out: &Path) {
    let files = ["contact.csv", "energy.csv", "multiplier.csv", "run.json"];
    let mut expected = vec![MANIFEST.to_string()];
    expected.extend(files.map(String::from));
    assert_eq!(names(out), expected, "{}", out.display());
    let manifest: serde_json::Value =
        serde_json::from_str(&fs::read_to_string(out.join(MANIFEST)).unwrap()).unwrap();
    let listed: Vec<&str> = manifest["files"]
        .as_object()
        .unwrap()
        .keys()
        .map(String::as_str)
        .collect();
    assert_eq!(listed, files, "the manifest lists the run's files");
    let json: serde_json::Value =
        serde_json::from_str(&fs::read_to_string(out.join("run.json")).unwrap()).unwrap();
    let steps = json["steps"].as_u64().unwrap() as usize;
    let last = |file: &str, column: usize| -> f64 {
        let text = fs::read_to_string(out.join(file)).unwrap();
        assert_eq!(text.lines().count(), steps + 2, "{file}: header + samples");
        let line = text.lines().last().unwrap();
        line.split(',').nth(column).unwrap().parse().unwrap()
    };
    let history = |key: &str, field: &str| -> f64 {
        json[key][field]
            .as_array()
            .and_then(|a| a.last())
            .and_then(|v| v.as_f64())
            .unwrap()
    };
    assert_eq!(last("energy.csv", 1), history("energy_history", "energy"));
    assert_eq!(
        last("contact.csv", 1),
        history("contact_history", "displacement")
    );
    assert_eq!(
        last("multiplier.csv", 1),
        history("contact_history", "multiplier")
    );
}

/// Waits until `ready` holds (polling every millisecond) or the child has exited.
fn wait_for(child: &mut Child, ready: impl Fn() -> bool) {
    let start = Instant::now();
    while !ready() && child.try_wait().unwrap().is_none() {
        assert!(start.elapsed() < Duration::from_secs(120), "timed out");
        std::thread::sleep(Duration::from_millis(1));
    }
}

#[test]
fn an_interrupted_run_leaves_its_out_whole_or_absent() {
    // Each run is interrupted at one stage: while it computes (the staging directory exists),
    // as it starts writing (a first file in the staging directory), in the middle of writing
    // (a second one). Whatever the timing on a loaded machine, the directory is then absent,
    // or whole if the run committed first, and nothing else is left beside it.
    let stages: [(usize, Signal); 4] = [
        (0, Signal::INT),
        (1, Signal::INT),
        (2, Signal::INT),
        (1, Signal::TERM),
    ];
    for (k, (files, signal)) in stages.into_iter().enumerate() {
        let dir = scratch(&format!("interrupt-{k}"));
        let out = dir.join("out");
        let mut child = spawn(&run_args("standard", "640", &out));
        let staging = dir.join(format!(".out.staging-{}", child.id()));
        wait_for(&mut child, || {
            staging.is_dir() && names(&staging).len() >= files
        });
        let pid = Pid::from_child(&child);
        let _ = kill_process(pid, signal);
        let status = child.wait().unwrap();
        assert!(
            status.success() || status.signal() == Some(signal.as_raw()),
            "stage {k}: {status:?}"
        );
        // A signal that arrives during the commit waits for it: the run then ends by the
        // signal with its directory whole.
        if out.exists() {
            assert_whole(&out);
        }
        let left: Vec<String> = names(&dir).into_iter().filter(|n| n != "out").collect();
        assert!(left.is_empty(), "stage {k}: left behind {left:?}");
        fs::remove_dir_all(&dir).unwrap();
    }
}

#[test]
fn two_runs_into_one_out_do_not_mix() {
    // Different masses give different histories: a mix would show in `assert_whole`. The
    // second run either waits its turn (it started after the first finished) or is refused,
    // naming the directory and the other process.
    for trial in 0..3 {
        let dir = scratch(&format!("two-{trial}"));
        let out = dir.join("out");
        let mut a = spawn(&run_args("standard", "320", &out));
        let mut b = spawn(&run_args("redistributed", "320", &out));
        let (pa, pb) = (a.id(), b.id());
        let (sa, sb) = (a.wait().unwrap(), b.wait().unwrap());
        let stderr = |c: &mut Child| {
            let mut s = String::new();
            std::io::Read::read_to_string(c.stderr.as_mut().unwrap(), &mut s).unwrap();
            s
        };
        let (ea, eb) = (stderr(&mut a), stderr(&mut b));
        assert!(sa.success() || sb.success(), "{ea}\n{eb}");
        for (status, err, other) in [(sa, &ea, pb), (sb, &eb, pa)] {
            if !status.success() {
                assert_eq!(status.code(), Some(1), "{err}");
                assert!(
                    err.contains("being written by another signorini process")
                        && err.contains(&format!("(pid {other})"))
                        && err.contains(&out.to_string_lossy().into_owned()),
                    "{err}"
                );
            }
        }
        assert_whole(&out);
        assert_eq!(names(&dir), ["out"]);
        fs::remove_dir_all(&dir).unwrap();
    }
}

#[test]
fn a_run_refused_after_start_up_leaves_no_directory() {
    let dir = scratch("refused");
    let out = dir.join("a").join("b").join("out");
    for (nx, extra, field) in [("0", None, "nx"), ("10", Some("0"), "ratio")] {
        let mut args = run_args("standard", nx, &out);
        if let Some(ratio) = extra {
            args.extend(["--ratio".to_string(), ratio.to_string()]);
        }
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        expect_error(&args, 2, &[&format!("invalid {field} = 0")]);
        assert!(names(&dir).is_empty(), "{field}: left {:?}", names(&dir));
    }
    fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn an_out_that_is_a_file_or_holds_other_files_is_refused_with_exit_2() {
    let dir = scratch("refuse");
    let file = dir.join("file");
    fs::write(&file, "mine").unwrap();
    let args = run_args("standard", "10", &file);
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    let message = format!("--out {} is a file, not a directory", file.display());
    expect_error(&args, 2, &[&message]);
    assert_eq!(fs::read_to_string(&file).unwrap(), "mine");

    let out = dir.join("out");
    fs::create_dir(&out).unwrap();
    fs::write(out.join("notes.txt"), "mine").unwrap();
    let args = run_args("standard", "10", &out);
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    expect_error(&args, 2, &["holds notes.txt", "choose another directory"]);
    assert_eq!(names(&out), ["notes.txt"]);
    assert_eq!(names(&dir), ["file", "out"]);
    fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_new_run_replaces_an_earlier_one_whole_and_removes_what_a_killed_one_left() {
    // The earlier run wrote points.csv (a scene with observed points); the new one does not,
    // so points.csv goes with the earlier run's files. A killed run's staging directory (its
    // manifest shows signorini created it) is removed; a directory of the user's with a name
    // like it is kept.
    let dir = scratch("replace");
    let out = dir.join("out");
    let points = dir.join("points.json");
    let mut scene: serde_json::Value = serde_json::from_str(
        &fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join(DIRICHLET)).unwrap(),
    )
    .unwrap();
    scene["observables"]["points"] = serde_json::json!([0.5]);
    fs::write(&points, scene.to_string()).unwrap();
    let mut earlier = run_args("standard", "10", &out);
    earlier[1] = points.to_string_lossy().into_owned();
    let earlier: Vec<&str> = earlier.iter().map(String::as_str).collect();
    success_stdout(&signorini(&earlier));
    assert!(out.join("points.csv").is_file());
    let killed = dir.join(".out.staging-4000000");
    let staged_by_killed = run_args("standard", "10", &killed);
    let staged_by_killed: Vec<&str> = staged_by_killed.iter().map(String::as_str).collect();
    success_stdout(&signorini(&staged_by_killed));
    let users = dir.join(".out.staging-4000001");
    fs::create_dir(&users).unwrap();
    fs::write(users.join("notes.txt"), "mine").unwrap();
    fs::write(dir.join(".out.lock"), "4000000").unwrap();
    let args = run_args("standard", "10", &out);
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    success_stdout(&signorini(&args));
    assert_whole(&out);
    assert_eq!(names(&dir), [".out.staging-4000001", "out", "points.json"]);
    assert_eq!(fs::read_to_string(users.join("notes.txt")).unwrap(), "mine");
    fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_shared_directory_keeps_its_other_files() {
    // `figures` writes README.md and figures/ into a reports directory; with no data it draws
    // nothing, but the index is written and the directory's other files stay.
    let dir = scratch("shared");
    let reports = dir.join("reports");
    fs::create_dir(&reports).unwrap();
    fs::write(reports.join("tables.md"), "committed").unwrap();
    let r = reports.to_string_lossy().into_owned();
    success_stdout(&signorini(&["figures", "--out", &r]));
    assert_eq!(names(&reports), [MANIFEST, "README.md", "tables.md"]);
    assert_eq!(
        fs::read_to_string(reports.join("tables.md")).unwrap(),
        "committed"
    );
    assert_eq!(names(&dir), ["reports"]);
    fs::remove_dir_all(&dir).unwrap();
}

/// Every file under `dir` (relative name, content), sorted.
fn listing(dir: &Path) -> Vec<(PathBuf, Vec<u8>)> {
    let mut files = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for entry in fs::read_dir(&d).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                stack.push(path);
            } else {
                let rel = path.strip_prefix(dir).unwrap().to_path_buf();
                files.push((rel, fs::read(&path).unwrap()));
            }
        }
    }
    files.sort();
    files
}

#[test]
fn an_output_directory_holding_the_commands_inputs_is_refused_and_kept() {
    let dir = scratch("holds-inputs");
    // The harness's own run of the 2D bar at level 10, every step, into r10 ...
    let r10 = dir.join("r10");
    let r10s = r10.to_string_lossy().to_string();
    success_stdout(&signorini(&[
        "run",
        "scenes/bar2d.json",
        "--scheme",
        "crank-nicolson",
        "--mass",
        "standard",
        "--nx",
        "10",
        "--fields-every-step",
        "--out",
        &r10s,
    ]));
    let before = listing(&r10);
    assert!(before.len() > 40, "{} files", before.len());
    let pvd = before
        .iter()
        .find(|(name, _)| name.extension().is_some_and(|e| e == "pvd"))
        .map(|(name, _)| r10.join(name))
        .unwrap();
    // ... verified with `--out r10`: refused before the reference is computed, r10 untouched.
    expect_error(
        &[
            "verify",
            "scenes/bar2d.json",
            &pvd.to_string_lossy(),
            "--code",
            "mine",
            "--code-version",
            "1",
            "--out",
            &r10s,
        ],
        2,
        &[
            "--out",
            "which this command reads",
            "choose another directory",
        ],
    );
    assert!(listing(&r10) == before, "r10 changed");
    // `cluster-plan --out` into a directory holding the user's own cluster-plan.md: refused,
    // the user's file kept.
    let plan = dir.join("plan");
    fs::create_dir_all(&plan).unwrap();
    fs::write(plan.join("cluster-plan.md"), "my own notes\n").unwrap();
    let measured: Vec<String> = fs::read_dir("reports/cluster/measured")
        .unwrap()
        .map(|e| e.unwrap().path().to_string_lossy().to_string())
        .collect();
    let mut args = vec![
        "cluster-plan",
        "scenes/bar3d.json",
        "--level",
        "320",
        "--measured-cores",
        "2",
        "--out",
    ];
    let plans = plan.to_string_lossy().to_string();
    args.push(&plans);
    args.push("--measured");
    args.extend(measured.iter().map(String::as_str));
    expect_error(&args, 2, &["cluster-plan.md", "signorini did not write"]);
    assert_eq!(
        fs::read_to_string(plan.join("cluster-plan.md")).unwrap(),
        "my own notes\n"
    );
}

/// A measurement whose numbers cannot be one run's is refused by `cluster-plan`, naming the file
/// and the field (issue 55 item 4: negative seconds predicted −14.4 hours, zero steps printed
/// null).
#[test]
fn cluster_plan_refuses_a_measurement_that_cannot_be_a_run() {
    let dir = scratch("measurement");
    for (field, value, allowed) in [
        (
            "step_seconds",
            serde_json::json!(-19.4),
            "a finite number of seconds, at least 0",
        ),
        ("steps", serde_json::json!(0), "at least 1"),
        ("dofs", serde_json::json!(0), "at least 1"),
        (
            "contact_seconds",
            serde_json::json!(1e9),
            "at most step_seconds",
        ),
        ("peak_bytes", serde_json::json!([]), "one peak per rank"),
    ] {
        let mut measured: Vec<String> = Vec::new();
        for entry in fs::read_dir("reports/cluster/measured").unwrap() {
            let path = entry.unwrap().path();
            let copy = dir.join(path.file_name().unwrap());
            let mut json: serde_json::Value =
                serde_json::from_str(&fs::read_to_string(&path).unwrap()).unwrap();
            if path.ends_with("160-ranks1-threads1-run1.json") {
                json[field] = value.clone();
            }
            fs::write(&copy, json.to_string()).unwrap();
            measured.push(copy.to_string_lossy().into_owned());
        }
        let mut args = vec![
            "cluster-plan",
            "scenes/bar3d.json",
            "--level",
            "320",
            "--measured-cores",
            "2",
            "--measured",
        ];
        args.extend(measured.iter().map(String::as_str));
        let out = dir.join("out");
        let out = out.to_string_lossy();
        args.extend(["--out", &out]);
        expect_error(
            &args,
            2,
            &[
                "160-ranks1-threads1-run1.json",
                &format!("{field} = "),
                allowed,
            ],
        );
    }
}
