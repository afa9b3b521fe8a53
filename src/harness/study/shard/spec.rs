//! `--shard k/n`: which share of a job list one machine runs.

use std::fmt;
use std::str::FromStr;

use serde::{Deserialize, Serialize};

use crate::engine::error::ParameterError;

/// The most shards one command may be split into (`--shard k/n`, and `n` in a shard file): a
/// GitHub Actions matrix holds 256 jobs, a Slurm array 1 001 by default.
pub const MAX_SHARDS: usize = 10_000;

/// The most jobs a shard file may say its command's job list has (`jobs`): the largest study
/// has a few hundred.
pub const MAX_JOBS: usize = 1_000_000;

/// Shard `k` of `n` (`1 ≤ k ≤ n`): the jobs at positions `k − 1`, `k − 1 + n`, `k − 1 + 2n`, …
/// of a job list in its largest-first order, so that every shard gets a fair part of the large
/// jobs and the `n` shards together run each job exactly once. A command that hands several
/// lists to its executor deals them on: the positions run through the lists' orders one after
/// the other.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct ShardSpec {
    /// This shard's number, from 1.
    pub k: usize,
    /// The number of shards.
    pub n: usize,
}

/// What `--shard` accepts, for its error messages.
const ALLOWED: &str =
    "k/n with integers 1 <= k <= n <= 10000 (e.g. 2/4: the second of four shards)";

impl ShardSpec {
    /// The jobs of this shard out of `order`, the job indices of a list in their largest-first
    /// order, when `dealt` jobs of earlier lists were dealt round the shards before them.
    pub fn share(&self, order: &[usize], dealt: usize) -> Vec<usize> {
        let first = (self.k - 1 + self.n - dealt % self.n) % self.n;
        order.iter().skip(first).step_by(self.n).copied().collect()
    }
}

impl FromStr for ShardSpec {
    type Err = ParameterError;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let invalid = || ParameterError::new("--shard", s, ALLOWED);
        let (k, n) = s.split_once('/').ok_or_else(invalid)?;
        let k: usize = k.trim().parse().map_err(|_| invalid())?;
        let n: usize = n.trim().parse().map_err(|_| invalid())?;
        if k == 0 || k > n || n > MAX_SHARDS {
            return Err(invalid());
        }
        Ok(Self { k, n })
    }
}

impl fmt::Display for ShardSpec {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}/{}", self.k, self.n)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_k_of_n_and_refuses_the_rest() {
        assert_eq!("2/4".parse(), Ok(ShardSpec { k: 2, n: 4 }));
        assert_eq!("1/1".parse(), Ok(ShardSpec { k: 1, n: 1 }));
        for bad in [
            "0/3",
            "4/3",
            "3",
            "a/3",
            "1/0",
            "-1/3",
            "1/3/4",
            "",
            "1/10001",
            "1/18446744073709551615",
        ] {
            let e = bad.parse::<ShardSpec>().unwrap_err();
            assert_eq!(e.name, "--shard", "{bad}");
        }
    }

    #[test]
    fn the_shares_partition_the_order() {
        let order = [4, 0, 3, 1, 2, 5, 6];
        for dealt in [0, 1, 2, 3, 7] {
            let mut all: Vec<usize> = (1..=3)
                .flat_map(|k| ShardSpec { k, n: 3 }.share(&order, dealt))
                .collect();
            all.sort_unstable();
            assert_eq!(all, (0..7).collect::<Vec<_>>(), "{dealt} dealt before");
        }
        assert_eq!(ShardSpec { k: 1, n: 3 }.share(&order, 0), vec![4, 1, 6]);
        // Two jobs dealt before: shard 1's turn comes at the list's second position.
        assert_eq!(ShardSpec { k: 1, n: 3 }.share(&order, 2), vec![0, 2]);
        assert_eq!(ShardSpec { k: 3, n: 3 }.share(&order, 2), vec![4, 1, 6]);
    }
}
