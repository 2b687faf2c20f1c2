//! The report directory is written whole or not at all: a study writes
//! into a hidden staging folder beside `DIR` and renames it into place at
//! the end, so a failed or interrupted study leaves no partial report.

use crate::error::StudyError;
use std::path::{Path, PathBuf};

/// The file that marks a directory as a study report.
pub const MARKER: &str = "study.json";

/// Checks that `dir` can receive a report: its parent exists, and `dir`
/// is absent, empty or an earlier report (which is then replaced).
pub fn check(dir: &Path) -> Result<(), StudyError> {
    let parent = parent_of(dir);
    if !parent.is_dir() {
        return Err(StudyError::file(
            dir,
            format!("the folder {} does not exist", parent.display()),
        ));
    }
    if !dir.exists() {
        return Ok(());
    }
    if !dir.is_dir() {
        return Err(StudyError::file(
            dir,
            "exists and is not a directory; give -o a new or report directory",
        ));
    }
    let empty = std::fs::read_dir(dir)
        .map_err(|e| StudyError::file(dir, e))?
        .next()
        .is_none();
    if !empty && !dir.join(MARKER).is_file() {
        return Err(StudyError::file(
            dir,
            "exists and is neither empty nor a study report (no study.json); choose another -o",
        ));
    }
    Ok(())
}

/// A staging folder beside `dir`, removed on drop unless [`Staging::finish`]
/// moved it into place.
#[derive(Debug)]
pub struct Staging {
    dir: tempfile::TempDir,
}

impl Staging {
    pub fn new(dir: &Path) -> Result<Self, StudyError> {
        let name = dir
            .file_name()
            .ok_or_else(|| StudyError::file(dir, "is not a directory name"))?;
        let staging = tempfile::Builder::new()
            .prefix(&format!(".{}.partial-", name.to_string_lossy()))
            .tempdir_in(parent_of(dir))
            .map_err(|e| StudyError::file(dir, format!("cannot create a staging folder: {e}")))?;
        Ok(Self { dir: staging })
    }

    pub fn path(&self) -> &Path {
        self.dir.path()
    }

    /// Moves the finished report to `dir`, replacing an earlier one.
    pub fn finish(self, dir: &Path) -> Result<(), StudyError> {
        let staging = self.dir.keep();
        let io = |p: &Path, e: std::io::Error| StudyError::file(p, e);
        let result = (|| {
            if dir.exists() {
                let old = sibling(dir, "old");
                std::fs::rename(dir, &old).map_err(|e| io(dir, e))?;
                std::fs::rename(&staging, dir).map_err(|e| io(dir, e))?;
                std::fs::remove_dir_all(&old).map_err(|e| io(&old, e))
            } else {
                std::fs::rename(&staging, dir).map_err(|e| io(dir, e))
            }
        })();
        if result.is_err() && staging.exists() {
            let _ = std::fs::remove_dir_all(&staging);
        }
        result
    }
}

fn parent_of(dir: &Path) -> &Path {
    match dir.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    }
}

fn sibling(dir: &Path, tag: &str) -> PathBuf {
    let name = dir.file_name().unwrap_or_default().to_string_lossy();
    dir.with_file_name(format!(".{name}.{tag}-{}", std::process::id()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn refuses_files_and_foreign_directories() {
        let tmp = tempfile::tempdir().unwrap();
        let file = tmp.path().join("report");
        std::fs::write(&file, "x").unwrap();
        let e = check(&file).unwrap_err().to_string();
        assert!(e.contains("not a directory") && e.contains("report"), "{e}");
        let foreign = tmp.path().join("photos");
        std::fs::create_dir(&foreign).unwrap();
        std::fs::write(foreign.join("a.jpg"), "x").unwrap();
        assert!(
            check(&foreign)
                .unwrap_err()
                .to_string()
                .contains("no study.json")
        );
        assert!(check(&tmp.path().join("missing/deeper")).is_err());
        assert!(check(&tmp.path().join("new")).is_ok());
    }

    #[test]
    fn staging_is_removed_unless_finished_and_replaces_a_report() {
        let tmp = tempfile::tempdir().unwrap();
        let dir = tmp.path().join("study");
        {
            let s = Staging::new(&dir).unwrap();
            std::fs::write(s.path().join(MARKER), "{}").unwrap();
        }
        assert_eq!(std::fs::read_dir(tmp.path()).unwrap().count(), 0);
        for content in ["first", "second"] {
            check(&dir).unwrap();
            let s = Staging::new(&dir).unwrap();
            std::fs::write(s.path().join(MARKER), content).unwrap();
            s.finish(&dir).unwrap();
        }
        assert_eq!(std::fs::read_to_string(dir.join(MARKER)).unwrap(), "second");
        // Nothing but the report is left beside it.
        assert_eq!(std::fs::read_dir(tmp.path()).unwrap().count(), 1);
    }
}
