//! Verifying another code's runs against a scene: every file read, checked and measured against
//! the reference the scene declares ([`DeclaredReference`]: a bar's exact solution, [`exact`]; a
//! box's fine-mesh reference, [`fine_mesh`]), the files grouped by label into refinement series,
//! and each series' norms fitted into rates by the harness's own fit
//! (`crate::harness::study::fit_norm_rates`). A norm whose data a series' file lacks is not
//! computed, and says why. What a file leaves out (`λ` null at some samples) is said in the
//! series' notes, and a code's own energy is shown beside the norms ([`ReportedEnergy`]). What
//! comes back is measured ([`Measured`]); a report judges it.

pub mod exact;
pub mod fine_mesh;
pub mod own_mesh;

use std::collections::{BTreeMap, BTreeSet};
use std::path::PathBuf;

use serde::{Deserialize, Serialize};

use super::box_run::SeriesOptions;
use super::error::ExternalError;
use super::format::{Code, EnergyDefinition};
use super::replay::TimeNorms;
use super::rerun::StepDifferences;
use crate::engine::fem::MassVariant;
use crate::engine::schemes::Scheme;
use crate::harness::reference::declared::DeclaredReference;
use crate::harness::reference::fine_mesh::rate_bias_bound;
use crate::harness::run::nested_comparison::error_series::DisplacementError;
use crate::harness::run::norms::Norm;
use crate::harness::study::scene::Scene;
use crate::harness::study::{
    fit_norm_rates, rates_inconsistency, Case, CaseStudy, LevelRecord, NormRates,
};
use exact::AgainstExact;
use fine_mesh::{AgainstFineMesh, ReferenceSource};

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
    /// A box run on its own mesh: its cells, `h`, `Δt`, what it is measured against and the
    /// bound of each error ([`own_mesh`]); absent on the scene's mesh.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub own_mesh: Option<own_mesh::OwnMeshRecord>,
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

    /// The coarsest of its files compared with the harness's run of the declared scheme and
    /// mass, when they part by more than round-off ([`StepDifferences::differs`]): the series
    /// does not solve the discrete problem it declares, and is not judged as that case. Only the
    /// coarsest decides (a box series' only comparison): on the finer levels of a round-off
    /// chaotic case two correct codes part by more.
    pub fn differs_from_declared(&self) -> Option<&StepDifferences> {
        self.step_differences.first().filter(|d| d.differs())
    }

    /// What a series read back from a file must satisfy ([`rates_inconsistency`] of its
    /// levels and rates): a file edited after `verify` (a rate typed in, an error made
    /// negative) fails it.
    pub fn inconsistency(&self) -> Option<(String, String, String)> {
        rates_inconsistency(&self.levels, &self.rates)
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

/// The verification of another code's runs (`verify.json`), with what a report judged on it
/// (`J`; [`Unjudged`] as the harness measures it).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Verification<J = Unjudged> {
    /// The crate version that verified.
    pub signorini_version: String,
    /// The scene's name.
    pub scene: String,
    /// The reference the errors are measured against: the exact solution's name, or the
    /// fine-mesh reference's description.
    pub reference: String,
    /// The scene's horizon `T`.
    pub horizon: f64,
    /// The scene's norms: each series computes those its files have the data of.
    pub norms: Vec<Norm>,
    /// One series per label, in the order the labels first appear among the files.
    pub series: Vec<Series>,
    /// A fine-mesh reference's rate-bias bound per norm key, the largest over the cases the
    /// series declare ([`declared_cases`]; `None`: no bound can be formed); absent against an
    /// exact solution, whose rates carry no bias.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rate_bias: Option<BTreeMap<String, Option<f64>>>,
    /// What a report judged on the series.
    #[serde(flatten)]
    pub judgement: J,
    /// The codes' own energies file by file, when the series do not list them (against a
    /// fine-mesh reference).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub reported_energy: Vec<ReportedEnergy>,
}

/// A verification no report has judged: nothing is added to verify.json.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct Unjudged;

impl Verification {
    /// The verification with `judgement` added.
    pub fn judged<J>(self, judgement: J) -> Verification<J> {
        Verification {
            signorini_version: self.signorini_version,
            scene: self.scene,
            reference: self.reference,
            horizon: self.horizon,
            norms: self.norms,
            series: self.series,
            rate_bias: self.rate_bias,
            judgement,
            reported_energy: self.reported_energy,
        }
    }
}

/// A verification as measured, before a report judges it.
pub struct Measured {
    /// What verify.json records.
    pub verification: Verification,
    /// A fine-mesh reference's check distance per norm key, which bounds a case's rate bias
    /// ([`Measured::rate_bias`]); `None` against an exact solution.
    pub reference_distance: Option<BTreeMap<String, f64>>,
}

impl Measured {
    /// The rate-bias bound a fine-mesh reference puts on a case's rate of a norm
    /// ([`rate_bias_bound`]), each error off by at most the reference's check distance plus,
    /// for a series on its own mesh, the largest bound its runs state
    /// ([`own_mesh::OwnMeshRecord::bound`]); `None` against an exact solution, whose rates carry
    /// no bias.
    pub fn rate_bias(&self) -> Option<impl Fn(&CaseStudy, Norm) -> Option<f64> + '_> {
        let distance = self.reference_distance.as_ref()?;
        let series = &self.verification.series;
        Some(move |case: &CaseStudy, n: Norm| {
            let own = declared_series(series)
                .find(|(_, c)| *c == case.case)
                .map_or(0.0, |(s, _)| own_mesh_bound(s, n));
            rate_bias_bound(case, n, distance[n.key()] + own)
        })
    }
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
    /// What its norms leave out.
    pub notes: Vec<String>,
    /// Its own energy beside the norms.
    pub reported_energy: Option<ReportedEnergy>,
    /// The harness's run of what it declares, compared with it.
    pub step_differences: Option<StepDifferences>,
}

/// What the files of a scene are measured against: its exact solution, or its fine-mesh
/// reference obtained once.
#[allow(clippy::large_enum_variant)] // one per verification, never moved
enum Against<'a> {
    /// A bar's exact solution; each file is read when it is measured.
    Exact(AgainstExact<'a>, &'a [PathBuf]),
    /// A box's fine-mesh reference, its files read before it was obtained.
    FineMesh(AgainstFineMesh),
}

/// What a verification reads beside the run files: what a `.pvd` does not say, and where a box
/// scene's reference comes from.
pub struct VerifySources<'a> {
    /// The `.pvd` files' code, label, scheme, mass and arrays.
    pub pvd: &'a SeriesOptions,
    /// The fine-mesh reference's cache and the limits of computing one.
    pub reference: ReferenceSource<'a>,
}

/// Reads the `k`-th run file and measures it against the scene's reference: a bar's file replayed
/// through the error observers against the exact solution, a box's compared at every step with
/// the fine-mesh reference's projection on its level.
fn verify_file(against: &Against<'_>, k: usize) -> Result<VerifiedFile, ExternalError> {
    match against {
        Against::Exact(exact, files) => exact.measure(&files[k]),
        Against::FineMesh(fine) => fine.measure(k),
    }
}

/// Verifies the run files `files` against `scene`, measured against the reference it declares
/// (a box's read from `sources`' cache when its key matches, computed otherwise; `note` hears
/// why a cache was not used). A bar's files are read and measured one at a time (a file's
/// samples are dropped once its norms are computed); a box's are all read and checked before
/// its reference is obtained. Then the files are grouped by label into series, each checked to
/// come from one code and version with one file per `NX`, and fitted.
pub fn verify(
    scene: &Scene,
    files: &[PathBuf],
    sources: &VerifySources<'_>,
    note: &mut dyn FnMut(String),
) -> Result<Measured, ExternalError> {
    let all_norms: BTreeSet<Norm> = Norm::ALL.into_iter().collect();
    let against = match DeclaredReference::of(scene)? {
        DeclaredReference::Exact(problem) => Against::Exact(
            AgainstExact {
                scene: &scene.name,
                problem,
                norms: &scene.observables.norms,
            },
            files,
        ),
        DeclaredReference::FineMesh(declared) => Against::FineMesh(AgainstFineMesh::obtain(
            &scene.name,
            declared,
            files,
            sources.pvd,
            &sources.reference,
            note,
        )?),
    };
    let mut verified = (0..files.len())
        .map(|k| verify_file(&against, k))
        .collect::<Result<Vec<_>, _>>()?;
    let (reference, horizon, norms, reference_distance) = match &against {
        Against::Exact(exact, _) => (
            exact.problem.exact.name().to_string(),
            exact.problem.horizon,
            exact.norms,
            None,
        ),
        Against::FineMesh(fine) => (
            fine.description(),
            fine.horizon(),
            &all_norms,
            Some(fine.distance().clone()),
        ),
    };
    // Against a fine-mesh reference, the codes' own energies follow the series, file by file.
    let reported_energy = match reference_distance {
        None => Vec::new(),
        Some(_) => verified
            .iter_mut()
            .filter_map(|f| f.reported_energy.take())
            .collect(),
    };
    let series = into_series(verified, norms)?;
    let mut measured = Measured {
        verification: Verification {
            signorini_version: env!("CARGO_PKG_VERSION").to_string(),
            scene: scene.name.clone(),
            reference,
            horizon,
            norms: norms.iter().copied().collect(),
            series,
            rate_bias: None,
            judgement: Unjudged,
            reported_energy,
        },
        reference_distance,
    };
    let rate_bias = measured.rate_bias().map(|bias| {
        let mut worst = BTreeMap::new();
        for case in &declared_cases(&measured.verification.series) {
            for n in Norm::ALL {
                let bound: &mut Option<f64> = worst.entry(n.key().to_string()).or_insert(Some(0.0));
                *bound = bound.zip(bias(case, n)).map(|(a, b)| a.max(b));
            }
        }
        worst
    });
    measured.verification.rate_bias = rate_bias;
    Ok(measured)
}

/// The cases of the series that declare a scheme and a mass the harness names (the first
/// series of each case), with their levels and rates: what the note's findings are judged on. A
/// series whose files part from the harness's run of what they declare
/// ([`Series::differs_from_declared`]) is left out: it is not that case.
pub fn declared_cases(series: &[Series]) -> Vec<CaseStudy> {
    declared_series(series)
        .map(|(s, case)| CaseStudy {
            case,
            levels: s.levels.clone(),
            rates: s.rates.clone(),
        })
        .collect()
}

/// The first series of each case the series `series` declare (a scheme and a mass the harness
/// names), with its case, leaving out those that part from the harness's run of what they
/// declare: [`declared_cases`]'s series.
pub fn declared_series(series: &[Series]) -> impl Iterator<Item = (&Series, Case)> {
    let mut seen: Vec<Case> = Vec::new();
    series
        .iter()
        .filter(|s| s.differs_from_declared().is_none())
        .filter_map(move |s| {
            let scheme = s.declared.scheme.as_deref()?.parse::<Scheme>().ok()?;
            let mass = s.declared.mass.as_deref()?.parse::<MassVariant>().ok()?;
            let case = Case { scheme, mass };
            (!seen.contains(&case)).then(|| {
                seen.push(case);
                (s, case)
            })
        })
}

/// The largest bound the runs of `s` on their own mesh state for `norm`'s errors (0 on the
/// scene's mesh, or for a norm without one).
pub fn own_mesh_bound(s: &Series, norm: Norm) -> f64 {
    s.runs
        .iter()
        .filter_map(|r| r.own_mesh.as_ref()?.bound.get(norm.key()).copied())
        .fold(0.0, f64::max)
}

/// The files `verified` grouped by label into series, in the order the labels first appear,
/// each checked and fitted ([`series`]).
fn into_series(
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
    let notes = group.iter().flat_map(|l| l.notes.iter().cloned()).collect();
    let reported_energy = group
        .iter()
        .filter_map(|l| l.reported_energy.clone())
        .collect();
    let step_differences = group
        .iter()
        .filter_map(|l| l.step_differences.clone())
        .collect();
    Ok(Series {
        code: group[0].code.clone(),
        declared: group[0].declared.clone(),
        rates: fit_norm_rates(&levels, errors),
        runs: group.into_iter().map(|l| l.record).collect(),
        levels,
        not_computed,
        notes,
        reported_energy,
        step_differences,
        label,
    })
}
