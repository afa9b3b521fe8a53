//! What the job runner of this thread does with the next job list it is given: run it all (the
//! default), run one shard's share of it and stop the study ([`record_share`]), or take its
//! results from merged shards instead of running it ([`replay`]).
//!
//! The plan is per thread: a command installs it around the study it calls, and the study's
//! top-level job list is scheduled on that thread. Job lists nested inside a job run on the
//! worker threads, which have no plan, and run whole as part of their job.

use std::cell::RefCell;

use super::{ShardError, ShardSpec};
use crate::harness::error::Error;

/// One job's result as [`super::codec`] writes it, with the job's index in its list.
#[derive(Debug, Clone, PartialEq)]
pub struct EncodedResult {
    /// The job's index in its list (the order the study gives its jobs, not the run order).
    pub index: usize,
    /// The job's result, [`super::codec::encode`]d.
    pub result: String,
}

/// What one shard ran: the size of the job list and the results of its share.
#[derive(Debug, Clone, PartialEq)]
pub struct Share {
    /// The number of jobs in the whole list.
    pub jobs: usize,
    /// The results of this shard's jobs, by index.
    pub results: Vec<EncodedResult>,
}

/// How the runner schedules the job list it is given ([`next_list`]).
#[derive(Debug)]
pub enum Schedule {
    /// Run every job.
    All,
    /// Run this shard's share, hand the results to [`finish_share`] and stop.
    Share(ShardSpec),
    /// Run nothing: every job's result, in job order, [`super::codec::encode`]d.
    Replay(Vec<String>),
}

enum Plan {
    Unsharded,
    Sharding {
        spec: ShardSpec,
        share: Option<Share>,
    },
    Replaying {
        results: Option<Vec<String>>,
    },
}

thread_local! {
    static PLAN: RefCell<Plan> = const { RefCell::new(Plan::Unsharded) };
}

/// Puts the plan back to [`Plan::Unsharded`] when dropped, however the study ended.
struct Installed;

impl Installed {
    fn new(plan: Plan) -> Self {
        PLAN.with(|p| *p.borrow_mut() = plan);
        Self
    }

    fn take(&self) -> Plan {
        PLAN.with(|p| std::mem::replace(&mut *p.borrow_mut(), Plan::Unsharded))
    }
}

impl Drop for Installed {
    fn drop(&mut self) {
        self.take();
    }
}

/// Runs `study` as shard `spec`: its first job list runs only this shard's share, whose results
/// are returned; the study stops there (its reports are the merge's to write).
pub fn record_share<T>(
    spec: ShardSpec,
    study: impl FnOnce() -> Result<T, Error>,
) -> Result<Share, Error> {
    let installed = Installed::new(Plan::Sharding { spec, share: None });
    let outcome = study();
    let share = match installed.take() {
        Plan::Sharding { share, .. } => share,
        Plan::Unsharded | Plan::Replaying { .. } => None,
    };
    match (outcome, share) {
        (Err(Error::Shard(ShardError::Recorded)), Some(share)) => Ok(share),
        (Err(e), _) => Err(e),
        (Ok(_), _) => Err(ShardError::NoJobList.into()),
    }
}

/// Runs `study` with the results of its job list taken from `results` (every job's, in job
/// order) instead of running the jobs.
pub fn replay<T, E: From<ShardError>>(
    results: Vec<String>,
    study: impl FnOnce() -> Result<T, E>,
) -> Result<T, E> {
    let installed = Installed::new(Plan::Replaying {
        results: Some(results),
    });
    let value = study()?;
    match installed.take() {
        Plan::Replaying { results: None } => Ok(value),
        _ => Err(ShardError::NoJobList.into()),
    }
}

/// Whether a merge is replaying its shards' results on this thread: the study it runs computes
/// none of its jobs.
pub fn replaying() -> bool {
    PLAN.with(|p| matches!(&*p.borrow(), Plan::Replaying { .. }))
}

/// How to schedule a job list of `jobs` jobs given on this thread.
pub fn next_list(jobs: usize) -> Result<Schedule, Error> {
    PLAN.with(|p| match &mut *p.borrow_mut() {
        Plan::Unsharded => Ok(Schedule::All),
        Plan::Sharding { spec, share: None } => Ok(Schedule::Share(*spec)),
        Plan::Sharding { share: Some(_), .. } | Plan::Replaying { results: None } => {
            Err(ShardError::SecondJobList.into())
        }
        Plan::Replaying { results } => {
            let given = results.take().expect("matched Some");
            if given.len() == jobs {
                Ok(Schedule::Replay(given))
            } else {
                Err(ShardError::JobCount {
                    shards: given.len(),
                    study: jobs,
                }
                .into())
            }
        }
    })
}

/// Keeps the results of this shard's share of a list of `jobs` jobs and returns the error that
/// stops the study ([`record_share`] catches it).
pub fn finish_share(jobs: usize, results: Vec<EncodedResult>) -> Error {
    PLAN.with(|p| {
        if let Plan::Sharding { share, .. } = &mut *p.borrow_mut() {
            *share = Some(Share { jobs, results });
        }
    });
    ShardError::Recorded.into()
}
