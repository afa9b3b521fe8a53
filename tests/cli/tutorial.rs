//! The book's tutorials run as written: every command of `docs/src/first-steps.md` and
//! `docs/src/tutorial-verify.md` is run, in the chapter's order, in a fresh directory that holds
//! what a clone holds for them (`scenes/`, `examples/`), with the binary this suite built as
//! `signorini` on the PATH and as `./target/release/signorini`; each must exit with 0 and print
//! every line its sample shows.
//!
//! The rule: in a fenced block whose info string is `sh`, every line is a command (a `#`
//! comment cut off); in any other fenced block, a line that starts with `$ ` is a command, and
//! the lines after it (to the block's end or the next `$ `) are its sample, but for those with
//! `…` (lines left out) and blank ones. A command runs through `sh -c` if its program is
//! `signorini`, `./target/release/signorini`, `python3` or `cat`; `make TARGET` is checked to be
//! a target of the Makefile (the targets build the binary, run the suite this test is part of,
//! or the long studies); `git`, `cd` and `cargo` fetch and build the binary under test and are
//! not run. Any other program is an error: the chapter shows a command no test runs. Without
//! `python3` the tutorial's commands are skipped with a message.

use std::fs;
use std::path::{Path, PathBuf};
use std::process::Command;

/// A command of a chapter with the sample of its output shown after it.
#[derive(Debug, PartialEq)]
struct Shown {
    line: usize,
    command: String,
    sample: Vec<String>,
}

/// What the test does with a command, from its program.
#[derive(Debug, PartialEq)]
enum Kind {
    /// Run it and compare its output with the sample.
    Run,
    /// A `make` target: it must be one of the Makefile's.
    Make(String),
    /// Fetching or building the binary under test: not run.
    Setup,
}

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The commands of `chapter`, by the rule of the module.
fn commands(chapter: &str) -> Vec<Shown> {
    let mut found: Vec<Shown> = Vec::new();
    let mut fence: Option<String> = None;
    let mut sampling = false;
    for (n, raw) in chapter.lines().enumerate() {
        let line = raw.trim();
        if let Some(info) = line.strip_prefix("```") {
            fence = match fence {
                Some(_) => None,
                None => Some(info.trim().to_string()),
            };
            sampling = false;
            continue;
        }
        let Some(info) = &fence else { continue };
        let command = if info == "sh" {
            Some(line.split(" #").next().unwrap().trim())
        } else {
            line.strip_prefix("$ ")
        };
        match command {
            Some(command) if !command.is_empty() && !command.starts_with('#') => {
                sampling = info != "sh";
                found.push(Shown {
                    line: n + 1,
                    command: command.to_string(),
                    sample: Vec::new(),
                });
            }
            _ if sampling && !line.is_empty() && !line.contains('…') => {
                found.last_mut().unwrap().sample.push(line.to_string());
            }
            _ => {}
        }
    }
    found
}

/// What to do with `command`; `None` for a program no test runs.
fn kind(command: &str) -> Option<Kind> {
    let mut words = command.split_whitespace();
    match words.next()? {
        "signorini" | "./target/release/signorini" | "python3" | "cat" => Some(Kind::Run),
        "make" => Some(Kind::Make(words.next().unwrap_or("").to_string())),
        "git" | "cd" | "cargo" => Some(Kind::Setup),
        _ => None,
    }
}

/// The targets of the Makefile (`name:` at the start of a line).
fn make_targets() -> Vec<String> {
    fs::read_to_string(root().join("Makefile"))
        .unwrap()
        .lines()
        .filter_map(|l| l.split_once(':').map(|(name, _)| name))
        .filter(|name| {
            !name.is_empty()
                && name
                    .chars()
                    .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '-')
        })
        .map(String::from)
        .collect()
}

/// A fresh directory laid out as a clone for the chapters' commands: `scenes/` and
/// `examples/` of the repository, and the binary under test as `bin/signorini` and
/// `target/release/signorini`.
fn workspace(name: &str) -> PathBuf {
    let dir =
        std::env::temp_dir().join(format!("signorini-tutorial-{}-{name}", std::process::id()));
    let _ = fs::remove_dir_all(&dir);
    for sub in ["bin", "target/release"] {
        fs::create_dir_all(dir.join(sub)).unwrap();
    }
    let binary = Path::new(env!("CARGO_BIN_EXE_signorini"));
    for link in ["bin/signorini", "target/release/signorini"] {
        std::os::unix::fs::symlink(binary, dir.join(link)).unwrap();
    }
    for shared in ["scenes", "examples"] {
        std::os::unix::fs::symlink(root().join(shared), dir.join(shared)).unwrap();
    }
    dir
}

/// Runs every command of the chapter `name` (under `docs/src/`) as written.
fn run_chapter(name: &str) {
    let path = root().join("docs").join("src").join(name);
    let shown = commands(&fs::read_to_string(&path).unwrap());
    assert!(shown.len() >= 3, "{name}: {} commands found", shown.len());
    let targets = make_targets();
    let dir = workspace(name.trim_end_matches(".md"));
    let search_path = format!(
        "{}:{}",
        dir.join("bin").display(),
        std::env::var("PATH").unwrap_or_default()
    );
    for s in shown {
        match kind(&s.command) {
            Some(Kind::Setup) => {}
            Some(Kind::Make(target)) => assert!(
                targets.contains(&target),
                "{name}:{}: `{}`: no target {target:?} in the Makefile",
                s.line,
                s.command
            ),
            Some(Kind::Run) => {
                let out = Command::new("sh")
                    .arg("-c")
                    .arg(&s.command)
                    .current_dir(&dir)
                    .env("PATH", &search_path)
                    .env("CI", "true")
                    .env("SIGNORINI_CACHE", crate::common::test_cache())
                    .output()
                    .expect("sh runs");
                let stdout = String::from_utf8_lossy(&out.stdout);
                assert!(
                    out.status.success(),
                    "{name}:{}: `{}` failed: {}",
                    s.line,
                    s.command,
                    String::from_utf8_lossy(&out.stderr)
                );
                let printed: Vec<&str> = stdout.lines().map(str::trim).collect();
                for line in &s.sample {
                    assert!(
                        printed.contains(&line.as_str()),
                        "{name}:{}: the sample line {line:?} is not printed by `{}`:\n{stdout}",
                        s.line,
                        s.command
                    );
                }
            }
            None => panic!(
                "{name}:{}: `{}`: a command no test runs (see tests/cli/tutorial.rs)",
                s.line, s.command
            ),
        }
    }
    let _ = fs::remove_dir_all(&dir);
}

fn python_present() -> bool {
    Command::new("python3")
        .arg("--version")
        .output()
        .is_ok_and(|o| o.status.success())
}

#[test]
fn first_steps_run_as_written() {
    run_chapter("first-steps.md");
}

#[test]
fn the_tutorial_verifies_its_python_codes_as_written() {
    if !python_present() {
        eprintln!("SKIPPED: python3 is not installed; the tutorial's examples need it");
        return;
    }
    run_chapter("tutorial-verify.md");
}

#[test]
fn chapter_commands_are_found_with_their_samples_and_kinds() {
    let chapter = "text\n```sh\ngit clone x  # a comment\nmake report\n```\n\
                   ```text\n$ signorini list\nline one\n… left out\n\n  line two\n\
                   $ python3 a.py out\n```\n  ```text\n  $ cat f\n  shown\n  ```\n";
    let found = commands(chapter);
    let texts: Vec<&str> = found.iter().map(|s| s.command.as_str()).collect();
    assert_eq!(
        texts,
        [
            "git clone x",
            "make report",
            "signorini list",
            "python3 a.py out",
            "cat f"
        ]
    );
    assert_eq!(found[2].sample, ["line one", "line two"]);
    assert!(found[3].sample.is_empty());
    assert_eq!(found[4].sample, ["shown"]);
    assert_eq!(kind("git clone x"), Some(Kind::Setup));
    assert_eq!(kind("make report"), Some(Kind::Make("report".into())));
    assert_eq!(kind("./target/release/signorini list"), Some(Kind::Run));
    assert_eq!(kind("rm -rf /"), None);
    assert!(make_targets().iter().any(|t| t == "report"));
}
