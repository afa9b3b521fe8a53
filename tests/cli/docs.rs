//! The documentation: README.md is a first screen, and every relative link of the README, of the
//! book (`docs/src/`, mdBook) and of the committed reports' pages (`reports/**/*.md`: the index,
//! its gallery, the league and the finer studies' indexes) leads to a file that exists inside
//! the clone and that git does not ignore; so does every file a chapter includes (`{{#include PATH}}`); every chapter is in
//! the book's table of contents (`docs/src/SUMMARY.md`) and every entry of it is a chapter. The
//! commands the tutorials show are run by `tutorial.rs`, those of the README by
//! `readme_commands.rs`.

use std::collections::BTreeSet;
use std::fs;
use std::path::{Path, PathBuf};

/// The most lines README.md may have: what it is, the two commands, a map of the book.
const README_MAX_LINES: usize = 250;

/// The lines of README.md's first screen.
const README_FIRST_SCREEN: usize = 45;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn book_src() -> PathBuf {
    root().join("docs").join("src")
}

/// The book's markdown files, sorted.
fn chapters() -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = fs::read_dir(book_src())
        .unwrap_or_else(|e| panic!("{}: {e}", book_src().display()))
        .map(|entry| entry.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "md"))
        .collect();
    files.sort();
    files
}

/// The targets of the inline markdown links `[text](target)` of `text`, outside code spans and
/// fenced code blocks, with their line numbers. A target ends at the first space (a title may
/// follow) or at the closing parenthesis; `<target>` is unwrapped and may hold spaces.
fn link_targets(text: &str) -> Vec<(usize, String)> {
    let mut links = Vec::new();
    let mut fenced = false;
    for (index, line) in text.lines().enumerate() {
        if line.trim_start().starts_with("```") {
            fenced = !fenced;
            continue;
        }
        if fenced {
            continue;
        }
        let chars: Vec<char> = line.chars().collect();
        let mut in_code = false;
        let mut i = 0;
        while i < chars.len() {
            match chars[i] {
                '`' => in_code = !in_code,
                ']' if !in_code && chars.get(i + 1) == Some(&'(') => {
                    let start = i + 2;
                    let mut depth = 0usize;
                    let mut end = start;
                    while end < chars.len() {
                        match chars[end] {
                            '(' => depth += 1,
                            ')' if depth == 0 => break,
                            ')' => depth -= 1,
                            _ => {}
                        }
                        end += 1;
                    }
                    if end < chars.len() {
                        let inside: String = chars[start..end].iter().collect();
                        let inside = inside.trim();
                        let target = match inside.strip_prefix('<') {
                            Some(rest) => rest.split('>').next().unwrap_or(""),
                            None => inside.split_whitespace().next().unwrap_or(""),
                        };
                        links.push((index + 1, target.to_string()));
                        i = end;
                    }
                }
                _ => {}
            }
            i += 1;
        }
    }
    links
}

/// The file a link leads to, relative to `file`'s directory; `None` for links that leave the
/// repository's files (a URL, mail) or stay in the page (`#anchor`).
fn local_target(file: &Path, target: &str) -> Option<PathBuf> {
    let lower = target.to_ascii_lowercase();
    if target.is_empty()
        || target.starts_with('#')
        || lower.starts_with("http://")
        || lower.starts_with("https://")
        || lower.starts_with("mailto:")
    {
        return None;
    }
    let path = target.split('#').next().unwrap_or(target);
    Some(file.parent().unwrap().join(path))
}

/// `path` with its `.` and `..` components resolved without the file system.
fn normalised(path: &Path) -> PathBuf {
    let mut out = PathBuf::new();
    for part in path.components() {
        match part {
            std::path::Component::CurDir => {}
            std::path::Component::ParentDir => {
                out.pop();
            }
            other => out.push(other),
        }
    }
    out
}

/// Whether git ignores `path` (`git check-ignore`): such a file is on this machine only, never
/// in a clone. Panics when git cannot answer, rather than pass a link it could not judge.
fn ignored_by_git(path: &Path) -> bool {
    let status = std::process::Command::new("git")
        .arg("-C")
        .arg(root())
        .args(["check-ignore", "-q"])
        .arg(path)
        .status()
        .unwrap_or_else(|e| panic!("git check-ignore {}: {e}", path.display()));
    match status.code() {
        Some(0) => true,
        Some(1) => false,
        _ => panic!("git check-ignore {} failed: {status}", path.display()),
    }
}

/// Every relative link of `text`, the page `file`, that leads nowhere, out of the clone (a
/// file beside the repository exists on one machine only) or to a file git ignores (written
/// here, absent from a clone), as `file:line: target`.
fn broken_links_in(file: &Path, text: &str) -> Vec<String> {
    let shown = file.strip_prefix(root()).unwrap_or(file);
    link_targets(text)
        .into_iter()
        .filter(|(_, target)| {
            local_target(file, target).is_some_and(|path| {
                !path.exists() || !normalised(&path).starts_with(root()) || ignored_by_git(&path)
            })
        })
        .map(|(line, target)| format!("{}:{line}: {target}", shown.display()))
        .collect()
}

/// [`broken_links_in`] of every page of `files`.
fn broken_links(files: &[PathBuf]) -> Vec<String> {
    files
        .iter()
        .flat_map(|file| {
            let text =
                fs::read_to_string(file).unwrap_or_else(|e| panic!("{}: {e}", file.display()));
            broken_links_in(file, &text)
        })
        .collect()
}

#[test]
fn every_relative_link_in_the_readme_and_the_book_resolves() {
    let mut files = vec![root().join("README.md")];
    files.extend(chapters());
    assert!(
        files.len() > 2,
        "no chapters found in {}",
        book_src().display()
    );
    let broken = broken_links(&files);
    assert!(
        broken.is_empty(),
        "{} broken link(s):\n{}",
        broken.len(),
        broken.join("\n")
    );
}

/// The markdown files under `dir`, recursively, sorted.
fn markdown_under(dir: &Path) -> Vec<PathBuf> {
    let mut files = Vec::new();
    for entry in fs::read_dir(dir).unwrap_or_else(|e| panic!("{}: {e}", dir.display())) {
        let path = entry.unwrap().path();
        if path.is_dir() {
            files.extend(markdown_under(&path));
        } else if path.extension().is_some_and(|e| e == "md") {
            files.push(path);
        }
    }
    files.sort();
    files
}

/// Every page of the committed reports: the index (`reports/README.md`), its gallery, the
/// finer studies' indexes (`reports/fine/README.md`, `reports/finest/README.md`), the league
/// (`reports/league.md`) and each report and verification page.
#[test]
fn every_relative_link_in_the_reports_resolves() {
    let reports = root().join("reports");
    let files = markdown_under(&reports);
    for page in [
        "README.md",
        "gallery.md",
        "league.md",
        "fine/README.md",
        "finest/README.md",
    ] {
        assert!(
            files.contains(&reports.join(page)),
            "reports/{page} is not committed"
        );
    }
    let broken = broken_links(&files);
    assert!(
        broken.is_empty(),
        "{} broken link(s):\n{}",
        broken.len(),
        broken.join("\n")
    );
}

/// The paths of mdBook's `{{#include PATH}}` (or `PATH:anchor`, `PATH:1:10`) in `text`.
fn includes(text: &str) -> Vec<String> {
    text.split("{{#include ")
        .skip(1)
        .filter_map(|rest| rest.split("}}").next())
        .map(|inside| inside.trim().split(':').next().unwrap_or("").to_string())
        .collect()
}

#[test]
fn every_file_the_book_includes_exists() {
    let mut missing = Vec::new();
    let mut found = 0;
    for chapter in chapters() {
        let text = fs::read_to_string(&chapter).unwrap();
        for path in includes(&text) {
            found += 1;
            if !chapter.parent().unwrap().join(&path).is_file() {
                missing.push(format!("{}: {path}", chapter.display()));
            }
        }
    }
    assert!(found > 0, "no {{{{#include}}}} found in the book");
    assert!(
        missing.is_empty(),
        "included files missing:\n{}",
        missing.join("\n")
    );
    assert_eq!(
        includes("a {{#include ../x.py}} b {{#include y.rs:anchor}}"),
        ["../x.py", "y.rs"]
    );
}

#[test]
fn every_chapter_is_in_the_summary_and_every_entry_is_a_chapter() {
    let summary_path = book_src().join("SUMMARY.md");
    let summary = fs::read_to_string(&summary_path)
        .unwrap_or_else(|e| panic!("{}: {e}", summary_path.display()));
    let listed: BTreeSet<String> = link_targets(&summary)
        .into_iter()
        .filter_map(|(_, target)| local_target(&summary_path, &target))
        .map(|p| p.file_name().unwrap().to_string_lossy().into_owned())
        .collect();
    let present: BTreeSet<String> = chapters()
        .iter()
        .map(|p| p.file_name().unwrap().to_string_lossy().into_owned())
        .filter(|name| name != "SUMMARY.md")
        .collect();
    let unlisted: Vec<&String> = present.difference(&listed).collect();
    let missing: Vec<&String> = listed.difference(&present).collect();
    assert!(
        unlisted.is_empty() && missing.is_empty(),
        "docs/src/SUMMARY.md and the chapters differ: not in SUMMARY.md: {unlisted:?}; \
         listed but missing: {missing:?}"
    );
}

#[test]
fn the_readme_is_a_first_screen() {
    let readme = fs::read_to_string(root().join("README.md")).unwrap();
    let lines = readme.lines().count();
    assert!(
        lines <= README_MAX_LINES,
        "README.md has {lines} lines, more than {README_MAX_LINES}: move the detail into a \
         chapter of the book (docs/src/)"
    );
}

/// The first screen cites the papers, explains "redistributed mass" and what a verdict means, and
/// gives the two commands, before anything else.
#[test]
fn the_readme_first_screen_cites_the_papers_and_gives_the_two_commands() {
    let readme = fs::read_to_string(root().join("README.md")).unwrap();
    let screen: Vec<&str> = readme.lines().take(README_FIRST_SCREEN).collect();
    let screen = screen.join("\n");
    for needle in [
        "Dabaghi, A. Petrov, J. Pousin, Y. Renard",
        "hal-00917450",
        "Numerical study of convergence of the mass",
        "**redistributed mass**",
        "*undecided*",
        "make report",
        "make test",
    ] {
        assert!(
            screen.contains(needle),
            "README.md's first {README_FIRST_SCREEN} lines do not contain {needle:?}"
        );
    }
}

#[test]
fn link_extraction_finds_file_links_and_skips_code() {
    let text = "see [a](a.md#x) and [b](<b c.md> \"title\"), `[not](code.md)`\n\
                ```\n[fenced](f.md)\n```\n[web](https://example.org) [here](#top)";
    let targets: Vec<String> = link_targets(text).into_iter().map(|(_, t)| t).collect();
    assert_eq!(targets, ["a.md#x", "b c.md", "https://example.org", "#top"]);
    let file = Path::new("/book/src/page.md");
    assert_eq!(
        local_target(file, "a.md#x"),
        Some(PathBuf::from("/book/src/a.md"))
    );
    assert_eq!(local_target(file, "#top"), None);
    assert_eq!(local_target(file, "HTTPS://example.org"), None);
    assert_eq!(local_target(file, "mailto:someone@example.org"), None);
    assert_eq!(
        normalised(Path::new("/book/src/../../shared/DEPENDENCIES.md")),
        PathBuf::from("/shared/DEPENDENCIES.md")
    );
    let outside = std::env::temp_dir().join(format!("signorini-docs-{}", std::process::id()));
    fs::create_dir_all(&outside).unwrap();
    let page = root().join("docs").join("src").join("introduction.md");
    let relative = format!(
        "{}{}/page.md",
        "../".repeat(root().join("docs/src").components().count() - 1),
        outside.strip_prefix("/").unwrap().display()
    );
    fs::write(outside.join("page.md"), "").unwrap();
    let found = broken_links_in(&page, &format!("[out]({relative}) [in](first-steps.md)"));
    fs::remove_dir_all(&outside).unwrap();
    assert_eq!(found, [format!("docs/src/introduction.md:1: {relative}")]);
}
