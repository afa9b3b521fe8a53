//! Structured Q1 finite elements for the 2D/3D bar of the note (§2.1, §3): quadrilaterals on
//! `Ω₂ = [0, L₁] × [0, L₂]`, hexahedra on `Ω₃ = [0, L₁] × [0, L₂] × [0, L₃]`.
//!
//! The **last** coordinate axis is the bar's (vertical) axis: the face `x_d = 0` is the
//! Signorini boundary `Γ_Sig` (the obstacle lies below it, outward normal `ν = −e_d`), the face
//! `x_d = L_d` is the Dirichlet boundary `Γ_Dir` (`u = 0`, its nodes' dofs eliminated, as
//! [`Bar1d`](super::Bar1d) eliminates its clamped node), and the other faces are free
//! (`σ(u)ν = 0`, eq. 3a).
//!
//! The space is `V_h = {v ∈ Q1(T_h)^d : v = 0 on Γ_Dir}` (the note writes "piecewise linear";
//! on squares and cubes the Lagrange elements are bilinear and trilinear). The matrices are
//! those of the semi-discrete problem (5): `M_ij = ρ ∫ φ_i · φ_j`, `S_ij = a(φ_i, φ_j)` with
//! the isotropic Hooke tensor `A_ijkl = λ δ_ij δ_kl + μ (δ_ik δ_jl + δ_il δ_jk)`, and the
//! nodal contact condition on the normal displacement of each node of `Γ_Sig`. The result is a
//! [`Model`](crate::engine::model::Model), the same type the 1D engine uses, so every scheme and contact solver runs on it
//! unchanged.
//!
//! Numbering: nodes are lexicographic with the first coordinate fastest,
//! `node = i₁ + (n₁+1)(i₂ + (n₂+1) i₃)`; dof `node·d + component` for every node off `Γ_Dir`.
//! Because the Dirichlet nodes are the last layer, the kept dofs are exactly `0..n_dofs()`, but
//! callers should go through [`BoxMesh::dof_of`].

use nalgebra::{SMatrix, SVector};
use serde::{Deserialize, Serialize};

use super::separable::{AxisMatrix, SeparablePart};
use super::stencil::Stencil;
use super::{MassVariant, SymmetricMatrix};
use crate::engine::error::{require_positive, ParameterError};

/// VTK cell type of a 4-node quadrilateral (`VTK_QUAD`).
pub const VTK_QUAD: u8 = 9;
/// VTK cell type of an 8-node hexahedron (`VTK_HEXAHEDRON`).
pub const VTK_HEXAHEDRON: u8 = 12;

/// Corners of the reference square `[−1, 1]²` in VTK_QUAD order (counter-clockwise).
pub const QUAD_CORNERS: [[f64; 2]; 4] = [[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]];

/// Corners of the reference cube `[−1, 1]³` in VTK_HEXAHEDRON order (the face `ξ₃ = −1`
/// counter-clockwise, then the face `ξ₃ = +1`).
pub const HEX_CORNERS: [[f64; 3]; 8] = [
    [-1.0, -1.0, -1.0],
    [1.0, -1.0, -1.0],
    [1.0, 1.0, -1.0],
    [-1.0, 1.0, -1.0],
    [-1.0, -1.0, 1.0],
    [1.0, -1.0, 1.0],
    [1.0, 1.0, 1.0],
    [-1.0, 1.0, 1.0],
];

/// A homogeneous isotropic linear elastic material (note §1, eq. 1):
/// `σ(u) = λ tr(ε(u)) I + 2μ ε(u)`, density `ρ`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Elasticity {
    /// Mass density `ρ > 0`.
    pub density: f64,
    /// First Lamé parameter `λ` (the note's §3: `λ = 0.25`).
    pub lame_lambda: f64,
    /// Shear modulus, the second Lamé parameter `μ > 0` (the note's §3: `μ = 0.5`).
    pub lame_mu: f64,
}

impl Elasticity {
    /// The note's material (§3): `ρ = 1`, `λ = 0.25`, `μ = 0.5`.
    pub const NOTE: Elasticity = Elasticity {
        density: 1.0,
        lame_lambda: 0.25,
        lame_mu: 0.5,
    };

    /// Checks that the energy `½ a(u, u) = ∫ μ |ε|² + ½ λ (tr ε)²` is positive definite in
    /// dimension `dim` and the density positive: `ρ > 0`, `μ > 0` and `λ + 2μ/d > 0` (the bulk
    /// modulus). The error names the field (`density`, `lame_mu`, `lame_lambda`).
    ///
    /// The bound depends on `d` (plane strain in 2D needs only `λ + μ > 0`), hence the argument.
    pub fn validate(&self, dim: usize) -> Result<(), ParameterError> {
        require_positive("density", self.density)?;
        require_positive("lame_mu", self.lame_mu)?;
        let bulk = self.lame_lambda + 2.0 * self.lame_mu / dim as f64;
        if !(self.lame_lambda.is_finite() && bulk > 0.0) {
            return Err(ParameterError::new(
                "lame_lambda",
                self.lame_lambda,
                "a finite number with lame_lambda + 2 lame_mu / d > 0 (positive bulk modulus)",
            ));
        }
        Ok(())
    }

    /// Young's modulus `E = μ(3λ + 2μ)/(λ + μ)` (uniaxial stress, 3D).
    pub fn young_modulus(&self) -> f64 {
        let (l, m) = (self.lame_lambda, self.lame_mu);
        m * (3.0 * l + 2.0 * m) / (l + m)
    }
}

/// The element stiffness `K_e = ∫_K Bᵀ D B dx` of a Q1 quadrilateral (plane strain) with corners
/// `coords` in VTK_QUAD order, 2×2 Gauss quadrature. Voigt strain `(ε₁₁, ε₂₂, γ₁₂)` with the
/// engineering shear `γ₁₂ = 2ε₁₂`; `D` is the Hooke tensor of eq. (1) in that notation. Local
/// dof `2a + c` is component `c` of corner `a`.
pub fn quad_stiffness(coords: &[[f64; 2]; 4], elasticity: &Elasticity) -> SMatrix<f64, 8, 8> {
    element_stiffness::<2, 4, 8, 3>(coords, &QUAD_CORNERS, elasticity)
}

/// The element stiffness `K_e = ∫_K Bᵀ D B dx` of a Q1 hexahedron with corners `coords` in
/// VTK_HEXAHEDRON order, 2×2×2 Gauss quadrature. Voigt strain
/// `(ε₁₁, ε₂₂, ε₃₃, γ₂₃, γ₁₃, γ₁₂)`, engineering shears. Local dof `3a + c`.
pub fn hex_stiffness(coords: &[[f64; 3]; 8], elasticity: &Elasticity) -> SMatrix<f64, 24, 24> {
    element_stiffness::<3, 8, 24, 6>(coords, &HEX_CORNERS, elasticity)
}

/// The consistent element mass `M_e = ρ ∫_K Nᵀ N dx` of a Q1 quadrilateral (the element part
/// of `M_ij = ρ ∫ φ_i · φ_j`, eq. 5), 2×2 Gauss quadrature (exact for parallelograms).
pub fn quad_mass(coords: &[[f64; 2]; 4], density: f64) -> SMatrix<f64, 8, 8> {
    element_mass::<2, 4, 8>(coords, &QUAD_CORNERS, density)
}

/// The consistent element mass `M_e = ρ ∫_K Nᵀ N dx` of a Q1 hexahedron, 2×2×2 Gauss
/// quadrature.
pub fn hex_mass(coords: &[[f64; 3]; 8], density: f64) -> SMatrix<f64, 24, 24> {
    element_mass::<3, 8, 24>(coords, &HEX_CORNERS, density)
}

/// The isotropic Hooke matrix in Voigt notation with engineering shears: `λ + 2μ` on the normal
/// diagonal, `λ` off it, `μ` on the shear diagonal.
fn hooke<const D: usize, const V: usize>(e: &Elasticity) -> SMatrix<f64, V, V> {
    let mut d = SMatrix::<f64, V, V>::zeros();
    for i in 0..D {
        for j in 0..D {
            d[(i, j)] = e.lame_lambda;
        }
        d[(i, i)] += 2.0 * e.lame_mu;
    }
    for s in D..V {
        d[(s, s)] = e.lame_mu;
    }
    d
}

/// The coordinate pairs `(p, q)` of the shear strains `γ_pq`, in Voigt order after the normal
/// strains.
fn shear_pairs(dim: usize) -> &'static [(usize, usize)] {
    if dim == 2 {
        &[(0, 1)]
    } else {
        &[(1, 2), (0, 2), (0, 1)]
    }
}

/// Shape functions `N_a(ξ) = Π_i (1 + s_{a,i} ξ_i)/2` and their reference derivatives
/// `∂N_a/∂ξ_k` (rows `k`, columns `a`).
fn reference_shape<const D: usize, const N: usize>(
    corners: &[[f64; D]; N],
    xi: &[f64; D],
) -> (SVector<f64, N>, SMatrix<f64, D, N>) {
    let mut values = SVector::<f64, N>::zeros();
    let mut derivs = SMatrix::<f64, D, N>::zeros();
    for (a, s) in corners.iter().enumerate() {
        let factors: [f64; D] = std::array::from_fn(|i| 0.5 * (1.0 + s[i] * xi[i]));
        values[a] = factors.iter().product();
        for k in 0..D {
            let others: f64 = (0..D).filter(|&i| i != k).map(|i| factors[i]).product();
            derivs[(k, a)] = 0.5 * s[k] * others;
        }
    }
    (values, derivs)
}

/// Values, physical gradients `∂N_a/∂x_j` (rows `j`) and `det J` at `ξ`, with the general
/// Jacobian `J = (∂N/∂ξ) X`, `J_kj = ∂x_j/∂ξ_k`, so that `∂N/∂x = J⁻¹ ∂N/∂ξ`.
fn physical_shape<const D: usize, const N: usize>(
    coords: &[[f64; D]; N],
    corners: &[[f64; D]; N],
    xi: &[f64; D],
) -> (SVector<f64, N>, SMatrix<f64, D, N>, f64) {
    let (values, dn) = reference_shape(corners, xi);
    let x = SMatrix::<f64, N, D>::from_fn(|a, j| coords[a][j]);
    let jac = dn * x;
    let (det, inverse) = determinant_and_inverse(&jac);
    (values, inverse * dn, det)
}

/// `det J` and `J⁻¹ = Cᵀ / det J` (cofactor matrix `C`) of a 2×2 or 3×3 matrix. (nalgebra's
/// `determinant` and `try_inverse` are not available for a generic `Const<D>`.)
fn determinant_and_inverse<const D: usize>(j: &SMatrix<f64, D, D>) -> (f64, SMatrix<f64, D, D>) {
    let cofactor = |r: usize, c: usize| -> f64 {
        if D == 2 {
            let sign = if (r + c) % 2 == 0 { 1.0 } else { -1.0 };
            sign * j[(1 - r, 1 - c)]
        } else {
            let (r1, r2, c1, c2) = ((r + 1) % 3, (r + 2) % 3, (c + 1) % 3, (c + 2) % 3);
            j[(r1, c1)] * j[(r2, c2)] - j[(r1, c2)] * j[(r2, c1)]
        }
    };
    let det: f64 = (0..D).map(|c| j[(0, c)] * cofactor(0, c)).sum();
    assert!(
        det > 0.0,
        "a Q1 element with corners in VTK order has det J > 0 (got {det})"
    );
    (
        det,
        SMatrix::<f64, D, D>::from_fn(|r, c| cofactor(c, r) / det),
    )
}

/// The Gauss points `ξ ∈ {±1/√3}^D` (all weights 1).
fn gauss_points<const D: usize>() -> impl Iterator<Item = [f64; D]> {
    let g = 1.0 / 3f64.sqrt();
    (0..1usize << D)
        .map(move |bits| std::array::from_fn(|i| if bits >> i & 1 == 1 { g } else { -g }))
}

/// The strain-displacement matrix `B` (`ε_Voigt = B u_e`) from the physical gradients.
fn strain_matrix<const D: usize, const N: usize, const ND: usize, const V: usize>(
    grad: &SMatrix<f64, D, N>,
) -> SMatrix<f64, V, ND> {
    let pairs = shear_pairs(D);
    debug_assert_eq!(ND, N * D);
    debug_assert_eq!(V, D + pairs.len());
    let mut b = SMatrix::<f64, V, ND>::zeros();
    for a in 0..N {
        for i in 0..D {
            b[(i, a * D + i)] = grad[(i, a)];
        }
        for (s, &(p, q)) in pairs.iter().enumerate() {
            b[(D + s, a * D + p)] = grad[(q, a)];
            b[(D + s, a * D + q)] = grad[(p, a)];
        }
    }
    b
}

fn element_stiffness<const D: usize, const N: usize, const ND: usize, const V: usize>(
    coords: &[[f64; D]; N],
    corners: &[[f64; D]; N],
    elasticity: &Elasticity,
) -> SMatrix<f64, ND, ND> {
    let d = hooke::<D, V>(elasticity);
    let mut k = SMatrix::<f64, ND, ND>::zeros();
    for xi in gauss_points::<D>() {
        let (_, grad, det) = physical_shape(coords, corners, &xi);
        let b = strain_matrix::<D, N, ND, V>(&grad);
        k += b.transpose() * d * b * det;
    }
    // `Bᵀ D B` is symmetric only up to round-off; make it exact so that the assembled matrix
    // is exactly symmetric (SymmetricMatrix reads row i as column i).
    (k + k.transpose()) * 0.5
}

fn element_mass<const D: usize, const N: usize, const ND: usize>(
    coords: &[[f64; D]; N],
    corners: &[[f64; D]; N],
    density: f64,
) -> SMatrix<f64, ND, ND> {
    let mut scalar = SMatrix::<f64, N, N>::zeros();
    for xi in gauss_points::<D>() {
        let (values, _, det) = physical_shape(coords, corners, &xi);
        scalar += values * values.transpose() * (density * det);
    }
    SMatrix::<f64, ND, ND>::from_fn(|i, j| {
        if i % D == j % D {
            scalar[(i / D, j / D)]
        } else {
            0.0
        }
    })
}

/// The strain `ε_Voigt` at the element centre `ξ = 0` and the Hooke matrix applied to it.
fn centre_stress<const D: usize, const N: usize, const ND: usize, const V: usize>(
    coords: &[[f64; D]; N],
    corners: &[[f64; D]; N],
    u_e: &SVector<f64, ND>,
    elasticity: &Elasticity,
) -> (SVector<f64, V>, SVector<f64, V>) {
    let (_, grad, _) = physical_shape(coords, corners, &[0.0; D]);
    let strain = strain_matrix::<D, N, ND, V>(&grad) * u_e;
    (strain, hooke::<D, V>(elasticity) * strain)
}

/// The von Mises stress of a symmetric 3×3 stress given by its components:
/// `√(½[(σ₁₁−σ₂₂)² + (σ₂₂−σ₃₃)² + (σ₃₃−σ₁₁)²] + 3(σ₁₂² + σ₂₃² + σ₁₃²))`.
fn von_mises_of(normal: [f64; 3], shear: [f64; 3]) -> f64 {
    let [s11, s22, s33] = normal;
    let deviatoric = 0.5 * ((s11 - s22).powi(2) + (s22 - s33).powi(2) + (s33 - s11).powi(2));
    let shear: f64 = shear.iter().map(|t| t * t).sum();
    (deviatoric + 3.0 * shear).sqrt()
}

/// A structured Q1 mesh of the box `[0, L₁] × … × [0, L_d]`, `d ∈ {2, 3}`, with the space
/// `V_h` (Dirichlet face `x_d = L_d` eliminated) and the contact face `x_d = 0` (note §2.1).
///
/// Its nodes, elements and dofs are numbered lexicographically, the first axis fastest, and
/// computed from the grid index when asked for: the mesh holds its lengths and counts only,
/// so a box of any size costs nothing until a vector or matrix is built on it (a rank of a
/// distributed run builds only its slab's).
#[derive(Debug, Clone, PartialEq)]
pub struct BoxMesh {
    dim: usize,
    lengths: Vec<f64>,
    counts: Vec<usize>,
}

/// The corner nodes of an element, in VTK_QUAD / VTK_HEXAHEDRON order ([`BoxMesh::element`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ElementNodes {
    nodes: [usize; 8],
    len: usize,
}

impl std::ops::Deref for ElementNodes {
    type Target = [usize];

    fn deref(&self) -> &[usize] {
        &self.nodes[..self.len]
    }
}

impl IntoIterator for ElementNodes {
    type Item = usize;
    type IntoIter = std::iter::Take<std::array::IntoIter<usize, 8>>;

    fn into_iter(self) -> Self::IntoIter {
        self.nodes.into_iter().take(self.len)
    }
}

impl BoxMesh {
    /// The box `Π [0, lengths[k]]` with `counts[k]` elements in direction `x_{k+1}`. Errors:
    /// `lengths` (not 2 or 3 values, or a value not finite > 0) and `elements` (not one count
    /// per direction, or a count of 0); the value names the direction.
    pub fn new(lengths: &[f64], counts: &[usize]) -> Result<Self, ParameterError> {
        let dim = lengths.len();
        if !(2..=3).contains(&dim) {
            return Err(ParameterError::new(
                "lengths",
                format!("{lengths:?}"),
                "2 or 3 values (the dimension d of the box)",
            ));
        }
        if counts.len() != dim {
            return Err(ParameterError::new(
                "elements",
                format!("{counts:?}"),
                "one count per direction (as many as lengths)",
            ));
        }
        for (k, &l) in lengths.iter().enumerate() {
            if !(l.is_finite() && l > 0.0) {
                return Err(ParameterError::new(
                    "lengths",
                    format!("{l} in direction x{}", k + 1),
                    "a finite number > 0",
                ));
            }
        }
        for (k, &n) in counts.iter().enumerate() {
            if n == 0 {
                return Err(ParameterError::new(
                    "elements",
                    format!("{n} in direction x{}", k + 1),
                    "an integer >= 1",
                ));
            }
        }

        Ok(Self {
            dim,
            lengths: lengths.to_vec(),
            counts: counts.to_vec(),
        })
    }

    /// The note's 2D bar (§3): `Ω₂ = [0, 0.1] × [0, 1]` with `n₁ × n₂` elements.
    pub fn note_2d(n1: usize, n2: usize) -> Result<Self, ParameterError> {
        Self::new(&[0.1, 1.0], &[n1, n2])
    }

    /// The note's 3D bar (§3): `Ω₃ = [0, 0.1]² × [0, 1]` with `n₁ × n₂ × n₃` elements.
    pub fn note_3d(n1: usize, n2: usize, n3: usize) -> Result<Self, ParameterError> {
        Self::new(&[0.1, 0.1, 1.0], &[n1, n2, n3])
    }

    /// The dimension `d`.
    pub fn dim(&self) -> usize {
        self.dim
    }

    /// The box lengths `L₁, …, L_d`.
    pub fn lengths(&self) -> &[f64] {
        &self.lengths
    }

    /// The numbers of elements per direction `n₁, …, n_d`.
    pub fn counts(&self) -> &[usize] {
        &self.counts
    }

    /// The element sizes `h_k = L_k / n_k`.
    pub fn element_sizes(&self) -> Vec<f64> {
        self.lengths
            .iter()
            .zip(&self.counts)
            .map(|(l, &n)| l / n as f64)
            .collect()
    }

    /// Number of nodes `Π (n_k + 1)`, Dirichlet nodes included.
    pub fn n_nodes(&self) -> usize {
        self.nodes_per_axis().iter().product()
    }

    /// The nodes off `Γ_Dir`, which carry the dofs: those below the last layer along the
    /// axis, the first `Π_{k<d} (n_k + 1) · n_d` in the numbering.
    fn kept_nodes(&self) -> usize {
        self.counts[..self.dim - 1]
            .iter()
            .map(|n| n + 1)
            .product::<usize>()
            * self.counts[self.dim - 1]
    }

    /// Number of elements `Π n_k`.
    pub fn n_elements(&self) -> usize {
        self.counts.iter().product()
    }

    /// Number of corners per element: 4 (quadrilateral) or 8 (hexahedron).
    pub fn nodes_per_element(&self) -> usize {
        1 << self.dim
    }

    /// The VTK cell type of the elements: [`VTK_QUAD`] or [`VTK_HEXAHEDRON`].
    pub fn vtk_cell_type(&self) -> u8 {
        if self.dim == 2 {
            VTK_QUAD
        } else {
            VTK_HEXAHEDRON
        }
    }

    /// Number of unknowns: `d` per node off `Γ_Dir`.
    pub fn n_dofs(&self) -> usize {
        self.dim * self.kept_nodes()
    }

    /// The coordinates of `node`, always three (`x₃ = 0` in 2D, as VTK wants): `i_k L_k / n_k`
    /// of its grid index, exactly `L_k` on the last face.
    pub fn node(&self, node: usize) -> [f64; 3] {
        let index = self.node_index(node);
        let mut x = [0.0; 3];
        for k in 0..self.dim {
            x[k] = if index[k] == self.counts[k] {
                self.lengths[k]
            } else {
                index[k] as f64 * self.lengths[k] / self.counts[k] as f64
            };
        }
        x
    }

    /// Every node's coordinates ([`BoxMesh::node`]), in the numbering's order.
    pub fn nodes(&self) -> impl ExactSizeIterator<Item = [f64; 3]> + '_ {
        (0..self.n_nodes()).map(|node| self.node(node))
    }

    /// The grid index `(i₁, …, i_d)` of a node (`i_k ∈ 0..=n_k`; the unused third entry is 0
    /// in 2D).
    pub fn node_index(&self, node: usize) -> [usize; 3] {
        unflatten(node, &self.nodes_per_axis()[..self.dim])
    }

    /// Nodes per axis, `n_k + 1` (1 on an unused third axis).
    fn nodes_per_axis(&self) -> [usize; 3] {
        let mut per_axis = [1; 3];
        for (p, n) in per_axis.iter_mut().zip(&self.counts) {
            *p = n + 1;
        }
        per_axis
    }

    /// The node indices of every element ([`BoxMesh::element`]), in the elements' order.
    pub fn elements(&self) -> impl ExactSizeIterator<Item = ElementNodes> + '_ {
        (0..self.n_elements()).map(|e| self.element(e))
    }

    /// The nodes of element `e` in VTK_QUAD / VTK_HEXAHEDRON order (the element matrices'
    /// local order: local dof `a·d + c` is component `c` of the `a`-th node listed): the
    /// element's lowest grid corner shifted by each corner of the reference element.
    pub fn element(&self, e: usize) -> ElementNodes {
        let per_axis = self.nodes_per_axis();
        let base = unflatten(e, &self.counts);
        let corners: &[[f64; 3]] = if self.dim == 2 {
            &[
                [-1.0, -1.0, 0.0],
                [1.0, -1.0, 0.0],
                [1.0, 1.0, 0.0],
                [-1.0, 1.0, 0.0],
            ]
        } else {
            &HEX_CORNERS
        };
        let mut nodes = [0; 8];
        for (node, s) in nodes.iter_mut().zip(corners) {
            let mut index = [0usize; 3];
            for k in 0..self.dim {
                index[k] = base[k] + usize::from(s[k] > 0.0);
            }
            *node = flatten(&index[..self.dim], &per_axis[..self.dim]);
        }
        ElementNodes {
            nodes,
            len: corners.len(),
        }
    }

    /// The dof of component `component` of `node`; `None` on `Γ_Dir` (eliminated). The dofs
    /// follow the nodes, `d` per node: `node · d + component` below the last layer.
    pub fn dof_of(&self, node: usize, component: usize) -> Option<usize> {
        assert!(component < self.dim, "component {component} >= d");
        (node < self.kept_nodes()).then_some(node * self.dim + component)
    }

    /// Whether `node` lies on `Γ_Sig` (`x_d = 0`).
    pub fn on_contact_boundary(&self, node: usize) -> bool {
        self.node_index(node)[self.dim - 1] == 0
    }

    /// Whether `node` lies on `Γ_Dir` (`x_d = L_d`).
    pub fn on_dirichlet_boundary(&self, node: usize) -> bool {
        self.node_index(node)[self.dim - 1] == self.counts[self.dim - 1]
    }

    /// Whether `node` lies on any face of the box.
    pub fn on_boundary(&self, node: usize) -> bool {
        self.node_index(node)
            .iter()
            .zip(&self.counts)
            .any(|(&i, &n)| i == 0 || i == n)
    }

    /// The nodes of `Γ_Sig` (`x_d = 0`), in increasing order: the first `Π_{k<d} (n_k + 1)`.
    pub fn contact_nodes(&self) -> Vec<usize> {
        let layer: usize = self.counts[..self.dim - 1].iter().map(|n| n + 1).product();
        (0..layer).collect()
    }

    /// The contact node nearest the centre of `Γ_Sig` (the first in [`Self::contact_nodes`]'s
    /// order among equals): its index in that list.
    pub fn face_centre(&self) -> usize {
        let d = self.dim;
        let mid: Vec<f64> = self.lengths[..d - 1].iter().map(|l| 0.5 * l).collect();
        let distance = |k: usize| {
            let x = self.node(k);
            mid.iter()
                .enumerate()
                .map(|(i, m)| (x[i] - m).powi(2))
                .sum::<f64>()
        };
        (0..self.contact_nodes().len())
            .min_by(|&a, &b| distance(a).total_cmp(&distance(b)))
            .unwrap_or(0)
    }

    /// `a = ∫_{Γ_Sig} φ` of the shape function of contact node `node`: `Π_{k<d} h_k`, halved
    /// along each axis where the node is on the face's edge (the lumped face mass that turns a
    /// nodal force into a pressure, [`crate::harness::external::mesh::ContactFace`]).
    pub fn face_share(&self, node: usize) -> f64 {
        let index = self.node_index(node);
        let sizes = self.element_sizes();
        (0..self.dim - 1)
            .map(|k| match index[k] == 0 || index[k] == self.counts[k] {
                true => 0.5 * sizes[k],
                false => sizes[k],
            })
            .product()
    }

    /// Whether element `e` touches `Γ_Sig` (has a node on `x_d = 0`): its layer along `x_d` is
    /// the first. These are the elements removed from `Ω^mod_{d,h}` (note §2.1).
    pub fn touches_contact_boundary(&self, e: usize) -> bool {
        unflatten(e, &self.counts)[self.dim - 1] == 0
    }

    /// The global dofs of element `e` in local order (`None` for eliminated dofs).
    fn element_dofs<const ND: usize>(&self, e: usize) -> [Option<usize>; ND] {
        let nodes = self.element(e);
        std::array::from_fn(|i| self.dof_of(nodes[i / self.dim], i % self.dim))
    }

    /// The corner coordinates of element `e` in local order.
    fn element_coords<const D: usize, const N: usize>(&self, e: usize) -> [[f64; D]; N] {
        let nodes = self.element(e);
        std::array::from_fn(|a| {
            let x = self.node(nodes[a]);
            std::array::from_fn(|k| x[k])
        })
    }

    fn assemble<const D: usize, const N: usize, const ND: usize>(
        &self,
        element_matrix: impl Fn(&[[f64; D]; N]) -> SMatrix<f64, ND, ND>,
        include: impl Fn(usize) -> bool,
    ) -> SymmetricMatrix {
        // The upper triangle's contributions `(column · n + row, value)`, in element order.
        let n = self.n_dofs();
        let mut upper: Vec<(usize, f64)> =
            Vec::with_capacity(self.n_elements() * ND * (ND + 1) / 2);
        for e in (0..self.n_elements()).filter(|&e| include(e)) {
            let matrix = element_matrix(&self.element_coords::<D, N>(e));
            let dofs = self.element_dofs::<ND>(e);
            for (a, da) in dofs.iter().enumerate() {
                let Some(i) = *da else { continue };
                for (b, db) in dofs.iter().enumerate() {
                    match *db {
                        Some(j) if i <= j => upper.push((j * n + i, matrix[(a, b)])),
                        _ => {}
                    }
                }
            }
        }
        SymmetricMatrix::from_upper_contributions(n, upper)
    }

    /// The mass matrix `M_ij = ρ ∫_Ω φ_i · φ_j` (eq. 5), or for
    /// [`MassVariant::Redistributed`] the note's `M^mod_ij = ρ ∫_{Ω^mod_{d,h}} φ_i · φ_j` with
    /// `Ω^mod_{d,h}` the elements that do not touch `Γ_Sig` (§2.1).
    ///
    /// With `M^mod`, a node of `Γ_Sig` belongs only to removed elements, so **every** component
    /// of it (normal and tangential) has a zero row and column: `ker M^mod` is spanned by the
    /// `d · #(Γ_Sig nodes)` unit vectors of those dofs, not by the normals `ν_i` alone as the
    /// note states. (With one element layer, `n_d = 1`, every element is removed and `M^mod = 0`.)
    ///
    /// The lumped and extended variants ([`MassVariant`]) are built from the consistent matrix;
    /// the extension of a node `(a, 0)` of `Γ_Sig` reads the same component of the nodes
    /// `(a, 1)`, `(a, 2)` straight above it (node `a + k·#Γ_Sig` in the lexicographic order).
    pub fn mass(&self, variant: MassVariant, density: f64) -> SymmetricMatrix {
        let include = |e| variant.includes_element(self.touches_contact_boundary(e));
        let consistent = match self.dim {
            2 => {
                self.assemble::<2, 4, 8>(|x| variant.element_matrix(quad_mass(x, density)), include)
            }
            _ => {
                self.assemble::<3, 8, 24>(|x| variant.element_matrix(hex_mass(x, density)), include)
            }
        };
        let layer = self.contact_nodes().len();
        let contact_dofs: Vec<Option<(usize, usize)>> = {
            let mut owner = vec![None; self.n_dofs()];
            for node in 0..layer {
                for c in 0..self.dim {
                    if let Some(d) = self.dof_of(node, c) {
                        owner[d] = Some((node, c));
                    }
                }
            }
            owner
        };
        variant.from_consistent(consistent, |d| {
            let ext = variant.contact_extension()?;
            let (node, c) = contact_dofs[d]?;
            Some(
                (ext.weights.iter().enumerate())
                    .filter(|&(k, _)| k < self.counts[self.dim - 1])
                    .filter_map(|(k, &w)| self.dof_of(node + (k + 1) * layer, c).map(|j| (j, w)))
                    .collect(),
            )
        })
    }

    /// The mass matrix of [`BoxMesh::mass`] stored matrix-free ([`Stencil`]), for the variants
    /// built element by element (`standard`, `redistributed`, `lumped`); `None` for the
    /// extended ones, which edit the assembled matrix.
    pub fn mass_stencil(&self, variant: MassVariant, density: f64) -> Option<SymmetricMatrix> {
        if variant.contact_extension().is_some() {
            return None;
        }
        let without_first_layer = !variant.includes_element(true);
        let stencil = match self.dim {
            2 => self.stencil_of(
                &variant.element_matrix(quad_mass(&self.element_coords(0), density)),
                without_first_layer,
            ),
            _ => self.stencil_of(
                &variant.element_matrix(hex_mass(&self.element_coords(0), density)),
                without_first_layer,
            ),
        };
        Some(SymmetricMatrix::from_stencil(match variant {
            MassVariant::Lumped => stencil,
            _ => {
                stencil.with_separable_part(self.mass_separable_part(density, without_first_layer))
            }
        }))
    }

    /// The matrix-free operator of the element matrix `element` (every element's: they are
    /// translates of element 0), the first element layer left out when `without_first_layer`.
    fn stencil_of<const ND: usize>(
        &self,
        element: &SMatrix<f64, ND, ND>,
        without_first_layer: bool,
    ) -> Stencil {
        Stencil::from_element(&self.counts, |p, q| element[(p, q)], without_first_layer)
    }

    /// The 1D factors `M_k` of the consistent mass ([`AxisMatrix::p1_mass`]), the first axis
    /// first: free ends on the faces across the axis; along it a free end on `Γ_Sig` and both
    /// elements at the last kept layer (the next is eliminated). For `M^mod`
    /// (`without_first_layer`) the axial factor leaves out the first element: zero on `Γ_Sig`.
    fn mass_axes(&self, without_first_layer: bool) -> Vec<AxisMatrix> {
        let d = self.dim;
        let sizes = self.element_sizes();
        (0..d)
            .map(|k| {
                let (n, h) = (self.counts[k], sizes[k]);
                if k + 1 < d {
                    return AxisMatrix::p1_mass(n + 1, h, true, true);
                }
                let mut axis = AxisMatrix::p1_mass(n, h, true, false);
                if without_first_layer {
                    axis.diag[0] = 0.0;
                    if n > 1 {
                        axis.diag[1] = h / 3.0;
                        axis.off[0] = 0.0;
                    }
                }
                axis
            })
            .collect()
    }

    /// The separable part of the mass (`ρ ⊗ M_k`, [`SeparablePart`]).
    fn mass_separable_part(&self, density: f64, without_first_layer: bool) -> SeparablePart {
        SeparablePart {
            components: self.dim,
            mass_scale: density,
            mass_axes: self.mass_axes(without_first_layer),
            coefficients: Vec::new(),
            stiffness_axes: Vec::new(),
        }
    }

    /// The separable part of the stiffness: `E_cc = λ + 2μ`, `E_ck = μ` with the 1D
    /// stiffnesses ([`AxisMatrix::p1_stiffness`], free ends where the mass has them).
    fn stiffness_separable_part(&self, e: &Elasticity) -> SeparablePart {
        let d = self.dim;
        let sizes = self.element_sizes();
        let stiffness_axes = (0..d)
            .map(|k| {
                let last = k + 1 == d;
                let nodes = self.counts[k] + usize::from(!last);
                AxisMatrix::p1_stiffness(nodes, sizes[k], true, !last)
            })
            .collect();
        let coefficients = (0..d * d)
            .map(|ck| {
                if ck / d == ck % d {
                    e.lame_lambda + 2.0 * e.lame_mu
                } else {
                    e.lame_mu
                }
            })
            .collect();
        SeparablePart {
            components: d,
            mass_scale: 0.0,
            mass_axes: self.mass_axes(false),
            coefficients,
            stiffness_axes,
        }
    }

    /// The stiffness matrix of [`BoxMesh::stiffness`] stored matrix-free ([`Stencil`]).
    pub fn stiffness_stencil(&self, elasticity: &Elasticity) -> SymmetricMatrix {
        let stencil = match self.dim {
            2 => self.stencil_of(&quad_stiffness(&self.element_coords(0), elasticity), false),
            _ => self.stencil_of(&hex_stiffness(&self.element_coords(0), elasticity), false),
        };
        SymmetricMatrix::from_stencil(
            stencil.with_separable_part(self.stiffness_separable_part(elasticity)),
        )
    }

    /// Whether `variant` is defined on this mesh ([`MassVariant::check_layers`] with the
    /// `n_d` element layers between `Γ_Sig` and `Γ_Dir`).
    pub fn check_mass(&self, variant: MassVariant) -> Result<(), ParameterError> {
        variant.check_layers(self.counts[self.dim - 1], true, false)
    }

    /// The stiffness matrix `S_ij = a(φ_i, φ_j) = ∫_Ω A ε(φ_i) : ε(φ_j)` (eq. 4–5), plane strain
    /// in 2D. The material is assumed valid ([`Elasticity::validate`]); otherwise `S` is not
    /// positive definite.
    pub fn stiffness(&self, elasticity: &Elasticity) -> SymmetricMatrix {
        match self.dim {
            2 => self.assemble::<2, 4, 8>(|x| quad_stiffness(x, elasticity), |_| true),
            _ => self.assemble::<3, 8, 24>(|x| hex_stiffness(x, elasticity), |_| true),
        }
    }

    /// The normal-displacement dof of every node of `Γ_Sig`, in increasing node order: the
    /// constrained dofs of the nodal contact condition of (5).
    pub fn contact_dofs(&self) -> Vec<usize> {
        self.contact_nodes()
            .into_iter()
            .map(|node| {
                self.dof_of(node, self.dim - 1)
                    .expect("contact nodes are off the Dirichlet face")
            })
            .collect()
    }

    /// The full nodal displacement `u_h(a_i)` from the dofs `u`: zero at the Dirichlet nodes,
    /// three components (the third zero in 2D) as VTK wants.
    pub fn nodal_vector(&self, u: &[f64]) -> Vec<[f64; 3]> {
        assert_eq!(u.len(), self.n_dofs(), "dof vector length");
        (0..self.n_nodes())
            .map(|node| {
                let mut value = [0.0; 3];
                for (c, v) in value.iter_mut().enumerate().take(self.dim) {
                    if let Some(dof) = self.dof_of(node, c) {
                        *v = u[dof];
                    }
                }
                value
            })
            .collect()
    }

    /// The nodal interpolant `Σ_i f(a_i)·φ_i` as a dof vector: `f` gets the node's `d`
    /// coordinates and returns three components, of which the first `d` are used. Values at
    /// the Dirichlet nodes are ignored (those dofs are eliminated).
    pub fn interpolate(&self, f: impl Fn(&[f64]) -> [f64; 3]) -> Vec<f64> {
        let mut u = vec![0.0; self.n_dofs()];
        for (node, x) in self.nodes().enumerate() {
            if self.dof_of(node, 0).is_none() {
                continue;
            }
            let value = f(&x[..self.dim]);
            for (c, v) in value.iter().enumerate().take(self.dim) {
                if let Some(dof) = self.dof_of(node, c) {
                    u[dof] = *v;
                }
            }
        }
        u
    }

    /// Per element: (tensor strain `[ε₁₁, ε₂₂, ε₃₃, ε₂₃, ε₁₃, ε₁₂]`, stress
    /// `[σ₁₁, σ₂₂, σ₃₃, σ₂₃, σ₁₃, σ₁₂]`) at the centre; plane strain in 2D
    /// (`ε₃₃ = 0`, `σ₃₃ = λ(ε₁₁ + ε₂₂)`).
    fn centre_fields(&self, u: &[f64], e: &Elasticity) -> Vec<([f64; 6], [f64; 6])> {
        let nodal = self.nodal_vector(u);
        (0..self.n_elements())
            .map(|el| {
                let nodes = self.element(el);
                if self.dim == 2 {
                    let u_e = SVector::<f64, 8>::from_fn(|i, _| nodal[nodes[i / 2]][i % 2]);
                    let (eps, sig) = centre_stress::<2, 4, 8, 3>(
                        &self.element_coords::<2, 4>(el),
                        &QUAD_CORNERS,
                        &u_e,
                        e,
                    );
                    let s33 = e.lame_lambda * (eps[0] + eps[1]);
                    (
                        [eps[0], eps[1], 0.0, 0.0, 0.0, 0.5 * eps[2]],
                        [sig[0], sig[1], s33, 0.0, 0.0, sig[2]],
                    )
                } else {
                    let u_e = SVector::<f64, 24>::from_fn(|i, _| nodal[nodes[i / 3]][i % 3]);
                    let (eps, sig) = centre_stress::<3, 8, 24, 6>(
                        &self.element_coords::<3, 8>(el),
                        &HEX_CORNERS,
                        &u_e,
                        e,
                    );
                    (
                        [
                            eps[0],
                            eps[1],
                            eps[2],
                            0.5 * eps[3],
                            0.5 * eps[4],
                            0.5 * eps[5],
                        ],
                        [sig[0], sig[1], sig[2], sig[3], sig[4], sig[5]],
                    )
                }
            })
            .collect()
    }

    /// The von Mises stress `√(3/2 s : s)`, `s = σ − ⅓ tr(σ) I`, at the centre of each element
    /// (note §3.1, Figures 4–5), with `σ = λ tr(ε) I + 2μ ε` of `u_h`. In 2D, plane strain:
    /// `σ₃₃ = λ(ε₁₁ + ε₂₂)` enters the 3D formula.
    pub fn von_mises(&self, u: &[f64], elasticity: &Elasticity) -> Vec<f64> {
        self.centre_fields(u, elasticity)
            .into_iter()
            .map(|(_, s)| von_mises_of([s[0], s[1], s[2]], [s[3], s[4], s[5]]))
            .collect()
    }

    /// The nodal average of a per-element field: at each node, the mean over the elements that
    /// contain it (for VTK point data).
    pub fn nodal_average(&self, per_element: &[f64]) -> Vec<f64> {
        assert_eq!(
            per_element.len(),
            self.n_elements(),
            "one value per element"
        );
        let mut sum = vec![0.0; self.n_nodes()];
        let mut count = vec![0usize; self.n_nodes()];
        for (nodes, &v) in self.elements().zip(per_element) {
            for n in nodes {
                sum[n] += v;
                count[n] += 1;
            }
        }
        sum.iter().zip(&count).map(|(s, &c)| s / c as f64).collect()
    }
}

/// The lexicographic index of a grid point (first coordinate fastest).
fn flatten(index: &[usize], sizes: &[usize]) -> usize {
    index
        .iter()
        .zip(sizes)
        .rev()
        .fold(0, |acc, (&i, &n)| acc * n + i)
}

/// The grid point of a lexicographic index (first coordinate fastest); unused axes are 0.
fn unflatten(mut flat: usize, sizes: &[usize]) -> [usize; 3] {
    let mut index = [0; 3];
    for (k, &n) in sizes.iter().enumerate() {
        index[k] = flat % n;
        flat /= n;
    }
    index
}
