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

pub mod context;
pub mod gpu;
pub mod renderer;
pub mod shaders;

pub use wgpu;

pub use context::{AdapterSummary, GpuContext, GpuError, SOFTWARE_VULKAN_PACKAGES};
pub use renderer::{
    DEFAULT_NORMAL_OFFSET, DEFAULT_SHADOW_MAP_SIZE, DEFAULT_SLOPE_BIAS, ForwardRenderer, MAX_PCF,
    RasterOptions, RasterOutput, SceneData, ShadowMode, gpu_camera, map_read, render_scene,
    shadow_views, view_projection,
};
