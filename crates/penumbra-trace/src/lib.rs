//! penumbra-trace: CPU ray tracing — BVH, light sampling, integrators
//! (`local`, `direct`, `path`, `ao`) and the tiled, reproducible render loop.

pub mod accel;
pub mod bench;
pub mod geometry;
pub mod integrator;
pub mod lights;
pub mod ray;
pub mod render;

pub use render::{Progress, RenderOptions, RenderOutput, render, scene_camera};
