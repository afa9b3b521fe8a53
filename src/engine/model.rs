//! The semi-discrete model `M U'' + S U = F − Bᵀλ`, `0 ≤ B U + g ⟂ λ ≤ 0` (1D paper eq. 30,
//! with `B` selecting the contact dofs): matrices, load and contact set, independent of the
//! dimension. Schemes are written against this type, never against 1D arrays. A penalty or
//! Nitsche treatment of the contact replaces the multiplier through a
//! [`ContactLaw`] (see [`crate::engine::contact::law`]).

pub use crate::engine::contact::ContactSet;
use crate::engine::contact::{ContactLaw, ContactTreatment};
use crate::engine::fem::box_mesh::{BoxMesh, Elasticity};
use crate::engine::fem::{Bar1d, MassVariant, SparseAssembler, SymmetricMatrix};
use crate::engine::solver_plan::SolverPlan;

/// Matrices, load and constraints of one spatial discretisation.
#[derive(Debug, Clone)]
pub struct Model {
    mass: SymmetricMatrix,
    stiffness: SymmetricMatrix,
    load: Option<Vec<f64>>,
    contact: Option<ContactSet>,
    law: ContactLaw,
    massless: Vec<usize>,
    solver_plan: SolverPlan,
}

impl Model {
    /// A model from its parts; `load` is constant in time, the solver plan the default one
    /// (`direct`, the full contact operator). The massless dofs (zero rows of `mass`) are found
    /// here, once.
    pub fn new(
        mass: SymmetricMatrix,
        stiffness: SymmetricMatrix,
        load: Option<Vec<f64>>,
        contact: Option<ContactSet>,
    ) -> Self {
        let massless = (0..mass.dim()).filter(|&i| mass.row_is_zero(i)).collect();
        let law = ContactLaw::multiplier(contact.as_ref().map_or(0, ContactSet::len));
        Self {
            mass,
            stiffness,
            load,
            contact,
            law,
            massless,
            solver_plan: SolverPlan::default(),
        }
    }

    /// The model with its steps solved as `plan` says (the step solver and the contact
    /// steps' Delassus operator, resolved where the problem was discretised).
    pub fn with_solver_plan(mut self, plan: SolverPlan) -> Self {
        self.solver_plan = plan;
        self
    }

    /// How the schemes solve their step matrices and contact steps.
    pub fn solver_plan(&self) -> &SolverPlan {
        &self.solver_plan
    }

    /// The model with the contact treated by `law` instead of the multiplier. For Nitsche the
    /// stiffness becomes `S − (θ/γ) a aᵀ` (`σ_h(U) = aᵀU`, CHR 2015 eq. 2.5; a rank-one
    /// update on the dofs of the first element, so a 1D matrix stays tridiagonal).
    pub fn with_contact_law(mut self, law: ContactLaw) -> Self {
        if let Some((a, scale)) = law.stiffness_update() {
            let mut asm = SparseAssembler::new(self.n_dofs());
            asm.add_scaled(&self.stiffness, 1.0);
            for &(i, ai) in a {
                for &(j, aj) in a {
                    asm.add(i, j, scale * ai * aj);
                }
            }
            self.stiffness = asm.finish();
        }
        self.law = law;
        self
    }

    /// The box of the note: its semi-discrete problem (5) (with `M^mod` for the redistributed
    /// variant, eq. 7), without body force: `M U'' + S U = −Bᵀλ`,
    /// `0 ≤ U_d(a_i) + g ⟂ λ_i ≤ 0` on `Γ_Sig` ([`ContactSet::on_box_face`]), or no contact
    /// when `obstacle_gap` is `None`. The material is assumed valid ([`Elasticity::validate`]).
    pub fn of_box(
        mesh: &BoxMesh,
        elasticity: &Elasticity,
        mass_variant: MassVariant,
        obstacle_gap: Option<f64>,
    ) -> Self {
        Self::new(
            mesh.mass(mass_variant, elasticity.density),
            mesh.stiffness(elasticity),
            None,
            obstacle_gap.map(|g| ContactSet::on_box_face(mesh, g)),
        )
    }

    /// The model of [`Model::of_box`] with its mass and stiffness stored matrix-free
    /// ([`BoxMesh::mass_stencil`], [`BoxMesh::stiffness_stencil`]): `O(n)` memory and products
    /// that read only the vectors, for the iterative step solver. `None` for a mass variant
    /// that exists only assembled.
    pub fn of_box_matrix_free(
        mesh: &BoxMesh,
        elasticity: &Elasticity,
        mass_variant: MassVariant,
        obstacle_gap: Option<f64>,
    ) -> Option<Self> {
        Some(Self::new(
            mesh.mass_stencil(mass_variant, elasticity.density)?,
            mesh.stiffness_stencil(elasticity),
            None,
            obstacle_gap.map(|g| ContactSet::on_box_face(mesh, g)),
        ))
    }

    /// The 1D bar with the obstacle at `x = 0` (gap `obstacle_gap`, `None` for no obstacle)
    /// and a constant body force density.
    pub fn bar1d(
        bar: &Bar1d,
        mass: MassVariant,
        obstacle_gap: Option<f64>,
        body_force: Option<f64>,
    ) -> Self {
        let contact = obstacle_gap.map(|g| ContactSet {
            dofs: vec![bar.contact_dof()],
            gaps: vec![g],
        });
        Self::new(
            bar.mass(mass),
            bar.stiffness(),
            body_force.map(|f| bar.load(f)),
            contact,
        )
    }

    /// Number of unknowns.
    pub fn n_dofs(&self) -> usize {
        self.mass.dim()
    }

    /// Mass matrix (possibly singular).
    pub fn mass(&self) -> &SymmetricMatrix {
        &self.mass
    }

    /// Stiffness matrix (for Nitsche, the modified `S − (θ/γ) a aᵀ` the schemes integrate).
    pub fn stiffness(&self) -> &SymmetricMatrix {
        &self.stiffness
    }

    /// Constant load vector, if the model declares a body force.
    pub fn load(&self) -> Option<&[f64]> {
        self.load.as_deref()
    }

    /// The contact constraints, if the model declares an obstacle.
    pub fn contact(&self) -> Option<&ContactSet> {
        self.contact.as_ref()
    }

    /// How the contact condition is treated.
    pub fn contact_law(&self) -> &ContactLaw {
        &self.law
    }

    /// The contact energy of `u` (penalty or Nitsche; 0 for the multiplier), see
    /// [`ContactLaw::energy`].
    pub fn contact_energy(&self, u: &[f64]) -> f64 {
        self.contact.as_ref().map_or(0.0, |c| self.law.energy(c, u))
    }

    /// The dofs spanning `ker M` (rows of `M` that are identically zero).
    pub fn massless_dofs(&self) -> &[usize] {
        &self.massless
    }

    /// The dofs with mass `R`, the complement of [`Model::massless_dofs`], increasing.
    pub fn dofs_with_mass(&self) -> Vec<usize> {
        (0..self.n_dofs())
            .filter(|i| self.massless.binary_search(i).is_err())
            .collect()
    }

    /// Whether every contact dof is massless (the redistributed mass).
    pub fn contact_is_massless(&self) -> bool {
        self.contact.as_ref().is_some_and(|c| {
            c.dofs
                .iter()
                .all(|d| self.massless.binary_search(d).is_ok())
        })
    }

    /// The discrete energy `½ VᵀMV + ½ UᵀSU − FᵀU` (1D paper eq. 31, with the load's
    /// potential written `−FᵀU`: the printed `−U_tᵀF` is an erratum, see docs/src/errata.md), plus the
    /// contact energy of a penalty or Nitsche treatment ([`Model::contact_energy`]; with
    /// Nitsche's `S` this is CHR's `… − (θ/2γ)σ_h(U)² + (1/2γ)[P_γ(U)]_−²`).
    pub fn energy(&self, u: &[f64], v: &[f64]) -> f64 {
        let load = self
            .load
            .as_ref()
            .map_or(0.0, |f| f.iter().zip(u).map(|(a, b)| a * b).sum::<f64>());
        let elastic =
            0.5 * self.mass.quadratic_form(v) + 0.5 * self.stiffness.quadratic_form(u) - load;
        match self.law.treatment() {
            ContactTreatment::Multiplier => elastic,
            _ => elastic + self.contact_energy(u),
        }
    }
}
