//! penumbra-bake: quantities precomputed by ray tracing for static scenes
//! and looked up in real time (notes 004), stored in one light-map atlas:
//!
//! * [`bake_ao`]: the ambient-occlusion term kA(p) per texel, with the
//!   definition of the `ao` integrator;
//! * [`bake_lightmap`]: irradiance E(p) [W/m²] by path tracing, direct and
//!   indirect, per light or in total (`B = c_diff · E`, maps add up);
//! * [`radiosity::bake_radiosity`]: E by classic radiosity (patches, form
//!   factors by ray casting, progressive refinement).
//!
//! A bake is data: [`write_bake`] writes a directory (manifest, layouts,
//! float EXR pages) that the raster engine reads with [`read_bake`]
//! without calling the baker.

pub mod ao;
pub mod atlas;
pub mod bake_dir;
pub mod baked;
mod baker;
pub mod convergence;
pub mod dilate;
pub mod error;
pub mod gltf_export;
pub mod irradiance;
pub mod lookup;
pub mod manifest;
pub mod plot;
pub mod radiosity;
pub mod scene_hash;
pub mod texels;
pub mod validity;

pub use ao::{AoSettings, bake_ao};
pub use atlas::{Atlas, AtlasSettings, Density, InstanceRect, MeshLayout, UvSource};
pub use bake_dir::{LoadedBake, read_bake, write_bake};
pub use baked::{Bake, BakeKind, BakeStats, BakedMap};
pub use baker::BakeProgress;
pub use convergence::ConvergenceStep;
pub use error::BakeError;
pub use irradiance::{LightmapSettings, bake_lightmap};
pub use manifest::Manifest;
pub use scene_hash::geometry_hash;
pub use texels::{Texel, Texels};
