//! What can go wrong in a bake or when reading one back.

use std::path::PathBuf;

/// A bake error: names the file (where there is one) and what is wrong.
#[derive(Debug, thiserror::Error)]
pub enum BakeError {
    /// A setting out of range (sample counts, densities, tolerances).
    #[error("{0}")]
    Settings(String),
    /// The light-map atlas could not be made (chart generation or packing),
    /// or would not fit in memory.
    #[error("light-map atlas: {0}")]
    Atlas(String),
    /// A bake directory or one of its files is unreadable, malformed or
    /// made for another scene.
    #[error("{}: {message}", path.display())]
    File { path: PathBuf, message: String },
    #[error(transparent)]
    Image(#[from] penumbra_image::ImageError),
    /// More triangles than the ray tracer's BVH holds.
    #[error(transparent)]
    SceneTooLarge(#[from] penumbra_trace::SceneTooLarge),
}

impl BakeError {
    pub(crate) fn file(path: impl Into<PathBuf>, message: impl Into<String>) -> Self {
        Self::File {
            path: path.into(),
            message: message.into(),
        }
    }
}
