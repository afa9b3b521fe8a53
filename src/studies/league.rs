//! The league table (`signorini league`, `make league`): every verification kept under one
//! directory (`<dir>/<entry>/verify.json`, as `signorini verify --out <dir>/<entry>` writes
//! it) side by side, one row per refinement series: the code and version, the scheme, mass
//! and contact treatment the files declare, the levels, the rates with their 95 % intervals,
//! the oscillation indicator's verdict, the energy verdict; and the note's findings judged on
//! every series of one code on one scene together, across its entries.
//!
//! The energy verdict is "the energy error converges" (`energy_Linf`'s rate above 0,
//! [`vocabulary::converges`]), decided by [`crate::harness::study::decision`]: the rate's interval widened by the reference's
//! rate-bias bound (0 against an exact solution, the entry's `rate_bias` against a fine-mesh
//! reference) must lie above 0 to hold, at or below it to fail; otherwise it is undecided and
//! says what would decide it. The oscillation verdict is the indicator's word as measured (an
//! indicator has no interval).
//!
//! `league.json` (format `signorini-league/1`): `format`; `findings`, one per code, scene and
//! mesh kind with a declared case (`scene`, `code`, `own_mesh`, `entries`, `findings`); `entries`, one per directory, each
//! with `entry` (the directory's name), `scene`, `reference`, `findings` (as in verify.json) and
//! `rows`, one per series: `label`, `code`, `declared` (`scheme`, `mass`, `contact`, each
//! omitted when not declared), `levels` (NX), `rates` (per computed norm: `norm`, `rate`,
//! `ci_low`, `ci_high` (null with fewer than three levels), `levels`, `bias`), `not_computed`
//! (norm keys), `oscillation_indicator` and `oscillation` (the word, null without λ),
//! `energy_verdict` (`holds`, `fails`, `undecided`), `energy_reason`, and
//! `differs_from_declared` (present only when its files part from the harness's run of their
//! declared scheme and mass beyond round-off: the largest difference).

use std::fmt::Write as _;

use serde::{Deserialize, Serialize};

use super::elastic_study::external::{caveats_list, JudgedVerification};
use super::elastic_study::findings::{findings_of_cases, Finding};
use super::elastic_study::report::findings_table;
use crate::harness::external::format::Code;
use crate::harness::external::rerun::StepDifferences;
use crate::harness::external::verify::own_mesh::own_mesh_caveats;
use crate::harness::external::verify::{declared_cases, Declared, Series};
use crate::harness::render::report::table_text;
use crate::harness::run::norms::Norm;
use crate::harness::study::decision::{Estimate, Verdict};
use crate::harness::study::verdicts::{oscillation_ratio_text, oscillation_word};
use crate::harness::study::{Case, CaseStudy};
use crate::harness::vocabulary::{self, convergence_word};

/// `league.json`'s format.
pub const LEAGUE_FORMAT: &str = "signorini-league/1";

/// The norms the markdown table shows (league.json has every computed norm).
const SHOWN: [Norm; 4] = [
    Norm::DisplacementLinfH,
    Norm::DisplacementL2V,
    Norm::MultiplierL2,
    Norm::EnergyLinf,
];

/// One norm's rate in a row.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct LeagueRate {
    /// The norm.
    pub norm: Norm,
    /// The least-squares rate over the series' levels.
    pub rate: f64,
    /// The 95 % interval's lower end (null with fewer than three levels).
    pub ci_low: Option<f64>,
    /// Its upper end.
    pub ci_high: Option<f64>,
    /// The levels fitted.
    pub levels: usize,
    /// The reference's rate-bias bound (0 for an exact solution; null: unbounded).
    pub bias: Option<f64>,
}

/// One series of one entry.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct LeagueRow {
    /// The series' label.
    pub label: String,
    /// The code and its version.
    pub code: Code,
    /// What the files declare.
    pub declared: Declared,
    /// `NX` of each level.
    pub levels: Vec<usize>,
    /// The computed norms' rates.
    pub rates: Vec<LeagueRate>,
    /// The norms not computed (keys).
    pub not_computed: Vec<String>,
    /// `TV(λ_h) / TV(λ)` on the finest level.
    pub oscillation_indicator: Option<f64>,
    /// Its word (`No`, `Small`, `Yes`, `Big`).
    pub oscillation: Option<String>,
    /// "The energy error converges".
    pub energy_verdict: Verdict,
    /// Why.
    pub energy_reason: String,
    /// The largest difference between its files and the harness's run of what they declare,
    /// when that is beyond round-off: the series does not solve its declared scheme and mass.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub differs_from_declared: Option<f64>,
}

/// One directory's verification.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct LeagueEntry {
    /// The directory's name.
    pub entry: String,
    /// The scene.
    pub scene: String,
    /// What the errors are measured against.
    pub reference: String,
    /// The note's findings judged on its series (box scenes).
    pub findings: Vec<Finding>,
    /// One row per series.
    pub rows: Vec<LeagueRow>,
}

/// The note's findings on one code's series of one scene, across the entries that hold them.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CodeFindings {
    /// The scene.
    pub scene: String,
    /// The code and its version.
    pub code: Code,
    /// Whether these series are on the code's own mesh (`signorini verify`'s own-mesh path:
    /// triangles, tetrahedra, `--own-mesh`): judged apart from the same code's series on the
    /// scene's mesh, since their displacement errors carry their own bound.
    #[serde(default)]
    pub own_mesh: bool,
    /// The entries whose series were judged together.
    pub entries: Vec<String>,
    /// The findings.
    pub findings: Vec<Finding>,
    /// What the findings rest on when the series are on the code's own mesh
    /// ([`own_mesh_caveats`]); empty otherwise.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub caveats: Vec<String>,
}

/// `league.json`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct League {
    /// [`LEAGUE_FORMAT`].
    pub format: String,
    /// One per entry directory, by name.
    pub entries: Vec<LeagueEntry>,
    /// The note's findings per code and scene, across entries.
    pub findings: Vec<CodeFindings>,
}

impl League {
    /// The league of the verifications `read`, one entry per `(name, verification)`, in the
    /// order given.
    pub fn of(read: &[(String, JudgedVerification)]) -> Self {
        Self {
            format: LEAGUE_FORMAT.to_string(),
            entries: read.iter().map(|(name, v)| entry(name, v)).collect(),
            findings: findings_by_code(read),
        }
    }
}

/// The reference's rate-bias bound of `norm` in `v`: 0 against an exact solution (a bar's
/// verification has no `rate_bias`), the recorded bound against a fine-mesh reference (`None`:
/// unbounded or not formed).
fn bias(v: &JudgedVerification, norm: Norm) -> Option<f64> {
    match &v.rate_bias {
        None => Some(0.0),
        Some(map) => map.get(norm.key()).copied().flatten(),
    }
}

fn entry(name: &str, v: &JudgedVerification) -> LeagueEntry {
    let bias = |norm: Norm| bias(v, norm);
    let rows = v.series.iter().map(|s| row(s, &bias)).collect();
    LeagueEntry {
        entry: name.to_string(),
        scene: v.scene.clone(),
        reference: v.reference.clone(),
        findings: v.judgement.findings.clone().unwrap_or_default(),
        rows,
    }
}

/// Whether a series was measured on its own mesh (any of its runs was).
fn on_own_mesh(s: &Series) -> bool {
    s.runs.iter().any(|r| r.own_mesh.is_some())
}

/// The note's findings judged on every series of one code on one scene, across the entries
/// (the first series of each declared scheme × mass), each rate's interval widened by the bias
/// bound of the entry its series comes from (that entry's largest over the cases it declares;
/// the harness's entries declare one case each); codes without a declared case have none. A
/// code's series on its own mesh are judged apart from its series on the scene's mesh.
fn findings_by_code(files: &[(String, JudgedVerification)]) -> Vec<CodeFindings> {
    let mut keys: Vec<(String, Code, bool)> = Vec::new();
    for (_, v) in files {
        for s in &v.series {
            let key = (v.scene.clone(), s.code.clone(), on_own_mesh(s));
            if !keys.contains(&key) {
                keys.push(key);
            }
        }
    }
    keys.into_iter()
        .filter_map(|(scene, code, own_mesh)| {
            let mut entries = Vec::new();
            let mut series: Vec<Series> = Vec::new();
            let mut holders: Vec<(Vec<Case>, &JudgedVerification)> = Vec::new();
            for (name, v) in files.iter().filter(|(_, v)| v.scene == scene) {
                let own: Vec<Series> = v
                    .series
                    .iter()
                    .filter(|s| s.code == code && on_own_mesh(s) == own_mesh)
                    .cloned()
                    .collect();
                let declared: Vec<Case> = declared_cases(&own).iter().map(|c| c.case).collect();
                if !declared.is_empty() {
                    entries.push(name.clone());
                    holders.push((declared, v));
                    series.extend(own);
                }
            }
            let cases = declared_cases(&series);
            if cases.is_empty() {
                return None;
            }
            // A case's rate is widened by the bound of the entry whose series it is (the first
            // that declares it, as `declared_cases` keeps the first series of each case).
            let bias = |c: &CaseStudy, norm: Norm| -> Option<f64> {
                holders
                    .iter()
                    .find(|(declared, _)| declared.contains(&c.case))
                    .and_then(|(_, v)| bias(v, norm))
            };
            Some(CodeFindings {
                scene,
                code,
                own_mesh,
                entries,
                findings: findings_of_cases(&cases, &bias),
                caveats: own_mesh_caveats(&series),
            })
        })
        .collect()
}

fn row(s: &Series, bias: &dyn Fn(Norm) -> Option<f64>) -> LeagueRow {
    let rates = s
        .rates
        .iter()
        .filter_map(|r| {
            let fit = r.fit?;
            Some(LeagueRate {
                norm: r.norm,
                rate: fit.rate,
                ci_low: fit.ci_low,
                ci_high: fit.ci_high,
                levels: fit.levels,
                bias: bias(r.norm),
            })
        })
        .collect();
    let energy = vocabulary::converges(&Estimate::rate(
        format!("{} rate", Norm::EnergyLinf.key()),
        s.norm(Norm::EnergyLinf).and_then(|r| r.fit),
        bias(Norm::EnergyLinf),
    ));
    let indicator = s.oscillation_indicator();
    LeagueRow {
        label: s.label.clone(),
        code: s.code.clone(),
        declared: s.declared.clone(),
        levels: s.levels.iter().map(|l| l.nx).collect(),
        rates,
        not_computed: s
            .not_computed
            .iter()
            .map(|n| n.norm.key().to_string())
            .collect(),
        oscillation_indicator: indicator,
        oscillation: indicator.map(|r| oscillation_word(r).to_string()),
        energy_verdict: energy.verdict,
        energy_reason: energy.reason,
        differs_from_declared: s.differs_from_declared().map(StepDifferences::largest),
    }
}

/// A rate as the table shows it: `r [low, high]`, `r (n levels)` without an interval, `—`
/// when not computed.
fn rate_cell(row: &LeagueRow, norm: Norm) -> String {
    match row.rates.iter().find(|r| r.norm == norm) {
        None => "—".to_string(),
        Some(r) => match r.ci_low.zip(r.ci_high) {
            Some((low, high)) => format!("{:.2} [{low:.2}, {high:.2}]", r.rate),
            None => format!("{:.2} ({} levels)", r.rate, r.levels),
        },
    }
}

/// `league.md`, each row linked to its entry's `verify.md` under `entries` (the entries'
/// directory as the prefix of a link from where `league.md` is written: empty, or ending in
/// `/`).
pub fn render(league: &League, entries: &str) -> String {
    let mut out = String::new();
    let _ = writeln!(
        out,
        "# The league table\n\nEvery external run set verified side by side (`make league`; \
         your own code: docs/src/external-runs.md, \"The league table\"). One row per \
         refinement series. Rates: the least-squares rate over the series' levels with its \
         95 % interval (`(n levels)` without one: an interval needs three; `—` not computed). \
         Energy: \"the energy error converges\", decided by the interval of the \
         `{}` rate widened by the reference's rate-bias bound (*converges* above 0, *does not \
         converge* at or below, *undecided* when it straddles: docs/src/vocabulary.md). \
         Oscillations: the indicator's grade (No, Small, Yes, Big) on the finest level, from \
         one run: as measured.\n",
        Norm::EnergyLinf.key()
    );
    let names: Vec<&str> = SHOWN.iter().map(|n| n.key()).collect();
    let _ = writeln!(
        out,
        "| entry | code | series | scheme | mass | contact | levels | {} | oscillations | \
         energy |\n|---|---|---|---|---|---|---|{}---|---|",
        names.join(" | "),
        "---|".repeat(SHOWN.len())
    );
    let declared = |d: &Option<String>| d.as_deref().map_or("not declared".into(), table_text);
    for e in &league.entries {
        for r in &e.rows {
            let levels: Vec<String> = r.levels.iter().map(usize::to_string).collect();
            let rates: Vec<String> = SHOWN.iter().map(|&n| rate_cell(r, n)).collect();
            let oscillation = r.oscillation_indicator.map_or("—".to_string(), |i| {
                format!("{} ({})", oscillation_word(i), oscillation_ratio_text(i))
            });
            let word = convergence_word(r.energy_verdict);
            let energy = match r.energy_verdict {
                Verdict::Holds => word.to_string(),
                Verdict::Fails => format!("**{word}**"),
                Verdict::Undecided => format!("*{word}*"),
            };
            let _ = writeln!(
                out,
                "| [{}]({entries}{}/verify.md) | {} {} | {} | {} | {} | {} | {} | {} | \
                 {oscillation} | {energy} |",
                table_text(&e.entry),
                e.entry,
                table_text(&r.code.name),
                table_text(&r.code.version),
                table_text(&r.label),
                declared(&r.declared.scheme)
                    + &r.differs_from_declared.map_or(String::new(), |d| {
                        format!(" (**its files differ from it: {d:.1e}**)")
                    }),
                declared(&r.declared.mass),
                declared(&r.declared.contact),
                levels.join(", "),
                rates.join(" | ")
            );
        }
    }
    let _ = writeln!(out, "\n## Against what\n");
    for e in &league.entries {
        let _ = writeln!(out, "- `{}`: scene `{}`, {}", e.entry, e.scene, e.reference);
    }
    let _ = writeln!(out, "\n## The energy verdicts' reasons\n");
    for e in &league.entries {
        for r in &e.rows {
            let _ = writeln!(
                out,
                "- `{}` {}: {}: {}",
                e.entry,
                table_text(&r.label),
                convergence_word(r.energy_verdict),
                r.energy_reason
            );
        }
    }
    for f in &league.findings {
        let entries: Vec<String> = f.entries.iter().map(|e| format!("`{e}`")).collect();
        let _ = writeln!(
            out,
            "\n## The note's findings: {} {} on `{}`{}\n\nJudged on the series of {} together \
             (each rate's interval widened by the largest bias bound among them).\n\n{}",
            table_text(&f.code.name),
            table_text(&f.code.version),
            f.scene,
            match f.own_mesh {
                true => ", on its own mesh",
                false => "",
            },
            entries.join(", "),
            findings_table(&f.findings)
        );
        out.push_str(&caveats_list(&f.caveats));
    }
    out
}
