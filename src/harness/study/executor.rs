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
//! A study asks for its jobs once, through one call of [`Executor::execute`]; a command that
//! runs several studies hands their lists one after the other into one [`Batch`]
//! ([`Executor::execute_lists`]), which a shard deals as one list and writes as one file. Each
//! list's results come with its wall time ([`ListResults`]): a shard records its time on each
//! list, and a merge reports the longest shard's. The executor holds no state between calls and
//! nothing of it is global; the jobs it computes are counted in the progress a command shows
//! ([`progress::stage`]).

use std::time::Instant;

use rayon::prelude::*;
use serde::de::DeserializeOwned;
use serde::Serialize;

use crate::harness::files::error as files;
use crate::harness::study::error::Error;
use crate::harness::study::progress::{self, Stage};
use crate::harness::study::shard::{
    codec, EncodedResult, InRange, ListRun, MergedJobs, ShardError, ShardSpec, Share,
};

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

    /// The level job `index` runs at, where the list has levels: a result read back from a
    /// shard must say the same ([`InRange::level`]).
    fn level(&self, _index: usize) -> Option<usize> {
        None
    }
}

/// The jobs of a list given as items, their sizes and a function of an item: a [`JobList`]
/// written in one expression. A job fails with a run's or a file's error, or with any other
/// that lifts into a study's (`E`).
pub struct Jobs<'a, J, T, E = files::Error> {
    /// The items, one per job.
    pub items: &'a [J],
    /// The work of an item.
    pub size: &'a (dyn Fn(&J) -> usize + Sync),
    /// The job of an item.
    pub run: &'a (dyn Fn(&J) -> Result<T, E> + Sync),
}

impl<J, T, E> JobList for Jobs<'_, J, T, E>
where
    J: Sync,
    T: Send + Serialize + DeserializeOwned + InRange,
    E: Into<Error>,
{
    type Output = T;

    fn count(&self) -> usize {
        self.items.len()
    }

    fn size(&self, index: usize) -> usize {
        (self.size)(&self.items[index])
    }

    fn run(&self, index: usize) -> Result<T, Error> {
        (self.run)(&self.items[index]).map_err(Into::into)
    }
}

/// Who runs a job list.
#[derive(Debug, Clone, PartialEq)]
pub enum Executor {
    /// Every job, here.
    Local,
    /// This shard's share of the jobs.
    Shard(ShardSpec),
    /// No job: every job's result, in job order, [`codec::encode`]d, read from the shards with
    /// their times on each list.
    Merge(MergedJobs),
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

/// Every result of one job list, in job order, and the list's wall time: measured here around
/// its jobs when they ran here; after a merge, the longest of the shards' times on their shares
/// of it (the list's wall time had the shards run at once, [`MergedJobs::lists`]).
#[derive(Debug, Clone, PartialEq)]
pub struct ListResults<T> {
    /// Every job's result, in job order.
    pub results: Vec<T>,
    /// The list's wall time, seconds (see the type).
    pub wall_seconds: f64,
}

impl Executor {
    /// Hands `list` to this executor: every result in job order, or this shard's share. The
    /// jobs computed here run in parallel.
    pub fn execute<L: JobList>(&self, list: &L) -> Result<Executed<ListResults<L::Output>>, Error> {
        self.execute_lists(|batch| batch.execute(list))
    }

    /// [`Executor::execute`] with the jobs computed here run one at a time, the largest first:
    /// for jobs that each take the whole machine.
    pub fn execute_in_turn<L: JobList>(
        &self,
        list: &L,
    ) -> Result<Executed<ListResults<L::Output>>, Error> {
        self.execute_lists(|batch| batch.execute_with(list, Parallel::No))
    }

    /// Hands `plan` a [`Batch`] of this executor, into which it hands its job lists one after
    /// the other, and returns what it makes of their results; a shard's share of every list
    /// when the executor is a shard's (`plan` then returns `None`: no list hands it results).
    pub fn execute_lists<T, E: From<Error>>(
        &self,
        plan: impl FnOnce(&mut Batch<'_>) -> Result<Option<T>, E>,
    ) -> Result<Executed<T>, E> {
        let mut batch = Batch {
            executor: self,
            lists: Vec::new(),
            results: Vec::new(),
        };
        let value = plan(&mut batch)?;
        Ok(batch.finish(value)?)
    }
}

/// The job lists of one command handed to one executor as one list: each list's jobs are
/// numbered on from the previous list's, a shard's share deals on through them
/// ([`ShardSpec::share`]), and a merge hands each list its own results. The lists must not
/// depend on one another's results, which a shard does not have: a list that needs the cases
/// an earlier study ran runs every case, and its reduce step keeps those cases.
pub struct Batch<'e> {
    executor: &'e Executor,
    /// The lists handed so far, with their wall times.
    lists: Vec<ListRun>,
    /// A shard's results so far, by index in the whole list.
    results: Vec<EncodedResult>,
}

impl Batch<'_> {
    /// Hands `list` to the executor as the batch's next list: every result in job order, or
    /// `None` for a shard, whose share the batch keeps for its file. The jobs computed here run
    /// in parallel, the largest first.
    pub fn execute<L: JobList>(
        &mut self,
        list: &L,
    ) -> Result<Option<ListResults<L::Output>>, Error> {
        self.execute_with(list, Parallel::Yes)
    }

    fn execute_with<L: JobList>(
        &mut self,
        list: &L,
        parallel: Parallel,
    ) -> Result<Option<ListResults<L::Output>>, Error> {
        let dealt: usize = self.lists.iter().map(|l| l.jobs).sum();
        let jobs = list.count();
        let list_jobs = list;
        let clock = Instant::now();
        let (results, wall_seconds) = match self.executor {
            Executor::Local => (
                Some(run_all(list, parallel, &self.lists)?),
                clock.elapsed().as_secs_f64(),
            ),
            Executor::Shard(spec) => {
                let order = spec.share(&largest_first(&sizes_of(list)), dealt);
                let stage = list_stage(&self.lists, order.len());
                for (index, r) in run_in_order(list, &order, parallel, &stage)? {
                    self.results.push(EncodedResult {
                        index: dealt + index,
                        result: codec::encode(&r)?,
                    });
                }
                (None, clock.elapsed().as_secs_f64())
            }
            Executor::Merge(merged) => {
                let number = self.lists.len();
                let list = merged.lists.get(number);
                let texts = merged.results.get(dealt..dealt + jobs);
                let (Some(list), Some(texts)) = (list.filter(|l| l.jobs == jobs), texts) else {
                    return Err(ShardError::JobCount {
                        list: number + 1,
                        shards: list.map_or(0, |l| l.jobs),
                        study: jobs,
                    }
                    .into());
                };
                (
                    Some(decode_all(list_jobs, texts, dealt)?),
                    list.wall_seconds,
                )
            }
        };
        self.lists.push(ListRun { jobs, wall_seconds });
        Ok(results.map(|results| ListResults {
            results,
            wall_seconds,
        }))
    }

    /// What the batch hands back once every list is handed: `value`, what the command made of
    /// the lists' results, or a shard's share of every list. A merge whose shards hold lists
    /// the command did not hand is refused.
    fn finish<T>(self, value: Option<T>) -> Result<Executed<T>, Error> {
        if let Executor::Merge(merged) = self.executor {
            if merged.lists.len() != self.lists.len() {
                return Err(ShardError::ListCount {
                    shards: merged.lists.len(),
                    study: self.lists.len(),
                }
                .into());
            }
        }
        match (self.executor, value) {
            (Executor::Shard(_), _) => Ok(Executed::Share(Share {
                lists: self.lists,
                results: self.results,
            })),
            (_, Some(value)) => Ok(Executed::Complete(value)),
            (_, None) => Err(ShardError::NoResult.into()),
        }
    }
}

/// The results `texts` of the jobs of `list`, numbered from `first` in the whole batch,
/// decoded and checked ([`InRange`]: their values, and their level against the job's).
fn decode_all<L: JobList>(
    list: &L,
    texts: &[String],
    first: usize,
) -> Result<Vec<L::Output>, Error> {
    texts
        .iter()
        .enumerate()
        .map(|(k, text)| {
            let index = first + k;
            let result: L::Output = codec::decode(index, text)?;
            let level = match (list.level(k), result.level()) {
                (Some(job), Some(said)) if job != said => Some(format!(
                    "a result of level {said} where the job's level is {job}"
                )),
                _ => None,
            };
            match result.out_of_range().or(level) {
                Some(why) => Err(ShardError::OutOfRange { index, why }.into()),
                None => Ok(result),
            }
        })
        .collect()
}

/// Runs every job of `list` here, in parallel, the largest first (they take longest; ties in
/// list order), and returns the results in list order with the list's wall time. The first
/// error stops the rest. What [`Executor::Local`] does, for the studies that are never sharded.
pub fn run_local<L: JobList>(list: &L) -> Result<ListResults<L::Output>, Error> {
    let clock = Instant::now();
    let results = run_all(list, Parallel::Yes, &[])?;
    Ok(ListResults {
        results,
        wall_seconds: clock.elapsed().as_secs_f64(),
    })
}

/// Every job of `list`, the largest started first, after the lists `before` of its batch; the
/// results in list order.
fn run_all<L: JobList>(
    list: &L,
    parallel: Parallel,
    before: &[ListRun],
) -> Result<Vec<L::Output>, Error> {
    let order = largest_first(&sizes_of(list));
    let stage = list_stage(before, order.len());
    Ok(run_in_order(list, &order, parallel, &stage)?
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

/// The progress stage of the `jobs` computed here of a batch's list that comes after the lists
/// `before`.
fn list_stage(before: &[ListRun], jobs: usize) -> Stage {
    match before.len() {
        0 => progress::stage("jobs", jobs, "jobs"),
        n => progress::stage(&format!("job list {}", n + 1), jobs, "jobs"),
    }
}

/// Runs the jobs `order` of `list`, starting them in that order (in parallel or one at a time),
/// and returns their results with their indices, by index; each job done is counted in `stage`.
fn run_in_order<L: JobList>(
    list: &L,
    order: &[usize],
    parallel: Parallel,
    stage: &Stage,
) -> Result<Vec<(usize, L::Output)>, Error> {
    let run = |&k: &usize| {
        let result = list.run(k).map(|r| (k, r));
        stage.advance(1);
        result
    };
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

/// The indices of the jobs of sizes `sizes`, a command's only list, that `executor` computes
/// here: every job, a shard's share of the largest-first order, or none under a merge.
pub fn computed_here(sizes: &[usize], executor: &Executor) -> Vec<usize> {
    match executor {
        Executor::Local => (0..sizes.len()).collect(),
        Executor::Shard(spec) => spec.share(&largest_first(sizes), 0),
        Executor::Merge(_) => Vec::new(),
    }
}
