//! What a rank exchanges with the others ([`CountedRanks`]): the figures a cost model of a
//! distributed run is fitted to.

use std::cell::Cell;

use super::Ranks;

/// A rank's messages and collective sums so far.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Traffic {
    /// Point-to-point messages sent (an exchange sends one).
    pub messages: u64,
    /// Their bytes.
    pub bytes_sent: u64,
    /// Bytes received point to point.
    pub bytes_received: u64,
    /// Collective sums ([`Ranks::sum`]; each one gathers a value from every rank).
    pub sums: u64,
}

/// Ranks that count what this rank sends, receives and sums ([`Traffic`]), passing every call
/// on to `inner`.
pub struct CountedRanks<'a, R: Ranks + ?Sized> {
    inner: &'a R,
    traffic: Cell<Traffic>,
}

impl<'a, R: Ranks + ?Sized> CountedRanks<'a, R> {
    /// `inner`, counted from now on.
    pub fn new(inner: &'a R) -> Self {
        Self {
            inner,
            traffic: Cell::new(Traffic::default()),
        }
    }

    /// What this rank has exchanged so far.
    pub fn traffic(&self) -> Traffic {
        self.traffic.get()
    }

    fn count(&self, update: impl FnOnce(&mut Traffic)) {
        let mut t = self.traffic.get();
        update(&mut t);
        self.traffic.set(t);
    }
}

/// The bytes of `values`.
fn bytes(values: &[f64]) -> u64 {
    (std::mem::size_of_val(values)) as u64
}

impl<R: Ranks + ?Sized> Ranks for CountedRanks<'_, R> {
    fn rank(&self) -> usize {
        self.inner.rank()
    }

    fn size(&self) -> usize {
        self.inner.size()
    }

    fn send(&self, to: usize, values: &[f64]) {
        self.count(|t| {
            t.messages += 1;
            t.bytes_sent += bytes(values);
        });
        self.inner.send(to, values);
    }

    fn receive(&self, from: usize, into: &mut [f64]) {
        self.count(|t| t.bytes_received += bytes(into));
        self.inner.receive(from, into);
    }

    fn exchange(&self, with: usize, values: &[f64], into: &mut [f64]) {
        self.count(|t| {
            t.messages += 1;
            t.bytes_sent += bytes(values);
            t.bytes_received += bytes(into);
        });
        self.inner.exchange(with, values, into);
    }

    fn gather_all(&self, value: f64, into: &mut [f64]) {
        self.count(|t| t.sums += 1);
        self.inner.gather_all(value, into);
    }

    fn on_this_machine(&self) -> usize {
        self.inner.on_this_machine()
    }

    fn traffic(&self) -> Option<Traffic> {
        Some(self.traffic.get())
    }

    fn sum(&self, part: f64) -> f64 {
        self.count(|t| t.sums += 1);
        self.inner.sum(part)
    }
}
