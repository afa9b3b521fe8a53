//! Helpers shared by the tests that drive the `signorini` binary.

use std::process::{Command, Output};

/// The reference cache of this test's process (`SIGNORINI_CACHE`): the commands' default
/// cache is the user's, which a test must neither read nor fill.
pub fn test_cache() -> std::path::PathBuf {
    std::env::temp_dir().join(format!("signorini-test-cache-{}", std::process::id()))
}

/// Runs the binary from the repository root, as CI would (`CI=true`: no progress bar), with
/// this test's own reference cache ([`test_cache`]).
pub fn signorini(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_signorini"))
        .args(args)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .env("CI", "true")
        .env("SIGNORINI_CACHE", test_cache())
        .output()
        .expect("the binary runs")
}

/// The standard output of a run that must have succeeded (its stderr otherwise).
pub fn success_stdout(out: &Output) -> String {
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// Runs `args`, expects `code`, a message on stderr containing every needle, no panic.
pub fn expect_error(args: &[&str], code: i32, needles: &[&str]) {
    let out = signorini(args);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(code), "{args:?}: stderr {stderr}");
    assert!(!stderr.contains("panicked"), "{args:?} panicked: {stderr}");
    assert!(!stderr.contains("RUST_BACKTRACE"), "{args:?}: {stderr}");
    for n in needles {
        assert!(stderr.contains(n), "{args:?}: {n:?} not in {stderr}");
    }
}
