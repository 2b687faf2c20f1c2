//! penumbra-trace: CPU ray tracing — BVH, light sampling, integrators
//! (`local`, `direct`, `path`, `ao`, `whitted`), the tiled, reproducible
//! render loop, and surface queries that start on a surface instead of at
//! the camera (ambient occlusion and irradiance at a point: the bakes).

pub mod accel;
pub mod bench;
pub mod geometry;
pub mod integrator;
pub mod lights;
pub mod ray;
pub mod render;
pub mod stages;
pub mod stats;
pub mod texture_lod;

pub use geometry::SceneTooLarge;
pub use render::{
    Crop, MIN_SPP_FOR_TARGET, Progress, RenderOptions, RenderOutput, Resume, Stop, render,
    scene_camera, scene_camera_for,
};
