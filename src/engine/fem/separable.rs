//! The separable (tensor-product) part of the box operators, from which
//! [`crate::engine::linalg`] builds the step matrices' product preconditioner.
//!
//! On a box of identical Q1 elements (2×2(×2) Gauss points, exact) the mass and the
//! component-diagonal blocks of the stiffness are sums of Kronecker products of 1D P1 matrices
//! along the axes (node-major dofs, the first axis fastest):
//! ```text
//! M    = ρ (M_d ⊗ … ⊗ M_1) ⊗ I_d
//! S_cc = Σ_k E_ck (M_d ⊗ … ⊗ K_k ⊗ … ⊗ M_1),   E_cc = λ + 2μ,  E_ck = μ (k ≠ c)
//! ```
//! with `M_k = h_k/6 · tridiag(1, 4, 1)`, `K_k = 1/h_k · tridiag(−1, 2, −1)` (halved diagonal
//! at a free end). The coupling blocks `S_cd` (`c ≠ d`, the `(λ + μ) ∂_c ∂_d` terms) are not
//! separable and are left out.
//!
//! The step matrix `K = αM + S` is preconditioned, component by component, by the product
//! ```text
//! P_c = ⊗_k (a M_k + b_ck K_k),   a = (αρ)^{1/d},   b_ck = E_ck / a^{d−1}
//! ```
//! whose expansion is `αρ M_⊗ + Σ_k E_ck (… ⊗ K_k ⊗ …)`, the separable part of `K`, plus
//! positive semi-definite cross terms `a^{d−2} b b (K ⊗ K ⊗ M)`, … that are small where the
//! mass dominates. `P_c⁻¹` is one tridiagonal solve per axis
//! ([`crate::engine::linalg::ProductPreconditioner`]). At
//! `Δx/Δt` fixed both `αM` and `S` scale alike with `h`, so `κ(P⁻¹K)` is bounded independently
//! of the mesh; the measured iteration counts are in docs/src/bars-2d-3d.md.

/// A symmetric tridiagonal matrix: its diagonal and its off-diagonal `off[i] = A[i+1, i]`.
#[derive(Debug, Clone, PartialEq)]
pub struct AxisMatrix {
    /// The diagonal.
    pub diag: Vec<f64>,
    /// The off-diagonal.
    pub off: Vec<f64>,
}

impl AxisMatrix {
    /// The 1D P1 mass `∫ φ_i φ_j` on `nodes` nodes `h` apart: `h/6 · tridiag(1, 4, 1)`, with
    /// `h/3` on the diagonal at a free end (`first_free`, `last_free`: the node has an element
    /// on one side only; a node next to an eliminated one keeps both elements).
    pub fn p1_mass(nodes: usize, h: f64, first_free: bool, last_free: bool) -> Self {
        Self::p1(nodes, [2.0 * h / 3.0, h / 6.0], first_free, last_free)
    }

    /// The 1D P1 stiffness `∫ φ_i' φ_j'`: `1/h · tridiag(−1, 2, −1)`, `1/h` on the diagonal at a
    /// free end.
    pub fn p1_stiffness(nodes: usize, h: f64, first_free: bool, last_free: bool) -> Self {
        Self::p1(nodes, [2.0 / h, -1.0 / h], first_free, last_free)
    }

    fn p1(nodes: usize, [diag, off]: [f64; 2], first_free: bool, last_free: bool) -> Self {
        let mut d = vec![diag; nodes];
        if first_free {
            d[0] = 0.5 * diag;
        }
        if last_free {
            d[nodes - 1] = 0.5 * diag;
        }
        Self {
            diag: d,
            off: vec![off; nodes.saturating_sub(1)],
        }
    }

    /// The matrix without its first row and column.
    pub fn without_first_node(&self) -> AxisMatrix {
        AxisMatrix {
            diag: self.diag[1..].to_vec(),
            off: self.off[1..].to_vec(),
        }
    }

    /// The leading `nodes × nodes` block: the matrix on the first `nodes` nodes, the last of
    /// which keeps both elements' entries (the principal submatrix, as at a cut).
    pub fn first_nodes(&self, nodes: usize) -> AxisMatrix {
        AxisMatrix {
            diag: self.diag[..nodes].to_vec(),
            off: self.off[..nodes.saturating_sub(1)].to_vec(),
        }
    }

    /// `a·self + b·other`.
    pub fn combine(&self, a: f64, other: &AxisMatrix, b: f64) -> AxisMatrix {
        let mix = |x: &[f64], y: &[f64]| x.iter().zip(y).map(|(p, q)| a * p + b * q).collect();
        AxisMatrix {
            diag: mix(&self.diag, &other.diag),
            off: mix(&self.off, &other.off),
        }
    }
}

/// The separable part of a box operator (module documentation):
/// `mass_scale · (⊗_k mass_axes[k]) ⊗ I + Σ_c Σ_k E_ck (⊗_{j≠k} M_j ⊗ stiffness_axes[k]) e_c e_cᵀ`.
#[derive(Debug, Clone, PartialEq)]
pub struct SeparablePart {
    /// Components per node `d`.
    pub components: usize,
    /// The mass's scale (`ρ`; 0 for the stiffness alone).
    pub mass_scale: f64,
    /// The mass's 1D factors, the first axis first (for `M^mod`, the axial one leaves out the
    /// first element).
    pub mass_axes: Vec<AxisMatrix>,
    /// `E_ck` row-major (`component · d + axis`); empty for the mass alone.
    pub coefficients: Vec<f64>,
    /// The 1D stiffnesses `K_k`; empty for the mass alone.
    pub stiffness_axes: Vec<AxisMatrix>,
}

impl SeparablePart {
    /// The separable part on the nodes off the first layer of the last axis: the interior of a
    /// box whose `Γ_Sig` plane is condensed ([`crate::engine::linalg::CondensedPlane`]). The
    /// interior's first node keeps both elements' stiffness (the plane's share, which the
    /// Schur complement reduces by an amount that depends on the lateral frequency, is left
    /// in): on the 3D bar at level 80 this took 10.3 CG iterations per Crank–Nicolson solve and
    /// 14.1 per backward Euler one, the free-end value `1/h` 10.9 and 15.1.
    pub fn without_first_layer(&self) -> SeparablePart {
        self.with_last_axis(AxisMatrix::without_first_node)
    }

    /// The separable part on the first `layers` node layers of the last axis: the principal
    /// submatrix of the operator on those nodes (the last axis's factors cut to their leading
    /// blocks, [`AxisMatrix::first_nodes`]).
    pub fn first_layers(&self, layers: usize) -> SeparablePart {
        self.with_last_axis(|m| m.first_nodes(layers))
    }

    /// The same part with the mass and stiffness factors of the last axis replaced by `f` of
    /// them; the other axes' factors kept.
    fn with_last_axis(&self, f: impl Fn(&AxisMatrix) -> AxisMatrix) -> SeparablePart {
        let map = |axes: &[AxisMatrix]| -> Vec<AxisMatrix> {
            let last = axes.len().saturating_sub(1);
            (axes.iter().enumerate())
                .map(|(k, m)| if k == last { f(m) } else { m.clone() })
                .collect()
        };
        SeparablePart {
            components: self.components,
            mass_scale: self.mass_scale,
            mass_axes: map(&self.mass_axes),
            coefficients: self.coefficients.clone(),
            stiffness_axes: map(&self.stiffness_axes),
        }
    }

    /// `a·p + b·q` when at most one of them has a mass and at most one a stiffness (a step
    /// matrix `αM + S`); `None` otherwise.
    pub fn combine(p: &SeparablePart, a: f64, q: &SeparablePart, b: f64) -> Option<Self> {
        let has_mass = |s: &SeparablePart| s.mass_scale != 0.0;
        let has_stiffness = |s: &SeparablePart| !s.coefficients.is_empty();
        if p.components != q.components
            || (has_mass(p) && has_mass(q))
            || (has_stiffness(p) && has_stiffness(q))
        {
            return None;
        }
        let (mass, mass_factor) = if has_mass(q) { (q, b) } else { (p, a) };
        let (stiffness, stiffness_factor) = if has_stiffness(q) { (q, b) } else { (p, a) };
        Some(Self {
            components: p.components,
            mass_scale: mass_factor * mass.mass_scale,
            mass_axes: mass.mass_axes.clone(),
            coefficients: (stiffness.coefficients.iter())
                .map(|e| stiffness_factor * e)
                .collect(),
            stiffness_axes: stiffness.stiffness_axes.clone(),
        })
    }
}
