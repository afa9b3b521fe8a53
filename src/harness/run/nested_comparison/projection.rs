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

use super::norm_matrices::NormMatrices;
use super::slab_fine::{SlabFine, SlabSetup};
use crate::engine::distributed::{Ranks, Slabs};
use crate::engine::error::ParameterError;
use crate::engine::fem::{BoxMesh, Elasticity, Prolongation};
use crate::engine::linalg::SpdSolver;
use crate::engine::schemes::Integration;
use crate::harness::files::error::Error;
use crate::harness::run::distributed::{SlabObserver, SlabState};
use crate::harness::run::Observer;

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
/// chain (none for the finest, whose prolongation into the reference is the [`FineSide`]'s),
/// the factorised `A_ℓ` of both norms and what has been recorded.
struct LevelRecorder {
    /// Into the next finer level; `None` for the finest.
    prolongation: Option<Prolongation>,
    mass: SpdSolver,
    energy: SpdSolver,
    /// Restricted loads `Pᵀ M u`, `Pᵀ (M + S) u` at the current step.
    h_load: Vec<f64>,
    v_load: Vec<f64>,
    recorded: LevelProjections,
}

/// The reference's side of the projections: its products with the fine norm matrices and the
/// prolongation of the finest level into it.
enum FineSide<'a> {
    /// The whole reference mesh, in this process.
    Whole {
        norms: &'a NormMatrices,
        prolongation: Prolongation,
        mass_u: Vec<f64>,
        energy_u: Vec<f64>,
        pw: Vec<f64>,
        residual: Vec<f64>,
        scratch: Vec<f64>,
    },
    /// A distributed run's, before the run has cut the box into slabs.
    Unstarted(SlabSetup<'a>),
    /// This rank's slab of it ([`SlabFine`]).
    Slab(Box<SlabFine<'a>>),
}

/// Records the [`LevelProjections`] of every level while the reference runs: an observer of
/// the reference run in one process, or a [`SlabObserver`] of every rank of a distributed
/// one, rank 0 holding the levels ([`ProjectionRecorder::distributed`]). The levels form a
/// chain of nested prolongations, coarsest first, so only the finest level's prolongation has
/// the reference's size.
pub struct ProjectionRecorder<'a> {
    fine: FineSide<'a>,
    /// Fine steps between two steps of each level.
    strides: Vec<usize>,
    /// The levels (empty on a distributed run's ranks other than 0).
    levels: Vec<LevelRecorder>,
    step: usize,
    /// `P w` of a level's `w` up the chain, each the next finer level's length.
    up: Vec<Vec<f64>>,
}

impl<'a> ProjectionRecorder<'a> {
    /// A recorder for the nested `levels` (increasing, each dividing the next and the
    /// reference's count along the axis) of the reference mesh `reference`, whose norm
    /// matrices are `fine`; `mesh_of(n)` is the mesh on `n` elements along the axis. With
    /// `ranks`, for the rank `ranks.rank()` of a distributed run: its part is set up when the
    /// run has cut the box ([`SlabObserver::start`]), and only rank 0 holds the levels and
    /// records.
    pub fn new(
        (levels, mesh_of): (&[usize], &dyn Fn(usize) -> Result<BoxMesh, Error>),
        (reference, fine): (&'a BoxMesh, &'a NormMatrices),
        elasticity: &Elasticity,
        ranks: Option<&'a dyn Ranks>,
    ) -> Result<Self, Error> {
        let mut meshes = Self::meshes(levels, mesh_of)?;
        let finest = meshes.last().ok_or_else(no_level)?;
        let side = match ranks {
            None => {
                let n = reference.n_dofs();
                FineSide::Whole {
                    norms: fine,
                    prolongation: Prolongation::new(finest, reference)?,
                    mass_u: vec![0.0; n],
                    energy_u: vec![0.0; n],
                    pw: vec![0.0; n],
                    residual: vec![0.0; n],
                    scratch: vec![0.0; n],
                }
            }
            Some(ranks) => {
                let side = FineSide::Unstarted(SlabSetup {
                    ranks,
                    norms: fine,
                    coarse: finest.clone(),
                    fine: reference,
                });
                if ranks.rank() != 0 {
                    meshes.clear();
                }
                side
            }
        };
        Self::with_side(side, levels, reference, &meshes, elasticity)
    }

    fn meshes(
        levels: &[usize],
        mesh_of: &dyn Fn(usize) -> Result<BoxMesh, Error>,
    ) -> Result<Vec<BoxMesh>, Error> {
        levels.iter().map(|&n| mesh_of(n)).collect()
    }

    fn strides(levels: &[usize], reference: &BoxMesh) -> Vec<usize> {
        let n_axis = reference.counts()[reference.dim() - 1];
        levels.iter().map(|&level| n_axis / level).collect()
    }

    /// The recorder of the levels on `meshes` (none: a rank that holds no level).
    fn with_side(
        fine: FineSide<'a>,
        levels: &[usize],
        reference: &BoxMesh,
        meshes: &[BoxMesh],
        elasticity: &Elasticity,
    ) -> Result<Self, Error> {
        let mut recorders = Vec::with_capacity(meshes.len());
        let mut up = Vec::with_capacity(meshes.len());
        for (i, (mesh, &level)) in meshes.iter().zip(levels).enumerate() {
            let finer = meshes.get(i + 1);
            let norms = NormMatrices::of(mesh, elasticity);
            let energy_matrix = norms.mass.linear_combination(1.0, &norms.stiffness, 1.0);
            let dofs = mesh.n_dofs();
            recorders.push(LevelRecorder {
                prolongation: finer.map(|f| Prolongation::new(mesh, f)).transpose()?,
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
            up.push(vec![0.0; finer.map_or(0, BoxMesh::n_dofs)]);
        }
        Ok(Self {
            fine,
            strides: Self::strides(levels, reference),
            levels: recorders,
            step: 0,
            up,
        })
    }

    /// The recorded projections, coarsest level first (none on a distributed run's ranks
    /// other than 0).
    pub fn finish(self) -> Vec<LevelProjections> {
        self.levels.into_iter().map(|l| l.recorded).collect()
    }

    /// `‖u − P w‖²_A` with `A = M` (`energy` false) or `M + S`, `w` on level `from` (`None`:
    /// a distributed run's rank other than 0, which holds no level).
    fn remainder(&mut self, from: usize, u: &[f64], w: Option<&[f64]>, energy: bool) -> f64 {
        let finest = w.map(|w| prolongate_to_finest(&self.levels, &mut self.up, from, w));
        self.fine.remainder(u, finest, energy)
    }

    /// The step's observation of the reference's `u` (the whole of it, or this rank's part
    /// of it): at each reference step that is a step of some level, `M u` and `(M + S) u`
    /// once, restricted down the chain to every level due, then each level's `w_H`, `w_V`
    /// and remainders. A coarser level's stride is a multiple of a finer one's, so the levels
    /// due are the finest ones from the coarsest due on.
    fn record(&mut self, u: &[f64]) {
        let step = self.step;
        self.step += 1;
        let Some(first) = self.strides.iter().position(|&s| step % s == 0) else {
            return;
        };
        let due = first..self.strides.len();
        if self.levels.is_empty() {
            // A rank other than 0 of a distributed run: its part of every collective.
            self.fine.loads(u, None);
            for _ in due {
                self.fine.remainder(u, None, false);
                self.fine.remainder(u, None, true);
            }
            return;
        }
        let last = self.levels.len() - 1;
        {
            let finest = &mut self.levels[last];
            self.fine
                .loads(u, Some((&mut finest.h_load, &mut finest.v_load)));
        }
        for i in due.clone().rev().filter(|&i| i < last) {
            let (coarser, finer) = self.levels.split_at_mut(i + 1);
            let level = &mut coarser[i];
            let next = &finer[0];
            let prolongation = level.prolongation.as_ref().expect("a coarser level");
            prolongation.restrict_into(&next.h_load, &mut level.h_load);
            prolongation.restrict_into(&next.v_load, &mut level.v_load);
        }
        for i in due {
            // The loads are spent (every coarser level has been restricted from them): solve
            // in place, and give the buffers back for the next step.
            let mut w_h = std::mem::take(&mut self.levels[i].h_load);
            let mut w_v = std::mem::take(&mut self.levels[i].v_load);
            self.levels[i].mass.solve_in_place(&mut w_h);
            self.levels[i].energy.solve_in_place(&mut w_v);
            let h_remainder = self.remainder(i, u, Some(&w_h), false);
            let v_remainder = self.remainder(i, u, Some(&w_v), true);
            let level = &mut self.levels[i];
            level.recorded.h_projection.extend_from_slice(&w_h);
            level.recorded.v_projection.extend_from_slice(&w_v);
            level.recorded.h_remainder.push(h_remainder);
            level.recorded.v_remainder.push(v_remainder);
            (level.h_load, level.v_load) = (w_h, w_v);
        }
    }
}

/// `P w` of level `from`'s `w` up the chain of `levels` to the finest one, through the
/// buffers `up` (`w` itself for the finest).
fn prolongate_to_finest<'w>(
    levels: &[LevelRecorder],
    up: &'w mut [Vec<f64>],
    from: usize,
    w: &'w [f64],
) -> &'w [f64] {
    let last = levels.len() - 1;
    if from == last {
        return w;
    }
    let into_finer = |i: usize| {
        levels[i]
            .prolongation
            .as_ref()
            .expect("a coarser level prolongates into the next")
    };
    into_finer(from).apply_into(w, &mut up[from]);
    for i in from + 1..last {
        let (done, rest) = up.split_at_mut(i);
        into_finer(i).apply_into(&done[i - 1], &mut rest[0]);
    }
    &up[last - 1]
}

/// A recorder without a level.
fn no_level() -> Error {
    ParameterError::new(
        "levels",
        "none",
        "at least one level to project the reference on",
    )
    .into()
}

impl FineSide<'_> {
    /// The loads `Pᵀ M u` and `Pᵀ (M + S) u` of the finest level into `loads` (`None` on a
    /// distributed run's ranks other than 0).
    fn loads(&mut self, u: &[f64], loads: Option<(&mut [f64], &mut [f64])>) {
        match self {
            FineSide::Whole {
                norms,
                prolongation,
                mass_u,
                energy_u,
                ..
            } => {
                let (h, v) = loads.expect("one process holds the levels");
                norms.mass.mul_into(u, mass_u);
                norms.stiffness.mul_into(u, energy_u);
                for (e, m) in energy_u.iter_mut().zip(mass_u.iter()) {
                    *e += m;
                }
                prolongation.restrict_into(mass_u, h);
                prolongation.restrict_into(energy_u, v);
            }
            FineSide::Slab(slab) => slab.loads(u, loads),
            FineSide::Unstarted(_) => unreachable!("a distributed recorder is started first"),
        }
    }

    /// `‖u − P w‖²_A` of the finest level's `w` (`None` on a distributed run's ranks other
    /// than 0).
    fn remainder(&mut self, u: &[f64], w: Option<&[f64]>, energy: bool) -> f64 {
        match self {
            FineSide::Whole {
                norms,
                prolongation,
                pw,
                residual,
                scratch,
                ..
            } => {
                prolongation.apply_into(w.expect("one process holds the levels"), pw);
                for ((r, ui), pi) in residual.iter_mut().zip(u).zip(pw.iter()) {
                    *r = ui - pi;
                }
                if energy {
                    norms.v_squared(residual, scratch)
                } else {
                    norms.h_squared(residual, scratch)
                }
            }
            FineSide::Slab(slab) => slab.remainder(u, w, energy),
            FineSide::Unstarted(_) => unreachable!("a distributed recorder is started first"),
        }
    }
}

impl Observer for ProjectionRecorder<'_> {
    /// The step's projections ([`ProjectionRecorder::record`]) of the whole reference.
    fn observe(&mut self, state: &Integration<'_>) -> Result<(), Error> {
        self.record(state.displacement());
        Ok(())
    }
}

impl SlabObserver for ProjectionRecorder<'_> {
    /// Cuts the reference's side into this rank's slab.
    fn start(&mut self, slabs: &Slabs) -> Result<(), Error> {
        if let FineSide::Unstarted(setup) = &self.fine {
            self.fine = FineSide::Slab(Box::new(setup.start(slabs)?));
        }
        Ok(())
    }

    /// The step's projections ([`ProjectionRecorder::record`]) from this rank's part of `U`.
    fn observe_slab(&mut self, state: &SlabState) {
        self.record(state.u);
    }
}
