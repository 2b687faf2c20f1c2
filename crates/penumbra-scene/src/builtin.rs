//! Scenes compiled into the binary, so `penumbra` renders something with no
//! arguments.

use crate::load::{LoadOptions, load_toml_str};
use crate::scene::Scene;
use std::path::Path;

/// Text of `scenes/cornell-box.toml`, embedded at build time.
pub const CORNELL_BOX_TOML: &str = include_str!("../../../scenes/cornell-box.toml");

/// Virtual path naming the embedded Cornell box in messages.
pub const CORNELL_BOX_PATH: &str = "<builtin>/cornell-box.toml";

/// The Cornell box of the reference scene (`/work/shared/reference/cornell`):
/// same camera, albedos and emitter (radiance (18.387, 13.9873, 6.75357),
/// front side only, facing −y), walls and light as the reference quads, the
/// two blocks as rotated boxes; millimetres; 512×512, path tracing,
/// max_depth 8, 64 spp. Self-contained: it references no files.
pub fn cornell_box() -> Scene {
    match load_toml_str(
        CORNELL_BOX_TOML,
        Path::new(CORNELL_BOX_PATH),
        &LoadOptions::default(),
    ) {
        Ok(scene) => scene,
        // The text is fixed at build time and covered by tests.
        Err(e) => panic!("the built-in Cornell box does not load: {e}"),
    }
}
