//! `signorini league`: the verifications under a directory side by side. A bar entry (two
//! contact traces) and a box entry (GetFEM's 2D runs at levels 10 and 20) give one row per
//! series with what the files declare, the rates with their intervals, the oscillation word and
//! the energy verdict; a directory without entries is refused.

use std::path::{Path, PathBuf};

use super::verify_box::{read_json, s, scene_at_levels, scratch};
use crate::common::{expect_error, signorini, success_stdout};

const TRACE4: &str = "tests/data/external/contact-trace-nx4.csv";
const TRACE8: &str = "tests/data/external/contact-trace-nx8.csv";

/// GetFEM's 2D runs in the box form, written into `out`.
fn getfem_2d(out: &Path) -> Vec<PathBuf> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut runs: Vec<PathBuf> = std::fs::read_dir(root.join("tests/data/getfem2d"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.to_string_lossy().ends_with(".json.gz"))
        .collect();
    runs.sort();
    let mut args = vec!["getfem-box"];
    args.extend(runs.iter().map(|p| s(p)));
    args.extend(["--out", s(out)]);
    success_stdout(&signorini(&args))
        .lines()
        .map(PathBuf::from)
        .collect()
}

#[test]
fn the_league_puts_every_verification_under_a_directory_side_by_side() {
    let dir = scratch("league");
    let entries = dir.join("entries");
    success_stdout(&signorini(&[
        "verify",
        "scenes/bar1d-dirichlet.json",
        TRACE4,
        TRACE8,
        "--out",
        s(&entries.join("traces")),
    ]));
    let scene = scene_at_levels(&dir, "scenes/bar2d.json", &[10, 20]);
    let files = getfem_2d(&dir.join("getfem"));
    let mut args = vec!["verify", s(&scene)];
    args.extend(files.iter().map(|p| s(p)));
    let cache = dir.join("references");
    let out = entries.join("getfem-2d");
    args.extend(["--cache", s(&cache), "--out", s(&out)]);
    success_stdout(&signorini(&args));
    let reports = dir.join("reports");
    let said = success_stdout(&signorini(&["league", s(&entries), "--out", s(&reports)]));
    assert!(said.contains("2 entries, 5 series"), "{said}");
    let league = read_json(&reports.join("league.json"));
    assert_eq!(league["format"], "signorini-league/1");
    let names: Vec<&str> = league["entries"]
        .as_array()
        .unwrap()
        .iter()
        .map(|e| e["entry"].as_str().unwrap())
        .collect();
    assert_eq!(names, ["getfem-2d", "traces"], "by name");
    let getfem = &league["entries"][0];
    let verified = read_json(&out.join("verify.json"));
    assert_eq!(
        getfem["rows"].as_array().unwrap().len(),
        verified["series"].as_array().unwrap().len()
    );
    assert_eq!(
        getfem["findings"], verified["findings"],
        "the findings as verify judged them"
    );
    let across = &league["findings"][0];
    assert_eq!(across["entries"], serde_json::json!(["getfem-2d"]));
    assert_eq!(
        across["findings"], verified["findings"],
        "one entry: the findings across entries are verify's"
    );
    for row in getfem["rows"].as_array().unwrap() {
        let label = row["label"].as_str().unwrap();
        let declared = &row["declared"];
        assert!(
            label.contains(declared["scheme"].as_str().unwrap())
                && label.contains(declared["mass"].as_str().unwrap()),
            "{label}: {declared}"
        );
        assert!(declared["contact"].as_str().unwrap().contains("Alart"));
        assert_eq!(row["levels"], serde_json::json!([10, 20]));
        let lambda = &row["rates"][0];
        assert_eq!(lambda["norm"], "lambda_L2", "{row}");
        assert!(lambda["ci_low"].is_null(), "two levels: no interval");
        assert_eq!(
            lambda["bias"], verified["rate_bias"]["lambda_L2"],
            "the reference's bias bound"
        );
        assert!(row["not_computed"].to_string().contains("energy_Linf"));
        assert_eq!(row["energy_verdict"], "undecided");
        assert!(row["energy_reason"]
            .as_str()
            .unwrap()
            .contains("not computed"));
    }
    let traces = &league["entries"][1]["rows"][0];
    assert!(traces["declared"].is_object());
    for rate in traces["rates"].as_array().unwrap() {
        assert_eq!(rate["bias"], 0.0, "an exact solution has no bias");
    }
    let md = std::fs::read_to_string(reports.join("league.md")).unwrap();
    // Each row links to its entry's verify.md from where league.md is.
    assert!(md.contains("| [getfem-2d](../entries/getfem-2d/verify.md) | GetFEM 5.4.2"));
    assert!(md.contains("| [traces](../entries/traces/verify.md) | hand-copied 1 |"));
    assert!(md.contains("## The note's findings: GetFEM 5.4.2"));
}

#[test]
fn a_league_without_entries_is_refused() {
    let dir = scratch("league-empty");
    expect_error(
        &["league", s(&dir), "--out", s(&dir.join("out"))],
        2,
        &["holds no <entry>/verify.json", "signorini verify"],
    );
    assert!(!dir.join("out").exists(), "nothing is written");
}

/// An edit of a verify.json.
type Edit = dyn Fn(&mut serde_json::Value);

/// An entry edited after `verify` is refused, naming the file and the field: a rate typed in
/// (9.5 where its own errors fit 0.62), a negative error, a verify.json that is a directory.
#[test]
fn a_league_entry_that_is_not_what_verify_wrote_is_refused() {
    let committed = Path::new("reports/league/dolfinx-2d-backward-euler-standard/verify.json");
    let text = std::fs::read_to_string(committed).unwrap();
    let cases: [(&str, &Edit, &[&str]); 2] = [
        (
            "typed-rate",
            &|v| v["series"][0]["rates"][0]["fit"]["rate"] = 9.5.into(),
            &[
                "series[0].rates[u_Linf_H].fit",
                "9.5",
                "the fit of its own errors",
            ],
        ),
        (
            "negative-error",
            &|v| v["series"][0]["rates"][1]["errors"][2] = (-1e-3).into(),
            &["series[0].rates[", ".errors", "-0.001", "not negative"],
        ),
    ];
    for (name, edit, needles) in cases {
        let dir = scratch(&format!("league-{name}"));
        let entry = dir.join("entries/edited");
        std::fs::create_dir_all(&entry).unwrap();
        let mut v: serde_json::Value = serde_json::from_str(&text).unwrap();
        edit(&mut v);
        std::fs::write(entry.join("verify.json"), v.to_string()).unwrap();
        expect_error(
            &[
                "league",
                s(&dir.join("entries")),
                "--out",
                s(&dir.join("out")),
            ],
            2,
            needles,
        );
        assert!(!dir.join("out").exists(), "{name}: nothing is written");
    }
    let dir = scratch("league-directory");
    std::fs::create_dir_all(dir.join("entries/odd/verify.json")).unwrap();
    expect_error(
        &[
            "league",
            s(&dir.join("entries")),
            "--out",
            s(&dir.join("out")),
        ],
        2,
        &["verify.json"],
    );
}

/// The committed reports/league.md and league.json are what `signorini league` writes from the
/// committed entries under reports/league/ (`make league` is their only writer).
#[test]
fn the_committed_league_is_rendered_from_its_entries() {
    let dir = scratch("league-committed");
    success_stdout(&signorini(&["league", "reports/league", "--out", s(&dir)]));
    // The rows link to the entries from where league.md is: reports/league/… from reports/.
    let away = std::fs::read_to_string(dir.join("league.md")).unwrap();
    let first_link = away.split("](").nth(1).unwrap().split(')').next().unwrap();
    let entries = format!(
        "{}/",
        Path::new(first_link)
            .parent()
            .and_then(Path::parent)
            .unwrap()
            .display()
    );
    for file in ["league.md", "league.json"] {
        let committed = std::fs::read_to_string(Path::new("reports").join(file)).unwrap();
        let written = std::fs::read_to_string(dir.join(file))
            .unwrap()
            .replace(&format!("]({entries}"), "](league/");
        assert!(
            committed == written,
            "reports/{file} is not what make league writes"
        );
    }
}

#[test]
fn every_link_of_the_committed_league_resolves() {
    let md = std::fs::read_to_string("reports/league.md").unwrap();
    let links: Vec<&str> = md
        .split("](")
        .skip(1)
        .filter_map(|rest| rest.split(')').next())
        .filter(|link| !link.starts_with("http"))
        .collect();
    assert!(links.len() >= 43, "{} links", links.len());
    let broken: Vec<&&str> = links
        .iter()
        .filter(|link| !Path::new("reports").join(link).exists())
        .collect();
    assert!(
        broken.is_empty(),
        "links of reports/league.md that resolve to nothing: {broken:?}"
    );
}

/// The harness's own runs in the committed league, exported through `.pvd` and verified, have
/// the rates of the committed 2D/3D studies to the bits (both come from the same runs against
/// the same cached reference), and the note's findings judged across those entries are the
/// studies' own, verdict, reason and evidence.
#[test]
fn the_harness_league_entries_have_the_committed_studies_rates() {
    let league = read_json(Path::new("reports/league.json"));
    let mut compared = 0;
    for d in [2, 3] {
        let study = read_json(Path::new(&format!("reports/elastic-{d}d.json")));
        let judged = league["findings"]
            .as_array()
            .unwrap()
            .iter()
            .find(|f| f["code"]["name"] == "signorini" && f["scene"] == format!("bar{d}d"))
            .expect("the harness's findings across its entries");
        let mut expected = study["findings"].clone();
        for finding in expected.as_array_mut().unwrap() {
            let evidence = finding["evidence"].as_str().unwrap().to_string();
            let without = evidence.split("; physics: ").next().unwrap().to_string();
            finding["evidence"] = serde_json::Value::String(without);
        }
        assert_eq!(judged["findings"], expected, "{d}D findings");
        let cases = study["study"]["cases"].as_array().unwrap();
        let prefix = format!("signorini-{d}d-");
        let entries = league["entries"].as_array().unwrap();
        for entry in entries.iter().filter(|e| {
            e["entry"]
                .as_str()
                .is_some_and(|name| name.starts_with(&prefix))
        }) {
            let row = &entry["rows"][0];
            let crank_nicolson = row["declared"]["scheme"] == "crank-nicolson";
            let case = cases
                .iter()
                .find(|c| {
                    c["case"]["mass"] == row["declared"]["mass"]
                        && (c["case"]["scheme"]["family"] == "newmark") == crank_nicolson
                })
                .unwrap_or_else(|| panic!("the study has the case of {}", entry["entry"]));
            for rate in row["rates"].as_array().unwrap() {
                let theirs = case["rates"]
                    .as_array()
                    .unwrap()
                    .iter()
                    .find(|r| r["norm"] == rate["norm"])
                    .unwrap();
                assert_eq!(
                    theirs["fit"]["rate"], rate["rate"],
                    "{} {}",
                    entry["entry"], rate["norm"]
                );
                compared += 1;
            }
        }
    }
    assert_eq!(compared, 2 * 4 * 7, "every norm of the 8 entries");
}

/// `rejudge` of a committed 2D study whose errors were cut shorter than its levels, or made
/// negative, is refused naming the field (it panicked on the first), and the study is kept; the
/// study as committed is judged again.
#[test]
fn rejudge_refuses_a_study_that_is_not_what_study_wrote() {
    let committed = std::fs::read_to_string("reports/elastic-2d.json").unwrap();
    let edits: [(&str, &Edit, &str); 2] = [
        (
            "short",
            &|v| {
                let errors = v["study"]["cases"][0]["rates"][0]["errors"].as_array_mut();
                errors.unwrap().truncate(2);
            },
            "study.cases[0].rates[u_Linf_H].errors = 2 errors",
        ),
        (
            "negative",
            &|v| v["study"]["cases"][1]["rates"][2]["errors"][1] = (-0.5).into(),
            "not negative",
        ),
    ];
    for (name, edit, needle) in edits {
        let dir = scratch(&format!("rejudge-{name}"));
        let mut v: serde_json::Value = serde_json::from_str(&committed).unwrap();
        edit(&mut v);
        let text = v.to_string();
        std::fs::write(dir.join("elastic-2d.json"), &text).unwrap();
        expect_error(
            &["rejudge", "scenes/bar2d.json", "--out", s(&dir)],
            2,
            &["elastic-2d.json", needle],
        );
        let kept = std::fs::read_to_string(dir.join("elastic-2d.json")).unwrap();
        assert_eq!(kept, text, "{name}: the study is kept");
    }
    // The study as committed, with the entry of reports/'s manifest that proves it the
    // harness's (rejudge rewrites it in place, as make rejudge does).
    let dir = scratch("rejudge-committed");
    std::fs::write(dir.join("elastic-2d.json"), &committed).unwrap();
    let manifest = ".signorini-manifest.json";
    let mut proof: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(Path::new("reports").join(manifest)).unwrap(),
    )
    .unwrap();
    let entry = proof["files"]["elastic-2d.json"].clone();
    assert!(entry.is_string(), "reports/ records elastic-2d.json");
    proof["files"] = serde_json::json!({ "elastic-2d.json": entry });
    proof.as_object_mut().unwrap().remove("created");
    std::fs::write(dir.join(manifest), proof.to_string()).unwrap();
    success_stdout(&signorini(&[
        "rejudge",
        "scenes/bar2d.json",
        "--out",
        s(&dir),
    ]));
}

/// An entry whose verify.json was edited after `verify` wrote it (its manifest not updated) is
/// warned about; an entry as written is not (issue 55 item 4).
#[test]
fn an_entry_edited_after_verify_is_warned_about() {
    let dir = std::env::temp_dir().join(format!("signorini-league-edited-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let entries = dir.join("entries");
    std::fs::create_dir_all(&entries).unwrap();
    let entry = entries.join("getfem-1d");
    std::fs::create_dir_all(&entry).unwrap();
    let source = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("reports/league/getfem-1d");
    for name in ["verify.json", ".signorini-manifest.json"] {
        std::fs::copy(source.join(name), entry.join(name)).unwrap();
    }
    let league = |out: &str| {
        let out = dir.join(out);
        crate::common::signorini(&[
            "league",
            &entries.to_string_lossy(),
            "--out",
            &out.to_string_lossy(),
        ])
    };
    let as_written = league("a");
    assert!(as_written.status.success());
    assert!(!String::from_utf8_lossy(&as_written.stderr).contains("warning"));
    let text = std::fs::read_to_string(entry.join("verify.json")).unwrap();
    std::fs::write(entry.join("verify.json"), format!(" {text}")).unwrap();
    let edited = league("b");
    assert!(edited.status.success());
    let stderr = String::from_utf8_lossy(&edited.stderr);
    assert!(
        stderr.contains("getfem-1d/verify.json: not as `signorini verify` wrote it"),
        "{stderr}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}
