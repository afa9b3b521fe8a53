//! Issue 11's extended table: the Signorini–Dirichlet benchmark (1D paper §5) with
//! Crank–Nicolson and backward Euler, every mass variant ([`MassVariant::ON_EVERY_MESH`]) and every contact
//! treatment of [`TREATMENTS`], one refinement study per treatment. Per row (treatment, scheme,
//! mass) it reports the seven least-squares rates, the oscillation indicator and an
//! [`EnergyVerdict`]; the golden file [`ExtendedGolden`] gates it like Tables 1–2. Its files:
//! `extended.md`, `extended.json` ([`ExtendedFile`]) and [`GOLDEN_EXTENDED`].

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;
use std::str::FromStr;

use serde::{Deserialize, Serialize};

use crate::harness::files::artifacts::{read_json, write_atomic, write_json};
use crate::harness::files::input::GOLDEN_FILE;
use crate::harness::problem::{ContactTreatment, MassVariant, Problem1d, Scheme};
use crate::harness::reference::exact::{run_study, ExactSolution};
use crate::harness::run::norms::Norm;
use crate::harness::study::decision::{Estimate, Verdict};
use crate::harness::study::executor::Batch;
use crate::harness::study::golden::{check_values, Golden, Tolerances};
use crate::harness::study::sensitivity::{
    run_sensitivity, EnsembleConfig, Sensitivity, SensitivityClass, SensitivityJobs, Spread,
};
use crate::harness::study::verdicts::{oscillates, oscillation_word, OSCILLATES_FROM};
use crate::harness::study::{Case, CaseStudy, Study, StudyConfig};
use crate::harness::vocabulary::{self, wholly_above, BOUNDED_RATE_WITHIN, CONVERGES_ABOVE};
use crate::studies::benchmark::dirichlet;
use crate::studies::error::Error;

/// The golden file of the extended table, relative to the repository root.
pub const GOLDEN_EXTENDED: &str = "golden/rates-1d-extended.json";

/// The table, under a reports directory.
pub const EXTENDED_MD: &str = "extended.md";

/// [`ExtendedFile`], under a reports directory.
pub const EXTENDED_JSON: &str = "extended.json";

/// The contact treatments of the table, as [`ContactTreatment::from_str`] parses them.
pub const TREATMENTS: [&str; 5] = [
    "multiplier",
    "penalty(gamma0=10)",
    "nitsche(theta=-1,gamma0=10)",
    "nitsche(theta=0,gamma0=10)",
    "nitsche(theta=1,gamma0=10)",
];

/// The schemes of the table.
pub const SCHEMES: [Scheme; 2] = [Scheme::CRANK_NICOLSON, Scheme::BACKWARD_EULER];

/// The study of one contact treatment.
#[derive(Debug, Clone, PartialEq)]
pub struct ExtendedStudy {
    /// The treatment's name (one of [`TREATMENTS`]).
    pub contact: String,
    /// Its study: [`SCHEMES`] × [`MassVariant::ON_EVERY_MESH`], all seven norms.
    pub study: Study,
    /// The round-off sensitivity of its cases, when measured ([`ExtendedStudy::with_sensitivity`]).
    pub sensitivity: Option<Sensitivity>,
}

impl ExtendedStudy {
    /// The study with the round-off sensitivity of all its cases measured
    /// ([`extended_sensitivity`]); `root` is the repository root.
    pub fn with_sensitivity(self, root: &Path) -> Result<Self, Error> {
        let cases: Vec<Case> = self.study.cases.iter().map(|c| c.case).collect();
        let sensitivity = extended_sensitivity(root, &self.contact, &cases)?;
        Ok(Self {
            sensitivity: Some(sensitivity),
            ..self
        })
    }
}

/// The levels, ratio and horizon of the extended studies: those of Tables 1–2
/// ([`StudyConfig::paper_default`]).
pub fn extended_config() -> StudyConfig {
    StudyConfig::paper_default()
}

/// The cases of one treatment's study: every scheme of [`SCHEMES`] with every mass variant.
pub fn extended_cases() -> Vec<Case> {
    Case::matrix(&SCHEMES, &MassVariant::ON_EVERY_MESH)
}

/// The Signorini–Dirichlet benchmark (its scene under the repository root `root`) on the
/// horizon of [`extended_config`] with the contact treatment named `contact` (one of
/// [`TREATMENTS`]).
pub fn extended_problem(root: &Path, contact: &str) -> Result<Problem1d, Error> {
    let mut problem = dirichlet(root, extended_config().horizon)?;
    problem.contact = ContactTreatment::from_str(contact)?;
    Ok(problem)
}

/// Runs one study per treatment of [`TREATMENTS`] on the Signorini–Dirichlet benchmark with
/// [`extended_config`] and [`extended_cases`], all seven norms; `root` is the repository root.
pub fn extended_studies(root: &Path) -> Result<Vec<ExtendedStudy>, Error> {
    let config = extended_config();
    let norms: BTreeSet<Norm> = Norm::ALL.into_iter().collect();
    let cases = extended_cases();
    TREATMENTS
        .into_iter()
        .map(|name| {
            Ok(ExtendedStudy {
                contact: name.to_string(),
                study: run_study(&extended_problem(root, name)?, &cases, &norms, &config)?,
                sensitivity: None,
            })
        })
        .collect()
}

/// The round-off sensitivity (`crate::harness::study::sensitivity`, default ensemble) of `cases` under the
/// treatment `contact`, on the extended studies' levels with all seven norms: what `make report`
/// classifies the rows by and what the gate holds the chaotic ones to. `root` is the repository
/// root.
pub fn extended_sensitivity(
    root: &Path,
    contact: &str,
    cases: &[Case],
) -> Result<Sensitivity, Error> {
    Ok(run_sensitivity(
        &extended_problem(root, contact)?,
        cases,
        &Norm::ALL.into_iter().collect(),
        &extended_config(),
        EnsembleConfig::default(),
    )?)
}

/// What the energy error does under refinement, in the words of
/// [`crate::harness::vocabulary`], decided by the interval of the least-squares rate `r` of
/// `‖E_h − E‖_{L∞(0,T)}` over all levels (its 95 % interval; for a round-off chaotic row, the
/// ensemble's `[min, max]` joined with its members' own 95 % intervals, as the tables' agreement
/// ([`crate::studies::tables::agreement`]); the exact solution is the reference, so no bias bound widens it:
/// [`crate::harness::study::decision`]) and its value `e` on the finest level:
/// * `converges`: the interval lies above [`CONVERGES_ABOVE`] = 0 and `e` is finite;
/// * `does not converge`: the interval lies at or below 0, or `e` is not finite; then, by the
///   same interval, *bounded* when it lies within `±`[`BOUNDED_RATE_WITHIN`] (the error stays
///   about the size it has: the report prints `e / E_0`, so that a bounded error as large as
///   the energy does not read as good), *grows* when it lies at or below
///   `−BOUNDED_RATE_WITHIN` (or `e` is not finite), neither when it overlaps that end;
/// * `undecided`: the interval contains 0, or there is none.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum EnergyVerdict {
    /// The energy error decreases with the mesh size.
    Converges,
    /// It does not decrease, and neither decreases nor increases markedly.
    Bounded,
    /// It increases with refinement (or is not finite).
    Grows,
    /// It does not decrease; whether it grows is undecided.
    DoesNotConverge,
    /// The rate's interval contains 0: whether it converges is undecided.
    Undecided,
}

impl EnergyVerdict {
    /// The verdict on the energy-error rate `rate` and the finest-level energy error (see the
    /// type), with what decided it or what would.
    pub fn decide(rate: &Estimate, finest_error: f64) -> (Self, String) {
        if !finest_error.is_finite() {
            return (
                Self::Grows,
                format!("the finest-level energy error is {finest_error}"),
            );
        }
        let converges = vocabulary::converges(rate);
        match converges.verdict {
            Verdict::Holds => return (Self::Converges, converges.reason),
            Verdict::Undecided => return (Self::Undecided, converges.reason),
            Verdict::Fails => {}
        }
        let grows = vocabulary::grows(rate);
        if grows.verdict == Verdict::Holds {
            return (Self::Grows, grows.reason);
        }
        let bounded = vocabulary::bounded(rate);
        match bounded.verdict {
            Verdict::Holds => (Self::Bounded, bounded.reason),
            Verdict::Fails | Verdict::Undecided => (
                Self::DoesNotConverge,
                format!("{}; {}", converges.reason, bounded.reason),
            ),
        }
    }

    /// The word in the markdown table (a bounded error's size follows it there).
    pub fn word(self) -> &'static str {
        match self {
            Self::Converges => "converges",
            Self::Bounded => "does not converge (bounded)",
            Self::Grows => "does not converge (grows)",
            Self::DoesNotConverge => "does not converge",
            Self::Undecided => "undecided",
        }
    }
}

/// One row of the extended table.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ExtendedRow {
    /// The contact treatment's name.
    pub contact: String,
    /// The scheme's name.
    pub scheme: String,
    /// The mass variant's name.
    pub mass: &'static str,
    /// The round-off class of the case, when its sensitivity was measured.
    pub class: Option<SensitivityClass>,
    /// Norm key → least-squares rate over all levels (`None` when the fit is undefined); for a
    /// round-off chaotic case, the ensemble median rate.
    pub rates: BTreeMap<&'static str, Option<f64>>,
    /// A round-off chaotic case's norm key → ensemble spread of the rate (empty otherwise).
    #[serde(skip_serializing_if = "BTreeMap::is_empty")]
    pub rate_ranges: BTreeMap<&'static str, Spread>,
    /// `TV(λ_h)/TV(λ)` on the finest level.
    pub oscillation_indicator: Option<f64>,
    /// [`oscillation_word`] of the indicator.
    pub oscillation_word: Option<&'static str>,
    /// `‖E_h − E‖_{L∞(0,T)}` on the finest level (for a chaotic case, the ensemble median).
    pub energy_error_finest: f64,
    /// The energy at `t = 0` of the finest level's run (`E_0`, which the exact energy keeps);
    /// `None` for a study written before the runs measured it.
    pub energy_start: Option<f64>,
    /// [`EnergyVerdict::decide`] on the `energy_Linf` rate (a chaotic row: its ensemble) and
    /// `energy_error_finest`.
    pub energy_verdict: EnergyVerdict,
    /// What decided `energy_verdict`, or what would decide an undecided one.
    pub energy_verdict_reason: String,
}

impl ExtendedRow {
    /// The row of one case of a treatment's study; with its sensitivity, a round-off chaotic
    /// case's rates and finest energy error are the ensemble medians (one run is one sample).
    pub fn of(
        contact: &str,
        study: &Study,
        case: &CaseStudy,
        sensitivity: Option<&Sensitivity>,
    ) -> Self {
        let measured = sensitivity.and_then(|s| s.case(&case.case.id()));
        let chaotic = measured.filter(|s| s.chaotic);
        let rate_ranges: BTreeMap<&'static str, Spread> = Norm::ALL
            .into_iter()
            .filter_map(|n| Some((n.key(), *chaotic?.rates.get(n.key())?)))
            .collect();
        let rates: BTreeMap<&'static str, Option<f64>> = Norm::ALL
            .into_iter()
            .map(|n| {
                let rate = match chaotic {
                    Some(_) => rate_ranges.get(n.key()).map(|s| s.median),
                    None => case.norm(n).and_then(|r| r.fit).map(|f| f.rate),
                };
                (n.key(), rate)
            })
            .collect();
        let energy_key = Norm::EnergyLinf.key();
        let energy_error_finest = match chaotic {
            Some(s) => s
                .errors
                .get(energy_key)
                .and_then(|levels| levels.last())
                .map_or(f64::NAN, |e| e.median),
            None => case
                .norm(Norm::EnergyLinf)
                .and_then(|r| r.errors.last().copied())
                .unwrap_or(f64::NAN),
        };
        let energy_fit = case.norm(Norm::EnergyLinf).and_then(|r| r.fit);
        let ensemble_interval = chaotic.and_then(|s| s.rate_interval(energy_key));
        let energy_rate = match (rate_ranges.get(energy_key), ensemble_interval) {
            (Some(spread), Some(interval)) => Estimate::of_ensemble(
                format!(
                    "{energy_key} rate (ensemble median, [min, max] ∪ members' 95 % intervals)"
                ),
                spread.median,
                interval,
                energy_fit.map_or(0, |f| f.levels),
            ),
            _ => Estimate::rate(format!("{energy_key} rate"), energy_fit, Some(0.0)),
        };
        let (energy_verdict, energy_verdict_reason) =
            EnergyVerdict::decide(&energy_rate, energy_error_finest);
        let indicator = case.oscillation_indicator();
        Self {
            contact: contact.to_string(),
            scheme: case.case.scheme.name(),
            mass: case.case.mass.name(),
            class: measured.map(|s| s.class),
            energy_verdict,
            energy_verdict_reason,
            rates,
            rate_ranges,
            oscillation_indicator: indicator,
            oscillation_word: indicator.map(oscillation_word),
            energy_error_finest,
            energy_start: study
                .physics
                .get(&case.case.id())
                .and_then(|levels| levels.last())
                .map(|p| p.energy_start),
        }
    }

    /// The energy verdict as the table prints it: its word, and for a bounded error its size
    /// relative to `E_0` (`does not converge (bounded, e = 2.9 E₀)`).
    pub fn energy_verdict_text(&self) -> String {
        match (self.energy_verdict, self.energy_start) {
            (EnergyVerdict::Bounded, Some(e0)) if e0 != 0.0 => format!(
                "does not converge (bounded, e = {:.2} E₀)",
                self.energy_error_finest / e0.abs()
            ),
            (v, _) => v.word().to_string(),
        }
    }

    /// The rate of `norm`.
    pub fn rate(&self, norm: Norm) -> Option<f64> {
        self.rates.get(norm.key()).copied().flatten()
    }

    /// Whether the case is round-off chaotic.
    pub fn is_chaotic(&self) -> bool {
        self.class == Some(SensitivityClass::Chaotic)
    }
}

/// The rows of all studies: per treatment, per case in study order.
pub fn extended_rows(studies: &[ExtendedStudy]) -> Vec<ExtendedRow> {
    studies
        .iter()
        .flat_map(|s| {
            s.study
                .cases
                .iter()
                .map(|c| ExtendedRow::of(&s.contact, &s.study, c, s.sensitivity.as_ref()))
        })
        .collect()
}

/// For one scheme and norm, the row with the highest rate, and whether the rates' intervals
/// decide that it is the fastest.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Fastest {
    /// The scheme's name.
    pub scheme: String,
    /// The norm key.
    pub norm: &'static str,
    /// The contact treatment of the row with the highest rate.
    pub contact: String,
    /// The mass variant of the row with the highest rate.
    pub mass: &'static str,
    /// Its rate.
    pub rate: f64,
    /// Its rate's interval `[low, high]`: the fit's 95 % interval, or a round-off chaotic row's
    /// ensemble `[min, max]`; `None` without one.
    pub interval: Option<(f64, f64)>,
    /// "This row is the fastest": `holds` when its interval lies wholly above every other row's
    /// of the scheme, `undecided` otherwise.
    pub verdict: Verdict,
    /// What decided it, or the rows whose intervals it does not clear.
    pub reason: String,
    /// The rows (`mass/contact`) no other row's interval lies wholly above, the fastest among
    /// them: the row alone when the verdict holds.
    pub candidates: Vec<String>,
}

/// A row's rate of one norm with its interval, for [`fastest`].
struct RateOf {
    contact: String,
    mass: &'static str,
    rate: f64,
    interval: Option<(f64, f64)>,
}

impl RateOf {
    /// `mass/contact`.
    fn name(&self) -> String {
        format!("{}/{}", self.mass, self.contact)
    }

    /// `0.98 [0.95, 1.01]`, or `0.98 (no interval)`.
    fn text(&self) -> String {
        match self.interval {
            Some((low, high)) => format!("{:.2} [{low:.2}, {high:.2}]", self.rate),
            None => format!("{:.2} (no interval)", self.rate),
        }
    }

    /// Whether `self`'s interval lies wholly above `other`'s.
    fn above(&self, other: &RateOf) -> bool {
        match (self.interval, other.interval) {
            (Some(a), Some(b)) => wholly_above(a, b),
            _ => false,
        }
    }
}

/// The rate of `norm` of every case of `study` of `scheme` with its interval: a round-off
/// chaotic case's ensemble median and `[min, max]`, else the fit's rate and 95 % interval.
fn rates_of(study: &ExtendedStudy, scheme: &str, norm: Norm) -> Vec<RateOf> {
    study
        .study
        .cases
        .iter()
        .filter(|c| c.case.scheme.name() == scheme)
        .filter_map(|c| {
            let chaotic = study
                .sensitivity
                .as_ref()
                .and_then(|s| s.case(&c.case.id()))
                .filter(|s| s.chaotic);
            let (rate, interval) = match chaotic {
                Some(s) => {
                    let spread = s.rates.get(norm.key())?;
                    (spread.median, Some((spread.min, spread.max)))
                }
                None => {
                    let fit = c.norm(norm)?.fit?;
                    (fit.rate, fit.ci_low.zip(fit.ci_high))
                }
            };
            Some(RateOf {
                contact: study.contact.clone(),
                mass: c.case.mass.name(),
                rate,
                interval,
            })
        })
        .collect()
}

/// For every scheme of [`SCHEMES`] and every norm, the row of `studies` with the highest defined
/// rate (the first one on ties) and whether it is decidedly the fastest: its interval wholly
/// above every other row's (a row without an interval is never cleared).
pub fn fastest(studies: &[ExtendedStudy]) -> Vec<Fastest> {
    let mut out = Vec::new();
    for scheme in SCHEMES {
        let name = scheme.name();
        for norm in Norm::ALL {
            let rows: Vec<RateOf> = studies
                .iter()
                .flat_map(|s| rates_of(s, &name, norm))
                .collect();
            let best =
                rows.iter()
                    .enumerate()
                    .fold(None, |best: Option<usize>, (k, r)| match best {
                        Some(b) if rows[b].rate >= r.rate => best,
                        _ => Some(k),
                    });
            let Some(best) = best else { continue };
            let leader = &rows[best];
            let uncleared: Vec<&RateOf> = rows
                .iter()
                .enumerate()
                .filter(|&(k, r)| k != best && !leader.above(r))
                .map(|(_, r)| r)
                .collect();
            let candidates: Vec<String> = rows
                .iter()
                .filter(|r| !rows.iter().any(|o| o.above(r)))
                .map(RateOf::name)
                .collect();
            let (verdict, reason) = if uncleared.is_empty() {
                (
                    Verdict::Holds,
                    format!(
                        "{} {} lies wholly above the interval of every other row",
                        leader.name(),
                        leader.text()
                    ),
                )
            } else {
                let shown: Vec<String> = uncleared
                    .iter()
                    .take(3)
                    .map(|r| format!("{} {}", r.name(), r.text()))
                    .collect();
                let more = uncleared.len().saturating_sub(shown.len());
                (
                    Verdict::Undecided,
                    format!(
                        "{} {} does not lie wholly above {} other {} intervals ({}{}): \
                         narrower intervals (more levels) would decide it",
                        leader.name(),
                        leader.text(),
                        uncleared.len(),
                        if uncleared.len() == 1 {
                            "row's"
                        } else {
                            "rows'"
                        },
                        shown.join(", "),
                        if more > 0 {
                            format!(" and {more} more")
                        } else {
                            String::new()
                        }
                    ),
                )
            };
            out.push(Fastest {
                scheme: name.clone(),
                norm: norm.key(),
                contact: leader.contact.clone(),
                mass: leader.mass,
                rate: leader.rate,
                interval: leader.interval,
                verdict,
                reason,
                candidates,
            });
        }
    }
    out
}

/// The rows whose oscillation indicator is at least [`OSCILLATES_FROM`], scheme by scheme in
/// the order of [`SCHEMES`].
pub fn oscillating(rows: &[ExtendedRow]) -> Vec<&ExtendedRow> {
    SCHEMES
        .into_iter()
        .flat_map(|scheme| {
            let name = scheme.name();
            rows.iter().filter(move |r| {
                r.scheme == name && r.oscillation_indicator.is_some_and(oscillates)
            })
        })
        .collect()
}

/// `reports/extended.json`.
#[derive(Debug, Serialize)]
pub struct ExtendedFile {
    /// The crate version that wrote it.
    pub signorini_version: &'static str,
    /// `signorini-dirichlet`.
    pub problem: &'static str,
    /// The studies' levels.
    pub levels: Vec<usize>,
    /// The studies' `Δx/Δt`.
    pub ratio: f64,
    /// The studies' horizon.
    pub horizon: f64,
    /// Wall time of all studies together, seconds.
    pub wall_seconds: f64,
    /// The ensemble that classified the rows (`null` when no sensitivity was measured).
    pub ensemble: Option<EnsembleConfig>,
    /// [`CONVERGES_ABOVE`].
    pub verdict_converges_above: f64,
    /// [`BOUNDED_RATE_WITHIN`]: a rate at or below its negative grows.
    pub verdict_bounded_within: f64,
    /// Every row.
    pub rows: Vec<ExtendedRow>,
    /// [`fastest`] of the studies: per scheme and norm the row with the highest rate and
    /// whether its interval decides that it is the fastest.
    pub fastest: Vec<Fastest>,
    /// [`oscillating`] rows as `{contact, scheme, mass, indicator}`.
    pub oscillating: Vec<OscillatingRow>,
}

/// One oscillating row in `extended.json`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct OscillatingRow {
    /// The contact treatment.
    pub contact: String,
    /// The scheme's name.
    pub scheme: String,
    /// The mass variant.
    pub mass: &'static str,
    /// The oscillation indicator.
    pub indicator: f64,
}

/// A rate cell: `–` when undefined, `†` after a round-off chaotic case's median.
fn cell(rate: Option<f64>, chaotic: bool) -> String {
    let mark = if chaotic { "†" } else { "" };
    rate.map_or_else(|| "–".to_string(), |r| format!("{r:.2}{mark}"))
}

/// The classification paragraph and the rate ranges of the round-off chaotic rows.
fn sensitivity_section(
    rows: &[ExtendedRow],
    ensemble: Option<EnsembleConfig>,
    wall_seconds: f64,
) -> String {
    let Some(ensemble) = ensemble else {
        return "\n## Round-off sensitivity\n\nNot measured: every rate is one run's.\n"
            .to_string();
    };
    let count = |class: SensitivityClass| rows.iter().filter(|r| r.class == Some(class)).count();
    let mut md = format!(
        "\n## Round-off sensitivity\n\nEvery row run as {} (the rules of `sensitivity.md`): {} \
         reproducible, {} event-sensitive, {} round-off chaotic (†: the ensemble median rate, \
         whose [min, max] follows; the energy verdict of such a row is decided by the \
         `energy_Linf` rate's [min, max] joined with its members' own 95 % intervals). The \
         ensembles took {wall_seconds:.1} s wall.\n",
        ensemble.describe(),
        count(SensitivityClass::Reproducible),
        count(SensitivityClass::EventSensitive),
        count(SensitivityClass::Chaotic),
    );
    let chaotic: Vec<&ExtendedRow> = rows.iter().filter(|r| r.is_chaotic()).collect();
    if chaotic.is_empty() {
        return md;
    }
    md.push_str("\n| scheme | mass | contact |");
    for norm in Norm::ALL {
        md.push_str(&format!(" {} |", norm.key()));
    }
    md.push_str("\n|---|---|---|");
    md.push_str(&"---|".repeat(Norm::ALL.len()));
    md.push('\n');
    for r in chaotic {
        md.push_str(&format!("| {} | {} | {} |", r.scheme, r.mass, r.contact));
        for norm in Norm::ALL {
            let range = r.rate_ranges.get(norm.key()).map_or_else(
                || "–".to_string(),
                |s| format!("[{:.3}, {:.3}]", s.min, s.max),
            );
            md.push_str(&format!(" {range} |"));
        }
        md.push('\n');
    }
    md
}

/// The rows whose energy verdict is undecided, or that do not converge and are neither decided
/// bounded nor growing, each with what it has and what would decide it.
fn undecided_section(rows: &[ExtendedRow]) -> String {
    let undecided: Vec<&ExtendedRow> = rows
        .iter()
        .filter(|r| {
            matches!(
                r.energy_verdict,
                EnergyVerdict::Undecided | EnergyVerdict::DoesNotConverge
            )
        })
        .collect();
    let mut md = format!(
        "\n## Undecided energy verdicts\n\n{} of {} rows: the interval of the `energy_Linf` \
         rate contains {CONVERGES_ABOVE} (undecided) or there is none, or it lies at or below \
         {CONVERGES_ABOVE} and overlaps −{BOUNDED_RATE_WITHIN} (does not converge; bounded or \
         grows undecided).\n",
        undecided.len(),
        rows.len()
    );
    if !undecided.is_empty() {
        md.push_str("\n| scheme | mass | contact | why |\n|---|---|---|---|\n");
        for r in undecided {
            md.push_str(&format!(
                "| {} | {} | {} | {} |\n",
                r.scheme, r.mass, r.contact, r.energy_verdict_reason
            ));
        }
    }
    md
}

/// The markdown and the JSON file of the studies.
pub fn render(studies: &[ExtendedStudy]) -> (String, ExtendedFile) {
    let rows = extended_rows(studies);
    let fastest = fastest(studies);
    let oscillating: Vec<OscillatingRow> = oscillating(&rows)
        .into_iter()
        .map(|r| OscillatingRow {
            contact: r.contact.clone(),
            scheme: r.scheme.clone(),
            mass: r.mass,
            indicator: r.oscillation_indicator.unwrap_or(f64::NAN),
        })
        .collect();
    let config = studies
        .first()
        .map_or_else(extended_config, |s| s.study.config.clone());
    let wall_seconds: f64 = studies.iter().map(|s| s.study.wall_seconds).sum();
    let ensemble = studies
        .iter()
        .find_map(|s| s.sensitivity.as_ref().map(|s| s.ensemble));

    let mut md = format!(
        "# Extended table: every mass variant × contact treatment\n\nSignorini–Dirichlet benchmark (1D paper §5), levels NX = \
         {:?}, Δx/Δt = {}, T = {}; every mass variant × contact treatment. Each rate: the \
         least-squares rate over all levels. Oscillation: `TV(λ_h)/TV(λ)` on the finest level \
         (No < 5 ≤ Small < 100 ≤ Yes < 2000 ≤ Big). Energy verdict from the 95 % interval of the \
         `energy_Linf` rate (a chaotic row: the ensemble's [min, max] joined with its members' \
         own 95 % intervals) and the finest-level \
         energy error e, in the words of docs/src/vocabulary.md: *converges* when it lies above \
         {CONVERGES_ABOVE}, *does not converge* when at or below it (or e not finite), then \
         *bounded* when within ±{BOUNDED_RATE_WITHIN}, printed with e / E₀ (bounded is not \
         small: an error the size of the energy is bounded), *grows* when at or below \
         −{BOUNDED_RATE_WITHIN}; *undecided* when it contains {CONVERGES_ABOVE} (the section \
         \"Undecided energy verdicts\" gives why). Generated by `make report` (signorini {}); the studies took {:.1} s wall.\n",
        config.levels,
        config.ratio,
        config.horizon,
        env!("CARGO_PKG_VERSION"),
        wall_seconds
    );
    for scheme in SCHEMES {
        let name = scheme.name();
        md.push_str(&format!("\n## {}\n\n| mass | contact |", scheme.label()));
        for norm in Norm::ALL {
            md.push_str(&format!(" {} |", norm.key()));
        }
        md.push_str(" oscillation | energy error (finest) | energy verdict |\n|---|---|");
        md.push_str(&"---|".repeat(Norm::ALL.len() + 3));
        md.push('\n');
        for mass in MassVariant::ON_EVERY_MESH {
            for r in rows
                .iter()
                .filter(|r| r.scheme == name && r.mass == mass.name())
            {
                md.push_str(&format!("| {} | {} |", r.mass, r.contact));
                for norm in Norm::ALL {
                    md.push_str(&format!(" {} |", cell(r.rate(norm), r.is_chaotic())));
                }
                let osc = match (r.oscillation_indicator, r.oscillation_word) {
                    (Some(i), Some(w)) => format!("{i:.3} ({w})"),
                    _ => "–".to_string(),
                };
                md.push_str(&format!(
                    " {osc} | {:.3e} | {} |\n",
                    r.energy_error_finest,
                    r.energy_verdict_text()
                ));
            }
        }
    }
    md.push_str(&undecided_section(&rows));
    let sensitivity_seconds = studies
        .iter()
        .filter_map(|s| s.sensitivity.as_ref())
        .map(|s| s.wall_seconds)
        .sum();
    md.push_str(&sensitivity_section(&rows, ensemble, sensitivity_seconds));
    let decided = fastest
        .iter()
        .filter(|f| f.verdict == Verdict::Holds)
        .count();
    md.push_str(&format!(
        "\n## Fastest per norm\n\nPer scheme and norm, the row with the highest rate and \
         whether it is the fastest: it is when its rate's interval (its 95 % interval; a \
         round-off chaotic row's ensemble [min, max]) lies wholly above every other row's of \
         the scheme; otherwise the fastest is *undecided* between the rows no other row's \
         interval lies wholly above. Decided for {decided} of {}.\n\n",
        fastest.len()
    ));
    md.push_str(
        "| scheme | norm | fastest | highest rate [interval] (row) | why |\n|---|---|---|---|---|\n",
    );
    for f in &fastest {
        let row = format!("{}/{}", f.mass, f.contact);
        let rate = match f.interval {
            Some((low, high)) => format!("{:.2} [{low:.2}, {high:.2}] ({row})", f.rate),
            None => format!("{:.2} (no interval) ({row})", f.rate),
        };
        let which = match f.verdict {
            Verdict::Holds => row,
            _ => format!(
                "*undecided* between {} rows: {}",
                f.candidates.len(),
                f.candidates.join(", ")
            ),
        };
        md.push_str(&format!(
            "| {} | {} | {which} | {rate} | {} |\n",
            f.scheme, f.norm, f.reason
        ));
    }
    md.push_str(&format!(
        "\n## Oscillating rows\n\nIndicator ≥ {OSCILLATES_FROM}: {} of {} rows.\n\n",
        oscillating.len(),
        rows.len()
    ));
    if !oscillating.is_empty() {
        md.push_str("| scheme | mass | contact | indicator |\n|---|---|---|---|\n");
        for o in &oscillating {
            md.push_str(&format!(
                "| {} | {} | {} | {:.3} |\n",
                o.scheme, o.mass, o.contact, o.indicator
            ));
        }
    }
    let file = ExtendedFile {
        signorini_version: env!("CARGO_PKG_VERSION"),
        problem: "signorini-dirichlet",
        levels: config.levels,
        ratio: config.ratio,
        horizon: config.horizon,
        wall_seconds,
        ensemble,
        verdict_converges_above: CONVERGES_ABOVE,
        verdict_bounded_within: BOUNDED_RATE_WITHIN,
        rows,
        fastest,
        oscillating,
    };
    (md, file)
}

/// The extended studies ([`extended_studies`]), each with its round-off sensitivity measured.
pub fn extended_studies_with_sensitivity(root: &Path) -> Result<Vec<ExtendedStudy>, Error> {
    extended_studies(root)?
        .into_iter()
        .map(|s| s.with_sensitivity(root))
        .collect()
}

/// Hands the extended studies' job lists to `batch` — one study per treatment of
/// [`TREATMENTS`], then the round-off ensembles of every case of each — and returns the studies
/// with their sensitivity (`None` for a shard), as [`extended_studies_with_sensitivity`] makes
/// them: a case a study could not run keeps no ensemble. `root` is the repository root.
pub fn extended_studies_in(
    root: &Path,
    batch: &mut Batch<'_>,
) -> Result<Option<Vec<ExtendedStudy>>, Error> {
    let config = extended_config();
    let norms: BTreeSet<Norm> = Norm::ALL.into_iter().collect();
    let cases = extended_cases();
    let problems = TREATMENTS
        .iter()
        .map(|name| extended_problem(root, name))
        .collect::<Result<Vec<_>, _>>()?;
    let studies = problems
        .iter()
        .map(|p| ExactSolution::jobs(p, &cases, &norms, &config))
        .collect::<Result<Vec<_>, _>>()?;
    let ensembles = problems
        .iter()
        .map(|p| SensitivityJobs::new(p, &cases, &norms, &config, EnsembleConfig::default()))
        .collect::<Result<Vec<_>, _>>()?;
    let runs = studies
        .iter()
        .map(|s| batch.execute(&s.list()))
        .collect::<Result<Vec<_>, _>>()?;
    let members = ensembles
        .iter()
        .map(|e| batch.execute(&e.list()))
        .collect::<Result<Vec<_>, _>>()?;
    let (Some(runs), Some(members)) = (
        runs.into_iter().collect::<Option<Vec<_>>>(),
        members.into_iter().collect::<Option<Vec<_>>>(),
    ) else {
        return Ok(None);
    };
    TREATMENTS
        .iter()
        .zip(studies.iter().zip(runs))
        .zip(ensembles.iter().zip(members))
        .map(|((name, (jobs, runs)), (ensemble, members))| {
            let study = jobs.reduce(runs, &cases);
            let kept: Vec<Case> = study.cases.iter().map(|c| c.case).collect();
            Ok(ExtendedStudy {
                contact: name.to_string(),
                sensitivity: Some(ensemble.reduce(members, &kept)?),
                study,
            })
        })
        .collect::<Result<_, Error>>()
        .map(Some)
}

/// Writes `extended.md` and `extended.json` of `studies` into `out_dir`.
pub fn write_extended_report(studies: &[ExtendedStudy], out_dir: &Path) -> Result<(), Error> {
    let (md, file) = render(studies);
    write_atomic(&out_dir.join(EXTENDED_MD), md.as_bytes())?;
    write_json(&out_dir.join(EXTENDED_JSON), &file)?;
    Ok(())
}

/// The golden values of one treatment.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TreatmentGolden {
    /// The treatment's name (one of [`TREATMENTS`]).
    pub contact: String,
    /// Its study's golden values.
    pub golden: Golden,
}

/// `golden/rates-1d-extended.json`: one [`Golden`] per treatment.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ExtendedGolden {
    /// What produced it (`make golden`).
    pub generated_by: String,
    /// One entry per treatment, in the order of [`TREATMENTS`].
    pub treatments: Vec<TreatmentGolden>,
}

impl ExtendedGolden {
    /// The golden values of the studies; each treatment keeps the tolerances it has in
    /// `previous` (the file being replaced), the default tolerances otherwise, and is held at
    /// what its measured sensitivity allows ([`Golden::with_sensitivity`]) when it has one.
    pub fn from_studies(studies: &[ExtendedStudy], previous: Option<&ExtendedGolden>) -> Self {
        Self {
            generated_by: "make golden".to_string(),
            treatments: studies
                .iter()
                .map(|s| {
                    let tolerances = previous
                        .and_then(|p| p.treatment(&s.contact))
                        .map_or_else(Tolerances::default, |g| g.tolerances.clone());
                    let golden = Golden::from_study(&s.study, tolerances);
                    TreatmentGolden {
                        contact: s.contact.clone(),
                        golden: match &s.sensitivity {
                            Some(sensitivity) => golden.with_sensitivity(sensitivity),
                            None => golden,
                        },
                    }
                })
                .collect(),
        }
    }

    /// The golden values of the treatment named `contact`.
    pub fn treatment(&self, contact: &str) -> Option<&Golden> {
        self.treatments
            .iter()
            .find(|t| t.contact == contact)
            .map(|t| &t.golden)
    }
}

/// Reads the extended table's golden file.
pub fn read_extended_golden(path: &Path) -> Result<ExtendedGolden, Error> {
    let golden: ExtendedGolden = read_json(path, GOLDEN_FILE)?;
    for t in &golden.treatments {
        let cases = t.golden.cases.iter().map(|c| (c.case.as_str(), &c.norms));
        check_values(path, &t.golden.tolerances, cases)?;
    }
    Ok(golden)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rate(value: f64, half: Option<f64>) -> Estimate {
        Estimate {
            what: "energy_Linf rate".into(),
            value,
            interval: half.map(|h| (value - h, value + h)),
            bias: Some(0.0),
            levels: if half.is_some() { 7 } else { 2 },
        }
    }

    fn verdict(value: f64, half: Option<f64>, finest: f64) -> EnergyVerdict {
        EnergyVerdict::decide(&rate(value, half), finest).0
    }

    #[test]
    fn an_interval_clear_of_the_thresholds_decides_the_energy_verdict() {
        assert_eq!(verdict(0.9, Some(0.1), 1e-3), EnergyVerdict::Converges);
        assert_eq!(verdict(0.2, Some(0.1), 1e-3), EnergyVerdict::Converges);
        assert_eq!(verdict(-0.1, Some(0.05), 1e-3), EnergyVerdict::Bounded);
        assert_eq!(verdict(-0.9, Some(0.1), 1e-3), EnergyVerdict::Grows);
        assert_eq!(verdict(-0.4, Some(0.1), 1e-3), EnergyVerdict::Grows);
        assert_eq!(
            verdict(-0.25, Some(0.05), 1e-3),
            EnergyVerdict::DoesNotConverge
        );
        assert_eq!(verdict(0.9, Some(0.1), f64::INFINITY), EnergyVerdict::Grows);
    }

    #[test]
    fn an_interval_straddling_zero_is_undecided_with_what_would_decide_it() {
        let (v, reason) = EnergyVerdict::decide(&rate(0.02, Some(0.05)), 1e-3);
        assert_eq!(v, EnergyVerdict::Undecided);
        assert!(reason.contains("contains 0"), "{reason}");
        assert!(reason.contains("would decide it"), "{reason}");
        assert_eq!(verdict(0.0, Some(1.0), 1e-3), EnergyVerdict::Undecided);
        let (v, reason) = EnergyVerdict::decide(&rate(3.0, None), 1e-3);
        assert_eq!(v, EnergyVerdict::Undecided);
        assert!(reason.contains("no 95 % interval"), "{reason}");
        let (v, reason) = EnergyVerdict::decide(&rate(-0.26, Some(0.05)), 1e-3);
        assert_eq!(v, EnergyVerdict::DoesNotConverge);
        assert!(
            reason.contains("overlaps an end of [-0.25, 0.25]"),
            "{reason}"
        );
    }

    #[test]
    fn a_chaotic_row_is_decided_by_its_ensemble_range() {
        let decided = Estimate::of_ensemble("energy_Linf rate", 0.8, (0.7, 0.9), 7);
        assert_eq!(
            EnergyVerdict::decide(&decided, 1e-3).0,
            EnergyVerdict::Converges
        );
        let straddling = Estimate::of_ensemble("energy_Linf rate", -0.1, (-0.3, 0.1), 7);
        assert_eq!(
            EnergyVerdict::decide(&straddling, 1e-3).0,
            EnergyVerdict::Undecided
        );
        let at_zero = Estimate::of_ensemble("energy_Linf rate", -0.05, (-0.11, -0.0), 7);
        assert_eq!(
            EnergyVerdict::decide(&at_zero, 1e-3).0,
            EnergyVerdict::Bounded
        );
    }

    /// A treatment's study of Crank–Nicolson and backward Euler with the standard mass, whose
    /// `u_Linf_H` errors fall as `h^p` (`p` by scheme) with a fixed wobble of ±`wobble` relative
    /// (so that each fit has a 95 % interval).
    fn treatment(contact: &str, rates: [f64; 2], wobble: f64) -> ExtendedStudy {
        use crate::harness::study::LevelRecord;
        let config = StudyConfig {
            levels: vec![10, 20, 40, 80, 160],
            ..extended_config()
        };
        let cases = SCHEMES
            .iter()
            .zip(rates)
            .map(|(&scheme, p)| {
                let levels: Vec<LevelRecord> = config
                    .levels
                    .iter()
                    .map(|&nx| LevelRecord::synthetic(nx))
                    .collect();
                let errors = levels
                    .iter()
                    .enumerate()
                    .map(|(k, l)| l.h.powf(p) * (1.0 + if k % 2 == 0 { wobble } else { -wobble }))
                    .collect();
                CaseStudy::from_levels(
                    Case {
                        scheme,
                        mass: MassVariant::Standard,
                    },
                    levels,
                    BTreeMap::from([(Norm::DisplacementLinfH, errors)]),
                )
            })
            .collect();
        ExtendedStudy {
            contact: contact.to_string(),
            study: Study {
                config,
                norms: vec![Norm::DisplacementLinfH],
                cases,
                not_run: Vec::new(),
                wall_seconds: 0.0,
                physics: BTreeMap::new(),
            },
            sensitivity: None,
        }
    }

    /// The fastest row is named only when its rate's interval lies wholly above every other
    /// row's: Crank–Nicolson's penalty row (rate 2 against 1) is; backward Euler's two rows
    /// (rates 1.00 and 1.01, their intervals overlapping) leave it undecided between them.
    #[test]
    fn the_fastest_row_is_named_only_when_its_interval_clears_the_others() {
        let studies = [
            treatment("multiplier", [1.0, 1.0], 0.05),
            treatment("penalty(gamma0=10)", [2.0, 1.01], 0.05),
        ];
        let fastest = fastest(&studies);
        assert_eq!(fastest.len(), 2, "{fastest:?}");
        let cn = &fastest[0];
        assert_eq!(
            (cn.verdict, cn.contact.as_str(), cn.candidates.len()),
            (Verdict::Holds, "penalty(gamma0=10)", 1),
            "{}",
            cn.reason
        );
        let be = &fastest[1];
        assert_eq!(be.verdict, Verdict::Undecided, "{}", be.reason);
        assert_eq!(
            be.candidates,
            ["standard/multiplier", "standard/penalty(gamma0=10)"]
        );
        assert!(
            be.reason
                .contains("does not lie wholly above 1 other row's"),
            "{}",
            be.reason
        );
        let (md, _) = render(&studies);
        assert!(md.contains("Decided for 1 of 2."), "{md}");
        assert!(
            md.contains(
                "| *undecided* between 2 rows: standard/multiplier, standard/penalty(gamma0=10) |"
            ),
            "{md}"
        );
    }
}
