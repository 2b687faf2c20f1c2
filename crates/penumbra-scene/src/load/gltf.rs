//! glTF 2.0 loader (to be written).
use super::LoadOptions;
use crate::{Scene, SceneError};
use std::path::Path;

/// Loads a `.gltf` (+ external buffers) or `.glb` file.
pub fn load_gltf(path: &Path, _options: &LoadOptions) -> Result<Scene, SceneError> {
    Err(SceneError::in_file(
        path,
        "glTF loading is not implemented yet",
    ))
}
