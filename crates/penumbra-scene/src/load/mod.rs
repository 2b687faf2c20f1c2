//! Scene loaders, chosen by file extension.

mod gltf;
mod obj;
mod toml;

pub use self::gltf::load_gltf;
pub use self::obj::load_obj;
pub use self::toml::{load_toml, load_toml_str};

use crate::error::SceneError;
use crate::scene::Scene;
use std::path::{Path, PathBuf};

/// Options shared by all loaders.
#[derive(Clone, Debug, Default)]
pub struct LoadOptions {
    /// Absolute paths the user named explicitly (e.g. on the command line);
    /// only these may be referenced by absolute URIs inside scene files.
    pub allowed_absolute_paths: Vec<PathBuf>,
}

/// Loads a `.gltf`, `.glb`, `.obj` or `.toml` scene.
pub fn load_scene(path: &Path, options: &LoadOptions) -> Result<Scene, SceneError> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    match ext.as_deref() {
        Some("gltf") | Some("glb") => load_gltf(path, options),
        Some("obj") => load_obj(path, options),
        Some("toml") => load_toml(path, options),
        _ => Err(SceneError::UnknownFormat {
            file: path.to_path_buf(),
        }),
    }
}

/// Reads a whole file, mapping the I/O error to a [`SceneError`] naming it.
pub(crate) fn read_file(path: &Path) -> Result<Vec<u8>, SceneError> {
    std::fs::read(path).map_err(|cause| SceneError::Io {
        file: path.to_path_buf(),
        cause,
    })
}
