//! Who runs a study's jobs: every study is a list of independent jobs and a reduce step, and
//! the list is handed to an [`Executor`] given explicitly by the caller.
//!
//! - [`Executor::Local`] runs every job here, in parallel, the largest first (rayon).
//! - [`Executor::Shard`] runs one shard's share of the largest-first order
//!   ([`ShardSpec::share`]) and hands back the share's encoded results ([`Executed::Share`]):
//!   the study does not reduce, the command writes the shard's file ([`super::shard`]).
//! - [`Executor::Merge`] runs nothing: every job's result is decoded from the merged shards,
//!   checked ([`InRange`]) and handed to the reduce step, which writes what the unsharded
//!   command writes.
//!
//! A study asks for its jobs once, through one call of [`Executor::execute`]; the executor holds
//! no state between calls and nothing of it is global.

use rayon::prelude::*;
use serde::de::DeserializeOwned;
use serde::Serialize;

use crate::harness::files::error::Error;
use crate::harness::study::shard::{codec, EncodedResult, InRange, ShardError, ShardSpec, Share};

/// A list of independent jobs: the unit a study hands to an [`Executor`].
pub trait JobList: Sync {
    /// What one job returns: what a shard writes and a merge reads back.
    type Output: Send + Serialize + DeserializeOwned + InRange;

    /// The number of jobs.
    fn count(&self) -> usize;

    /// The work of job `index`, in any unit: the larger start first.
    fn size(&self, index: usize) -> usize;

    /// Runs job `index`.
    fn run(&self, index: usize) -> Result<Self::Output, Error>;
}

/// The jobs of a list given as items, their sizes and a function of an item: a [`JobList`]
/// written in one expression.
pub struct Jobs<'a, J, T> {
    /// The items, one per job.
    pub items: &'a [J],
    /// The work of an item.
    pub size: &'a (dyn Fn(&J) -> usize + Sync),
    /// The job of an item.
    pub run: &'a (dyn Fn(&J) -> Result<T, Error> + Sync),
}

impl<J: Sync, T: Send + Serialize + DeserializeOwned + InRange> JobList for Jobs<'_, J, T> {
    type Output = T;

    fn count(&self) -> usize {
        self.items.len()
    }

    fn size(&self, index: usize) -> usize {
        (self.size)(&self.items[index])
    }

    fn run(&self, index: usize) -> Result<T, Error> {
        (self.run)(&self.items[index])
    }
}

/// Who runs a job list.
#[derive(Debug, Clone, PartialEq)]
pub enum Executor {
    /// Every job, here.
    Local,
    /// This shard's share of the jobs.
    Shard(ShardSpec),
    /// No job: every job's result, in job order, [`codec::encode`]d, read from the shards.
    Merge(Vec<String>),
}

/// What an executor hands back: every job's result (local or merged), or a shard's share.
#[derive(Debug, Clone, PartialEq)]
pub enum Executed<T> {
    /// Every job's result, or what the study made of them.
    Complete(T),
    /// The results of one shard's share, for its file.
    Share(Share),
}

impl<T> Executed<T> {
    /// The complete results passed through `reduce`; a share as it is.
    pub fn reduce<U>(
        self,
        reduce: impl FnOnce(T) -> Result<U, Error>,
    ) -> Result<Executed<U>, Error> {
        match self {
            Self::Complete(value) => reduce(value).map(Executed::Complete),
            Self::Share(share) => Ok(Executed::Share(share)),
        }
    }
}

impl Executor {
    /// Hands `list` to this executor: every result in job order, or this shard's share. The
    /// jobs computed here run in parallel.
    pub fn execute<L: JobList>(&self, list: &L) -> Result<Executed<Vec<L::Output>>, Error> {
        self.execute_with(list, Parallel::Yes)
    }

    /// [`Executor::execute`] with the jobs computed here run one at a time, the largest first:
    /// for jobs that each take the whole machine.
    pub fn execute_in_turn<L: JobList>(&self, list: &L) -> Result<Executed<Vec<L::Output>>, Error> {
        self.execute_with(list, Parallel::No)
    }

    fn execute_with<L: JobList>(
        &self,
        list: &L,
        parallel: Parallel,
    ) -> Result<Executed<Vec<L::Output>>, Error> {
        match self {
            Self::Local => run_all(list, parallel).map(Executed::Complete),
            Self::Shard(spec) => {
                let order = spec.share(&largest_first(&sizes_of(list)));
                let results = run_in_order(list, &order, parallel)?
                    .iter()
                    .map(|(index, r)| {
                        codec::encode(r).map(|result| EncodedResult {
                            index: *index,
                            result,
                        })
                    })
                    .collect::<Result<_, _>>()?;
                Ok(Executed::Share(Share {
                    jobs: list.count(),
                    results,
                }))
            }
            Self::Merge(results) => {
                if results.len() != list.count() {
                    return Err(ShardError::JobCount {
                        shards: results.len(),
                        study: list.count(),
                    }
                    .into());
                }
                results
                    .iter()
                    .enumerate()
                    .map(|(index, text)| {
                        let result: L::Output = codec::decode(index, text)?;
                        match result.out_of_range() {
                            Some(why) => Err(ShardError::OutOfRange { index, why }.into()),
                            None => Ok(result),
                        }
                    })
                    .collect::<Result<_, Error>>()
                    .map(Executed::Complete)
            }
        }
    }
}

/// Runs every job of `list` here, in parallel, the largest first (they take longest; ties in
/// list order), and returns the results in list order. The first error stops the rest. What
/// [`Executor::Local`] does, for the studies that are never sharded.
pub fn run_local<L: JobList>(list: &L) -> Result<Vec<L::Output>, Error> {
    run_all(list, Parallel::Yes)
}

/// Every job of `list`, the largest started first; the results in list order.
fn run_all<L: JobList>(list: &L, parallel: Parallel) -> Result<Vec<L::Output>, Error> {
    let order = largest_first(&sizes_of(list));
    Ok(run_in_order(list, &order, parallel)?
        .into_iter()
        .map(|(_, r)| r)
        .collect())
}

/// Whether the jobs computed here run in parallel.
#[derive(Clone, Copy)]
enum Parallel {
    Yes,
    No,
}

/// Runs the jobs `order` of `list`, starting them in that order (in parallel or one at a time),
/// and returns their results with their indices, by index.
fn run_in_order<L: JobList>(
    list: &L,
    order: &[usize],
    parallel: Parallel,
) -> Result<Vec<(usize, L::Output)>, Error> {
    let run = |&k: &usize| list.run(k).map(|r| (k, r));
    let mut results = match parallel {
        Parallel::Yes => order
            .par_iter()
            .map(run)
            .collect::<Result<Vec<_>, Error>>()?,
        Parallel::No => order.iter().map(run).collect::<Result<Vec<_>, Error>>()?,
    };
    results.sort_by_key(|&(k, _)| k);
    Ok(results)
}

/// The sizes of the jobs of `list`, in list order.
fn sizes_of<L: JobList>(list: &L) -> Vec<usize> {
    (0..list.count()).map(|k| list.size(k)).collect()
}

/// The order in which jobs of sizes `sizes` start: their indices, the largest first, ties in
/// index order. A shard runs its share of this order ([`ShardSpec::share`]).
pub fn largest_first(sizes: &[usize]) -> Vec<usize> {
    let mut order: Vec<usize> = (0..sizes.len()).collect();
    order.sort_by_key(|&k| (std::cmp::Reverse(sizes[k]), k));
    order
}

/// The indices of the jobs of sizes `sizes` that `executor` computes here: every job, a
/// shard's share of the largest-first order, or none under a merge.
pub fn computed_here(sizes: &[usize], executor: &Executor) -> Vec<usize> {
    match executor {
        Executor::Local => (0..sizes.len()).collect(),
        Executor::Shard(spec) => spec.share(&largest_first(sizes)),
        Executor::Merge(_) => Vec::new(),
    }
}
