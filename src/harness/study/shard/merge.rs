//! Putting shards back together: the files must be of one invocation, shards `1..=n` each
//! present once, and every job of the list present once.

use std::path::PathBuf;

use super::file::{Invocation, ShardFile, SHARD_FORMAT};
use super::spec::{MAX_JOBS, MAX_SHARDS};
use super::ShardError;

/// The shards of one invocation put back together.
#[derive(Debug, Clone, PartialEq)]
pub struct Merged {
    /// The invocation the shards ran.
    pub invocation: Invocation,
    /// The identity the shards recorded ([`Invocation::identity`]).
    pub identity: String,
    /// Every job's result, in job order.
    pub results: Vec<String>,
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
    Ok(Merged {
        invocation: Invocation {
            command: first.command.clone(),
            arguments: first.arguments.clone(),
            request: first.request.clone(),
            inputs: first.inputs.clone(),
        },
        identity: first.identity.clone(),
        results,
    })
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
        assert_eq!(m.results, ["r0", "r1", "r2", "r3"]);
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
        let e = merge(vec![(p, huge.sealed())]).unwrap_err();
        assert!(e.to_string().contains("n = 10001"), "{e}");
    }

    #[test]
    fn refuses_shards_of_other_invocations_and_lost_jobs() {
        let (p, mut other) = shard(2, 2, &[2, 3]);
        other.arguments.push("--levels".into());
        let other = other.sealed();
        let e = merge(vec![shard(1, 2, &[0, 1]), (p, other)]).unwrap_err();
        assert!(e.to_string().contains("arguments"), "{e}");
        let e = merge(vec![shard(1, 2, &[0, 1]), shard(2, 2, &[2])]).unwrap_err();
        assert!(e.to_string().contains("job 3"), "{e}");
        let e = merge(vec![shard(1, 2, &[0, 1]), shard(2, 2, &[1, 2, 3])]).unwrap_err();
        assert!(e.to_string().contains("job 1"), "{e}");
    }
}
