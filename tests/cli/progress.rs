//! Progress on a terminal: a box `study` and a `reference` run under a pseudo-terminal draw
//! their progress (what they do, done/total, elapsed, an estimate) on stderr; through a pipe,
//! or with `CI` set, they draw none. The pseudo-terminal is util-linux's `script` (in Debian's
//! essential `bsdutils`), which runs a command with its stdin, stdout and stderr on one.

use std::path::{Path, PathBuf};
use std::process::Command;

use crate::common::{signorini, success_stdout};

/// What a drawn progress line holds, whatever the stage: the time elapsed and the estimate.
const PROGRESS: [&str; 2] = [" elapsed, about ", " left"];

/// A fresh scratch directory with a small 2D scene: the committed `bar2d.json` with levels 8
/// and 16 against a reference on 64 elements, without its round-off ensemble (about a second).
fn small_scene(name: &str) -> (PathBuf, PathBuf) {
    let dir =
        std::env::temp_dir().join(format!("signorini-progress-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let committed = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/bar2d.json");
    let mut scene: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(committed).unwrap()).unwrap();
    let d = &mut scene["discretisation"];
    d["levels"] = serde_json::json!([8, 16]);
    d["reference_level"] = serde_json::json!(64);
    d["schemes"] = serde_json::json!(["crank-nicolson", "backward-euler"]);
    d.as_object_mut().unwrap().remove("sensitivity");
    let path = dir.join("small-2d.json");
    std::fs::write(&path, serde_json::to_string_pretty(&scene).unwrap()).unwrap();
    (dir, path)
}

/// `args` single-quoted for the shell.
fn quoted(args: &[&str]) -> String {
    args.iter()
        .map(|a| format!("'{}'", a.replace('\'', r"'\''")))
        .collect::<Vec<_>>()
        .join(" ")
}

/// Runs the binary with `args` under a pseudo-terminal (without `CI` unless `ci`) and returns
/// what it drew there, stdout and stderr together.
fn on_a_terminal(args: &[&str], ci: bool) -> String {
    let binary = env!("CARGO_BIN_EXE_signorini");
    let mut command = Command::new("script");
    command
        .args([
            "-qec",
            // A terminal 160 columns wide, as a person's would be (a new one has none).
            &format!(
                "stty cols 160 rows 40; exec {} {}",
                quoted(&[binary]),
                quoted(args)
            ),
            "/dev/null",
        ])
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .env("SIGNORINI_CACHE", crate::common::test_cache())
        .env_remove("CI");
    if ci {
        command.env("CI", "true");
    }
    let out = command
        .output()
        .expect("util-linux's `script` runs (Debian: bsdutils, an essential package)");
    let drawn = String::from_utf8_lossy(&out.stdout).into_owned();
    assert!(out.status.success(), "{args:?} under a terminal: {drawn}");
    drawn
}

/// The lines of `drawn` that are progress, without the terminal's control sequences (a bar is
/// redrawn in place: `\r`, `ESC [2K` erases the line).
fn progress_lines(drawn: &str) -> Vec<String> {
    let mut text = String::with_capacity(drawn.len());
    let mut chars = drawn.chars();
    while let Some(c) = chars.next() {
        match c {
            '\x1b' => {
                // A control sequence: ESC [ parameters, ended by a letter.
                for c in chars.by_ref() {
                    if c.is_ascii_alphabetic() {
                        break;
                    }
                }
                text.push('\n');
            }
            c => text.push(c),
        }
    }
    text.split(['\r', '\n'])
        .filter(|l| PROGRESS.iter().all(|p| l.contains(p)))
        .map(|l| l.trim().to_string())
        .collect()
}

#[test]
fn a_box_study_and_a_reference_show_progress_on_a_terminal_and_none_through_a_pipe() {
    let (dir, scene) = small_scene("terminal");
    let (scene, cache) = (scene.to_str().unwrap(), dir.join("cache"));
    let cache = cache.to_str().unwrap();
    let study = ["study", scene, "--cache", cache];
    let reference = ["reference", scene, "--cache", cache];
    let _ = std::fs::remove_dir_all(cache);
    let drawn = on_a_terminal(&study, false);
    let lines = progress_lines(&drawn);
    println!("study on a terminal:\n{}", lines.join("\n"));
    assert!(
        lines
            .iter()
            .any(|l| l.contains("reference on 64 elements") && l.contains("steps")),
        "no progress of the reference's steps: {drawn}"
    );
    assert!(
        lines
            .iter()
            .any(|l| l.contains("signorini study: jobs") && l.contains("/8 jobs")),
        "no progress of the study's 8 jobs (2 schemes × 2 masses × 2 levels): {drawn}"
    );
    let _ = std::fs::remove_dir_all(cache);
    let drawn = on_a_terminal(&reference, false);
    let lines = progress_lines(&drawn);
    println!("reference on a terminal:\n{}", lines.join("\n"));
    assert!(
        lines
            .iter()
            .any(|l| l.starts_with("signorini reference:") && l.contains("steps")),
        "no progress of the reference's steps: {drawn}"
    );
    assert!(drawn.contains("computed and cached in"), "{drawn}");
    // The same commands with CI set on a terminal, and through pipes: nothing drawn.
    for args in [&study[..], &reference[..]] {
        let _ = std::fs::remove_dir_all(cache);
        let drawn = on_a_terminal(args, true);
        assert_eq!(
            progress_lines(&drawn),
            Vec::<String>::new(),
            "CI set: {drawn}"
        );
        let _ = std::fs::remove_dir_all(cache);
        let out = Command::new(env!("CARGO_BIN_EXE_signorini"))
            .args(args)
            .current_dir(env!("CARGO_MANIFEST_DIR"))
            .env("SIGNORINI_CACHE", crate::common::test_cache())
            .env_remove("CI")
            .output()
            .unwrap();
        let stdout = success_stdout(&out);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(
            progress_lines(&stderr),
            Vec::<String>::new(),
            "piped: {stderr}"
        );
        assert!(!stderr.contains('\r'), "piped: {stderr:?}");
        assert!(!stdout.is_empty());
    }
    // A cache hit says the time it took now, and the time the reference took when computed.
    let hit = success_stdout(&signorini(&reference));
    assert!(
        hit.contains("read from") && hit.contains("(computing it took"),
        "{hit}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}
