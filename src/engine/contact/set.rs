//! The contact constraints of a model: which dofs touch the obstacle, and how far away.

use crate::engine::fem::box_mesh::BoxMesh;

/// The contact constraints: `u[dofs[i]] + gaps[i] ≥ 0`, each with a multiplier `λ_i ≤ 0`
/// entering the equation as `−λ_i e_{dofs[i]}` (1D paper sign convention, eq. 30).
#[derive(Debug, Clone, PartialEq)]
pub struct ContactSet {
    /// The constrained dofs (the normal displacement of each contact node).
    pub dofs: Vec<usize>,
    /// The initial distance to the obstacle of each constrained dof.
    pub gaps: Vec<f64>,
}

impl ContactSet {
    /// Number of contact constraints.
    pub fn len(&self) -> usize {
        self.dofs.len()
    }

    /// Whether there is no constraint.
    pub fn is_empty(&self) -> bool {
        self.dofs.is_empty()
    }

    /// The nodal contact condition of the note's (5) on a box: one constraint per node of
    /// `Γ_Sig` on its normal displacement. With `ν = −e_d`, `νᵀu ≤ g` reads
    /// `u_d(node) + gap ≥ 0`, and the note's force `+Bᵀλ = λ ν` (`λ ≤ 0`, pushing up) is the
    /// set's `−λ e_dof`: the multipliers are the note's `λ_i`, nodal contact forces.
    /// Constraints in increasing node order.
    pub fn on_box_face(mesh: &BoxMesh, gap: f64) -> Self {
        let dofs = mesh.contact_dofs();
        Self {
            gaps: vec![gap; dofs.len()],
            dofs,
        }
    }

    /// The constraint values `B u + g` (the gaps of `u`).
    pub fn gaps_of(&self, u: &[f64], out: &mut [f64]) {
        for ((o, &d), &g) in out.iter_mut().zip(&self.dofs).zip(&self.gaps) {
            *o = u[d] + g;
        }
    }
}
