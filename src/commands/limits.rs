//! The resource limits of the commands that read or compute: one set of options, checked
//! against the estimate of [`crate::harness::study::budget`] before anything is allocated.

use serde::{Deserialize, Serialize};

use super::failure::Failure;
use crate::harness::study::budget::{parse_bytes, parse_dof_steps, BudgetError, Estimate, Limits};

/// `--max-memory`, `--max-files` and `--max-dof-steps`: the limits a run or a study is held
/// to before it starts.
#[derive(Debug, Clone, Copy, clap::Args, Serialize, Deserialize)]
pub struct LimitArgs {
    /// Largest estimated memory to accept, in bytes or with a suffix K, M, G or T (powers of
    /// 1024). Default: the machine's available memory (MemAvailable in /proc/meminfo; 4G where
    /// it cannot be read).
    #[arg(long, value_parser = parse_bytes)]
    pub max_memory: Option<u64>,
    /// Most files to write. Default: 1000.
    #[arg(long)]
    pub max_files: Option<u64>,
    /// Largest estimated work to accept, in dof-steps (unknowns × time steps, summed over the
    /// runs). Default: 1e12 (hours).
    #[arg(long, value_parser = parse_dof_steps)]
    pub max_dof_steps: Option<f64>,
}

impl LimitArgs {
    /// `Ok` when `estimate` is within the limits; otherwise a usage error (exit code 2) that
    /// states the estimate and the limit.
    pub fn check(&self, estimate: Estimate) -> Result<(), Failure> {
        estimate.check(&self.limits()).map_err(Failure::from)
    }

    /// The limits given, the defaults for the others ([`Limits::or_defaults`]).
    pub fn limits(&self) -> Limits {
        Limits::or_defaults(self.max_memory, self.max_files, self.max_dof_steps)
    }
}

impl From<BudgetError> for Failure {
    fn from(e: BudgetError) -> Self {
        Self::usage(e)
    }
}
