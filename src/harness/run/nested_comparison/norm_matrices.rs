//! The matrices of the norms the reference is compared in ([`NormMatrices`]).

use crate::engine::fem::{BoxMesh, Elasticity, MassVariant, SymmetricMatrix};

/// The matrices of the norms on one mesh: the standard consistent mass (`H`: `ρ ∫ |e|²`) and
/// the stiffness (`a(e, e)`; `V` is their sum), matrix-free.
#[derive(Debug, Clone)]
pub struct NormMatrices {
    /// Consistent mass.
    pub mass: SymmetricMatrix,
    /// Stiffness.
    pub stiffness: SymmetricMatrix,
}

impl NormMatrices {
    /// The norm matrices of `mesh` with the density and the Lamé coefficients of `elasticity`.
    pub fn of(mesh: &BoxMesh, elasticity: &Elasticity) -> Self {
        Self {
            mass: mesh
                .mass_stencil(MassVariant::Standard, elasticity.density)
                .expect("the standard mass is built element by element"),
            stiffness: mesh.stiffness_stencil(elasticity),
        }
    }

    /// `‖e‖²_H = eᵀ M e` (`scratch` has `e`'s length).
    pub fn h_squared(&self, e: &[f64], scratch: &mut [f64]) -> f64 {
        self.mass.mul_dot(e, scratch)
    }

    /// `‖e‖²_V = eᵀ M e + eᵀ S e`.
    pub fn v_squared(&self, e: &[f64], scratch: &mut [f64]) -> f64 {
        self.h_squared(e, scratch) + self.stiffness.mul_dot(e, scratch)
    }

    /// `(‖e‖²_H, ‖e‖²_V)` of one `e`, the mass product done once.
    pub fn squared(&self, e: &[f64], scratch: &mut [f64]) -> (f64, f64) {
        let h2 = self.h_squared(e, scratch);
        (h2, h2 + self.stiffness.mul_dot(e, scratch))
    }
}
