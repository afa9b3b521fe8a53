//! The harness's own run of what a bar's file declares, compared with the file sample by
//! sample: the declared `scheme` with the declared `mass` (and the scene's contact treatment)
//! on the scene's bar with the file's `NX`, from the file's first sample `(U⁰, V⁰)`, at the
//! file's time step. Where the other code solves the same discrete problem the differences are
//! round-off (Siconos's Moreau–Jean, `make verify-siconos`); where they are not, they measure
//! how far its discrete problem is from the harness's, which the norms alone cannot tell apart
//! from a discretisation error.

use serde::{Deserialize, Serialize};

use super::format::ExternalRun;
use crate::engine::contact::ContactTreatment;
use crate::engine::model::Model;
use crate::engine::schemes::{integrator, Conventions, Scheme, SchemeState, Timed};

/// The relative tolerance within which a file's sample times must be `t_0 + k Δt` for one `Δt`
/// for the harness to step to them.
const UNIFORM_TIMES: f64 = 1e-9;

/// The largest relative difference between a file and the harness's run of its declared scheme
/// and mass that round-off explains when the file's numbers are doubles: two double-precision
/// solves of one discrete problem part by less (measured: DOLFINx's and Siconos's runs, 2e-13 at
/// most; GetFEM's shared 2D runs 3.5e-11 of the harness's study).
pub const RERUN_ROUNDOFF: f64 = 1e-10;

/// How many machine epsilons of its numbers' type a file may be from the harness's run when
/// that is more than [`RERUN_ROUNDOFF`]: a file rounds each value to its type (single precision:
/// GetFEM's `Float32` files, 3.8e-8 = 0.3 ε measured) or to fewer digits than its type holds
/// (GetFEM's ASCII, 6 significant digits: 3.3e-6 = 28 ε).
pub const RERUN_ROUNDINGS: f64 = 1e3;

/// The round-off bound of a file whose numbers have the machine epsilon `value_epsilon`:
/// [`RERUN_ROUNDOFF`], or [`RERUN_ROUNDINGS`] × `value_epsilon` when larger.
pub fn rerun_tolerance(value_epsilon: f64) -> f64 {
    RERUN_ROUNDOFF.max(RERUN_ROUNDINGS * value_epsilon)
}

/// The bound of a `verify.json` written before the bound was recorded: its files were doubles.
fn double_precision_tolerance() -> f64 {
    rerun_tolerance(f64::EPSILON)
}

/// The largest differences between a file and the harness's run of its declared scheme and mass,
/// each relative to the largest value of the harness's run (`verify.json`, `step_differences`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct StepDifferences {
    /// The file, as its record names it.
    pub file: String,
    /// The scheme the harness ran (the file's `scheme`).
    pub scheme: String,
    /// The samples compared (every sample; the multiplier at those with `λ`).
    pub samples: usize,
    /// `max_n max_i |U_file − U_h| / max_n max_i |U_h|`.
    pub displacement: f64,
    /// The same of the velocities (`None` when the file has none at every sample).
    pub velocity: Option<f64>,
    /// The same of the multipliers, over the samples where the file has `λ` at the time the
    /// harness reports its own (`None` at none).
    pub multiplier: Option<f64>,
    /// The largest difference round-off explains for this file ([`rerun_tolerance`] of the
    /// precision of its numbers).
    #[serde(default = "double_precision_tolerance")]
    pub tolerance: f64,
}

impl StepDifferences {
    /// Whether the file and the harness's run part by more than round-off (a difference that is
    /// not a number counts): the file does not solve the discrete problem of the scheme and mass
    /// it declares.
    pub fn differs(&self) -> bool {
        [Some(self.displacement), self.velocity, self.multiplier]
            .into_iter()
            .flatten()
            .any(|x| !(x <= self.tolerance))
    }

    /// The largest of the differences.
    pub fn largest(&self) -> f64 {
        [Some(self.displacement), self.velocity, self.multiplier]
            .into_iter()
            .flatten()
            .fold(0.0, f64::max)
    }
}

/// The largest `|a − b|` and `|b|` seen, for a relative difference.
#[derive(Debug, Default, Clone, Copy)]
struct Largest {
    difference: f64,
    value: f64,
}

impl Largest {
    fn add(&mut self, file: &[f64], harness: &[f64]) {
        for (a, b) in file.iter().zip(harness) {
            self.difference = self.difference.max((a - b).abs());
            self.value = self.value.max(b.abs());
        }
    }

    /// The largest difference over the largest value (the difference itself when every value
    /// is 0).
    fn relative(self) -> f64 {
        if self.value > 0.0 {
            self.difference / self.value
        } else {
            self.difference
        }
    }
}

/// One sample of a file as a rerun compares it: its displacement and (when the file has it) its
/// velocity on the model's unknowns, and (when it has them) its multipliers with the time they
/// approximate, from the file's first sample.
pub struct FileSample {
    /// `U` on the model's unknowns.
    pub displacement: Vec<f64>,
    /// `V` on the model's unknowns.
    pub velocity: Option<Vec<f64>>,
    /// `λ`, as many as the file gives (the first of the harness's are compared with them).
    pub multipliers: Option<Timed<Vec<f64>>>,
}

/// The harness's run of `scheme` with `conventions` on `model`, from the file's first sample,
/// stepped by the file's time step to each of its `times` (one step apart), compared with the
/// file's samples (`sample(k)`, `Err` saying why one cannot be compared): the largest
/// differences of `file` ([`StepDifferences`]), whose numbers have the machine epsilon
/// `value_epsilon`.
pub fn compare_with_harness(
    (file, value_epsilon): (&str, f64),
    (model, scheme, conventions): (&Model, Scheme, &Conventions),
    times: &[f64],
    sample: &mut dyn FnMut(usize) -> Result<FileSample, String>,
) -> Result<StepDifferences, String> {
    let samples = times.len();
    if samples < 2 {
        return Err("it has fewer than two samples".to_string());
    }
    let (t0, span) = (times[0], times[samples - 1] - times[0]);
    let dt = span / (samples - 1) as f64;
    if (0..samples).any(|k| (times[k] - (t0 + k as f64 * dt)).abs() > UNIFORM_TIMES * span) {
        return Err("its samples are not every step of one time step".to_string());
    }
    let first = sample(0)?;
    let zero = vec![0.0; first.displacement.len()];
    let v0 = first.velocity.as_deref().unwrap_or(&zero);
    let (mut harness, mut state) =
        integrator(model, scheme, dt, &first.displacement, v0, conventions)
            .map_err(|e| format!("the harness refuses it: {e}"))?;
    let mut seen = Seen::default();
    seen.add(&first, &state, (t0, span));
    for k in 1..samples {
        harness
            .advance(&mut state)
            .map_err(|e| format!("the harness's run fails: {e}"))?;
        seen.add(&sample(k)?, &state, (t0, span));
    }
    Ok(StepDifferences {
        file: file.to_string(),
        scheme: scheme.name(),
        samples,
        displacement: seen.displacement.relative(),
        velocity: (seen.velocities == samples).then(|| seen.velocity.relative()),
        multiplier: (seen.multipliers > 0).then(|| seen.multiplier.relative()),
        tolerance: rerun_tolerance(value_epsilon),
    })
}

/// The largest differences seen so far, and how many samples had a velocity and multipliers
/// to compare.
#[derive(Default)]
struct Seen {
    displacement: Largest,
    velocity: Largest,
    multiplier: Largest,
    velocities: usize,
    multipliers: usize,
}

impl Seen {
    /// Adds the file's sample `s` against the harness's `state`, the file's samples starting at
    /// `t0` and spanning `span`: its multipliers where they approximate the harness's time.
    fn add(&mut self, s: &FileSample, state: &SchemeState, (t0, span): (f64, f64)) {
        self.displacement.add(&s.displacement, state.displacement());
        if let Some(v) = &s.velocity {
            self.velocity.add(v, state.velocity());
            self.velocities += 1;
        }
        let reported = state.multiplier();
        if let Some(l) = &s.multipliers {
            let same_time = (l.time - (t0 + reported.time)).abs() <= UNIFORM_TIMES * span;
            if same_time && reported.value.len() >= l.value.len() {
                self.multiplier
                    .add(&l.value, &reported.value[..l.value.len()]);
                self.multipliers += 1;
            }
        }
    }
}

/// The harness's run of `run`'s declared `scheme` on `model` (the scene's bar with the file's
/// `NX`, its declared mass and the scene's contact treatment `contact`; `dofs` its unknowns, the
/// nodes less a clamped end), compared with the file at every sample
/// ([`compare_with_harness`]); `Err` says why it is not compared (a declared contact treatment
/// other than the scene's, no displacement field at every sample, sample times that are not one
/// time step apart, or a run the harness refuses or that fails). A `contact` text that names no
/// treatment is the code's own words: the scene's treatment is run.
pub fn rerun_declared(
    run: &ExternalRun,
    scheme: Scheme,
    (model, contact): (&Model, ContactTreatment),
    dofs: usize,
) -> Result<StepDifferences, String> {
    let declared = run
        .contact
        .as_deref()
        .and_then(|c| c.parse::<ContactTreatment>().ok());
    if let Some(other) = declared.filter(|&c| c != contact) {
        return Err(format!(
            "it declares the contact treatment {other}, the scene's is {contact}"
        ));
    }
    let samples = run.samples();
    let u = |k| run.row(&run.displacement, k).map(|r| &r[..dofs]);
    if samples < 2 || (0..samples).any(|k| u(k).is_none()) {
        return Err("it has no displacement field at every sample".to_string());
    }
    let lambda_time = |k: usize| run.lambda_time.as_ref().map_or(run.time[k], |t| t[k]);
    compare_with_harness(
        (&run.path.display().to_string(), f64::EPSILON),
        (model, scheme, &Conventions::HARNESS),
        &run.time,
        &mut |k| {
            Ok(FileSample {
                displacement: u(k).expect("checked above").to_vec(),
                velocity: run.row(&run.velocity, k).map(|r| r[..dofs].to_vec()),
                multipliers: run.lambda_at(k).map(|l| Timed {
                    time: lambda_time(k),
                    value: vec![l],
                }),
            })
        },
    )
}
