//! Native TOML scene loader (to be written).
use super::LoadOptions;
use crate::{Scene, SceneError};
use std::path::Path;

/// Loads a `.toml` scene file.
pub fn load_toml(path: &Path, options: &LoadOptions) -> Result<Scene, SceneError> {
    let bytes = super::read_file(path)?;
    let text =
        String::from_utf8(bytes).map_err(|_| SceneError::in_file(path, "not valid UTF-8"))?;
    load_toml_str(&text, path, options)
}

/// Parses TOML scene text; `path` names it in errors and anchors relative paths.
pub fn load_toml_str(
    _text: &str,
    path: &Path,
    _options: &LoadOptions,
) -> Result<Scene, SceneError> {
    Err(SceneError::in_file(
        path,
        "TOML loading is not implemented yet",
    ))
}
