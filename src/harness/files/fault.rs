//! Fault injection into the file operations of a commit, for the tests only:
//! `SIGNORINI_COMMIT_FAULT=<n>:kill` aborts the process (as SIGKILL would: no handler runs) at
//! the `n`-th operation of the process's commits ([`step`]), and `<n>:enospc` makes that operation
//! fail with "no space left on device" instead. `tests/cli/commit_faults.rs` sets it at every
//! operation in turn; nothing else does, and without it [`step`] only runs its operation.

use std::io;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::OnceLock;

/// What `SIGNORINI_COMMIT_FAULT` asks for: the operation's number and whether to abort.
fn fault() -> Option<(usize, bool)> {
    static FAULT: OnceLock<Option<(usize, bool)>> = OnceLock::new();
    *FAULT.get_or_init(|| {
        let spec = std::env::var("SIGNORINI_COMMIT_FAULT").ok()?;
        let (n, kind) = spec.split_once(':')?;
        Some((n.parse().ok()?, kind == "kill"))
    })
}

/// One file operation of a commit: `op`, unless the fault injection stops the process or fails
/// the operation here.
pub fn step<T>(op: impl FnOnce() -> io::Result<T>) -> io::Result<T> {
    static DONE: AtomicUsize = AtomicUsize::new(0);
    if let Some((n, kill)) = fault() {
        if DONE.fetch_add(1, Ordering::SeqCst) + 1 == n {
            if kill {
                std::process::abort();
            }
            return Err(io::Error::from_raw_os_error(28));
        }
    }
    op()
}
