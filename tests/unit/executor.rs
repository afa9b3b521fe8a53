//! The executor of a study's jobs (`harness::study::executor`) on a list whose results are known in
//! advance: the shards' shares partition the largest-first order, their merge hands the reduce
//! step exactly what the local executor does (bit for bit, a NaN included), and a merge with
//! the wrong number of results, or a result out of range, is refused naming what is wrong.

use std::sync::atomic::{AtomicUsize, Ordering};

use serde::{Deserialize, Serialize};
use signorini::harness::files::error::Error;
use signorini::harness::study::executor::{largest_first, run_local, Executed, Executor, JobList};
use signorini::harness::study::shard::{InRange, ShardSpec};

/// A job's result: its index and a value that no formula in the test recomputes from it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
struct Sample {
    index: usize,
    value: f64,
}

impl InRange for Sample {
    fn out_of_range(&self) -> Option<String> {
        (self.value < 0.0).then(|| format!("value = {}; allowed: >= 0", self.value))
    }
}

/// Eleven jobs of uneven sizes (ties included) whose results are fixed values, counting the
/// jobs run.
struct Fixed {
    sizes: Vec<usize>,
    values: Vec<f64>,
    ran: AtomicUsize,
}

impl Fixed {
    fn new() -> Self {
        Self {
            sizes: vec![3, 9, 1, 9, 4, 4, 7, 2, 8, 5, 6],
            values: vec![
                0.5,
                1e-300,
                f64::NAN,
                2.0,
                0.1,
                3.5,
                7.25,
                1.0 / 3.0,
                9.0,
                0.0,
                1e300,
            ],
            ran: AtomicUsize::new(0),
        }
    }
}

impl JobList for Fixed {
    type Output = Sample;

    fn count(&self) -> usize {
        self.sizes.len()
    }

    fn size(&self, index: usize) -> usize {
        self.sizes[index]
    }

    fn run(&self, index: usize) -> Result<Sample, Error> {
        self.ran.fetch_add(1, Ordering::Relaxed);
        Ok(Sample {
            index,
            value: self.values[index],
        })
    }
}

/// The bits of every value, NaN included, in list order.
fn bits(samples: &[Sample]) -> Vec<(usize, u64)> {
    samples
        .iter()
        .map(|s| (s.index, s.value.to_bits()))
        .collect()
}

#[test]
fn the_shares_partition_the_list_and_their_merge_is_the_local_run() {
    let list = Fixed::new();
    let local = run_local(&list).unwrap();
    assert_eq!(
        local.iter().map(|s| s.index).collect::<Vec<_>>(),
        (0..11).collect::<Vec<_>>()
    );
    let n = 4;
    let mut merged: Vec<Option<String>> = vec![None; list.count()];
    let mut shared = 0;
    for k in 1..=n {
        let Executed::Share(share) = Executor::Shard(ShardSpec { k, n }).execute(&list).unwrap()
        else {
            panic!("a shard hands back its share");
        };
        assert_eq!(share.jobs, 11);
        for r in share.results {
            assert!(merged[r.index].is_none(), "job {} in two shares", r.index);
            merged[r.index] = Some(r.result);
            shared += 1;
        }
    }
    assert_eq!(shared, 11, "every job in exactly one share");
    let results: Vec<String> = merged.into_iter().map(Option::unwrap).collect();
    let ran_before = list.ran.load(Ordering::Relaxed);
    let Executed::Complete(replayed) = Executor::Merge(results).execute(&list).unwrap() else {
        panic!("a merge hands back every result");
    };
    assert_eq!(
        list.ran.load(Ordering::Relaxed),
        ran_before,
        "a merge runs no job"
    );
    assert_eq!(bits(&replayed), bits(&local));
}

#[test]
fn a_shard_takes_every_nth_job_of_the_largest_first_order() {
    let list = Fixed::new();
    let order = largest_first(&list.sizes);
    assert_eq!(order, [1, 3, 8, 6, 10, 9, 4, 5, 0, 7, 2]);
    let Executed::Share(share) = Executor::Shard(ShardSpec { k: 2, n: 3 })
        .execute(&list)
        .unwrap()
    else {
        panic!("a shard hands back its share");
    };
    let mut expected = vec![order[1], order[4], order[7], order[10]];
    expected.sort_unstable();
    let indices: Vec<usize> = share.results.iter().map(|r| r.index).collect();
    assert_eq!(indices, expected);
}

#[test]
fn a_merge_refuses_a_wrong_count_and_a_result_out_of_range() {
    let list = Fixed::new();
    let e = Executor::Merge(vec![])
        .execute(&list)
        .unwrap_err()
        .to_string();
    assert!(e.contains("0 job results") && e.contains("11 jobs"), "{e}");

    let mut negative = Fixed::new();
    negative.values[5] = -1.0;
    let mut results = vec![String::new(); 11];
    for k in 1..=2 {
        let Executed::Share(share) = Executor::Shard(ShardSpec { k, n: 2 })
            .execute(&negative)
            .unwrap()
        else {
            panic!("a shard hands back its share");
        };
        for r in share.results {
            results[r.index] = r.result;
        }
    }
    let e = Executor::Merge(results)
        .execute(&list)
        .unwrap_err()
        .to_string();
    assert!(e.contains("job 5") && e.contains("value = -1"), "{e}");
}
