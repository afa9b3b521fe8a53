//! The ranks of a distributed run as threads of one process ([`ThreadRanks`]): the same
//! algorithms as under MPI, exchanging the same messages through channels, so that the slab
//! decomposition is tested by `cargo nextest run` without an MPI installation.

use std::sync::mpsc::{channel, Receiver, Sender};

use super::Ranks;

/// One rank of [`ThreadRanks::run`]: a channel to every other rank and one from each.
#[derive(Debug)]
pub struct ThreadRanks {
    rank: usize,
    /// `to[r]`: the channel into rank `r` (unused for this rank).
    to: Vec<Sender<Vec<f64>>>,
    /// `from[r]`: the channel out of rank `r` (unused for this rank).
    from: Vec<Receiver<Vec<f64>>>,
}

impl ThreadRanks {
    /// Runs `body` on `size` ranks, each in its own thread, and returns their results in rank
    /// order. A rank that panics makes this panic (the others may then wait forever on it:
    /// this is for tests, where the harness's time limit ends them).
    pub fn run<T: Send>(size: usize, body: impl Fn(&ThreadRanks) -> T + Sync) -> Vec<T> {
        let size = size.max(1);
        let mut senders: Vec<Vec<Option<Sender<Vec<f64>>>>> = (0..size)
            .map(|_| (0..size).map(|_| None).collect())
            .collect();
        let mut receivers: Vec<Vec<Option<Receiver<Vec<f64>>>>> = (0..size)
            .map(|_| (0..size).map(|_| None).collect())
            .collect();
        for from in 0..size {
            for to in 0..size {
                let (tx, rx) = channel();
                senders[from][to] = Some(tx);
                receivers[to][from] = Some(rx);
            }
        }
        let ranks: Vec<ThreadRanks> = senders
            .into_iter()
            .zip(receivers)
            .enumerate()
            .map(|(rank, (to, from))| ThreadRanks {
                rank,
                to: to.into_iter().map(|s| s.expect("every pair")).collect(),
                from: from.into_iter().map(|r| r.expect("every pair")).collect(),
            })
            .collect();
        let body = &body;
        std::thread::scope(|scope| {
            let handles: Vec<_> = ranks
                .into_iter()
                .map(|ranks| scope.spawn(move || body(&ranks)))
                .collect();
            handles
                .into_iter()
                .map(|h| h.join().unwrap_or_else(|p| std::panic::resume_unwind(p)))
                .collect()
        })
    }
}

impl Ranks for ThreadRanks {
    fn rank(&self) -> usize {
        self.rank
    }

    fn size(&self) -> usize {
        self.to.len()
    }

    /// Every rank: they are threads of one process.
    fn on_this_machine(&self) -> usize {
        self.to.len()
    }

    fn send(&self, to: usize, values: &[f64]) {
        self.to[to]
            .send(values.to_vec())
            .expect("the receiving rank is running");
    }

    fn receive(&self, from: usize, into: &mut [f64]) {
        let values = self.from[from].recv().expect("the sending rank is running");
        assert_eq!(values.len(), into.len(), "message of rank {from}");
        into.copy_from_slice(&values);
    }

    fn exchange(&self, with: usize, values: &[f64], into: &mut [f64]) {
        self.send(with, values);
        self.receive(with, into);
    }

    fn gather_all(&self, value: f64, into: &mut [f64]) {
        for r in (0..self.size()).filter(|&r| r != self.rank) {
            self.send(r, &[value]);
        }
        for (r, slot) in into.iter_mut().enumerate() {
            if r == self.rank {
                *slot = value;
            } else {
                self.receive(r, std::slice::from_mut(slot));
            }
        }
    }
}
