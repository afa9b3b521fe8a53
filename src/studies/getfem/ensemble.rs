//! A round-off-chaotic configuration (`reports/sensitivity.md`) cannot agree with GetFEM step by step after its
//! predictability horizon: there, GetFEM's run is one more member of the harness's round-off
//! ensemble, and it is judged against the ensemble's distribution, never against the
//! harness's one (unperturbed) trajectory. [`ensemble_agreement`] runs that ensemble, the
//! unperturbed run and the two sets of members of
//! `crate::harness::study::sensitivity` ([`Member`]): `K` whose initial displacement carries
//! seeded noise of relative size `A`, and `K` whose carried state is perturbed after every step
//! by the unit round-off ([`STEP_EPSILON`](crate::harness::study::sensitivity::STEP_EPSILON)); it measures GetFEM's run against it: before the
//! horizon step by step, after it through the demo's error norms.
//!
//! The two codes' round-off differences build up over the steps (different linear solvers,
//! operation orders). [`GETFEM_ENSEMBLE`] is fixed before the comparison: it is the ensemble of
//! `reports/sensitivity.md` (`A` = 1e-13, `ε` the unit round-off), not an amplitude chosen to
//! make GetFEM's runs pass. GetFEM, one more member, is *in time* when it parts no earlier than
//! the ensemble's first member (of either set): a rule that fails where GetFEM's round-off acts
//! like a larger perturbation than the ensemble's. Where GetFEM's run parts among ensembles of
//! initial-data amplitude `1e-13 … 1e-9` ([`AMPLITUDE_DECADES`]) measures the size of data
//! perturbation it acts like (`reports/getfem.md`), a measurement and not a verdict. Members
//! perturbed on the initial data only follow the unperturbed dynamics; another code's round-off
//! enters at every step, which the per-step members reproduce: the norms are judged against the
//! range of both sets.

use super::{parting, solve, Difference};
use crate::harness::getfem::{DemoConfig, DemoErrorNorms, DemoMass, DemoRun, DemoVersion};
use crate::harness::study::sensitivity::{EnsembleConfig, Member, Spread};
use crate::studies::error::Error;
use std::path::Path;

/// The amplitudes whose ensembles' horizons bracket GetFEM's parting step in the report.
pub const AMPLITUDE_DECADES: [f64; 5] = [1e-13, 1e-12, 1e-11, 1e-10, 1e-9];

/// The ensemble GetFEM's round-off-chaotic runs are judged against, fixed before the
/// comparison: `signorini sensitivity`'s default ([`EnsembleConfig::default`]), 16 members of
/// each set and initial-data amplitude `1e-13` (the module's documentation says why).
pub const GETFEM_ENSEMBLE: EnsembleConfig = EnsembleConfig {
    members: 16,
    amplitude: 1e-13,
};

/// One of the demo's norms: GetFEM's printed value and the ensemble's spreads of it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NormInEnsemble {
    /// The demo's name of the norm (`LinfL2u`, …).
    pub name: &'static str,
    /// GetFEM's value.
    pub getfem: f64,
    /// The unperturbed run and the initial-data members: the ensemble before the per-step
    /// members.
    pub initial_data: Spread,
    /// The whole ensemble: the unperturbed run and both sets of members.
    pub spread: Spread,
}

impl NormInEnsemble {
    /// Whether GetFEM's value lies in the whole ensemble's `[min, max]`.
    pub fn inside(&self) -> bool {
        (self.spread.min..=self.spread.max).contains(&self.getfem)
    }

    /// Whether GetFEM's value lies in the initial-data ensemble's `[min, max]`.
    pub fn inside_initial_data(&self) -> bool {
        (self.initial_data.min..=self.initial_data.max).contains(&self.getfem)
    }

    /// Whether GetFEM's value is as far from the whole ensemble's median as the ensemble's own
    /// extremes may be: `|getfem − median| ≤ max − min`. A value drawn like the members' lies
    /// within `[min, max]` but for chance 2/(K + 2); a value beyond this bound, twice as wide on
    /// each side, is unlike any member.
    pub fn within(&self) -> bool {
        (self.getfem - self.spread.median).abs() <= self.spread.range()
    }
}

/// Whether GetFEM's run parts no earlier than the ensemble's first member: the timing rule
/// ([`EnsembleAgreement::in_time`]), or how many steps before it GetFEM parts.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Timing {
    /// GetFEM parts no earlier than the first member (or never parts).
    InTime,
    /// GetFEM parts this many steps before the ensemble's first member (all the steps left
    /// when no member parts).
    Early(usize),
}

/// What GetFEM's run is, judged against the ensemble's distribution.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Judgement {
    /// It parts no earlier than the ensemble's first member ([`Timing::InTime`]), and every
    /// compared norm lies in the ensemble's `[min, max]` ([`NormInEnsemble::inside`]).
    Agrees,
    /// It parts after the first impact but before the ensemble's first member (GetFEM's
    /// round-off acts like a larger perturbation than the ensemble's, which then is not its
    /// distribution), or it is in time and some norm lies outside `[min, max]` but none is
    /// unlike the members ([`NormInEnsemble::within`]): the ensemble does not cover it, so it
    /// neither agrees nor disagrees.
    Undecided,
    /// It parts at or before the first impact (where the problem is not chaotic), or it is in
    /// time and some norm is unlike any member.
    Disagrees,
}

impl Judgement {
    /// `agrees`, `undecided` or `disagrees`.
    pub fn name(self) -> &'static str {
        match self {
            Judgement::Agrees => "agrees",
            Judgement::Undecided => "undecided",
            Judgement::Disagrees => "disagrees",
        }
    }
}

/// GetFEM's run of a configuration beside the harness's round-off ensemble of it.
#[derive(Debug, Clone, PartialEq)]
pub struct EnsembleAgreement {
    /// The ensemble's size and initial-data noise.
    pub ensemble: EnsembleConfig,
    /// The predictability horizon: the first step where an initial-data member's contact
    /// displacement parts from the unperturbed run's by more than `PARTING` (`None`: none
    /// parts).
    pub horizon: Option<usize>,
    /// The same for the members perturbed at every step.
    pub step_horizon: Option<usize>,
    /// The step of the first impact of the exact solution (`t = 1`).
    pub first_impact: usize,
    /// The last step of the run.
    pub last_step: usize,
    /// The first step where GetFEM's parts from the unperturbed run's.
    pub getfem_parting: Option<usize>,
    /// GetFEM's largest difference from the unperturbed run up to the horizon (all steps when
    /// no member parts).
    pub before_horizon: Difference,
    /// The demo's norms that the two codes report alike ([`reported_alike`]), each with
    /// GetFEM's value and the ensemble's spreads.
    pub norms: Vec<NormInEnsemble>,
}

impl EnsembleAgreement {
    /// The first step where a member of either set parts from the unperturbed run.
    pub fn first_member(&self) -> Option<usize> {
        match (self.horizon, self.step_horizon) {
            (Some(a), Some(b)) => Some(a.min(b)),
            (a, b) => a.or(b),
        }
    }

    /// The timing rule: GetFEM, one more member, parts no earlier than the ensemble's first
    /// member ([`EnsembleAgreement::first_member`]).
    pub fn in_time(&self) -> Timing {
        match (self.getfem_parting, self.first_member()) {
            (None, _) => Timing::InTime,
            (Some(g), Some(h)) if g >= h => Timing::InTime,
            (Some(g), h) => Timing::Early(h.unwrap_or(self.last_step + 1) - g),
        }
    }

    /// Whether GetFEM parts after the first impact (or never): before it the problem is not
    /// chaotic, and the two codes must take the same steps.
    pub fn parts_after_impact(&self) -> bool {
        self.getfem_parting.is_none_or(|g| g > self.first_impact)
    }

    /// The judgement ([`Judgement`]): where GetFEM parts (after the first impact, and no
    /// earlier than the ensemble's first member), then, in time, its norms against the whole
    /// ensemble.
    pub fn judgement(&self) -> Judgement {
        let in_time = self.in_time() == Timing::InTime;
        let unlike = !self.norms.iter().all(NormInEnsemble::within);
        if !self.parts_after_impact() || in_time && unlike {
            Judgement::Disagrees
        } else if in_time && self.norms.iter().all(NormInEnsemble::inside) {
            Judgement::Agrees
        } else {
            Judgement::Undecided
        }
    }
}

/// Whether the demo and the harness report the norm `name` alike for `config` (the reporting
/// conventions of `reports/getfem.md`): the velocity norms not with Paoli–Schatzman (the demo
/// reports `V` at `t_n`, the harness at `t_{n−½}`) nor with a massless contact node (masses 1
/// and 2: the dynamics leave its velocity undefined), the stress norm not with a massless
/// contact node (the demo stores 0 at `t = 0`, the harness `λ⁰`).
fn reported_alike(config: &DemoConfig, name: &str) -> bool {
    let massless = config.mass != DemoMass::Consistent;
    let velocity = name.ends_with('v');
    let stress = name == "L2sn";
    !(velocity && (massless || config.version == DemoVersion::PaoliSchatzman) || stress && massless)
}

/// The members of `members` run on `run`'s configuration (initial-data noise of relative
/// amplitude `amplitude` of `max|U⁰|`): their earliest parting from `base_u0`, the unperturbed
/// contact displacement, and their demo norms.
fn run_members(
    root: &Path,
    run: &DemoRun,
    base_u0: &[f64],
    amplitude: f64,
    members: impl Iterator<Item = Member>,
) -> Result<(Option<usize>, Vec<DemoErrorNorms>), Error> {
    let mut horizon: Option<usize> = None;
    let mut norms = Vec::new();
    for member in members {
        let trace = solve(root, &run.config, Some((member, amplitude)))?;
        if let Some(n) = parting(base_u0, &trace.u0) {
            horizon = Some(horizon.map_or(n, |h| h.min(n)));
        }
        norms.push(trace.demo_norms);
    }
    Ok((horizon, norms))
}

/// The predictability horizon of `run`'s configuration under `ensemble`'s initial-data members
/// alone (the amplitude sweep of the report).
pub fn initial_data_horizon(
    root: &Path,
    run: &DemoRun,
    ensemble: EnsembleConfig,
) -> Result<Option<usize>, Error> {
    ensemble.validate()?;
    let base = solve(root, &run.config, None)?;
    let amplitude = ensemble.amplitude * base.initial_scale;
    let members = ensemble.initial_data_members();
    Ok(run_members(root, run, &base.u0, amplitude, members)?.0)
}

/// Runs the harness's round-off ensemble of `run`'s configuration (`ensemble.members` members
/// of each set: initial-data noise of relative amplitude `ensemble.amplitude` of `max|U⁰|`, and
/// the per-step perturbation of `ε` = [`STEP_EPSILON`](crate::harness::study::sensitivity::STEP_EPSILON), seeds `1..=K`) and measures GetFEM's
/// run against it.
pub fn ensemble_agreement(
    root: &Path,
    run: &DemoRun,
    ensemble: EnsembleConfig,
) -> Result<EnsembleAgreement, Error> {
    ensemble.validate()?;
    let config = &run.config;
    let base = solve(root, config, None)?;
    let amplitude = ensemble.amplitude * base.initial_scale;
    let initial = ensemble.initial_data_members();
    let (horizon, initial_norms) = run_members(root, run, &base.u0, amplitude, initial)?;
    let every_step = ensemble.every_step_members();
    let (step_horizon, step_norms) = run_members(root, run, &base.u0, amplitude, every_step)?;
    let series = &run.series;
    let up_to = horizon
        .map_or(series.u0.len(), |h| h + 1)
        .min(base.u0.len());
    let before: Vec<&DemoErrorNorms> = std::iter::once(&base.demo_norms)
        .chain(&initial_norms)
        .collect();
    let all: Vec<&DemoErrorNorms> = before.iter().copied().chain(&step_norms).collect();
    let spread = |members: &[&DemoErrorNorms], k: usize| {
        Spread::of(&members.iter().map(|m| m.named()[k].1).collect::<Vec<_>>())
    };
    let norms = run
        .norms
        .named()
        .into_iter()
        .enumerate()
        .filter(|(_, (name, _))| reported_alike(config, name))
        .map(|(k, (name, getfem))| NormInEnsemble {
            name,
            getfem,
            initial_data: spread(&before, k),
            spread: spread(&all, k),
        })
        .collect();
    Ok(EnsembleAgreement {
        ensemble,
        horizon,
        step_horizon,
        first_impact: (1.0 / config.dt).round() as usize,
        last_step: base.u0.len().saturating_sub(1),
        getfem_parting: parting(&base.u0, &series.u0),
        before_horizon: Difference::between(&base.u0[..up_to], &series.u0, 0),
        norms,
    })
}
