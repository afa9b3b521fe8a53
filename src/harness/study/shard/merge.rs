//! Putting shards back together: the files must be of one invocation, shards `1..=n` each
//! present once, and every job of the list present once.

use std::path::PathBuf;

use super::file::{Invocation, ListRun, ShardFile, SHARD_FORMAT};
use super::spec::{MAX_JOBS, MAX_SHARDS};
use super::ShardError;

/// The shards of one invocation put back together.
#[derive(Debug, Clone, PartialEq)]
pub struct Merged {
    /// The invocation the shards ran.
    pub invocation: Invocation,
    /// The identity the shards recorded ([`Invocation::identity`]).
    pub identity: String,
    /// Every job's result, with the shards' times.
    pub jobs: MergedJobs,
}

/// What the shards of one invocation ran, put back together: what
/// [`crate::harness::study::executor::Executor::Merge`] hands to the command's studies.
#[derive(Debug, Clone, PartialEq)]
pub struct MergedJobs {
    /// Every job's result, in job order (the lists one after the other), encoded.
    pub results: Vec<String>,
    /// The job lists, in the order the command handed them, each with the longest of the
    /// shards' wall times on it: the list's wall time had the shards run at once.
    pub lists: Vec<ListRun>,
}

/// Merges `shards` (each with the path it was read from), or says which is wrong.
pub fn merge(shards: Vec<(PathBuf, ShardFile)>) -> Result<Merged, ShardError> {
    for (path, s) in &shards {
        if s.format != SHARD_FORMAT {
            return Err(ShardError::Format {
                path: path.clone(),
                found: s.format.clone(),
                expected: SHARD_FORMAT,
            });
        }
        if !s.verify() {
            return Err(ShardError::Checksum { path: path.clone() });
        }
        for (field, value, max) in [("n", s.n, MAX_SHARDS), ("jobs", s.jobs, MAX_JOBS)] {
            if value > max {
                return Err(ShardError::TooMany {
                    path: path.clone(),
                    field,
                    value,
                    max,
                });
            }
        }
        let listed: usize = s.lists.iter().map(|l| l.jobs).sum();
        if listed != s.jobs {
            return Err(ShardError::Lists {
                path: path.clone(),
                listed,
                jobs: s.jobs,
            });
        }
    }
    let Some((first_path, first)) = shards.first() else {
        return Err(ShardError::NoShards);
    };
    for (path, s) in &shards[1..] {
        let differs = [
            ("signorini", s.signorini != first.signorini),
            ("command", s.command != first.command),
            ("arguments", s.arguments != first.arguments),
            ("request", s.request != first.request),
            ("inputs", s.inputs != first.inputs),
            ("identity", s.identity != first.identity),
            ("n", s.n != first.n),
            ("jobs", s.jobs != first.jobs),
            ("lists", !same_lists(&s.lists, &first.lists)),
        ];
        if let Some((field, _)) = differs.iter().find(|(_, d)| *d) {
            return Err(ShardError::Mismatch {
                field,
                first: first_path.clone(),
                other: path.clone(),
            });
        }
    }
    let n = first.n;
    let mut by_k: Vec<Vec<PathBuf>> = vec![Vec::new(); n];
    for (path, s) in &shards {
        if s.k == 0 || s.k > n {
            return Err(ShardError::ShardNumber {
                path: path.clone(),
                k: s.k,
                n,
            });
        }
        by_k[s.k - 1].push(path.clone());
    }
    if let Some((k, paths)) = by_k.iter().enumerate().find(|(_, p)| p.len() > 1) {
        return Err(ShardError::Duplicate {
            k: k + 1,
            n,
            paths: paths.clone(),
        });
    }
    let missing: Vec<usize> = (1..=n).filter(|&k| by_k[k - 1].is_empty()).collect();
    if !missing.is_empty() {
        return Err(ShardError::Missing { missing, n });
    }
    let mut results: Vec<Option<String>> = vec![None; first.jobs];
    for (path, s) in &shards {
        for job in &s.results {
            let slot = results
                .get_mut(job.index)
                .filter(|slot| slot.is_none())
                .ok_or_else(|| ShardError::JobIndex {
                    path: path.clone(),
                    index: job.index,
                    jobs: first.jobs,
                })?;
            *slot = Some(job.result.clone());
        }
    }
    let results = results
        .into_iter()
        .enumerate()
        .map(|(index, r)| r.ok_or(ShardError::MissingJob { index }))
        .collect::<Result<_, _>>()?;
    let lists = first
        .lists
        .iter()
        .enumerate()
        .map(|(k, list)| ListRun {
            jobs: list.jobs,
            wall_seconds: shards
                .iter()
                .map(|(_, s)| s.lists[k].wall_seconds)
                .fold(0.0, f64::max),
        })
        .collect();
    Ok(Merged {
        invocation: Invocation {
            command: first.command.clone(),
            arguments: first.arguments.clone(),
            request: first.request.clone(),
            inputs: first.inputs.clone(),
        },
        identity: first.identity.clone(),
        jobs: MergedJobs { results, lists },
    })
}

/// Whether two shards' job lists are the same lists (their times differ from shard to shard).
fn same_lists(a: &[ListRun], b: &[ListRun]) -> bool {
    a.len() == b.len() && a.iter().zip(b).all(|(x, y)| x.jobs == y.jobs)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::harness::study::shard::file::JobResult;

    fn shard(k: usize, n: usize, indices: &[usize]) -> (PathBuf, ShardFile) {
        let file = ShardFile {
            format: SHARD_FORMAT.into(),
            signorini: "0".into(),
            command: "study".into(),
            arguments: vec!["scene.json".into()],
            request: String::new(),
            inputs: vec![],
            identity: "0123456789abcdef".into(),
            k,
            n,
            jobs: 4,
            lists: vec![
                ListRun {
                    jobs: 3,
                    wall_seconds: k as f64,
                },
                ListRun {
                    jobs: 1,
                    wall_seconds: 0.5,
                },
            ],
            checksum: String::new(),
            results: indices
                .iter()
                .map(|&index| JobResult {
                    index,
                    result: format!("r{index}"),
                })
                .collect(),
        }
        .sealed();
        (PathBuf::from(format!("s{k}.json")), file)
    }

    #[test]
    fn merges_the_jobs_back_in_order() {
        let m = merge(vec![shard(2, 2, &[3, 1]), shard(1, 2, &[0, 2])]).unwrap();
        assert_eq!(m.jobs.results, ["r0", "r1", "r2", "r3"]);
        let times: Vec<(usize, f64)> = m
            .jobs
            .lists
            .iter()
            .map(|l| (l.jobs, l.wall_seconds))
            .collect();
        assert_eq!(times, [(3, 2.0), (1, 0.5)], "each list's longest shard");
    }

    #[test]
    fn names_missing_and_duplicate_shards() {
        let e = merge(vec![shard(1, 3, &[0, 1]), shard(3, 3, &[2, 3])]).unwrap_err();
        assert!(e.to_string().contains("2/3"), "{e}");
        let e = merge(vec![shard(1, 2, &[0, 1]), shard(1, 2, &[2, 3])]).unwrap_err();
        assert!(e.to_string().contains("s1.json"), "{e}");
    }

    #[test]
    fn refuses_a_changed_file_and_absurd_counts() {
        let (p, mut changed) = shard(2, 2, &[2, 3]);
        changed.results[0].result = "r9".into();
        let e = merge(vec![shard(1, 2, &[0, 1]), (p.clone(), changed)]).unwrap_err();
        assert!(matches!(e, ShardError::Checksum { .. }), "{e}");
        let (_, mut huge) = shard(1, 1, &[0]);
        huge.n = MAX_SHARDS + 1;
        let e = merge(vec![(p.clone(), huge.sealed())]).unwrap_err();
        assert!(e.to_string().contains("n = 10001"), "{e}");
        let (_, mut short) = shard(1, 1, &[0]);
        short.lists.pop();
        let e = merge(vec![(p, short.sealed())]).unwrap_err();
        assert!(
            e.to_string().contains("3 jobs") && e.to_string().contains("jobs = 4"),
            "{e}"
        );
    }

    #[test]
    fn refuses_shards_of_other_invocations_and_lost_jobs() {
        let (p, mut other) = shard(2, 2, &[2, 3]);
        other.arguments.push("--levels".into());
        let other = other.sealed();
        let e = merge(vec![shard(1, 2, &[0, 1]), (p.clone(), other)]).unwrap_err();
        assert!(e.to_string().contains("arguments"), "{e}");
        let (_, mut split) = shard(2, 2, &[2, 3]);
        split.lists = vec![ListRun {
            jobs: 4,
            wall_seconds: 1.0,
        }];
        let e = merge(vec![shard(1, 2, &[0, 1]), (p, split.sealed())]).unwrap_err();
        assert!(e.to_string().contains("lists"), "{e}");
        let e = merge(vec![shard(1, 2, &[0, 1]), shard(2, 2, &[2])]).unwrap_err();
        assert!(e.to_string().contains("job 3"), "{e}");
        let e = merge(vec![shard(1, 2, &[0, 1]), shard(2, 2, &[1, 2, 3])]).unwrap_err();
        assert!(e.to_string().contains("job 1"), "{e}");
    }
}
