//! What the command-line tests share: running the binary, its stderr, the
//! files a run left.
#![allow(dead_code)] // each test binary uses some of these

use std::path::Path;
use std::process::{Command, Output};

/// Runs `penumbra ARGS` in `dir`.
pub fn penumbra(args: &[&str], dir: &Path) -> Output {
    command(args, dir).output().expect("run penumbra")
}

/// Runs `penumbra ARGS` in `dir` with the environment variable `var` set
/// to `value`, or removed where `value` is `None`.
pub fn penumbra_with_var(args: &[&str], dir: &Path, var: &str, value: Option<&str>) -> Output {
    let mut c = command(args, dir);
    match value {
        Some(v) => c.env(var, v),
        None => c.env_remove(var),
    };
    c.output().expect("run penumbra")
}

fn command(args: &[&str], dir: &Path) -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_penumbra"));
    c.args(args).current_dir(dir);
    c
}

pub fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// The names in `dir`, sorted.
pub fn files_in(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

/// Each (arguments, expected text) case fails, names the problem, does not
/// panic and leaves `dir` holding exactly `left` (sorted names).
pub fn expect_failures(cases: &[(&[&str], &str)], dir: &Path, left: &[&str]) {
    for (args, expected) in cases {
        let o = penumbra(args, dir);
        assert!(!o.status.success(), "{args:?} should fail");
        assert!(
            stderr(&o).contains(expected),
            "{args:?}: stderr does not mention '{expected}':\n{}",
            stderr(&o)
        );
        assert!(!stderr(&o).contains("panicked"), "{args:?} panicked");
        assert_eq!(files_in(dir), left, "{args:?} left files");
    }
}
