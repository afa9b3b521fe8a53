//! The stability suite: hard cases where time integrators for impact misbehave, every scheme ×
//! mass pair of the tables (the paper's and the rivals', [`Case::tables_matrix`]) run on each,
//! measured, and given a verdict by fixed rules.
//!
//! Verdict rules, in order (the first that applies), in the words and with the thresholds of
//! [`crate::harness::vocabulary`]:
//! 1. `diverged`: the run stopped on a non-finite value, or `max E / E_0 >`
//!    [`DIVERGED_ENERGY_RATIO`] = 10⁶;
//! 2. `gains energy`: the energy rises above its start by more than the physics check's
//!    allowance, `E_max / E_0 − 1 >` [`ENERGY_GAIN_TOLERANCE`] = 5 %, over every step of the run
//!    ([`Physics::gains_energy`]), or the least-squares slope of `E(t)` gains more than 5 % of
//!    `E_0` over the horizon with `max E / E_0 − 1 > 5 %` on the recorded history;
//! 3. `penetrating`: a contact node went into the obstacle by more than
//!    [`PENETRATION_TOLERANCE`](crate::harness::vocabulary::PENETRATION_TOLERANCE) = 1 % of the
//!    face's displacement scale ([`Physics::penetrates`]), or a contact force pulled
//!    ([`Physics::wrong_sign`]);
//! 4. `oscillates spuriously`: the contact force's total variation is at least
//!    [`OSCILLATION_YES_FROM`](crate::harness::vocabulary::OSCILLATION_YES_FROM) = 100 times
//!    the exact one's (the tables' Yes), or, when the exact force is constant, above
//!    [`CONSTANT_FORCE_VARIATION`] = 1e-9;
//! 5. `dissipative`: the energy ends more than
//!    [`DISSIPATIVE_LOSS_FROM`](crate::harness::vocabulary::DISSIPATIVE_LOSS_FROM) = 1 % of
//!    `E_0` below `E_0` (a run that loses 15 % of its energy over the horizon is dissipative,
//!    whatever round-off its steps add on the way);
//! 6. `stable`: none of the above.
//!
//! A run that penetrates or gains energy is therefore never `stable` nor `dissipative`, and its
//! record carries the time loop's figures ([`StabilityRecord::physics`]).
//!
//! Every run is also an ensemble ([`STABILITY_ENSEMBLE`],
//! `crate::harness::study::sensitivity::run_ensemble`): its members carry round-off-size noise on
//! the initial displacement, each gets its own verdict, and the run its [`RunSensitivity`]
//! (reproducible, event-sensitive, or chaotic with its predictability horizon).
//!
//! The ensemble decides what one run cannot ([`crate::harness::study::decision`]): the report's
//! verdict is the one the unperturbed run and every member share, and *undecided*, with the
//! members' split, when a threshold above is met by some of them and not by the others. A pair
//! *stays numerically stable* on a hard case when its verdict is `stable` or `dissipative` for
//! the unperturbed run and every member and the run's class is decided not chaotic
//! ([`StabilityRecord::stays_stable`]); it does not when no run is stable or dissipative or the
//! class is decided chaotic; otherwise (the runs split, or the class is undecided) it is
//! undecided.

use std::path::Path;
use std::sync::Arc;

use serde::{Deserialize, Serialize};

use crate::harness::files::artifacts::{write_atomic, write_json};
use crate::harness::files::error as files;
use crate::harness::problem::{AtRest, InitialData, Perturbation, Problem1d, Profile, Settings};
use crate::harness::run::physics::Physics;
use crate::harness::run::{BarRun, Observables, RunConfig};
use crate::harness::study::decision::{self, Decision};
use crate::harness::study::executor::{run_local, Executed, Executor, Jobs};
use crate::harness::study::rates::least_squares_slope;
use crate::harness::study::sensitivity::{
    class_text, run_ensemble, EnsembleConfig, RunSensitivity, SensitivityClass,
};
use crate::harness::study::shard::range::not_negative;
use crate::harness::study::shard::InRange;
use crate::harness::study::Case;
use crate::harness::vocabulary::{
    self, Interval, CONSTANT_FORCE_VARIATION, DIVERGED_ENERGY_RATIO, ENERGY_GAIN_TOLERANCE,
};
use crate::studies::benchmark::{bar_scene, DIRICHLET_SCENE};
use crate::studies::error::Error;

/// The suite's report, under a reports directory.
pub const STABILITY_MD: &str = "stability.md";

/// Every record of the suite (`Vec<StabilityRecord>`), under a reports directory; `make
/// figures` reads it back.
pub const STABILITY_JSON: &str = "stability.json";

/// The round-off ensemble of every stability run: 4 members with relative noise 1e-13. Fewer
/// than the refinement study's 16: at one mesh the ensemble only has to witness whether the
/// members part and how fast, and each member costs a whole run of the hard case.
pub const STABILITY_ENSEMBLE: EnsembleConfig = EnsembleConfig {
    members: 4,
    amplitude: 1e-13,
};

/// A hard case: a problem at one mesh and time step.
#[derive(Debug, Clone)]
pub struct HardCase {
    /// Short name.
    pub name: &'static str,
    /// What it exercises.
    pub description: &'static str,
    /// The problem.
    pub problem: Problem1d,
    /// `NX`.
    pub nx: usize,
    /// `Δx/Δt`.
    pub ratio: f64,
}

/// The hard cases, on the Signorini–Dirichlet benchmark (its scene under the repository root
/// `root`); `ci` selects the fast subset guarded by the test suite.
pub fn hard_cases(root: &Path, ci: bool) -> Result<Vec<HardCase>, Error> {
    let (_, declared) = bar_scene(root, DIRICHLET_SCENE)?;
    let dirichlet = |horizon: f64| Problem1d {
        horizon,
        ..declared.clone()
    };
    let mut cases = vec![HardCase {
        name: "long-horizon",
        description: "100 periods (T = 300) of the Dirichlet benchmark",
        problem: dirichlet(300.0),
        nx: 80,
        ratio: 10.0,
    }];
    if ci {
        return Ok(cases);
    }
    for (name, ratio) in [
        ("ratio-0.5", 0.5),
        ("ratio-1", 1.0),
        ("ratio-10", 10.0),
        ("ratio-100", 100.0),
        ("ratio-1000", 1000.0),
    ] {
        cases.push(HardCase {
            name,
            description: "time-step extreme: Δx/Δt at NX = 40, T = 3 (small steps: Grosu–Harari)",
            problem: dirichlet(3.0),
            nx: 40,
            ratio,
        });
    }
    cases.push(HardCase {
        name: "coarse-mesh",
        description: "mesh extreme: NX = 2, T = 3",
        problem: dirichlet(3.0),
        nx: 2,
        ratio: 10.0,
    });
    cases.push(HardCase {
        name: "fine-mesh",
        description: "mesh extreme: NX = 5000, T = 3",
        problem: dirichlet(3.0),
        nx: 5000,
        ratio: 10.0,
    });
    cases.push(HardCase {
        name: "grazing",
        description: "the bar at rest touching the obstacle: u ≡ 0, λ ≡ 0 is the solution",
        problem: Problem1d {
            exact: Arc::new(AtRest),
            initial: InitialData {
                displacement: Profile::Constant(0.0),
                velocity: Profile::Constant(0.0),
                ..InitialData::default()
            },
            ..dirichlet(3.0)
        },
        nx: 40,
        ratio: 10.0,
    });
    cases.push(HardCase {
        name: "repeated-impacts",
        description: "10 periods (10 impacts and releases) at NX = 40",
        problem: dirichlet(30.0),
        nx: 40,
        ratio: 10.0,
    });
    cases.push(HardCase {
        name: "rough-data",
        description: "initial displacement perturbed at every node by ±0.01 (seed 42)",
        problem: Problem1d {
            initial: InitialData {
                perturbation: Some(Perturbation {
                    amplitude: 0.01,
                    seed: 42,
                }),
                ..InitialData::default()
            },
            ..dirichlet(3.0)
        },
        nx: 80,
        ratio: 10.0,
    });
    Ok(cases)
}

/// The verdict on one run.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Verdict {
    /// Bounded energy, no spurious oscillation.
    Stable,
    /// Energy lost, never gained.
    Dissipative,
    /// Energy grows beyond its allowance.
    EnergyGrowth,
    /// A contact node went into the obstacle, or a contact force pulled.
    Penetrating,
    /// The contact force oscillates spuriously.
    Oscillating,
    /// Non-finite values or unbounded energy.
    Diverged,
}

impl Verdict {
    /// The word in the report: the vocabulary's ([`crate::harness::vocabulary::words`]).
    pub fn word(self) -> &'static str {
        match self {
            Verdict::Stable => "stable",
            Verdict::Dissipative => "dissipative",
            Verdict::EnergyGrowth => "gains energy",
            Verdict::Penetrating => "penetrating",
            Verdict::Oscillating => "oscillates spuriously",
            Verdict::Diverged => "diverged",
        }
    }
}

/// What one hard case × scheme × mass run measured.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct StabilityRecord {
    /// The hard case.
    pub hard_case: String,
    /// `scheme/mass`.
    pub case: String,
    /// `max |E − E_0| / E_0` (absolute when `E_0 = 0`).
    pub max_energy_drift: f64,
    /// `(E(T) − E_0) / E_0` from the least-squares line of `E(t)`, i.e. slope × T / E_0.
    pub energy_trend: f64,
    /// The largest one-step energy increase, relative to `E_0`.
    pub max_energy_step_increase: f64,
    /// `max |λ_h|`.
    pub max_multiplier: f64,
    /// The largest complementarity violation.
    pub complementarity_violation: f64,
    /// `TV(λ_h) / TV(λ)`, or `TV(λ_h)` when the exact force is constant.
    pub oscillation_indicator: f64,
    /// Whether the exact force varies (which form the indicator takes).
    pub indicator_is_ratio: bool,
    /// The verdict.
    pub verdict: Verdict,
    /// The error that stopped the run, if any.
    pub failure: Option<String>,
    /// Energy samples `(t, E)` thinned to about 200 points, for plots.
    pub energy_samples: Vec<(f64, f64)>,
    /// The verdict of each member of the round-off ensemble (`diverged` for a member whose run
    /// stopped); empty when the unperturbed run stopped.
    #[serde(default)]
    pub member_verdicts: Vec<Verdict>,
    /// The oscillation indicator of each member that completed (the form of
    /// `oscillation_indicator`); empty when the unperturbed run stopped, or in a record written
    /// before the suite kept them.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub member_indicators: Vec<f64>,
    /// The run's round-off sensitivity; `null` when the unperturbed run stopped.
    #[serde(default)]
    pub sensitivity: Option<RunSensitivity>,
    /// The largest per-step residual of the scheme's energy balance (1D paper eqs. 33, 35, 37;
    /// relative to the energy, see `schemes::energy_balance::BalanceMonitor`) over the
    /// unperturbed run; `null` when that run stopped.
    #[serde(default)]
    pub max_balance_residual: Option<f64>,
    /// The unperturbed run's penetration, largest energy above the start and contact-force
    /// sign, as the time loop measured them ([`Physics`]); `null` when that run stopped.
    #[serde(default)]
    pub physics: Option<Physics>,
}

impl StabilityRecord {
    /// The verdict the unperturbed run and every member share; `None` when they split (no
    /// members: the run's own).
    pub fn shared_verdict(&self) -> Option<Verdict> {
        self.member_verdicts
            .iter()
            .all(|&v| v == self.verdict)
            .then_some(self.verdict)
    }

    /// The run's verdict and the members', counted: `the run stable; members: 3 stable, 1
    /// energy growth`.
    pub fn split(&self) -> String {
        let mut counts: Vec<(Verdict, usize)> = Vec::new();
        for &v in &self.member_verdicts {
            match counts.iter_mut().find(|(w, _)| *w == v) {
                Some((_, n)) => *n += 1,
                None => counts.push((v, 1)),
            }
        }
        let members: Vec<String> = counts
            .iter()
            .map(|(v, n)| format!("{n} {}", v.word()))
            .collect();
        format!(
            "the run {}; members: {}",
            self.verdict.word(),
            members.join(", ")
        )
    }

    /// The verdict as the report prints it: the one the run and every member share, or
    /// `undecided` with their split.
    pub fn verdict_text(&self) -> String {
        match self.shared_verdict() {
            Some(v) => v.word().to_string(),
            None => format!("**undecided** ({})", self.split()),
        }
    }

    /// "Stable or dissipative": holds when the run and every member are, fails when none is,
    /// undecided when they split (round-off alone moves the verdict across a threshold).
    fn bounded(&self) -> Decision {
        let fine = |v: &&&Verdict| matches!(v, Verdict::Stable | Verdict::Dissipative);
        let runs: Vec<&Verdict> = std::iter::once(&self.verdict)
            .chain(&self.member_verdicts)
            .collect();
        let fine_runs = runs.iter().filter(fine).count();
        let named = || match self.shared_verdict() {
            Some(v) => v.word().to_string(),
            None => self.split(),
        };
        if fine_runs == runs.len() {
            Decision {
                verdict: decision::Verdict::Holds,
                reason: format!(
                    "{} in the run and its {} members",
                    named(),
                    self.member_verdicts.len()
                ),
            }
        } else if fine_runs == 0 {
            Decision {
                verdict: decision::Verdict::Fails,
                reason: named(),
            }
        } else {
            Decision::undecided(format!(
                "{}: round-off alone moves the verdict across a threshold, so no run at this \
                 mesh and step decides it",
                self.split()
            ))
        }
    }

    /// "Not round-off chaotic": holds for a decided reproducible or event-sensitive class,
    /// fails for a decided chaotic one, undecided when the class is not decided or was not
    /// measured.
    fn not_chaotic(&self) -> Decision {
        let Some(s) = self.sensitivity else {
            return Decision::undecided(
                "its round-off sensitivity was not measured: the ensemble would decide it",
            );
        };
        let class = s.class_decision();
        if class.verdict == decision::Verdict::Undecided {
            return Decision::undecided(format!("round-off class undecided: {}", class.reason));
        }
        match s.class {
            SensitivityClass::Chaotic => Decision {
                verdict: decision::Verdict::Fails,
                reason: format!(
                    "round-off chaotic (predictable to t = {})",
                    s.predictability_time
                        .map_or("—".to_string(), |t| format!("{t:.3}"))
                ),
            },
            class => Decision {
                verdict: decision::Verdict::Holds,
                reason: format!("round-off {}", class.name()),
            },
        }
    }

    /// Whether the pair stays numerically stable on this hard case: `stable` or `dissipative`
    /// for the unperturbed run and every member, and not round-off chaotic, in three-valued
    /// logic ([`decision::all_of`]): a split ensemble or an undecided class leaves it undecided
    /// unless the other part fails.
    pub fn stays_stable(&self) -> Decision {
        decision::all_of(vec![self.bounded(), self.not_chaotic()])
    }

    /// The distinct verdicts of the members that differ from the unperturbed run's.
    pub fn other_member_verdicts(&self) -> Vec<&'static str> {
        let mut others: Vec<&'static str> = Vec::new();
        for v in self.member_verdicts.iter().filter(|&&v| v != self.verdict) {
            if !others.contains(&v.word()) {
                others.push(v.word());
            }
        }
        others
    }
}

/// Runs one hard case with one scheme and mass as an ensemble ([`STABILITY_ENSEMBLE`]), and
/// judges the unperturbed run and every member.
pub fn judge(hard: &HardCase, case: Case) -> Result<StabilityRecord, files::Error> {
    let config = RunConfig {
        nx: hard.nx,
        ratio: hard.ratio,
        scheme: case.scheme,
        mass: case.mass,
        observables: Observables {
            energy_history: true,
            contact_history: true,
            energy_balance: true,
            ..Observables::default()
        },
        settings: Settings::default(),
    };
    let mut member_verdicts = Vec::new();
    let mut member_indicators = Vec::new();
    let mut separations = Vec::new();
    let base = run_ensemble(
        &hard.problem,
        &config,
        STABILITY_ENSEMBLE,
        &mut |member, separation| {
            member_verdicts.push(if member.status.is_completed() {
                let judged = assess(hard, case, &member);
                member_indicators.push(judged.oscillation_indicator);
                judged.verdict
            } else {
                Verdict::Diverged
            });
            separations.extend(separation);
            Ok(())
        },
    );
    match base {
        Ok(r) => match r.status.completed() {
            Ok(()) => Ok(StabilityRecord {
                member_verdicts,
                member_indicators,
                sensitivity: Some(RunSensitivity::of(&separations, r.dt, STABILITY_ENSEMBLE)),
                max_balance_residual: r.max_balance_residual,
                physics: r.physics,
                ..assess(hard, case, &r)
            }),
            Err(stopped) => Ok(StabilityRecord {
                failure: Some(stopped.to_string()),
                ..unmeasured(hard, case)
            }),
        },
        Err(files::Error::Solve(e)) => Ok(StabilityRecord {
            failure: Some(e.to_string()),
            ..unmeasured(hard, case)
        }),
        Err(e) => Err(e),
    }
}

/// The record of a run that measured nothing (verdict `diverged`).
fn unmeasured(hard: &HardCase, case: Case) -> StabilityRecord {
    StabilityRecord {
        hard_case: hard.name.to_string(),
        case: case.id(),
        max_energy_drift: f64::NAN,
        energy_trend: f64::NAN,
        max_energy_step_increase: f64::NAN,
        max_multiplier: f64::NAN,
        complementarity_violation: f64::NAN,
        oscillation_indicator: f64::NAN,
        indicator_is_ratio: false,
        verdict: Verdict::Diverged,
        failure: None,
        energy_samples: Vec::new(),
        member_verdicts: Vec::new(),
        member_indicators: Vec::new(),
        sensitivity: None,
        max_balance_residual: None,
        physics: None,
    }
}

/// The measures and the verdict of one run of `hard` (the module's rules).
fn assess(hard: &HardCase, case: Case, result: &BarRun) -> StabilityRecord {
    let energy = result.observed.energy_history.as_ref().expect("requested");
    let e0 = energy.energy[0];
    let scale = if e0.abs() > 0.0 { e0.abs() } else { 1.0 };
    let max_drift = energy
        .energy
        .iter()
        .map(|e| (e - e0).abs() / scale)
        .fold(0.0, f64::max);
    let max_ratio = energy.energy.iter().fold(0.0_f64, |m, e| m.max(e / scale));
    let step_increase = energy
        .energy
        .windows(2)
        .map(|w| (w[1] - w[0]) / scale)
        .fold(0.0, f64::max);
    let horizon = hard.problem.horizon;
    let trend = least_squares_slope(&energy.time, &energy.energy).unwrap_or(0.0) * horizon / scale;
    let variation = result.observed.multiplier_variation.unwrap_or_default();
    let (indicator, is_ratio) = match variation.ratio() {
        Some(r) => (r, true),
        None => (variation.discrete, false),
    };
    let last = *energy.energy.last().expect("at least the initial sample");
    let physics = result.physics;
    let holds = |d: Decision| d.verdict == decision::Verdict::Holds;
    let spurious = if is_ratio {
        holds(vocabulary::oscillates_spuriously(&Interval::point(
            "indicator",
            indicator,
        )))
    } else {
        indicator > CONSTANT_FORCE_VARIATION
    };
    let verdict = if !max_ratio.is_finite() || max_ratio > DIVERGED_ENERGY_RATIO {
        Verdict::Diverged
    } else if (max_ratio - 1.0 > ENERGY_GAIN_TOLERANCE && trend > ENERGY_GAIN_TOLERANCE)
        || physics.is_some_and(|p| p.gains_energy())
    {
        Verdict::EnergyGrowth
    } else if physics.is_some_and(|p| p.penetrates() || p.wrong_sign()) {
        Verdict::Penetrating
    } else if spurious {
        Verdict::Oscillating
    } else if holds(vocabulary::dissipative(&Interval::point(
        "energy lost",
        (e0 - last) / scale,
    ))) {
        Verdict::Dissipative
    } else {
        Verdict::Stable
    };
    let stride = (energy.time.len() / 200).max(1);
    StabilityRecord {
        max_energy_drift: max_drift,
        energy_trend: trend,
        max_energy_step_increase: step_increase,
        max_multiplier: variation.max_abs,
        complementarity_violation: result.complementarity_violation,
        oscillation_indicator: indicator,
        indicator_is_ratio: is_ratio,
        verdict,
        energy_samples: energy
            .time
            .iter()
            .zip(&energy.energy)
            .step_by(stride)
            .map(|(&t, &e)| (t, e))
            .collect(),
        ..unmeasured(hard, case)
    }
}

impl InRange for StabilityRecord {
    fn out_of_range(&self) -> Option<String> {
        not_negative("complementarity_violation", self.complementarity_violation)
            .or_else(|| not_negative("oscillation_indicator", self.oscillation_indicator))
            .or_else(|| not_negative("max_multiplier", self.max_multiplier))
    }
}

/// Every hard case × every case, in parallel (the finest meshes first), in that order.
pub fn run_suite(hard: &[HardCase], cases: &[Case]) -> Result<Vec<StabilityRecord>, Error> {
    let items = suite_jobs(hard, cases);
    Ok(run_local(&Jobs {
        items: &items,
        size: &|&(h, _)| hard[h].nx,
        run: &|&(h, c)| judge(&hard[h], cases[c]),
    })?
    .results)
}

/// [`run_suite`] with its runs handed to `executor`: the records, or a shard's share of them.
pub fn run_suite_on(
    executor: &Executor,
    hard: &[HardCase],
    cases: &[Case],
) -> Result<Executed<Vec<StabilityRecord>>, Error> {
    let items = suite_jobs(hard, cases);
    Ok(executor
        .execute(&Jobs {
            items: &items,
            size: &|&(h, _)| hard[h].nx,
            run: &|&(h, c)| judge(&hard[h], cases[c]),
        })?
        .reduce(|ran| Ok(ran.results))?)
}

/// The suite's jobs: (hard case, case) index pairs, hard case by hard case.
fn suite_jobs(hard: &[HardCase], cases: &[Case]) -> Vec<(usize, usize)> {
    (0..hard.len())
        .flat_map(|h| (0..cases.len()).map(move |c| (h, c)))
        .collect()
}

/// Writes `stability.md` and `stability.json` of the suite's `records` on `hard` into `out_dir`.
pub fn write_stability_files(
    out_dir: &Path,
    hard: &[HardCase],
    records: &[StabilityRecord],
) -> Result<(), Error> {
    write_atomic(
        &out_dir.join(STABILITY_MD),
        render(hard, records).as_bytes(),
    )?;
    Ok(write_json(&out_dir.join(STABILITY_JSON), &records)?)
}

/// The round-off column of a record: the class, a chaotic run's predictability horizon, and
/// the members' verdicts that differ from the unperturbed run's.
fn round_off_cell(r: &StabilityRecord) -> String {
    let Some(s) = r.sensitivity else {
        return "—".to_string();
    };
    let mut cell = class_text(s.class, &s.class_decision());
    if let Some(t) = s.predictability_time {
        cell.push_str(&format!(", parts at t = {t:.3}"));
    }
    let differ = r
        .member_verdicts
        .iter()
        .filter(|&&v| v != r.verdict)
        .count();
    if differ > 0 {
        cell.push_str(&format!(
            "; {differ} of {} members: {}",
            r.member_verdicts.len(),
            r.other_member_verdicts().join(", ")
        ));
    }
    cell
}

/// `E_max/E₀` of a run's physics, bold beyond the allowance; `—` unmeasured.
fn energy_ratio_cell(p: Option<&Physics>) -> String {
    let Some(p) = p else {
        return "—".to_string();
    };
    let text = match p.energy_ratio {
        Some(r) if r < 1e3 => format!("{r:.4}"),
        Some(r) => format!("{r:.3e}"),
        None => format!("E_max − E₀ = {:.2e}", p.energy_max - p.energy_start),
    };
    if p.gains_energy() {
        format!("**{text}**")
    } else {
        text
    }
}

/// The largest penetration relative to the face's displacement scale (absolute with `D = 0`),
/// bold beyond its tolerance, with a pulling force when there was one; `—` unmeasured.
fn penetration_cell(p: Option<&Physics>) -> String {
    let Some(p) = p else {
        return "—".to_string();
    };
    let mut text = match p.relative_penetration {
        Some(r) => format!("{r:.1e}"),
        None => format!("{:.1e} (D = 0)", p.penetration),
    };
    if p.penetrates() {
        text = format!("**{text}**");
    }
    if p.wrong_sign() {
        text.push_str(&format!("; **pulls** {:.1e}", p.wrong_sign_force));
    }
    text
}

/// The oscillation indicator of a record (`(ratio)` or `(TV)`), with the range over the run and
/// its members when they were kept: the interval that decides the spurious-oscillation rule.
fn oscillation_cell(r: &StabilityRecord) -> String {
    let figure = |x: f64| {
        if r.indicator_is_ratio {
            format!("{x:.3}")
        } else {
            format!("{x:.2e}")
        }
    };
    let form = if r.indicator_is_ratio { "ratio" } else { "TV" };
    if r.member_indicators.is_empty() {
        return format!("{} ({form})", figure(r.oscillation_indicator));
    }
    let range = Interval::of_runs("indicator", r.oscillation_indicator, &r.member_indicators);
    format!(
        "{} [{}, {}] ({form})",
        figure(r.oscillation_indicator),
        figure(range.low),
        figure(range.high)
    )
}

/// The markdown report: the parameters of each hard case, then one table per hard case.
pub fn render(hard: &[HardCase], records: &[StabilityRecord]) -> String {
    let mut md = String::from("# Stability of the schemes on hard cases\n\n");
    md.push_str(
        "Verdicts, first rule that applies, in the words of the book's *The verdict words* \
         (docs/src/vocabulary.md): **diverged** (non-finite value or E/E₀ > 10⁶); **gains \
         energy** (the largest energy of any step E_max/E₀ − 1 > 5 %, the physics check every \
         run makes, or the fitted trend of E gains > 5 % of E₀ over the horizon); \
         **penetrating** (a contact node inside the obstacle by more than 1 % of the face's \
         displacement scale D, its largest distance from the obstacle, or a pulling contact \
         force); **oscillates spuriously** (TV(λ_h)/TV(λ) ≥ 100, the tables' Yes, or TV(λ_h) \
         > 1e-9 when the exact force is constant); **dissipative** (E ends more than 1 % of E₀ \
         below E₀); **stable** otherwise. The verdict shown is the one the unperturbed run and \
         every member of its round-off ensemble share: each rule's figure is decided by its \
         range over those runs (the oscillation column shows the indicator's range), and where \
         a threshold lies within that range, met by some runs and not by the others, the \
         verdict is **undecided**, with their split. A range that lies on one side of its \
         threshold decides however near it lies: round-off does not move it across. \
         Generated by `make stability`.\n\n",
    );
    md.push_str(&format!(
        "Round-off: every run is also an ensemble of {} members with relative noise {:e} on the \
         initial displacement (contact dof untouched). *reproducible*: no member's contact-node \
         displacement parts from the unperturbed run by more than {:e}; *chaotic*: a \
         separation grows exponentially to {:e} (at one mesh there is no rate to compare, so \
         the separation alone decides), shown with the predictability horizon t at which the \
         first member parts; *event-sensitive*: members part, but not so. Members whose \
         verdict differs from the unperturbed run's are listed. A pair *stays numerically \
         stable* on a hard case when every run's verdict is stable or dissipative and it is \
         not chaotic; it does not when no run's verdict is or it is chaotic; it is undecided \
         when the runs split or the class is undecided.\n\n",
        STABILITY_ENSEMBLE.members,
        STABILITY_ENSEMBLE.amplitude,
        crate::harness::study::sensitivity::PARTING,
        crate::harness::study::sensitivity::RUNAWAY,
    ));
    md.push_str("| hard case | NX | Δx/Δt | T | what it exercises |\n|---|---|---|---|---|\n");
    for h in hard {
        md.push_str(&format!(
            "| {} | {} | {} | {} | {} |\n",
            h.name, h.nx, h.ratio, h.problem.horizon, h.description
        ));
    }
    for h in hard {
        md.push_str(&format!(
            "\n## {}\n\n| case | verdict | round-off | max abs(E − E₀)/E₀ | E_max/E₀ | penetration p/D | trend over T | max step gain | max abs(λ) | complementarity | oscillation |\n|---|---|---|---|---|---|---|---|---|---|---|\n",
            h.name
        ));
        for r in records.iter().filter(|r| r.hard_case == h.name) {
            if let Some(f) = &r.failure {
                md.push_str(&format!(
                    "| {} | **{}** | — | — | — | — | — | — | — | — | {} |\n",
                    r.case,
                    r.verdict.word(),
                    f
                ));
                continue;
            }
            let osc = oscillation_cell(r);
            md.push_str(&format!(
                "| {} | {} | {} | {:.2e} | {} | {} | {:+.2e} | {:.1e} | {:.3} | {:.1e} | {} |\n",
                r.case,
                r.verdict_text(),
                round_off_cell(r),
                r.max_energy_drift,
                energy_ratio_cell(r.physics.as_ref()),
                penetration_cell(r.physics.as_ref()),
                r.energy_trend,
                r.max_energy_step_increase,
                r.max_multiplier,
                r.complementarity_violation,
                osc
            ));
        }
    }
    md.push_str(
        "\n## Pairs that stay numerically stable on every hard case\n\nStable or dissipative \
         for the unperturbed run and every member, and not round-off chaotic; otherwise what \
         fails, hard case by hard case, and where the ensemble cannot tell (*undecided*: the \
         runs split, or the class is undecided) why.\n\n",
    );
    let mut ids: Vec<&str> = Vec::new();
    for r in records {
        if !ids.contains(&r.case.as_str()) {
            ids.push(&r.case);
        }
    }
    for id in ids {
        let bad: Vec<String> = records
            .iter()
            .filter(|r| r.case == id)
            .filter_map(|r| {
                let d = r.stays_stable();
                match d.verdict {
                    decision::Verdict::Holds => None,
                    decision::Verdict::Fails => Some(format!("{} ({})", r.hard_case, d.reason)),
                    decision::Verdict::Undecided => {
                        Some(format!("{} (undecided: {})", r.hard_case, d.reason))
                    }
                }
            })
            .collect();
        let line = if bad.is_empty() {
            "stays numerically stable on every hard case".to_string()
        } else {
            bad.join(", ")
        };
        md.push_str(&format!("- `{id}`: {line}\n"));
    }
    md
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::harness::study::decision::Verdict as Decided;

    /// A record of `verdict` with `members`, its class `class` measured with the members'
    /// median growth `growth` and largest separation `largest`.
    fn record(
        verdict: Verdict,
        members: &[Verdict],
        class: SensitivityClass,
        growth: Option<f64>,
        largest: f64,
    ) -> StabilityRecord {
        let parted = (class != SensitivityClass::Reproducible).then_some(400);
        StabilityRecord {
            hard_case: "long-horizon".into(),
            case: "newmark-1/standard".into(),
            max_energy_drift: 0.0,
            energy_trend: 0.0,
            max_energy_step_increase: 0.0,
            max_multiplier: 1.0,
            complementarity_violation: 0.0,
            oscillation_indicator: 1.0,
            indicator_is_ratio: true,
            verdict,
            failure: None,
            energy_samples: Vec::new(),
            member_verdicts: members.to_vec(),
            member_indicators: Vec::new(),
            sensitivity: Some(RunSensitivity {
                class,
                members: members.len(),
                amplitude: 1e-13,
                predictability_step: parted,
                predictability_time: parted.map(|n| n as f64 * 0.01),
                separation_growth: growth,
                largest_separation: largest,
            }),
            max_balance_residual: None,
            physics: None,
        }
    }

    fn reproducible(verdict: Verdict, members: &[Verdict]) -> StabilityRecord {
        record(
            verdict,
            members,
            SensitivityClass::Reproducible,
            None,
            1e-12,
        )
    }

    /// The suite's long-horizon run (NX = 80, T = 300) of `scheme` with `mass`, judged.
    fn long_horizon(scheme: &str, mass: crate::harness::problem::MassVariant) -> StabilityRecord {
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
        let hard = hard_cases(root, true)
            .unwrap()
            .into_iter()
            .find(|h| h.name == "long-horizon")
            .unwrap();
        let case = Case {
            scheme: scheme.parse().unwrap(),
            mass,
        };
        judge(&hard, case).unwrap()
    }

    /// Moreau–Jean with the redistributed mass over the long horizon (NX = 80, T = 300): its
    /// massless contact node sinks to 97 % of the face's displacement scale while its energy
    /// stays at E₀. The suite called it stable before the time loop measured penetration; it
    /// is penetrating now, and does not stay numerically stable.
    #[test]
    fn a_penetrating_run_is_never_stable() {
        let r = long_horizon(
            "moreau-jean",
            crate::harness::problem::MassVariant::Redistributed,
        );
        let p = r.physics.expect("measured");
        assert!(p.relative_penetration.unwrap() > 0.9, "{p:?}");
        assert!(p.energy_ratio.unwrap() < 1.0 + 1e-6, "{p:?}");
        assert_eq!(r.verdict, Verdict::Penetrating);
        assert_eq!(r.verdict_text(), "penetrating");
        assert_eq!(r.stays_stable().verdict, Decided::Fails);
    }

    /// Contact-stabilised Newmark with the standard mass over the long horizon loses 18 % of its
    /// energy while round-off raises single steps (by about 3e-13 E₀ since the energy's forms are
    /// summed in four lanes; 1e-11 E₀ before). The suite called it stable while its dissipative
    /// rule asked that no step gain more than 1e-12 E₀; it is dissipative now, whatever its
    /// steps gain, and still stays numerically stable.
    #[test]
    fn a_run_that_loses_energy_is_dissipative_whatever_round_off_its_steps_add() {
        let r = long_horizon(
            "contact-stabilised-newmark",
            crate::harness::problem::MassVariant::Standard,
        );
        assert!(r.max_energy_drift > 0.15, "{}", r.max_energy_drift);
        assert!(
            r.max_energy_step_increase > 0.0,
            "{}",
            r.max_energy_step_increase
        );
        assert_eq!(r.verdict_text(), "dissipative");
        assert_eq!(r.member_indicators.len(), STABILITY_ENSEMBLE.members);
        assert!(
            oscillation_cell(&r).contains(" ["),
            "{}",
            oscillation_cell(&r)
        );
        assert_eq!(r.stays_stable().verdict, Decided::Holds);
    }

    #[test]
    fn runs_that_agree_decide_the_verdict() {
        let r = reproducible(Verdict::Stable, &[Verdict::Stable; 4]);
        assert_eq!(r.shared_verdict(), Some(Verdict::Stable));
        assert_eq!(r.verdict_text(), "stable");
        let stays = r.stays_stable();
        assert_eq!(stays.verdict, Decided::Holds, "{}", stays.reason);
        let grows = reproducible(Verdict::EnergyGrowth, &[Verdict::EnergyGrowth; 4]);
        let stays = grows.stays_stable();
        assert_eq!(stays.verdict, Decided::Fails);
        assert_eq!(stays.reason, "gains energy");
    }

    #[test]
    fn a_threshold_met_by_some_runs_only_is_undecided_with_the_split() {
        use Verdict::{EnergyGrowth, Stable};
        let r = reproducible(EnergyGrowth, &[EnergyGrowth, Stable, EnergyGrowth, Stable]);
        assert_eq!(r.shared_verdict(), None);
        assert_eq!(
            r.verdict_text(),
            "**undecided** (the run gains energy; members: 2 gains energy, 2 stable)"
        );
        let stays = r.stays_stable();
        assert_eq!(stays.verdict, Decided::Undecided);
        assert!(stays.reason.contains("round-off alone"), "{}", stays.reason);
        let members_only = reproducible(Stable, &[Stable, Stable, Stable, EnergyGrowth]);
        assert_eq!(members_only.stays_stable().verdict, Decided::Undecided);
    }

    #[test]
    fn runs_unstable_in_different_ways_fail_to_stay_stable_with_an_undecided_verdict() {
        let r = reproducible(Verdict::Oscillating, &[Verdict::EnergyGrowth; 4]);
        assert!(r.verdict_text().starts_with("**undecided**"));
        let stays = r.stays_stable();
        assert_eq!(stays.verdict, Decided::Fails);
        assert_eq!(
            stays.reason,
            "the run oscillates spuriously; members: 4 gains energy"
        );
    }

    #[test]
    fn a_decided_chaotic_class_fails_and_an_undecided_one_leaves_it_undecided() {
        let chaotic = record(
            Verdict::Dissipative,
            &[Verdict::Dissipative; 4],
            SensitivityClass::Chaotic,
            Some(2.9),
            1.7e-4,
        );
        let stays = chaotic.stays_stable();
        assert_eq!(stays.verdict, Decided::Fails);
        assert_eq!(stays.reason, "round-off chaotic (predictable to t = 4.000)");
        let jump = record(
            Verdict::Stable,
            &[Verdict::Stable; 4],
            SensitivityClass::Chaotic,
            None,
            2e-3,
        );
        let stays = jump.stays_stable();
        assert_eq!(stays.verdict, Decided::Undecided);
        assert!(
            stays
                .reason
                .starts_with("round-off class undecided: chaotic or event-sensitive"),
            "{}",
            stays.reason
        );
        assert!(round_off_cell(&jump).contains("chaotic (**undecided**: "));
    }
}
