//! What a job's result read back from a shard file must satisfy to be taken for a result: the
//! checksum ([`super::file::ShardFile::verify`]) already refuses a changed file, and this refuses
//! values no run produces (a non-finite or negative error norm), should a shard have been
//! written by a damaged build or forged with a matching checksum.

use std::collections::BTreeMap;

use crate::harness::run::norms::Norm;

/// A job result's values within their ranges.
pub trait InRange {
    /// The first value out of its range, described; `None` when every value is in range.
    fn out_of_range(&self) -> Option<String>;

    /// The level (elements along the axis) the result says it was measured at, where it says
    /// one: a merge checks it against its job's ([`crate::harness::study::executor::JobList::level`]).
    fn level(&self) -> Option<usize> {
        None
    }
}

/// The first of `errors` that is not a finite number ≥ 0 (an error norm is one).
pub fn errors_out_of_range(errors: &BTreeMap<Norm, f64>) -> Option<String> {
    errors
        .iter()
        .find(|(_, e)| !(e.is_finite() && **e >= 0.0))
        .map(|(norm, e)| format!("error {} = {e}; allowed: a finite number >= 0", norm.key()))
}

/// `name = x` described when `x` is not a finite number > 0 (a mesh size, a time step).
pub fn positive(name: &str, x: f64) -> Option<String> {
    (!(x.is_finite() && x > 0.0)).then(|| format!("{name} = {x}; allowed: a finite number > 0"))
}

/// `name = x` described when `x` is negative (a quantity ≥ 0 by definition that a failed run
/// may leave non-finite).
pub fn not_negative(name: &str, x: f64) -> Option<String> {
    (x < 0.0).then(|| format!("{name} = {x}; allowed: a number >= 0 (or not finite)"))
}

/// A name (the scene a `reference` shard obtained) has no range: the merge compares it with the
/// scene it expects.
impl InRange for String {
    fn out_of_range(&self) -> Option<String> {
        None
    }
}

/// A job that keeps nothing besides its outcome has nothing out of range.
impl InRange for () {
    fn out_of_range(&self) -> Option<String> {
        None
    }
}
