//! A problem as the engine sees it: a 1D bar ([`Problem1d`]) or a 2D/3D box ([`BoxProblem`]),
//! and its [`Discretisation`] at a level: the mesh, the model and the initial dofs every run
//! starts from. Scene files (`crate::harness::study::scene`) are parsed into this.

mod bar;
mod elastic_box;
mod settings;
mod step_perturbation;

pub use bar::Problem1d;
pub use elastic_box::{box_mesh, initial_dofs, BoxProblem};
pub use settings::Settings;
pub use step_perturbation::{StepNoise, StepPerturbation, UNIT_ROUNDOFF};

use serde::{Deserialize, Serialize};

use crate::engine::exact::{ExactSolution, Pointwise};
use crate::engine::fem::box_mesh::BoxMesh;
use crate::engine::fem::Bar1d;
use crate::engine::model::Model;
use crate::engine::schemes::Conventions;

/// A problem: the 1D bar of the paper or the 2D/3D box of the note, as a scene describes it.
#[derive(Debug, Clone)]
pub enum Problem {
    /// A 1D bar with an exact solution.
    Bar(Problem1d),
    /// A 2D/3D box (no exact solution: compared with a fine-mesh reference).
    Box(BoxProblem),
}

/// A mesh with an axis: the direction of `Δx` in the ratio `Δx/Δt` of a run.
pub trait AxialMesh {
    /// The element size along the axis.
    fn axial_element_size(&self) -> f64;
}

impl AxialMesh for Bar1d {
    fn axial_element_size(&self) -> f64 {
        self.h()
    }
}

impl AxialMesh for BoxMesh {
    fn axial_element_size(&self) -> f64 {
        self.element_sizes()[self.dim() - 1]
    }
}

/// A problem discretised at one level on a mesh `M` ([`Problem1d::discretise`] on a
/// [`Bar1d`], [`BoxProblem::discretise`] on a [`BoxMesh`]): what every run starts from.
#[derive(Debug, Clone)]
pub struct Discretisation<M> {
    /// The mesh.
    pub mesh: M,
    /// The semi-discrete model (eq. 30 in 1D, the note's (5) on a box).
    pub model: Model,
    /// `U⁰`.
    pub displacement: Vec<f64>,
    /// `V⁰`.
    pub velocity: Vec<f64>,
    /// The implementation choices the schemes start and step with.
    pub conventions: Conventions,
    /// A round-off ensemble member's perturbation of the carried state after every step
    /// ([`Settings::step_round_off`]); `None`: the steps as computed.
    pub step_perturbation: Option<StepPerturbation>,
}

impl Problem {
    /// The horizon `T`.
    pub fn horizon(&self) -> f64 {
        match self {
            Problem::Bar(p) => p.horizon,
            Problem::Box(p) => p.horizon,
        }
    }
}

/// A spatial profile of initial data.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case", deny_unknown_fields)]
pub enum Profile {
    /// The reference solution at `t = 0` (its displacement or velocity).
    #[default]
    Reference,
    /// The same value everywhere.
    Constant(f64),
    /// Linear from `at_start` (x = 0) to `at_end` (x = L).
    Affine {
        /// Value at `x = 0`.
        at_start: f64,
        /// Value at `x = L`.
        at_end: f64,
    },
}

impl Profile {
    /// The profile's value at `x` on a bar of length `length`; `pick` selects `u` or `u_t` of
    /// the reference.
    pub fn at(
        &self,
        x: f64,
        length: f64,
        exact: &dyn ExactSolution,
        pick: impl Fn(Pointwise) -> f64,
    ) -> f64 {
        match *self {
            Profile::Reference => pick(exact.eval(x, 0.0)),
            Profile::Constant(c) => c,
            Profile::Affine { at_start, at_end } => at_start + (at_end - at_start) * x / length,
        }
    }

    /// The nodal interpolant as a dof vector; `pick` selects `u` or `u_t` of the reference.
    pub fn interpolate(
        &self,
        bar: &Bar1d,
        exact: &dyn ExactSolution,
        pick: impl Fn(Pointwise) -> f64,
    ) -> Vec<f64> {
        bar.interpolate(|x| self.at(x, bar.length(), exact, &pick))
    }
}

/// A seeded random perturbation of initial data: of a bar's displacement ("rough data"), of a
/// box's velocity (the members of a round-off ensemble).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Perturbation {
    /// Each dof moves by a uniform amount in `[−amplitude, amplitude]`.
    pub amplitude: f64,
    /// The seed: the same seed gives the same data.
    pub seed: u64,
}

impl Perturbation {
    /// Adds the perturbation to every dof of `u` except `contact_dofs` (displacement data stay
    /// admissible when they are the contact dofs).
    pub fn apply(&self, u: &mut [f64], contact_dofs: &[usize]) {
        let mut rng = fastrand::Rng::with_seed(self.seed);
        for (i, ui) in u.iter_mut().enumerate() {
            let shift = self.amplitude * (2.0 * rng.f64() - 1.0);
            if !contact_dofs.contains(&i) {
                *ui += shift;
            }
        }
    }
}

/// Initial displacement and velocity.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct InitialData {
    /// `u(·, 0)`.
    #[serde(default)]
    pub displacement: Profile,
    /// `u_t(·, 0)`.
    #[serde(default)]
    pub velocity: Profile,
    /// An optional seeded perturbation of the displacement.
    #[serde(default)]
    pub perturbation: Option<Perturbation>,
}
