//! The reference seen from each fitted level: what a coarse run's errors need of the fine-mesh
//! reference, recorded while the reference runs, so that its trajectory is never stored.
//!
//! Let `P` prolongate level `ℓ` into the reference mesh, `A` be the fine matrix of a norm
//! (`M` for `H`, `M + S` for `V`; standard consistent mass and stiffness) and
//! `A_ℓ = PᵀAP` the coarse one: for nested Q1 spaces it is exactly the matrix assembled on the
//! coarse mesh, since the coarse basis functions are fine finite element functions. With
//! ```text
//! w = A_ℓ⁻¹ Pᵀ A u        (the A-orthogonal projection of the reference u on level ℓ)
//! ```
//! the residual `u − P w` is `A`-orthogonal to the coarse space (`Pᵀ A (u − Pw) = 0`), so the
//! error of any coarse `U` splits by Pythagoras:
//! ```text
//! ‖P U − u‖²_A = ‖U − w‖²_{A_ℓ} + ‖u − P w‖²_A.
//! ```
//! The second term is the reference's own distance to the coarse space. A reference run records,
//! at each step of each level, `w_H`, `w_V` and the two remainders ([`ProjectionRecorder`]); a
//! coarse run's errors then cost two coarse products per step ([`LevelProjections::squared_errors`]),
//! in exact arithmetic the same numbers as the fine-space comparison. The remainder is computed
//! as a fine quadratic form of the residual, not as `‖u‖² − wᵀA_ℓw`, so no cancellation enters it.
//!
//! Memory: `2 · dofs_ℓ` per step of each level (about 100 MB for the 3D levels 10–80), instead of
//! the reference's trajectory (2.7 GB at 3D level 320 sampled at level 80's steps).

use crate::engine::fem::{BoxMesh, Elasticity, MassVariant, Prolongation, SymmetricMatrix};
use crate::engine::linalg::SpdSolver;
use crate::engine::schemes::TimeIntegrator;
use crate::harness::files::error::Error;
use crate::harness::run::Observer;

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

/// The projections of the reference on one level, at every step of that level.
#[derive(Debug, Clone, PartialEq)]
pub struct LevelProjections {
    /// Elements along the axis.
    pub level: usize,
    /// Unknowns of the level.
    pub dofs: usize,
    /// `w_H(t_k)` (`A = M`), step after step, `dofs` each.
    pub h_projection: Vec<f64>,
    /// `w_V(t_k)` (`A = M + S`).
    pub v_projection: Vec<f64>,
    /// `‖u(t_k) − P w_H(t_k)‖²_M`.
    pub h_remainder: Vec<f64>,
    /// `‖u(t_k) − P w_V(t_k)‖²_{M+S}`.
    pub v_remainder: Vec<f64>,
}

impl LevelProjections {
    /// Steps recorded (the level's steps `0..samples`, `t_k = k Δt_ℓ`).
    pub fn samples(&self) -> usize {
        self.h_remainder.len()
    }

    /// The squared `H` and `V` errors `‖P U − u(t_k)‖²` of the coarse displacement `u` at the
    /// level's step `k` (the module's splitting), `None` past the recorded steps; `norms` are
    /// the level's matrices, `scratch` two vectors of the level's length.
    pub fn squared_errors(
        &self,
        k: usize,
        u: &[f64],
        norms: &NormMatrices,
        scratch: &mut [Vec<f64>; 2],
    ) -> Option<(f64, f64)> {
        if k >= self.samples() {
            return None;
        }
        let n = self.dofs;
        let [e, work] = scratch;
        let difference = |e: &mut [f64], projection: &[f64]| {
            for ((ei, ui), wi) in e.iter_mut().zip(u).zip(&projection[k * n..(k + 1) * n]) {
                *ei = ui - wi;
            }
        };
        difference(e, &self.h_projection);
        let h2 = norms.h_squared(e, work);
        difference(e, &self.v_projection);
        let v2 = norms.v_squared(e, work);
        Some((h2 + self.h_remainder[k], v2 + self.v_remainder[k]))
    }

    /// The numbers of the cache file, in the order [`LevelProjections::read`] reads.
    pub fn values(&self) -> impl Iterator<Item = f64> + '_ {
        (self.h_projection.iter())
            .chain(&self.v_projection)
            .chain(&self.h_remainder)
            .chain(&self.v_remainder)
            .copied()
    }

    /// The number of values of a level of `dofs` unknowns and `samples` steps (`None` past
    /// `usize`).
    pub fn value_count(dofs: usize, samples: usize) -> Option<usize> {
        dofs.checked_add(1)?.checked_mul(samples)?.checked_mul(2)
    }

    /// Reads back [`LevelProjections::values`] from `next`, which yields the values in order:
    /// `None` when it runs out first.
    pub fn read(
        level: usize,
        dofs: usize,
        samples: usize,
        next: &mut impl FnMut(&mut [f64]) -> Option<()>,
    ) -> Option<Self> {
        let mut part = |len: usize| {
            let mut v = vec![0.0; len];
            next(&mut v).map(|()| v)
        };
        let field = samples.checked_mul(dofs)?;
        Some(Self {
            level,
            dofs,
            h_projection: part(field)?,
            v_projection: part(field)?,
            h_remainder: part(samples)?,
            v_remainder: part(samples)?,
        })
    }
}

/// One level of a [`ProjectionRecorder`]: its prolongation into the next finer level of the
/// chain, the factorised `A_ℓ` of both norms and what has been recorded.
struct LevelRecorder {
    /// Fine steps between two of the level's steps.
    stride: usize,
    /// Into the next finer level (the reference for the finest).
    prolongation: Prolongation,
    mass: SpdSolver,
    energy: SpdSolver,
    /// Restricted loads `Pᵀ M u`, `Pᵀ (M + S) u` at the current step.
    h_load: Vec<f64>,
    v_load: Vec<f64>,
    recorded: LevelProjections,
}

/// Records the [`LevelProjections`] of every level while the reference runs (an observer of
/// the reference run). The levels form a chain of nested prolongations, coarsest first, so only
/// the finest level's prolongation has the reference's size.
pub struct ProjectionRecorder<'a> {
    fine: &'a NormMatrices,
    levels: Vec<LevelRecorder>,
    step: usize,
    mass_u: Vec<f64>,
    energy_u: Vec<f64>,
    up: Vec<Vec<f64>>,
    residual: Vec<f64>,
    scratch: Vec<f64>,
}

impl<'a> ProjectionRecorder<'a> {
    /// A recorder for the nested `levels` (increasing, each dividing the next and the
    /// reference's count along the axis) of the reference mesh `reference`, whose norm
    /// matrices are `fine`; `mesh_of(n)` is the mesh on `n` elements along the axis.
    pub fn new(
        levels: &[usize],
        reference: &BoxMesh,
        fine: &'a NormMatrices,
        mesh_of: &dyn Fn(usize) -> Result<BoxMesh, Error>,
        elasticity: &Elasticity,
    ) -> Result<Self, Error> {
        let n_axis = reference.counts()[reference.dim() - 1];
        let meshes = (levels.iter())
            .map(|&n| mesh_of(n))
            .collect::<Result<Vec<BoxMesh>, Error>>()?;
        let mut recorders = Vec::with_capacity(levels.len());
        let mut up = Vec::with_capacity(levels.len());
        for (i, (mesh, &level)) in meshes.iter().zip(levels).enumerate() {
            let finer = meshes.get(i + 1).unwrap_or(reference);
            let norms = NormMatrices::of(mesh, elasticity);
            let energy_matrix = norms.mass.linear_combination(1.0, &norms.stiffness, 1.0);
            let dofs = mesh.n_dofs();
            recorders.push(LevelRecorder {
                stride: n_axis / level,
                prolongation: Prolongation::new(mesh, finer)?,
                mass: SpdSolver::factor(&norms.mass, "coarse mass of a norm")?,
                energy: SpdSolver::factor(&energy_matrix, "coarse M + S of a norm")?,
                h_load: vec![0.0; dofs],
                v_load: vec![0.0; dofs],
                recorded: LevelProjections {
                    level,
                    dofs,
                    h_projection: Vec::new(),
                    v_projection: Vec::new(),
                    h_remainder: Vec::new(),
                    v_remainder: Vec::new(),
                },
            });
            up.push(vec![0.0; finer.n_dofs()]);
        }
        let n = reference.n_dofs();
        Ok(Self {
            fine,
            levels: recorders,
            step: 0,
            mass_u: vec![0.0; n],
            energy_u: vec![0.0; n],
            up,
            residual: vec![0.0; n],
            scratch: vec![0.0; n],
        })
    }

    /// The recorded projections, coarsest level first.
    pub fn finish(self) -> Vec<LevelProjections> {
        self.levels.into_iter().map(|l| l.recorded).collect()
    }

    /// `P_{ℓ→ref} w`, through the chain of prolongations from level `from`, into
    /// `self.up[last]`.
    fn prolongate_to_reference(&mut self, from: usize, w: &[f64]) {
        self.levels[from]
            .prolongation
            .apply_into(w, &mut self.up[from]);
        for i in from + 1..self.levels.len() {
            let (done, rest) = self.up.split_at_mut(i);
            self.levels[i]
                .prolongation
                .apply_into(&done[i - 1], &mut rest[0]);
        }
    }

    /// `‖u − P w‖²_A` with `A = M` (`energy` false) or `M + S`, `w` on level `from`.
    fn remainder(&mut self, from: usize, u: &[f64], w: &[f64], energy: bool) -> f64 {
        self.prolongate_to_reference(from, w);
        let pw = self.up.last().expect("at least one level");
        for ((r, ui), pi) in self.residual.iter_mut().zip(u).zip(pw) {
            *r = ui - pi;
        }
        if energy {
            self.fine.v_squared(&self.residual, &mut self.scratch)
        } else {
            self.fine.h_squared(&self.residual, &mut self.scratch)
        }
    }
}

impl Observer for ProjectionRecorder<'_> {
    /// At each reference step that is a step of some level: `M u` and `(M + S) u` once,
    /// restricted down the chain to every level due, then each level's `w_H`, `w_V` and
    /// remainders. A coarser level's stride is a multiple of a finer one's, so the levels due
    /// are the finest ones from the coarsest due on.
    fn observe(&mut self, state: &dyn TimeIntegrator) -> Result<(), Error> {
        let step = self.step;
        self.step += 1;
        let Some(first) = self.levels.iter().position(|l| step % l.stride == 0) else {
            return Ok(());
        };
        let due = first..self.levels.len();
        let u = state.displacement();
        self.fine.mass.mul_into(u, &mut self.mass_u);
        self.fine.stiffness.mul_into(u, &mut self.energy_u);
        for (e, m) in self.energy_u.iter_mut().zip(&self.mass_u) {
            *e += m;
        }
        for i in due.clone().rev() {
            let (coarser, finer) = self.levels.split_at_mut(i + 1);
            let level = &mut coarser[i];
            let (h_from, v_from) = match finer.first() {
                Some(next) => (next.h_load.as_slice(), next.v_load.as_slice()),
                None => (self.mass_u.as_slice(), self.energy_u.as_slice()),
            };
            level.prolongation.restrict_into(h_from, &mut level.h_load);
            level.prolongation.restrict_into(v_from, &mut level.v_load);
        }
        for i in due {
            // The loads are spent (every coarser level has been restricted from them): solve
            // in place, and give the buffers back for the next step.
            let mut w_h = std::mem::take(&mut self.levels[i].h_load);
            let mut w_v = std::mem::take(&mut self.levels[i].v_load);
            self.levels[i].mass.solve_in_place(&mut w_h);
            self.levels[i].energy.solve_in_place(&mut w_v);
            let h_remainder = self.remainder(i, u, &w_h, false);
            let v_remainder = self.remainder(i, u, &w_v, true);
            let level = &mut self.levels[i];
            level.recorded.h_projection.extend_from_slice(&w_h);
            level.recorded.v_projection.extend_from_slice(&w_v);
            level.recorded.h_remainder.push(h_remainder);
            level.recorded.v_remainder.push(v_remainder);
            (level.h_load, level.v_load) = (w_h, w_v);
        }
        Ok(())
    }
}
