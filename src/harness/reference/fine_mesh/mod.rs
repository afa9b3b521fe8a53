//! The fine-mesh reference of a box scene (the note §3 has no exact solution: "(U, λ) can be
//! approximated by (U_h^n, λ^n) by taking Δt and Δx very small"), and the measure of a box run
//! against it.
//!
//! Every case (scheme × mass) runs on nested meshes `n = levels[k]` elements along the axis
//! (square or cubic elements, `Δx/Δt` fixed), and each run is compared at each of its steps with
//! one reference run on `reference_level` elements ([`fine_run`] for the run, [`cache`] for its
//! cache, [`comparison`] for the norms). The meshes and time grids are nested, so the coarse
//! solution is compared with the fine one exactly, at common times: through the reference's
//! projections on each level ([`crate::harness::run::nested_comparison::projection`]), recorded
//! while the reference runs, so that no trajectory of the reference is stored.
//!
//! The reference is Crank–Nicolson with the redistributed mass (the combination the note finds
//! convergent and energy-conserving). Whether it is fine enough is measured, not assumed: the
//! same case one level coarser than the reference runs beside it and is compared with it
//! ([`crate::harness::run::nested_comparison::check`]), and that distance is reported next to the
//! smallest error that enters a fit ([`ReferenceCheck`]), with the largest change of each fitted
//! rate that a reference error of that size could cause (the rate-bias bound).
//!
//! What a study of a box against its fine mesh gives back ([`FineMeshStudy`]) is a [`Study`] like
//! a bar's against its exact solution, the reference check, the round-off sensitivity of every
//! case when the config asks for an ensemble ([`ensemble`]), and the histories behind the note's
//! Figures 1, 2, 4–7 ([`ElasticHistories`]).

pub mod cache;
pub mod comparison;
pub mod ensemble;
pub mod fine_run;

use std::collections::{BTreeMap, BTreeSet};
use std::time::Instant;

use serde::{Deserialize, Serialize};

use crate::harness::files::error::{self as files, ParameterError};
use crate::harness::problem::{MassVariant, Scheme, Settings};
use crate::harness::run::distributed::Ranks;
use crate::harness::run::elastic::{box_mesh, BoxContactHistory, BoxProblem};
use crate::harness::run::nested_comparison::norm_matrices::NormMatrices;
use crate::harness::run::norms::Norm;
use crate::harness::run::{run, BoxRun, Integration, Observables, Observer, RunConfig};
use crate::harness::study::budget::{self, Estimate};
use crate::harness::study::error::Error;
use crate::harness::study::executor::{run_local, Executed, Executor};
use crate::harness::study::rates::fit_rate;
use crate::harness::study::scene::Scene;
use crate::harness::study::sensitivity::{EnsembleConfig, LevelEnsemble, Sensitivity};
use crate::harness::study::shard::InRange;
use crate::harness::study::{
    run_study_on, Case, CaseStudy, Fitted, LevelMeasure, LevelOutcome, LevelRecord, Measured,
    Study, StudyConfig, StudyJobs,
};
use cache::{ReferenceCache, ReferenceKey};
use comparison::ReferenceComparison;
use fine_run::FineReference;

/// Number of time samples of the von Mises space–time map (Figures 4–5).
const STRESS_MAP_SAMPLES: usize = 200;

/// Levels, reference and cases of a 2D/3D study.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ElasticStudyConfig {
    /// Elements along the axis of each fitted level, increasing, each a divisor of the next.
    pub levels: Vec<usize>,
    /// Elements along the axis of the reference (a multiple of `2 · levels.last()`).
    pub reference_level: usize,
    /// `Δx / Δt` (2 in the note).
    pub ratio: f64,
    /// The cases.
    pub cases: Vec<Case>,
    /// The round-off ensemble every case × level also runs as ([`mod@sensitivity`]; a box scene's
    /// `discretisation.sensitivity`); `None`: no ensemble.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sensitivity: Option<EnsembleConfig>,
    /// How every run of the study, the reference's included, is solved (not written: the
    /// reference's key holds the conventions that are not the harness's).
    #[serde(skip)]
    pub settings: Settings,
}

impl ElasticStudyConfig {
    /// The estimated work and memory of this study's fine-mesh reference alone (no level runs,
    /// no ensemble): what `signorini reference` checks, and `verify` before it computes one.
    pub fn reference_estimate(&self, problem: &BoxProblem) -> Estimate {
        budget::box_study(
            problem,
            &self.settings,
            &self.levels,
            self.reference_level,
            self.ratio,
            &[],
            0,
        )
    }

    /// The 2D/3D study of a box scene: its levels, ratio and reference level (`reference_level`
    /// when given, the scene's `discretisation.reference_level` otherwise), its schemes with
    /// both masses of the note. Errors when neither gives a reference level.
    pub fn from_scene(
        scene: &Scene,
        reference_level: Option<usize>,
    ) -> Result<Self, ParameterError> {
        let given = reference_level.or(scene.discretisation.reference_level);
        let reference_level = given.ok_or_else(|| {
            ParameterError::new(
                "discretisation.reference_level",
                "absent",
                "the number of elements along the axis of the fine-mesh reference (a box study \
                 has no exact solution)",
            )
        })?;
        let cases = Case::matrix(&scene.default_schemes(), &MassVariant::PAPER);
        Ok(Self {
            levels: scene.discretisation.levels.clone(),
            reference_level,
            ratio: scene.discretisation.ratio,
            cases,
            sensitivity: scene.discretisation.sensitivity,
            settings: scene.settings(),
        })
    }

    /// The case of the reference run.
    pub fn reference_case() -> Case {
        Case {
            scheme: Scheme::CRANK_NICOLSON,
            mass: MassVariant::Redistributed,
        }
    }

    /// Checks the nesting and the ensemble and returns the finest level: errors name `levels`,
    /// `reference_level`, `ratio`, `members` or `amplitude` and say what is allowed.
    pub fn validate(&self) -> Result<usize, ParameterError> {
        let nested = !self.levels.is_empty()
            && self.levels[0] > 0
            && self
                .levels
                .windows(2)
                .all(|w| w[1] > w[0] && w[1] % w[0] == 0);
        let Some(&finest) = self.levels.last().filter(|_| nested) else {
            return Err(ParameterError::new(
                "levels",
                format!("{:?}", self.levels),
                "increasing element counts > 0, each dividing the next (nested meshes)",
            ));
        };
        if self.reference_level < 2 * finest || self.reference_level % (2 * finest) != 0 {
            return Err(ParameterError::new(
                "reference_level",
                self.reference_level,
                "a multiple of 2 × the finest level, so that the reference and the run one \
                 level coarser are both nested with every level",
            ));
        }
        crate::harness::files::error::require_positive("ratio", self.ratio)?;
        if let Some(ensemble) = &self.sensitivity {
            ensemble.validate()?;
        }
        Ok(finest)
    }
}

/// Is the reference fine enough? The distance of the reference case one level coarser
/// (`reference_level / 2`) to the reference, next to the smallest error of any fitted level.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ReferenceCheck {
    /// `scheme/mass` of the reference.
    pub case: String,
    /// Elements along the axis.
    pub level: usize,
    /// Elements per direction.
    pub elements: Vec<usize>,
    /// Unknowns.
    pub dofs: usize,
    /// Steps.
    pub steps: usize,
    /// `Δt`.
    pub dt: f64,
    /// Wall-clock time of the reference run (when it was computed), seconds.
    pub seconds: f64,
    /// Whether it came from the cache.
    pub from_cache: bool,
    /// The level of the check run.
    pub next_coarser: usize,
    /// Norm key → distance of the check run to the reference.
    pub distance: BTreeMap<String, f64>,
    /// Norm key → smallest error of any case at any fitted level.
    pub smallest_fitted_error: BTreeMap<String, f64>,
    /// Norm key → the largest change of any case's fitted rate when each of its errors moves
    /// by the distance (up on the coarse half of the levels, down on the fine half, and the
    /// reverse): what a reference error of that size could do to the rates. `null` (`None`)
    /// when no bound can be formed: an error not larger than the distance could vanish.
    pub rate_bias: BTreeMap<String, Option<f64>>,
}

impl ReferenceCheck {
    /// Whether some norm has no rate-bias bound.
    pub fn some_bias_unbounded(&self) -> bool {
        self.rate_bias.values().any(Option::is_none)
    }

    /// The rate-bias bound of `case`'s rate in `norm` alone ([`rate_bias_bound`] with this
    /// check's distance): what the findings widen that rate's interval by. The stored
    /// [`ReferenceCheck::rate_bias`] of a norm is the largest of these over the study's cases.
    pub fn case_bias(&self, case: &CaseStudy, norm: Norm) -> Option<f64> {
        rate_bias_bound(case, norm, *self.distance.get(norm.key())?)
    }

    /// `smallest fitted error / distance` of a norm: how many times the reference's own
    /// error (bounded by the distance, for a converging reference) fits under the errors.
    pub fn margin(&self, norm: &str) -> Option<f64> {
        Some(self.smallest_fitted_error.get(norm)? / self.distance.get(norm)?)
    }
}

/// The von Mises stress along the bar's axis over time (Figures 4–5): at each sampled step,
/// the mean over each layer of elements across the section.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct AxialStressMap {
    /// Sample times.
    pub time: Vec<f64>,
    /// Height of each layer's centre above the contact face.
    pub position: Vec<f64>,
    /// `von_mises[k][j]`: layer `j` at `time[k]`.
    pub von_mises: Vec<Vec<f64>>,
}

/// The histories of one case at the finest level.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CaseHistories {
    /// `scheme/mass`.
    pub case: String,
    /// Elements along the axis.
    pub level: usize,
    /// The element size `h`.
    pub element_size: f64,
    /// The contact face's histories (Figures 1, 6).
    pub contact: BoxContactHistory,
    /// `(t, E_h)` (Figures 2, 7).
    pub energy: Vec<(f64, f64)>,
    /// Figures 4–5.
    pub stress: AxialStressMap,
}

/// The reference's histories, for the figures.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ReferenceCurves {
    /// Elements along the axis.
    pub level: usize,
    /// The element size `h`.
    pub element_size: f64,
    /// Sample times.
    pub time: Vec<f64>,
    /// Axial displacement of the centre contact node.
    pub centre_displacement: Vec<f64>,
    /// Its multiplier.
    pub centre_multiplier: Vec<f64>,
    /// `Σ λ_i`.
    pub total_force: Vec<f64>,
    /// `E_h`.
    pub energy: Vec<f64>,
}
/// The figure data of a study.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ElasticHistories {
    /// `d`.
    pub dimension: usize,
    /// Distance from the contact face to the obstacle (the contact histories store gaps).
    pub obstacle_gap: Option<f64>,
    /// The reference.
    pub reference: ReferenceCurves,
    /// One entry per case, at the finest level.
    pub cases: Vec<CaseHistories>,
}

/// What one (case, level) job of a box study keeps besides its outcome: when the study has
/// one, its round-off ensemble with the members' run time in seconds; at the finest level, the
/// case's histories. A run that stopped keeps nothing.
#[derive(Serialize, Deserialize)]
struct BoxKept {
    histories: Option<CaseHistories>,
    ensemble: Option<LevelEnsemble>,
    ensemble_seconds: f64,
}

impl InRange for BoxKept {
    fn out_of_range(&self) -> Option<String> {
        self.ensemble.as_ref().and_then(InRange::out_of_range)
    }
}

/// The reference of a study with what comparing a run with it takes: the norm matrices of every
/// fitted level.
pub struct Comparator {
    /// The reference.
    pub reference: FineReference,
    norms: BTreeMap<usize, NormMatrices>,
    /// The finest fitted level.
    pub finest: usize,
}

impl Comparator {
    /// The comparator of `reference` for runs on each of its projected levels, the finest
    /// being `finest`.
    pub fn new(
        problem: &BoxProblem,
        reference: FineReference,
        finest: usize,
    ) -> Result<Self, Error> {
        let norms = reference
            .projections
            .iter()
            .map(|p| {
                let mesh = box_mesh(problem, p.level)?;
                let matrices = NormMatrices::of(&mesh, &problem.elasticity);
                Ok((p.level, matrices))
            })
            .collect::<Result<_, Error>>()?;
        Ok(Self {
            reference,
            norms,
            finest,
        })
    }

    /// A fresh comparison for a run on `level` elements along the axis (a fitted level).
    pub fn comparison(&self, level: usize) -> ReferenceComparison<'_> {
        ReferenceComparison::new(
            &self.reference.histories,
            self.reference
                .projections_on(level)
                .expect("the reference is projected on every fitted level"),
            &self.norms[&level],
            self.finest / level,
        )
    }
}

/// The element size along the axis of a run on `n_axis` elements, as [`box_mesh`] makes it.
pub(crate) fn axial_element_size(problem: &BoxProblem, n_axis: usize) -> f64 {
    problem.lengths[problem.lengths.len() - 1] / n_axis as f64
}

/// A box study against its fine-mesh reference: what [`run_fine_mesh_study`] measured, before
/// any report judges it.
#[derive(Debug, Clone)]
pub struct FineMeshStudy {
    /// `d`.
    pub dimension: usize,
    /// The levels, reference and cases.
    pub config: ElasticStudyConfig,
    /// Errors, rates and per-level records of every case (norm keys as the 1D tables; see
    /// [`comparison`] for what each measures here).
    pub study: Study,
    /// Whether the reference is fine enough.
    pub reference: ReferenceCheck,
    /// The round-off sensitivity of every case, when `config.sensitivity` asks for an ensemble.
    pub sensitivity: Option<Sensitivity>,
}

/// Runs the study: one job per case × level, which also runs that level's round-off ensemble
/// when `config.sensitivity` asks for one ([`ensemble::run_members`]). The reference is read
/// from `cache` when its key matches, computed otherwise (and saved when `cache` may be
/// written); `note` hears why a cache was not used.
pub fn run_fine_mesh_study(
    problem: &BoxProblem,
    config: &ElasticStudyConfig,
    cache: &ReferenceCache,
    note: &mut dyn FnMut(String),
) -> Result<(FineMeshStudy, ElasticHistories), Error> {
    let prepared = PreparedBoxStudy::new(problem, config, cache, note)?;
    let jobs = prepared.jobs();
    let ran = run_local(&jobs.list())?;
    prepared.finish(jobs.reduce_keeping(ran, &config.cases))
}

/// [`run_fine_mesh_study`] with its case × level jobs handed to `executor`: the one study
/// ([`run_study_on`]) of the box against its fine-mesh reference ([`AgainstFineMesh`]), or a
/// shard's share of its jobs. The reference is obtained first, here, whatever the executor.
pub fn run_fine_mesh_study_on(
    executor: &Executor,
    problem: &BoxProblem,
    config: &ElasticStudyConfig,
    cache: &ReferenceCache,
    note: &mut dyn FnMut(String),
) -> Result<Executed<(FineMeshStudy, ElasticHistories)>, Error> {
    let prepared = PreparedBoxStudy::new(problem, config, cache, note)?;
    run_study_on(executor, &prepared.jobs())?.reduce(|fitted| prepared.finish(fitted))
}

/// A box study ready to run: its reference obtained, the measure of its jobs, the study's
/// levels and norms, and the time taken to prepare it.
struct PreparedBoxStudy<'a> {
    measure: AgainstFineMesh<'a>,
    study_config: StudyConfig,
    norms: BTreeSet<Norm>,
    /// The time spent before the jobs (the reference obtained), seconds.
    prepared_seconds: f64,
}

impl<'a> PreparedBoxStudy<'a> {
    /// The study of `config` on `problem`, its reference obtained from `cache` or computed
    /// ([`obtain_reference`]); an ensemble the problem cannot carry is refused before anything
    /// runs.
    fn new(
        problem: &'a BoxProblem,
        config: &'a ElasticStudyConfig,
        cache: &ReferenceCache,
        note: &mut dyn FnMut(String),
    ) -> Result<Self, Error> {
        let clock = Instant::now();
        let finest = config.validate()?;
        let ensemble = config
            .sensitivity
            .map(|ensemble| {
                ensemble::noise_scale(problem).map(|scale| ensemble::Noise { ensemble, scale })
            })
            .transpose()?;
        let reference = obtain_reference(problem, config, (cache, None), note, &|| Ok(()))?;
        let measure = AgainstFineMesh {
            problem,
            config,
            finest,
            ensemble,
            comparator: Comparator::new(problem, reference, finest)?,
        };
        Ok(Self {
            measure,
            study_config: StudyConfig {
                levels: config.levels.clone(),
                ratio: config.ratio,
                horizon: problem.horizon,
                settings: config.settings,
            },
            norms: Norm::ALL.into_iter().collect(),
            prepared_seconds: clock.elapsed().as_secs_f64(),
        })
    }

    /// Its case × level jobs: the box study's norms, every one.
    fn jobs(&self) -> StudyJobs<'_, &AgainstFineMesh<'a>> {
        StudyJobs::measured_by(
            &self.measure,
            &self.measure.config.cases,
            &self.norms,
            &self.study_config,
        )
    }

    /// The box study of the fitted study and what its cases kept; its wall time counts the
    /// preparation.
    fn finish(
        &self,
        (mut study, kept): Fitted<BoxKept>,
    ) -> Result<(FineMeshStudy, ElasticHistories), Error> {
        study.wall_seconds += self.prepared_seconds;
        self.measure.reduce(study, kept)
    }
}

/// A box's runs against the fine-mesh reference: each compared with the reference's projection
/// on its level at every step, with its round-off ensemble when the study has one; the finest
/// level keeps the case's histories.
struct AgainstFineMesh<'a> {
    problem: &'a BoxProblem,
    config: &'a ElasticStudyConfig,
    finest: usize,
    ensemble: Option<ensemble::Noise>,
    comparator: Comparator,
}

impl LevelMeasure for AgainstFineMesh<'_> {
    type Kept = BoxKept;

    /// `case` on `n` elements along the axis, with its ensemble when the study has one.
    fn measure(&self, case: Case, n: usize) -> Result<Measured<BoxKept>, files::Error> {
        let (problem, config, comparator) = (self.problem, self.config, &self.comparator);
        let (mut measured, base) = run_level(
            problem,
            config,
            case,
            n,
            n == self.finest,
            comparator.comparison(n),
        )?;
        if let Some(noise) = self
            .ensemble
            .filter(|_| measured.outcome.status.is_completed())
        {
            let members = Instant::now();
            measured.kept.ensemble = Some(ensemble::run_members(
                problem, config, case, n, comparator, &base, noise,
            )?);
            measured.kept.ensemble_seconds = members.elapsed().as_secs_f64();
        }
        Ok(measured)
    }
}

impl AgainstFineMesh<'_> {
    /// The box study of `study`, fitted from every job's outcome, with what each case it
    /// fitted kept of its levels (`kept`, in the order of the cases): the reference check, the
    /// note's findings, the round-off classes and the figure data.
    fn reduce(
        &self,
        study: Study,
        kept: Vec<(Case, Vec<BoxKept>)>,
    ) -> Result<(FineMeshStudy, ElasticHistories), Error> {
        let (problem, config, comparator) = (self.problem, self.config, &self.comparator);
        let ensemble = self.ensemble;
        let mut histories = Vec::new();
        let mut ensembles: Vec<Vec<LevelEnsemble>> = Vec::new();
        let mut ensemble_seconds = 0.0;
        let mut run_cases = Vec::new();
        for (case, levels) in kept {
            run_cases.push(case);
            let mut case_ensembles = Vec::new();
            for level in levels {
                histories.extend(level.histories);
                case_ensembles.extend(level.ensemble);
                ensemble_seconds += level.ensemble_seconds;
            }
            ensembles.push(case_ensembles);
        }
        let reference = &comparator.reference;
        let check = &reference.histories.check;
        let mut reference_check = ReferenceCheck {
            case: ElasticStudyConfig::reference_case().id(),
            level: config.reference_level,
            elements: reference.mesh.counts().to_vec(),
            dofs: reference.histories.dofs,
            steps: reference.histories.steps,
            dt: reference.histories.dt,
            seconds: reference.histories.seconds,
            from_cache: reference.from_cache,
            next_coarser: check.level,
            distance: check.distance.clone(),
            smallest_fitted_error: Norm::ALL
                .iter()
                .map(|n| {
                    let smallest = study
                        .cases
                        .iter()
                        .filter_map(|c| c.norm(*n))
                        .flat_map(|r| r.errors.iter().copied())
                        .fold(f64::INFINITY, f64::min);
                    (n.key().to_string(), smallest)
                })
                .collect(),
            rate_bias: BTreeMap::new(),
        };
        reference_check.rate_bias = Norm::ALL
            .iter()
            .map(|&n| {
                let delta = reference_check.distance[n.key()];
                let worst = study
                    .cases
                    .iter()
                    .map(|c| rate_bias(c, n, delta))
                    .fold(0.0, f64::max);
                (n.key().to_string(), worst.is_finite().then_some(worst))
            })
            .collect();
        let h = &reference.histories;
        let curves = ReferenceCurves {
            level: config.reference_level,
            element_size: reference.mesh.element_sizes()[reference.mesh.dim() - 1],
            time: h.time.clone(),
            centre_displacement: h.centre_displacement.clone(),
            centre_multiplier: h.centre_multiplier.clone(),
            total_force: h.total_force.clone(),
            energy: h.energy.clone(),
        };
        let run_config = ElasticStudyConfig {
            cases: run_cases,
            ..config.clone()
        };
        let sensitivity = ensemble.map(|noise| {
            ensemble::classify(
                problem,
                &run_config,
                noise.ensemble,
                ensembles,
                ensemble_seconds,
            )
        });
        Ok((
            FineMeshStudy {
                dimension: problem.lengths.len(),
                config: config.clone(),
                study,
                reference: reference_check,
                sensitivity,
            },
            ElasticHistories {
                dimension: problem.lengths.len(),
                obstacle_gap: problem.obstacle_gap,
                reference: curves,
                cases: histories,
            },
        ))
    }
}

/// [`rate_bias`] when it is finite: `None` when an error no larger than `delta` could vanish.
pub fn rate_bias_bound(case: &CaseStudy, norm: Norm, delta: f64) -> Option<f64> {
    let bias = rate_bias(case, norm, delta);
    bias.is_finite().then_some(bias)
}

/// How far the least-squares rate of `norm` in `case` can move when each error is off by at most
/// `delta`: the largest slope change is reached by moving the coarse half of the levels one way
/// and the fine half the other.
fn rate_bias(case: &CaseStudy, norm: Norm, delta: f64) -> f64 {
    let Some((r, base)) = case.norm(norm).and_then(|r| Some((r, r.fit?))) else {
        return 0.0;
    };
    let h: Vec<f64> = case.levels.iter().map(|l| l.h).collect();
    let half = r.errors.len() / 2;
    [1.0, -1.0]
        .into_iter()
        .map(|sign| {
            let moved: Vec<f64> = r
                .errors
                .iter()
                .enumerate()
                .map(|(k, e)| e + if k < half { sign } else { -sign } * delta)
                .collect();
            if moved.iter().any(|&e| e <= 0.0) {
                return f64::INFINITY;
            }
            fit_rate(&h, &moved).map_or(f64::INFINITY, |f| (f.rate - base.rate).abs())
        })
        .fold(0.0, f64::max)
}

/// The reference of a study: read from `cache` when the key matches, computed otherwise
/// (when `afford` allows it: see [`FineReference::obtain`]); with `ranks`, as rank 0 of a
/// distributed run (the other ranks run [`FineReference::follow`] with [`reference_key`]).
pub fn obtain_reference(
    problem: &BoxProblem,
    config: &ElasticStudyConfig,
    (cache, ranks): (&ReferenceCache, Option<&dyn Ranks>),
    note: &mut dyn FnMut(String),
    afford: &dyn Fn() -> Result<(), Error>,
) -> Result<FineReference, Error> {
    let key = reference_key(problem, config)?;
    FineReference::obtain(problem, &config.settings, (cache, key), note, afford, ranks)
}

/// The key of a study's reference ([`ElasticStudyConfig::reference_case`] on its reference
/// level, projected on its levels, sampled at its finest level's steps); errors name the
/// study's invalid field.
pub fn reference_key(
    problem: &BoxProblem,
    config: &ElasticStudyConfig,
) -> Result<ReferenceKey, ParameterError> {
    let finest = config.validate()?;
    let case = ElasticStudyConfig::reference_case();
    Ok(ReferenceKey::new(
        problem,
        config.settings.conventions,
        config.reference_level,
        config.ratio,
        (case.scheme, case.mass),
        &config.levels,
        config.reference_level / finest,
    ))
}

/// One run of `case` on `n_axis` elements with `Δx/Δt = ratio`, solved with `settings`,
/// compared with the reference at every step; `observers` see every step after the comparison.
fn run_compared(
    problem: &BoxProblem,
    ratio: f64,
    settings: Settings,
    case: Case,
    n_axis: usize,
    comparison: &mut ReferenceComparison<'_>,
    observers: &mut [&mut dyn Observer],
) -> Result<BoxRun, files::Error> {
    let config = RunConfig {
        nx: n_axis,
        ratio,
        scheme: case.scheme,
        mass: case.mass,
        observables: Observables::default(),
        settings,
    };
    let mut all: Vec<&mut dyn Observer> = vec![comparison];
    for o in observers.iter_mut() {
        all.push(&mut **o);
    }
    run(problem, &config, &mut all)
}

/// One case of a study of `config` at one level, compared with the reference at every step:
/// what it measured (no ensemble yet) and its contact history.
fn run_level(
    problem: &BoxProblem,
    config: &ElasticStudyConfig,
    case: Case,
    n_axis: usize,
    keep_histories: bool,
    mut comparison: ReferenceComparison<'_>,
) -> Result<(Measured<BoxKept>, BoxContactHistory), files::Error> {
    // `h` and the step count as the run computes them (`box_mesh`, `time_grid`).
    let h = axial_element_size(problem, n_axis);
    let (steps, _) = crate::harness::run::time_grid(problem.horizon, h, config.ratio);
    let every = (steps / STRESS_MAP_SAMPLES).max(1);
    let mut stress = AxialStressMap {
        position: (0..n_axis).map(|j| (j as f64 + 0.5) * h).collect(),
        ..AxialStressMap::default()
    };
    let mesh = box_mesh(problem, n_axis)?;
    let per_layer = mesh.n_elements() / n_axis;
    let mut step = 0usize;
    let mut sample_stress = |state: &Integration<'_>| -> Result<(), files::Error> {
        if keep_histories && step % every == 0 {
            let vm = mesh.von_mises(state.displacement(), &problem.elasticity);
            stress.time.push(state.time());
            stress.von_mises.push(
                vm.chunks(per_layer)
                    .map(|layer| layer.iter().sum::<f64>() / per_layer as f64)
                    .collect(),
            );
        }
        step += 1;
        Ok(())
    };
    let result = run_compared(
        problem,
        config.ratio,
        config.settings,
        case,
        n_axis,
        &mut comparison,
        &mut [&mut sample_stress],
    )?;
    let completed = result.status.is_completed();
    let measured = Measured {
        outcome: LevelOutcome {
            status: result.status.clone(),
            record: LevelRecord {
                nx: n_axis,
                h,
                dt: result.dt,
                steps: result.steps,
                dofs: result.dofs,
                timings: result.timings,
                multiplier_variation_ratio: comparison.variation_ratio(),
            },
            errors: if completed {
                comparison.errors()
            } else {
                BTreeMap::new()
            },
            physics: result.physics,
        },
        kept: BoxKept {
            histories: (keep_histories && completed).then(|| CaseHistories {
                case: case.id(),
                level: n_axis,
                element_size: h,
                contact: result.observed.contact.clone(),
                energy: result.observed.energy,
                stress,
            }),
            ensemble: None,
            ensemble_seconds: 0.0,
        },
    };
    Ok((measured, result.observed.contact))
}
