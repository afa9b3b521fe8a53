//! Refinement studies: a set of cases (scheme × mass variant) run at every level, in parallel,
//! with the rates of every requested norm.

use std::collections::{BTreeMap, BTreeSet};
use std::time::Instant;

use rayon::prelude::*;
use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};

use crate::engine::error::ParameterError;
use crate::engine::fem::MassVariant;
use crate::engine::schemes::Scheme;
use crate::harness::error::Error;
use crate::harness::norms::Norm;
use crate::harness::rates::{fit_rate, observed_orders, RateFit};
use crate::harness::run::{run, Observables, Problem1d, RunConfig, RunResult, RunStatus, Timings};
use crate::harness::shard::plan::{self, EncodedResult, Schedule};
use crate::harness::shard::range::{errors_out_of_range, positive};
use crate::harness::shard::{codec, InRange, ShardError};

/// A row of the tables: a scheme with its parameters and a mass variant.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Case {
    /// The time integrator.
    pub scheme: Scheme,
    /// The mass matrix.
    pub mass: MassVariant,
}

impl Case {
    /// Every scheme with every mass, scheme by scheme.
    pub fn matrix(schemes: &[Scheme], masses: &[MassVariant]) -> Vec<Case> {
        schemes
            .iter()
            .flat_map(|&scheme| masses.iter().map(move |&mass| Case { scheme, mass }))
            .collect()
    }

    /// The 14 rows of the paper's Tables 1–2, in order.
    pub fn paper_matrix() -> Vec<Case> {
        Self::matrix(&Scheme::paper_schemes(), &MassVariant::PAPER)
    }

    /// `scheme/mass`, e.g. `crank-nicolson/redistributed`.
    pub fn id(&self) -> String {
        format!("{}/{}", self.scheme.name(), self.mass.name())
    }
}

/// Levels, time-step ratio and horizon of a study.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct StudyConfig {
    /// `NX` of each level, increasing.
    pub levels: Vec<usize>,
    /// `Δx / Δt`.
    pub ratio: f64,
    /// Horizon `T`.
    pub horizon: f64,
}

impl StudyConfig {
    /// The defaults for the Signorini–Dirichlet tables: `NX = 10 · 2^k`, `k = 0..6`, the paper's
    /// ratio 10, one period `T = 3` (docs/src/choosing-t-and-levels.md gives the experiment
    /// behind these values).
    pub fn paper_default() -> Self {
        Self {
            levels: vec![10, 20, 40, 80, 160, 320, 640],
            ratio: 10.0,
            horizon: 3.0,
        }
    }

    /// Checks the levels are increasing and positive.
    pub fn validate(&self) -> Result<(), ParameterError> {
        if self.levels.len() < 2
            || self.levels[0] == 0
            || self.levels.windows(2).any(|w| w[0] >= w[1])
        {
            return Err(ParameterError::new(
                "levels",
                format!("{:?}", self.levels),
                "at least two increasing element counts >= 1",
            ));
        }
        Ok(())
    }
}

/// One level of one case.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct LevelRecord {
    /// `NX`.
    pub nx: usize,
    /// `h`.
    pub h: f64,
    /// `Δt`.
    pub dt: f64,
    /// Number of steps.
    pub steps: usize,
    /// Unknowns.
    pub dofs: usize,
    /// Wall-clock split of the run.
    pub timings: Timings,
    /// `TV(λ_h) / TV(λ)` of this level, when the multiplier is observed.
    pub multiplier_variation_ratio: Option<f64>,
}

/// The errors and rates of one norm for one case.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct NormRates {
    /// The norm.
    pub norm: Norm,
    /// The error at each level.
    pub errors: Vec<f64>,
    /// The observed order between consecutive levels (`None` on the first).
    pub orders: Vec<Option<f64>>,
    /// The least-squares rate over all levels.
    pub fit: Option<RateFit>,
    /// The least-squares rate over the last three levels.
    pub fit_last_three: Option<RateFit>,
    /// The least-squares rate over the first three levels (what the agreement with the paper
    /// compares). Not written to files, whose schema predates it: `None` in a study read back.
    #[serde(skip)]
    pub fit_first_three: Option<RateFit>,
}

/// The errors of each norm at `levels` with the observed orders and the least-squares rates
/// (all levels, first three, last three), in the order of `errors`: every series of levels is
/// fitted here, a study's case ([`CaseStudy::from_levels`]) as another code's runs
/// (`crate::harness::external`).
pub fn fit_norm_rates(levels: &[LevelRecord], errors: BTreeMap<Norm, Vec<f64>>) -> Vec<NormRates> {
    let h: Vec<f64> = levels.iter().map(|l| l.h).collect();
    let tail = h.len().saturating_sub(3);
    errors
        .into_iter()
        .map(|(norm, errors)| {
            let head = errors.len().min(3);
            NormRates {
                norm,
                orders: observed_orders(&h, &errors),
                fit: fit_rate(&h, &errors),
                fit_last_three: fit_rate(&h[tail..], &errors[tail..]),
                fit_first_three: fit_rate(&h[..head], &errors[..head]),
                errors,
            }
        })
        .collect()
}

/// All levels of one case.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CaseStudy {
    /// The case.
    pub case: Case,
    /// Per-level records.
    pub levels: Vec<LevelRecord>,
    /// Per-norm errors and rates, in the order of [`Norm::ALL`].
    pub rates: Vec<NormRates>,
}

impl CaseStudy {
    /// A case from its level records and the error of each norm at each level, fitted by
    /// [`fit_norm_rates`].
    pub fn from_levels(
        case: Case,
        levels: Vec<LevelRecord>,
        errors: BTreeMap<Norm, Vec<f64>>,
    ) -> Self {
        Self {
            case,
            rates: fit_norm_rates(&levels, errors),
            levels,
        }
    }

    /// The rates of `norm`, if it was requested.
    pub fn norm(&self, norm: Norm) -> Option<&NormRates> {
        self.rates.iter().find(|r| r.norm == norm)
    }

    /// The oscillation indicator: `TV(λ_h) / TV(λ)` on the finest level.
    pub fn oscillation_indicator(&self) -> Option<f64> {
        self.levels.last()?.multiplier_variation_ratio
    }
}

/// A case a study could not run to completion: the first level (in the study's order) whose
/// run stopped, and how it stopped. A stopped run has no error norm, so the case has no rate:
/// the study reports it as not run, never with numbers.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct NotRun {
    /// The case.
    pub case: Case,
    /// The level (`NX`, or elements along the axis) of the run that stopped.
    pub nx: usize,
    /// How it stopped (diverged, contact solver not converged, solver inaccurate).
    pub status: RunStatus,
}

impl NotRun {
    /// The first of `statuses` (one per level of `levels`) that is not completed, as the case's
    /// record; `None` when every run completed.
    pub fn first(case: Case, levels: &[usize], statuses: &[&RunStatus]) -> Option<Self> {
        levels
            .iter()
            .zip(statuses)
            .find(|(_, s)| !s.is_completed())
            .map(|(&nx, s)| Self {
                case,
                nx,
                status: (*s).clone(),
            })
    }

    /// What stopped the run, in words.
    pub fn reason(&self) -> String {
        self.status
            .completed()
            .err()
            .map_or_else(String::new, |e| e.to_string())
    }
}

/// A whole study.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Study {
    /// Levels, ratio and horizon.
    pub config: StudyConfig,
    /// The norms computed.
    pub norms: Vec<Norm>,
    /// One entry per case run to completion at every level, in the order given.
    pub cases: Vec<CaseStudy>,
    /// The cases not run to completion ([`NotRun`]); absent from the JSON when there are none.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub not_run: Vec<NotRun>,
    /// Wall-clock time of the whole study (parallel), seconds.
    pub wall_seconds: f64,
}

impl Study {
    /// The study of `case`, if it was run.
    pub fn case(&self, case: &Case) -> Option<&CaseStudy> {
        self.cases.iter().find(|c| c.case == *case)
    }
}

/// Runs every case at every level (in parallel over case × level, largest levels first) and
/// fits the rates of every norm in `norms`. Only those norms are evaluated.
pub fn run_study(
    problem: &Problem1d,
    cases: &[Case],
    norms: &BTreeSet<Norm>,
    config: &StudyConfig,
) -> Result<Study, Error> {
    run_study_with_progress(problem, cases, norms, config, &|| {})
}

/// The number of runs a study makes.
pub fn study_size(cases: &[Case], config: &StudyConfig) -> usize {
    cases.len() * config.levels.len()
}

/// [`run_study`], calling `done` after each run (from the worker threads).
pub fn run_study_with_progress(
    problem: &Problem1d,
    cases: &[Case],
    norms: &BTreeSet<Norm>,
    config: &StudyConfig,
    done: &(dyn Fn() + Sync),
) -> Result<Study, Error> {
    config.validate()?;
    let clock = Instant::now();
    let observables = Observables {
        norms: norms.clone(),
        ..Observables::default()
    };
    let per_case = run_case_levels(cases.len(), &config.levels, |c, l| {
        let cfg = RunConfig {
            nx: config.levels[l],
            ratio: config.ratio,
            scheme: cases[c].scheme,
            mass: cases[c].mass,
            observables: observables.clone(),
        };
        let result = run(problem, &cfg);
        done();
        result
    })?;
    let mut studied = Vec::new();
    let mut not_run = Vec::new();
    for (case, runs) in cases.iter().zip(per_case) {
        let statuses: Vec<&RunStatus> = runs.iter().map(|r| &r.status).collect();
        match NotRun::first(*case, &config.levels, &statuses) {
            Some(stopped) => not_run.push(stopped),
            None => studied.push(case_study(*case, &runs, norms)),
        }
    }
    Ok(Study {
        config: config.clone(),
        norms: norms.iter().copied().collect(),
        cases: studied,
        not_run,
        wall_seconds: clock.elapsed().as_secs_f64(),
    })
}

/// The order in which [`run_largest_first`] starts jobs of sizes `sizes`: their indices, the
/// largest first, ties in index order. A shard runs its share of this order
/// ([`crate::harness::shard::ShardSpec::share`]).
pub fn largest_first(sizes: &[usize]) -> Vec<usize> {
    let mut order: Vec<usize> = (0..sizes.len()).collect();
    order.sort_by_key(|&k| (std::cmp::Reverse(sizes[k]), k));
    order
}

/// Runs `job` on every item of `jobs` in parallel, the largest by `size` first (they take
/// longest; ties in the order of `jobs`), and returns the results in the order of `jobs`. The
/// first error stops the rest. Every study's case × level runs are scheduled here, and so are
/// shards ([`crate::harness::shard`]): under `--shard k/n` only that shard's share of the
/// largest-first order runs, its results are recorded and the study stops; under a merge the
/// results are read from the shards instead of run.
pub fn run_largest_first<J: Sync, T: Send + Serialize + DeserializeOwned + InRange>(
    jobs: &[J],
    size: impl Fn(&J) -> usize,
    job: impl Fn(&J) -> Result<T, Error> + Sync,
) -> Result<Vec<T>, Error> {
    let sizes: Vec<usize> = jobs.iter().map(size).collect();
    let order = largest_first(&sizes);
    let run_all = |order: &[usize]| -> Result<Vec<(usize, T)>, Error> {
        order
            .par_iter()
            .map(|&k| job(&jobs[k]).map(|r| (k, r)))
            .collect()
    };
    match plan::next_list(jobs.len())? {
        Schedule::All => {
            let mut results = run_all(&order)?;
            results.sort_by_key(|&(k, _)| k);
            Ok(results.into_iter().map(|(_, r)| r).collect())
        }
        Schedule::Share(spec) => {
            let mut results = run_all(&spec.share(&order))?;
            results.sort_by_key(|&(k, _)| k);
            let encoded = results
                .iter()
                .map(|(index, r)| {
                    codec::encode(r).map(|result| EncodedResult {
                        index: *index,
                        result,
                    })
                })
                .collect::<Result<_, _>>()?;
            Err(plan::finish_share(jobs.len(), encoded))
        }
        Schedule::Replay(results) => results
            .iter()
            .enumerate()
            .map(|(index, text)| {
                let result: T = codec::decode(index, text)?;
                match result.out_of_range() {
                    Some(why) => Err(ShardError::OutOfRange { index, why }.into()),
                    None => Ok(result),
                }
            })
            .collect(),
    }
}

/// Runs `job(case, level)` for every case index below `n_cases` and every level index of
/// `levels` ([`run_largest_first`]: the largest levels first), and returns each case's results
/// in level order.
pub fn run_case_levels<T: Send + Serialize + DeserializeOwned + InRange>(
    n_cases: usize,
    levels: &[usize],
    job: impl Fn(usize, usize) -> Result<T, Error> + Sync,
) -> Result<Vec<Vec<T>>, Error> {
    let jobs: Vec<(usize, usize)> = (0..n_cases)
        .flat_map(|c| (0..levels.len()).map(move |l| (c, l)))
        .collect();
    let mut results =
        run_largest_first(&jobs, |&(_, l)| levels[l], |&(c, l)| job(c, l))?.into_iter();
    Ok((0..n_cases)
        .map(|_| results.by_ref().take(levels.len()).collect())
        .collect())
}

fn case_study(case: Case, runs: &[RunResult], norms: &BTreeSet<Norm>) -> CaseStudy {
    let errors = norms
        .iter()
        .map(|&norm| (norm, runs.iter().map(|r| r.errors[&norm]).collect()))
        .collect();
    let levels = runs
        .iter()
        .map(|r| LevelRecord {
            nx: r.nx,
            h: r.h,
            dt: r.dt,
            steps: r.steps,
            dofs: r.dofs,
            timings: r.timings,
            multiplier_variation_ratio: r.multiplier_variation.and_then(|v| v.ratio()),
        })
        .collect();
    CaseStudy::from_levels(case, levels, errors)
}

impl InRange for RunResult {
    fn out_of_range(&self) -> Option<String> {
        positive("h", self.h)
            .or_else(|| positive("dt", self.dt))
            .or_else(|| errors_out_of_range(&self.errors))
    }
}
