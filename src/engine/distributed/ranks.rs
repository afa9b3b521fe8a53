//! The processes of a distributed run, as the slab decomposition needs them: point-to-point
//! messages between neighbouring slabs and a sum that every process computes alike.

/// The ranks of a distributed run, seen from one of them. Messages between two ranks arrive
/// in the order they were sent (as MPI guarantees for one communicator and tag), and every
/// rank calls the collective operations ([`Ranks::gather_all`], [`Ranks::sum`]) in the same
/// order.
pub trait Ranks {
    /// This rank, `0..size`.
    fn rank(&self) -> usize;

    /// The number of ranks.
    fn size(&self) -> usize;

    /// Sends `values` to rank `to`.
    fn send(&self, to: usize, values: &[f64]);

    /// Receives from rank `from` exactly `into.len()` values into `into`.
    fn receive(&self, from: usize, into: &mut [f64]);

    /// Sends `values` to rank `with` and receives as many of its values into `into` (both
    /// ranks call it with each other: MPI's `sendrecv`, which cannot deadlock on the pair).
    fn exchange(&self, with: usize, values: &[f64], into: &mut [f64]);

    /// The ranks that share this rank's machine, and so its memory (1 unless known).
    fn on_this_machine(&self) -> usize {
        1
    }

    /// What this rank has exchanged so far, where it is counted ([`super::CountedRanks`]).
    fn traffic(&self) -> Option<super::Traffic> {
        None
    }

    /// Every rank's `value`, in rank order, into `into` (`size` entries), on every rank.
    fn gather_all(&self, value: f64, into: &mut [f64]);

    /// `Σ_r part_r` summed in rank order, `((part_0 + part_1) + part_2) + …`, the same bits on
    /// every rank and in every run with as many ranks: a reduction whose order depended on the
    /// arrival of messages would make a run irreproducible. With one rank it is `part` itself,
    /// so a one-rank run computes what the one-process code computes.
    fn sum(&self, part: f64) -> f64 {
        let mut parts = vec![0.0; self.size()];
        self.gather_all(part, &mut parts);
        parts
            .iter()
            .copied()
            .reduce(|total, p| total + p)
            .unwrap_or(part)
    }
}
