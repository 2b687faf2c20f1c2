//! penumbra's real-time pipeline on the GPU (wgpu): a headless forward
//! renderer that shades every pixel with the sum over the scene's abstract
//! lights (point, directional, spot) of f · E⊥ · cos θ, with WGSL twins of
//! the Rust BRDFs (Lambert, Phong–Blinn) and lights: without shadows the
//! model of the CPU `local` integrator, with shadow maps
//! ([`ShadowMode::Map`]) an approximation of the CPU `direct` integrator's
//! hard shadows.
//!
//! [`GpuContext::new`] picks a hardware adapter if there is one, else any
//! adapter such as Mesa's lavapipe (software Vulkan); [`ForwardRenderer`]
//! draws a scene into an `Rgba32Float` target and reads it back as a
//! [`penumbra_image::Image`].

pub mod camera;
pub mod context;
pub mod gpu;
pub mod material_tables;
pub mod renderer;
pub mod scene_data;
pub mod shaders;
pub mod shadow_map;
pub mod timing;

pub use wgpu;

pub use camera::{gpu_camera, view_projection};
pub use context::{AdapterSummary, GpuContext, GpuError, SOFTWARE_VULKAN_PACKAGES};
pub use renderer::{
    ForwardRenderer, MAX_PCF, RasterOptions, RasterOutput, ShadowMode, map_read, render_scene,
};
pub use scene_data::SceneData;
pub use shadow_map::{
    DEFAULT_NORMAL_OFFSET, DEFAULT_SHADOW_MAP_SIZE, DEFAULT_SLOPE_BIAS, shadow_views,
};
pub use timing::{GpuTimer, PassTiming, total_ms};
