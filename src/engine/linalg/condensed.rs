//! The preconditioner of a box step matrix whose `Γ_Sig` plane is massless (`M^mod`).
//!
//! No product of 1D masses represents a massless plane, so the product preconditioner alone
//! needs two to three times the iterations it needs with the standard mass. Ordering the dofs
//! as the plane `p` (the first layer: the last axis is the slowest) and the interior `i`,
//! ```text
//! K = [A  B]  =  L [A  0] Lᵀ,   L = [I       0],   S = C − Bᵀ A⁻¹ B,
//!     [Bᵀ C]       [0  S]           [BᵀA⁻¹   I]
//! ```
//! and the preconditioner keeps `L` and `A` exact and replaces the Schur complement `S` by the
//! product preconditioner `Ŝ` of the interior ([`ProductPreconditioner`], the last axis without
//! its first node): `P = L diag(A, Ŝ) Lᵀ`, symmetric positive definite, with
//! `κ(P⁻¹K) = κ(Ŝ⁻¹S)`. Its inverse, applied to `r = (r_p, r_i)`:
//! ```text
//! y_p = A⁻¹ r_p,   z_i = Ŝ⁻¹ (r_i − Bᵀ y_p),   z_p = A⁻¹ (r_p − B z_i)
//! ```
//! `A` is the plane's block of `K` (the stiffness alone: the plane has no mass), a 2D-sized
//! system factorised once, in band storage when its band is small ([`BandCholesky`], two
//! solves per application of `P⁻¹`), by sparse Cholesky otherwise; `B` couples the plane to the
//! next layer only.

use super::{BandCholesky, ProductPreconditioner, SpdSolver};
use crate::engine::fem::separable::SeparablePart;
use crate::engine::fem::SymmetricMatrix;

/// The most entries a band factor of the plane may store (2 MiB): beyond, the sparse
/// Cholesky's fill (about `n log n` for a 2D grid against the band's `n^{3/2}`) is the smaller.
const BAND_ENTRIES: usize = 1 << 18;

/// The factor of the plane's block `A`.
#[derive(Debug)]
enum PlaneFactor {
    /// In band storage.
    Band(BandCholesky),
    /// Sparse Cholesky.
    Sparse(SpdSolver),
}

impl PlaneFactor {
    /// Factorises `a`, in band storage when that stores at most [`BAND_ENTRIES`]; `None` when
    /// `a` is not positive definite.
    fn of(a: &SymmetricMatrix) -> Option<Self> {
        let width = BandCholesky::width_of(a);
        if a.dim() * (width + 1) <= BAND_ENTRIES {
            BandCholesky::factor(a, width).map(PlaneFactor::Band)
        } else {
            SpdSolver::factor(a, "Γ_Sig plane")
                .ok()
                .map(PlaneFactor::Sparse)
        }
    }

    /// `b ← A⁻¹ b`.
    fn solve_in_place(&self, b: &mut [f64]) {
        match self {
            PlaneFactor::Band(f) => f.solve_in_place(b),
            PlaneFactor::Sparse(f) => f.solve_in_place(b),
        }
    }
}

/// `P⁻¹` with the massless plane condensed exactly (module documentation).
#[derive(Debug)]
pub struct CondensedPlane {
    /// The plane's dofs, `0..plane_dofs`.
    plane_dofs: usize,
    /// `A`, factorised.
    plane: PlaneFactor,
    /// `B` by rows: row `i`'s entries at `coupling_start[i]..coupling_start[i + 1]` of
    /// `coupling_columns` (interior indices, counted from the first interior dof) and
    /// `coupling_values`.
    coupling_start: Vec<usize>,
    coupling_columns: Vec<usize>,
    coupling_values: Vec<f64>,
    /// `Ŝ⁻¹`.
    interior: ProductPreconditioner,
}

impl CondensedPlane {
    /// Whether `part`'s mass is zero on the first layer of its last axis (and the box has
    /// another layer).
    pub fn applies_to(part: &SeparablePart) -> bool {
        part.mass_axes
            .last()
            .is_some_and(|m| m.diag.len() > 1 && m.diag[0] == 0.0)
    }

    /// The preconditioner of `a`, whose separable part is `part`; `None` when `part` has no
    /// massless plane ([`CondensedPlane::applies_to`]), `a` is not of its size, or a factor is
    /// not positive definite.
    pub fn of(a: &SymmetricMatrix, part: &SeparablePart) -> Option<CondensedPlane> {
        if !Self::applies_to(part) {
            return None;
        }
        let layer_nodes: usize = part.mass_axes[..part.mass_axes.len() - 1]
            .iter()
            .map(|m| m.diag.len())
            .product();
        let plane_dofs = part.components * layer_nodes;
        let interior = ProductPreconditioner::of(&part.without_first_layer())?;
        if plane_dofs + interior.dim() != a.dim() {
            return None;
        }
        let indices: Vec<usize> = (0..plane_dofs).collect();
        let plane = PlaneFactor::of(&a.principal_submatrix(&indices))?;
        let mut coupling_start = Vec::with_capacity(plane_dofs + 1);
        let mut coupling_columns = Vec::new();
        let mut coupling_values = Vec::new();
        coupling_start.push(0);
        for i in 0..plane_dofs {
            a.for_each_in_row(i, |j, v| {
                if j >= plane_dofs && v != 0.0 {
                    coupling_columns.push(j - plane_dofs);
                    coupling_values.push(v);
                }
            });
            coupling_start.push(coupling_columns.len());
        }
        Some(CondensedPlane {
            plane_dofs,
            plane,
            coupling_start,
            coupling_columns,
            coupling_values,
            interior,
        })
    }

    /// `(columns, values)` of row `i` of `B`.
    fn coupling_row(&self, i: usize) -> impl Iterator<Item = (usize, f64)> + '_ {
        let range = self.coupling_start[i]..self.coupling_start[i + 1];
        self.coupling_columns[range.clone()]
            .iter()
            .copied()
            .zip(self.coupling_values[range].iter().copied())
    }

    /// `z = P⁻¹ r` (module documentation).
    pub fn solve_into(&self, r: &[f64], z: &mut [f64]) {
        let (r_p, r_i) = r.split_at(self.plane_dofs);
        let (z_p, z_i) = z.split_at_mut(self.plane_dofs);
        z_i.copy_from_slice(r_i);
        self.eliminate_plane(r_p, z_p, z_i);
        self.interior.solve_in_place(z_i);
        self.back_substitute_plane(r_p, z_p, z_i);
    }

    /// The plane's dofs (the first ones).
    pub fn plane_dofs(&self) -> usize {
        self.plane_dofs
    }

    /// `Ŝ⁻¹`, the product preconditioner of the interior.
    pub fn interior(&self) -> &ProductPreconditioner {
        &self.interior
    }

    /// The first step of `P⁻¹`: `y_p = A⁻¹ r_p` into `z_p`, and `z_i ← z_i − Bᵀ y_p` on the
    /// interior's first entries `z_i` (it needs only the layer next to the plane: `B` couples
    /// nothing else), `z_i` holding `r_i` on entry.
    pub fn eliminate_plane(&self, r_p: &[f64], z_p: &mut [f64], z_i: &mut [f64]) {
        z_p.copy_from_slice(r_p);
        self.plane.solve_in_place(z_p);
        for (i, y) in z_p.iter().enumerate() {
            for (j, v) in self.coupling_row(i) {
                z_i[j] -= v * y;
            }
        }
    }

    /// The last step of `P⁻¹`, once `z_i = Ŝ⁻¹(r_i − Bᵀ y_p)`: `z_p = A⁻¹ (r_p − B z_i)`.
    pub fn back_substitute_plane(&self, r_p: &[f64], z_p: &mut [f64], z_i: &[f64]) {
        for (i, (zp, rp)) in z_p.iter_mut().zip(r_p).enumerate() {
            *zp = rp - self.coupling_row(i).map(|(j, v)| v * z_i[j]).sum::<f64>();
        }
        self.plane.solve_in_place(z_p);
    }
}
