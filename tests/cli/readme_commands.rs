//! Every `signorini` command of README.md runs as written, and prints what the README shows.
//!
//! The rule: in each fenced block of README.md, a line that starts with `signorini `,
//! `$ signorini ` or `./target/release/signorini ` (continued on the next line after a trailing
//! `\`, a `#` comment cut off) is a command. It is run with the binary this test suite built,
//! the one `cargo build --release` puts at `./target/release/signorini` and `cargo install
//! --path .` on the PATH (the README names both), from the repository root, and must exit with
//! 0. The lines a `$ ` command's sample shows after it in a `text` block (to the block's end or
//! the next `$ `) must be lines of its output, but for those with `…` (a time, or lines left
//! out). `make …` and `cargo …` lines are not run: they build the binary, install it or run the
//! whole suite, which this test is part of.

use std::fs;
use std::path::PathBuf;

use crate::common::{signorini, success_stdout};

/// A command of the README with the sample of its output shown after it.
struct Example {
    line: usize,
    args: Vec<String>,
    sample: Vec<String>,
}

/// The commands of `readme`, by the rule of the module.
fn examples(readme: &str) -> Vec<Example> {
    let prefixes = ["$ signorini ", "signorini ", "./target/release/signorini "];
    let mut found: Vec<Example> = Vec::new();
    let (mut fenced, mut sampling) = (false, false);
    let mut lines = readme.lines().enumerate();
    while let Some((n, line)) = lines.next() {
        if line.starts_with("```") {
            (fenced, sampling) = (!fenced, false);
            continue;
        }
        if !fenced {
            continue;
        }
        let Some(prefix) = prefixes.iter().find(|p| line.starts_with(*p)) else {
            if sampling && !line.contains('…') && !line.trim().is_empty() {
                found
                    .last_mut()
                    .unwrap()
                    .sample
                    .push(line.trim_end().to_string());
            }
            continue;
        };
        let mut command = line[prefix.len()..].to_string();
        while command.trim_end().ends_with('\\') {
            let next = lines.next().expect("a continued line").1;
            command = format!(
                "{} {}",
                command.trim_end().trim_end_matches('\\'),
                next.trim()
            );
        }
        let command = command.split(" #").next().unwrap();
        assert!(
            !command.contains(['\'', '"']),
            "README.md:{}: quoted arguments; this test splits at spaces",
            n + 1
        );
        sampling = prefix.starts_with('$');
        found.push(Example {
            line: n + 1,
            args: command.split_whitespace().map(String::from).collect(),
            sample: Vec::new(),
        });
    }
    found
}

#[test]
fn every_readme_command_runs_as_written() {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("README.md");
    let found = examples(&fs::read_to_string(path).unwrap());
    assert!(
        found.len() >= 3,
        "{} commands found in README.md",
        found.len()
    );
    for e in found {
        let args: Vec<&str> = e.args.iter().map(String::as_str).collect();
        let out = signorini(&args);
        assert!(
            out.status.success(),
            "README.md:{}: signorini {}: {}",
            e.line,
            args.join(" "),
            String::from_utf8_lossy(&out.stderr)
        );
        let stdout = success_stdout(&out);
        let printed: Vec<&str> = stdout.lines().map(str::trim_end).collect();
        for shown in &e.sample {
            assert!(
                printed.contains(&shown.as_str()),
                "README.md:{}: the sample line {shown:?} is not printed by signorini {}:\n{stdout}",
                e.line,
                args.join(" ")
            );
        }
    }
}

#[test]
fn readme_commands_are_found_with_their_samples() {
    let readme = "```sh\nmake report   # skipped\nsignorini list   # a comment\n```\n\
                  ```text\n$ signorini study a.json --levels 10,20 \\\n    --json\nline one\n… s\n\n\
                  line two\n```\n";
    let found = examples(readme);
    assert_eq!(found.len(), 2);
    assert_eq!(found[0].args, ["list"]);
    assert!(found[0].sample.is_empty());
    assert_eq!(
        found[1].args,
        ["study", "a.json", "--levels", "10,20", "--json"]
    );
    assert_eq!(found[1].sample, ["line one", "line two"]);
}
