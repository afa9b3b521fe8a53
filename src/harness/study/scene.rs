//! Scene files: a problem described once, in JSON, and parsed at load into a typed [`Scene`]:
//! the [`Problem`] (a bar or a box, with its contact treatment and reference), the study
//! parameters (with their schemes) and the observables (with their norms). Names are parsed
//! once, here; nothing downstream parses them again. Only what a scene declares is simulated:
//! no obstacle, no contact solve; no body force, no load vector; no norm asked for, no
//! quadrature.
//!
//! Every error names the file and the field, and says what is allowed.

use std::collections::BTreeSet;
use std::fmt;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use serde::Deserialize;

use crate::engine::contact::{ContactTreatment, TREATMENT_NAMES};
use crate::engine::error::{compact, ParameterError};
use crate::engine::exact::{
    AtRest, BouncingBar, ClampedFreeMode, ExactSolution, Pointwise, SignoriniDirichlet,
};
use crate::engine::fem::box_mesh::Elasticity;
use crate::engine::fem::EndCondition;
use crate::engine::problem::{BoxProblem, InitialData, Problem, Problem1d, Profile, Settings};
use crate::engine::schemes::{Conventions, Scheme, SCHEME_NAMES};
use crate::harness::run::norms::Norm;
use crate::harness::run::Observables;
use crate::harness::study::sensitivity::EnsembleConfig;
use crate::harness::study::StudyConfig;

use crate::harness::files::error::printable;
use crate::harness::files::input::{self, SCENE_FILE};
pub use crate::harness::study::scene_error::SceneError;

/// A scene: the problem, the study parameters and the observables a scene file declares,
/// checked and typed when the file is read ([`Scene::load`]).
#[derive(Debug, Clone)]
pub struct Scene {
    /// Short name.
    pub name: String,
    /// One sentence for `signorini list`.
    pub description: String,
    /// The problem: the bar or box, material, boundary, obstacle, load, initial data, horizon,
    /// contact treatment and (for a bar) its exact solution.
    problem: Problem,
    /// How its runs are solved: the scene's conventions, the default step solver and contact
    /// operator, no round-off perturbation.
    settings: Settings,
    /// Levels, `Δx/Δt` and schemes of studies.
    pub discretisation: Discretisation,
    /// What runs record.
    pub observables: SceneObservables,
}

/// Refinement levels, the time step and the schemes a study runs by default.
#[derive(Debug, Clone, PartialEq)]
pub struct Discretisation {
    /// `NX` of each level of a study, increasing (elements along the axis for a box).
    pub levels: Vec<usize>,
    /// `Δx / Δt`.
    pub ratio: f64,
    /// The schemes a study runs when none is given (`None`: the paper's seven).
    pub schemes: Option<Vec<Scheme>>,
    /// Elements along the axis of the fine-mesh reference of a box study; `None` for a bar.
    pub reference_level: Option<usize>,
    /// The round-off ensemble a box study also runs; `None` for a bar.
    pub sensitivity: Option<EnsembleConfig>,
}

/// What the runs of a scene record.
#[derive(Debug, Clone, PartialEq)]
pub struct SceneObservables {
    /// Error norms (none for a box: it has no exact solution).
    pub norms: BTreeSet<Norm>,
    /// Record the energy history of a run.
    pub energy_history: bool,
    /// Record the contact node's displacement and multiplier of a run.
    pub contact_history: bool,
    /// Positions `x` whose displacement history a run records (with the exact one).
    pub points: Vec<f64>,
    /// Times at which a run records the whole field.
    pub fields_at: Vec<f64>,
}

/// The largest scene file read: 16 MiB (the committed scenes are under 2 kB; 10⁵ field times
/// are under 1 MB).
pub const MAX_SCENE_BYTES: u64 = SCENE_FILE.max_bytes;

/// The largest magnitude of any number of a scene, and the smallest of a positive one (a
/// length, density, wave speed, `μ`, horizon, ratio): within `[1e-50, 1e50]`, products of a few
/// of them (an energy, a squared error integrated over the horizon) stay finite in `f64`.
pub const MAX_MAGNITUDE: f64 = 1e50;

/// The names of the exact solutions a scene can refer to.
pub const EXACT_SOLUTIONS: &str = "signorini-dirichlet, clamped-free-mode, at-rest, bouncing-bar";

/// The intervals of `[0, L]` whose end points check the initial data against a closed-form
/// reference.
const INITIAL_DATA_SAMPLES: usize = 256;

impl Scene {
    /// Reads and validates a scene file: a regular file (not a device or a FIFO, which could
    /// be endless or block) of at most [`MAX_SCENE_BYTES`], read by [`input::read_text`].
    pub fn load(path: &Path) -> Result<Self, SceneError> {
        let text = input::read_text(path, SCENE_FILE).map_err(SceneError::Input)?;
        Self::parse(&text, path)
    }

    /// The bar1d scene at `path` and its bar; a box scene is refused, naming the file and its
    /// `geometry.kind`, with `why` (what only a bar is for) as what is allowed.
    pub fn load_bar(path: &Path, why: &str) -> Result<(Self, Problem1d), SceneError> {
        let scene = Self::load(path)?;
        match scene.problem() {
            Problem::Bar(problem) => Ok((scene, problem)),
            Problem::Box(_) => Err(SceneError::Invalid {
                path: path.to_path_buf(),
                field: "geometry.kind".to_string(),
                value: "box".to_string(),
                allowed: format!("bar1d ({why})"),
            }),
        }
    }

    /// Parses and validates scene text; `path` is used in messages. A leading UTF-8 byte
    /// order mark is skipped.
    pub fn parse(text: &str, path: &Path) -> Result<Self, SceneError> {
        let text = text.strip_prefix('\u{feff}').unwrap_or(text);
        let file: SceneFile = serde_json::from_str(text).map_err(|e| SceneError::Json {
            path: path.to_path_buf(),
            line: e.line(),
            column: e.column(),
            message: e.to_string(),
        })?;
        file.into_scene(path)
    }

    /// The problem the scene declares: a [`Problem::Bar`] for a bar1d scene, a
    /// [`Problem::Box`] for a 2D/3D box scene.
    pub fn problem(&self) -> Problem {
        self.problem.clone()
    }

    /// The settings the scene's runs are solved with ([`Settings::default`] with the scene's
    /// `conventions` and `start`).
    pub fn settings(&self) -> Settings {
        self.settings
    }

    /// The bar a bar1d scene declares; a box scene is refused naming the scene, with `why`
    /// (what only a bar is for) as what is allowed.
    pub fn bar_problem(&self, why: &'static str) -> Result<Problem1d, ParameterError> {
        match &self.problem {
            Problem::Bar(p) => Ok(p.clone()),
            Problem::Box(_) => Err(ParameterError::new("scene", &self.name, why)),
        }
    }

    /// The box a 2D/3D box scene declares; a bar1d scene is refused naming the scene, with
    /// `why` (what only a box is for) as what is allowed.
    pub fn box_problem(&self, why: &'static str) -> Result<BoxProblem, ParameterError> {
        match &self.problem {
            Problem::Box(p) => Ok(p.clone()),
            Problem::Bar(_) => Err(ParameterError::new("scene", &self.name, why)),
        }
    }

    /// The observables of one run: the scene's, with the contact history only when there is
    /// an obstacle.
    pub fn observables(&self) -> Observables {
        let obstacle = match &self.problem {
            Problem::Bar(p) => p.obstacle_gap.is_some(),
            Problem::Box(p) => p.obstacle_gap.is_some(),
        };
        Observables {
            norms: self.observables.norms.clone(),
            contact_history: self.observables.contact_history && obstacle,
            energy_history: self.observables.energy_history,
            points: self.observables.points.clone(),
            fields_at: self.observables.fields_at.clone(),
            energy_balance: false,
            fields_dir: None,
        }
    }

    /// The schemes a study runs when none is given on the command line.
    pub fn default_schemes(&self) -> Vec<Scheme> {
        match &self.discretisation.schemes {
            Some(schemes) => schemes.clone(),
            None => Scheme::paper_schemes().to_vec(),
        }
    }

    /// The study parameters.
    pub fn study_config(&self) -> StudyConfig {
        StudyConfig {
            levels: self.discretisation.levels.clone(),
            ratio: self.discretisation.ratio,
            horizon: self.problem.horizon(),
            settings: self.settings,
        }
    }
}

/// The scene files (`*.json`) of a directory, sorted by name; unreadable entries are skipped.
pub fn scene_files(dir: &Path) -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
        .map(|entries| {
            entries
                .filter_map(|e| e.ok().map(|e| e.path()))
                .filter(|p| p.extension().is_some_and(|x| x == "json"))
                .collect()
        })
        .unwrap_or_default();
    files.sort();
    files
}

// The file as written: names are strings here, checked and parsed by `SceneFile::into_scene`.
// The serde names are the types' names of the format (`struct Scene`, …), as serde's messages
// show them.

/// A scene file as written.
#[derive(Debug, Deserialize)]
#[serde(rename = "Scene", deny_unknown_fields)]
struct SceneFile {
    /// Short name.
    name: String,
    /// One sentence for `signorini list`.
    description: String,
    /// Geometry and mesh family.
    geometry: Geometry,
    /// Density and wave speed, or density and Lamé constants.
    material: Material,
    /// Boundary conditions.
    boundary: Boundary,
    /// The obstacle, if any.
    #[serde(default)]
    obstacle: Option<Obstacle>,
    /// The body force, if any.
    #[serde(default)]
    body_force: Option<BodyForce>,
    /// Initial displacement and velocity (default: the reference at `t = 0`).
    #[serde(default)]
    initial: InitialData,
    /// Horizon `T` (> 0).
    horizon: f64,
    /// The reference solution.
    reference: Reference,
    /// Levels and `Δx/Δt` of studies.
    discretisation: DiscretisationFile,
    /// What runs record.
    observables: ObservablesFile,
    /// The contact treatment (`multiplier`, the default, `penalty(gamma0=G)`, or
    /// `nitsche(theta=T,gamma0=G)` for a bar1d).
    #[serde(default)]
    contact: Option<String>,
    /// The schemes' implementation choices as a named set: `harness` (the default) or
    /// `getfem-demo` (GetFEM demo's start, Nitsche acceleration and Paoli–Schatzman rows).
    #[serde(default)]
    conventions: Option<String>,
    /// The start (`static`, the default, or `implicit-multiplier`), over the set's.
    #[serde(default)]
    start: Option<String>,
}

/// The geometry and mesh family.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(tag = "kind", rename_all = "kebab-case", deny_unknown_fields)]
enum Geometry {
    /// A bar `[0, length]` meshed by uniform P1 elements; the obstacle side is `x = 0`.
    Bar1d {
        /// Length `L` (> 0).
        length: f64,
    },
    /// A 2D or 3D box `[0, L₁] × … × [0, L_d]` of Q1 elements, the last axis along the bar;
    /// the face `x_d = 0` faces the obstacle, the face `x_d = L_d` is held fixed.
    Box {
        /// `[L₁, L₂]` or `[L₁, L₂, L₃]` (> 0).
        lengths: Vec<f64>,
    },
}

/// Material constants: `density` and `wave_speed` for a bar, `density` and the Lamé constants
/// for a box.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
struct Material {
    /// Density `ρ` (> 0).
    density: f64,
    /// Wave speed `c = sqrt(E/ρ)` (> 0), bars only.
    #[serde(default)]
    wave_speed: Option<f64>,
    /// Lamé `λ` (boxes only; `λ + 2μ/d > 0`).
    #[serde(default)]
    lame_lambda: Option<f64>,
    /// Lamé `μ` (boxes only; > 0).
    #[serde(default)]
    lame_mu: Option<f64>,
}

/// Boundary conditions.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
struct Boundary {
    /// The end `x = L`: `clamped` (u = 0) or `free` (u_x = 0).
    far_end: EndCondition,
}

/// A rigid obstacle at the end `x = 0`.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
struct Obstacle {
    /// Distance of the bar's end from the obstacle when `u = 0` (≥ 0).
    gap: f64,
}

/// A constant body force.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
struct BodyForce {
    /// Force per unit length (negative: towards the obstacle).
    density: f64,
}

/// What the errors are measured against.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(rename_all = "kebab-case", deny_unknown_fields)]
enum Reference {
    /// A named closed-form solution (`signorini-dirichlet`, `clamped-free-mode`, `at-rest`,
    /// `bouncing-bar`).
    Exact(String),
    /// No reference: runs record energy, contact and fields, and no error norm.
    None,
}

/// Refinement levels, the time step and the schemes a study runs by default, as written.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(rename = "Discretisation", deny_unknown_fields)]
struct DiscretisationFile {
    /// `NX` of each level of a study, increasing.
    levels: Vec<usize>,
    /// `Δx / Δt`.
    ratio: f64,
    /// Scheme names a study runs when none is given (default: the paper's seven).
    #[serde(default)]
    schemes: Option<Vec<String>>,
    /// Elements along the axis of the fine-mesh reference of a box study (a multiple of twice
    /// the finest level); bar1d scenes have an exact reference and must not set it.
    #[serde(default)]
    reference_level: Option<usize>,
    /// The round-off ensemble a box study also runs (`{"members": K, "amplitude": A}`: `K`
    /// members whose initial velocity carries seeded noise of relative size `A`); bar1d scenes
    /// must not set it (`signorini sensitivity` takes `--members` and `--amplitude`).
    #[serde(default)]
    sensitivity: Option<EnsembleConfig>,
}

/// What to record, as written.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(rename = "SceneObservables", deny_unknown_fields)]
struct ObservablesFile {
    /// Error norms by key (`u_Linf_H`, `u_L2_H`, `u_Linf_V`, `u_L2_V`, `lambda_L2`,
    /// `energy_Linf`, `energy_L2`).
    #[serde(default)]
    norms: Vec<String>,
    /// Record the energy history of a run.
    #[serde(default)]
    energy_history: bool,
    /// Record the contact node's displacement and multiplier of a run.
    #[serde(default)]
    contact_history: bool,
    /// Positions `x` whose displacement history a run records (with the exact one).
    #[serde(default)]
    points: Vec<f64>,
    /// Times at which a run records the whole field (`u_h`, `∂x u_h` and the exact ones).
    #[serde(default)]
    fields_at: Vec<f64>,
}

fn invalid(path: &Path, field: &str, value: impl fmt::Display, allowed: &str) -> SceneError {
    SceneError::Invalid {
        path: path.to_path_buf(),
        field: field.to_string(),
        value: compact(value.to_string()),
        allowed: allowed.to_string(),
    }
}

/// `v` finite and > 0.
fn positive(path: &Path, field: &str, v: f64) -> Result<(), SceneError> {
    if v.is_finite() && v > 0.0 {
        Ok(())
    } else {
        Err(invalid(path, field, v, "a finite number > 0"))
    }
}

/// What the geometry-specific checks produce: the problem, the default schemes, the norms.
type Checked<P> = (P, Option<Vec<Scheme>>, BTreeSet<Norm>);

impl SceneFile {
    /// Checks every field and parses the names: the typed scene, or the first invalid field.
    fn into_scene(self, path: &Path) -> Result<Scene, SceneError> {
        self.check_magnitudes(path)?;
        positive(path, "material.density", self.material.density)?;
        positive(path, "horizon", self.horizon)?;
        positive(path, "discretisation.ratio", self.discretisation.ratio)?;
        if let Some(o) = &self.obstacle {
            if !(o.gap.is_finite() && o.gap >= 0.0) {
                return Err(invalid(path, "obstacle.gap", o.gap, "a finite number >= 0"));
            }
        }
        let contact = self.contact_treatment(path)?;
        let conventions = self.conventions(path)?;
        if let Some(b) = &self.body_force {
            if !b.density.is_finite() {
                return Err(invalid(
                    path,
                    "body_force.density",
                    b.density,
                    "a finite number",
                ));
            }
        }
        let (problem, schemes, norms) = match &self.geometry {
            Geometry::Bar1d { length } => {
                let (bar, schemes, norms) = self.bar1d(path, *length, contact)?;
                (Problem::Bar(bar), schemes, norms)
            }
            Geometry::Box { lengths } => {
                let (elastic_box, schemes, norms) = self.elastic_box(path, lengths, contact)?;
                (Problem::Box(elastic_box), schemes, norms)
            }
        };
        let DiscretisationFile {
            levels,
            ratio,
            reference_level,
            sensitivity,
            ..
        } = self.discretisation;
        let ObservablesFile {
            energy_history,
            contact_history,
            points,
            fields_at,
            ..
        } = self.observables;
        Ok(Scene {
            name: printable(&self.name),
            description: printable(&self.description),
            problem,
            settings: Settings {
                conventions,
                ..Settings::default()
            },
            discretisation: Discretisation {
                levels,
                ratio,
                schemes,
                reference_level,
                sensitivity,
            },
            observables: SceneObservables {
                norms,
                energy_history,
                contact_history,
                points,
                fields_at,
            },
        })
    }

    /// Every number of the scene within [`MAX_MAGNITUDE`] (positive ones at least its
    /// inverse); NaN and infinities are left to the checks of each field.
    fn check_magnitudes(&self, path: &Path) -> Result<(), SceneError> {
        let allowed_positive = "a number in [1e-50, 1e50] (MAX_MAGNITUDE: larger or smaller \
                                values overflow the run's energies and norms)";
        let allowed = "a number of magnitude at most 1e50 (MAX_MAGNITUDE: larger values overflow \
                       the run's energies and norms)";
        let mut positives: Vec<(&str, f64)> = vec![
            ("material.density", self.material.density),
            ("horizon", self.horizon),
            ("discretisation.ratio", self.discretisation.ratio),
        ];
        positives.extend(self.material.wave_speed.map(|c| ("material.wave_speed", c)));
        positives.extend(self.material.lame_mu.map(|m| ("material.lame_mu", m)));
        match &self.geometry {
            Geometry::Bar1d { length } => positives.push(("geometry.length", *length)),
            Geometry::Box { lengths } => {
                positives.extend(lengths.iter().map(|&l| ("geometry.lengths", l)))
            }
        }
        for (field, v) in positives {
            if v.is_finite() && v > 0.0 && !(1.0 / MAX_MAGNITUDE..=MAX_MAGNITUDE).contains(&v) {
                return Err(invalid(path, field, format!("{v:e}"), allowed_positive));
            }
        }
        let profile = |p: Profile| match p {
            Profile::Reference => vec![],
            Profile::Constant(c) => vec![c],
            Profile::Affine { at_start, at_end } => vec![at_start, at_end],
        };
        let mut signed: Vec<(&str, f64)> = Vec::new();
        signed.extend(
            self.material
                .lame_lambda
                .map(|l| ("material.lame_lambda", l)),
        );
        signed.extend(self.obstacle.as_ref().map(|o| ("obstacle.gap", o.gap)));
        signed.extend(
            self.body_force
                .as_ref()
                .map(|b| ("body_force.density", b.density)),
        );
        signed.extend(
            profile(self.initial.displacement)
                .into_iter()
                .map(|v| ("initial.displacement", v)),
        );
        signed.extend(
            profile(self.initial.velocity)
                .into_iter()
                .map(|v| ("initial.velocity", v)),
        );
        for (field, v) in signed {
            if v.is_finite() && v.abs() > MAX_MAGNITUDE {
                return Err(invalid(path, field, format!("{v:e}"), allowed));
            }
        }
        Ok(())
    }

    /// A bar1d scene's checks and its problem.
    fn bar1d(
        &self,
        path: &Path,
        length: f64,
        contact: ContactTreatment,
    ) -> Result<Checked<Problem1d>, SceneError> {
        positive(path, "geometry.length", length)?;
        let wave_speed = self.material.wave_speed.ok_or_else(|| {
            invalid(
                path,
                "material.wave_speed",
                "missing",
                "a finite number > 0 for a bar1d",
            )
        })?;
        positive(path, "material.wave_speed", wave_speed)?;
        for (field, v) in [
            ("material.lame_lambda", self.material.lame_lambda),
            ("material.lame_mu", self.material.lame_mu),
        ] {
            if let Some(v) = v {
                return Err(invalid(
                    path,
                    field,
                    v,
                    "absent for a bar1d (use wave_speed)",
                ));
            }
        }
        self.validate_levels_and_times(path)?;
        if let Some(p) = &self.initial.perturbation {
            if !(p.amplitude.is_finite() && p.amplitude > 0.0 && p.amplitude <= length) {
                return Err(invalid(
                    path,
                    "initial.perturbation.amplitude",
                    p.amplitude,
                    "a finite number in (0, L] (an absolute displacement, at most the bar's length)",
                ));
            }
        }
        if let Some(level) = self.discretisation.reference_level {
            return Err(invalid(
                path,
                "discretisation.reference_level",
                level,
                "absent for a bar1d (its reference is the exact solution)",
            ));
        }
        if self.discretisation.sensitivity.is_some() {
            return Err(invalid(
                path,
                "discretisation.sensitivity",
                "given",
                "absent for a bar1d (`signorini sensitivity` takes --members and --amplitude)",
            ));
        }
        let schemes = self.schemes(path)?;
        for &x in &self.observables.points {
            if !(x.is_finite() && (0.0..=length).contains(&x)) {
                return Err(invalid(
                    path,
                    "observables.points",
                    x,
                    "positions in [0, L]",
                ));
            }
        }
        let mut norms = BTreeSet::new();
        for n in &self.observables.norms {
            let norm: Norm = n.parse().map_err(|_| {
                invalid(
                    path,
                    "observables.norms",
                    n,
                    "u_Linf_H, u_L2_H, u_Linf_V, u_L2_V, lambda_L2, energy_Linf, energy_L2",
                )
            })?;
            if norm == Norm::MultiplierL2 && self.obstacle.is_none() {
                return Err(invalid(
                    path,
                    "observables.norms",
                    n,
                    "norms the scene defines (lambda_L2 needs an obstacle)",
                ));
            }
            norms.insert(norm);
        }
        let exact = self.exact_solution(path, length, wave_speed)?;
        self.check_initial_data(path, length, exact.as_ref())?;
        let problem = Problem1d {
            length,
            density: self.material.density,
            wave_speed,
            far_end: self.boundary.far_end,
            obstacle_gap: self.obstacle.as_ref().map(|o| o.gap),
            body_force: self.body_force.as_ref().map(|b| b.density),
            exact,
            initial: self.initial,
            horizon: self.horizon,
            contact,
        };
        Ok((problem, schemes, norms))
    }

    /// The scheme names of `discretisation.schemes` parsed (`None` when the scene names none).
    fn schemes(&self, path: &Path) -> Result<Option<Vec<Scheme>>, SceneError> {
        let Some(names) = &self.discretisation.schemes else {
            return Ok(None);
        };
        names
            .iter()
            .map(|name| {
                name.parse::<Scheme>().map_err(|e| {
                    invalid(path, "discretisation.schemes", name, SCHEME_NAMES)
                        .with_detail(e.to_string())
                })
            })
            .collect::<Result<_, _>>()
            .map(Some)
    }

    /// Levels increasing from 1 (element counts, along the axis for a box), field times in
    /// `[0, T]`; returns the finest level.
    fn validate_levels_and_times(&self, path: &Path) -> Result<usize, SceneError> {
        let levels = &self.discretisation.levels;
        let increasing = levels.windows(2).all(|w| w[0] < w[1]);
        let finest = match (levels.first(), levels.last()) {
            (Some(&coarsest), Some(&finest)) if coarsest > 0 && increasing => finest,
            _ => {
                return Err(invalid(
                    path,
                    "discretisation.levels",
                    format!("{levels:?}"),
                    "increasing element counts >= 1",
                ))
            }
        };
        for &t in &self.observables.fields_at {
            if !(t.is_finite() && (0.0..=self.horizon).contains(&t)) {
                return Err(invalid(
                    path,
                    "observables.fields_at",
                    t,
                    "times in [0, horizon]",
                ));
            }
        }
        Ok(finest)
    }

    /// The schemes' conventions: the named set of `conventions` (the harness's when absent)
    /// with the `start` the scene names, if any.
    fn conventions(&self, path: &Path) -> Result<Conventions, SceneError> {
        let mut conventions = match &self.conventions {
            None => Conventions::HARNESS,
            Some(name) => name
                .parse()
                .map_err(|e: ParameterError| invalid(path, "conventions", name, e.allowed))?,
        };
        if let Some(name) = &self.start {
            conventions.start = name
                .parse()
                .map_err(|e: ParameterError| invalid(path, "start", name, e.allowed))?;
        }
        Ok(conventions)
    }

    /// The contact treatment (the multiplier when the scene names none): a known treatment
    /// with valid parameters, other than the multiplier only with an obstacle, and Nitsche only
    /// for a bar1d.
    fn contact_treatment(&self, path: &Path) -> Result<ContactTreatment, SceneError> {
        let Some(name) = &self.contact else {
            return Ok(ContactTreatment::Multiplier);
        };
        let treatment: ContactTreatment = name.parse().map_err(|e: ParameterError| {
            invalid(path, "contact", name, TREATMENT_NAMES).with_detail(e.to_string())
        })?;
        if treatment != ContactTreatment::Multiplier && self.obstacle.is_none() {
            return Err(invalid(
                path,
                "contact",
                name,
                "multiplier for a scene without obstacle",
            ));
        }
        if matches!(self.geometry, Geometry::Box { .. })
            && matches!(treatment, ContactTreatment::Nitsche { .. })
        {
            return Err(invalid(
                path,
                "contact",
                name,
                "multiplier or penalty(gamma0=G) for a box (Nitsche is 1D only)",
            ));
        }
        Ok(treatment)
    }

    /// A box scene's checks and its problem.
    fn elastic_box(
        &self,
        path: &Path,
        lengths: &[f64],
        contact: ContactTreatment,
    ) -> Result<Checked<BoxProblem>, SceneError> {
        if !(2..=3).contains(&lengths.len()) || lengths.iter().any(|l| !(l.is_finite() && *l > 0.0))
        {
            return Err(invalid(
                path,
                "geometry.lengths",
                format!("{lengths:?}"),
                "two or three finite lengths > 0, the last along the bar",
            ));
        }
        if let Some(c) = self.material.wave_speed {
            return Err(invalid(
                path,
                "material.wave_speed",
                c,
                "absent for a box (use lame_lambda, lame_mu)",
            ));
        }
        let (Some(lame_lambda), Some(lame_mu)) = (self.material.lame_lambda, self.material.lame_mu)
        else {
            return Err(invalid(
                path,
                "material.lame_lambda, material.lame_mu",
                "missing",
                "both given for a box",
            ));
        };
        let elasticity = Elasticity {
            density: self.material.density,
            lame_lambda,
            lame_mu,
        };
        elasticity
            .validate(lengths.len())
            .map_err(|e| invalid(path, &format!("material.{}", e.name), e.value, e.allowed))?;
        if self.boundary.far_end != EndCondition::Clamped {
            return Err(invalid(
                path,
                "boundary.far_end",
                "free",
                "clamped (the box's top face is held)",
            ));
        }
        if self.reference != Reference::None {
            return Err(invalid(
                path,
                "reference",
                "exact",
                "\"none\" for a box (no closed form is known)",
            ));
        }
        if !self.observables.norms.is_empty() {
            return Err(invalid(
                path,
                "observables.norms",
                format!("{:?}", self.observables.norms),
                "empty: a box scene has no reference to measure errors against",
            ));
        }
        if !self.observables.points.is_empty() {
            return Err(invalid(
                path,
                "observables.points",
                format!("{:?}", self.observables.points),
                "empty for a box",
            ));
        }
        if self.body_force.is_some() {
            return Err(invalid(path, "body_force", "given", "absent for a box"));
        }
        let constant = |field: &str, profile: Profile| match profile {
            Profile::Constant(c) if c.is_finite() => Ok(c),
            _ => Err(invalid(
                path,
                field,
                format!("{profile:?}"),
                "{\"constant\": value} along the bar's axis for a box",
            )),
        };
        let initial_displacement = constant("initial.displacement", self.initial.displacement)?;
        let initial_velocity = constant("initial.velocity", self.initial.velocity)?;
        if self.initial.perturbation.is_some() {
            return Err(invalid(
                path,
                "initial.perturbation",
                "given",
                "absent for a box",
            ));
        }
        let finest = self.validate_levels_and_times(path)?;
        if let Some(level) = self.discretisation.reference_level {
            let nested = self
                .discretisation
                .levels
                .windows(2)
                .all(|w| w[1] % w[0] == 0);
            if !nested || level % (2 * finest) != 0 {
                return Err(invalid(
                    path,
                    "discretisation.reference_level",
                    level,
                    "a multiple of twice the finest level, with each level dividing the next \
                     (nested meshes)",
                ));
            }
        }
        if let Some(ensemble) = &self.discretisation.sensitivity {
            ensemble.validate().map_err(|e| {
                invalid(
                    path,
                    &format!("discretisation.sensitivity.{}", e.name),
                    e.value,
                    e.allowed,
                )
            })?;
        }
        let schemes = self.schemes(path)?;
        let problem = BoxProblem {
            lengths: lengths.to_vec(),
            elasticity,
            obstacle_gap: self.obstacle.as_ref().map(|o| o.gap),
            initial_displacement,
            initial_velocity,
            horizon: self.horizon,
            contact,
        };
        Ok((problem, schemes, BTreeSet::new()))
    }

    /// A closed-form reference solves only its own initial data: each initial profile that is
    /// not `"reference"` must equal the reference's displacement (within the declared
    /// perturbation's amplitude) or velocity at `t = 0`, checked at [`INITIAL_DATA_SAMPLES`] + 1
    /// points of `[0, L]` to a relative 1e-9.
    fn check_initial_data(
        &self,
        path: &Path,
        length: f64,
        exact: &dyn ExactSolution,
    ) -> Result<(), SceneError> {
        let displacement: fn(Pointwise) -> f64 = |p| p.u;
        let velocity: fn(Pointwise) -> f64 = |p| p.ut;
        let slack = self.initial.perturbation.map_or(0.0, |p| p.amplitude);
        for (field, profile, pick, slack) in [
            (
                "initial.displacement",
                self.initial.displacement,
                displacement,
                slack,
            ),
            ("initial.velocity", self.initial.velocity, velocity, 0.0),
        ] {
            if profile == Profile::Reference {
                continue;
            }
            for k in 0..=INITIAL_DATA_SAMPLES {
                let x = length * k as f64 / INITIAL_DATA_SAMPLES as f64;
                let given = profile.at(x, length, exact, pick);
                let wanted = pick(exact.eval(x, 0.0));
                let agrees = (given - wanted).abs() <= slack + 1e-9 * wanted.abs().max(1.0);
                if !agrees {
                    let profile = serde_json::to_string(&profile).unwrap_or_default();
                    return Err(invalid(
                        path,
                        field,
                        format!("{profile} ({given} at x = {x})"),
                        &format!(
                            "the data of the reference {}: {wanted} at x = {x} (\"reference\" \
                             takes them; other data need a reference that solves them)",
                            exact.name()
                        ),
                    ));
                }
            }
        }
        Ok(())
    }

    /// The reference solution of a bar of `length` and `wave_speed`, checked against the
    /// scene's parameters: a closed form is valid only for the problem it solves.
    fn exact_solution(
        &self,
        path: &Path,
        length: f64,
        wave_speed: f64,
    ) -> Result<Arc<dyn ExactSolution>, SceneError> {
        let Reference::Exact(name) = &self.reference else {
            return Err(invalid(
                path,
                "reference",
                "none",
                "{\"exact\": name} for a bar1d",
            ));
        };
        let unit = length == 1.0 && self.material.density == 1.0 && wave_speed == 1.0;
        let clamped = self.boundary.far_end == EndCondition::Clamped;
        let requirement = |ok: bool, needs: &str| {
            if ok {
                Ok(())
            } else {
                Err(invalid(path, "reference.exact", name, needs))
            }
        };
        match name.as_str() {
            "signorini-dirichlet" => {
                requirement(
                    unit && clamped
                        && self.obstacle.as_ref().is_some_and(|o| o.gap == 0.0)
                        && self.body_force.is_none(),
                    "signorini-dirichlet solves L = 1, density = wave_speed = 1, far_end clamped, \
                     obstacle gap 0, no body force",
                )?;
                Ok(Arc::new(SignoriniDirichlet))
            }
            "clamped-free-mode" => {
                requirement(
                    unit && clamped && self.obstacle.is_none() && self.body_force.is_none(),
                    "clamped-free-mode solves L = 1, density = wave_speed = 1, far_end clamped, \
                     no obstacle, no body force",
                )?;
                Ok(Arc::new(ClampedFreeMode))
            }
            "bouncing-bar" => {
                let height = match (self.initial.displacement, self.initial.velocity) {
                    (Profile::Constant(h), Profile::Constant(v)) if h > 0.0 && v == 0.0 => Some(h),
                    _ => None,
                };
                let gravity = self.body_force.as_ref().map(|b| -b.density);
                let ok = self.material.density == 1.0
                    && wave_speed == 1.0
                    && !clamped
                    && self.obstacle.as_ref().is_some_and(|o| o.gap == 0.0)
                    && gravity.is_some_and(|g| g > 0.0)
                    && height.is_some();
                requirement(
                    ok,
                    "bouncing-bar solves density = wave_speed = 1, far_end free, obstacle gap 0, \
                     body_force density −g < 0, initial displacement {\"constant\": u0 > 0} and \
                     velocity {\"constant\": 0}",
                )?;
                let bar = BouncingBar::new(length, gravity.unwrap_or(1.0), height.unwrap_or(1.0))
                    .and_then(|b| b.with_horizon(self.horizon))
                    .map_err(|e| {
                        invalid(path, "reference.exact", name, "").with_detail(e.to_string())
                    })?;
                Ok(Arc::new(bar))
            }
            "at-rest" => {
                requirement(
                    self.body_force.is_none(),
                    "at-rest (u ≡ 0) solves any bar without body force",
                )?;
                Ok(Arc::new(AtRest))
            }
            _ => Err(invalid(path, "reference.exact", name, EXACT_SOLUTIONS)),
        }
    }
}
