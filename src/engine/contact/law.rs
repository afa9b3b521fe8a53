//! A [`ContactTreatment`] resolved on one mesh: what each step of a scheme needs to impose it.
//!
//! Every treatment is written as one family. Constraint `i` has a value
//! `c_i(U) = m_iᵀU + g_i`, acts on the equations through a force vector `f_i`, and has a
//! compliance `ε_i ≥ 0`:
//! ```text
//! M U'' + S U = F − Σ_i λ_i f_i,     λ_i = −μ_i,     0 ≤ μ_i ⟂ c_i(U) + ε_i μ_i ≥ 0.
//! ```
//! * multiplier: `m_i = f_i = e_{d_i}`, `ε_i = 0` (1D paper eq. 30);
//! * penalty: `m_i = f_i = e_{d_i}`, `ε_i = 1/κ_i`. The last line says `μ_i = κ_i max(−c_i, 0)`,
//!   i.e. `λ_i = κ_i min(B U + g, 0)_i`;
//! * Nitsche (1D, Chouly–Hild–Renard 2015, eq. 2.5; derivation below): `m = e_0 + a/γ`,
//!   `f = e_0 + θ a/γ`, `ε = 1/γ`, and `S` replaced by `S − (θ/γ) a aᵀ`.
//!
//! In a step `K U = r − Σ λ_i f_i` gives `U = U_free + Σ μ_j K⁻¹f_j`, hence
//! `c_i + ε_i μ_i = c_i(U_free) + Σ_j (m_iᵀK⁻¹f_j + ε_i δ_ij) μ_j`: the complementarity problem
//! of the multiplier with the shifted Delassus operator `W + diag(ε)`, `W_ij = m_iᵀK⁻¹f_j`
//! (for the penalty `W + I/κ`, symmetric positive definite; for Nitsche a scalar).
//!
//! **Nitsche in this convention.** The bar is `[0, L]`, the obstacle below `x = 0`, the
//! constraint `d(u) = u(0) + g ≥ 0`. Integrating `ρu_tt − E u_xx = f` against `v` gives
//! `(ρu_tt, v) + a(u, v) + σ(u) v(0) = (f, v)` with `σ(u) = E u_x(0)`, the multiplier of the
//! paper (`λ = σ`). Signorini's condition `d ≥ 0, σ ≤ 0, σ d = 0` is equivalent, for any
//! `γ > 0`, to `σ = [P_γ(u)]_−` with `P_γ(u) = σ(u) + γ d(u)` and `[x]_− = min(x, 0)`; this
//! is CHR's `P_γ(u) = σ_n(u) − γ(u_n − g)` with `σ_n = σ`, `u_n = −u(0)`. Writing
//! `v(0) = (P_{θγ}(v) − θσ(v))/γ` with `P_{θγ}(v) = θσ(v) + γ v(0)` and replacing `σ(u)` by
//! `[P_γ(u)]_−` in the second product gives CHR's form
//! `(ρu_tt, v) + a(u, v) − (θ/γ) σ(u)σ(v) + (1/γ) [P_γ(u)]_− P_{θγ}(v) = (f, v)`.
//! In P1, `σ_h(U) = aᵀU`, `a = (E/h)(e_1 − e_0)`, so `P_γ = γ c(U)` with `m = e_0 + a/γ`, the
//! force is `λ f` with `λ = [P_γ]_− = γ min(c, 0)` (reported as the multiplier: it approximates
//! `σ(0)`), and `f = e_0 + θa/γ`. With `γ = γ₀E/h`, `a/γ = (e_1 − e_0)/γ₀`.
//!
//! **Energies.** The contact energy added to `½VᵀMV + ½UᵀSU − FᵀU` (with `S` the matrix the
//! scheme integrates, `S − (θ/γ)aaᵀ` for Nitsche) is `Σ_i min(c_i, 0)² / (2ε_i)`: the penalty
//! energy `½κ min(BU + g, 0)²`, and for Nitsche `(1/2γ)[P_γ(U)]_−²`, so that the total is CHR's
//! `½VᵀMV + ½UᵀSU − FᵀU − (θ/2γ)σ_h(U)² + (1/2γ)[P_γ(U)]_−²`. Along the semi-discrete flow
//! its derivative is `((1 − θ)/γ) [P_γ(U)]_− σ_h(U')`: conserved for `θ = 1` (CHR 2015,
//! §3), not for `θ ∈ {−1, 0}`; the penalty energy is conserved too.

use super::ContactTreatment;
use crate::engine::contact::ContactSet;
use crate::engine::error::ParameterError;
use crate::engine::fem::box_mesh::{BoxMesh, Elasticity};
use crate::engine::fem::Bar1d;

/// A sparse vector as `(dof, coefficient)` pairs.
pub type SparseVector = Vec<(usize, f64)>;

/// `vᵀu` for a sparse `v`.
pub fn sparse_dot(v: &[(usize, f64)], u: &[f64]) -> f64 {
    v.iter().map(|&(k, c)| c * u[k]).sum()
}

/// One constraint as a step sees it (see the module documentation).
#[derive(Debug, Clone, PartialEq)]
pub struct ConstraintRow {
    /// `m_i`: the constraint value is `m_iᵀU + g_i`.
    pub measure: SparseVector,
    /// `f_i`: the constraint enters the equations as `−λ_i f_i`.
    pub force: SparseVector,
    /// `ε_i ≥ 0`: `0` for the multiplier, `1/κ` for the penalty, `1/γ` for Nitsche.
    pub compliance: f64,
}

/// Nitsche's normal-stress term in 1D.
#[derive(Debug, Clone, PartialEq)]
struct NitscheTerm {
    /// `a`: `σ_h(U) = aᵀU`.
    stress: SparseVector,
    gamma: f64,
    theta: f64,
}

/// A contact treatment resolved on a mesh.
#[derive(Debug, Clone, PartialEq)]
pub struct ContactLaw {
    treatment: ContactTreatment,
    compliance: Vec<f64>,
    nitsche: Option<NitscheTerm>,
}

impl ContactLaw {
    /// The Lagrange multiplier on `n` constraints.
    pub fn multiplier(n: usize) -> Self {
        Self {
            treatment: ContactTreatment::Multiplier,
            compliance: vec![0.0; n],
            nitsche: None,
        }
    }

    /// The treatment on the 1D bar (one constraint at `x = 0`, `h` the bar's mesh size,
    /// `E = ρc²`): `κ = γ = γ₀E/h`. Nitsche with `θ = 1` needs `γ₀ > 1`: `S − (θ/γ)aaᵀ` is
    /// `S` with the first element's stiffness scaled by `1 − θ/γ₀`, positive (semi)definite
    /// with the kernel of `S` exactly when `γ₀ > θ`.
    pub fn bar1d(treatment: ContactTreatment, bar: &Bar1d) -> Result<Self, ParameterError> {
        let stiffness = bar.young_modulus() / bar.h();
        Ok(match treatment.validate()? {
            ContactTreatment::Multiplier => Self::multiplier(1),
            ContactTreatment::Penalty { gamma0 } => Self {
                treatment,
                compliance: vec![1.0 / (gamma0 * stiffness)],
                nitsche: None,
            },
            ContactTreatment::Nitsche { theta, gamma0 } => {
                if gamma0 <= theta {
                    return Err(ParameterError::new(
                        "gamma0",
                        gamma0,
                        "a number > 1 with theta = 1: otherwise the Nitsche stiffness \
                         S − (θ/γ) a aᵀ is not positive definite",
                    ));
                }
                let contact = bar.contact_dof();
                let mut stress = vec![(contact, -stiffness)];
                stress.extend(bar.dof_of_node(1).map(|d| (d, stiffness)));
                let gamma = gamma0 * stiffness;
                Self {
                    treatment,
                    compliance: vec![1.0 / gamma],
                    nitsche: Some(NitscheTerm {
                        stress,
                        gamma,
                        theta,
                    }),
                }
            }
        })
    }

    /// The treatment on a 2D/3D box: the penalty force of node `i` is
    /// `κ_i min(u_d + g, 0)` with `κ_i = γ₀ E w_i / h`, `w_i = ∫_{Γ_Sig} φ_i` its share of the
    /// contact face (the nodal quadrature of the pressure `γ₀E/h min(u_n + g, 0)`), `E` the
    /// Young modulus and `h` the element size along the axis. Nitsche is 1D only.
    pub fn boxed(
        treatment: ContactTreatment,
        mesh: &BoxMesh,
        elasticity: &Elasticity,
    ) -> Result<Self, ParameterError> {
        let nodes = mesh.contact_nodes();
        match treatment.validate()? {
            ContactTreatment::Multiplier => Ok(Self::multiplier(nodes.len())),
            ContactTreatment::Penalty { gamma0 } => {
                let d = mesh.dim();
                let sizes = mesh.element_sizes();
                let stiffness = gamma0 * elasticity.young_modulus() / sizes[d - 1];
                let compliance = nodes
                    .iter()
                    .map(|&node| {
                        let index = mesh.node_index(node);
                        let weight: f64 = (0..d - 1)
                            .map(|k| {
                                let end = index[k] == 0 || index[k] == mesh.counts()[k];
                                sizes[k] * if end { 0.5 } else { 1.0 }
                            })
                            .product();
                        1.0 / (stiffness * weight)
                    })
                    .collect();
                Ok(Self {
                    treatment,
                    compliance,
                    nitsche: None,
                })
            }
            ContactTreatment::Nitsche { .. } => Err(ParameterError::new(
                "contact",
                treatment,
                "multiplier or penalty(gamma0=G) for a 2D/3D box (Nitsche is implemented for \
                 the 1D bar only)",
            )),
        }
    }

    /// The treatment.
    pub fn treatment(&self) -> ContactTreatment {
        self.treatment
    }

    /// The rank-one stiffness update of Nitsche, `(a, −θ/γ)`: `S ← S − (θ/γ) a aᵀ`.
    pub fn stiffness_update(&self) -> Option<(&[(usize, f64)], f64)> {
        self.nitsche
            .as_ref()
            .map(|n| (n.stress.as_slice(), -n.theta / n.gamma))
    }

    /// The constraint rows of `set` under this treatment.
    pub fn rows(&self, set: &ContactSet) -> Vec<ConstraintRow> {
        set.dofs
            .iter()
            .zip(&self.compliance)
            .map(|(&d, &compliance)| {
                let Some(n) = &self.nitsche else {
                    return ConstraintRow {
                        measure: vec![(d, 1.0)],
                        force: vec![(d, 1.0)],
                        compliance,
                    };
                };
                let shifted = |scale: f64| {
                    let mut v: SparseVector =
                        n.stress.iter().map(|&(k, a)| (k, scale * a)).collect();
                    match v.iter_mut().find(|(k, _)| *k == d) {
                        Some(entry) => entry.1 += 1.0,
                        None => v.push((d, 1.0)),
                    }
                    v
                };
                ConstraintRow {
                    measure: shifted(1.0 / n.gamma),
                    force: shifted(n.theta / n.gamma),
                    compliance,
                }
            })
            .collect()
    }

    /// The contact energy `Σ_i min(c_i(U), 0)² / (2ε_i)` (zero for the multiplier).
    pub fn energy(&self, set: &ContactSet, u: &[f64]) -> f64 {
        if self.treatment == ContactTreatment::Multiplier {
            return 0.0;
        }
        self.rows(set)
            .iter()
            .zip(&set.gaps)
            .map(|(row, g)| {
                (sparse_dot(&row.measure, u) + g).min(0.0).powi(2) / (2.0 * row.compliance)
            })
            .sum()
    }

    /// The forces `λ_i = min(c_i(U), 0) / ε_i` of a regularised treatment at `U` (`None` for
    /// the multiplier, whose force is not a function of `U`).
    pub fn forces(&self, set: &ContactSet, u: &[f64]) -> Option<Vec<f64>> {
        (self.treatment != ContactTreatment::Multiplier).then(|| {
            self.rows(set)
                .iter()
                .zip(&set.gaps)
                .map(|(row, g)| (sparse_dot(&row.measure, u) + g).min(0.0) / row.compliance)
                .collect()
        })
    }
}
