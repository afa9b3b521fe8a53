//! `reports/README.md`, the index a person reads, and `reports/gallery.md`, every figure.
//!
//! The index gives each study one section: what it found, in a sentence computed from the
//! study's own data file, the one figure that shows it drawn inline, and links to its report and
//! data; the figures of its families are listed in the gallery, not in the index. Both are built
//! from what exists under the reports directory: a study whose report is absent is left out, a
//! report or a figure is listed when its file is there (or was just written), and the finer
//! studies, GetFEM's witness, the league, the cluster plan and the benchmarks are linked when
//! their files are present. A directory that holds 2D/3D studies only (`make report-fine`'s
//! `reports/fine/`, `make report-finest`'s `reports/finest/`) is titled after its studies and
//! points to the top index instead of repeating its preamble.

use std::collections::BTreeSet;
use std::fmt::Write as _;
use std::path::Path;

use serde::de::DeserializeOwned;

use crate::harness::files::input::REPORT_DATA;
use crate::harness::run::norms::Norm;
use crate::harness::study::decision::Verdict as FindingVerdict;
use crate::harness::study::sensitivity::{Sensitivity, SensitivityClass};
use crate::harness::study::{CaseStudy, Study};
use crate::harness::vocabulary::AGREES_WITHIN;
use crate::studies::cost::{
    cheapest_sentence, CostToTarget, WorkPrecisionFile, WORK_PRECISION_JSON,
};
use crate::studies::elastic_study::{files as elastic_files, ElasticStudy};
use crate::studies::figures::from_reports::FIGURES_DIR;
use crate::studies::gravity;
use crate::studies::league::League;
use crate::studies::stability::{StabilityRecord, Verdict, STABILITY_JSON};
use crate::studies::tables::{OscillationRecord, RatesFile, RATES_JSON, SENSITIVITY_JSON};

/// The index of a reports directory ([`reports_index`]).
pub const REPORTS_INDEX: &str = "README.md";

/// The figure gallery of a reports directory ([`figure_gallery`]).
pub const FIGURE_GALLERY: &str = "gallery.md";

/// One study's part of the index: the report that must exist for it to be listed, its title,
/// the other files it links, the files it writes that are not committed (named, never linked:
/// a clone does not have them), the figure drawn inline and the figure families it owns
/// (file-name prefix and what they show).
struct Section {
    report: &'static str,
    title: &'static str,
    data: &'static [&'static str],
    uncommitted: &'static [&'static str],
    shown: Option<&'static str>,
    families: &'static [(&'static str, &'static str)],
    headline: fn(&Path) -> Option<String>,
}

impl Section {
    /// Whether the study is a 2D/3D bar's (the only kind a finer study's directory holds,
    /// beside the cost page built from it).
    fn is_elastic(&self) -> bool {
        self.report.starts_with("elastic-") || self.report == "work-precision.md"
    }
}

const SECTIONS: &[Section] = &[
    Section {
        report: "tables.md",
        title: "Tables 1–2 of the 1D paper (Signorini–Dirichlet)",
        data: &["rates.json", "sensitivity.md", "sensitivity.json"],
        uncommitted: &[],
        shown: Some("contact-crank-nicolson.svg"),
        families: &[
            ("contact-", "The contact node's displacement and force at NX = 10, 20, 40 against the exact solution, the standard mass left, the redistributed right, one figure per scheme"),
            ("energy-", "The discrete energy against the exact 1/8, one figure per scheme"),
            ("convergence-", "Errors against h (log–log) for both masses, one figure per scheme and norm; a round-off chaotic case is drawn as its ensemble's median with the min–max band"),
        ],
        headline: tables_headline,
    },
    Section {
        report: "schemes.md",
        title: "Which scheme to trust: the paper's schemes and their rivals",
        data: &["rates.json", "sensitivity.json"],
        uncommitted: &[],
        shown: None,
        families: &[],
        headline: schemes_headline,
    },
    Section {
        report: "gravity.md",
        title: "The bouncing bar under gravity (§4)",
        data: &["gravity/study.json", "gravity/sensitivity.json"],
        uncommitted: &[],
        shown: Some("gravity-points-redistributed.svg"),
        families: &[
            ("gravity-points-", "The displacement u at x = 0, ½, 1 computed and exact (Figure 2), one figure per mass"),
            ("gravity-convergence-", "The four displacement errors against h (Figure 3), one figure per mass"),
            ("gravity-strain-", "The strain ∂x u along the bar at two times, computed and exact (Figure 4), one figure per mass"),
        ],
        headline: gravity_headline,
    },
    Section {
        report: "work-precision.md",
        title: "What accuracy costs",
        data: &["work-precision.json"],
        uncommitted: &[],
        shown: Some("work-precision.svg"),
        families: &[
            ("work-precision.svg", "The error in L∞(0,T;H) against wall time for the paper's 14 cases: lower-left is better"),
            ("work-precision-rivals", "The same for the rivals"),
        ],
        headline: cost_headline,
    },
    Section {
        report: "stability.md",
        title: "Stability over long horizons",
        data: &["stability.json"],
        uncommitted: &[],
        shown: Some("stability-standard.svg"),
        families: &[
            ("stability-standard", "The energy ratio E/E₀ over 100 periods of the paper's schemes with the standard mass, one curve per scheme"),
            ("stability-redistributed", "The same with the redistributed mass"),
            ("stability-rivals-", "The same for the rivals, one figure per mass"),
        ],
        headline: stability_headline,
    },
    Section {
        report: "elastic-2d.md",
        title: "The note's 2D bar against a fine-mesh reference",
        data: &["elastic-2d.json"],
        uncommitted: &["data/elastic-2d-histories.json"],
        shown: Some("elastic-2d-contact-crank-nicolson.svg"),
        families: &[
            ("elastic-2d-contact-", "The centre contact node's displacement and force at the finest level beside the reference (the note's Figures 1, 6), one figure per scheme"),
            ("elastic-2d-energy-", "The energy (Figures 2, 7), one figure per scheme"),
            ("elastic-2d-convergence-", "Errors against h, both masses (Figures 3, 8), one figure per scheme and norm"),
            ("elastic-2d-von-mises-", "The von Mises stress along the axis over time (Figures 4–5), one figure per scheme"),
        ],
        headline: |reports| elastic_headline(reports, 2),
    },
    Section {
        report: "elastic-3d.md",
        title: "The note's 3D bar against a fine-mesh reference",
        data: &["elastic-3d.json"],
        uncommitted: &["data/elastic-3d-histories.json"],
        shown: Some("elastic-3d-contact-crank-nicolson.svg"),
        families: &[
            ("elastic-3d-contact-", "The centre contact node against the reference (Figures 1, 6), one figure per scheme"),
            ("elastic-3d-energy-", "The energy (Figures 2, 7), one figure per scheme"),
            ("elastic-3d-convergence-", "Errors against h (Figures 3, 8), one figure per scheme and norm"),
            ("elastic-3d-von-mises-", "The von Mises stress along the axis over time, one figure per scheme"),
        ],
        headline: |reports| elastic_headline(reports, 3),
    },
    Section {
        report: "extended.md",
        title: "Every mass variant and contact treatment",
        data: &["extended.json"],
        uncommitted: &[],
        shown: None,
        families: &[],
        headline: extended_headline,
    },
    Section {
        report: "league.md",
        title: "Other codes' runs, verified side by side",
        data: &["league.json"],
        uncommitted: &[],
        shown: None,
        families: &[],
        headline: league_headline,
    },
    Section {
        report: "defaults-experiment.md",
        title: "How the rates move with the horizon and the levels",
        data: &[],
        uncommitted: &[],
        shown: None,
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
        "cluster/cluster-plan.md",
        "how many MPI ranks and nodes the largest 3D reference needs (`make cluster-plan`)",
    ),
    ("bench.md", "the speed and memory figures (`make bench`)"),
];

/// The figures of `reports`: those under its figures directory and those just `drawn`.
fn figures_of(reports: &Path, drawn: &[String]) -> BTreeSet<String> {
    let mut figures: BTreeSet<String> = drawn.iter().cloned().collect();
    if let Ok(entries) = std::fs::read_dir(reports.join(FIGURES_DIR)) {
        figures.extend(entries.filter_map(|e| {
            let name = e.ok()?.file_name().into_string().ok()?;
            name.ends_with(".svg").then_some(name)
        }));
    }
    figures
}

/// The sections of `reports` whose report is there or among the `pages` just written.
fn listed_sections<'a>(
    reports: &'a Path,
    pages: &'a [&str],
) -> impl Iterator<Item = &'static Section> + 'a {
    SECTIONS
        .iter()
        .filter(move |s| pages.contains(&s.report) || reports.join(s.report).is_file())
}

/// The members of the figure family `prefix` among `figures`.
fn family<'f>(figures: &'f BTreeSet<String>, prefix: &'f str) -> impl Iterator<Item = &'f String> {
    figures.iter().filter(move |f| f.starts_with(prefix))
}

/// The title and preamble of the index: the top one's, or for a directory of 2D/3D studies
/// only, a title naming its bars and references and a pointer to the top index when its
/// parent has one.
fn heading(reports: &Path, sections: &[&Section], gallery: bool) -> String {
    let gallery_note = if gallery {
        format!(" Every figure, by study, is in [{FIGURE_GALLERY}]({FIGURE_GALLERY}).")
    } else {
        String::new()
    };
    let studies: Vec<(usize, ElasticStudy)> = [2, 3]
        .into_iter()
        .filter_map(|d| Some((d, data(reports, &elastic_files::study_file(d))?)))
        .collect();
    if studies.is_empty() || !sections.iter().all(|s| s.is_elastic()) {
        return format!(
            "# Reports\n\nWhat each study found, in a sentence computed from its data, with the \
             figure that shows it and a link to its report.{gallery_note} `make report` \
             regenerates the tables, the 2D/3D studies and the figures; `make stability`, `make \
             report-fine`, `make report-finest`, `make verify-getfem` and `make bench` the \
             rest.\n"
        );
    }
    let title = match studies.as_slice() {
        [(d, study)] => format!(
            "The {d}D bar against a reference on {} elements",
            study.config.reference_level
        ),
        _ => {
            let bars: Vec<String> = studies.iter().map(|(d, _)| format!("{d}D")).collect();
            let references: Vec<String> = studies
                .iter()
                .map(|(d, s)| format!("{} ({d}D)", s.config.reference_level))
                .collect();
            format!(
                "The {} bars against references on {} elements",
                bars.join(" and "),
                references.join(" and ")
            )
        }
    };
    let top = match reports.parent() {
        Some(parent) if parent.join(REPORTS_INDEX).is_file() => format!(
            " The [top index](../{REPORTS_INDEX}) gives every study and sets these verdicts \
             beside the other studies' of the same bar."
        ),
        _ => String::new(),
    };
    format!(
        "# {title}\n\nWhat each study of this directory found, with the figure that shows it and \
         a link to its report.{gallery_note}{top}\n"
    )
}

/// The index of `reports`; `drawn`: the figures just drawn into it, and `pages`: the pages just
/// written into it (each listed whether or not the directory already holds it; the gallery is
/// linked when it is among them or there).
pub fn reports_index(reports: &Path, drawn: &[String], pages: &[&str]) -> String {
    let figures = figures_of(reports, drawn);
    let sections: Vec<&Section> = listed_sections(reports, pages).collect();
    let gallery = pages.contains(&FIGURE_GALLERY) || reports.join(FIGURE_GALLERY).is_file();
    let mut md = heading(reports, &sections, gallery);
    for s in &sections {
        let _ = write!(md, "\n## {}\n\n", s.title);
        if let Some(headline) = (s.headline)(reports) {
            let _ = writeln!(md, "{headline}\n");
        }
        if let Some(shown) = s.shown.filter(|f| figures.contains(*f)) {
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
        let _ = write!(md, "Report and data: {}.", files.join(", "));
        let uncommitted: Vec<String> = s.uncommitted.iter().map(|d| format!("`{d}`")).collect();
        if !uncommitted.is_empty() {
            let _ = write!(
                md,
                " The figures' data, {}, is written beside them by the study and not committed.",
                uncommitted.join(", ")
            );
        }
        let owned: usize = s
            .families
            .iter()
            .map(|(prefix, _)| family(&figures, prefix).count())
            .sum();
        if gallery && owned > 0 {
            let _ = write!(
                md,
                " Its {owned} figure{}: [{FIGURE_GALLERY}]({FIGURE_GALLERY}).",
                if owned == 1 { "" } else { "s" }
            );
        }
        md.push('\n');
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

/// The gallery of `reports`: every figure of each listed study's families, under the study's
/// title, one line per figure, or a table of scheme × norm for a family drawn per norm;
/// `None` when no study has a figure. `drawn` and `pages` as for [`reports_index`].
pub fn figure_gallery(reports: &Path, drawn: &[String], pages: &[&str]) -> Option<String> {
    let figures = figures_of(reports, drawn);
    let mut md = format!(
        "# Figure gallery\n\nEvery figure of this directory, by study; [{REPORTS_INDEX}]({REPORTS_INDEX}) \
         says what each study found.\n"
    );
    let mut any = false;
    for s in listed_sections(reports, pages) {
        let families: Vec<String> = s
            .families
            .iter()
            .filter_map(|(prefix, caption)| {
                let members: Vec<&String> = family(&figures, prefix).collect();
                (!members.is_empty()).then(|| family_block(prefix, caption, &members))
            })
            .collect();
        if families.is_empty() {
            continue;
        }
        any = true;
        let _ = write!(
            md,
            "\n## {}\n\nReport: {}.\n\n{}",
            s.title,
            link(s.report),
            families.join("\n")
        );
    }
    any.then_some(md)
}

/// A figure family in the gallery: its caption, then a scheme × norm table when every member's
/// name ends in a norm (`PREFIX<scheme>-<norm>.svg`), else one line per figure, named by what
/// follows the prefix.
fn family_block(prefix: &str, caption: &str, members: &[&String]) -> String {
    let figure = |f: &str| {
        let stem = f.trim_end_matches(".svg");
        let label = stem
            .strip_prefix(prefix)
            .filter(|l| !l.is_empty())
            .unwrap_or(stem);
        format!("[{label}]({FIGURES_DIR}/{f})")
    };
    let split: Option<Vec<(&str, Norm, &String)>> = members
        .iter()
        .map(|f| {
            let stem = f.strip_prefix(prefix)?.strip_suffix(".svg")?;
            let (scheme, norm) = stem.rsplit_once('-')?;
            Some((scheme, norm.parse().ok()?, *f))
        })
        .collect();
    let mut md = format!("{caption}:\n\n");
    match split {
        Some(cells) => {
            let norms: Vec<Norm> = Norm::ALL
                .into_iter()
                .filter(|n| cells.iter().any(|c| c.1 == *n))
                .collect();
            let mut schemes: Vec<&str> = Vec::new();
            for (scheme, _, _) in &cells {
                if !schemes.contains(scheme) {
                    schemes.push(scheme);
                }
            }
            let header: Vec<String> = norms.iter().map(|n| n.to_string()).collect();
            let _ = writeln!(
                md,
                "| scheme | {} |\n|---|{}",
                header.join(" | "),
                "---|".repeat(norms.len())
            );
            for scheme in schemes {
                let row: Vec<String> = norms
                    .iter()
                    .map(|n| {
                        cells
                            .iter()
                            .find(|c| c.0 == scheme && c.1 == *n)
                            .map_or("—".to_string(), |c| {
                                format!("[svg]({FIGURES_DIR}/{})", c.2)
                            })
                    })
                    .collect();
                let _ = writeln!(md, "| {scheme} | {} |", row.join(" | "));
            }
        }
        None => {
            for f in members {
                let _ = writeln!(md, "- {}", figure(f));
            }
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
         within {AGREES_WITHIN} (their 95 % interval lies outside the paper's value ± \
         {AGREES_WITHIN} or overlaps an end); `tables.md` gives each verdict and diagnoses it, with its rate over the longer \
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
    let mut schemes: Vec<(String, Vec<String>)> = Vec::new();
    for case in &study.cases {
        let Some(rate) = rate_with_interval(case, Norm::DisplacementLinfH) else {
            continue;
        };
        let label = case.case.scheme.label();
        let entry = format!("{} {rate}", case.case.mass);
        match schemes.iter_mut().find(|(l, _)| *l == label) {
            Some((_, rates)) => rates.push(entry),
            None => schemes.push((label, vec![entry])),
        }
    }
    let rates: Vec<String> = schemes
        .iter()
        .map(|(label, rates)| format!("{label}: {}", rates.join(", ")))
        .collect();
    Some(format!(
        "The displacement's rate in L∞(0,T;H) against the exact solution, with its 95 % \
         interval, per scheme and mass: {}.",
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
    let norm = file.cost_to_target_norm;
    let (smallest, smallest_case, smallest_seconds) = file
        .work_precision
        .iter()
        .filter(|w| w.norm == norm)
        .flat_map(|w| {
            w.errors
                .iter()
                .zip(&w.seconds)
                .map(move |(e, s)| (*e, w.case.as_str(), *s))
        })
        .min_by(|a, b| a.0.total_cmp(&b.0))?;
    let mut targets: Vec<f64> = file.cost_to_target.iter().map(|c| c.target).collect();
    targets.sort_by(|a, b| b.total_cmp(a));
    targets.dedup();
    let measured = |c: &&CostToTarget| !c.extrapolated && c.seconds.is_some();
    let target = file
        .cost_to_target
        .iter()
        .filter(measured)
        .map(|c| c.target)
        .min_by(f64::total_cmp)?;
    let reaching: Vec<&CostToTarget> = file
        .cost_to_target
        .iter()
        .filter(measured)
        .filter(|c| c.target == target)
        .collect();
    let targets: Vec<String> = targets.iter().map(|t| format!("{t:.0e}")).collect();
    Some(format!(
        "The smallest error in {} measured is {smallest:.2e} ({smallest_case}, \
         {smallest_seconds:.2} s, the median of its runs); of the error targets {}, the smallest \
         that a case reaches within its measured levels is {target:.0e}, and of the {} cases \
         that reach it, {} (`work-precision.md`: the estimated wall time to reach it over the \
         runs of each level, median [min, max], on the machine that wrote the report; one case \
         is cheaper than another only when its interval lies wholly below).",
        norm.label(),
        targets.join(", "),
        reaching.len(),
        cheapest_sentence(&reaching)
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
/// study's, one column per directory; `None` for fewer than two studies (the headline gives
/// one study's counts).
fn findings_table(studies: &[(&str, ElasticStudy)], dimension: usize) -> Option<String> {
    if studies.len() < 2 {
        return None;
    }
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

fn league_headline(reports: &Path) -> Option<String> {
    let league: League = data(reports, "league.json")?;
    let rows: Vec<_> = league.entries.iter().flat_map(|e| &e.rows).collect();
    let mut codes: Vec<String> = Vec::new();
    for row in &rows {
        let name = format!("{} {}", row.code.name, row.code.version);
        if !codes.contains(&name) {
            codes.push(name);
        }
    }
    let energy = |v: FindingVerdict| rows.iter().filter(|r| r.energy_verdict == v).count();
    let calm = rows
        .iter()
        .filter(|r| r.oscillation.as_deref() == Some("No"))
        .count();
    let findings: Vec<_> = league.findings.iter().flat_map(|c| &c.findings).collect();
    let judged = |v: FindingVerdict| findings.iter().filter(|f| f.verdict == v).count();
    Some(format!(
        "{} refinement series in {} run sets, from {}: the energy error converges in {} series, \
         does not in {} and is undecided in {}; {calm} show no contact-force oscillation. Of the \
         papers' findings judged on each code's series of a scene ({} code × scene pairs): {} \
         hold, {} fail, {} are undecided; `league.md` gives every rate and verdict with its \
         reason.",
        rows.len(),
        league.entries.len(),
        codes.join(", "),
        energy(FindingVerdict::Holds),
        energy(FindingVerdict::Fails),
        energy(FindingVerdict::Undecided),
        league.findings.len(),
        judged(FindingVerdict::Holds),
        judged(FindingVerdict::Fails),
        judged(FindingVerdict::Undecided)
    ))
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
