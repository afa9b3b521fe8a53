//! `--shard k/n` and `signorini merge`: the merge of a study's (or a sensitivity ensemble's, or the
//! stability suite's) shards prints or writes what the unsharded command does, byte for byte but
//! for the wall-clock fields (a 1D study's last markdown line, `wall_seconds` and each level's
//! `timings` in its JSON; the time in `sensitivity.md` and `wall_seconds` in `sensitivity.json`; a
//! box study's wall and run times); and every wrong set of shards or `--shard` value is a usage
//! error (exit 2) that names what is wrong.

use crate::{common, timings};

use std::path::{Path, PathBuf};

use signorini::engine::fem::MassVariant;
use signorini::harness::study::scene::Scene;
use signorini::harness::study::Case;

use common::{expect_error, signorini, success_stdout};
use timings::{assert_same_files_less_timings, without_timing_fields};

const DIRICHLET: &str = "scenes/bar1d-dirichlet.json";

const GRAVITY: &str = "scenes/bar1d-gravity.json";

/// A small, fast study: every paper case on three levels.
const LEVELS: [&str; 2] = ["--levels", "10,20,40"];

/// An empty scratch directory of this test process named after `name`: its path.
fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("signorini-shards-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// `p` as a command-line argument.
fn text(p: &Path) -> String {
    p.to_string_lossy().into_owned()
}

/// Runs shard `k` of `n` of `signorini <command>` (`command[0]` the subcommand) into
/// `dir/s<k>` and returns its file.
fn shard_of(dir: &Path, command: &[&str], k: usize, n: usize) -> String {
    let out = dir.join(format!("s{k}"));
    let spec = format!("{k}/{n}");
    let out_text = text(&out);
    let mut args = command.to_vec();
    args.extend(["--shard", &spec, "--out", &out_text]);
    let stdout = success_stdout(&signorini(&args));
    assert!(stdout.contains(&format!("shard {spec}")), "{stdout}");
    text(&out.join(format!("shard-{}-{k}-of-{n}.json", command[0])))
}

/// Runs shard `k` of `n` of `study <scene> <extra>` into `dir/s<k>` and returns its file.
fn shard(dir: &Path, scene: &str, extra: &[&str], k: usize, n: usize) -> String {
    let mut command = vec!["study", scene];
    command.extend_from_slice(extra);
    shard_of(dir, &command, k, n)
}

/// The stdout of `merge` of `files`.
fn merged(files: &[String]) -> String {
    let mut args = vec!["merge"];
    args.extend(files.iter().map(String::as_str));
    success_stdout(&signorini(&args))
}

/// `json` less its wall-clock fields.
fn without_timings(json: &str) -> serde_json::Value {
    let mut v: serde_json::Value = serde_json::from_str(json).unwrap();
    v.as_object_mut().unwrap().remove("wall_seconds").unwrap();
    for case in v["cases"].as_array_mut().unwrap() {
        for level in case["levels"].as_array_mut().unwrap() {
            level.as_object_mut().unwrap().remove("timings").unwrap();
        }
    }
    v
}

#[test]
fn the_merge_of_three_shards_prints_the_unsharded_study() {
    let dir = scratch("1d");
    let full = success_stdout(&signorini(&["study", DIRICHLET, LEVELS[0], LEVELS[1]]));
    let files: Vec<String> = (1..=3)
        .map(|k| shard(&dir, DIRICHLET, &LEVELS, k, 3))
        .collect();
    let merged_md = merged(&files);
    let (full_tables, full_wall) = full.trim_end().rsplit_once('\n').unwrap();
    let (merged_tables, merged_wall) = merged_md.trim_end().rsplit_once('\n').unwrap();
    assert_eq!(merged_tables, full_tables);
    let summary = |line: &str| line.split(", ").next().unwrap().to_string();
    assert_eq!(summary(merged_wall), summary(full_wall));
    assert!(full_wall.ends_with(" s wall"), "{full_wall}");

    let json_args = [LEVELS[0], LEVELS[1], "--json"];
    let full = success_stdout(&signorini(&[
        "study",
        DIRICHLET,
        json_args[0],
        json_args[1],
        "--json",
    ]));
    let files: Vec<String> = (1..=3)
        .map(|k| shard(&dir.join("json"), DIRICHLET, &json_args, k, 3))
        .collect();
    // The shards in another order: the merge puts the jobs back in job order.
    let reversed: Vec<String> = files.iter().rev().cloned().collect();
    assert_eq!(without_timings(&merged(&reversed)), without_timings(&full));
}

#[test]
fn the_merge_of_three_shards_of_a_gravity_study_prints_the_unsharded_json() {
    let dir = scratch("gravity");
    // Two schemes of two families (Newmark, Paoli–Schatzman) under the body force.
    let args = [
        LEVELS[0],
        LEVELS[1],
        "--scheme",
        "crank-nicolson",
        "--scheme",
        "paoli-schatzman-e0.5",
        "--json",
    ];
    let mut unsharded = vec!["study", GRAVITY];
    unsharded.extend(args);
    let full = success_stdout(&signorini(&unsharded));
    let files: Vec<String> = (1..=3).map(|k| shard(&dir, GRAVITY, &args, k, 3)).collect();
    assert_eq!(without_timings(&merged(&files)), without_timings(&full));
}

/// Runs `command` (one that writes a reports directory into `--out`) into `dir/unsharded`,
/// then as three shards merged into `dir/merged`, and asserts that the merge wrote the same
/// files less their wall-clock figures; returns how many.
fn merge_writes_the_unsharded_files(dir: &Path, command: &[&str]) -> usize {
    let (out, kept) = (text(&dir.join("merged")), text(&dir.join("unsharded")));
    let mut unsharded = command.to_vec();
    unsharded.extend(["--out", &kept]);
    success_stdout(&signorini(&unsharded));
    let files: Vec<String> = (1..=3).map(|k| shard_of(dir, command, k, 3)).collect();
    let mut args = vec!["merge", "--out", &out];
    args.extend(files.iter().map(String::as_str));
    success_stdout(&signorini(&args));
    assert_same_files_less_timings(Path::new(&out), Path::new(&kept))
}

/// bar1d-dirichlet.json on levels 20, 40 and 80 (instead of 10 to 640), in `dir`: its path.
/// Level 80 is the one whose parting step and separation growth `sensitivity.md` shows.
fn small_dirichlet_scene(dir: &Path) -> String {
    let scene =
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join(DIRICHLET)).unwrap();
    let levels = "\"levels\": [10, 20, 40, 80, 160, 320, 640]";
    assert!(
        scene.contains(levels),
        "bar1d-dirichlet.json has other levels"
    );
    let path = dir.join("bar1d-dirichlet-small.json");
    std::fs::write(&path, scene.replacen(levels, "\"levels\": [20, 40, 80]", 1)).unwrap();
    text(&path)
}

#[test]
fn the_merge_of_three_sensitivity_shards_writes_the_unsharded_reports() {
    let dir = scratch("sensitivity");
    let scene = small_dirichlet_scene(&dir);
    // The only wall-clock field of harness::study::sensitivity::Sensitivity is `wall_seconds` (the
    // unsharded run's time, the longest shard's in the merge), which sensitivity.json carries
    // and sensitivity.md prints as "Generated by `signorini sensitivity` in … s wall."; everything else
    // is computed from the members' results, which the shards carry bit for bit.
    let command = ["sensitivity", &scene, "--members", "2"];
    assert_eq!(merge_writes_the_unsharded_files(&dir, &command), 2);
}

#[test]
fn the_merge_of_three_stability_shards_writes_the_unsharded_reports() {
    let dir = scratch("stability");
    // stability.json and stability.md: every hard case × scheme × mass of the CI subset, each
    // run's record computed from its own run alone, which the shards carry bit for bit.
    let command = ["stability", "--ci-subset"];
    assert_eq!(merge_writes_the_unsharded_files(&dir, &command), 2);
}

/// `signorini report` whole (the gravity benchmark, Tables 1–2 with their sensitivity, the
/// longer horizon, the implicit start and the histories, the extended table): its merge writes
/// every file the unsharded command does (26: its own sections' data and pages, not the pages
/// the render step builds), but for the wall-clock figures and the work–precision data made of
/// the runs' times. 47 minutes on a shared 2-core machine: `make
/// test-report-shards`.
#[test]
#[ignore = "the whole report, twice: make test-report-shards"]
fn the_merge_of_three_report_shards_writes_the_unsharded_reports() {
    let dir = scratch("report");
    assert_eq!(merge_writes_the_unsharded_files(&dir, &["report"]), 26);
}

/// `signorini experiment` (the Tables 1–2 study at three horizons): its merge writes
/// `defaults-experiment.md` byte for byte. A few minutes on 2 cores: `make test-report-shards`.
#[test]
#[ignore = "three Tables 1–2 studies, twice: make test-report-shards"]
fn the_merge_of_three_experiment_shards_writes_the_unsharded_report() {
    let dir = scratch("experiment");
    assert_eq!(merge_writes_the_unsharded_files(&dir, &["experiment"]), 1);
}

#[test]
fn bad_shard_values_are_usage_errors_naming_the_option() {
    let dir = scratch("values");
    let out = text(&dir.join("out"));
    for bad in ["0/3", "4/3", "3", "a/b"] {
        expect_error(
            &["study", DIRICHLET, "--shard", bad, "--out", &out],
            2,
            &["--shard", "k/n", "1 <= k <= n"],
        );
    }
    expect_error(
        &["study", DIRICHLET, "--shard", "1/2"],
        2,
        &["--shard needs --out"],
    );
    assert!(!dir.join("out").exists(), "a refused shard writes nothing");
}

#[test]
fn merge_refuses_incomplete_or_foreign_shards() {
    let dir = scratch("refused");
    let s1 = shard(&dir, DIRICHLET, &LEVELS, 1, 3);
    let s3 = shard(&dir, DIRICHLET, &LEVELS, 3, 3);
    expect_error(&["merge", &s1, &s3], 2, &["missing shard 2/3"]);
    expect_error(
        &["merge", &s1, &s1, &s3],
        2,
        &["shard 1/3 is given more than once"],
    );
    let other = dir.join("other");
    let foreign = shard(&other, DIRICHLET, &["--levels", "10,20"], 2, 3);
    expect_error(
        &["merge", &s1, &foreign, &s3],
        2,
        &["different invocations", "arguments"],
    );
    let not_a_shard = text(&dir.join("s1"));
    expect_error(&["merge", &not_a_shard], 2, &["is a directory"]);
}

#[test]
fn merge_refuses_shards_of_a_scene_file_changed_since() {
    let dir = scratch("changed");
    let scene = dir.join("scene.json");
    let original =
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join(DIRICHLET)).unwrap();
    std::fs::write(&scene, &original).unwrap();
    let scene = text(&scene);
    let files: Vec<String> = (1..=2)
        .map(|k| shard(&dir, &scene, &LEVELS, k, 2))
        .collect();
    std::fs::write(&scene, original.replacen("3.0", "3.5", 1)).unwrap();
    expect_error(
        &["merge", &files[0], &files[1]],
        2,
        &["other inputs", &scene],
    );
}

/// `md` with its times masked: the study's wall time (`study wall time 0.1 s`) and the
/// ensemble's run time (`0.1 s of run time`).
fn without_wall_time(md: &str) -> String {
    let (head, tail) = md.split_once("study wall time ").unwrap();
    let (_, rest) = tail.split_once(" s ").unwrap();
    let masked = format!("{head}study wall time … s {rest}");
    let (head, tail) = masked.split_once(" s of run time").unwrap();
    let (head, _) = head.rsplit_once(' ').unwrap();
    format!("{head} … s of run time{tail}")
}

/// bar2d.json with a round-off ensemble of 2 members (instead of 16), on levels 10 and 20
/// against a reference on 80 elements, named `name`, in `dir`: its path.
fn small_box_scene(dir: &Path, name: &str) -> String {
    let scene =
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/bar2d.json"))
            .unwrap();
    let ensemble = "\"sensitivity\": { \"members\": 16, \"amplitude\": 1e-13 }";
    assert!(
        scene.contains(ensemble),
        "bar2d.json no longer has its ensemble"
    );
    let small = scene
        .replacen(
            ensemble,
            "\"sensitivity\": { \"members\": 2, \"amplitude\": 1e-13 }",
            1,
        )
        .replacen("\"name\": \"bar2d\"", &format!("\"name\": \"{name}\""), 1)
        .replacen("\"levels\": [10, 20, 40, 80]", "\"levels\": [10, 20]", 1)
        .replacen("\"reference_level\": 640", "\"reference_level\": 80", 1);
    let path = dir.join(format!("{name}.json"));
    std::fs::write(&path, small).unwrap();
    text(&path)
}

#[test]
fn the_merge_of_a_box_study_writes_the_unsharded_reports() {
    let dir = scratch("box");
    let scene = small_box_scene(&dir, "bar2d-small");
    let cache = text(&dir.join("refs"));
    let (out, kept) = (dir.join("out"), dir.join("unsharded"));
    let out_text = text(&out);
    let study = ["--cache", &cache];
    success_stdout(&signorini(&["reference", &scene, "--cache", &cache]));
    let mut full = vec!["study", &scene];
    full.extend(study);
    full.extend(["--out", &out_text]);
    success_stdout(&signorini(&full));
    std::fs::rename(&out, &kept).unwrap();
    let files: Vec<String> = (1..=3).map(|k| shard(&dir, &scene, &study, k, 3)).collect();
    let mut args = vec!["merge", "--out", &out_text];
    args.extend(files.iter().map(String::as_str));
    success_stdout(&signorini(&args));
    let read = |d: &Path, f: &str| std::fs::read_to_string(d.join(f)).unwrap();
    assert_eq!(
        read(&out, "data/elastic-2d-histories.json"),
        read(&kept, "data/elastic-2d-histories.json")
    );
    assert_eq!(
        without_wall_time(&read(&out, "elastic-2d.md")),
        without_wall_time(&read(&kept, "elastic-2d.md"))
    );
    let json = |d: &Path| {
        let mut v: serde_json::Value = serde_json::from_str(&read(d, "elastic-2d.json")).unwrap();
        without_timing_fields(&mut v);
        v
    };
    let merged = json(&out);
    assert_eq!(merged, json(&kept));
    let classes = merged["sensitivity"]["cases"].as_array().unwrap();
    let scene = Scene::load(Path::new(&scene)).unwrap();
    assert_eq!(
        classes.len(),
        Case::matrix(&scene.default_schemes(), &MassVariant::PAPER).len(),
        "the merge classifies every case's ensemble"
    );
}

#[test]
fn reference_shards_fill_one_cache_that_the_merge_reuses() {
    let dir = scratch("reference");
    let scenes = [
        small_box_scene(&dir, "box-a"),
        small_box_scene(&dir, "box-b"),
    ];
    // Another gap: another reference (the cache is keyed by the parameters, not the name).
    let b = std::fs::read_to_string(&scenes[1]).unwrap();
    assert!(b.contains("\"gap\": 0.2"));
    std::fs::write(&scenes[1], b.replacen("\"gap\": 0.2", "\"gap\": 0.25", 1)).unwrap();
    let cache = text(&dir.join("refs"));
    let files: Vec<String> = (1..=2)
        .map(|k| {
            let out = text(&dir.join(format!("s{k}")));
            let spec = format!("{k}/2");
            let stdout = success_stdout(&signorini(&[
                "reference",
                &scenes[0],
                &scenes[1],
                "--cache",
                &cache,
                "--shard",
                &spec,
                "--out",
                &out,
            ]));
            assert_eq!(stdout.matches("computed and cached").count(), 1, "{stdout}");
            format!("{out}/shard-reference-{k}-of-2.json")
        })
        .collect();
    let stdout = merged(&files);
    assert_eq!(
        stdout.matches("the cache matches").count(),
        2,
        "the merge finds both references: {stdout}"
    );
    expect_error(
        &["reference", &scenes[0], "--out", &cache],
        2,
        &["--out", "--shard"],
    );
}

/// A shard is held to its own work, not the study's: a `--max-dof-steps` between a quarter and
/// the whole of the study's estimate refuses the study and lets its shards of four run; their
/// merge, which runs none of the jobs, passes it too.
#[test]
fn a_shard_is_held_to_its_own_work() {
    let dir = scratch("budget");
    let out = signorini(&[
        "study",
        DIRICHLET,
        LEVELS[0],
        LEVELS[1],
        "--max-dof-steps",
        "1",
    ]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    let whole: f64 = stderr
        .split_once("the estimated work is ")
        .and_then(|(_, rest)| rest.split_once(' '))
        .and_then(|(number, _)| number.parse().ok())
        .unwrap_or_else(|| panic!("no estimate in {stderr}"));
    let limit = format!("{:e}", 0.6 * whole);
    let limited = [LEVELS[0], LEVELS[1], "--max-dof-steps", limit.as_str()];
    let mut unsharded = vec!["study", DIRICHLET];
    unsharded.extend(limited);
    expect_error(&unsharded, 2, &["estimated work", "--max-dof-steps"]);
    let files: Vec<String> = (1..=4)
        .map(|k| shard(&dir, DIRICHLET, &limited, k, 4))
        .collect();
    assert!(merged(&files).contains("Crank–Nicolson — standard"));
}
