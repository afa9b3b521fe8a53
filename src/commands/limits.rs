//! The resource limits of the commands that run simulations (`run`, `study`): one set of
//! options, checked against the estimate of [`crate::harness::study::budget`] before anything is
//! allocated.

use serde::{Deserialize, Serialize};

use super::failure::Failure;
use crate::harness::study::budget::{BudgetError, Estimate, Limits};

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

/// Bytes: an integer with an optional suffix K, M, G or T (powers of 1024).
fn parse_bytes(s: &str) -> Result<u64, String> {
    let t = s.trim();
    let (digits, shift) = match t.char_indices().last() {
        Some((i, c)) if c.eq_ignore_ascii_case(&'k') => (&t[..i], 10),
        Some((i, c)) if c.eq_ignore_ascii_case(&'m') => (&t[..i], 20),
        Some((i, c)) if c.eq_ignore_ascii_case(&'g') => (&t[..i], 30),
        Some((i, c)) if c.eq_ignore_ascii_case(&'t') => (&t[..i], 40),
        _ => (t, 0),
    };
    digits
        .trim()
        .parse::<u64>()
        .ok()
        .and_then(|n| n.checked_mul(1_u64 << shift))
        .ok_or_else(|| {
            format!("{s:?}: allowed: a number of bytes, optionally with K, M, G or T (e.g. 512M)")
        })
}

/// Dof-steps: a finite number > 0.
fn parse_dof_steps(s: &str) -> Result<f64, String> {
    s.trim()
        .parse::<f64>()
        .ok()
        .filter(|v| v.is_finite() && *v > 0.0)
        .ok_or_else(|| format!("{s:?}: allowed: a finite number of dof-steps > 0 (e.g. 1e9)"))
}
