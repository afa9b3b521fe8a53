//! The round-off sensitivity of a 2D/3D study: every case × level rerun as an ensemble of `K`
//! members whose initial velocity carries seeded noise and `K` members whose carried state is
//! perturbed after every step by the unit round-off
//! ([`crate::harness::study::sensitivity::Member`]), beside the study's unperturbed run and
//! compared with the same fine-mesh reference (the reference is not perturbed). It measures
//! what the 1D study measures ([`crate::harness::study::sensitivity`]: each member's errors, their
//! ensemble spread and that of each member's fitted rate, the predictability step and the
//! separation growth) and classifies each case by the same rules, into the same [`Sensitivity`], so
//! the golden gate (`Golden::with_sensitivity`, `compare_ensemble`) applies unchanged.
//!
//! - **The noise.** Member `m` (seed `m = 1..K`) adds to every velocity dof a uniform amount in
//!   `±A·max|v⁰|`. A box starts with the uniform axial velocity `v⁰ = initial_velocity · e_d`
//!   (the note's −0.5), so `max|v⁰| = |initial_velocity|`; a problem at rest has no velocity
//!   scale and is refused. The displacement is not touched.
//! - **The contact face is perturbed too.** The Signorini condition constrains displacements,
//!   not velocities, and at `t = 0` the face is the gap away from the obstacle, so every initial
//!   velocity is admissible (the 1D study leaves the contact dof's displacement alone only to
//!   keep `u⁰` admissible). Leaving those dofs out would make the noise less like round-off,
//!   which touches every dof.
//! - **The per-step members** perturb every carried value by a relative amount
//!   ([`crate::harness::problem::StepPerturbation`]): zeros stay zero, so the clamped face and a
//!   contact dof held at the obstacle stay where they are.
//! - **The separation** is taken on the centre contact node's gap (its normal displacement plus
//!   the constant gap) that every box run records (`BoxContactHistory::centre_gap`), with the 1D
//!   thresholds ([`crate::harness::study::sensitivity::PARTING`],
//!   [`crate::harness::study::sensitivity::RUNAWAY`]): the box falls 0.2 at speed 0.5,
//!   displacements of the size of the 1D benchmark's.
//! - **Members run in their job.** A (case, level) job of the study runs the unperturbed run,
//!   then its members one after the other ([`run_members`]), holding the unperturbed contact
//!   history and one member's run at a time, so memory does not grow with members × steps. The
//!   study is one job list, so it shards like any other (`--shard k/n`, `signorini merge`).

use std::collections::BTreeSet;

use super::{axial_element_size, run_compared, Comparator, ElasticStudyConfig};
use crate::harness::files::error::{Error, ParameterError};
use crate::harness::run::elastic::{BoxContactHistory, BoxProblem};
use crate::harness::run::norms::Norm;
use crate::harness::study::sensitivity::{
    classify_cases, EnsembleConfig, LevelEnsemble, Sensitivity, Separation,
};
use crate::harness::study::{Case, StudyConfig};

/// The velocity scale of the noise, `max|v⁰| = |initial_velocity|`. Refuses a problem that
/// cannot carry an ensemble: one at rest (no velocity scale), one without obstacle (no contact
/// node to measure the separation at).
pub fn noise_scale(problem: &BoxProblem) -> Result<f64, ParameterError> {
    if problem.obstacle_gap.is_none() {
        return Err(ParameterError::new(
            "obstacle_gap",
            "none",
            "an obstacle for a round-off ensemble (the separation is measured at the centre \
             contact node)",
        ));
    }
    let scale = problem.initial_velocity.abs();
    if !(scale.is_finite() && scale > 0.0) {
        return Err(ParameterError::new(
            "initial_velocity",
            problem.initial_velocity,
            "a finite nonzero velocity for a round-off ensemble (its noise is relative to \
             max|v⁰|)",
        ));
    }
    Ok(scale)
}

/// A study's round-off ensemble with the velocity scale of its noise ([`noise_scale`]).
#[derive(Debug, Clone, Copy)]
pub(super) struct Noise {
    /// Members and relative amplitude.
    pub(super) ensemble: EnsembleConfig,
    /// `max|v⁰|`.
    pub(super) scale: f64,
}

/// The round-off ensemble of `case` on `n_axis` elements, run inside that (case, level) job of
/// the study right after its unperturbed run, whose contact history is `base`: the members of
/// both sets ([`EnsembleConfig::members_of_study`]: initial-velocity noise of size
/// `amplitude · scale`, or the per-step perturbation), one after the
/// other, each compared with the reference and measured for its separation from `base`. A
/// member depends only on its job, so the ensemble shards with the study's one job list.
pub(super) fn run_members(
    problem: &BoxProblem,
    config: &ElasticStudyConfig,
    case: Case,
    n_axis: usize,
    comparator: &Comparator,
    base: &BoxContactHistory,
    noise: Noise,
) -> Result<LevelEnsemble, Error> {
    let Noise { ensemble, scale } = noise;
    let mut errors = Vec::with_capacity(2 * ensemble.members);
    let mut separations = Vec::with_capacity(2 * ensemble.members);
    for member in ensemble.members_of_study() {
        let perturbed = member.perturb(config.settings, ensemble.amplitude * scale);
        let mut comparison = comparator.comparison(n_axis);
        let run = run_compared(
            problem,
            config.ratio,
            perturbed,
            case,
            n_axis,
            &mut comparison,
            &mut [],
        )?;
        separations.push(Separation::between(
            &base.time,
            &base.centre_gap,
            &run.observed.contact.centre_gap,
        ));
        errors.push(comparison.errors());
    }
    Ok(LevelEnsemble {
        errors,
        separations,
        stopped: None,
    })
}

/// The sensitivity of every case of `config` from its level ensembles (`per_case[c][l]`: case
/// `c` at level `l`), each case classified by the 1D rules; `seconds` is the members' run time
/// summed over the jobs.
pub(super) fn classify(
    problem: &BoxProblem,
    config: &ElasticStudyConfig,
    ensemble: EnsembleConfig,
    per_case: Vec<Vec<LevelEnsemble>>,
    seconds: f64,
) -> Sensitivity {
    let norms: BTreeSet<Norm> = Norm::ALL.into_iter().collect();
    let h: Vec<f64> = config
        .levels
        .iter()
        .map(|&n| axial_element_size(problem, n))
        .collect();
    let study_config = StudyConfig {
        levels: config.levels.clone(),
        ratio: config.ratio,
        horizon: problem.horizon,
        settings: config.settings,
    };
    classify_cases(
        &config.cases,
        &study_config,
        &h,
        &norms,
        ensemble,
        per_case,
        seconds,
    )
}
