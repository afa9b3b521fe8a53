//! The 1D bar of the paper (§2–3.1): P1 elements on `[0, L]`, nodes `a_i = i h`, `h = L / NX`,
//! the obstacle at `x = 0` (node 0), the far end `x = L` clamped (`V^Dir`, its node eliminated)
//! or free (`V^Neu`).
//!
//! The equation is `ρ u_tt − E u_xx = f` with `E = ρ c²`; the paper takes `ρ = c = 1`.

use nalgebra::Matrix2;
use serde::{Deserialize, Serialize};

use super::{MassVariant, SparseAssembler, SymmetricMatrix};
use crate::engine::error::{require_positive, ParameterError};

/// The boundary condition at the far end `x = L`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum EndCondition {
    /// `u(L, t) = 0` (Section 5).
    Clamped,
    /// `u_x(L, t) = 0` (Section 4).
    Free,
}

/// A uniform P1 discretisation of the bar.
#[derive(Debug, Clone, PartialEq)]
pub struct Bar1d {
    length: f64,
    nx: usize,
    density: f64,
    wave_speed: f64,
    far_end: EndCondition,
}

impl Bar1d {
    /// A bar of `length` with `nx` elements. Errors name the parameter and its allowed range.
    pub fn new(
        length: f64,
        nx: usize,
        density: f64,
        wave_speed: f64,
        far_end: EndCondition,
    ) -> Result<Self, ParameterError> {
        require_positive("length", length)?;
        require_positive("density", density)?;
        require_positive("wave_speed", wave_speed)?;
        if nx == 0 {
            return Err(ParameterError::new("nx", nx, "an integer >= 1"));
        }
        Ok(Self {
            length,
            nx,
            density,
            wave_speed,
            far_end,
        })
    }

    /// The paper's bar: `L = 1`, `ρ = c = 1`.
    pub fn unit(nx: usize, far_end: EndCondition) -> Result<Self, ParameterError> {
        Self::new(1.0, nx, 1.0, 1.0, far_end)
    }

    /// Number of elements.
    pub fn nx(&self) -> usize {
        self.nx
    }

    /// Length `L`.
    pub fn length(&self) -> f64 {
        self.length
    }

    /// Mesh size `h = L / NX`.
    pub fn h(&self) -> f64 {
        self.length / self.nx as f64
    }

    /// Density `ρ`.
    pub fn density(&self) -> f64 {
        self.density
    }

    /// Young's modulus `E = ρ c²`.
    pub fn young_modulus(&self) -> f64 {
        self.density * self.wave_speed * self.wave_speed
    }

    /// The far-end condition.
    pub fn far_end(&self) -> EndCondition {
        self.far_end
    }

    /// Coordinate of node `i`.
    pub fn node(&self, i: usize) -> f64 {
        if i == self.nx {
            self.length
        } else {
            i as f64 * self.h()
        }
    }

    /// Number of unknowns: `NX` when clamped (node `NX` eliminated), `NX + 1` when free.
    pub fn n_dofs(&self) -> usize {
        match self.far_end {
            EndCondition::Clamped => self.nx,
            EndCondition::Free => self.nx + 1,
        }
    }

    /// The dof of node `i`, `None` for an eliminated Dirichlet node.
    pub fn dof_of_node(&self, i: usize) -> Option<usize> {
        (i < self.n_dofs()).then_some(i)
    }

    /// The dof of the contact node `x = 0`.
    pub fn contact_dof(&self) -> usize {
        0
    }

    fn element_dofs(&self, e: usize) -> [Option<usize>; 2] {
        [self.dof_of_node(e), self.dof_of_node(e + 1)]
    }

    /// The mass matrix of the chosen variant (see [`MassVariant`]): element matrix
    /// `ρh/6 [[2, 1], [1, 2]]`; the redistributed variant skips element 0, the one touching the
    /// contact node (§3.2); the extended variants take the contact node's velocity from the
    /// nodes `1, 2` (a clamped node contributes nothing: see [`Bar1d::check_mass`]).
    pub fn mass(&self, variant: MassVariant) -> SymmetricMatrix {
        let me = variant
            .element_matrix(Matrix2::new(2.0, 1.0, 1.0, 2.0) * (self.density * self.h() / 6.0));
        let mut asm = SparseAssembler::new(self.n_dofs());
        for e in 0..self.nx {
            if variant.includes_element(e == 0) {
                asm.add_element(&self.element_dofs(e), &me);
            }
        }
        let contact = self.contact_dof();
        variant.from_consistent(asm.finish(), |d| {
            let ext = variant.contact_extension()?;
            (d == contact).then(|| {
                (ext.weights.iter().enumerate())
                    .filter_map(|(k, &w)| self.dof_of_node(k + 1).map(|dof| (dof, w)))
                    .collect()
            })
        })
    }

    /// Whether `variant` is defined on this bar ([`MassVariant::check_layers`]: the extended
    /// variants need nodes above the contact node that exist and are not clamped).
    pub fn check_mass(&self, variant: MassVariant) -> Result<(), ParameterError> {
        variant.check_layers(self.nx, self.far_end == EndCondition::Clamped, true)
    }

    /// The stiffness matrix: element matrix `E/h [[1, -1], [-1, 1]]`.
    pub fn stiffness(&self) -> SymmetricMatrix {
        let se = Matrix2::new(1.0, -1.0, -1.0, 1.0) * (self.young_modulus() / self.h());
        let mut asm = SparseAssembler::new(self.n_dofs());
        for e in 0..self.nx {
            asm.add_element(&self.element_dofs(e), &se);
        }
        asm.finish()
    }

    /// The load vector `F_i = ∫ f φ_i` of a constant force density `f` (per unit length).
    pub fn load(&self, force_density: f64) -> Vec<f64> {
        let mut f = vec![0.0; self.n_dofs()];
        let half = 0.5 * force_density * self.h();
        for e in 0..self.nx {
            for dof in self.element_dofs(e).into_iter().flatten() {
                f[dof] += half;
            }
        }
        f
    }

    /// The nodal interpolant of `g` as a dof vector.
    pub fn interpolate(&self, g: impl Fn(f64) -> f64) -> Vec<f64> {
        (0..self.n_dofs()).map(|i| g(self.node(i))).collect()
    }

    /// The value of the finite element function with dofs `u` at node `i` (0 at a clamped end).
    pub fn nodal_value(&self, u: &[f64], i: usize) -> f64 {
        self.dof_of_node(i).map_or(0.0, |d| u[d])
    }

    /// Fills `out` with the nodal values of the dof vector `u` at every node, the clamped one
    /// (0) included: [`Bar1d::nodal_value`] node by node, as one copy (node `i < n_dofs` is dof
    /// `i`, [`Bar1d::dof_of_node`]).
    pub fn nodal_values(&self, u: &[f64], out: &mut Vec<f64>) {
        out.clear();
        out.extend_from_slice(&u[..self.n_dofs()]);
        out.resize(self.nx + 1, 0.0);
    }

    /// The P1 function with dofs `u` evaluated at `x ∈ [0, L]`.
    pub fn value_at(&self, u: &[f64], x: f64) -> f64 {
        let e = ((x / self.h()) as usize).min(self.nx - 1);
        let (xa, xb) = (self.node(e), self.node(e + 1));
        let (ua, ub) = (self.nodal_value(u, e), self.nodal_value(u, e + 1));
        ua + (ub - ua) * (x - xa) / (xb - xa)
    }
}
