//! Reliability, round 3 (issue 31), item by item: nothing of the user's is deleted or replaced
//! (their files checked byte for byte after every refused or successful run); every input file
//! goes through one reader that refuses what is not a regular file of bounded size; sizes read
//! from files or flags are checked before they size anything; shard files and cached references
//! carry checksums; inaccurate solves end a run with a status and no norm; scene loading is
//! bounded; no infinite interval is printed; and the smaller items. Every run here is watched:
//! within [`SECONDS`] and under [`PEAK_KB`].

use std::fs;
use std::os::unix::fs::{FileTypeExt, MetadataExt};
use std::path::{Path, PathBuf};
use std::process::Output;

use serde_json::{json, Value};
use signorini::engine::fem::MassVariant;
use signorini::engine::schemes::Scheme;
use signorini::harness::study::shard::ShardFile;

use crate::external_runs::{export_run, write_csv};
use crate::watched::{scratch, watched};

/// The slowest any of these runs may take.
const SECONDS: u64 = 10;
/// The largest peak resident size (kB) any of them may reach: 1 GB.
const PEAK_KB: u64 = 1024 * 1024;

const DIRICHLET: &str = "scenes/bar1d-dirichlet.json";
const TRACE4: &str = "tests/data/external/contact-trace-nx4.csv";
const TRACE8: &str = "tests/data/external/contact-trace-nx8.csv";
const INTERPOLANT: &str = "tests/data/external/interpolant-nx4.json";

/// A change made to a cached reference's files.
type Tamper<'a> = Box<dyn Fn() + 'a>;

/// A change made to a scene.
type SceneEdit = fn(&mut Value);

/// The arguments that read a file, given the file.
type Command = Box<dyn Fn(&Path) -> Vec<String>>;

/// The repository root.
fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// `path` as an argument.
fn arg(path: &Path) -> String {
    path.to_string_lossy().into_owned()
}

/// A watched run of `args` from `dir` (the repository root when `None`).
fn run_in(dir: Option<&Path>, args: &[&str]) -> Output {
    watched(args, dir, SECONDS, PEAK_KB)
}

/// A watched run that must exit with `code`, every needle in its stderr; the stderr.
fn exits(dir: Option<&Path>, args: &[&str], code: i32, needles: &[&str]) -> String {
    let out = run_in(dir, args);
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    assert_eq!(out.status.code(), Some(code), "{args:?}: {stderr}");
    for n in needles {
        assert!(stderr.contains(n), "{args:?}: {n:?} not in {stderr}");
    }
    stderr
}

/// A watched run that must succeed; its stdout.
fn succeeds(dir: Option<&Path>, args: &[&str]) -> String {
    let out = run_in(dir, args);
    assert!(
        out.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// `run` of the Dirichlet scene at NX = 10 with Crank–Nicolson, into `out`.
fn run_into(out: &str) -> Vec<String> {
    let scene = arg(&root().join(DIRICHLET));
    [
        "run",
        &scene,
        "--scheme",
        "crank-nicolson",
        "--mass",
        "standard",
        "--nx",
        "10",
        "--out",
        out,
    ]
    .map(String::from)
    .to_vec()
}

fn strs(v: &[String]) -> Vec<&str> {
    v.iter().map(String::as_str).collect()
}

/// The names in `dir`, sorted.
fn names(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

/// The committed scene `name` as JSON.
fn scene(name: &str) -> Value {
    serde_json::from_str(&fs::read_to_string(root().join("scenes").join(name)).unwrap()).unwrap()
}

/// `value` written as the scene `dir/name`; its path.
fn write_scene(dir: &Path, name: &str, value: &Value) -> String {
    let path = dir.join(name);
    fs::write(&path, value.to_string()).unwrap();
    arg(&path)
}

/// Makes a FIFO at `path`; false where `mkfifo` is missing.
fn fifo(path: &Path) -> bool {
    std::process::Command::new("mkfifo")
        .arg(path)
        .status()
        .is_ok_and(|s| s.success())
}

// Item 1: nothing of the user's is ever deleted or replaced.

#[test]
fn out_dot_in_an_empty_working_directory_writes_in_place() {
    let dir = scratch("reliability", "dot");
    let cwd = dir.join("work");
    fs::create_dir(&cwd).unwrap();
    let inode = fs::metadata(&cwd).unwrap().ino();
    for _ in 0..2 {
        succeeds(Some(&cwd), &strs(&run_into(".")));
        assert_eq!(
            fs::metadata(&cwd).unwrap().ino(),
            inode,
            "the directory itself kept"
        );
        assert!(cwd.join("run.json").is_file());
    }
    // The working directory one level down: its parent holds it, a directory the user made.
    let below = cwd.join("below");
    fs::create_dir(&below).unwrap();
    fs::write(below.join("notes.txt"), "mine").unwrap();
    exits(
        Some(&below),
        &strs(&run_into("..")),
        2,
        &["below/notes.txt"],
    );
    assert_eq!(fs::read_to_string(below.join("notes.txt")).unwrap(), "mine");
    assert_eq!(fs::metadata(&cwd).unwrap().ino(), inode);
    fs::remove_dir_all(dir).unwrap();
}

#[test]
fn a_run_refuses_a_directory_holding_the_users_files_and_keeps_them() {
    let dir = scratch("reliability", "user");
    let out = dir.join("out");
    fs::create_dir(&out).unwrap();
    fs::write(out.join("mycode-nx10.csv"), "time,u0\n0,0\n").unwrap();
    fs::write(out.join("my-mesh.vtu"), "<VTKFile/>").unwrap();
    exits(
        None,
        &strs(&run_into(&arg(&out))),
        2,
        &["my-mesh.vtu", "mycode-nx10.csv", "did not write"],
    );
    assert_eq!(names(&out), ["my-mesh.vtu", "mycode-nx10.csv"]);
    assert_eq!(
        fs::read_to_string(out.join("mycode-nx10.csv")).unwrap(),
        "time,u0\n0,0\n"
    );
    assert_eq!(
        fs::read_to_string(out.join("my-mesh.vtu")).unwrap(),
        "<VTKFile/>"
    );
    // A file the harness wrote and the user edited since is theirs now.
    let ours = dir.join("ours");
    succeeds(None, &strs(&run_into(&arg(&ours))));
    fs::write(ours.join("energy.csv"), "edited").unwrap();
    exits(None, &strs(&run_into(&arg(&ours))), 2, &["energy.csv"]);
    assert_eq!(
        fs::read_to_string(ours.join("energy.csv")).unwrap(),
        "edited"
    );
    fs::remove_dir_all(dir).unwrap();
}

#[test]
fn an_out_through_a_symbolic_link_fills_its_target_and_keeps_the_link() {
    let dir = scratch("reliability", "link");
    let target = dir.join("target");
    fs::create_dir(&target).unwrap();
    let link = dir.join("link");
    std::os::unix::fs::symlink(&target, &link).unwrap();
    for _ in 0..2 {
        succeeds(None, &strs(&run_into(&arg(&link))));
        assert!(fs::symlink_metadata(&link)
            .unwrap()
            .file_type()
            .is_symlink());
        assert!(target.join("run.json").is_file(), "{:?}", names(&target));
    }
    fs::remove_dir_all(dir).unwrap();
}

#[test]
fn a_directory_the_harness_made_is_swapped_unless_it_is_the_working_directory() {
    let dir = scratch("reliability", "swap");
    let out = dir.join("out");
    succeeds(None, &strs(&run_into(&arg(&out))));
    let first = fs::metadata(&out).unwrap().ino();
    succeeds(None, &strs(&run_into(&arg(&out))));
    let second = fs::metadata(&out).unwrap().ino();
    assert_ne!(first, second, "replaced whole: a new directory");
    succeeds(Some(&out), &strs(&run_into(".")));
    assert_eq!(
        fs::metadata(&out).unwrap().ino(),
        second,
        "the working directory is kept"
    );
    fs::remove_dir_all(dir).unwrap();
}

#[test]
fn a_shared_directory_refuses_to_replace_a_users_namesake() {
    let dir = scratch("reliability", "shared");
    let reports = dir.join("reports");
    fs::create_dir(&reports).unwrap();
    fs::write(reports.join("README.md"), "my notes").unwrap();
    exits(
        None,
        // `--reports`, the old name of `--out`, is kept as a hidden alias.
        &["figures", "--reports", &arg(&reports)],
        2,
        &["README.md", "would be replaced"],
    );
    assert_eq!(
        fs::read_to_string(reports.join("README.md")).unwrap(),
        "my notes"
    );
    assert_eq!(names(&reports), ["README.md"]);
    fs::remove_dir_all(dir).unwrap();
}

#[test]
fn a_file_to_write_that_is_a_fifo_is_refused_before_the_runs() {
    let dir = scratch("reliability", "fifo-out");
    let pipe = dir.join("golden.json");
    if !fifo(&pipe) {
        return;
    }
    let link = dir.join("link.json");
    std::os::unix::fs::symlink(&pipe, &link).unwrap();
    for target in [&pipe, &link] {
        exits(
            None,
            &[
                "verify",
                DIRICHLET,
                TRACE4,
                TRACE8,
                "--write-golden",
                &arg(target),
            ],
            2,
            &["is a FIFO", "allowed: a regular file"],
        );
    }
    assert!(fs::symlink_metadata(&pipe).unwrap().file_type().is_fifo());
    assert!(fs::symlink_metadata(&link)
        .unwrap()
        .file_type()
        .is_symlink());
    fs::remove_dir_all(dir).unwrap();
}

// Item 2: one reader for every input file.

#[test]
fn inputs_that_are_not_regular_files_are_refused_before_a_byte_is_read() {
    let dir = scratch("reliability", "special");
    let pipe = dir.join("pipe.json");
    let zero = dir.join("zero.csv");
    let zero_json = dir.join("zero.json");
    let have_fifo = fifo(&pipe);
    let have_zero = Path::new("/dev/zero").exists();
    if have_zero {
        std::os::unix::fs::symlink("/dev/zero", &zero).unwrap();
        std::os::unix::fs::symlink("/dev/zero", &zero_json).unwrap();
    }
    let mut inputs: Vec<(PathBuf, &str)> = Vec::new();
    if have_fifo {
        inputs.push((pipe.clone(), "is a FIFO"));
    }
    if have_zero {
        inputs.push((zero.clone(), "is a character device"));
        inputs.push((zero_json.clone(), "is a character device"));
    }
    for (path, kind) in &inputs {
        let p = arg(path);
        exits(None, &["verify", DIRICHLET, &p], 2, &[kind]);
        exits(
            None,
            &["verify", DIRICHLET, TRACE4, TRACE8, "--golden", &p],
            2,
            &[kind],
        );
        exits(None, &["merge", &p], 2, &[kind]);
        exits(
            None,
            &[
                "run",
                &p,
                "--scheme",
                "crank-nicolson",
                "--mass",
                "standard",
            ],
            2,
            &[kind],
        );
    }
    fs::remove_dir_all(dir).unwrap();
}

/// A JSON run file's header, before its samples.
const RUN_HEAD: &str = r#"{"format":"signorini-external/1","scene":"bar1d-dirichlet","code":{"name":"x","version":"1"},"label":"x","mesh":{"nodes":[0,0.25,0.5,0.75,1]},"samples":["#;

#[test]
fn large_run_files_are_read_in_bounded_memory() {
    let dir = scratch("reliability", "large");
    // 99 MB of tiny samples: 9 M samples, held as one number each.
    let many = dir.join("many.json");
    let sample = r#"{"time":0},"#;
    let count = (99_000_000 - RUN_HEAD.len()) / sample.len();
    let mut text = String::with_capacity(99_000_000);
    text.push_str(RUN_HEAD);
    text.push_str(&sample.repeat(count - 1));
    text.push_str(r#"{"time":0}]}"#);
    fs::write(&many, text).unwrap();
    exits(None, &["verify", DIRICHLET, &arg(&many)], 2, &["many.json"]);
    // One CSV row of 60 MB of commas: refused at its first cell, never split whole; one of 80 MB
    // is longer than a line may be.
    let head = fs::read_to_string(root().join(TRACE4)).unwrap();
    let header_end = head.find("\ntime").unwrap() + 1;
    for (megabytes, needle) in [(60, "invalid time = \"\""), (80, "is longer than")] {
        let commas = dir.join(format!("commas-{megabytes}.csv"));
        let mut text = head[..header_end].to_string();
        text.push_str("time,lambda\n0,0\n");
        text.push_str(&",".repeat(megabytes * 1_000_000));
        text.push('\n');
        fs::write(&commas, text).unwrap();
        exits(None, &["verify", DIRICHLET, &arg(&commas)], 2, &[needle]);
    }
    // A header of 200 001 displacement columns: checked in linear time.
    let wide = dir.join("wide.csv");
    let n = 200_000;
    let mut text = head[..header_end].replace(
        "mesh.nodes: 0, 0.25, 0.5, 0.75, 1",
        &format!(
            "mesh.nodes: {}",
            (0..=n)
                .map(|i| (i as f64 / n as f64).to_string())
                .collect::<Vec<_>>()
                .join(", ")
        ),
    );
    text.push_str("time,");
    text.push_str(
        &(0..=n)
            .map(|i| format!("u{i}"))
            .collect::<Vec<_>>()
            .join(","),
    );
    text.push('\n');
    fs::write(&wide, text).unwrap();
    exits(None, &["verify", DIRICHLET, &arg(&wide)], 2, &[]);
    fs::remove_dir_all(dir).unwrap();
}

#[test]
fn a_bom_is_skipped_and_an_empty_run_says_so() {
    let dir = scratch("reliability", "bom");
    let bom = dir.join("bom.csv");
    let mut bytes = "\u{feff}".as_bytes().to_vec();
    bytes.extend(fs::read(root().join(TRACE4)).unwrap());
    fs::write(&bom, bytes).unwrap();
    succeeds(None, &["verify", DIRICHLET, &arg(&bom), TRACE8]);
    let empty = dir.join("empty.json");
    fs::write(&empty, format!("{RUN_HEAD}]}}")).unwrap();
    exits(
        None,
        &["verify", DIRICHLET, &arg(&empty)],
        2,
        &["invalid samples = none"],
    );
    fs::remove_dir_all(dir).unwrap();
}

// Item 3: every size read from a file or flag is checked before it sizes anything.

/// The one shard of a 1/1-sharded small study, written under `dir`: its file.
fn one_shard(dir: &Path) -> PathBuf {
    let out = dir.join("s");
    succeeds(
        None,
        &[
            "study",
            DIRICHLET,
            "--levels",
            "10,20",
            "--shard",
            "1/1",
            "--out",
            &arg(&out),
        ],
    );
    out.join("shard-study-1-of-1.json")
}

#[test]
fn absurd_shard_counts_are_refused_on_the_command_line_and_in_files() {
    for n in ["18446744073709551615", "100000000000", "10001"] {
        let spec = format!("1/{n}");
        exits(
            None,
            &[
                "study",
                DIRICHLET,
                "--shard",
                &spec,
                "--out",
                "/nonexistent",
            ],
            2,
            &["--shard", "n <= 10000"],
        );
    }
    let dir = scratch("reliability", "shard-n");
    let path = one_shard(&dir);
    let mut file: ShardFile = serde_json::from_str(&fs::read_to_string(&path).unwrap()).unwrap();
    for (field, value) in [
        ("n", 1_000_000_000_000_000_usize),
        ("jobs", 1_000_000_000_000_000),
    ] {
        let mut forged = file.clone();
        match field {
            "n" => forged.n = value,
            _ => forged.jobs = value,
        }
        let forged = forged.sealed();
        let p = dir.join(format!("{field}.json"));
        fs::write(&p, serde_json::to_string(&forged).unwrap()).unwrap();
        exits(
            None,
            &["merge", &arg(&p)],
            2,
            &[&format!("{field} = {value}"), "at most"],
        );
    }
    // The merge of one shard of many names the missing ones as ranges, on one short line.
    file.n = 10_000;
    let lone = dir.join("lone.json");
    fs::write(
        &lone,
        serde_json::to_string(&file.clone().sealed()).unwrap(),
    )
    .unwrap();
    let stderr = exits(None, &["merge", &arg(&lone)], 2, &["2/10000–10000/10000"]);
    assert!(stderr.len() < 300, "{stderr}");
    fs::remove_dir_all(dir).unwrap();
}

#[test]
fn getfem_checks_a_demo_file_and_its_work_before_running_it() {
    let dir = scratch("reliability", "getfem");
    let runs = dir.join("runs");
    fs::create_dir(&runs).unwrap();
    let name = "getfem_v0_b0.25_g0.5_m0_nx20.json.gz";
    let source = root().join("tests/data/getfem").join(name);
    let read = |path: &Path| -> Value {
        let mut text = String::new();
        std::io::Read::read_to_string(
            &mut flate2::read::GzDecoder::new(fs::File::open(path).unwrap()),
            &mut text,
        )
        .unwrap();
        serde_json::from_str(&text).unwrap()
    };
    let write = |value: &Value| {
        let file = fs::File::create(runs.join(name)).unwrap();
        let mut gz = flate2::write::GzEncoder::new(file, flate2::Compression::fast());
        std::io::Write::write_all(&mut gz, value.to_string().as_bytes()).unwrap();
        gz.finish().unwrap();
    };
    let original = read(&source);
    let mut forged = original.clone();
    forged["params"]["T"] = json!(1e7);
    write(&forged);
    let out = arg(&dir.join("out"));
    exits(
        None,
        &["getfem", "--runs", &arg(&runs), "--out", &out],
        2,
        &["params.T", "time points"],
    );
    write(&original);
    exits(
        None,
        &[
            "getfem",
            "--runs",
            &arg(&runs),
            "--out",
            &out,
            "--max-dof-steps",
            "1e4",
        ],
        2,
        &["estimated work", "--max-dof-steps"],
    );
    fs::remove_dir_all(dir).unwrap();
}

// Item 4: integrity.

#[test]
fn a_shard_changed_after_it_was_written_is_refused_naming_it() {
    let dir = scratch("reliability", "tamper");
    let path = one_shard(&dir);
    let original = fs::read_to_string(&path).unwrap();
    let file: ShardFile = serde_json::from_str(&original).unwrap();
    // A result edited by hand: one hexadecimal digit of its MessagePack changed.
    let mut changed = file.clone();
    let digits = &mut changed.results[0].result;
    let last = digits.pop().unwrap();
    digits.push(if last == '0' { '1' } else { '0' });
    fs::write(&path, serde_json::to_string(&changed).unwrap()).unwrap();
    exits(
        None,
        &["merge", &arg(&path)],
        2,
        &["checksum does not match", "shard-study-1-of-1.json"],
    );
    // A negative error with a checksum that matches (a forged file): out of its range.
    let key = format!("a8{}cb", hex(b"u_Linf_H"));
    let mut negative = file.clone();
    let text = &mut negative.results[0].result;
    let at = text.find(&key).expect("u_Linf_H in the result") + key.len();
    let value = f64::from_be_bytes(unhex(&text[at..at + 16]).try_into().unwrap());
    text.replace_range(at..at + 16, &hex(&(-value).to_be_bytes()));
    fs::write(&path, serde_json::to_string(&negative.sealed()).unwrap()).unwrap();
    exits(
        None,
        &["merge", &arg(&path)],
        2,
        &["out of range", "u_Linf_H"],
    );
    fs::remove_dir_all(dir).unwrap();
}

fn hex(bytes: &[u8]) -> String {
    bytes.iter().map(|b| format!("{b:02x}")).collect()
}

fn unhex(text: &str) -> Vec<u8> {
    (0..text.len())
        .step_by(2)
        .map(|i| u8::from_str_radix(&text[i..i + 2], 16).unwrap())
        .collect()
}

/// `study scenes/bar2d.json` on `levels` against a reference on 8, cached in `cache`: its
/// stdout and stderr.
fn small_box_study(cache: &Path, levels: &str) -> (String, String) {
    let out = run_in(
        None,
        &[
            "study",
            "scenes/bar2d.json",
            "--levels",
            levels,
            "--reference-level",
            "8",
            "--cache",
            &arg(cache),
        ],
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    (
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

#[test]
fn a_cached_reference_changed_since_it_was_written_is_recomputed_and_said() {
    let dir = scratch("reliability", "cache");
    let cache = dir.join("cache");
    let (fresh, _) = small_box_study(&cache, "1,2");
    let file = |ext: &str| {
        fs::read_dir(&cache)
            .unwrap()
            .map(|e| e.unwrap().path())
            .find(|p| p.extension().is_some_and(|e| e == ext))
            .unwrap()
    };
    let (json_path, bin_path) = (file("json"), file("bin"));
    let tables = |s: &str| {
        s.lines()
            .filter(|l| l.starts_with('|'))
            .collect::<Vec<_>>()
            .join("\n")
    };
    let tamperings: [(&str, Tamper); 3] = [
        (
            "total_force",
            Box::new(|| {
                let mut v: Value =
                    serde_json::from_str(&fs::read_to_string(&json_path).unwrap()).unwrap();
                let f = v["total_force"][3].as_f64().unwrap();
                v["total_force"][3] = json!(2.0 * f - 1.0);
                fs::write(&json_path, v.to_string()).unwrap();
            }),
        ),
        (
            "1e308",
            Box::new(|| {
                let n = fs::metadata(&bin_path).unwrap().len() as usize / 8;
                fs::write(&bin_path, 1e308_f64.to_le_bytes().repeat(n)).unwrap();
            }),
        ),
        (
            "NaN",
            Box::new(|| {
                let mut bytes = fs::read(&bin_path).unwrap();
                bytes[80..88].copy_from_slice(&f64::NAN.to_le_bytes());
                fs::write(&bin_path, bytes).unwrap();
            }),
        ),
    ];
    for (what, tamper) in &tamperings {
        tamper();
        let (again, stderr) = small_box_study(&cache, "1,2");
        assert!(stderr.contains("is stale"), "{what}: {stderr}");
        assert_eq!(tables(&again), tables(&fresh), "{what}: recomputed alike");
    }
    fs::remove_dir_all(dir).unwrap();
}

/// An edit of a cached reference's contents.
type Forgery<'a> =
    &'a dyn Fn(&mut signorini::harness::reference::fine_mesh::cache::CachedReference);

/// A cached reference forged with a valid checksum (written through the cache's own `save`) but
/// numbers no run can have is stale, recomputed and said (issue 55 item 4): times that run
/// backwards made every error 0, a projection of 1e300 made every error `inf`, and histories cut
/// to three samples were read as the whole run.
#[test]
fn a_forged_cache_whose_numbers_cannot_be_a_runs_is_recomputed_and_said() {
    use signorini::harness::reference::fine_mesh::cache::{load, save, CacheLookup};
    let dir = scratch("reliability", "forged-cache");
    let cache = dir.join("cache");
    let (fresh, _) = small_box_study(&cache, "1,2");
    let stem = fs::read_dir(&cache)
        .unwrap()
        .map(|e| e.unwrap().path())
        .find(|p| p.extension().is_some_and(|e| e == "json"))
        .and_then(|p| p.file_stem().map(|s| s.to_string_lossy().into_owned()))
        .unwrap();
    let tables = |s: &str| {
        s.lines()
            .filter(|l| l.starts_with('|'))
            .collect::<Vec<_>>()
            .join("\n")
    };
    let forge =
        |edit: &dyn Fn(&mut signorini::harness::reference::fine_mesh::cache::CachedReference)| {
            let json: Value = serde_json::from_str(
                &fs::read_to_string(cache.join(format!("{stem}.json"))).unwrap(),
            )
            .unwrap();
            let key = serde_json::from_value(json["key"].clone()).unwrap();
            let CacheLookup::Hit(mut cached) = load(&cache, &stem, &key).unwrap() else {
                panic!("the fresh cache is not found");
            };
            edit(&mut cached);
            save((&cached.histories, &cached.projections), &cache, &stem).unwrap();
        };
    let cut: Forgery = &|c| {
        let h = &mut c.histories;
        for series in [
            &mut h.time,
            &mut h.energy,
            &mut h.total_force,
            &mut h.centre_displacement,
            &mut h.centre_multiplier,
        ] {
            series.truncate(3);
        }
    };
    let forgeries: [(&str, Forgery, &str); 3] = [
        ("cut to 3 samples", cut, "not from 0 to the horizon"),
        (
            "times backwards",
            &|c| c.histories.time.swap(4, 5),
            "does not follow",
        ),
        (
            "1e300",
            &|c| c.projections[0].h_projection[3] = 1e300,
            "beyond 1e100",
        ),
    ];
    for (what, edit, why) in forgeries {
        forge(edit);
        let (again, stderr) = small_box_study(&cache, "1,2");
        assert!(
            stderr.contains("is stale") && stderr.contains(why),
            "{what}: {stderr}"
        );
        assert_eq!(tables(&again), tables(&fresh), "{what}: recomputed alike");
    }
    fs::remove_dir_all(dir).unwrap();
}

// Item 5: solves that are checked.

#[test]
fn an_inaccurate_cg_solve_ends_the_run_with_no_norm_and_a_study_says_not_run() {
    let dir = scratch("reliability", "stiff");
    let mut stiff = scene("bar2d.json");
    stiff["material"]["lame_lambda"] = json!(0.5e14);
    let s = write_scene(&dir, "stiff.json", &stiff);
    let out = dir.join("out");
    let run = [
        "run",
        &s,
        "--scheme",
        "crank-nicolson",
        "--mass",
        "standard",
        "--nx",
        "10",
        "--linear-solver",
        "cg",
        "--out",
        &arg(&out),
    ];
    let output = run_in(None, &run);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("inaccurate solve at step 1") && stderr.contains("true relative residual")
    );
    assert!(!String::from_utf8_lossy(&output.stdout).contains("u_Linf_H"));
    assert!(!out.exists(), "nothing written");
    // An unstable scheme whose balance fails in round-off it cannot bound, in a 1D study: the
    // case is not run, the others are.
    let stdout = succeeds(
        None,
        &[
            "study",
            DIRICHLET,
            "--scheme",
            "newmark(beta=0.25,gamma=0.55)",
            "--scheme",
            "crank-nicolson",
            "--mass",
            "redistributed",
            "--levels",
            "10,20,40,80",
        ],
    );
    assert!(stdout.contains("#### Not run"), "{stdout}");
    assert!(stdout.contains("| newmark(beta=0.25,gamma=0.55)/redistributed | 80 | non-finite"));
    assert!(stdout.contains("#### Crank–Nicolson — redistributed"));
    fs::remove_dir_all(dir).unwrap();
}

// Item 6: scene load is bounded.

#[test]
fn bouncing_bars_with_extreme_parameters_load_quickly_or_are_refused() {
    let dir = scratch("reliability", "bouncing");
    let cases: [(&str, SceneEdit); 3] = [
        ("gravity", |s| s["body_force"]["density"] = json!(-1e-20)),
        ("height", |s| {
            s["initial"]["displacement"]["constant"] = json!(1e30)
        }),
        ("length", |s| {
            s["geometry"]["length"] = json!(1e-10);
            s["observables"]["points"] = json!([0.0, 0.5e-10, 1e-10]);
        }),
    ];
    for (name, edit) in cases {
        let sub = dir.join(name);
        fs::create_dir(&sub).unwrap();
        let mut s = scene("bar1d-gravity.json");
        edit(&mut s);
        let path = write_scene(&sub, "bouncing.json", &s);
        let run = run_in(
            None,
            &[
                "run",
                &path,
                "--scheme",
                "crank-nicolson",
                "--mass",
                "redistributed",
                "--nx",
                "10",
            ],
        );
        let stderr = String::from_utf8_lossy(&run.stderr);
        if name == "length" {
            assert_eq!(run.status.code(), Some(2), "{stderr}");
            assert!(
                stderr.contains("horizon") && stderr.contains("MAX_WINDOWS"),
                "{stderr}"
            );
        } else {
            assert!(run.status.success(), "{name}: {stderr}");
        }
        succeeds(None, &["list", "--scenes", &arg(&sub)]);
    }
    fs::remove_dir_all(dir).unwrap();
}

// Item 7: no infinite interval.

#[test]
fn a_study_whose_check_level_is_fitted_prints_no_infinite_interval() {
    let dir = scratch("reliability", "interval");
    // The check run is one level below the reference, 4 elements: a fitted level here.
    let (stdout, _) = small_box_study(&dir.join("cache"), "2,4");
    let cells: Vec<&str> = stdout.split(['|', ' ', '\n']).collect();
    assert!(
        !cells
            .iter()
            .any(|c| ["inf", "±inf", "-inf", "NaN"].contains(c)),
        "{stdout}"
    );
    assert!(
        stdout.contains("none¹") && stdout.contains("¹ No bound"),
        "{stdout}"
    );
    fs::remove_dir_all(dir).unwrap();
}

// Item 8: the smaller items.

#[test]
fn the_smaller_items_get_clear_errors() {
    let dir = scratch("reliability", "small");
    // A negative golden tolerance is a malformed file (exit 2), not a drift.
    let golden = dir.join("golden.json");
    let g = json!({
        "generated_by": "a hand",
        "scene": "bar1d-dirichlet",
        "tolerances": { "rate_abs": -0.02, "error_rel": 0.01 },
        "series": []
    });
    fs::write(&golden, g.to_string()).unwrap();
    exits(
        None,
        &[
            "verify",
            DIRICHLET,
            TRACE4,
            TRACE8,
            "--golden",
            &arg(&golden),
        ],
        2,
        &["tolerances.rate_abs = -0.02", "a finite number >= 0"],
    );
    // 1e-300 is shown as such, not as 300 digits.
    let tiny = dir.join("tiny.json");
    let mut run: Value =
        serde_json::from_str(&fs::read_to_string(root().join(INTERPOLANT)).unwrap()).unwrap();
    run["samples"][0]["time"] = json!(1e-300);
    fs::write(&tiny, run.to_string()).unwrap();
    let stderr = exits(None, &["verify", DIRICHLET, &arg(&tiny)], 2, &["1e-300"]);
    assert!(stderr.len() < 400, "{stderr}");
    // A path with a newline is escaped: the message is one line.
    let odd = dir.join("bad\nname.csv");
    fs::write(&odd, "not a run").unwrap();
    let stderr = exits(
        None,
        &["verify", DIRICHLET, &arg(&odd)],
        2,
        &["bad\\u{a}name.csv"],
    );
    assert_eq!(stderr.trim_end().lines().count(), 1, "{stderr}");
    // A cache path that is a file is refused before the reference is computed.
    let file = dir.join("cache-file");
    fs::write(&file, "mine").unwrap();
    exits(
        None,
        &["reference", "scenes/bar2d.json", "--cache", &arg(&file)],
        2,
        &["--cache", "is not a directory"],
    );
    assert_eq!(fs::read_to_string(&file).unwrap(), "mine");
    fs::remove_dir_all(dir).unwrap();
}

// Evidence: a seeded property test over corrupted input files.

/// How a file is corrupted: the bytes of the valid file and what is done to them.
#[derive(Debug, Clone)]
enum Corruption {
    /// A byte set to a value.
    Byte { at: usize, value: u8 },
    /// Cut at a fraction of its length.
    Truncate { at: usize },
    /// A number (a run of digits) replaced by a word of [`HOSTILE_NUMBERS`].
    Number { which: usize, word: usize },
    /// A span repeated in place.
    Repeat { at: usize, len: usize },
}

/// What a corrupted number becomes: non-finite, negative, huge, tiny or not a number at all.
const HOSTILE_NUMBERS: [&str; 8] = [
    "NaN", "-1", "1e308", "-0", "null", "1e-300", "\"x\"", "9e99999",
];

impl Corruption {
    /// `bytes` corrupted (positions taken modulo the length, so that any draw applies).
    fn apply(&self, bytes: &[u8]) -> Vec<u8> {
        let n = bytes.len().max(1);
        let mut out = bytes.to_vec();
        match *self {
            Corruption::Byte { at, value } => out[at % n] = value,
            Corruption::Truncate { at } => out.truncate(at % n),
            Corruption::Number { which, word } => {
                let text = String::from_utf8_lossy(bytes);
                let numbers: Vec<(usize, usize)> = text
                    .char_indices()
                    .filter(|(_, c)| c.is_ascii_digit())
                    .map(|(i, _)| {
                        let end = text[i..]
                            .find(|c: char| !(c.is_ascii_digit() || ".e-+".contains(c)))
                            .map_or(text.len(), |k| i + k);
                        (i, end)
                    })
                    .collect();
                if let Some(&(start, end)) = numbers.get(which % numbers.len().max(1)) {
                    let mut t = text.into_owned();
                    t.replace_range(start..end, HOSTILE_NUMBERS[word % HOSTILE_NUMBERS.len()]);
                    out = t.into_bytes();
                }
            }
            Corruption::Repeat { at, len } => {
                let start = at % n;
                let span = out[start..(start + len).min(out.len())].to_vec();
                out.splice(start..start, span);
            }
        }
        out
    }
}

fn corruption() -> impl proptest::strategy::Strategy<Value = Corruption> {
    use proptest::prelude::*;
    prop_oneof![
        (any::<usize>(), any::<u8>()).prop_map(|(at, value)| Corruption::Byte { at, value }),
        any::<usize>().prop_map(|at| Corruption::Truncate { at }),
        (any::<usize>(), any::<usize>())
            .prop_map(|(which, word)| Corruption::Number { which, word }),
        (any::<usize>(), 1..64_usize).prop_map(|(at, len)| Corruption::Repeat { at, len }),
    ]
}

/// Whether `stdout` shows a non-finite number in a table cell.
fn shows_non_finite(stdout: &str) -> bool {
    stdout
        .split(['|', ' ', '\n', ','])
        .any(|cell| ["NaN", "inf", "-inf", "±inf"].contains(&cell))
}

/// Valid files of every kind a user or a run hands the harness back (a run file in both forms,
/// a golden file, a shard file, a cached reference), each corrupted by a seeded generator, 12
/// times a kind: every one is accepted with finite results (exit 0) or refused (exit 2), never
/// anything else, within the time and memory bounds.
#[test]
fn corrupted_input_files_are_accepted_with_finite_results_or_refused() {
    use proptest::test_runner::{Config, RngAlgorithm, TestRng, TestRunner};
    let dir = scratch("reliability", "fuzz");
    let problem = signorini::studies::benchmark::dirichlet(root(), 3.0).unwrap();
    let runs: Vec<String> = [10, 20, 40]
        .map(|nx| {
            let e = export_run(
                &problem,
                nx,
                10.0,
                Scheme::BACKWARD_EULER,
                MassVariant::Redistributed,
            );
            let csv = dir.join(format!("be-nx{nx}.csv"));
            write_csv(&csv, &e, "backward Euler, MOD");
            arg(&csv)
        })
        .to_vec();
    let golden = dir.join("golden.json");
    let mut write = vec!["verify", DIRICHLET];
    write.extend(runs.iter().map(String::as_str));
    let golden_arg = arg(&golden);
    write.extend(["--write-golden", &golden_arg]);
    succeeds(None, &write);
    let shard = one_shard(&dir);
    let cache = dir.join("cache");
    small_box_study(&cache, "1,2");
    let cached: Vec<PathBuf> = fs::read_dir(&cache)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();

    let mut kinds: Vec<(PathBuf, Command)> = vec![
        (
            root().join(TRACE4),
            Box::new(|p: &Path| {
                ["verify", DIRICHLET, &arg(p), TRACE8]
                    .map(String::from)
                    .to_vec()
            }),
        ),
        (
            root().join(INTERPOLANT),
            Box::new(|p: &Path| ["verify", DIRICHLET, &arg(p)].map(String::from).to_vec()),
        ),
        (
            shard.clone(),
            Box::new(|p: &Path| ["merge", &arg(p)].map(String::from).to_vec()),
        ),
    ];
    kinds.push((
        golden.clone(),
        Box::new(move |p: &Path| {
            let mut a = vec!["verify".to_string(), DIRICHLET.to_string()];
            a.extend(runs.iter().cloned());
            a.extend(["--golden".to_string(), arg(p)]);
            a
        }),
    ));
    let study_args: Vec<String> = [
        "study",
        "scenes/bar2d.json",
        "--levels",
        "1,2",
        "--reference-level",
        "8",
        "--cache",
        &arg(&cache),
    ]
    .map(String::from)
    .to_vec();
    for file in &cached {
        let args = study_args.clone();
        kinds.push((file.clone(), Box::new(move |_: &Path| args.clone())));
    }
    let (accepted, refused) = (std::cell::Cell::new(0), std::cell::Cell::new(0));
    for (k, (valid, command)) in kinds.iter().enumerate() {
        let original = fs::read(valid).unwrap();
        let target = if valid.starts_with(&cache) {
            valid.clone()
        } else {
            dir.join(format!(
                "fuzzed-{k}.{}",
                valid.extension().unwrap().to_string_lossy()
            ))
        };
        let config = Config {
            cases: 12,
            failure_persistence: None,
            ..Config::default()
        };
        let rng = TestRng::deterministic_rng(RngAlgorithm::ChaCha);
        let mut runner = TestRunner::new_with_rng(config, rng);
        let outcome = runner.run(&corruption(), |c| {
            fs::write(&target, c.apply(&original)).unwrap();
            let args = command(&target);
            let out = run_in(None, &strs(&args));
            let stdout = String::from_utf8_lossy(&out.stdout);
            let stderr = String::from_utf8_lossy(&out.stderr);
            proptest::prop_assert!(
                matches!(out.status.code(), Some(0 | 2)),
                "{c:?} of {}: exit {:?}: {stderr}",
                valid.display(),
                out.status.code()
            );
            proptest::prop_assert!(
                !(out.status.success() && shows_non_finite(&stdout)),
                "{c:?} of {}: a non-finite result was accepted:\n{stdout}",
                valid.display()
            );
            let tally = if out.status.success() {
                &accepted
            } else {
                &refused
            };
            tally.set(tally.get() + 1);
            Ok(())
        });
        if valid.starts_with(&cache) {
            // Put the cache back whole (a stale file was recomputed and saved already).
            fs::write(valid, &original).unwrap();
        }
        outcome.unwrap();
    }
    // Both outcomes occur: a corruption the readers accept (a stale cache recomputed, a byte
    // changed in a comment or a label) and one they refuse.
    assert!(
        accepted.get() > 0 && refused.get() > 0,
        "accepted {}, refused {}",
        accepted.get(),
        refused.get()
    );
    fs::remove_dir_all(dir).unwrap();
}
