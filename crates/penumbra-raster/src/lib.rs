//! penumbra's real-time pipeline on the GPU (wgpu): a headless renderer
//! that shades every pixel with the sum over the scene's abstract lights
//! (point, directional, spot, and area lights' far fields) of f · E⊥ ·
//! cos θ, with WGSL twins of every Rust BSDF's `eval` and of the lights:
//! without shadows the model of the CPU `local`
//! integrator; with shadow maps, planar projected shadows or stencil shadow
//! volumes ([`ShadowMode`]) the hard shadows of the CPU `direct` integrator.
//! A depth prepass feeds tiled light culling, so scenes with thousands of
//! lights of finite range shade each pixel with the few that reach it.
//!
//! [`GpuContext::new`] picks a hardware adapter if there is one, else any
//! adapter such as Mesa's lavapipe (software Vulkan); [`ForwardRenderer`]
//! draws a scene into an `Rgba32Float` target and reads it back as a
//! [`penumbra_image::Image`].

pub mod camera;
pub mod context;
pub mod gpu;
pub mod light_culling;
pub mod material_tables;
pub mod passes;
mod planar_shadow;
pub mod readback;
pub mod receivers;
pub mod renderer;
pub mod scene_data;
mod scene_gpu;
pub mod shaders;
pub mod shadow_map;
mod shadow_volume;
pub mod textures;
pub mod timing;
pub mod topology;

pub use wgpu;

pub use camera::{gpu_camera, view_projection};
pub use context::{AdapterSummary, GpuContext, GpuError, SOFTWARE_VULKAN_PACKAGES};
pub use light_culling::CullingStats;
pub use passes::lightmap::BakedMaps;
pub use renderer::{
    ForwardRenderer, MAX_ENVIRONMENT_TAPS, MAX_PCF, RasterOptions, RasterOutput, ShadowMode,
    map_read, render_scene,
};
pub use scene_data::SceneData;
pub use shadow_map::{
    DEFAULT_NORMAL_OFFSET, DEFAULT_SHADOW_MAP_SIZE, DEFAULT_SLOPE_BIAS, shadow_views,
};
pub use timing::{GpuTimer, PassTiming, total_ms};
