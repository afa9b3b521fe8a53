//! A bar's run file measured against the scene's exact solution: read (JSON or CSV), checked
//! and replayed through the run's own error observers ([`super::super::replay`]); a version 2
//! file's energy norms measure the energy the harness computes from its fields, and a file that
//! declares its scheme and mass is compared sample by sample with the harness's own run of them
//! ([`rerun_declared`]).

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

use super::{Declared, ReportedEnergy, RunRecord, VerifiedFile};
use crate::engine::error::{SolveError, StateField};
use crate::engine::problem::Problem1d;
use crate::harness::external::error::ExternalError;
use crate::harness::external::format::{ExternalRun, SampledField, Version};
use crate::harness::external::load::load;
use crate::harness::external::replay::{replay, EnergySource};
use crate::harness::external::rerun::rerun_declared;
use crate::harness::files::error::Error;
use crate::harness::run::norms::Norm;
use crate::harness::run::Timings;
use crate::harness::study::LevelRecord;

/// A bar scene's exact solution, against which its files are measured in its norms.
pub struct AgainstExact<'a> {
    /// The scene's name, which every file must name.
    pub scene: &'a str,
    /// The bar.
    pub problem: Problem1d,
    /// The scene's norms.
    pub norms: &'a BTreeSet<Norm>,
}

/// What a field of `run` lacks to be given at every sample (`what` names it), if anything.
fn lacking_field(run: &ExternalRun, field: &Option<SampledField>, what: &str) -> Option<String> {
    let samples = run.samples();
    match field {
        None => Some(what.to_string()),
        Some(f) if !f.is_complete() => Some(format!(
            "{what} at every sample ({} of {samples} samples have none)",
            samples - f.sampled()
        )),
        Some(_) => None,
    }
}

/// The data a file lacks for `norm`, if any.
fn missing_data(run: &ExternalRun, norm: Norm) -> Option<String> {
    match norm {
        Norm::DisplacementLinfH
        | Norm::DisplacementL2H
        | Norm::DisplacementLinfV
        | Norm::DisplacementL2V => {
            lacking_field(run, &run.displacement, "displacement fields (u0…uNX)").map(|what| {
                match &run.displacement {
                    Some(_) => {
                        format!("{what}: the errors at the samples that have them are listed")
                    }
                    None => what,
                }
            })
        }
        Norm::MultiplierL2 => match &run.lambda {
            None => Some("contact multiplier (lambda)".to_string()),
            Some(l) if l.iter().all(Option::is_none) => {
                Some("contact multiplier (lambda) at any sample: every one is null".to_string())
            }
            Some(_) => None,
        },
        Norm::EnergyLinf | Norm::EnergyL2 => match run.version {
            Version::One => run.energy.is_none().then(|| "energy".to_string()),
            Version::Two if run.mass.is_none() => Some(
                "declared mass (`mass`: the harness computes the energy from the fields with its \
                 own matrices for it)"
                    .to_string(),
            ),
            Version::Two => {
                let from_fields = "the harness computes the energy from both";
                lacking_field(run, &run.displacement, "displacement fields")
                    .or_else(|| lacking_field(run, &run.velocity, "velocity fields (v0…vNX)"))
                    .map(|what| format!("{what}: {from_fields}"))
            }
        },
    }
}

/// The error whose norm `norm` is (the quantity its observer names when it overflows).
fn error_of(norm: Norm) -> StateField {
    match norm {
        Norm::DisplacementLinfH
        | Norm::DisplacementL2H
        | Norm::DisplacementLinfV
        | Norm::DisplacementL2V => StateField::DisplacementError,
        Norm::MultiplierL2 => StateField::MultiplierError,
        Norm::EnergyLinf | Norm::EnergyL2 => StateField::EnergyError,
    }
}

impl AgainstExact<'_> {
    /// Reads, checks and replays the file `path` for the scene's norms.
    pub fn measure(&self, path: &Path) -> Result<VerifiedFile, ExternalError> {
        let problem = &self.problem;
        let norms = self.norms;
        let run = load(path, self.scene, problem)?;
        let bar = problem.bar(run.nx()).map_err(Error::from)?;
        let model = match run.mass {
            Some(mass) => {
                let (_, model) = problem.model(run.nx(), mass).map_err(|e| {
                    let name = format!("{:?}", mass.name());
                    ExternalError::invalid(path, "mass", None, name, e.to_string())
                })?;
                Some(model)
            }
            None => None,
        };
        let mut lacks: BTreeMap<Norm, String> = norms
            .iter()
            .filter_map(|&n| missing_data(&run, n).map(|what| (n, what)))
            .collect();
        let energy = match (run.version, &model) {
            (Version::One, _) => EnergySource::Reported,
            (Version::Two, Some(model)) if !lacks.contains_key(&Norm::EnergyLinf) => {
                EnergySource::Fields(model)
            }
            (Version::Two, _) => EnergySource::Absent,
        };
        // A diverged run's errors overflow: the norms of that error are not computed, the others
        // are replayed again without them.
        let replayed = loop {
            let allowed: BTreeSet<Norm> = norms
                .iter()
                .copied()
                .filter(|n| !lacks.contains_key(n))
                .collect();
            match replay(&run, &bar, problem.exact.as_ref(), &allowed, energy) {
                Ok(replayed) => break replayed,
                Err(Error::Solve(SolveError::NonFinite { step, quantity, .. }))
                    if allowed.iter().any(|&n| error_of(n) == quantity) =>
                {
                    for n in allowed.into_iter().filter(|&n| error_of(n) == quantity) {
                        lacks.insert(
                            n,
                            format!(
                                "finite {quantity} (it overflows at sample {step}: the run \
                                 diverged)"
                            ),
                        );
                    }
                }
                Err(e) => return Err(e.into()),
            }
        };
        let spacing = run.time.windows(2).map(|w| w[1] - w[0]);
        let dt_min = spacing.clone().fold(f64::INFINITY, f64::min);
        let dt_max = spacing.fold(0.0, f64::max);
        let file = path.display().to_string();
        let reported_energy = run
            .energy_definition
            .zip(replayed.reported_energy_error)
            .map(|(definition, e)| ReportedEnergy {
                file: file.clone(),
                definition,
                linf: e.linf,
                l2: e.l2,
            });
        let overflow = reported_energy
            .as_ref()
            .filter(|e| !e.is_finite())
            .map(|_| {
                format!("{file}: its reported energy overflows (the run diverged): not compared")
            });
        // A trace (no fields) has nothing to compare; its norms' notes say what it lacks.
        let has_fields = lacking_field(&run, &run.displacement, "").is_none();
        let rerun = run
            .scheme
            .zip(model.as_ref())
            .filter(|_| has_fields)
            .map(|(scheme, model)| {
                rerun_declared(&run, scheme, (model, problem.contact), bar.n_dofs())
            });
        let not_rerun = match &rerun {
            Some(Err(why)) => Some(format!(
                "{file}: not compared with the harness's run of its declared scheme and mass: \
                 {why}"
            )),
            _ => None,
        };
        let notes = lambda_note(&run, &file, &lacks)
            .into_iter()
            .chain(overflow)
            .chain(not_rerun)
            .collect();
        Ok(VerifiedFile {
            declared: Declared::of(run.scheme, run.mass, run.contact.as_deref()),
            record: RunRecord {
                file,
                nx: run.nx(),
                samples: run.samples(),
                dt_min,
                dt_max,
                contact_displacement_error: replayed.contact_displacement_error,
                displacement_at_samples: replayed.displacement_at_samples,
                own_mesh: None,
            },
            level: LevelRecord {
                nx: run.nx(),
                h: bar.h(),
                dt: dt_max,
                steps: run.samples() - 1,
                dofs: bar.n_dofs(),
                timings: Timings {
                    observe: replayed.seconds,
                    ..Timings::default()
                },
                multiplier_variation_ratio: replayed.multiplier_variation.and_then(|v| v.ratio()),
            },
            errors: replayed.errors,
            lacks,
            notes,
            reported_energy: reported_energy.filter(ReportedEnergy::is_finite),
            step_differences: rerun.and_then(Result::ok),
            label: run.label,
            code: run.code,
        })
    }
}

/// The note of a file whose `λ` is null at some samples, when its `lambda_L2` is computed: how
/// many samples it leaves out, and that the norm is over the others.
fn lambda_note(run: &ExternalRun, file: &str, lacks: &BTreeMap<Norm, String>) -> Option<String> {
    let lambda = run.lambda.as_ref()?;
    let null = lambda.iter().filter(|l| l.is_none()).count();
    if null == 0 || lacks.contains_key(&Norm::MultiplierL2) {
        return None;
    }
    let times: Vec<String> = (0..run.samples())
        .filter(|&k| lambda[k].is_none())
        .take(3)
        .map(|k| format!("t = {}", run.time[k]))
        .collect();
    let more = if null > times.len() { ", …" } else { "" };
    Some(format!(
        "{file}: λ is null (not computed) at {null} of its {} samples ({}{more}): `{}` and the \
         oscillation ratio are over the other {} samples",
        run.samples(),
        times.join(", "),
        Norm::MultiplierL2.key(),
        run.samples() - null
    ))
}
