//! The experiment behind the default horizon and levels (`make experiment`, part of `make
//! report`): the Tables 1–2 study recomputed with other horizons, and its rates refitted over
//! sub-ranges of the levels, each compared with the default's; its file is
//! `defaults-experiment.md`.

use std::collections::BTreeSet;
use std::path::Path;

use crate::harness::files::artifacts::write_atomic;
use crate::harness::reference::exact::ExactSolution;
use crate::harness::run::norms::Norm;
use crate::harness::study::executor::Batch;
use crate::harness::study::rates::fit_rate;
use crate::harness::study::{Case, CaseStudy, Study, StudyConfig};
use crate::studies::benchmark::dirichlet;
use crate::studies::error::Error;

/// The experiment's markdown, under a reports directory.
pub const DEFAULTS_EXPERIMENT_MD: &str = "defaults-experiment.md";

/// The horizons compared by the defaults experiment.
pub const EXPERIMENT_HORIZONS: [f64; 3] = [3.0, 6.0, 9.0];

/// The level ranges compared by the defaults experiment (first and last `NX`, inclusive).
pub const EXPERIMENT_RANGES: [(usize, usize); 5] =
    [(10, 640), (20, 640), (40, 640), (10, 320), (160, 640)];

/// One case and norm of the experiment.
#[derive(Debug, Clone, PartialEq)]
pub struct ExperimentEntry {
    /// `scheme/mass`.
    pub case: String,
    /// The norm.
    pub norm: Norm,
    /// The rate over all levels with each of [`EXPERIMENT_HORIZONS`], then the rate at the
    /// first horizon over each of [`EXPERIMENT_RANGES`] but the first (`None` when undefined).
    pub rates: Vec<Option<f64>>,
}

/// The defaults experiment: the base configuration and every entry with a defined rate at the
/// first horizon.
#[derive(Debug, Clone, PartialEq)]
pub struct DefaultsExperiment {
    /// The configuration whose horizon and levels are varied.
    pub base: StudyConfig,
    /// One entry per case and norm, case by case in the order of the tables.
    pub entries: Vec<ExperimentEntry>,
}

/// The least-squares rate of `norm` in `c` over the levels with `lo ≤ NX ≤ hi`.
fn range_rate(c: &CaseStudy, norm: Norm, (lo, hi): (usize, usize)) -> Option<f64> {
    let idx: Vec<usize> = c
        .levels
        .iter()
        .enumerate()
        .filter(|(_, l)| (lo..=hi).contains(&l.nx))
        .map(|(k, _)| k)
        .collect();
    let r = c.norm(norm)?;
    let h: Vec<f64> = idx.iter().map(|&k| c.levels[k].h).collect();
    let e: Vec<f64> = idx.iter().map(|&k| r.errors[k]).collect();
    fit_rate(&h, &e).map(|f| f.rate)
}

/// Hands the Tables 1–2 study at every horizon of [`EXPERIMENT_HORIZONS`] to `batch`, one job
/// list each, and returns the experiment (`None` for a shard): the first horizon's rates
/// refitted over [`EXPERIMENT_RANGES`] and compared with the others'.
pub fn defaults_experiment(
    root: &Path,
    batch: &mut Batch<'_>,
) -> Result<Option<DefaultsExperiment>, Error> {
    let base = StudyConfig::paper_default();
    let norms: BTreeSet<Norm> = Norm::ALL.into_iter().collect();
    let cases = Case::paper_matrix();
    let configs: Vec<StudyConfig> = EXPERIMENT_HORIZONS
        .iter()
        .map(|&horizon| StudyConfig {
            horizon,
            ..base.clone()
        })
        .collect();
    let problems = EXPERIMENT_HORIZONS
        .iter()
        .map(|&t| dirichlet(root, t))
        .collect::<Result<Vec<_>, _>>()?;
    let jobs = problems
        .iter()
        .zip(&configs)
        .map(|(problem, config)| ExactSolution::jobs(problem, &cases, &norms, config))
        .collect::<Result<Vec<_>, _>>()?;
    let runs = jobs
        .iter()
        .map(|j| batch.execute(&j.list()))
        .collect::<Result<Vec<_>, _>>()?;
    let Some(runs) = runs.into_iter().collect::<Option<Vec<_>>>() else {
        return Ok(None);
    };
    let studies: Vec<Study> = jobs
        .iter()
        .zip(runs)
        .map(|(j, runs)| j.reduce(runs, &cases))
        .collect();
    let reference = &studies[0];
    let mut entries = Vec::new();
    for c in &reference.cases {
        for &norm in &Norm::ALL {
            if c.norm(norm).and_then(|r| r.fit).is_none() {
                continue;
            }
            let mut rates: Vec<Option<f64>> = studies
                .iter()
                .map(|s| {
                    s.case(&c.case)
                        .and_then(|sc| sc.norm(norm))
                        .and_then(|r| r.fit)
                        .map(|f| f.rate)
                })
                .collect();
            for &range in EXPERIMENT_RANGES.iter().skip(1) {
                rates.push(range_rate(c, norm, range));
            }
            entries.push(ExperimentEntry {
                case: c.case.id(),
                norm,
                rates,
            });
        }
    }
    Ok(Some(DefaultsExperiment { base, entries }))
}

/// `defaults-experiment.md`: per variant the median and largest change of the rates, then
/// every entry.
pub fn render(experiment: &DefaultsExperiment) -> String {
    let base = &experiment.base;
    let mut md = String::from("# Choosing the horizon T and the levels\n\n");
    md.push_str(&format!(
        "Tables 1–2 study (14 cases × 7 norms, Δx/Δt = {}) recomputed with T ∈ {:?} over the \
         levels {:?}, and the T = {} rates refitted over sub-ranges of levels. Generated by \
         `make experiment` (part of `make report`).\n\n",
        base.ratio, EXPERIMENT_HORIZONS, base.levels, EXPERIMENT_HORIZONS[0]
    ));
    let mut header = String::from("| variant | median of abs(Δrate) | max of abs(Δrate) | entries with abs(Δrate) > 0.1 |\n|---|---|---|---|\n");
    let mut detail = String::from("\n## Every entry\n\n| case | norm |");
    for t in EXPERIMENT_HORIZONS {
        detail.push_str(&format!(" T = {t} |"));
    }
    for (lo, hi) in EXPERIMENT_RANGES.iter().skip(1) {
        detail.push_str(&format!(" NX {lo}–{hi} |"));
    }
    detail.push('\n');
    detail.push_str(&format!(
        "|---|---|{}\n",
        "---|".repeat(EXPERIMENT_HORIZONS.len() + EXPERIMENT_RANGES.len() - 1)
    ));
    let n_variants = EXPERIMENT_HORIZONS.len() - 1 + EXPERIMENT_RANGES.len() - 1;
    let mut deltas: Vec<Vec<f64>> = vec![Vec::new(); n_variants];
    for entry in &experiment.entries {
        let Some(base_rate) = entry.rates[0] else {
            continue;
        };
        let mut row = format!("| {} | {} |", entry.case, entry.norm.key());
        for (k, v) in entry.rates.iter().enumerate() {
            row.push_str(&v.map_or(" — |".to_string(), |x| format!(" {x:.2} |")));
            if k > 0 {
                if let Some(x) = v {
                    deltas[k - 1].push((x - base_rate).abs());
                }
            }
        }
        detail.push_str(&row);
        detail.push('\n');
    }
    let names: Vec<String> = EXPERIMENT_HORIZONS
        .iter()
        .skip(1)
        .map(|t| format!("T = {t} instead of {}", EXPERIMENT_HORIZONS[0]))
        .chain(
            EXPERIMENT_RANGES
                .iter()
                .skip(1)
                .map(|(lo, hi)| format!("levels NX {lo}–{hi} instead of 10–640")),
        )
        .collect();
    for (name, d) in names.iter().zip(&mut deltas) {
        d.sort_by(f64::total_cmp);
        let median = d.get(d.len() / 2).copied().unwrap_or(f64::NAN);
        let max = d.last().copied().unwrap_or(f64::NAN);
        let big = d.iter().filter(|&&x| x > 0.1).count();
        header.push_str(&format!(
            "| {name} | {median:.3} | {max:.2} | {big} of {} |\n",
            d.len()
        ));
    }
    md.push_str(&header);
    md.push_str(&detail);
    md
}

/// How the rates of Tables 1–2 move with the horizon and with the level range: writes
/// `defaults-experiment.md` of `experiment` into `out_dir` and returns the markdown.
pub fn write_defaults_experiment(
    experiment: &DefaultsExperiment,
    out_dir: &Path,
) -> Result<String, Error> {
    let md = render(experiment);
    write_atomic(&out_dir.join(DEFAULTS_EXPERIMENT_MD), md.as_bytes())?;
    Ok(md)
}
