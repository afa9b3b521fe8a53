//! The 1D paper's Tables 1–2 recomputed (`make report`): the study, its round-off sensitivity,
//! the agreement with the paper ([`agreement`], [`paper`]) and the files of this section:
//! `tables.md`, `rates.json` ([`RatesFile`]), `rates-longer-horizon.json`
//! ([`LongerHorizonFile`]), `sensitivity.md` and `sensitivity.json` ([`Sensitivity`]), and the
//! golden file [`GOLDEN_TABLES`].

pub mod agreement;
pub mod paper;
pub mod starts;

use std::collections::BTreeSet;
use std::path::Path;

use serde::{Deserialize, Serialize};

use self::agreement::{disagreement_section, disagreements, paper_tables, Disagreement};
use self::paper::PaperTables;
use self::starts::starts_section;
use crate::harness::files::artifacts::{write_atomic, write_json};
use crate::harness::problem::Settings;
use crate::harness::reference::exact::run_study;
use crate::harness::render::report::convergence_tables;
use crate::harness::run::norms::Norm;
use crate::harness::study::sensitivity::{
    run_sensitivity, EnsembleConfig, InitialNoise, Sensitivity,
};
use crate::harness::study::verdicts::oscillation_word;
use crate::harness::study::{Case, Study, StudyConfig};
use crate::studies::benchmark::dirichlet;
use crate::studies::error::Error;

/// The golden file of the Tables 1–2 study, relative to the repository root.
pub const GOLDEN_TABLES: &str = "golden/rates-1d-dirichlet.json";

/// The tables beside the paper's, under a reports directory.
pub const TABLES_MD: &str = "tables.md";

/// [`RatesFile`], under a reports directory.
pub const RATES_JSON: &str = "rates.json";

/// The problem of the tables' data files.
const PROBLEM: &str = "signorini-dirichlet";

/// [`LongerHorizonFile`], under a reports directory.
pub const LONGER_HORIZON_JSON: &str = "rates-longer-horizon.json";

/// The round-off sensitivity of the tables' cases, rendered, under a reports directory.
pub const SENSITIVITY_MD: &str = "sensitivity.md";

/// The round-off sensitivity of the tables' cases ([`Sensitivity`]), under a reports directory.
pub const SENSITIVITY_JSON: &str = "sensitivity.json";

/// The horizon of the second study that tests whether a disagreement with the paper is due to
/// the horizon: three periods.
pub const LONGER_HORIZON: f64 = 9.0;

/// The level whose predictability horizon and separation growth `sensitivity.md` shows (the
/// paper's NX = 80); a study without it shows its finest level.
const SENSITIVITY_SHOWN_LEVEL: usize = 80;

/// The Tables 1–2 study with the default levels, ratio and horizon: the paper's cases and the
/// rivals ([`Case::tables_matrix`]).
pub fn tables_study(root: &Path) -> Result<Study, Error> {
    let config = StudyConfig::paper_default();
    let problem = dirichlet(root, config.horizon)?;
    let norms: BTreeSet<Norm> = Norm::ALL.into_iter().collect();
    Ok(run_study(
        &problem,
        &Case::tables_matrix(),
        &norms,
        &config,
    )?)
}

/// One case's oscillation indicator in `rates.json`, classified, beside the paper's word.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct OscillationRecord {
    /// `scheme/mass`.
    pub case: String,
    /// `TV(λ_h)/TV(λ)` on the finest level.
    pub indicator: Option<f64>,
    /// [`oscillation_word`] of the indicator.
    pub word: Option<String>,
    /// The paper's word for the case.
    pub paper_word: Option<String>,
}

/// `rates.json`: the Tables 1–2 study with every rate, the oscillation words, and the rates of
/// the longer-horizon study of the disagreements. `make figures` reads it back and needs only
/// the study: a file with nothing else is read with the other fields empty.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RatesFile {
    /// The crate version that wrote it.
    #[serde(default)]
    pub signorini_version: String,
    /// `signorini-dirichlet`.
    #[serde(default)]
    pub problem: String,
    /// The study.
    pub study: Study,
    /// One record per case, in the study's order.
    #[serde(default)]
    pub oscillations: Vec<OscillationRecord>,
    /// [`LONGER_HORIZON`].
    #[serde(default)]
    pub longer_horizon: f64,
    /// `(case, norm, rate over all levels with T = longer_horizon)` of each disagreement.
    #[serde(default)]
    pub longer_horizon_rates: Vec<(String, Norm, Option<f64>)>,
}

/// `rates-longer-horizon.json`: the Tables 1–2 study run to [`LONGER_HORIZON`] (three periods
/// of the benchmark), every case and every norm. `tables.md` takes the rates of its
/// disagreements from it (`rates.json` lists them), and the render step judges on it the
/// energy error over the longer horizon of `schemes.md`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct LongerHorizonFile {
    /// The crate version that wrote it.
    pub signorini_version: String,
    /// `signorini-dirichlet`.
    pub problem: String,
    /// The study, its configuration's horizon [`LONGER_HORIZON`].
    pub study: Study,
}

/// The disagreements of `study` with the paper, each with its rate over all levels at
/// [`LONGER_HORIZON`] from `longer`, the Tables 1–2 study run to that horizon (every case and
/// norm, so that it does not depend on which disagree; a case it could not run has no rate).
pub fn disagreements_with_longer_horizon(
    study: &Study,
    paper: &PaperTables,
    sensitivity: &Sensitivity,
    longer: &Study,
) -> Vec<Disagreement> {
    let mut list = disagreements(study, paper, Some(sensitivity));
    for d in &mut list {
        d.longer_horizon = longer
            .cases
            .iter()
            .find(|c| c.case.id() == d.case)
            .and_then(|c| c.norm(d.norm))
            .and_then(|r| r.fit)
            .map(|f| f.rate);
    }
    list
}

/// `tables.md`: Tables 1–2 beside the paper's, the agreement section, the M^mod rows under both
/// starts (`implicit`: those cases with the implicit-multiplier start) and the per-level errors.
pub fn render(
    study: &Study,
    paper: &PaperTables,
    sensitivity: &Sensitivity,
    list: &[Disagreement],
    implicit: &Study,
) -> String {
    let mut md = String::new();
    md.push_str("# Tables 1–2 recomputed\n\n");
    md.push_str(&format!(
        "Signorini–Dirichlet benchmark (1D paper §5), levels NX = {:?}, Δx/Δt = {}, T = {}. \
         Each cell: our least-squares rate over all levels (the paper's rate, ours − paper). \
         The rows after the paper's fourteen are its rivals (docs/src/schemes-and-balances.md), \
         which the paper has no rate for (`—`); contact-stabilised Newmark runs with the standard \
         mass only (its predictor is an M-projection, blind to the massless contact node). \
         Generated by `make report` (signorini {}); the whole study took {:.1} s wall.\n\n",
        study.config.levels,
        study.config.ratio,
        study.config.horizon,
        env!("CARGO_PKG_VERSION"),
        study.wall_seconds
    ));
    md.push_str(&paper_tables(study, paper, Some(sensitivity)));
    md.push_str(&format!(
        "\n† round-off chaotic (`sensitivity.md`): the ensemble median rate of {}, and the \
         ensemble [min, max]; the unperturbed run's rate is one sample of that range (its \
         per-level errors are below). The agreement with the paper is decided on that range \
         joined with the members' own 95 % fit intervals.\n",
        sensitivity.ensemble.describe()
    ));
    md.push_str(
        "\nOscillations: `TV(λ_h)/TV(λ)` on the finest level, the total variation of the computed \
         multiplier over that of the exact one; No < 5 ≤ Small < 100 ≤ Yes < 2000 ≤ Big.\n\n",
    );
    md.push_str("## Agreement with the paper\n\n");
    md.push_str(&disagreement_section(list, LONGER_HORIZON));
    md.push('\n');
    md.push_str(&starts_section(study, implicit));
    md.push_str("\n## Per-level errors and observed orders\n\n");
    md.push_str(&convergence_tables(study));
    md
}

/// The [`RatesFile`] of `study` and its disagreements.
pub fn rates_file(study: &Study, paper: &PaperTables, list: &[Disagreement]) -> RatesFile {
    RatesFile {
        signorini_version: env!("CARGO_PKG_VERSION").to_string(),
        problem: PROBLEM.to_string(),
        study: study.clone(),
        oscillations: study
            .cases
            .iter()
            .map(|c| OscillationRecord {
                case: c.case.id(),
                indicator: c.oscillation_indicator(),
                word: c
                    .oscillation_indicator()
                    .map(|r| oscillation_word(r).to_string()),
                paper_word: paper.row(&c.case).map(|r| r.oscillations.clone()),
            })
            .collect(),
        longer_horizon: LONGER_HORIZON,
        longer_horizon_rates: list
            .iter()
            .map(|d| (d.case.clone(), d.norm, d.longer_horizon))
            .collect(),
    }
}

/// Compares `study` with the paper (with `longer`, the study at [`LONGER_HORIZON`], for the
/// disagreements) and with its M^mod cases under the implicit-multiplier start (`implicit`),
/// and writes `tables.md`, `rates.json` and `rates-longer-horizon.json` (`longer`) into
/// `out_dir`.
pub fn write_tables(
    study: &Study,
    sensitivity: &Sensitivity,
    longer: &Study,
    implicit: &Study,
    out_dir: &Path,
) -> Result<(), Error> {
    let paper = PaperTables::load();
    let list = disagreements_with_longer_horizon(study, &paper, sensitivity, longer);
    write_atomic(
        &out_dir.join(TABLES_MD),
        render(study, &paper, sensitivity, &list, implicit).as_bytes(),
    )?;
    write_json(&out_dir.join(RATES_JSON), &rates_file(study, &paper, &list))?;
    write_json(
        &out_dir.join(LONGER_HORIZON_JSON),
        &LongerHorizonFile {
            signorini_version: env!("CARGO_PKG_VERSION").to_string(),
            problem: PROBLEM.to_string(),
            study: longer.clone(),
        },
    )?;
    Ok(())
}

/// The round-off sensitivity of `cases` on the Tables 1–2 study (its problem, levels and all
/// seven norms) with the default ensemble: what `make report` reports and what the gate holds
/// the chaotic cases to.
pub fn tables_sensitivity(root: &Path, cases: &[Case]) -> Result<Sensitivity, Error> {
    tables_sensitivity_under(root, Settings::default(), cases)
}

/// [`tables_sensitivity`] solved with `settings`: the Tables 1–2 benchmark under other settings
/// (the round-off test of the gate runs it with the factored predictor).
pub fn tables_sensitivity_under(
    root: &Path,
    settings: Settings,
    cases: &[Case],
) -> Result<Sensitivity, Error> {
    let config = StudyConfig {
        settings,
        ..StudyConfig::paper_default()
    };
    Ok(run_sensitivity(
        &dirichlet(root, config.horizon)?,
        cases,
        &Norm::ALL.into_iter().collect(),
        &config,
        EnsembleConfig::default(),
    )?)
}

/// Writes `sensitivity.md` and `sensitivity.json` of `s`, whose members' initial noise is on
/// `noise` and which `made_by` made, into `out_dir`.
pub fn write_sensitivity_files(
    s: &Sensitivity,
    (noise, made_by): (InitialNoise, &str),
    out_dir: &Path,
) -> Result<(), Error> {
    let levels = &s.config.levels;
    let shown = match levels.last() {
        Some(&finest) if !levels.contains(&SENSITIVITY_SHOWN_LEVEL) => finest,
        _ => SENSITIVITY_SHOWN_LEVEL,
    };
    write_atomic(
        &out_dir.join(SENSITIVITY_MD),
        crate::harness::study::sensitivity::render(s, shown, noise, made_by).as_bytes(),
    )?;
    write_json(&out_dir.join(SENSITIVITY_JSON), s)?;
    Ok(())
}
