//! The executor of a study's jobs (`harness::study::executor`) on a list whose results are known in
//! advance: the shards' shares partition the largest-first order, their merge hands the reduce
//! step exactly what the local executor does (bit for bit, a NaN included), and a merge with
//! the wrong number of results, or a result out of range, is refused naming what is wrong. A
//! batch of several lists is dealt as one list, its merge hands each list its own results and
//! the longest shard's time on it, and shards of other lists are refused.

use std::sync::atomic::{AtomicUsize, Ordering};

use serde::{Deserialize, Serialize};
use signorini::harness::study::error::Error;
use signorini::harness::study::executor::{
    largest_first, run_local, Batch, Executed, Executor, JobList, ListResults,
};
use signorini::harness::study::shard::merge::merge;
use signorini::harness::study::shard::{
    InRange, Invocation, ListRun, MergedJobs, ShardSpec, Share,
};

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
    let local = run_local(&list).unwrap().results;
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
        assert_eq!(share.jobs(), 11);
        for r in share.results {
            assert!(merged[r.index].is_none(), "job {} in two shares", r.index);
            merged[r.index] = Some(r.result);
            shared += 1;
        }
    }
    assert_eq!(shared, 11, "every job in exactly one share");
    let results: Vec<String> = merged.into_iter().map(Option::unwrap).collect();
    let ran_before = list.ran.load(Ordering::Relaxed);
    let Executed::Complete(replayed) = Executor::Merge(one_list(results)).execute(&list).unwrap()
    else {
        panic!("a merge hands back every result");
    };
    let replayed = replayed.results;
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
    let e = Executor::Merge(one_list(vec![]))
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
    let e = Executor::Merge(one_list(results))
        .execute(&list)
        .unwrap_err()
        .to_string();
    assert!(e.contains("job 5") && e.contains("value = -1"), "{e}");
}

/// `results`, the merged results of a command that hands one list to its executor.
fn one_list(results: Vec<String>) -> MergedJobs {
    MergedJobs {
        lists: vec![ListRun {
            jobs: results.len(),
            wall_seconds: 0.0,
        }],
        results,
    }
}

/// The results of two lists of samples.
type Both = (ListResults<Sample>, ListResults<Sample>);

/// Two lists into one batch, as a command that runs two studies hands them: the values of both
/// lists' results (`None` for a shard).
fn two_lists(batch: &mut Batch<'_>, first: &Fixed, second: &Fixed) -> Result<Option<Both>, Error> {
    let a = batch.execute(first)?;
    let b = batch.execute(second)?;
    Ok(a.zip(b))
}

#[test]
fn a_batch_of_two_lists_is_dealt_as_one_and_its_merge_hands_each_list_its_own() {
    let (first, second) = (Fixed::new(), Fixed::new());
    let Executed::Complete((a, b)) = Executor::Local
        .execute_lists(|batch| two_lists(batch, &first, &second))
        .unwrap()
    else {
        panic!("a local batch hands back every result");
    };
    let n = 3;
    let invocation = Invocation {
        command: "report".into(),
        arguments: vec![],
        request: String::new(),
        inputs: vec![],
    };
    let shards: Vec<(std::path::PathBuf, _)> = (1..=n)
        .map(|k| {
            let spec = ShardSpec { k, n };
            let Executed::Share(share) = Executor::Shard(spec)
                .execute_lists(|batch| two_lists(batch, &first, &second))
                .unwrap()
            else {
                panic!("a shard hands back its share");
            };
            assert_eq!(
                share.lists.iter().map(|l| l.jobs).collect::<Vec<_>>(),
                [11, 11]
            );
            (
                format!("shard-{k}").into(),
                invocation.shard_file(spec, share).unwrap(),
            )
        })
        .collect();
    // 22 jobs dealt round three shards: 8, 7 and 7, the second list's dealt on from the first's.
    let counts: Vec<usize> = shards.iter().map(|(_, f)| f.results.len()).collect();
    assert_eq!(counts, [8, 7, 7]);
    let slowest: Vec<f64> = (0..2)
        .map(|l| {
            shards
                .iter()
                .map(|(_, f)| f.lists[l].wall_seconds)
                .fold(0.0, f64::max)
        })
        .collect();
    let merged = merge(shards).unwrap().jobs;
    let merged_times: Vec<f64> = merged.lists.iter().map(|l| l.wall_seconds).collect();
    assert_eq!(
        merged_times, slowest,
        "each list's time is its longest shard's"
    );
    let ran_before = first.ran.load(Ordering::Relaxed) + second.ran.load(Ordering::Relaxed);
    let executor = Executor::Merge(merged);
    let Executed::Complete((ma, mb)) = executor
        .execute_lists(|batch| two_lists(batch, &first, &second))
        .unwrap()
    else {
        panic!("a merge hands back every result");
    };
    let ran_after = first.ran.load(Ordering::Relaxed) + second.ran.load(Ordering::Relaxed);
    assert_eq!(ran_after, ran_before, "a merge runs no job");
    assert_eq!(bits(&ma.results), bits(&a.results));
    assert_eq!(bits(&mb.results), bits(&b.results));
    assert_eq!((ma.wall_seconds, mb.wall_seconds), (slowest[0], slowest[1]));

    // The same shards merged into a command that hands one list, or three: refused.
    let e = executor.execute(&first).unwrap_err().to_string();
    assert!(e.contains("2 job lists") && e.contains("has 1"), "{e}");
    let e = executor
        .execute_lists(|batch| {
            two_lists(batch, &first, &second)?;
            batch.execute(&first).map(|r| r.map(|_| ()))
        })
        .unwrap_err()
        .to_string();
    assert!(e.contains("0 job results for job list 3"), "{e}");
}

#[test]
fn a_shard_hands_back_its_share_of_every_list_of_a_batch() {
    let (first, second) = (Fixed::new(), Fixed::new());
    let spec = ShardSpec { k: 2, n: 3 };
    let Executed::Share(Share { lists, results }) = Executor::Shard(spec)
        .execute_lists(|batch| two_lists(batch, &first, &second))
        .unwrap()
    else {
        panic!("a shard hands back its share");
    };
    assert_eq!(lists.len(), 2);
    // The first list's order from position 1, every third; the second list's continues the
    // dealing: 11 jobs dealt before it, so shard 2 takes its positions 2, 5 and 8.
    let order = largest_first(&first.sizes);
    let mut expected: Vec<usize> = [1, 4, 7, 10].iter().map(|&p| order[p]).collect();
    expected.sort_unstable();
    let mut second_share: Vec<usize> = [2, 5, 8].iter().map(|&p| 11 + order[p]).collect();
    second_share.sort_unstable();
    expected.extend(second_share);
    let indices: Vec<usize> = results.iter().map(|r| r.index).collect();
    assert_eq!(indices, expected);
}

/// A result that says the level it was measured at.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
struct LevelSample {
    level: usize,
}

impl InRange for LevelSample {
    fn out_of_range(&self) -> Option<String> {
        None
    }

    fn level(&self) -> Option<usize> {
        Some(self.level)
    }
}

/// Three jobs at levels 10, 20 and 40 whose results say the levels `said`.
struct AtLevels {
    said: [usize; 3],
}

impl JobList for AtLevels {
    type Output = LevelSample;

    fn count(&self) -> usize {
        3
    }

    fn size(&self, index: usize) -> usize {
        index + 1
    }

    fn run(&self, index: usize) -> Result<LevelSample, Error> {
        Ok(LevelSample {
            level: self.said[index],
        })
    }

    fn level(&self, index: usize) -> Option<usize> {
        Some([10, 20, 40][index])
    }
}

/// The results of `list` as one shard writes them.
fn shard_results(list: &AtLevels) -> Vec<String> {
    let Executed::Share(share) = Executor::Shard(ShardSpec { k: 1, n: 1 })
        .execute(list)
        .unwrap()
    else {
        panic!("a shard hands back its share");
    };
    let mut results = vec![String::new(); 3];
    for r in share.results {
        results[r.index] = r.result;
    }
    results
}

/// A merged result whose level is not its job's (a level-10 result saying 20, which the study
/// tabulated as a second level 20) is refused naming the job (issue 55 item 4).
#[test]
fn a_merge_refuses_a_result_of_another_level_than_its_job() {
    let honest = AtLevels { said: [10, 20, 40] };
    let merged = Executor::Merge(one_list(shard_results(&honest)))
        .execute(&honest)
        .unwrap();
    assert!(matches!(merged, Executed::Complete(_)));
    let forged = shard_results(&AtLevels { said: [20, 20, 40] });
    let e = Executor::Merge(one_list(forged))
        .execute(&honest)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("job 0") && e.contains("a result of level 20 where the job's level is 10"),
        "{e}"
    );
}
