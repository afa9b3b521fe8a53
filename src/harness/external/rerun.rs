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
use crate::engine::schemes::{integrator, Conventions, Scheme};

/// The relative tolerance within which a file's sample times must be `t_0 + k Δt` for one `Δt`
/// for the harness to step to them.
const UNIFORM_TIMES: f64 = 1e-9;

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

/// The harness's run of `run`'s declared `scheme` on `model` (the scene's bar with the file's
/// `NX`, its declared mass and the scene's contact treatment `contact`; `dofs` its unknowns, the
/// nodes less a clamped end), compared with the file at every sample; `Err` says why it is not
/// compared (a declared contact treatment other than the scene's, no displacement field at
/// every sample, sample times that are not one time step apart, or a run the harness refuses
/// or that fails). A `contact` text that names no treatment is the code's own words: the
/// scene's treatment is run.
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
    let v = |k| run.row(&run.velocity, k).map(|r| &r[..dofs]);
    if samples < 2 || (0..samples).any(|k| u(k).is_none()) {
        return Err("it has no displacement field at every sample".to_string());
    }
    let (t0, span) = (run.time[0], run.time[samples - 1] - run.time[0]);
    let dt = span / (samples - 1) as f64;
    if (0..samples).any(|k| (run.time[k] - (t0 + k as f64 * dt)).abs() > UNIFORM_TIMES * span) {
        return Err("its samples are not every step of one time step".to_string());
    }
    let u0 = u(0).expect("checked above");
    let zero = vec![0.0; dofs];
    let v0 = v(0).unwrap_or(&zero);
    let (mut harness, mut state) = integrator(model, scheme, dt, u0, v0, &Conventions::HARNESS)
        .map_err(|e| format!("the harness refuses it: {e}"))?;
    let (mut du, mut dv, mut dl) = (Largest::default(), Largest::default(), Largest::default());
    let (mut velocities, mut multipliers) = (0, 0);
    let lambda_time = |k: usize| run.lambda_time.as_ref().map_or(run.time[k], |t| t[k]);
    for k in 0..samples {
        if k > 0 {
            harness
                .advance(&mut state)
                .map_err(|e| format!("the harness's run fails: {e}"))?;
        }
        du.add(u(k).expect("checked above"), state.displacement());
        if let Some(vk) = v(k) {
            dv.add(vk, state.velocity());
            velocities += 1;
        }
        let reported = state.multiplier();
        let same_time = (lambda_time(k) - (t0 + reported.time)).abs() <= UNIFORM_TIMES * span;
        if let (Some(l), Some(&h), true) = (run.lambda_at(k), reported.value.first(), same_time) {
            dl.add(&[l], &[h]);
            multipliers += 1;
        }
    }
    Ok(StepDifferences {
        file: run.path.display().to_string(),
        scheme: scheme.name(),
        samples,
        displacement: du.relative(),
        velocity: (velocities == samples).then(|| dv.relative()),
        multiplier: (multipliers > 0).then(|| dl.relative()),
    })
}
