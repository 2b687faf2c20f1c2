//! OBJ + MTL loader (to be written).
use super::LoadOptions;
use crate::{Scene, SceneError};
use std::path::Path;

/// Loads an `.obj` file with its `.mtl` libraries.
pub fn load_obj(path: &Path, _options: &LoadOptions) -> Result<Scene, SceneError> {
    Err(SceneError::in_file(
        path,
        "OBJ loading is not implemented yet",
    ))
}
