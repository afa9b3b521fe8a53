//! Mass-matrix variants.
//!
//! * `standard`: the consistent P1/Q1 mass matrix, `M_ij = ∫_Ω ρ φ_i φ_j`.
//! * `redistributed`: the paper's `M^mod` (1D paper §3.2; 2D/3D note §2.1),
//!   `M^mod_ij = ∫_{Ω^mod} ρ φ_i φ_j` with `Ω^mod` the union of the elements that do **not**
//!   touch the contact boundary. Every dof of a node on the contact boundary then has a zero row
//!   and column: the node carries no inertia and evolves quasi-statically. The mass of the
//!   removed elements is removed, not moved (the total mass drops by that of one element layer).
//! * `lumped`: the row-sum diagonal of the consistent matrix, `M^L_ii = Σ_j M_ij` (GetFEM's
//!   "basic lumped mass matrix" of `demo_dynamic_contact_1D.py`), the sum running over every
//!   node, the fixed (Dirichlet) ones included: it is assembled from the row-summed element
//!   matrices ([`MassVariant::element_matrix`]), so a node next to a clamped end keeps the
//!   mass `ρh` of its two half-elements (a row sum of the matrix with the Dirichlet dofs already
//!   eliminated would give it `5ρh/6`). No dof is massless.
//! * `redistributed-conserving` and `singular-dynamic`: the kinetic energy is that of a velocity
//!   field whose values at the nodes of `Γ_Sig` are *extended* from the nodes above them along the
//!   normal, `M^P = Pᵀ M P` (see [`ContactExtension`]). The contact nodes' own velocities never
//!   enter it, so every component of a node of `Γ_Sig` is massless, yet no mass is discarded:
//!   - `redistributed-conserving`, `ṽ(a, 0) = v(a, 1)`: the contact node moves with its
//!     neighbour, so its mass is given to that neighbour. `P 1 = 1`: the total mass
//!     `1ᵀ M 1` (per component) is the standard one. The first moment along the normal is not
//!     kept (in 1D it grows by `ρ h²/2`: the contact node's lumped mass `ρh/2` moved by `h`).
//!   - `singular-dynamic`, `ṽ(a, 0) = 2 v(a, 1) − v(a, 2)` (linear extrapolation): the singular
//!     dynamic mass matrix (Y. Renard, J. Comput. Appl. Math. 234 (2010) 906–923; Hager,
//!     Hüeber, Wohlmuth 2008): contact-node inertia removed with a consistent correction of its
//!     neighbours. `P` reproduces every affine field, so `M^sing` keeps the kinetic energy of
//!     every affine velocity field: the total mass, the first moment (centre of mass) and the
//!     second moment (inertia) of `M`. In 1D P1 (`ρ = 1`) it changes only
//!     `M_11 = 2h/3 → 8h/3`, `M_12 = h/6 → −2h/3`, `M_22 = 2h/3 → h`, and it is the only matrix
//!     that differs from `M` only on the nodes 1, 2 and keeps those three moments. (Minimising
//!     the Frobenius distance to `M` on that block under the mass and first-moment constraints
//!     alone gives `M_22 = 0` with `M_12 ≠ 0`, which is indefinite; hence the inertia
//!     constraint.) GetFEM's demo sets `M_11 = 7h/12`, which keeps neither the mass nor the
//!     first moment.
//!
//! * `getfem-redistributed` and `getfem-singular`: the two masses of GetFEM's public demo
//!   `demo_dynamic_contact_1D.py` (`mass_matrix_type` 1 and 2), kept so that the harness can
//!   solve the demo's discrete problem (issue 17, `tests/data/getfem/`). Both zero the row and
//!   column of the contact node `0` and change only the diagonal of its neighbour `1`:
//!   - `getfem-redistributed`: `M_11 ← M_11 + M_00 + M_10` (`2h/3 + h/3 + h/6 = 7h/6` for
//!     `ρ = 1`): the contact node's row sum is moved onto the neighbour's diagonal. It is not a
//!     congruence of `M` (so not `redistributed-conserving`, whose `M_11` is `4h/3`), nor the
//!     paper's `M^mod` (which removes the first element's mass: `M_11 = h/3`);
//!   - `getfem-singular`: `M_11 ← 7ρh/12` (the demo's "singular dynamic" mass; it keeps neither
//!     the total mass nor the first moment, unlike `singular-dynamic`).
//!
//!   They are defined on the 1D bar only: the demo writes them on its dof numbering, and the
//!   constant `7h/12` has no counterpart on a box face; [`MassVariant::check_layers`] refuses
//!   them on a box.
//!
//! The extension is defined when the nodes it reads exist and are not on the Dirichlet face
//! (otherwise the mass would be moved onto a fixed node and lost); [`MassVariant::check_layers`]
//! says so with a [`ParameterError`] on `mass`.

use std::fmt;
use std::str::FromStr;

use serde::{Deserialize, Serialize};

use nalgebra::SMatrix;

use super::{SparseAssembler, SymmetricMatrix};
use crate::engine::error::ParameterError;

/// Which mass matrix the semi-discrete problem uses.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum MassVariant {
    /// Consistent mass matrix `M`.
    Standard,
    /// The paper's `M^mod`: elements touching the contact boundary removed from the integral.
    Redistributed,
    /// Row-sum lumped (diagonal) mass matrix.
    Lumped,
    /// `Pᵀ M P` with the contact nodes moving with their neighbours: massless contact nodes,
    /// total mass kept.
    RedistributedConserving,
    /// `Pᵀ M P` with the contact nodes' velocities extrapolated linearly: massless contact
    /// nodes, total mass, centre of mass and inertia kept (Renard 2010).
    SingularDynamic,
    /// GetFEM demo's `mass_matrix_type = 1`: the contact node's row sum moved onto its
    /// neighbour's diagonal, the contact row and column zero (1D only).
    GetfemRedistributed,
    /// GetFEM demo's `mass_matrix_type = 2`: the neighbour's diagonal set to `7ρh/12`, the
    /// contact row and column zero (1D only).
    GetfemSingular,
}

/// How the velocity of a node of `Γ_Sig` is extended from the nodes above it along the normal:
/// `ṽ(a, 0) = Σ_k weights[k] v(a, k + 1)`, `a` the node's position on `Γ_Sig`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactExtension {
    /// The weights of the nodes at distance `1, 2, …` along the normal.
    pub weights: &'static [f64],
}

impl MassVariant {
    /// Every variant, in table order.
    pub const ALL: [MassVariant; 7] = [
        MassVariant::Standard,
        MassVariant::Redistributed,
        MassVariant::Lumped,
        MassVariant::RedistributedConserving,
        MassVariant::SingularDynamic,
        MassVariant::GetfemRedistributed,
        MassVariant::GetfemSingular,
    ];

    /// The variants defined on every mesh, bar and box (all but GetFEM's two): the extended
    /// study's.
    pub const ON_EVERY_MESH: [MassVariant; 5] = [
        MassVariant::Standard,
        MassVariant::Redistributed,
        MassVariant::Lumped,
        MassVariant::RedistributedConserving,
        MassVariant::SingularDynamic,
    ];

    /// GetFEM demo's masses, `mass_matrix_type` 1 and 2 (1D only).
    pub const GETFEM: [MassVariant; 2] = [
        MassVariant::GetfemRedistributed,
        MassVariant::GetfemSingular,
    ];

    /// The two variants of the paper's Tables 1–2 (STD, MOD), in table order.
    pub const PAPER: [MassVariant; 2] = [MassVariant::Standard, MassVariant::Redistributed];

    /// Whether the mass leaves dofs without mass (the contact dofs of every variant but the
    /// standard and the lumped one).
    pub fn has_massless_dofs(self) -> bool {
        !matches!(self, MassVariant::Standard | MassVariant::Lumped)
    }

    /// The name used in scene files, on the command line and in reports.
    pub fn name(self) -> &'static str {
        match self {
            MassVariant::Standard => "standard",
            MassVariant::Redistributed => "redistributed",
            MassVariant::Lumped => "lumped",
            MassVariant::RedistributedConserving => "redistributed-conserving",
            MassVariant::SingularDynamic => "singular-dynamic",
            MassVariant::GetfemRedistributed => "getfem-redistributed",
            MassVariant::GetfemSingular => "getfem-singular",
        }
    }

    /// The short label of tables (`STD`, `MOD` as in the paper; `LUMP`, `MODC`, `SING`).
    pub fn paper_label(self) -> &'static str {
        match self {
            MassVariant::Standard => "STD",
            MassVariant::Redistributed => "MOD",
            MassVariant::Lumped => "LUMP",
            MassVariant::RedistributedConserving => "MODC",
            MassVariant::SingularDynamic => "SING",
            MassVariant::GetfemRedistributed => "GF1",
            MassVariant::GetfemSingular => "GF2",
        }
    }

    /// A one-line description (for `signorini list`).
    pub fn description(self) -> &'static str {
        match self {
            MassVariant::Standard => "consistent mass matrix M",
            MassVariant::Redistributed => {
                "the paper's M^mod: elements touching the contact boundary removed (mass lost)"
            }
            MassVariant::Lumped => "row-sum diagonal of M",
            MassVariant::RedistributedConserving => {
                "contact nodes massless, their mass moved onto the nodes above (total mass kept)"
            }
            MassVariant::SingularDynamic => {
                "singular dynamic mass (Renard 2010): contact nodes massless, linear extrapolation \
                 (mass, centre of mass and inertia kept)"
            }
            MassVariant::GetfemRedistributed => {
                "GetFEM demo's mass type 1: contact node massless, its row sum added to its \
                 neighbour's diagonal (M_11 = 7h/6; 1D only)"
            }
            MassVariant::GetfemSingular => {
                "GetFEM demo's mass type 2: contact node massless, M_11 = 7h/12 (1D only)"
            }
        }
    }

    /// The element matrix this variant assembles from the consistent element matrix `m`: its
    /// row sums on the diagonal for `lumped` (so the lumped matrix is the row sums over every
    /// node, fixed ones included), `m` itself for the others.
    pub fn element_matrix<const N: usize>(self, m: SMatrix<f64, N, N>) -> SMatrix<f64, N, N> {
        match self {
            MassVariant::Lumped => SMatrix::from_diagonal(&m.column_sum()),
            _ => m,
        }
    }

    /// Whether an element contributes to the mass integral.
    pub fn includes_element(self, touches_contact_boundary: bool) -> bool {
        match self {
            MassVariant::Redistributed => !touches_contact_boundary,
            _ => true,
        }
    }

    /// The velocity extension of the variants `Pᵀ M P`; for GetFEM's masses, the neighbour
    /// (weight 1) whose diagonal receives the contact node's mass; `None` for the others.
    pub fn contact_extension(self) -> Option<ContactExtension> {
        match self {
            MassVariant::RedistributedConserving
            | MassVariant::GetfemRedistributed
            | MassVariant::GetfemSingular => Some(ContactExtension { weights: &[1.0] }),
            MassVariant::SingularDynamic => Some(ContactExtension {
                weights: &[2.0, -1.0],
            }),
            _ => None,
        }
    }

    /// Whether this is one of GetFEM demo's masses ([`MassVariant::GETFEM`]), which edit the
    /// contact node's neighbour along the normal.
    pub fn is_getfem(self) -> bool {
        MassVariant::GETFEM.contains(&self)
    }

    /// Checks that the variant is defined on a mesh with `layers` element layers between the
    /// contact boundary and the far face, which is fixed (Dirichlet) or free. The extension of
    /// `redistributed-conserving` (`singular-dynamic`) reads the nodes 1 (and 2) layers above
    /// `Γ_Sig`: they must exist and must not be fixed, or mass is lost.
    ///
    /// GetFEM's masses are refused on a box (`on_bar` false), and need a neighbour node that
    /// is not fixed on a bar.
    pub fn check_layers(
        self,
        layers: usize,
        far_face_fixed: bool,
        on_bar: bool,
    ) -> Result<(), ParameterError> {
        if self.is_getfem() {
            let allowed = if !on_bar {
                "a variant other than getfem-redistributed and getfem-singular on a box (GetFEM \
                 demo's masses are defined on the 1D bar only)"
            } else if layers < 1 + usize::from(far_face_fixed) {
                "a variant other than getfem-redistributed and getfem-singular on a bar with one \
                 element and a clamped end (the contact node's neighbour is fixed); use at least \
                 2 elements"
            } else {
                return Ok(());
            };
            return Err(ParameterError::new("mass", self.name(), allowed));
        }
        let Some(ext) = self.contact_extension() else {
            return Ok(());
        };
        let needed = ext.weights.len() + usize::from(far_face_fixed);
        if layers >= needed {
            return Ok(());
        }
        Err(ParameterError::new(
            "mass",
            self.name(),
            match (self, far_face_fixed) {
                (MassVariant::RedistributedConserving, _) => {
                    "a variant other than redistributed-conserving on a mesh with one element \
                     between the contact and the Dirichlet boundary (the contact nodes' mass \
                     would be moved onto fixed nodes and lost); use at least 2 elements"
                }
                (_, true) => {
                    "a variant other than singular-dynamic on a mesh with fewer than 3 elements \
                     between the contact and the Dirichlet boundary (the linear extrapolation \
                     would read fixed nodes, losing mass and moments); use at least 3 elements"
                }
                (_, false) => {
                    "a variant other than singular-dynamic on a single element (the linear \
                     extrapolation needs the two nodes above the contact node); use at least 2 \
                     elements"
                }
            },
        ))
    }

    /// The variant built from the matrix `consistent` assembled with
    /// [`includes_element`](Self::includes_element) and [`element_matrix`](Self::element_matrix)
    /// (so already lumped for `lumped`): `standard`, `redistributed` and `lumped` unchanged, the
    /// extended variants `Pᵀ M P` where `extension(d)` lists `(dof, weight)` of the extension of
    /// a contact dof `d` and is `None` for the other dofs, and GetFEM's two edited on the
    /// contact dofs' neighbours.
    pub fn from_consistent(
        self,
        consistent: SymmetricMatrix,
        extension: impl Fn(usize) -> Option<Vec<(usize, f64)>>,
    ) -> SymmetricMatrix {
        match self {
            MassVariant::Standard | MassVariant::Redistributed => consistent,
            MassVariant::Lumped => diagonal_of(&consistent),
            MassVariant::RedistributedConserving | MassVariant::SingularDynamic => {
                let expand: Vec<Vec<(usize, f64)>> = (0..consistent.dim())
                    .map(|d| extension(d).unwrap_or_else(|| vec![(d, 1.0)]))
                    .collect();
                consistent.congruence(&expand)
            }
            MassVariant::GetfemRedistributed | MassVariant::GetfemSingular => {
                let pairs: Vec<(usize, usize)> = (0..consistent.dim())
                    .filter_map(|d| Some((d, extension(d)?.first()?.0)))
                    .collect();
                getfem_demo_mass(self, &consistent, &pairs)
            }
        }
    }
}

/// GetFEM demo's masses from the consistent matrix `m`, for each `(contact, neighbour)` of
/// `pairs`: the row and column `contact` zeroed, and `M_nn ← M_nn + M_cc + M_nc`
/// (`getfem-redistributed`) or `M_nn ← 7 M_cc / 4` (`getfem-singular`: `7ρh/12` with the
/// contact node's consistent diagonal `ρh/3`). The other entries are kept.
fn getfem_demo_mass(
    variant: MassVariant,
    m: &SymmetricMatrix,
    pairs: &[(usize, usize)],
) -> SymmetricMatrix {
    let mut asm = SparseAssembler::new(m.dim());
    asm.add_scaled(m, 1.0);
    for &(c, n) in pairs {
        let (m_cc, m_nc, m_nn) = (m.get(c, c), m.get(n, c), m.get(n, n));
        let new_nn = match variant {
            MassVariant::GetfemRedistributed => m_nn + m_cc + m_nc,
            _ => 7.0 * m_cc / 4.0,
        };
        asm.add(n, n, new_nn - m_nn);
        asm.add(c, c, -m_cc);
        asm.add(n, c, -m_nc);
        asm.add(c, n, -m.get(c, n));
    }
    asm.finish()
}

/// The diagonal of `m` as a matrix with no other entry (the assembly of diagonal element
/// matrices stores their zeros).
fn diagonal_of(m: &SymmetricMatrix) -> SymmetricMatrix {
    let mut asm = SparseAssembler::new(m.dim());
    for i in 0..m.dim() {
        asm.add(i, i, m.get(i, i));
    }
    asm.finish()
}

impl fmt::Display for MassVariant {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for MassVariant {
    type Err = ParameterError;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Self::ALL
            .into_iter()
            .find(|m| m.name() == s)
            .ok_or_else(|| {
                ParameterError::new(
                    "mass",
                    s,
                    "one of: standard, redistributed, lumped, redistributed-conserving, \
                     singular-dynamic, getfem-redistributed, getfem-singular",
                )
            })
    }
}
