//! What the command-line tests share: running the binary, its stderr, the
//! files a run left.
#![allow(dead_code)] // each test binary uses some of these

use std::path::Path;
use std::process::{Command, Output};

/// Runs `penumbra ARGS` in `dir`.
pub fn penumbra(args: &[&str], dir: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_penumbra"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("run penumbra")
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
