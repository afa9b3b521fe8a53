//! Studies: a set of cases (scheme × mass variant) run at every level, in parallel, with the
//! rates of every requested norm, whatever the geometry: one job per case × level measured
//! against the study's reference, one reduce; every study's jobs and who
//! runs them, round-off ensembles, the regression gate, the scene a study is described by and
//! what the cost of a run or a study is held to. Above [`crate::harness::run`], whose runs it
//! drives.
//!
//! | module | its face |
//! |---|---|
//! | this file | [`Case`], [`StudyConfig`], [`run_study_on`] (the study of any geometry: [`StudyJobs`] measured by a [`LevelMeasure`], which [`crate::harness::reference`] implements), [`LevelOutcome`], [`Study::assemble`], [`CaseStudy`], [`NormRates`], [`fit_norm_rates`]; the case × level jobs [`CaseLevels`], [`by_case`] |
//! | [`executor`] | [`executor::JobList`], [`executor::Executor`] (local, a shard's share, a merge of the shards) and [`executor::Executed`] |
//! | [`shard`] | `--shard K/N` and `merge`: [`shard::ShardSpec`], [`shard::ShardFile`], [`shard::merge`], [`shard::codec`], [`shard::InRange`] |
//! | [`rates`] | [`rates::fit_rate`], [`rates::RateFit`], [`rates::observed_orders`] |
//! | [`sensitivity`] | round-off ensembles: [`sensitivity::run_sensitivity`], [`sensitivity::Sensitivity`], [`sensitivity::SensitivityClass`] |
//! | [`class_decision`] | how sure a round-off class is: [`class_decision::class_decision`] |
//! | [`decision`] | verdicts decided by 95 % intervals widened by a bias bound: [`decision::Estimate`], [`decision::Verdict`], [`decision::Decision`], [`decision::all_of`] |
//! | [`timing`] | costs with an interval and the orders they decide: [`timing::WallCost`], [`timing::cheapest`], [`timing::rank_ranges`], [`timing::level_costs`] |
//! | [`verdicts`] | the oscillation thresholds and words: [`verdicts::oscillates`], [`verdicts::oscillation_word`] |
//! | [`golden`] | the regression gate: [`golden::Golden`], [`golden::compare`], [`golden::gate`], [`golden::Drift`] |
//! | [`scene`] | scene files typed at load: [`scene::Scene`] |
//! | [`budget`] | what a run or a study costs and its limits: [`budget::Estimate`], [`budget::Limits`] |

pub mod budget;
pub mod class_decision;
pub mod decision;
pub mod error;
pub mod executor;
pub mod golden;
pub mod progress;
pub mod rates;
pub mod scene;
pub mod scene_error;
pub mod sensitivity;
pub mod shard;
pub mod timing;
pub mod verdicts;

use std::collections::{BTreeMap, BTreeSet};
use std::marker::PhantomData;

use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};

use crate::engine::error::ParameterError;
use crate::engine::fem::MassVariant;
use crate::engine::problem::Settings;
use crate::engine::schemes::Scheme;
use crate::harness::files::error as files;
use crate::harness::run::norms::Norm;
use crate::harness::run::physics::Physics;
use crate::harness::run::{BarRun, RunStatus, Timings};
use crate::harness::study::error::Error;
use crate::harness::study::executor::{Executed, Executor, JobList, ListResults};
use crate::harness::study::rates::{fit_rate, observed_orders, RateFit};
use crate::harness::study::shard::range::{errors_out_of_range, positive};
use crate::harness::study::shard::{InRange, ShardError};

/// A row of the tables: a scheme with its parameters and a mass variant.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Case {
    /// The time integrator.
    pub scheme: Scheme,
    /// The mass matrix.
    pub mass: MassVariant,
}

impl Case {
    /// Every scheme with every mass it is defined with ([`Scheme::is_defined_with`]), scheme
    /// by scheme.
    pub fn matrix(schemes: &[Scheme], masses: &[MassVariant]) -> Vec<Case> {
        schemes
            .iter()
            .flat_map(|&scheme| masses.iter().map(move |&mass| Case { scheme, mass }))
            .filter(|c| c.scheme.is_defined_with(c.mass))
            .collect()
    }

    /// The 14 rows of the paper's Tables 1–2, in order.
    pub fn paper_matrix() -> Vec<Case> {
        Self::matrix(&Scheme::paper_schemes(), &MassVariant::PAPER)
    }

    /// The rows of the tables report: the paper's 14, then every rival
    /// ([`Scheme::rival_schemes`]) with each of the paper's masses it is defined with.
    pub fn tables_matrix() -> Vec<Case> {
        let mut cases = Self::paper_matrix();
        cases.extend(Self::matrix(&Scheme::rival_schemes(), &MassVariant::PAPER));
        cases
    }

    /// `scheme/mass`, e.g. `crank-nicolson/redistributed`.
    pub fn id(&self) -> String {
        format!("{}/{}", self.scheme.name(), self.mass.name())
    }
}

/// Levels, time-step ratio, horizon and settings of a study.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct StudyConfig {
    /// `NX` of each level, increasing.
    pub levels: Vec<usize>,
    /// `Δx / Δt`.
    pub ratio: f64,
    /// Horizon `T`.
    pub horizon: f64,
    /// How every run of the study is solved (not written: a study's files name its
    /// conventions where they are not the harness's).
    #[serde(skip)]
    pub settings: Settings,
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
            settings: Settings::default(),
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

#[cfg(test)]
impl LevelRecord {
    /// A level of `nx` elements for the tests of the reports: `h = 1/nx`, `Δt = h/10`,
    /// `30·nx` steps, `nx` unknowns, no timings.
    pub(crate) fn synthetic(nx: usize) -> Self {
        Self {
            nx,
            h: 1.0 / nx as f64,
            dt: 0.1 / nx as f64,
            steps: 30 * nx,
            dofs: nx,
            timings: Timings::default(),
            multiplier_variation_ratio: None,
        }
    }
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

/// What the levels and rates of a series read back from a file (a verification's, a study's)
/// must satisfy, the first violation as `(field, value, what is allowed)`: levels of increasing
/// `NX` with a finite positive `h` and, where given, a finite multiplier variation ratio not
/// negative (the oscillation indicator, a ratio of total variations), one error per level in
/// every norm, each finite and not negative, and every fit the fit of its own errors (its rate
/// and interval within 1e-9 of a refit).
pub fn rates_inconsistency(
    levels: &[LevelRecord],
    rates: &[NormRates],
) -> Option<(String, String, String)> {
    let nx: Vec<usize> = levels.iter().map(|l| l.nx).collect();
    if nx.windows(2).any(|w| w[0] >= w[1]) || levels.iter().any(|l| !(l.h > 0.0 && l.h.is_finite()))
    {
        return Some((
            "levels".into(),
            format!("NX {nx:?}"),
            "increasing NX, each with a finite h > 0".into(),
        ));
    }
    for (k, level) in levels.iter().enumerate() {
        if let Some(ratio) = level
            .multiplier_variation_ratio
            .filter(|r| !(r.is_finite() && *r >= 0.0))
        {
            return Some((
                format!("levels[{k}].multiplier_variation_ratio"),
                ratio.to_string(),
                "a finite ratio of total variations, not negative".into(),
            ));
        }
    }
    for r in rates {
        let field = |what: &str| format!("rates[{}].{what}", r.norm.key());
        if r.errors.len() != levels.len() {
            return Some((
                field("errors"),
                format!("{} errors", r.errors.len()),
                format!("one per level ({})", levels.len()),
            ));
        }
        if let Some(e) = r.errors.iter().find(|e| !(e.is_finite() && **e >= 0.0)) {
            return Some((
                field("errors"),
                e.to_string(),
                "finite errors, not negative".into(),
            ));
        }
        let refit = fit_norm_rates(levels, BTreeMap::from([(r.norm, r.errors.clone())]));
        let expected = refit.first().and_then(|n| n.fit);
        let close = |a: Option<f64>, b: Option<f64>| match (a, b) {
            (Some(a), Some(b)) => (a - b).abs() <= 1e-9 * b.abs().max(1.0),
            (None, None) => true,
            _ => false,
        };
        let same = match (r.fit, expected) {
            (Some(f), Some(e)) => {
                close(Some(f.rate), Some(e.rate))
                    && close(f.ci_low, e.ci_low)
                    && close(f.ci_high, e.ci_high)
            }
            (None, None) => true,
            _ => false,
        };
        if !same {
            let shown = |f: Option<RateFit>| {
                f.map_or("none".to_string(), |f| {
                    format!("{:.6} [{:?}, {:?}]", f.rate, f.ci_low, f.ci_high)
                })
            };
            return Some((
                field("fit"),
                shown(r.fit),
                format!("the fit of its own errors: {}", shown(expected)),
            ));
        }
    }
    None
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

/// What one case × level job of a study measured, whatever the geometry: how its run ended,
/// the level's record and its errors against the study's reference (a bar's exact solution, a
/// box's fine-mesh reference). A run that stopped has no errors.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct LevelOutcome {
    /// How the run ended.
    #[serde(default)]
    pub status: RunStatus,
    /// The level's record.
    pub record: LevelRecord,
    /// The error of each norm measured.
    pub errors: BTreeMap<Norm, f64>,
    /// The run's penetration, energy above the start and contact-force sign, as its time loop
    /// measured them ([`crate::harness::run::physics::Physics`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub physics: Option<Physics>,
}

impl LevelOutcome {
    /// A bar's run at its level, its errors measured against the exact solution while it ran.
    pub fn of_bar_run(run: BarRun) -> Self {
        let bar = run.observed;
        Self {
            status: run.status,
            record: LevelRecord {
                nx: bar.nx,
                h: bar.h,
                dt: run.dt,
                steps: run.steps,
                dofs: run.dofs,
                timings: run.timings,
                multiplier_variation_ratio: bar.multiplier_variation.and_then(|v| v.ratio()),
            },
            errors: bar.errors,
            physics: run.physics,
        }
    }
}

impl InRange for LevelOutcome {
    fn out_of_range(&self) -> Option<String> {
        positive("h", self.record.h)
            .or_else(|| positive("dt", self.record.dt))
            .or_else(|| errors_out_of_range(&self.errors))
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
    /// What the time loop measured of each fitted case's runs, by case id, one entry per level
    /// in level order ([`crate::harness::run::physics::Physics`]); absent from a study written
    /// before the loop measured them.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub physics: BTreeMap<String, Vec<Physics>>,
}

impl Study {
    /// The study of `config` measuring `norms` from the outcomes of each case's levels (in
    /// level order), bar or box alike: a case whose runs all completed is fitted
    /// ([`CaseStudy::from_levels`]); one with a stopped run is listed as [`NotRun`] at its
    /// first stopped level. `wall_seconds`: the study's wall-clock time.
    pub fn assemble(
        config: StudyConfig,
        norms: Vec<Norm>,
        by_case: impl IntoIterator<Item = (Case, Vec<LevelOutcome>)>,
        wall_seconds: f64,
    ) -> Self {
        let mut cases = Vec::new();
        let mut not_run = Vec::new();
        let mut physics = BTreeMap::new();
        for (case, outcomes) in by_case {
            let statuses: Vec<&RunStatus> = outcomes.iter().map(|o| &o.status).collect();
            if let Some(stopped) = NotRun::first(case, &config.levels, &statuses) {
                not_run.push(stopped);
                continue;
            }
            let mut records = Vec::with_capacity(outcomes.len());
            let mut errors: BTreeMap<Norm, Vec<f64>> = BTreeMap::new();
            let measured: Option<Vec<Physics>> = outcomes.iter().map(|o| o.physics).collect();
            if let Some(levels) = measured {
                physics.insert(case.id(), levels);
            }
            for outcome in outcomes {
                for (norm, e) in outcome.errors {
                    errors.entry(norm).or_default().push(e);
                }
                records.push(outcome.record);
            }
            cases.push(CaseStudy::from_levels(case, records, errors));
        }
        Self {
            config,
            norms,
            cases,
            not_run,
            wall_seconds,
            physics,
        }
    }

    /// The study of `case`, if it was run.
    pub fn case(&self, case: &Case) -> Option<&CaseStudy> {
        self.cases.iter().find(|c| c.case == *case)
    }
}

/// A study of any geometry against its reference: its case × level jobs handed to `executor`,
/// each measured by `jobs`' [`LevelMeasure`], then fitted ([`Study::assemble`]). What the
/// study, or a shard's share of its jobs, gives back: the study and what each case it fitted
/// kept of its levels ([`LevelMeasure::Kept`]), in the order of its cases.
pub fn run_study_on<M: LevelMeasure>(
    executor: &Executor,
    jobs: &StudyJobs<'_, M>,
) -> Result<Executed<Fitted<M::Kept>>, Error> {
    executor.execute(&jobs.list())?.reduce(|ran| {
        jobs.check_norms(&ran.results)?;
        Ok(jobs.reduce_keeping(ran, jobs.cases))
    })
}

/// A study and what each case it fitted kept of its levels, in level order.
pub type Fitted<K> = (Study, Vec<(Case, Vec<K>)>);

/// How a study measures one case at one level against its reference: a bar's run against its
/// exact solution ([`crate::harness::reference::exact::ExactSolution`]), a box's run against a
/// fine-mesh reference ([`crate::harness::reference::fine_mesh`]).
pub trait LevelMeasure: Sync {
    /// What a job keeps besides its outcome, for the study's own use (nothing for a bar; a
    /// box's histories and round-off ensemble).
    type Kept: Send + Serialize + DeserializeOwned + InRange;

    /// The outcome of `case` at `level` (`NX`, or elements along a box's axis) against the
    /// reference, with what the job keeps.
    fn measure(&self, case: Case, level: usize) -> Result<Measured<Self::Kept>, files::Error>;
}

impl<T: LevelMeasure> LevelMeasure for &T {
    type Kept = T::Kept;

    fn measure(&self, case: Case, level: usize) -> Result<Measured<T::Kept>, files::Error> {
        (**self).measure(case, level)
    }
}

/// One job's measure: its outcome and what it keeps.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Measured<K> {
    /// The level's outcome against the reference.
    pub outcome: LevelOutcome,
    /// What the study keeps besides.
    pub kept: K,
}

impl<K: InRange> InRange for Measured<K> {
    fn out_of_range(&self) -> Option<String> {
        self.outcome
            .out_of_range()
            .or_else(|| self.kept.out_of_range())
    }

    fn level(&self) -> Option<usize> {
        Some(self.outcome.record.nx)
    }
}

/// A study as its jobs (one per case × level, [`StudyJobs::list`], each measured by `M`) and
/// its reduce step ([`StudyJobs::reduce`]), for [`run_study_on`] or a command that hands
/// several lists to one executor ([`crate::harness::study::executor::Batch`]).
pub struct StudyJobs<'a, M> {
    measure: M,
    cases: &'a [Case],
    norms: Vec<Norm>,
    config: &'a StudyConfig,
}

impl<'a, M: LevelMeasure> StudyJobs<'a, M> {
    /// The study of `cases` at the levels of `config`, each measured by `measure`, of the
    /// norms `norms`.
    pub fn measured_by(
        measure: M,
        cases: &'a [Case],
        norms: &BTreeSet<Norm>,
        config: &'a StudyConfig,
    ) -> Self {
        Self {
            measure,
            cases,
            norms: norms.iter().copied().collect(),
            config,
        }
    }

    /// The measure of each job.
    pub fn measure(&self) -> &M {
        &self.measure
    }

    /// The jobs: case `c` at level `l` is job `c · levels + l` ([`CaseLevels`]).
    pub fn list(&self) -> impl JobList<Output = Measured<M::Kept>> + '_ {
        CaseLevels::new(self.cases.len(), &self.config.levels, |c, l| {
            self.measure.measure(self.cases[c], self.config.levels[l])
        })
    }

    /// The study of the cases `kept` from every job of the list (`ran`, in the list's order),
    /// as a study of those cases alone would be: `kept` are some of the list's cases in its
    /// order (all of them, or those an earlier study ran, so that the list need not depend on
    /// that study). Its wall time is the list's.
    pub fn reduce(&self, ran: ListResults<Measured<M::Kept>>, kept: &[Case]) -> Study {
        self.reduce_keeping(ran, kept).0
    }

    /// Refuses `results` (case by case, level by level, as [`CaseLevels`] orders them) where a
    /// completed run's errors are not of this study's norms or a stopped run has errors: what
    /// only a forged shard holds, which the fit would take for a level's errors.
    fn check_norms(&self, results: &[Measured<M::Kept>]) -> Result<(), ShardError> {
        let levels = &self.config.levels;
        for (k, measured) in results.iter().enumerate() {
            let outcome = &measured.outcome;
            let found: Vec<Norm> = outcome.errors.keys().copied().collect();
            let mut asked = self.norms.clone();
            asked.sort();
            if !outcome.status.is_completed() {
                asked.clear();
            }
            if found != asked {
                let key = |norms: &[Norm]| norms.iter().map(|n| n.key().to_string()).collect();
                return Err(ShardError::Norms {
                    case: self
                        .cases
                        .get(k / levels.len().max(1))
                        .map_or_else(String::new, Case::id),
                    level: levels.get(k % levels.len().max(1)).copied().unwrap_or(0),
                    found: key(&found),
                    asked: key(&asked),
                });
            }
        }
        Ok(())
    }

    /// [`StudyJobs::reduce`], with what each case the study fitted kept of its levels.
    pub fn reduce_keeping(
        &self,
        ran: ListResults<Measured<M::Kept>>,
        kept: &[Case],
    ) -> Fitted<M::Kept> {
        let config = self.config;
        let mut by_case = Vec::new();
        let mut kept_by_case = Vec::new();
        for (case, measured) in kept_cases(self.cases, ran.results, config.levels.len(), kept) {
            let completed = measured.iter().all(|m| m.outcome.status.is_completed());
            let (outcomes, levels_kept): (Vec<LevelOutcome>, Vec<M::Kept>) =
                measured.into_iter().map(|m| (m.outcome, m.kept)).unzip();
            if completed {
                kept_by_case.push((case, levels_kept));
            }
            by_case.push((case, outcomes));
        }
        let study = Study::assemble(
            config.clone(),
            self.norms.clone(),
            by_case,
            ran.wall_seconds,
        );
        (study, kept_by_case)
    }
}

/// The case × level jobs of a study: job `c · levels + l` runs case `c` at level `l`, its size
/// the level; [`by_case`] splits their results back into cases.
pub struct CaseLevels<'a, T, F> {
    jobs: Vec<(usize, usize)>,
    levels: &'a [usize],
    job: F,
    output: PhantomData<fn() -> T>,
}

impl<'a, T, F: Fn(usize, usize) -> Result<T, files::Error> + Sync> CaseLevels<'a, T, F> {
    /// The jobs of `n_cases` cases at every level of `levels`, each running `job(case, level)`
    /// with their indices.
    pub fn new(n_cases: usize, levels: &'a [usize], job: F) -> Self {
        Self {
            jobs: (0..n_cases)
                .flat_map(|c| (0..levels.len()).map(move |l| (c, l)))
                .collect(),
            levels,
            job,
            output: PhantomData,
        }
    }
}

impl<T, F> JobList for CaseLevels<'_, T, F>
where
    T: Send + Serialize + DeserializeOwned + InRange,
    F: Fn(usize, usize) -> Result<T, files::Error> + Sync,
{
    type Output = T;

    fn count(&self) -> usize {
        self.jobs.len()
    }

    fn size(&self, index: usize) -> usize {
        self.levels[self.jobs[index].1]
    }

    fn run(&self, index: usize) -> Result<T, Error> {
        let (c, l) = self.jobs[index];
        Ok((self.job)(c, l)?)
    }

    fn level(&self, index: usize) -> Option<usize> {
        Some(self.levels[self.jobs[index].1])
    }
}

/// The results of the [`CaseLevels`] jobs of `cases` (in job order, `levels` per case), case by
/// case, of the cases in `kept` only.
pub fn kept_cases<T>(
    cases: &[Case],
    results: Vec<T>,
    levels: usize,
    kept: &[Case],
) -> Vec<(Case, Vec<T>)> {
    cases
        .iter()
        .copied()
        .zip(by_case(results, levels))
        .filter(|(case, _)| kept.contains(case))
        .collect()
}

/// The results of [`CaseLevels`] jobs, in job order, as each case's in level order.
pub fn by_case<T>(results: Vec<T>, levels: usize) -> Vec<Vec<T>> {
    let cases = results.len().checked_div(levels).unwrap_or(0);
    let mut results = results.into_iter();
    (0..cases)
        .map(|_| results.by_ref().take(levels).collect())
        .collect()
}

impl InRange for BarRun {
    fn out_of_range(&self) -> Option<String> {
        positive("h", self.observed.h)
            .or_else(|| positive("dt", self.dt))
            .or_else(|| errors_out_of_range(&self.observed.errors))
    }
}
