//! Classic radiosity (being written): patches, form factors by ray casting,
//! progressive refinement.

use crate::baked::Bake;
use crate::baker::BakeProgress;
use crate::error::BakeError;
use penumbra_scene::Scene;

/// Settings of a radiosity bake.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RadiositySettings {
    /// About how many patches to solve for.
    pub patches: u32,
    /// Stop when the unshot power is below this fraction of the emitted power.
    pub tolerance: f32,
    /// Form-factor rays per patch of the scene, over the whole solve.
    pub rays_per_patch: u32,
    pub seed: u32,
}

/// Not built yet in this commit: refuses with an error.
pub fn bake_radiosity(
    _scene: &Scene,
    _settings: &RadiositySettings,
    _progress: Option<BakeProgress<'_>>,
) -> Result<Bake, BakeError> {
    Err(BakeError::Settings("radiosity is not built yet".into()))
}
