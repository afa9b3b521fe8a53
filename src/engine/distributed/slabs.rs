//! The decomposition of a box into slabs of node layers along its axis, one per rank.

use std::ops::Range;

use super::DecompositionError;

/// Which node layers along the box's axis (its last, slowest axis: a layer is a contiguous
/// range of the numbering) each rank holds: rank `r` the layers `bounds[r]..bounds[r + 1]`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Slabs {
    bounds: Vec<usize>,
}

impl Slabs {
    /// `layers` node layers over `ranks` ranks, as evenly as whole layers allow (the first
    /// ranks one layer more when they do not divide), rank 0 holding at least `first_layers`
    /// (the layers its contact or condensed plane needs, [`Slabs::FIRST_LAYERS_CONDENSED`]) and
    /// every rank at least one. Refused, with the reason, when the layers do not allow it.
    pub fn even(
        layers: usize,
        ranks: usize,
        first_layers: usize,
    ) -> Result<Self, DecompositionError> {
        let first_layers = first_layers.max(1);
        if ranks == 0 {
            return Err(DecompositionError::NoRanks);
        }
        if layers < first_layers + (ranks - 1) {
            return Err(DecompositionError::TooManyRanks {
                ranks,
                layers,
                most: (layers + 1).saturating_sub(first_layers),
                first_layers,
            });
        }
        let (share, extra) = (layers / ranks, layers % ranks);
        let mut sizes: Vec<usize> = (0..ranks).map(|r| share + usize::from(r < extra)).collect();
        // Rank 0 takes what it needs from the others, the last ones first.
        let mut missing = first_layers.saturating_sub(sizes[0]);
        sizes[0] += missing;
        for size in sizes.iter_mut().skip(1).rev() {
            let given = missing.min(*size - 1);
            *size -= given;
            missing -= given;
        }
        let mut bounds = vec![0];
        for size in sizes {
            bounds.push(bounds.last().copied().unwrap_or(0) + size);
        }
        Ok(Self { bounds })
    }

    /// The layers rank 0 needs when the step matrix's `Γ_Sig` plane is condensed
    /// ([`crate::engine::linalg::CondensedPlane`]): the plane and the layer it couples to.
    pub const FIRST_LAYERS_CONDENSED: usize = 2;

    /// The number of ranks.
    pub fn ranks(&self) -> usize {
        self.bounds.len() - 1
    }

    /// The node layers of the box.
    pub fn layers(&self) -> usize {
        self.bounds.last().copied().unwrap_or(0)
    }

    /// The layers of rank `rank`.
    pub fn of(&self, rank: usize) -> Range<usize> {
        self.bounds[rank]..self.bounds[rank + 1]
    }
}
