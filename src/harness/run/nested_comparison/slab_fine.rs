//! The reference's fine space cut into the slabs of a distributed run ([`SlabFine`]): what the
//! projections of the reference on its coarse levels, and its comparison with the check run,
//! need of the fine field, computed by every rank on its slab, so that no rank holds the whole
//! field for them.
//!
//! With `P` the prolongation from the finest coarse level into the reference mesh and `A` a
//! fine norm matrix (`M`, or `M + S`), the projections need two things of the fine space
//! ([`super::projection`]):
//! ```text
//! Pᵀ A u = Σ_r P_rᵀ (A u)_r          the coarse loads: each rank restricts its rows;
//! ‖u − P w‖²_A = Σ_r (u − P w)_rᵀ (A (u − P w))_r    each rank its rows' part.
//! ```
//! The products `A u` read one layer of each neighbour (exchanged, [`SlabOperator`]); a rank's
//! rows of `P` read a contiguous range of the coarse dofs ([`Prolongation::of_layers`]), which is
//! all rank 0 sends it of `w` and all it sends rank 0 of its restriction. Rank 0 adds the
//! restrictions in rank order and every sum is [`Ranks::sum`]'s, so a run on `N` ranks is
//! reproducible, and on one rank every number is the one-process recorder's.

use std::ops::Range;

use super::norm_matrices::NormMatrices;
use crate::engine::distributed::{Ranks, SlabOperator, Slabs};
use crate::engine::fem::{BoxMesh, Prolongation};
use crate::harness::files::error::Error;

/// What a [`SlabFine`] is made from before the run has cut the box into slabs: the ranks, the
/// reference mesh's norm matrices, the coarse mesh whose field is prolongated and the
/// reference mesh.
pub struct SlabSetup<'r> {
    /// The ranks of the run.
    pub ranks: &'r dyn Ranks,
    /// The reference mesh's norm matrices.
    pub norms: &'r NormMatrices,
    /// The coarse mesh prolongated from.
    pub coarse: BoxMesh,
    /// The reference mesh.
    pub fine: &'r BoxMesh,
}

impl<'r> SlabSetup<'r> {
    /// This rank's [`SlabFine`] on the run's `slabs` (every rank together).
    pub fn start(&self, slabs: &Slabs) -> Result<SlabFine<'r>, Error> {
        SlabFine::new(self.ranks, self.norms, (&self.coarse, self.fine), slabs)
    }
}

/// This rank's slab of the reference's fine space, for the projections on the coarse
/// levels and the check comparison.
pub struct SlabFine<'r> {
    ranks: &'r dyn Ranks,
    mass: SlabOperator<'r, dyn Ranks + 'r>,
    stiffness: SlabOperator<'r, dyn Ranks + 'r>,
    /// This rank's rows of the prolongation from the finest coarse level.
    prolongation: Prolongation,
    /// Every rank's range of the finest level's dofs (rank 0's to send and receive them).
    ranges: Vec<Range<usize>>,
    /// This rank's parts of `M u` and `(M + S) u`.
    mass_u: Vec<f64>,
    energy_u: Vec<f64>,
    /// This rank's part of `u − P w`, and the product's.
    residual: Vec<f64>,
    scratch: Vec<f64>,
    /// This rank's range of a finest-level vector.
    part: Vec<f64>,
}

impl<'r> SlabFine<'r> {
    /// Rank `ranks.rank()`'s slab in `slabs` of the reference mesh `fine`, whose norm matrices
    /// are `norms`, projected on `finest` (the finest coarse level). Every rank together.
    pub fn new(
        ranks: &'r dyn Ranks,
        norms: &NormMatrices,
        (finest, fine): (&BoxMesh, &BoxMesh),
        slabs: &Slabs,
    ) -> Result<Self, Error> {
        let operator = |m: &crate::engine::fem::SymmetricMatrix| {
            let stencil = m.stencil().ok_or_else(|| {
                Error::from(
                    crate::engine::distributed::DecompositionError::NotABoxMatrix(
                        "the norm matrices of the reference mesh are assembled",
                    ),
                )
            })?;
            SlabOperator::new(ranks, stencil, slabs).map_err(Error::from)
        };
        let mass = operator(&norms.mass)?;
        let stiffness = operator(&norms.stiffness)?;
        let prolongation = Prolongation::of_layers(finest, fine, slabs.of(ranks.rank()))?;
        let own = mass.own_dofs().len();
        if prolongation.fine_dofs() != own {
            return Err(
                crate::engine::distributed::DecompositionError::NotABoxMatrix(
                    "the slab's prolongation rows are not its unknowns",
                )
                .into(),
            );
        }
        let range = prolongation.coarse_range();
        let (mut starts, mut ends) = (vec![0.0; ranks.size()], vec![0.0; ranks.size()]);
        ranks.gather_all(range.start as f64, &mut starts);
        ranks.gather_all(range.end as f64, &mut ends);
        let ranges = (starts.iter().zip(&ends))
            .map(|(&s, &e)| s as usize..e as usize)
            .collect();
        Ok(Self {
            ranks,
            mass,
            stiffness,
            ranges,
            part: vec![0.0; range.len()],
            prolongation,
            mass_u: vec![0.0; own],
            energy_u: vec![0.0; own],
            residual: vec![0.0; own],
            scratch: vec![0.0; own],
        })
    }

    /// The coarse loads `Pᵀ M u` and `Pᵀ (M + S) u` of this rank's part `u` of the reference,
    /// into `loads` on rank 0 (the whole finest level; `None` on the others). Every rank
    /// together.
    pub fn loads(&mut self, u: &[f64], loads: Option<(&mut [f64], &mut [f64])>) {
        self.mass.mul_dot(u, &mut self.mass_u);
        self.stiffness.mul_dot(u, &mut self.energy_u);
        for (e, m) in self.energy_u.iter_mut().zip(&self.mass_u) {
            *e += m;
        }
        match loads {
            Some((h, v)) => {
                self.restrict_onto_rank_0(true, h);
                self.restrict_onto_rank_0(false, v);
            }
            None => {
                self.restrict_onto_rank_0(true, &mut []);
                self.restrict_onto_rank_0(false, &mut []);
            }
        }
    }

    /// `Pᵀ (M u)` (`mass`) or `Pᵀ ((M + S) u)` summed on rank 0 into `whole`, the ranks'
    /// restrictions added in rank order.
    fn restrict_onto_rank_0(&mut self, mass: bool, whole: &mut [f64]) {
        let rows = if mass { &self.mass_u } else { &self.energy_u };
        self.prolongation.restrict_into(rows, &mut self.part);
        if self.ranks.rank() != 0 {
            self.ranks.send(0, &self.part);
            return;
        }
        whole.fill(0.0);
        whole[self.ranges[0].clone()].copy_from_slice(&self.part);
        for r in 1..self.ranks.size() {
            let range = self.ranges[r].clone();
            self.part.resize(range.len(), 0.0);
            self.ranks.receive(r, &mut self.part);
            for (w, p) in whole[range].iter_mut().zip(&self.part) {
                *w += p;
            }
        }
        self.part.resize(self.ranges[0].len(), 0.0);
    }

    /// `‖u − P w‖²_M` (`energy` false) or `‖u − P w‖²_{M+S}` of this rank's part `u` of the
    /// reference and the coarse `w` (given on rank 0, `None` elsewhere), on every rank. Every
    /// rank together.
    pub fn remainder(&mut self, u: &[f64], w: Option<&[f64]>, energy: bool) -> f64 {
        self.residual(u, w);
        let h = self.h_squared();
        if energy {
            h + self.s_squared()
        } else {
            h
        }
    }

    /// `(‖u − P w‖²_M, ‖u − P w‖²_{M+S})`, as [`SlabFine::remainder`].
    pub fn distances(&mut self, u: &[f64], w: Option<&[f64]>) -> (f64, f64) {
        self.residual(u, w);
        let h = self.h_squared();
        (h, h + self.s_squared())
    }

    /// Whether rank 0 says yes (`yes`, read on rank 0 only), on every rank.
    pub fn rank_0_says(&self, yes: bool) -> bool {
        self.ranks
            .sum(f64::from(u8::from(self.ranks.rank() == 0 && yes)))
            > 0.0
    }

    /// This rank.
    pub fn rank(&self) -> usize {
        self.ranks.rank()
    }

    /// `u − P w` on this rank's rows into `residual`, the parts of `w` sent by rank 0.
    fn residual(&mut self, u: &[f64], w: Option<&[f64]>) {
        if self.ranks.rank() == 0 {
            let w = w.expect("rank 0 holds the coarse field");
            for r in 1..self.ranks.size() {
                self.ranks.send(r, &w[self.ranges[r].clone()]);
            }
            self.part.copy_from_slice(&w[self.ranges[0].clone()]);
        } else {
            self.ranks.receive(0, &mut self.part);
        }
        self.prolongation.apply_into(&self.part, &mut self.residual);
        for (r, ui) in self.residual.iter_mut().zip(u) {
            *r = ui - *r;
        }
    }

    /// `rᵀ M r` of the residual, summed.
    fn h_squared(&mut self) -> f64 {
        self.ranks
            .sum(self.mass.mul_dot(&self.residual, &mut self.scratch))
    }

    /// `rᵀ S r` of the residual, summed.
    fn s_squared(&mut self) -> f64 {
        self.ranks
            .sum(self.stiffness.mul_dot(&self.residual, &mut self.scratch))
    }
}
