//! The choices the papers leave to the implementation, where two codes solving "the same"
//! scheme can differ: how the start treats data that violate the quasi-static equation of a
//! massless contact node, which stiffness the Nitsche acceleration is recovered with, and how
//! Paoli–Schatzman treats the rows of `ker M` and its first step; and, for the round-off test of
//! the regression gate, the order in which the one-step predictor is summed. The harness's defaults are
//! [`Conventions::HARNESS`]; [`Conventions::GETFEM_DEMO`] are those of GetFEM's public demo
//! `demo_dynamic_contact_1D.py`, read from its source (see `tests/data/getfem/README.md`), with
//! which the harness solves the demo's discrete problems (issue 17).

use std::fmt;
use std::str::FromStr;

use serde::{Deserialize, Serialize};

use crate::engine::error::ParameterError;

/// How the initial state treats the massless dofs (zero rows of `M`) when the data `U⁰` do
/// not satisfy their static equation (the Dirichlet benchmark with `M^mod`: `u₀(0) = ½` but a
/// strained first element). With a mass on every dof both starts are the same.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Start {
    /// The massless dofs of `U⁰` are replaced by the solution of the static contact problem
    /// with the other dofs fixed, which yields `λ⁰` (the harness's default, `u₀ = u₁` on the
    /// benchmark).
    #[default]
    Static,
    /// `U⁰` is kept and the rows `Z` of `M A⁰ = F − S U⁰ − Bᵀλ⁰` are simply not imposed
    /// (`A⁰_Z = 0`): the contact multiplier is the implicit `λ⁰ = −(S U⁰ − F)_c` of a massless
    /// contact dof `c` (the 1D paper's and GetFEM's convention: GetFEM zeroes the contact row
    /// of `M·A⁰`). On the benchmark `λ⁰ = −½`, the exact `u_x(0, 0)`.
    ImplicitMultiplier,
}

/// Which stiffness the acceleration of a Nitsche run is recovered with (θ ≠ 0; the same for
/// θ = 0, penalty and the multiplier).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum NitscheAcceleration {
    /// `A` is the one of the step: `M A = F − S_θ U − Σ λ_i f_i` with the Nitsche stiffness
    /// `S_θ = S − (θ/γ) a aᵀ` that the displacement update integrates (the harness's default).
    #[default]
    Consistent,
    /// `M A = F − S U − Σ λ_i f_i` with the elastic `S`, at the start and after every step,
    /// while the displacement update still integrates `S_θ` (GetFEM's demo: its `MA0 = −K U0`
    /// and `MA1 = Fc1 − K U1`, `Fc1` the residual of the step matrix that contains the θ-term).
    /// The two accelerations differ by `M⁻¹(θ/γ) a (aᵀU)` (`σ_h(U) = aᵀU`): the runs part by
    /// `O(h)` from the first step.
    ElasticStiffness,
}

/// How Paoli–Schatzman (1D paper eq. 36) treats the rows of `ker M` (a massless contact node)
/// and its first step.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum MasslessRows {
    /// The paper's projection `P` onto `(ker M)^⊥` of the three-level force: the rows `Z`
    /// read `β R(U^{n+1}) = −Bᵀλ^n`, static equilibrium at `t_{n+1}` (the harness's default).
    #[default]
    Projected,
    /// No projection: the rows `Z` impose `β R(U^{n+1}) + (1 − 2β) R(U^n) + β R(U^{n−1}) =
    /// −Bᵀλ^n`, the equilibrium of a three-level average, whose `(−1)^n` mode is undamped.
    /// This is what GetFEM's demo integrates with its masses 1 and 2 (its bookkeeping of `M·V`
    /// and `M·A` on the zeroed row reduces to it); the residual of `U⁰` in that average is the
    /// one the start imposed (`R(U⁰) + Bᵀλ⁰`, zero on `Z`).
    ThreeLevel,
}

/// The contact condition of Paoli–Schatzman's first step, the Newmark(β, ½) step that gives
/// `U¹`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum FirstStepContact {
    /// On `U¹` (the harness's default).
    #[default]
    AtNewStep,
    /// On `(U¹ + e U⁻¹)/(1 + e)` with `U⁻¹ = U⁰`, the two-step condition of eq. (36) with
    /// GetFEM's `U₋₁ = U0`. The two differ only when the first step meets the obstacle.
    PreviousEqualsInitial,
}

/// How the one-step schemes evaluate their predictor `P = U^n + ΔtV^n + aΔt²A^n` (1D paper
/// eqs. 32 and 34 written in the form of `super::one_step`): the same arithmetic in two
/// roundings. The regression gate's round-off test runs a chaotic case in the factored form to
/// show the gate holds it by its ensemble (`tests/roundoff_gate.rs`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum PredictorForm {
    /// `U^n + ΔtV^n + aΔt²A^n`, term by term (the harness's and every committed result's).
    #[default]
    Expanded,
    /// `U^n + Δt(V^n + aΔtA^n)`.
    Factored,
}

/// Whether `form` is the default form (left out of written conventions).
fn is_expanded(form: &PredictorForm) -> bool {
    *form == PredictorForm::Expanded
}

/// The implementation choices of a run (see the module documentation).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Conventions {
    /// The start.
    #[serde(default)]
    pub start: Start,
    /// The Nitsche acceleration.
    #[serde(default)]
    pub nitsche_acceleration: NitscheAcceleration,
    /// Paoli–Schatzman's massless rows.
    #[serde(default)]
    pub paoli_schatzman_massless_rows: MasslessRows,
    /// Paoli–Schatzman's first step.
    #[serde(default)]
    pub paoli_schatzman_first_step: FirstStepContact,
    /// The one-step schemes' predictor (written only when it is not the default).
    #[serde(default, skip_serializing_if = "is_expanded")]
    pub predictor: PredictorForm,
}

impl Conventions {
    /// The harness's defaults.
    pub const HARNESS: Conventions = Conventions {
        start: Start::Static,
        nitsche_acceleration: NitscheAcceleration::Consistent,
        paoli_schatzman_massless_rows: MasslessRows::Projected,
        paoli_schatzman_first_step: FirstStepContact::AtNewStep,
        predictor: PredictorForm::Expanded,
    };

    /// GetFEM's public demo `demo_dynamic_contact_1D.py`.
    pub const GETFEM_DEMO: Conventions = Conventions {
        start: Start::ImplicitMultiplier,
        nitsche_acceleration: NitscheAcceleration::ElasticStiffness,
        paoli_schatzman_massless_rows: MasslessRows::ThreeLevel,
        paoli_schatzman_first_step: FirstStepContact::PreviousEqualsInitial,
        predictor: PredictorForm::Expanded,
    };

    /// The named sets, for the command line and scene files.
    pub const NAMED: [(&'static str, Conventions); 2] = [
        ("harness", Conventions::HARNESS),
        ("getfem-demo", Conventions::GETFEM_DEMO),
    ];
}

impl Start {
    /// The name used in scene files and on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Start::Static => "static",
            Start::ImplicitMultiplier => "implicit-multiplier",
        }
    }
}

impl fmt::Display for Start {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Start {
    type Err = ParameterError;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        [Start::Static, Start::ImplicitMultiplier]
            .into_iter()
            .find(|v| v.name() == s)
            .ok_or_else(|| ParameterError::new("start", s, "one of: static, implicit-multiplier"))
    }
}

impl FromStr for Conventions {
    type Err = ParameterError;

    /// A named set: `harness` or `getfem-demo`.
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Conventions::NAMED
            .into_iter()
            .find(|(name, _)| *name == s)
            .map(|(_, c)| c)
            .ok_or_else(|| ParameterError::new("conventions", s, "one of: harness, getfem-demo"))
    }
}
