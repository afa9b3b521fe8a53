//! Verifying another code's runs against a scene: every file read, checked and replayed
//! ([`super::replay`]), the files grouped by label into refinement series, and each series'
//! norms fitted into rates by the harness's own fit (`crate::harness::study::fit_norm_rates`).
//! A norm whose data a series' file lacks is not computed, and says why. A version 2 file's
//! energy norms measure the energy the harness computes from its fields; what a file leaves
//! out (`λ` null at some samples) is said in the series' notes, and a code's own energy is
//! shown beside the norms ([`ReportedEnergy`]).

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use super::error::ExternalError;
use super::format::{Code, EnergyDefinition, ExternalRun, SampledField, Version};
use super::load::load;
use super::replay::{replay, EnergySource, TimeNorms};
use super::rerun::{rerun_declared, StepDifferences};
use crate::engine::error::{SolveError, StateField};
use crate::engine::fem::MassVariant;
use crate::engine::problem::{Problem, Problem1d};
use crate::engine::schemes::Scheme;
use crate::harness::files::error::Error;
use crate::harness::run::nested_comparison::error_series::DisplacementError;
use crate::harness::run::norms::Norm;
use crate::harness::run::Timings;
use crate::harness::study::scene::Scene;
use crate::harness::study::{fit_norm_rates, LevelRecord, NormRates};

/// One file of a series.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RunRecord {
    /// The file, as given on the command line.
    pub file: String,
    /// `NX`.
    pub nx: usize,
    /// The number of time samples `N + 1`.
    pub samples: usize,
    /// The smallest spacing of the sample times.
    pub dt_min: f64,
    /// The largest spacing of the sample times.
    pub dt_max: f64,
    /// `u_h(0, t) − u(0, t)` in `L∞(0, T)` and `L²(0, T)` over the samples, when the file has
    /// the contact node's displacement (not a table norm: not fitted, not gated).
    pub contact_displacement_error: Option<TimeNorms>,
    /// A box run's displacement error in `H` and `V` at each sample that has the field, when
    /// some sample lacks it (its time norms are then not computed).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub displacement_at_samples: Vec<DisplacementError>,
}

/// A code's own energy (version 2) beside the harness's: its distance to the reference's
/// energy (the exact one for a bar, the fine-mesh reference's for a box).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ReportedEnergy {
    /// The file.
    pub file: String,
    /// What the code says its energy is.
    pub definition: EnergyDefinition,
    /// `max_n |E_code(t_n) − E_ref(t_n)|` over the samples that report it (at `energy_time`
    /// when given).
    pub linf: f64,
    /// The trapezoidal `L²(0, T)` norm of that difference over the same times.
    pub l2: f64,
}

impl ReportedEnergy {
    /// Whether both distances are finite: a code's energy that overflows (a diverged run) is
    /// never shown as a number.
    pub fn is_finite(&self) -> bool {
        self.linf.is_finite() && self.l2.is_finite()
    }
}

/// A norm a series does not report, and why.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct NotComputed {
    /// The norm.
    pub norm: Norm,
    /// Why: the file that lacks its data, and which data.
    pub reason: String,
}

/// What a run file declares about how it was computed; each `None` when it does not say.
#[derive(Debug, Clone, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct Declared {
    /// The scheme: a preset name or a parametrised form (`signorini list`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub scheme: Option<String>,
    /// The mass matrix: a mass variant's name.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mass: Option<String>,
    /// How contact is enforced, in the code's words (e.g. `nodal Alart–Curnier, exact`,
    /// `penalty, γ₀ = 100`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub contact: Option<String>,
}

impl Declared {
    /// What a file declares, as its series shows it: the scheme and mass by their names.
    pub fn of(scheme: Option<Scheme>, mass: Option<MassVariant>, contact: Option<&str>) -> Self {
        Self {
            scheme: scheme.map(|s| s.name()),
            mass: mass.map(|m| m.name().to_string()),
            contact: contact.map(str::to_string),
        }
    }

    /// Whether nothing is declared.
    pub fn is_empty(&self) -> bool {
        *self == Self::default()
    }
}

/// One refinement series: the files with one label, by increasing `NX`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Series {
    /// The configuration's label.
    pub label: String,
    /// The code and its version.
    pub code: Code,
    /// What its files declare (the same for every file of the series); left out when nothing.
    #[serde(default, skip_serializing_if = "Declared::is_empty")]
    pub declared: Declared,
    /// One record per file, by increasing `NX`.
    pub runs: Vec<RunRecord>,
    /// One level per file (`dt` the largest spacing of its sample times, `steps` its samples
    /// less one, `dofs` its nodes less a clamped end, `timings.observe` the replay's seconds).
    pub levels: Vec<LevelRecord>,
    /// The errors and rates of each computed norm, in the order of [`Norm::ALL`].
    pub rates: Vec<NormRates>,
    /// The scene's norms that are not computed, with the reason.
    pub not_computed: Vec<NotComputed>,
    /// What the norms of the series' files leave out, file by file (the samples whose `λ` is
    /// null).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub notes: Vec<String>,
    /// The codes' own energies beside the energy norms, file by file (version 2).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub reported_energy: Vec<ReportedEnergy>,
    /// The harness's own run of each file's declared scheme and mass, compared with it sample
    /// by sample ([`rerun_declared`]; version 2 bar files that declare both).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub step_differences: Vec<StepDifferences>,
}

impl Series {
    /// The oscillation indicator `TV(λ_h) / TV(λ)` on the finest level, when `lambda_L2` was
    /// computed.
    pub fn oscillation_indicator(&self) -> Option<f64> {
        self.levels.last()?.multiplier_variation_ratio
    }

    /// The rates of `norm`, if it was computed.
    pub fn norm(&self, norm: Norm) -> Option<&NormRates> {
        self.rates.iter().find(|r| r.norm == norm)
    }

    /// Why `norm` was not computed, if it was not.
    pub fn not_computed(&self, norm: Norm) -> Option<&str> {
        self.not_computed
            .iter()
            .find(|n| n.norm == norm)
            .map(|n| n.reason.as_str())
    }
}

/// The verification of another code's runs (`verify.json`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Verification {
    /// The crate version that verified.
    pub signorini_version: String,
    /// The scene's name.
    pub scene: String,
    /// The exact solution the errors are measured against.
    pub reference: String,
    /// The scene's horizon `T`.
    pub horizon: f64,
    /// The scene's norms: each series computes those its files have the data of.
    pub norms: Vec<Norm>,
    /// One series per label, in the order the labels first appear among the files.
    pub series: Vec<Series>,
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

/// What a bar's file adds to its series beyond its norms.
struct FileNotes {
    /// The file, as its record names it.
    file: String,
    /// What its norms leave out.
    notes: Vec<String>,
    /// Its own energy beside the norms.
    reported_energy: Option<ReportedEnergy>,
    /// The harness's run of what it declares, compared with it.
    step_differences: Option<StepDifferences>,
}

/// One file's results, before the files are grouped into series.
pub struct VerifiedFile {
    /// Its configuration's label.
    pub label: String,
    /// The code that wrote it.
    pub code: Code,
    /// What it declares about how it was computed.
    pub declared: Declared,
    /// What the series lists of it.
    pub record: RunRecord,
    /// Its level, as a study's.
    pub level: LevelRecord,
    /// The norms computed.
    pub errors: BTreeMap<Norm, f64>,
    /// The norms not computed, each with the data the file lacks for it.
    pub lacks: BTreeMap<Norm, String>,
}

/// Reads, checks and replays one file against `problem` for the norms `norms`.
fn verify_file(
    path: &Path,
    scene: &str,
    problem: &Problem1d,
    norms: &BTreeSet<Norm>,
) -> Result<(VerifiedFile, FileNotes), ExternalError> {
    let run = load(path, scene, problem)?;
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
                            "finite {quantity} (it overflows at sample {step}: the run diverged)"
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
        .map(|_| format!("{file}: its reported energy overflows (the run diverged): not compared"));
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
            "{file}: not compared with the harness's run of its declared scheme and mass: {why}"
        )),
        _ => None,
    };
    let notes = FileNotes {
        file: file.clone(),
        notes: lambda_note(&run, &file, &lacks)
            .into_iter()
            .chain(overflow)
            .chain(not_rerun)
            .collect(),
        reported_energy: reported_energy.filter(ReportedEnergy::is_finite),
        step_differences: rerun.and_then(Result::ok),
    };
    let verified = VerifiedFile {
        declared: Declared::of(run.scheme, run.mass, run.contact.as_deref()),
        record: RunRecord {
            file,
            nx: run.nx(),
            samples: run.samples(),
            dt_min,
            dt_max,
            contact_displacement_error: replayed.contact_displacement_error,
            displacement_at_samples: replayed.displacement_at_samples,
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
        label: run.label,
        code: run.code,
    };
    Ok((verified, notes))
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

/// Verifies the run files `files` against `scene`: each is read, checked against the scene and
/// replayed for the scene's norms, one at a time (a file's samples are dropped once its norms
/// are computed); then the files are grouped by label into series, each checked to come from
/// one code and version with one file per `NX`, and fitted.
pub fn verify(scene: &Scene, files: &[PathBuf]) -> Result<Verification, ExternalError> {
    let Problem::Bar(problem) = scene.problem() else {
        return Err(ExternalError::NoExactReference {
            scene: scene.name.clone(),
        });
    };
    let norms = &scene.observables.norms;
    let (verified, notes): (Vec<_>, Vec<_>) = files
        .iter()
        .map(|path| verify_file(path, &scene.name, &problem, norms))
        .collect::<Result<Vec<_>, _>>()?
        .into_iter()
        .unzip();
    let mut series = into_series(verified, norms)?;
    for s in &mut series {
        for run in &s.runs {
            if let Some(n) = notes.iter().find(|n| n.file == run.file) {
                s.notes.extend(n.notes.iter().cloned());
                s.reported_energy.extend(n.reported_energy.clone());
                s.step_differences.extend(n.step_differences.clone());
            }
        }
    }
    Ok(Verification {
        signorini_version: env!("CARGO_PKG_VERSION").to_string(),
        scene: scene.name.clone(),
        reference: problem.exact.name().to_string(),
        horizon: problem.horizon,
        norms: norms.iter().copied().collect(),
        series,
    })
}

/// The files `verified` grouped by label into series, in the order the labels first appear,
/// each checked and fitted ([`series`]).
pub fn into_series(
    verified: Vec<VerifiedFile>,
    norms: &BTreeSet<Norm>,
) -> Result<Vec<Series>, ExternalError> {
    let mut groups: Vec<Vec<VerifiedFile>> = Vec::new();
    for file in verified {
        match groups.iter_mut().find(|g| g[0].label == file.label) {
            Some(group) => group.push(file),
            None => groups.push(vec![file]),
        }
    }
    groups
        .into_iter()
        .map(|group| series(group, norms))
        .collect()
}

/// The series of the files `group` (one label): one code and version, one file per `NX`, the
/// norms every file has the data of fitted, the others not computed.
fn series(mut group: Vec<VerifiedFile>, norms: &BTreeSet<Norm>) -> Result<Series, ExternalError> {
    let label = group[0].label.clone();
    let series_error = |problem: String| ExternalError::Series {
        label: label.clone(),
        problem,
    };
    if let Some(other) = group.iter().find(|l| l.declared != group[0].declared) {
        return Err(series_error(format!(
            "{} declares {:?} but {} declares {:?}: the files of one label must declare one \
             scheme, mass and contact treatment",
            group[0].record.file, group[0].declared, other.record.file, other.declared
        )));
    }
    if let Some(other) = group.iter().find(|l| l.code != group[0].code) {
        return Err(series_error(format!(
            "{} is from {} {} but {} from {} {}: the files of one label must come from one \
             code and version",
            group[0].record.file,
            group[0].code.name,
            group[0].code.version,
            other.record.file,
            other.code.name,
            other.code.version
        )));
    }
    group.sort_by_key(|l| l.level.nx);
    if let Some(w) = group.windows(2).find(|w| w[0].level.nx == w[1].level.nx) {
        return Err(series_error(format!(
            "{} and {} are both at NX = {}: one file per level",
            w[0].record.file, w[1].record.file, w[0].level.nx
        )));
    }
    let mut errors = BTreeMap::new();
    let mut not_computed = Vec::new();
    for &norm in norms {
        match group
            .iter()
            .find_map(|l| l.lacks.get(&norm).map(|what| (&l.record.file, what)))
        {
            Some((file, what)) => not_computed.push(NotComputed {
                norm,
                reason: format!("the file {file} has no {what}"),
            }),
            None => {
                errors.insert(norm, group.iter().map(|l| l.errors[&norm]).collect());
            }
        }
    }
    let levels: Vec<LevelRecord> = group.iter().map(|l| l.level.clone()).collect();
    Ok(Series {
        code: group[0].code.clone(),
        declared: group[0].declared.clone(),
        rates: fit_norm_rates(&levels, errors),
        runs: group.into_iter().map(|l| l.record).collect(),
        levels,
        not_computed,
        notes: Vec::new(),
        reported_energy: Vec::new(),
        step_differences: Vec::new(),
        label,
    })
}
