//! Scene files: a problem described once, in JSON, and parsed into a [`Problem1d`] plus the
//! study parameters and observables it declares. Only what a scene declares is simulated: no
//! obstacle, no contact solve; no body force, no load vector; no norm asked for, no quadrature.
//!
//! Every error names the file and the field, and says what is allowed.

use std::collections::BTreeSet;
use std::fmt;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use serde::{Deserialize, Serialize};

use crate::engine::contact::{ContactTreatment, TREATMENT_NAMES};
use crate::engine::error::ParameterError;
use crate::engine::exact::{
    AtRest, BouncingBar, ClampedFreeMode, ExactSolution, SignoriniDirichlet,
};
use crate::engine::fem::box_mesh::Elasticity;
use crate::engine::fem::EndCondition;
use crate::engine::problem::Profile;
use crate::engine::problem::{InitialData, Problem1d};
use crate::engine::schemes::Scheme;
use crate::harness::elastic::BoxProblem;
use crate::harness::norms::Norm;
use crate::harness::run::Observables;
use crate::harness::sensitivity::EnsembleConfig;
use crate::harness::study::StudyConfig;

/// The geometry and mesh family.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "kebab-case", deny_unknown_fields)]
pub enum Geometry {
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
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Material {
    /// Density `ρ` (> 0).
    pub density: f64,
    /// Wave speed `c = sqrt(E/ρ)` (> 0), bars only.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub wave_speed: Option<f64>,
    /// Lamé `λ` (boxes only; `λ + 2μ/d > 0`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub lame_lambda: Option<f64>,
    /// Lamé `μ` (boxes only; > 0).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub lame_mu: Option<f64>,
}

/// Boundary conditions.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Boundary {
    /// The end `x = L`: `clamped` (u = 0) or `free` (u_x = 0).
    pub far_end: EndCondition,
}

/// A rigid obstacle at the end `x = 0`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Obstacle {
    /// Distance of the bar's end from the obstacle when `u = 0` (≥ 0).
    pub gap: f64,
}

/// A constant body force.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BodyForce {
    /// Force per unit length (negative: towards the obstacle).
    pub density: f64,
}

/// What the errors are measured against.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case", deny_unknown_fields)]
pub enum Reference {
    /// A named closed-form solution (`signorini-dirichlet`, `clamped-free-mode`, `at-rest`,
    /// `bouncing-bar`).
    Exact(String),
    /// No reference: runs record energy, contact and fields, and no error norm.
    None,
}

/// Refinement levels, the time step and the schemes a study runs by default.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Discretisation {
    /// `NX` of each level of a study, increasing.
    pub levels: Vec<usize>,
    /// `Δx / Δt`.
    pub ratio: f64,
    /// Scheme names a study runs when none is given (default: the paper's seven).
    #[serde(default)]
    pub schemes: Option<Vec<String>>,
    /// Elements along the axis of the fine-mesh reference of a box study (a multiple of twice
    /// the finest level); bar1d scenes have an exact reference and must not set it.
    #[serde(default)]
    pub reference_level: Option<usize>,
    /// The round-off ensemble a box study also runs (`{"members": K, "amplitude": A}`: `K`
    /// members whose initial velocity carries seeded noise of relative size `A`); bar1d scenes
    /// must not set it (`signorini sensitivity` takes `--members` and `--amplitude`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sensitivity: Option<EnsembleConfig>,
}

/// What to record.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SceneObservables {
    /// Error norms by key (`u_Linf_H`, `u_L2_H`, `u_Linf_V`, `u_L2_V`, `lambda_L2`,
    /// `energy_Linf`, `energy_L2`).
    #[serde(default)]
    pub norms: Vec<String>,
    /// Record the energy history of a run.
    #[serde(default)]
    pub energy_history: bool,
    /// Record the contact node's displacement and multiplier of a run.
    #[serde(default)]
    pub contact_history: bool,
    /// Positions `x` whose displacement history a run records (with the exact one).
    #[serde(default)]
    pub points: Vec<f64>,
    /// Times at which a run records the whole field (`u_h`, `∂x u_h` and the exact ones).
    #[serde(default)]
    pub fields_at: Vec<f64>,
}

/// A scene file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scene {
    /// Short name.
    pub name: String,
    /// One sentence for `signorini list`.
    pub description: String,
    /// Geometry and mesh family.
    pub geometry: Geometry,
    /// Density and wave speed.
    pub material: Material,
    /// Boundary conditions.
    pub boundary: Boundary,
    /// The obstacle, if any.
    #[serde(default)]
    pub obstacle: Option<Obstacle>,
    /// The body force, if any.
    #[serde(default)]
    pub body_force: Option<BodyForce>,
    /// Initial displacement and velocity (default: the reference at `t = 0`).
    #[serde(default)]
    pub initial: InitialData,
    /// Horizon `T` (> 0).
    pub horizon: f64,
    /// The reference solution.
    pub reference: Reference,
    /// Levels and `Δx/Δt` of studies.
    pub discretisation: Discretisation,
    /// What runs record.
    pub observables: SceneObservables,
    /// The contact treatment (`multiplier`, the default, `penalty(gamma0=G)`, or
    /// `nitsche(theta=T,gamma0=G)` for a bar1d).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub contact: Option<String>,
}

/// A scene that could not be read or is not valid.
#[derive(Debug)]
pub enum SceneError {
    /// The file cannot be read.
    Io {
        /// The scene file.
        path: PathBuf,
        /// What the system said.
        source: std::io::Error,
    },
    /// Malformed JSON, an unknown or missing field, or a value of the wrong type.
    Json {
        /// The scene file.
        path: PathBuf,
        /// 1-based line.
        line: usize,
        /// 1-based column.
        column: usize,
        /// serde's message (names the field and, for unknown fields, the allowed ones).
        message: String,
    },
    /// A value out of range or inconsistent with the rest of the scene.
    Invalid {
        /// The scene file.
        path: PathBuf,
        /// The field, dotted (`material.density`).
        field: String,
        /// The offending value.
        value: String,
        /// What is allowed.
        allowed: String,
    },
}

impl fmt::Display for SceneError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SceneError::Io { path, source } => {
                write!(f, "cannot read scene file {}: {source}", path.display())
            }
            SceneError::Json {
                path,
                line,
                column,
                message,
            } => write!(
                f,
                "scene file {} is not a valid scene (line {line}, column {column}): {message}",
                path.display()
            ),
            SceneError::Invalid {
                path,
                field,
                value,
                allowed,
            } => write!(
                f,
                "scene file {}: invalid {field} = {value}; allowed: {allowed}",
                path.display()
            ),
        }
    }
}

impl SceneError {
    /// Appends `detail` to what an [`SceneError::Invalid`] says is allowed.
    fn with_detail(self, detail: String) -> Self {
        match self {
            SceneError::Invalid {
                path,
                field,
                value,
                allowed,
            } => SceneError::Invalid {
                path,
                field,
                value,
                allowed: if allowed.is_empty() {
                    detail
                } else {
                    format!("{allowed} ({detail})")
                },
            },
            other => other,
        }
    }
}

impl std::error::Error for SceneError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            SceneError::Io { source, .. } => Some(source),
            _ => None,
        }
    }
}

/// The names of the exact solutions a scene can refer to.
pub const EXACT_SOLUTIONS: &str = "signorini-dirichlet, clamped-free-mode, at-rest, bouncing-bar";

impl Scene {
    /// Reads and validates a scene file.
    pub fn load(path: &Path) -> Result<Self, SceneError> {
        let text = std::fs::read_to_string(path).map_err(|source| SceneError::Io {
            path: path.to_path_buf(),
            source,
        })?;
        Self::parse(&text, path)
    }

    /// Parses and validates scene text; `path` is used in messages.
    pub fn parse(text: &str, path: &Path) -> Result<Self, SceneError> {
        let scene: Scene = serde_json::from_str(text).map_err(|e| SceneError::Json {
            path: path.to_path_buf(),
            line: e.line(),
            column: e.column(),
            message: e.to_string(),
        })?;
        scene.validate(path)?;
        Ok(scene)
    }

    fn invalid(path: &Path, field: &str, value: impl fmt::Display, allowed: &str) -> SceneError {
        SceneError::Invalid {
            path: path.to_path_buf(),
            field: field.to_string(),
            value: value.to_string(),
            allowed: allowed.to_string(),
        }
    }

    fn validate(&self, path: &Path) -> Result<(), SceneError> {
        let positive = |field: &str, v: f64| {
            if v.is_finite() && v > 0.0 {
                Ok(())
            } else {
                Err(Self::invalid(path, field, v, "a finite number > 0"))
            }
        };
        positive("material.density", self.material.density)?;
        positive("horizon", self.horizon)?;
        positive("discretisation.ratio", self.discretisation.ratio)?;
        if let Some(o) = &self.obstacle {
            if !(o.gap.is_finite() && o.gap >= 0.0) {
                return Err(Self::invalid(
                    path,
                    "obstacle.gap",
                    o.gap,
                    "a finite number >= 0",
                ));
            }
        }
        self.validate_contact(path)?;
        if let Some(b) = &self.body_force {
            if !b.density.is_finite() {
                return Err(Self::invalid(
                    path,
                    "body_force.density",
                    b.density,
                    "a finite number",
                ));
            }
        }
        let length = match &self.geometry {
            Geometry::Bar1d { length } => {
                positive("geometry.length", *length)?;
                let c = self.material.wave_speed.ok_or_else(|| {
                    Self::invalid(
                        path,
                        "material.wave_speed",
                        "missing",
                        "a finite number > 0 for a bar1d",
                    )
                })?;
                positive("material.wave_speed", c)?;
                for (field, v) in [
                    ("material.lame_lambda", self.material.lame_lambda),
                    ("material.lame_mu", self.material.lame_mu),
                ] {
                    if let Some(v) = v {
                        return Err(Self::invalid(
                            path,
                            field,
                            v,
                            "absent for a bar1d (use wave_speed)",
                        ));
                    }
                }
                *length
            }
            Geometry::Box { .. } => return self.validate_box(path),
        };
        self.validate_levels_and_times(path)?;
        if let Some(p) = &self.initial.perturbation {
            if !(p.amplitude.is_finite() && p.amplitude > 0.0 && p.amplitude <= length) {
                return Err(Self::invalid(
                    path,
                    "initial.perturbation.amplitude",
                    p.amplitude,
                    "a finite number in (0, L] (an absolute displacement, at most the bar's length)",
                ));
            }
        }
        if let Some(level) = self.discretisation.reference_level {
            return Err(Self::invalid(
                path,
                "discretisation.reference_level",
                level,
                "absent for a bar1d (its reference is the exact solution)",
            ));
        }
        if self.discretisation.sensitivity.is_some() {
            return Err(Self::invalid(
                path,
                "discretisation.sensitivity",
                "given",
                "absent for a bar1d (`signorini sensitivity` takes --members and --amplitude)",
            ));
        }
        for name in self.discretisation.schemes.iter().flatten() {
            name.parse::<Scheme>().map_err(|e| {
                Self::invalid(
                    path,
                    "discretisation.schemes",
                    name,
                    crate::engine::schemes::SCHEME_NAMES,
                )
                .with_detail(e.to_string())
            })?;
        }
        for &x in &self.observables.points {
            if !(x.is_finite() && (0.0..=length).contains(&x)) {
                return Err(Self::invalid(
                    path,
                    "observables.points",
                    x,
                    "positions in [0, L]",
                ));
            }
        }
        for n in &self.observables.norms {
            let norm: Norm = n.parse().map_err(|_| {
                Self::invalid(
                    path,
                    "observables.norms",
                    n,
                    "u_Linf_H, u_L2_H, u_Linf_V, u_L2_V, lambda_L2, energy_Linf, energy_L2",
                )
            })?;
            if norm == Norm::MultiplierL2 && self.obstacle.is_none() {
                return Err(Self::invalid(
                    path,
                    "observables.norms",
                    n,
                    "norms the scene defines (lambda_L2 needs an obstacle)",
                ));
            }
        }
        self.exact_solution(path).map(|_| ())
    }

    /// Levels increasing from 1 (element counts, along the axis for a box), field times in
    /// `[0, T]`.
    fn validate_levels_and_times(&self, path: &Path) -> Result<(), SceneError> {
        let levels = &self.discretisation.levels;
        if levels.is_empty() || levels[0] == 0 || levels.windows(2).any(|w| w[0] >= w[1]) {
            return Err(Self::invalid(
                path,
                "discretisation.levels",
                format!("{levels:?}"),
                "increasing element counts >= 1",
            ));
        }
        for &t in &self.observables.fields_at {
            if !(t.is_finite() && (0.0..=self.horizon).contains(&t)) {
                return Err(Self::invalid(
                    path,
                    "observables.fields_at",
                    t,
                    "times in [0, horizon]",
                ));
            }
        }
        Ok(())
    }

    /// A known treatment with valid parameters, other than the multiplier only with an
    /// obstacle, and Nitsche only for a bar1d.
    fn validate_contact(&self, path: &Path) -> Result<(), SceneError> {
        let Some(name) = &self.contact else {
            return Ok(());
        };
        let treatment: ContactTreatment = name.parse().map_err(|e: ParameterError| {
            Self::invalid(path, "contact", name, TREATMENT_NAMES).with_detail(e.to_string())
        })?;
        if treatment != ContactTreatment::Multiplier && self.obstacle.is_none() {
            return Err(Self::invalid(
                path,
                "contact",
                name,
                "multiplier for a scene without obstacle",
            ));
        }
        if self.is_box() && matches!(treatment, ContactTreatment::Nitsche { .. }) {
            return Err(Self::invalid(
                path,
                "contact",
                name,
                "multiplier or penalty(gamma0=G) for a box (Nitsche is 1D only)",
            ));
        }
        Ok(())
    }

    /// The scene's contact treatment (the multiplier when the scene names none).
    pub fn contact_treatment(&self) -> ContactTreatment {
        self.contact
            .as_deref()
            .map_or(ContactTreatment::Multiplier, |n| {
                n.parse().expect("validated when the scene was parsed")
            })
    }

    fn validate_box(&self, path: &Path) -> Result<(), SceneError> {
        let Geometry::Box { lengths } = &self.geometry else {
            unreachable!("called for boxes")
        };
        if !(2..=3).contains(&lengths.len()) || lengths.iter().any(|l| !(l.is_finite() && *l > 0.0))
        {
            return Err(Self::invalid(
                path,
                "geometry.lengths",
                format!("{lengths:?}"),
                "two or three finite lengths > 0, the last along the bar",
            ));
        }
        if let Some(c) = self.material.wave_speed {
            return Err(Self::invalid(
                path,
                "material.wave_speed",
                c,
                "absent for a box (use lame_lambda, lame_mu)",
            ));
        }
        let elasticity = self.elasticity().ok_or_else(|| {
            Self::invalid(
                path,
                "material.lame_lambda, material.lame_mu",
                "missing",
                "both given for a box",
            )
        })?;
        elasticity.validate(lengths.len()).map_err(|e| {
            Self::invalid(path, &format!("material.{}", e.name), e.value, e.allowed)
        })?;
        if self.boundary.far_end != EndCondition::Clamped {
            return Err(Self::invalid(
                path,
                "boundary.far_end",
                "free",
                "clamped (the box's top face is held)",
            ));
        }
        if self.reference != Reference::None {
            return Err(Self::invalid(
                path,
                "reference",
                "exact",
                "\"none\" for a box (no closed form is known)",
            ));
        }
        if !self.observables.norms.is_empty() {
            return Err(Self::invalid(
                path,
                "observables.norms",
                format!("{:?}", self.observables.norms),
                "empty: a box scene has no reference to measure errors against",
            ));
        }
        if !self.observables.points.is_empty() {
            return Err(Self::invalid(
                path,
                "observables.points",
                format!("{:?}", self.observables.points),
                "empty for a box",
            ));
        }
        if self.body_force.is_some() {
            return Err(Self::invalid(
                path,
                "body_force",
                "given",
                "absent for a box",
            ));
        }
        for (field, profile) in [
            ("initial.displacement", self.initial.displacement),
            ("initial.velocity", self.initial.velocity),
        ] {
            if !matches!(profile, Profile::Constant(c) if c.is_finite()) {
                return Err(Self::invalid(
                    path,
                    field,
                    format!("{profile:?}"),
                    "{\"constant\": value} along the bar's axis for a box",
                ));
            }
        }
        if self.initial.perturbation.is_some() {
            return Err(Self::invalid(
                path,
                "initial.perturbation",
                "given",
                "absent for a box",
            ));
        }
        self.validate_levels_and_times(path)?;
        if let Some(level) = self.discretisation.reference_level {
            let finest = *self.discretisation.levels.last().expect("levels validated");
            let nested = self
                .discretisation
                .levels
                .windows(2)
                .all(|w| w[1] % w[0] == 0);
            if !nested || level % (2 * finest) != 0 {
                return Err(Self::invalid(
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
                Self::invalid(
                    path,
                    &format!("discretisation.sensitivity.{}", e.name),
                    e.value,
                    e.allowed,
                )
            })?;
        }
        Ok(())
    }

    fn elasticity(&self) -> Option<Elasticity> {
        Some(Elasticity {
            density: self.material.density,
            lame_lambda: self.material.lame_lambda?,
            lame_mu: self.material.lame_mu?,
        })
    }

    /// Whether the scene is a 2D/3D box (run by [`crate::harness::elastic`]).
    pub fn is_box(&self) -> bool {
        matches!(self.geometry, Geometry::Box { .. })
    }

    /// The box problem of a box scene, `None` for a bar.
    pub fn box_problem(&self) -> Option<BoxProblem> {
        let Geometry::Box { lengths } = &self.geometry else {
            return None;
        };
        let constant = |p: Profile| match p {
            Profile::Constant(c) => c,
            _ => 0.0,
        };
        Some(BoxProblem {
            lengths: lengths.clone(),
            elasticity: self.elasticity()?,
            obstacle_gap: self.obstacle.as_ref().map(|o| o.gap),
            initial_displacement: constant(self.initial.displacement),
            initial_velocity: constant(self.initial.velocity),
            horizon: self.horizon,
            contact: self.contact_treatment(),
            velocity_perturbation: None,
        })
    }

    /// The reference solution, checked against the scene's parameters: a closed form is valid
    /// only for the problem it solves.
    fn exact_solution(&self, path: &Path) -> Result<Arc<dyn ExactSolution>, SceneError> {
        let Reference::Exact(name) = &self.reference else {
            return Err(Self::invalid(
                path,
                "reference",
                "none",
                "{\"exact\": name} for a bar1d",
            ));
        };
        let Geometry::Bar1d { length } = self.geometry else {
            return Err(Self::invalid(path, "reference", name, "\"none\" for a box"));
        };
        let wave_speed = self.material.wave_speed.unwrap_or(f64::NAN);
        let unit = length == 1.0 && self.material.density == 1.0 && wave_speed == 1.0;
        let clamped = self.boundary.far_end == EndCondition::Clamped;
        let requirement = |ok: bool, needs: &str| {
            if ok {
                Ok(())
            } else {
                Err(Self::invalid(path, "reference.exact", name, needs))
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
                        Self::invalid(path, "reference.exact", name, "").with_detail(e.to_string())
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
            _ => Err(Self::invalid(
                path,
                "reference.exact",
                name,
                EXACT_SOLUTIONS,
            )),
        }
    }

    /// The problem the 1D engine runs (a bar1d scene; see [`Scene::box_problem`] for boxes).
    pub fn problem(&self) -> Problem1d {
        let Geometry::Bar1d { length } = self.geometry else {
            panic!("Scene::problem is for bar1d scenes; check Scene::is_box first")
        };
        Problem1d {
            length,
            density: self.material.density,
            wave_speed: self
                .material
                .wave_speed
                .expect("validated when the scene was parsed"),
            far_end: self.boundary.far_end,
            obstacle_gap: self.obstacle.as_ref().map(|o| o.gap),
            body_force: self.body_force.as_ref().map(|b| b.density),
            exact: self
                .exact_solution(Path::new(&self.name))
                .expect("validated when the scene was parsed"),
            initial: self.initial,
            horizon: self.horizon,
            contact: self.contact_treatment(),
        }
    }

    /// The norms the scene asks for.
    pub fn norms(&self) -> BTreeSet<Norm> {
        self.observables
            .norms
            .iter()
            .map(|n| n.parse().expect("validated when the scene was parsed"))
            .collect()
    }

    /// The observables of one run.
    pub fn observables(&self) -> Observables {
        Observables {
            norms: self.norms(),
            contact_history: self.observables.contact_history && self.obstacle.is_some(),
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
            Some(names) => names
                .iter()
                .map(|n| n.parse().expect("validated when the scene was parsed"))
                .collect(),
            None => Scheme::paper_schemes().to_vec(),
        }
    }

    /// The study parameters.
    pub fn study_config(&self) -> StudyConfig {
        StudyConfig {
            levels: self.discretisation.levels.clone(),
            ratio: self.discretisation.ratio,
            horizon: self.horizon,
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
