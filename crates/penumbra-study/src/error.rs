//! What can stop a study. A technique that cannot run on a scene or a
//! machine does not stop it: it becomes a skipped row with its reason.

use std::path::{Path, PathBuf};

#[derive(Debug, thiserror::Error)]
pub enum StudyError {
    /// Bad input: options that contradict each other or the scene.
    #[error("{0}")]
    Input(String),
    /// A file or directory that could not be read or written.
    #[error("{}: {message}", path.display())]
    File { path: PathBuf, message: String },
    #[error(transparent)]
    Image(#[from] penumbra_image::ImageError),
    #[error(transparent)]
    Report(#[from] crate::report::ReportError),
    /// More triangles than the ray tracer's BVH holds.
    #[error(transparent)]
    SceneTooLarge(#[from] penumbra_trace::SceneTooLarge),
}

impl StudyError {
    pub fn file(path: &Path, e: impl std::fmt::Display) -> Self {
        StudyError::File {
            path: path.to_path_buf(),
            message: e.to_string(),
        }
    }
}
