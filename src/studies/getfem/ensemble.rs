//! A round-off-chaotic configuration (issue 12) cannot agree with GetFEM step by step after its
//! predictability horizon: there, GetFEM's run is one more member of the harness's round-off
//! ensemble. [`ensemble_agreement`] runs that ensemble (the unperturbed run and members whose
//! initial displacement carries seeded noise of relative size `A`, as
//! `crate::harness::study::sensitivity` does) and measures GetFEM's run against it: before the
//! horizon step by step, after it through the demo's error norms.
//!
//! The two codes' round-off differences build up over the steps (different linear solvers,
//! operation orders); they act as a perturbation of the data of some size. Where GetFEM's run
//! parts among ensembles of amplitude `1e-13 … 1e-9` ([`AMPLITUDE_DECADES`]) measures that size:
//! on the eight chaotic runs of `tests/data/getfem` it lies between `1e-13` and `1e-11`
//! (`reports/getfem.md`). An ensemble represents GetFEM's run only if its members part no later
//! than GetFEM's does, so the agreement is judged with [`GETFEM_ENSEMBLE`], the smallest decade
//! that does so on all eight.

use super::{parting, solve, Difference};
use crate::harness::files::error::Error;
use crate::harness::getfem::{DemoConfig, DemoErrorNorms, DemoMass, DemoRun, DemoVersion};
use crate::harness::problem::Perturbation;
use crate::harness::study::sensitivity::{EnsembleConfig, Spread};
use std::path::Path;

/// The amplitudes whose ensembles' horizons bracket GetFEM's parting step in the report.
pub const AMPLITUDE_DECADES: [f64; 5] = [1e-13, 1e-12, 1e-11, 1e-10, 1e-9];

/// The ensemble GetFEM's round-off-chaotic runs are judged against: 16 members (as `signorini
/// sensitivity`), relative amplitude `1e-11` (the module's documentation says why).
pub const GETFEM_ENSEMBLE: EnsembleConfig = EnsembleConfig {
    members: 16,
    amplitude: 1e-11,
};

/// One of the demo's norms: GetFEM's printed value and the ensemble's spread of it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NormInEnsemble {
    /// The demo's name of the norm (`LinfL2u`, …).
    pub name: &'static str,
    /// GetFEM's value.
    pub getfem: f64,
    /// The ensemble's (the unperturbed run and its members).
    pub spread: Spread,
}

impl NormInEnsemble {
    /// Whether GetFEM's value is as far from the ensemble's median as the ensemble's own
    /// extremes may be: `|getfem − median| ≤ max − min`. A value drawn like the members' lies
    /// within `[min, max]` but for chance 2/(K + 2); this bound, twice as wide on each side,
    /// fails only for a value unlike any member.
    pub fn within(&self) -> bool {
        (self.getfem - self.spread.median).abs() <= self.spread.range()
    }
}

/// GetFEM's run of a configuration beside the harness's round-off ensemble of it.
#[derive(Debug, Clone, PartialEq)]
pub struct EnsembleAgreement {
    /// The ensemble's size and noise.
    pub ensemble: EnsembleConfig,
    /// The predictability horizon: the first step where a member's contact displacement parts
    /// from the unperturbed run's by more than `PARTING` (`None`: none parts).
    pub horizon: Option<usize>,
    /// The first step where GetFEM's parts from the unperturbed run's.
    pub getfem_parting: Option<usize>,
    /// GetFEM's largest difference from the unperturbed run up to the horizon (all steps when
    /// no member parts).
    pub before_horizon: Difference,
    /// The demo's norms that the two codes report alike ([`reported_alike`]), each with
    /// GetFEM's value and the ensemble's spread.
    pub norms: Vec<NormInEnsemble>,
}

impl EnsembleAgreement {
    /// GetFEM agrees with the ensemble: to `PARTING` up to the horizon (it parts no earlier
    /// than the first member), and every compared norm [`NormInEnsemble::within`] after it.
    pub fn holds(&self) -> bool {
        let in_time = match (self.horizon, self.getfem_parting) {
            (_, None) => true,
            (None, Some(_)) => false,
            (Some(h), Some(g)) => g >= h,
        };
        in_time && self.norms.iter().all(NormInEnsemble::within)
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

/// Runs the harness's round-off ensemble of `run`'s configuration (`ensemble.members` members,
/// relative amplitude `ensemble.amplitude` of `max|U⁰|`, seeds `1..=K`) and measures GetFEM's
/// run against it.
pub fn ensemble_agreement(
    root: &Path,
    run: &DemoRun,
    ensemble: EnsembleConfig,
) -> Result<EnsembleAgreement, Error> {
    ensemble.validate()?;
    let config = &run.config;
    let base = solve(root, config, None)?;
    let mut horizon: Option<usize> = None;
    let mut members: Vec<DemoErrorNorms> = vec![base.demo_norms];
    for seed in 1..=ensemble.members as u64 {
        let member = solve(
            root,
            config,
            Some(Perturbation {
                amplitude: ensemble.amplitude * base.initial_scale,
                seed,
            }),
        )?;
        if let Some(n) = parting(&base.u0, &member.u0) {
            horizon = Some(horizon.map_or(n, |h| h.min(n)));
        }
        members.push(member.demo_norms);
    }
    let series = &run.series;
    let up_to = horizon
        .map_or(series.u0.len(), |h| h + 1)
        .min(base.u0.len());
    let norms = run
        .norms
        .named()
        .into_iter()
        .enumerate()
        .filter(|(_, (name, _))| reported_alike(config, name))
        .map(|(k, (name, getfem))| {
            let values: Vec<f64> = members.iter().map(|m| m.named()[k].1).collect();
            NormInEnsemble {
                name,
                getfem,
                spread: Spread::of(&values),
            }
        })
        .collect();
    Ok(EnsembleAgreement {
        ensemble,
        horizon,
        getfem_parting: parting(&base.u0, &series.u0),
        before_horizon: Difference::between(&base.u0[..up_to], &series.u0, 0),
        norms,
    })
}
