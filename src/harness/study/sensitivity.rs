//! Round-off sensitivity of a study: every case and level is run as an ensemble beside the
//! unperturbed run, of two sets of `K` members each ([`Member`]):
//! - **initial data**: member `m = 1..=K` adds to the initial displacement seeded noise of
//!   relative size `A` (about 1e-13, far below anything physical);
//! - **every step**: member `m = 1..=K` perturbs the state its scheme carries after every step
//!   by a seeded relative amount in `±ε`, `ε` = [`STEP_EPSILON`], the unit round-off
//!   ([`crate::engine::problem::StepPerturbation`]: why this rule).
//!
//! Perturbing the initial data only does not reproduce what another code's round-off at every
//! step does to a chaotic case (its members start apart and then follow the unperturbed
//! dynamics); the per-step members do. The spread of all the members' errors and rates, and how
//! fast their contact-node displacements part from the unperturbed run, tell reproducible cases
//! from round-off chaotic ones.
//!
//! The classification rules were fixed before any result was looked at:
//! - **reproducible**: no member's contact-node displacement ever differs from the unperturbed
//!   run's by more than [`PARTING`] (1e-8), at any level;
//! - **chaotic**: at some level a member's separation grows through at least
//!   [`MIN_GROWTH_DECADES`] decade thresholds with a positive exponential rate and reaches
//!   [`RUNAWAY`] (1e-4, the size of the solution's own features), **and** some norm's fitted rate
//!   varies over the ensemble by more than [`CHAOTIC_RATE_RANGE`] (0.005);
//! - **event-sensitive**: members part, but not in that way (isolated contact-set flips that
//!   cause a bounded jump).
//!
//! A bar's case is **screened** first ([`SCREEN_MEMBERS`]): at every level, the first
//! `s = min(SCREEN_MEMBERS, K)` members of each set run; only when one of them parts (by more
//! than [`PARTING`], at some level) do the other `K − s` of each set run, at every level. A case
//! none of whose `2s` screening members parts is reproducible on them alone: the rule for
//! *reproducible* cannot be met by more members once a screening member parts, and a case that
//! parts keeps the same `2K` members, seed for seed, as without the screen.
//!
//! Members stream their observers; a case's job holds the unperturbed contact history and one
//! member's at a time, so memory does not grow with members × steps.

use std::collections::{BTreeMap, BTreeSet};

use serde::{Deserialize, Serialize};

use crate::engine::error::{require_positive, ParameterError};
use crate::engine::problem::{Perturbation, Settings, StepPerturbation, UNIT_ROUNDOFF};
use crate::harness::files::error::Error;
use crate::harness::run::norms::Norm;
use crate::harness::run::{run, BarRun, Observables, Problem1d, RunConfig, RunStatus};
use crate::harness::study::decision::{Decision, Verdict};
use crate::harness::study::error as study;
use crate::harness::study::executor::{run_local, Executed, Executor, JobList, ListResults};
use crate::harness::study::rates::{fit_rate, least_squares_slope, RateFit};
use crate::harness::study::shard::range::{errors_out_of_range, not_negative};
use crate::harness::study::shard::InRange;
use crate::harness::study::{Case, StudyConfig};

/// A separation above this is a member that has parted from the unperturbed run.
pub const PARTING: f64 = 1e-8;

/// A separation that reaches this has run away: it is of the size of the solution's features.
pub const RUNAWAY: f64 = 1e-4;

/// The fewest decade thresholds a separation must cross for its growth rate to be fitted.
pub const MIN_GROWTH_DECADES: usize = 3;

/// A case whose fitted rate of some norm varies over the ensemble by more than this (and whose
/// members run away) is round-off chaotic.
pub const CHAOTIC_RATE_RANGE: f64 = 0.005;

/// `ε` of the members perturbed at every step: the unit round-off `u = 2⁻⁵³`, the size of one
/// rounding (not tuned to any comparison).
pub const STEP_EPSILON: f64 = UNIT_ROUNDOFF;

/// The members of each set a bar's case is first run with at every level; the rest of its
/// ensemble runs only when one of them parts (the module's screen).
pub const SCREEN_MEMBERS: usize = 4;

/// The decade thresholds whose first-crossing times give the separation growth rate.
const DECADES: [f64; 8] = [1e-11, 1e-10, 1e-9, 1e-8, 1e-7, 1e-6, 1e-5, 1e-4];

/// The ensemble: how many perturbed members of each set, and the initial-data noise's size
/// relative to `max |u⁰|` (JSON `{"members": K, "amplitude": A}`). A study's ensemble runs `2K`
/// perturbed members ([`EnsembleConfig::members_of_study`]): `K` on the initial data, `K` at
/// every step with `ε` = [`STEP_EPSILON`].
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EnsembleConfig {
    /// Members of each set per case and level (the unperturbed run comes on top).
    pub members: usize,
    /// Relative amplitude `A`: each displacement dof but the contact dof moves by a uniform
    /// amount in `±A·max|u⁰|`.
    pub amplitude: f64,
}

/// The initial data an ensemble's initial-data members carry their noise on.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum InitialNoise {
    /// A bar's initial displacement, the contact dof untouched ([`run_members`]).
    Displacement,
    /// A box's initial velocity, every dof (`crate::harness::reference::fine_mesh::ensemble`).
    Velocity,
}

impl InitialNoise {
    /// Where the noise is, as the reports say it.
    fn describe(self) -> &'static str {
        match self {
            Self::Displacement => "initial displacement carries seeded noise",
            Self::Velocity => "initial velocity carries seeded noise",
        }
    }

    /// What the noise leaves alone, as the reports say it.
    fn untouched(self) -> &'static str {
        match self {
            Self::Displacement => "contact dof untouched",
            Self::Velocity => "displacement untouched",
        }
    }

    /// Whether an ensemble with this noise is screened ([`SCREEN_MEMBERS`]): a bar's
    /// ([`SensitivityJobs`]) is, a box's runs every member.
    fn screened(self) -> bool {
        matches!(self, Self::Displacement)
    }
}

impl EnsembleConfig {
    /// What its members are, as the reports say it: the two sets of [`Member`]s, a bar's.
    pub fn describe(&self) -> String {
        self.describe_on(InitialNoise::Displacement)
    }

    /// What its members are with their initial noise on `noise`.
    pub fn describe_on(&self, noise: InitialNoise) -> String {
        let screen = if noise.screened() && self.screened() < self.members {
            format!(
                "; each case runs the first {s} of each set at every level, and the other {rest} \
                 of each set only when one of those {both} parts from the unperturbed run by \
                 more than {PARTING:e} (a case none of them parts is reproducible on {both} \
                 members)",
                s = self.screened(),
                rest = self.members - self.screened(),
                both = 2 * self.screened(),
            )
        } else {
            String::new()
        };
        format!(
            "{} members whose {} of relative size {:e} ({}) and {} members whose carried state \
             is perturbed after every step by a relative amount in ±{:.2e} (the unit \
             round-off){screen}",
            self.members,
            noise.describe(),
            self.amplitude,
            noise.untouched(),
            self.members,
            STEP_EPSILON
        )
    }

    /// The members of each set a bar's case is screened with: [`SCREEN_MEMBERS`], at most `K`.
    pub fn screened(&self) -> usize {
        SCREEN_MEMBERS.min(self.members)
    }
}

impl Default for EnsembleConfig {
    fn default() -> Self {
        Self {
            members: 16,
            amplitude: 1e-13,
        }
    }
}

/// One perturbed member of an ensemble, by the seed of its noise.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Member {
    /// Seeded noise on the initial data ([`Settings::round_off`]).
    InitialData {
        /// The seed.
        seed: u64,
    },
    /// A seeded relative perturbation of `ε` = [`STEP_EPSILON`] of the carried state after
    /// every step ([`Settings::step_round_off`]).
    EveryStep {
        /// The seed.
        seed: u64,
    },
}

impl Member {
    /// `settings` with this member's perturbation: initial-data noise of absolute amplitude
    /// `amplitude` (the relative `A` times the data's scale), or the per-step one.
    pub fn perturb(self, settings: Settings, amplitude: f64) -> Settings {
        match self {
            Member::InitialData { seed } => {
                settings.with_round_off(Perturbation { amplitude, seed })
            }
            Member::EveryStep { seed } => settings.with_step_round_off(StepPerturbation {
                epsilon: STEP_EPSILON,
                seed,
            }),
        }
    }
}

impl EnsembleConfig {
    /// The members perturbed on the initial data, seeds `1..=K`.
    pub fn initial_data_members(&self) -> impl Iterator<Item = Member> {
        (1..=self.members as u64).map(|seed| Member::InitialData { seed })
    }

    /// The members perturbed at every step, seeds `1..=K`.
    pub fn every_step_members(&self) -> impl Iterator<Item = Member> {
        (1..=self.members as u64).map(|seed| Member::EveryStep { seed })
    }

    /// How many perturbed members a study runs per case and level: `2K`, both sets.
    pub fn perturbed_members(&self) -> usize {
        2 * self.members
    }

    /// A study's members: the initial-data set, then the every-step set (`2K`).
    pub fn members_of_study(&self) -> impl Iterator<Item = Member> {
        self.initial_data_members().chain(self.every_step_members())
    }

    /// The members of each set with seeds in `seeds`: the initial-data ones, then the
    /// every-step ones.
    fn members_seeded(&self, seeds: std::ops::RangeInclusive<u64>) -> Vec<Member> {
        let initial = seeds.clone().map(|seed| Member::InitialData { seed });
        initial
            .chain(seeds.map(|seed| Member::EveryStep { seed }))
            .collect()
    }

    /// At least two members, an amplitude in (0, 1e-3].
    pub fn validate(&self) -> Result<(), ParameterError> {
        if !(2..=1024).contains(&self.members) {
            return Err(ParameterError::new(
                "members",
                self.members,
                "an integer in [2, 1024]",
            ));
        }
        require_positive("amplitude", self.amplitude)?;
        if self.amplitude > 1e-3 {
            return Err(ParameterError::new(
                "amplitude",
                self.amplitude,
                "a relative size in (0, 1e-3] (round-off scale: 1e-13 by default)",
            ));
        }
        Ok(())
    }
}

/// The class of a case.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum SensitivityClass {
    /// Members stay within [`PARTING`] of the unperturbed run.
    Reproducible,
    /// Members part through bounded jumps that do not grow.
    EventSensitive,
    /// The separation grows exponentially and some rate's ensemble range exceeds
    /// [`CHAOTIC_RATE_RANGE`].
    Chaotic,
}

impl SensitivityClass {
    /// `reproducible`, `event-sensitive` or `chaotic`.
    pub fn name(self) -> &'static str {
        match self {
            Self::Reproducible => "reproducible",
            Self::EventSensitive => "event-sensitive",
            Self::Chaotic => "chaotic",
        }
    }
}

/// The ensemble minimum, median and maximum of one quantity.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Spread {
    /// Smallest member value.
    pub min: f64,
    /// Median (the mean of the two middle values for an even count).
    pub median: f64,
    /// Largest member value.
    pub max: f64,
}

impl Spread {
    /// The spread of `values` (at least one, all finite).
    pub fn of(values: &[f64]) -> Self {
        let mut v = values.to_vec();
        v.sort_by(f64::total_cmp);
        let n = v.len();
        let median = if n % 2 == 1 {
            v[n / 2]
        } else {
            0.5 * (v[n / 2 - 1] + v[n / 2])
        };
        Self {
            min: v[0],
            median,
            max: v[n - 1],
        }
    }

    /// `max − min`.
    pub fn range(&self) -> f64 {
        self.max - self.min
    }
}

/// How one member's contact-node displacement parts from the unperturbed run's (the box
/// ensembles of `crate::harness::reference::fine_mesh::ensemble` measure it on the centre contact node).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Separation {
    /// The first step at which `|u_m(0, t_n) − u(0, t_n)| > PARTING`.
    pub parting_step: Option<usize>,
    /// The least-squares slope of `ln(threshold)` against the first time the running maximum of
    /// the separation crosses each decade threshold (a finite-time Lyapunov exponent), when at
    /// least [`MIN_GROWTH_DECADES`] thresholds are crossed after the start and the member parts.
    growth: Option<f64>,
    /// The largest separation.
    largest: f64,
}

impl Separation {
    /// The separation of `member` from `base`, two histories of the contact node's displacement
    /// (or of its gap: the same up to the constant gap) at the times `time`.
    pub fn between(time: &[f64], base: &[f64], member: &[f64]) -> Self {
        let mut largest = 0.0_f64;
        let mut parting_step = None;
        let (mut crossing_times, mut crossing_levels) = (Vec::new(), Vec::new());
        let start = (base[0] - member[0]).abs();
        for (n, ((&t, &a), &b)) in time.iter().zip(base).zip(member).enumerate() {
            let d = (a - b).abs();
            if d > PARTING && parting_step.is_none() {
                parting_step = Some(n);
            }
            if d > largest {
                for &threshold in DECADES.iter().filter(|&&x| x > start.max(largest)) {
                    if d >= threshold {
                        crossing_times.push(t);
                        crossing_levels.push(threshold.ln());
                    }
                }
                largest = d;
            }
        }
        let parted = parting_step.is_some();
        // Thresholds all crossed within one step: an instantaneous jump, infinitely fast.
        let growth = (parted && crossing_times.len() >= MIN_GROWTH_DECADES).then(|| {
            least_squares_slope(&crossing_times, &crossing_levels).unwrap_or(f64::INFINITY)
        });
        Self {
            parting_step,
            growth,
            largest,
        }
    }
}

/// One case of the sensitivity study (the field names are the documented JSON fields of
/// `reports/sensitivity.json`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CaseSensitivity {
    /// The golden case name, e.g. `crank-nicolson/standard`.
    pub case: String,
    /// The class by the module's rules.
    pub class: SensitivityClass,
    /// `class == chaotic`.
    pub chaotic: bool,
    /// Members perturbed on the initial data per level: the ensemble's `K`, or for a screened
    /// case none of whose screening members parted, [`EnsembleConfig::screened`].
    pub members: usize,
    /// The relative amplitude `A`.
    pub amplitude: f64,
    /// Members perturbed at every step per level, as many as [`CaseSensitivity::members`] (0 in
    /// a file written before they were run).
    #[serde(default)]
    pub step_members: usize,
    /// Their relative perturbation `ε` per step.
    #[serde(default)]
    pub step_epsilon: f64,
    /// `NX` of each level.
    pub levels: Vec<usize>,
    /// Norm key → the ensemble spread (all members of both sets and levels) of the rate fitted
    /// over all levels, member by member.
    pub rates: BTreeMap<String, Spread>,
    /// Norm key → the hull `[lowest, highest]` of the members' own 95 % fit intervals of that
    /// rate (the members whose fit has one); absent in a file written before it was recorded.
    #[serde(default)]
    pub rate_fit_intervals: BTreeMap<String, (f64, f64)>,
    /// Norm key → the ensemble spread of the error at each level.
    pub errors: BTreeMap<String, Vec<Spread>>,
    /// Per level: the first step at which some member parts (separation > 1e-8); `null` where
    /// no member parts.
    pub predictability_steps: Vec<Option<usize>>,
    /// Per level: the median growth rate of the separation over the members whose growth could
    /// be fitted (per unit time); `null` where none.
    pub separation_growth: Vec<Option<f64>>,
    /// Per level: the largest separation of any member.
    pub largest_separation: Vec<f64>,
    /// Per level: the wall seconds of the ensemble's runs that do the study's own work, the
    /// unperturbed run then the initial-data members (the every-step members are left out: they
    /// draw a perturbation of every carried value after every step); empty in a file written
    /// before they were kept, and for a box's ensembles. The costs of `work-precision.md` and
    /// `schemes.md` are timed over them ([`crate::harness::study::timing`]).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub wall_seconds: Vec<Vec<f64>>,
}

impl CaseSensitivity {
    /// The interval the ensemble gives the rate of `norm`: the members' `[min, max]` joined with
    /// their own 95 % fit intervals ([`CaseSensitivity::rate_fit_intervals`]), the smallest
    /// interval holding every member's rate and every member's interval; `None` without a rate.
    pub fn rate_interval(&self, norm: &str) -> Option<(f64, f64)> {
        let spread = self.rates.get(norm)?;
        Some(match self.rate_fit_intervals.get(norm) {
            Some(&(low, high)) => (spread.min.min(low), spread.max.max(high)),
            None => (spread.min, spread.max),
        })
    }

    /// The largest relative spread `(max − min)/|median|` of any error of `norm` over the levels.
    pub fn relative_error_spread(&self, norm: &str) -> Option<f64> {
        self.errors.get(norm).map(|levels| {
            levels
                .iter()
                .map(|s| s.range() / s.median.abs())
                .fold(0.0, f64::max)
        })
    }
}

/// The sensitivity study of a scene's cases.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Sensitivity {
    /// The ensemble.
    pub ensemble: EnsembleConfig,
    /// Levels, ratio and horizon.
    pub config: StudyConfig,
    /// One entry per case.
    pub cases: Vec<CaseSensitivity>,
    /// Wall-clock time of the whole study, seconds.
    pub wall_seconds: f64,
}

impl Sensitivity {
    /// The entry of the case named `id` (`scheme/mass`).
    pub fn case(&self, id: &str) -> Option<&CaseSensitivity> {
        self.cases.iter().find(|c| c.case == id)
    }

    /// One line per case, `  scheme/mass  class`, the classes aligned in one column.
    pub fn class_lines(&self) -> Vec<String> {
        let width = self.cases.iter().map(|c| c.case.len()).max().unwrap_or(0);
        self.cases
            .iter()
            .map(|c| format!("  {:width$}  {}", c.case, c.class.name()))
            .collect()
    }
}

/// Runs `problem` with `config` as an ensemble of its initial-data members
/// ([`EnsembleConfig::initial_data_members`]; the stability suite's): see [`run_members`].
pub fn run_ensemble(
    problem: &Problem1d,
    config: &RunConfig,
    ensemble: EnsembleConfig,
    observe: &mut dyn FnMut(BarRun, Option<Separation>) -> Result<(), Error>,
) -> Result<BarRun, Error> {
    ensemble.validate()?;
    let members: Vec<Member> = ensemble.initial_data_members().collect();
    run_members(problem, config, ensemble.amplitude, &members, observe)
}

/// Runs `problem` with `config` as an ensemble: the unperturbed run ([`Unperturbed::run`]), then
/// each of `members` beside it ([`Unperturbed::members`]). Returns the unperturbed result; when
/// it did not complete, no member runs.
pub fn run_members(
    problem: &Problem1d,
    config: &RunConfig,
    amplitude: f64,
    members: &[Member],
    observe: &mut dyn FnMut(BarRun, Option<Separation>) -> Result<(), Error>,
) -> Result<BarRun, Error> {
    let base = Unperturbed::run(problem, config)?;
    base.members(problem, amplitude, members, observe)?;
    Ok(base.result)
}

/// An ensemble's unperturbed run, kept so that members can be run beside it at any time.
struct Unperturbed {
    /// Its result, with its contact history.
    result: BarRun,
    /// The members' configuration: `config` with the contact history, without the balance.
    config: RunConfig,
    /// `max |u⁰|` of the unperturbed initial displacement (at least the smallest positive
    /// number): the scale of the initial-data noise.
    scale: f64,
}

impl Unperturbed {
    /// Runs `problem` with `config`, the contact history recorded whatever `config` asks; the
    /// energy balance, when `config` asks for it, is evaluated on this run only.
    fn run(problem: &Problem1d, config: &RunConfig) -> Result<Self, Error> {
        let mut config = config.clone();
        config.observables.contact_history = true;
        let (bar, model) = problem.model(config.nx, config.mass)?;
        let (u0, _) = problem.initial_dofs(&bar, &model);
        let scale = u0
            .iter()
            .fold(0.0_f64, |m, x| m.max(x.abs()))
            .max(f64::MIN_POSITIVE);
        let result = run(problem, &config, &mut [])?;
        config.observables.energy_balance = false;
        Ok(Self {
            result,
            config,
            scale,
        })
    }

    /// Runs each of `members` ([`Member::perturb`]: initial-data noise of amplitude
    /// `amplitude·max|u⁰|`, the contact dofs untouched; or the per-step perturbation) and hands
    /// its result to `observe` with its [`Separation`] from the unperturbed run (`None` for a
    /// member that did not complete: its status says why), then drops it, so memory holds the
    /// unperturbed contact history and one member's; an error `observe` returns stops the
    /// ensemble. Runs none when the unperturbed run did not complete.
    fn members(
        &self,
        problem: &Problem1d,
        amplitude: f64,
        members: &[Member],
        observe: &mut dyn FnMut(BarRun, Option<Separation>) -> Result<(), Error>,
    ) -> Result<(), Error> {
        let Some(base_history) = self
            .result
            .observed
            .contact_history
            .as_ref()
            .filter(|_| self.result.status.is_completed())
        else {
            return Ok(());
        };
        let mut config = self.config.clone();
        for member in members {
            config.settings = member.perturb(self.config.settings, amplitude * self.scale);
            let r = run(problem, &config, &mut [])?;
            let separation = r
                .observed
                .contact_history
                .as_ref()
                .filter(|_| r.status.is_completed())
                .map(|h| {
                    Separation::between(
                        &base_history.time,
                        &base_history.displacement,
                        &h.displacement,
                    )
                });
            observe(r, separation)?;
        }
        Ok(())
    }
}

/// Whether some member's separation grows exponentially (a positive fitted growth) to
/// [`RUNAWAY`].
fn runs_away(separations: &[Separation]) -> bool {
    separations
        .iter()
        .any(|s| s.largest >= RUNAWAY && s.growth.is_some_and(|g| g > 0.0))
}

/// The round-off sensitivity of one run (one mesh, one time step), as the stability suite
/// reports it. With no rate to fit at one mesh, a run is *chaotic* on the separation rule
/// alone: some member's separation grows exponentially to [`RUNAWAY`]; *reproducible* when no
/// member parts by more than [`PARTING`]; *event-sensitive* otherwise.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct RunSensitivity {
    /// The class by the rule above.
    pub class: SensitivityClass,
    /// Perturbed members.
    pub members: usize,
    /// The relative amplitude `A`.
    pub amplitude: f64,
    /// The first step at which some member parts; `null` where none does.
    pub predictability_step: Option<usize>,
    /// `predictability_step × Δt`: the predictability horizon in time.
    pub predictability_time: Option<f64>,
    /// The median fitted growth rate of the separation (per unit time); `null` where none.
    pub separation_growth: Option<f64>,
    /// The largest separation of any member.
    pub largest_separation: f64,
}

impl RunSensitivity {
    /// The sensitivity of a run with time step `dt` from its members' separations.
    pub fn of(separations: &[Separation], dt: f64, ensemble: EnsembleConfig) -> Self {
        let predictability_step = separations.iter().filter_map(|s| s.parting_step).min();
        let class = if predictability_step.is_none() {
            SensitivityClass::Reproducible
        } else if runs_away(separations) {
            SensitivityClass::Chaotic
        } else {
            SensitivityClass::EventSensitive
        };
        Self {
            class,
            members: ensemble.members,
            amplitude: ensemble.amplitude,
            predictability_step,
            predictability_time: predictability_step.map(|n| n as f64 * dt),
            separation_growth: median_growth(separations),
            largest_separation: largest_separation(separations),
        }
    }
}

/// The median fitted growth rate over the members whose growth could be fitted.
fn median_growth(separations: &[Separation]) -> Option<f64> {
    let g: Vec<f64> = separations.iter().filter_map(|s| s.growth).collect();
    (!g.is_empty()).then(|| Spread::of(&g).median)
}

/// The largest separation of any member.
fn largest_separation(separations: &[Separation]) -> f64 {
    separations.iter().fold(0.0_f64, |m, s| m.max(s.largest))
}

/// What one (case, level) job measured: every member's errors and separation, or the run that
/// stopped it.
#[derive(Serialize, Deserialize)]
pub struct LevelEnsemble {
    /// Member by member, the error of every norm.
    pub(crate) errors: Vec<BTreeMap<Norm, f64>>,
    /// Member by member, its separation from the unperturbed run.
    pub(crate) separations: Vec<Separation>,
    /// How the unperturbed run, or the first member that did not complete, stopped; the
    /// members after it were not measured. A study that keeps the case fails with it; one that
    /// does not (a case an earlier study could not run) drops it.
    #[serde(default)]
    pub(crate) stopped: Option<RunStatus>,
}

impl InRange for LevelEnsemble {
    fn out_of_range(&self) -> Option<String> {
        self.errors
            .iter()
            .find_map(errors_out_of_range)
            .or_else(|| {
                self.separations
                    .iter()
                    .find_map(|s| not_negative("separation", s.largest))
            })
    }
}

/// One level of a case: `members` (`initial` initial-data ones first, then every-step ones) run
/// beside its unperturbed run `base` ([`Unperturbed::members`]), with the wall seconds of the
/// initial-data members; stopped with `base` when it did not complete.
fn level_ensemble(
    problem: &Problem1d,
    base: &Unperturbed,
    amplitude: f64,
    members: &[Member],
    initial: usize,
) -> Result<TimedEnsemble, Error> {
    let mut errors = Vec::with_capacity(members.len());
    let mut separations = Vec::with_capacity(members.len());
    let mut seconds = Vec::with_capacity(initial);
    let mut stopped = None;
    let observe = &mut |member: BarRun, separation| {
        if let Err(e) = member.status.completed() {
            stopped = Some(member.status);
            return Err(e.into());
        }
        if errors.len() < initial {
            seconds.push(member.timings.total());
        }
        errors.push(member.observed.errors);
        separations.extend(separation);
        Ok(())
    };
    let stopped = match base.members(problem, amplitude, members, observe) {
        Err(_) if stopped.is_some() => stopped,
        outcome => {
            outcome?;
            Some(base.result.status.clone()).filter(|s| !s.is_completed())
        }
    };
    Ok(TimedEnsemble {
        ensemble: LevelEnsemble {
            errors,
            separations,
            stopped,
        },
        seconds,
    })
}

/// Every level of `case` as its ensemble, screened (the module's rule): the unperturbed run and
/// the first [`EnsembleConfig::screened`] members of each set at every level; when one of them
/// parts, the others beside the same unperturbed runs, appended in one order at every level
/// (every statistic of an ensemble takes each member level by level, in whatever order). A level
/// that stops ends the case there.
fn case_ensemble(
    problem: &Problem1d,
    case: Case,
    config: &StudyConfig,
    norms: &BTreeSet<Norm>,
    ensemble: EnsembleConfig,
) -> Result<Vec<TimedEnsemble>, Error> {
    let run_config = |nx| RunConfig {
        nx,
        ratio: config.ratio,
        scheme: case.scheme,
        mass: case.mass,
        observables: Observables {
            norms: norms.clone(),
            ..Observables::default()
        },
        settings: config.settings,
    };
    let amplitude = ensemble.amplitude;
    let screened = ensemble.screened();
    let screen = ensemble.members_seeded(1..=screened as u64);
    let (mut bases, mut levels) = (Vec::new(), Vec::new());
    for &nx in &config.levels {
        let base = Unperturbed::run(problem, &run_config(nx))?;
        let mut level = level_ensemble(problem, &base, amplitude, &screen, screened)?;
        level.seconds.insert(0, base.result.timings.total());
        let stopped = level.ensemble.stopped.is_some();
        levels.push(level);
        bases.push(base);
        if stopped {
            return Ok(levels);
        }
    }
    let parted = levels
        .iter()
        .flat_map(|l| &l.ensemble.separations)
        .any(|s| s.parting_step.is_some());
    let rest = ensemble.members - screened;
    if !parted || rest == 0 {
        return Ok(levels);
    }
    let others = ensemble.members_seeded(screened as u64 + 1..=ensemble.members as u64);
    for (level, base) in levels.iter_mut().zip(&bases) {
        level.absorb(level_ensemble(problem, base, amplitude, &others, rest)?);
        if level.ensemble.stopped.is_some() {
            break;
        }
    }
    Ok(levels)
}

/// A bar's level ensemble with the wall seconds of its runs that do the study's own work: the
/// unperturbed run, then the initial-data members ([`CaseSensitivity::wall_seconds`]).
#[derive(Serialize, Deserialize)]
pub struct TimedEnsemble {
    /// What the ensemble measured.
    ensemble: LevelEnsemble,
    /// The unperturbed run's wall seconds, then each initial-data member's.
    seconds: Vec<f64>,
}

impl TimedEnsemble {
    /// `self` with `more`, members run beside the same unperturbed run, appended; a stop of
    /// `more` is the level's.
    fn absorb(&mut self, more: TimedEnsemble) {
        let level = &mut self.ensemble;
        level.errors.extend(more.ensemble.errors);
        level.separations.extend(more.ensemble.separations);
        self.seconds.extend(more.seconds);
        if more.ensemble.stopped.is_some() {
            level.stopped = more.ensemble.stopped;
        }
    }
}

impl InRange for TimedEnsemble {
    fn out_of_range(&self) -> Option<String> {
        self.ensemble.out_of_range().or_else(|| {
            self.seconds
                .iter()
                .find_map(|&s| not_negative("wall seconds", s))
        })
    }
}

/// What one case's job measured: its level ensembles, in level order (fewer than the study's
/// levels when one stopped).
#[derive(Serialize, Deserialize)]
pub struct CaseEnsemble {
    /// The level ensembles.
    levels: Vec<TimedEnsemble>,
}

impl InRange for CaseEnsemble {
    fn out_of_range(&self) -> Option<String> {
        self.levels.iter().find_map(InRange::out_of_range)
    }
}

/// The jobs of a [`SensitivityJobs`]: one per case.
struct CaseJobs<'s, 'a> {
    jobs: &'s SensitivityJobs<'a>,
}

impl JobList for CaseJobs<'_, '_> {
    type Output = CaseEnsemble;

    fn count(&self) -> usize {
        self.jobs.cases.len()
    }

    /// The case's work: `Σ NX²` over the levels (steps and dofs both grow with `NX`).
    fn size(&self, _index: usize) -> usize {
        self.jobs.config.levels.iter().map(|nx| nx * nx).sum()
    }

    fn run(&self, index: usize) -> Result<CaseEnsemble, study::Error> {
        let j = self.jobs;
        let levels = case_ensemble(j.problem, j.cases[index], j.config, j.norms, j.ensemble)?;
        Ok(CaseEnsemble { levels })
    }
}

/// Runs every case at every level as an ensemble of both sets of members
/// ([`EnsembleConfig::members_of_study`], [`run_members`], in parallel over case × level) and
/// classifies each case. A problem that declares its own perturbation keeps it: the
/// members' round-off perturbations come on top.
pub fn run_sensitivity(
    problem: &Problem1d,
    cases: &[Case],
    norms: &BTreeSet<Norm>,
    config: &StudyConfig,
    ensemble: EnsembleConfig,
) -> Result<Sensitivity, study::Error> {
    let study = SensitivityJobs::new(problem, cases, norms, config, ensemble)?;
    let ran = run_local(&study.list())?;
    study.reduce(ran, cases)
}

/// [`run_sensitivity`] with its case × level ensembles handed to `executor`: the study, or a
/// shard's share of its ensembles.
pub fn run_sensitivity_on(
    executor: &Executor,
    problem: &Problem1d,
    cases: &[Case],
    norms: &BTreeSet<Norm>,
    config: &StudyConfig,
    ensemble: EnsembleConfig,
) -> Result<Executed<Sensitivity>, study::Error> {
    let study = SensitivityJobs::new(problem, cases, norms, config, ensemble)?;
    let executed = executor.execute(&study.list())?;
    executed.reduce(|levels| study.reduce(levels, cases))
}

/// A sensitivity study as its jobs (one ensemble per case × level, [`SensitivityJobs::list`])
/// and its reduce step ([`SensitivityJobs::reduce`]), for a command that hands several lists
/// to one executor ([`crate::harness::study::executor::Batch`]).
pub struct SensitivityJobs<'a> {
    problem: &'a Problem1d,
    cases: &'a [Case],
    norms: &'a BTreeSet<Norm>,
    config: &'a StudyConfig,
    ensemble: EnsembleConfig,
}

impl<'a> SensitivityJobs<'a> {
    /// The ensembles of `cases` of `problem` at the levels of `config`, evaluating `norms`;
    /// the configuration and the ensemble checked, and the problem refused without an obstacle
    /// (the separation is measured at the contact node).
    pub fn new(
        problem: &'a Problem1d,
        cases: &'a [Case],
        norms: &'a BTreeSet<Norm>,
        config: &'a StudyConfig,
        ensemble: EnsembleConfig,
    ) -> Result<Self, Error> {
        config.validate()?;
        ensemble.validate()?;
        if problem.obstacle_gap.is_none() {
            return Err(ParameterError::new(
                "obstacle",
                "none",
                "an obstacle (the separation is measured at the contact node)",
            )
            .into());
        }
        Ok(Self {
            problem,
            cases,
            norms,
            config,
            ensemble,
        })
    }

    /// The jobs: case `c` is job `c`, every level of it screened together
    /// ([`case_ensemble`]: whether the rest of its members run depends on all its levels).
    pub fn list(&self) -> impl JobList<Output = CaseEnsemble> + '_ {
        CaseJobs { jobs: self }
    }

    /// The cases `kept` classified from every level ensemble of the list (`ran`, in the list's
    /// order), as a study of those cases alone would be: `kept` are some of the list's cases in
    /// its order (all of them, or those an earlier study ran). A kept case whose ensemble
    /// stopped is the error of the run that stopped it. Its wall time is the list's.
    pub fn reduce(
        &self,
        ran: ListResults<CaseEnsemble>,
        kept: &[Case],
    ) -> Result<Sensitivity, study::Error> {
        let h: Vec<f64> = self
            .config
            .levels
            .iter()
            .map(|&nx| self.problem.length / nx as f64)
            .collect();
        let (cases, per_case): (Vec<Case>, Vec<Vec<TimedEnsemble>>) = self
            .cases
            .iter()
            .copied()
            .zip(ran.results)
            .filter(|(case, _)| kept.contains(case))
            .map(|(case, ensemble)| (case, ensemble.levels))
            .unzip();
        for level in per_case.iter().flatten() {
            if let Some(status) = &level.ensemble.stopped {
                status.completed()?;
            }
        }
        let (per_case, seconds): (Vec<Vec<LevelEnsemble>>, Vec<Vec<Vec<f64>>>) = per_case
            .into_iter()
            .map(|levels| levels.into_iter().map(|l| (l.ensemble, l.seconds)).unzip())
            .unzip();
        let mut sensitivity = classify_cases(
            &cases,
            self.config,
            &h,
            self.norms,
            self.ensemble,
            per_case,
            ran.wall_seconds,
        );
        for (case, seconds) in sensitivity.cases.iter_mut().zip(seconds) {
            case.wall_seconds = seconds;
        }
        Ok(sensitivity)
    }
}

/// The sensitivity study from the level ensembles of every case (`per_case[c][l]`: case `c` at
/// level `l`, element sizes `h`), each case classified by the module's rules; `wall_seconds` is
/// what the study reports as its time.
pub(crate) fn classify_cases(
    cases: &[Case],
    config: &StudyConfig,
    h: &[f64],
    norms: &BTreeSet<Norm>,
    ensemble: EnsembleConfig,
    per_case: Vec<Vec<LevelEnsemble>>,
    wall_seconds: f64,
) -> Sensitivity {
    let cases = cases
        .iter()
        .zip(per_case)
        .map(|(case, levels)| classify(*case, config, h, norms, ensemble, &levels))
        .collect();
    Sensitivity {
        ensemble,
        config: config.clone(),
        cases,
        wall_seconds,
    }
}

fn classify(
    case: Case,
    config: &StudyConfig,
    h: &[f64],
    norms: &BTreeSet<Norm>,
    ensemble: EnsembleConfig,
    levels: &[LevelEnsemble],
) -> CaseSensitivity {
    let mut rates = BTreeMap::new();
    let mut rate_fit_intervals = BTreeMap::new();
    let mut errors = BTreeMap::new();
    let members = levels.first().map_or(0, |l| l.errors.len());
    for &norm in norms {
        let per_member: Vec<Vec<f64>> = (0..members)
            .map(|m| levels.iter().map(|l| l.errors[m][&norm]).collect())
            .collect();
        let member_fits: Vec<RateFit> = per_member.iter().filter_map(|e| fit_rate(h, e)).collect();
        let member_rates: Vec<f64> = member_fits.iter().map(|f| f.rate).collect();
        if !member_rates.is_empty() {
            rates.insert(norm.key().to_string(), Spread::of(&member_rates));
        }
        let intervals = member_fits
            .iter()
            .filter_map(|f| Some((f.ci_low?, f.ci_high?)));
        if let Some(hull) = intervals.reduce(|(l, h), (a, b)| (l.min(a), h.max(b))) {
            rate_fit_intervals.insert(norm.key().to_string(), hull);
        }
        let spreads = (0..levels.len())
            .map(|l| Spread::of(&per_member.iter().map(|e| e[l]).collect::<Vec<_>>()))
            .collect();
        errors.insert(norm.key().to_string(), spreads);
    }
    let predictability_steps: Vec<Option<usize>> = levels
        .iter()
        .map(|l| l.separations.iter().filter_map(|s| s.parting_step).min())
        .collect();
    let separation_growth: Vec<Option<f64>> = levels
        .iter()
        .map(|l| median_growth(&l.separations))
        .collect();
    let largest_separation: Vec<f64> = levels
        .iter()
        .map(|l| largest_separation(&l.separations))
        .collect();
    let runs_away = levels.iter().any(|l| runs_away(&l.separations));
    let rate_range_large = rates.values().any(|s| s.range() > CHAOTIC_RATE_RANGE);
    let class = if predictability_steps.iter().all(Option::is_none) {
        SensitivityClass::Reproducible
    } else if runs_away && rate_range_large {
        SensitivityClass::Chaotic
    } else {
        SensitivityClass::EventSensitive
    };
    CaseSensitivity {
        case: case.id(),
        class,
        chaotic: class == SensitivityClass::Chaotic,
        members: members / 2,
        amplitude: ensemble.amplitude,
        step_members: members - members / 2,
        step_epsilon: STEP_EPSILON,
        levels: config.levels.clone(),
        rates,
        rate_fit_intervals,
        errors,
        predictability_steps,
        separation_growth,
        largest_separation,
        wall_seconds: Vec::new(),
    }
}

/// `reports/sensitivity.md`: one row per case with its class, and at `nx_shown` the
/// predictability horizon and growth rate; then the rate ranges of every case. The members'
/// initial noise is on `noise`; the page says it was made by `made_by` (a make target or a
/// command).
pub fn render(s: &Sensitivity, nx_shown: usize, noise: InitialNoise, made_by: &str) -> String {
    let mut md = format!(
        "# Round-off sensitivity\n\nEvery case at every level NX = {:?} (Δx/Δt = {}, T = {}) run \
         as {}, beside the unperturbed run. {} Generated by `{made_by}` in {:.1} s wall.\n\n",
        s.config.levels,
        s.config.ratio,
        s.config.horizon,
        s.ensemble.describe_on(noise),
        class_rules(),
        s.wall_seconds
    );
    md.push_str(&class_table(s, nx_shown));
    md.push_str(
        "\n## Rate ranges\n\nEnsemble minimum, median and maximum of the rate fitted over all \
         levels.\n\n",
    );
    md.push_str(&rate_ranges(&s.cases));
    md
}

/// The classification rules in one sentence, with their thresholds.
pub(crate) fn class_rules() -> String {
    format!(
        "Classes (rules fixed before the results, see docs/src/roundoff-sensitivity.md): \
         *reproducible*: no member's contact-node displacement parts from the unperturbed run \
         by more than {PARTING:e}; *chaotic*: the separation grows exponentially to \
         {RUNAWAY:e} and some rate's ensemble range exceeds {CHAOTIC_RATE_RANGE}; \
         *event-sensitive*: members part, but not so. A class these cannot decide (the \
         separation reaches {RUNAWAY:e} in a jump, with no growth fitted; no rate fitted) is \
         shown *undecided*, with what it lacks (docs/src/roundoff-sensitivity.md)."
    )
}

/// A class as a table shows it: its name, and when the ensemble cannot decide it
/// ([`CaseSensitivity::class_decision`], [`RunSensitivity::class_decision`]), `undecided` with
/// the reason.
pub(crate) fn class_text(class: SensitivityClass, decision: &Decision) -> String {
    match decision.verdict {
        Verdict::Undecided => format!("{} (**undecided**: {})", class.name(), decision.reason),
        Verdict::Holds | Verdict::Fails => class.name().to_string(),
    }
}

/// One row per case: its class, and at `nx_shown` the predictability step and the separation
/// growth; then the largest ensemble range of a rate and the largest relative error spread.
pub(crate) fn class_table(s: &Sensitivity, nx_shown: usize) -> String {
    let shown = s.config.levels.iter().position(|&nx| nx == nx_shown);
    let mut md = format!(
        "| case | class | parting step at NX = {nx_shown} | separation growth at NX = {nx_shown} (1/time) | largest rate range (norm) | largest relative error spread |\n|---|---|---|---|---|---|\n"
    );
    for c in &s.cases {
        let step = shown
            .and_then(|k| c.predictability_steps[k])
            .map_or("never".to_string(), |n| n.to_string());
        let growth = shown
            .and_then(|k| c.separation_growth[k])
            .map_or("—".to_string(), |g| format!("{g:.1}"));
        let (norm, range) = c
            .rates
            .iter()
            .map(|(n, r)| (n.as_str(), r.range()))
            .fold(("—", 0.0), |a, b| if b.1 > a.1 { b } else { a });
        let spread = c
            .errors
            .keys()
            .filter_map(|n| c.relative_error_spread(n))
            .fold(0.0, f64::max);
        md.push_str(&format!(
            "| {} | {} | {step} | {growth} | {range:.2e} ({norm}) | {spread:.2e} |\n",
            c.case,
            class_text(c.class, &c.class_decision())
        ));
    }
    md
}

/// The ensemble minimum, median and maximum of every norm's rate of `cases`, one row each.
pub(crate) fn rate_ranges<'c>(cases: impl IntoIterator<Item = &'c CaseSensitivity>) -> String {
    let mut md = String::from("| case | norm | min | median | max |\n|---|---|---|---|---|\n");
    for c in cases {
        for (norm, r) in &c.rates {
            md.push_str(&format!(
                "| {} | {norm} | {:.4} | {:.4} | {:.4} |\n",
                c.case, r.min, r.median, r.max
            ));
        }
    }
    md
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A case's rate interval joins the members' `[min, max]` with the hull of their own 95 %
    /// fit intervals (issue 53, item 4).
    #[test]
    fn the_rate_interval_joins_the_members_range_with_their_fit_intervals() {
        let h = [0.1, 0.05, 0.025];
        let members = [[1.0, 0.55, 0.24], [1.0, 0.45, 0.26]];
        let norm = Norm::EnergyL2;
        let level = |l: usize| LevelEnsemble {
            errors: members
                .iter()
                .map(|e| BTreeMap::from([(norm, e[l])]))
                .collect(),
            separations: Vec::new(),
            stopped: None,
        };
        let config = StudyConfig::paper_default();
        let case = Case::tables_matrix()[0];
        let s = classify_cases(
            &[case],
            &config,
            &h,
            &BTreeSet::from([norm]),
            EnsembleConfig::default(),
            vec![(0..3).map(level).collect()],
            0.0,
        );
        let c = &s.cases[0];
        let fits: Vec<RateFit> = members.iter().map(|e| fit_rate(&h, e).unwrap()).collect();
        let low = fits
            .iter()
            .map(|f| f.ci_low.unwrap())
            .fold(f64::INFINITY, f64::min);
        let high = fits
            .iter()
            .map(|f| f.ci_high.unwrap())
            .fold(f64::NEG_INFINITY, f64::max);
        assert_eq!(c.rate_fit_intervals[norm.key()], (low, high));
        let spread = c.rates[norm.key()];
        assert!(
            low < spread.min && spread.max < high,
            "{spread:?} in [{low}, {high}]"
        );
        assert_eq!(c.rate_interval(norm.key()), Some((low, high)));
        let mut without = c.clone();
        without.rate_fit_intervals.clear();
        assert_eq!(
            without.rate_interval(norm.key()),
            Some((spread.min, spread.max)),
            "a file written before the intervals were recorded falls back to [min, max]"
        );
    }
}
