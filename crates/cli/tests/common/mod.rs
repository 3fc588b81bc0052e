//! Helpers shared by the end-to-end tests of the `caustica` binary.

#![allow(dead_code)] // each test file uses a different subset

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// Runs the built binary with `args` in the current directory.
pub fn caustica(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_caustica"))
        .args(args)
        .output()
        .expect("run caustica")
}

/// Runs the built binary with `args` in `dir`.
pub fn caustica_in(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_caustica"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("run caustica")
}

/// `name` inside a directory of this test process, `caustica-<group>-<pid>` under the system
/// temporary directory (created if missing).
pub fn tmp_in(group: &str, name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("caustica-{group}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

pub fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

pub fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

/// Asserts a failed run: non-zero exit, no panic, and every string of `must_contain` in stderr.
pub fn assert_clean_failure(o: &Output, must_contain: &[&str]) {
    let err = stderr(o);
    assert!(
        !o.status.success(),
        "expected failure, got success; stderr: {err}"
    );
    assert!(!err.contains("panicked"), "panic: {err}");
    for m in must_contain {
        assert!(err.contains(m), "stderr lacks '{m}': {err}");
    }
}
