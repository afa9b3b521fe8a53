//! `reports/README.md`, the index a person reads: one section per study with what it found, in a
//! sentence or two computed from the study's own data file, the one or two figures that show it
//! drawn inline, then links to its report, its data and every figure of its families. Built from
//! what exists under the reports directory: a study whose report is absent is left out, a report
//! or a figure is listed when its file is there (or was just written), and the finer studies, GetFEM's witness
//! and the benchmarks are linked when their directories or files are present.

use std::collections::BTreeSet;
use std::fmt::Write as _;
use std::path::Path;

use serde::de::DeserializeOwned;

use crate::harness::files::input::REPORT_DATA;
use crate::harness::run::norms::Norm;
use crate::harness::study::decision::Verdict as FindingVerdict;
use crate::harness::study::sensitivity::{Sensitivity, SensitivityClass};
use crate::harness::study::{CaseStudy, Study};
use crate::studies::cost::{CostToTarget, WorkPrecisionFile, WORK_PRECISION_JSON};
use crate::studies::elastic_study::{files as elastic_files, ElasticStudy};
use crate::studies::figures::from_reports::FIGURES_DIR;
use crate::studies::gravity;
use crate::studies::stability::{StabilityRecord, Verdict, STABILITY_JSON};
use crate::studies::tables::{OscillationRecord, RatesFile, RATES_JSON, SENSITIVITY_JSON};

/// The index of a reports directory ([`reports_index`]).
pub const REPORTS_INDEX: &str = "README.md";

/// One study's part of the index: the report that must exist for it to be listed, its title,
/// the other files it links, the figures drawn inline and the figure families it owns
/// (file-name prefix and what to look for).
struct Section {
    report: &'static str,
    title: &'static str,
    data: &'static [&'static str],
    shown: &'static [&'static str],
    families: &'static [(&'static str, &'static str)],
    headline: fn(&Path) -> Option<String>,
}

const SECTIONS: &[Section] = &[
    Section {
        report: "tables.md",
        title: "Tables 1–2 of the 1D paper (Signorini–Dirichlet)",
        data: &["rates.json", "sensitivity.md", "sensitivity.json"],
        shown: &["contact-crank-nicolson.svg", "energy-crank-nicolson.svg"],
        families: &[
            ("contact-", "the contact node's displacement and force at NX = 10, 20, 40 against the exact solution, the standard mass left, the redistributed right"),
            ("energy-", "the discrete energy against the exact 1/8"),
            ("convergence-", "errors against h (log–log) for both masses with the fitted slope; a round-off chaotic case is drawn as its ensemble's median with the min–max band"),
        ],
        headline: tables_headline,
    },
    Section {
        report: "schemes.md",
        title: "Which scheme to trust: the paper's schemes and their rivals",
        data: &["rates.json", "sensitivity.json"],
        shown: &[],
        families: &[],
        headline: schemes_headline,
    },
    Section {
        report: "gravity.md",
        title: "The bouncing bar under gravity (§4)",
        data: &["gravity/study.json", "gravity/sensitivity.json"],
        shown: &["gravity-points-redistributed.svg"],
        families: &[
            ("gravity-points-", "u at x = 0, ½, 1 computed and exact (Figure 2)"),
            ("gravity-convergence-", "the four displacement errors against h with fitted slopes (Figure 3)"),
            ("gravity-strain-", "∂x u along the bar at two times, computed and exact (Figure 4)"),
        ],
        headline: gravity_headline,
    },
    Section {
        report: "work-precision.md",
        title: "What accuracy costs",
        data: &["work-precision.json"],
        shown: &["work-precision.svg"],
        families: &[
            ("work-precision.svg", "error in L∞(0,T;H) against wall time for the paper's 14 cases: lower-left is better"),
            ("work-precision-rivals", "the same for the rivals"),
        ],
        headline: cost_headline,
    },
    Section {
        report: "stability.md",
        title: "Stability over long horizons",
        data: &["stability.json"],
        shown: &["stability-standard.svg", "stability-redistributed.svg"],
        families: &[
            ("stability-standard", "E/E₀ over 100 periods of the paper's schemes with the standard mass, one curve per scheme"),
            ("stability-redistributed", "the same with the redistributed mass"),
            ("stability-rivals-", "the same for the rivals, standard and redistributed mass"),
        ],
        headline: stability_headline,
    },
    Section {
        report: "elastic-2d.md",
        title: "The note's 2D bar against a fine-mesh reference",
        data: &["elastic-2d.json", "data/elastic-2d-histories.json"],
        shown: &["elastic-2d-contact-crank-nicolson.svg", "elastic-2d-energy-crank-nicolson.svg"],
        families: &[
            ("elastic-2d-contact-", "the centre contact node's displacement and force at the finest level beside the reference (the note's Figures 1, 6)"),
            ("elastic-2d-energy-", "the energy (Figures 2, 7)"),
            ("elastic-2d-convergence-", "errors against h with fitted slopes, both masses (Figures 3, 8)"),
            ("elastic-2d-von-mises-", "the von Mises stress along the axis over time (Figures 4–5)"),
        ],
        headline: |reports| elastic_headline(reports, 2),
    },
    Section {
        report: "elastic-3d.md",
        title: "The note's 3D bar against a fine-mesh reference",
        data: &["elastic-3d.json", "data/elastic-3d-histories.json"],
        shown: &["elastic-3d-contact-crank-nicolson.svg"],
        families: &[
            ("elastic-3d-contact-", "the centre contact node against the reference (Figures 1, 6)"),
            ("elastic-3d-energy-", "the energy (Figures 2, 7)"),
            ("elastic-3d-convergence-", "errors against h with fitted slopes (Figures 3, 8)"),
            ("elastic-3d-von-mises-", "the von Mises stress along the axis over time"),
        ],
        headline: |reports| elastic_headline(reports, 3),
    },
    Section {
        report: "extended.md",
        title: "Every mass variant and contact treatment",
        data: &["extended.json"],
        shown: &[],
        families: &[],
        headline: extended_headline,
    },
    Section {
        report: "defaults-experiment.md",
        title: "How the rates move with the horizon and the levels",
        data: &[],
        shown: &[],
        families: &[],
        headline: |_| None,
    },
];

/// What else a reports directory may hold, linked when present: (path, what it is).
const ELSEWHERE: &[(&str, &str)] = &[
    (
        "getfem.md",
        "GetFEM's 1D demo solved again by the harness and compared step by step",
    ),
    (
        "getfem-verify/verify.md",
        "the demo's runs verified as external runs (`signorini verify`)",
    ),
    (
        "fine/README.md",
        "the finer 2D/3D studies (`make report-fine`)",
    ),
    (
        "finest/README.md",
        "the 3D study against a reference on 640 elements (`make report-finest`)",
    ),
    (
        "league.md",
        "every external run set verified side by side (`make league`)",
    ),
    ("bench.md", "the speed and memory figures (`make bench`)"),
];

/// The index of `reports`; `drawn`: the figures just drawn into it, and `pages`: the pages just
/// written into it (each listed whether or not the directory already holds it).
pub fn reports_index(reports: &Path, drawn: &[String], pages: &[&str]) -> String {
    let mut figures: BTreeSet<String> = drawn.iter().cloned().collect();
    if let Ok(entries) = std::fs::read_dir(reports.join(FIGURES_DIR)) {
        figures.extend(entries.filter_map(|e| {
            let name = e.ok()?.file_name().into_string().ok()?;
            name.ends_with(".svg").then_some(name)
        }));
    }
    let mut md = String::from(
        "# Reports\n\nWhat each study found, the figure that shows it, and every file it wrote. \
         `make report` regenerates the tables, the 2D/3D studies and the figures; `make \
         stability`, `make report-fine`, `make report-finest`, `make verify-getfem` and `make \
         bench` the rest.\n",
    );
    let listed = |s: &&Section| pages.contains(&s.report) || reports.join(s.report).is_file();
    for s in SECTIONS.iter().filter(listed) {
        let _ = write!(md, "\n## {}\n\n", s.title);
        if let Some(headline) = (s.headline)(reports) {
            let _ = writeln!(md, "{headline}\n");
        }
        for shown in s.shown.iter().filter(|f| figures.contains(**f)) {
            let _ = writeln!(
                md,
                "![{}]({FIGURES_DIR}/{shown})\n",
                shown.trim_end_matches(".svg")
            );
        }
        let mut files = vec![link(s.report)];
        files.extend(
            s.data
                .iter()
                .filter(|d| reports.join(d).is_file())
                .map(|d| link(d)),
        );
        let _ = writeln!(md, "Report and data: {}.", files.join(", "));
        let families: Vec<String> = s
            .families
            .iter()
            .filter_map(|(prefix, caption)| {
                let mine: Vec<String> = figures
                    .iter()
                    .filter(|f| f.starts_with(prefix))
                    .map(|f| format!("[{}]({FIGURES_DIR}/{f})", f.trim_end_matches(".svg")))
                    .collect();
                (!mine.is_empty()).then(|| format!("- {caption}: {}\n", mine.join(" ")))
            })
            .collect();
        if !families.is_empty() {
            let _ = write!(md, "\n{}", families.concat());
        }
    }
    let present: Vec<&(&str, &str)> = ELSEWHERE
        .iter()
        .filter(|(path, _)| reports.join(path).is_file())
        .collect();
    if !present.is_empty() {
        md.push_str("\n## Elsewhere in this directory\n\n");
        for (path, what) in present {
            let _ = writeln!(md, "- {}: {what}", link(path));
        }
    }
    md
}

/// `[path](path)`.
fn link(path: &str) -> String {
    format!("[{path}]({path})")
}

/// A study's data file under `reports`, when it is there and reads.
fn data<T: DeserializeOwned>(reports: &Path, file: &str) -> Option<T> {
    crate::harness::files::artifacts::read_json(&reports.join(file), REPORT_DATA).ok()
}

/// The rate of `norm` in `case` with its 95 % interval, e.g. `0.98 [0.91, 1.05]`.
fn rate_with_interval(case: &CaseStudy, norm: Norm) -> Option<String> {
    let fit = case.norm(norm)?.fit?;
    Some(match (fit.ci_low, fit.ci_high) {
        (Some(low), Some(high)) => format!("{:.2} [{low:.2}, {high:.2}]", fit.rate),
        _ => format!("{:.2}", fit.rate),
    })
}

fn tables_headline(reports: &Path) -> Option<String> {
    let rates: RatesFile = data(reports, RATES_JSON)?;
    let in_the_paper: Vec<&OscillationRecord> = rates
        .oscillations
        .iter()
        .filter(|o| o.paper_word.is_some())
        .collect();
    let compared = in_the_paper.len() * rates.study.norms.len();
    let agreeing_words = in_the_paper
        .iter()
        .filter(|o| o.word == o.paper_word)
        .count();
    let mut text = format!(
        "{} of the {compared} rates (case × norm) are not shown to agree with the paper's \
         within 0.1 (their 95 % interval lies outside the paper's value ± 0.1 or overlaps an \
         end); `tables.md` gives each verdict and diagnoses it, with its rate over the longer \
         horizon T = {}. The \
         oscillation column agrees with the paper's in {agreeing_words} of {} cases.",
        rates.longer_horizon_rates.len(),
        rates.longer_horizon,
        in_the_paper.len()
    );
    if let Some(s) = data::<Sensitivity>(reports, SENSITIVITY_JSON) {
        let chaotic: Vec<&str> = s
            .cases
            .iter()
            .filter(|c| c.class == SensitivityClass::Chaotic)
            .map(|c| c.case.as_str())
            .collect();
        let _ = write!(
            text,
            " Round-off chaotic ({} members per ensemble): {} (their rates are ensemble ranges, \
             marked † in the tables).",
            s.ensemble.members,
            if chaotic.is_empty() {
                "none".to_string()
            } else {
                chaotic.join(", ")
            }
        );
    }
    Some(text)
}

fn gravity_headline(reports: &Path) -> Option<String> {
    let study: Study = data(
        reports,
        &format!("{}/{}", gravity::GRAVITY_DIR, gravity::STUDY_JSON),
    )?;
    let rates: Vec<String> = study
        .cases
        .iter()
        .filter_map(|c| {
            let rate = rate_with_interval(c, Norm::DisplacementLinfH)?;
            Some(format!("{} {rate}", c.case.mass))
        })
        .collect();
    Some(format!(
        "The displacement's rate in L∞(0,T;H) with its 95 % interval, {}: {}.",
        study
            .cases
            .first()
            .map_or(String::new(), |c| c.case.scheme.to_string()),
        rates.join("; ")
    ))
}

fn schemes_headline(reports: &Path) -> Option<String> {
    let rates: RatesFile = data(reports, RATES_JSON)?;
    let calm: Vec<&str> = rates
        .oscillations
        .iter()
        .filter(|o| o.word.as_deref() == Some("No"))
        .map(|o| o.case.as_str())
        .collect();
    Some(format!(
        "{} of the {} scheme × mass cases (the paper's and the rivals') show no contact-force \
         oscillation at the finest level: {}. `schemes.md` ranks every case on each criterion \
         and says which orders the intervals decide.",
        calm.len(),
        rates.oscillations.len(),
        calm.join(", ")
    ))
}

fn cost_headline(reports: &Path) -> Option<String> {
    let file: WorkPrecisionFile = data(reports, WORK_PRECISION_JSON)?;
    let measured = |c: &&CostToTarget| !c.extrapolated && c.seconds.is_some();
    let target = file
        .cost_to_target
        .iter()
        .filter(measured)
        .map(|c| c.target)
        .min_by(f64::total_cmp)?;
    let cheapest = file
        .cost_to_target
        .iter()
        .filter(measured)
        .filter(|c| c.target == target)
        .filter_map(|c| Some((c.seconds?, c.case.as_str())))
        .min_by(|a, b| a.0.total_cmp(&b.0))?;
    Some(format!(
        "The smallest error in {} that a case reaches within its measured levels is {target:.0e}; \
         the cheapest to reach it is {} ({:.3} s of wall time on the machine that wrote the \
         report).",
        file.cost_to_target_norm.label(),
        cheapest.1,
        cheapest.0
    ))
}

fn stability_headline(reports: &Path) -> Option<String> {
    let records: Vec<StabilityRecord> = data(reports, STABILITY_JSON)?;
    let hard: BTreeSet<&str> = records.iter().map(|r| r.hard_case.as_str()).collect();
    let per_mass = |mass: &str| {
        let runs: Vec<&StabilityRecord> = records
            .iter()
            .filter(|r| r.case.ends_with(&format!("/{mass}")))
            .collect();
        let kept = runs
            .iter()
            .filter(|r| {
                matches!(
                    r.shared_verdict(),
                    Some(Verdict::Stable | Verdict::Dissipative)
                )
            })
            .count();
        let undecided = runs.iter().filter(|r| r.shared_verdict().is_none()).count();
        match undecided {
            0 => format!("{mass} mass {kept} of {}", runs.len()),
            u => format!("{mass} mass {kept} of {} ({u} undecided)", runs.len()),
        }
    };
    Some(format!(
        "Runs judged stable or dissipative, with every member of their round-off ensemble, on \
         the {} hard cases: {}, {}; `stability.md` gives every verdict and the round-off \
         ensemble's.",
        hard.len(),
        per_mass("standard"),
        per_mass("redistributed")
    ))
}

/// The reports directories that commit a 2D/3D study, relative to the top one: `make
/// report`'s, `make report-fine`'s and `make report-finest`'s.
const ELASTIC_STUDY_DIRS: [&str; 3] = [".", "fine", "finest"];

/// A committed study's strength: its reference level, then its finest level, then how many
/// levels it fits (the larger, the finer the reference and the level range).
fn strength(study: &ElasticStudy) -> (usize, usize, usize) {
    let levels = &study.config.levels;
    (
        study.config.reference_level,
        levels.last().copied().unwrap_or(0),
        levels.len(),
    )
}

/// The strongest of `studies` (by [`strength`]; the first of equals).
fn strongest<'s>(studies: &'s [(&'s str, ElasticStudy)]) -> Option<&'s (&'s str, ElasticStudy)> {
    studies
        .iter()
        .rev()
        .max_by_key(|(_, study)| strength(study))
}

/// `dir/elastic-<d>d.md` as a link from the top reports directory.
fn study_link(dir: &str, dimension: usize) -> String {
    let file = elastic_files::report_file(dimension);
    if dir == "." {
        link(&file)
    } else {
        link(&format!("{dir}/{file}"))
    }
}

/// The committed `dimension`-D studies under `reports` and its finer studies' directories,
/// with the directory each is in.
fn committed_studies(reports: &Path, dimension: usize) -> Vec<(&'static str, ElasticStudy)> {
    ELASTIC_STUDY_DIRS
        .iter()
        .filter_map(|dir| {
            let study = data(&reports.join(dir), &elastic_files::study_file(dimension))?;
            Some((*dir, study))
        })
        .collect()
}

/// Each finding of the `dimension`-D studies: the strongest study's verdict, then every
/// study's, one column per directory.
fn findings_table(studies: &[(&str, ElasticStudy)], dimension: usize) -> Option<String> {
    let (best_dir, best) = strongest(studies)?;
    let mut md = format!(
        "Each finding of the note with the verdict of the strongest study that tested it (finest \
         reference and levels: {}, levels {:?} against {} elements), then every study's.\n\n\
         | finding | strongest study |",
        study_link(best_dir, dimension),
        best.config.levels,
        best.config.reference_level
    );
    for (dir, study) in studies {
        let _ = write!(
            md,
            " {} (levels {:?}, reference {}) |",
            study_link(dir, dimension),
            study.config.levels,
            study.config.reference_level
        );
    }
    let _ = write!(md, "\n|---|---|{}\n", "---|".repeat(studies.len()));
    for finding in &best.findings {
        let _ = write!(md, "| {} | {} |", finding.claim, finding.verdict.word());
        for (_, study) in studies {
            let verdict = study
                .findings
                .iter()
                .find(|f| f.claim == finding.claim)
                .map_or("—", |f| f.verdict.word());
            let _ = write!(md, " {verdict} |");
        }
        md.push('\n');
    }
    Some(md.trim_end().to_string())
}

fn elastic_headline(reports: &Path, dimension: usize) -> Option<String> {
    let study: ElasticStudy = data(reports, &elastic_files::study_file(dimension))?;
    let count = |v: FindingVerdict| study.findings.iter().filter(|f| f.verdict == v).count();
    let mut text = format!(
        "{} cases on levels {:?} against a reference on {} elements along the axis. Of the \
         note's {} findings tested, decided by their rates' 95 % intervals widened by the \
         reference's rate-bias bounds: {} hold, {} fail, {} are undecided; \
         `elastic-{dimension}d.md` gives each verdict with what decided it or would.",
        study.study.cases.len(),
        study.config.levels,
        study.config.reference_level,
        study.findings.len(),
        count(FindingVerdict::Holds),
        count(FindingVerdict::Fails),
        count(FindingVerdict::Undecided)
    );
    if let Some(table) = findings_table(&committed_studies(reports, dimension), dimension) {
        let _ = write!(text, "\n\n{table}");
    }
    Some(text)
}

fn extended_headline(reports: &Path) -> Option<String> {
    let file: serde_json::Value = data(reports, "extended.json")?;
    let count = |field: &str| file.get(field)?.as_array().map(Vec::len);
    Some(format!(
        "{} scheme × mass × contact-treatment rows; {} of them oscillate at the finest level.",
        count("rows")?,
        count("oscillating")?
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The committed 3D study, its findings judged by the current rule.
    fn committed_3d() -> ElasticStudy {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("reports/elastic-3d.json");
        let mut value: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
        value["findings"] = serde_json::json!([]);
        let mut study: ElasticStudy = serde_json::from_value(value).unwrap();
        study.findings = study.judged_findings();
        study
    }

    /// `base` with other levels and reference, every finding given `verdict`.
    fn variant(
        base: &ElasticStudy,
        levels: &[usize],
        reference_level: usize,
        verdict: FindingVerdict,
    ) -> ElasticStudy {
        let mut study = base.clone();
        study.config.levels = levels.to_vec();
        study.config.reference_level = reference_level;
        for f in &mut study.findings {
            f.verdict = verdict;
        }
        study
    }

    #[test]
    fn the_index_gives_each_finding_the_verdict_of_the_strongest_study() {
        let base = committed_3d();
        let studies = vec![
            (
                ".",
                variant(&base, &[10, 20, 40], 160, FindingVerdict::Undecided),
            ),
            (
                "fine",
                variant(&base, &[10, 20, 40, 80], 320, FindingVerdict::Fails),
            ),
            (
                "finest",
                variant(&base, &[10, 20, 40, 80, 160], 640, FindingVerdict::Holds),
            ),
        ];
        assert_eq!(strongest(&studies).unwrap().0, "finest");
        let table = findings_table(&studies, 3).unwrap();
        assert!(
            table.contains(
                "[finest/elastic-3d.md](finest/elastic-3d.md), levels [10, 20, 40, 80, 160]"
            ),
            "{table}"
        );
        for f in &base.findings {
            let row = format!("| {} | holds | undecided | fails | holds |", f.claim);
            assert!(table.contains(&row), "{row} missing:\n{table}");
        }
        let same_reference = vec![
            (
                "fine",
                variant(&base, &[10, 20, 40], 320, FindingVerdict::Fails),
            ),
            (
                ".",
                variant(&base, &[10, 20, 40, 80], 320, FindingVerdict::Holds),
            ),
        ];
        assert_eq!(
            strongest(&same_reference).unwrap().0,
            ".",
            "with equal references, the finer level range"
        );
    }
}
