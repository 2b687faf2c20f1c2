//! Scene builders shared by the tracer's tests.
#![allow(dead_code)]

use glam::{Mat4, Vec3};
use penumbra_scene::{
    Camera, IntegratorKind, Material, Mesh, Projection, RenderSettings, Scene, SceneAreaLight,
};
use penumbra_shading::Rgb;
use penumbra_shading::light::{AreaLight, Shape};

/// `primitives::quad` (front normal e1 × e2) with a material.
pub fn quad(c: Vec3, e1: Vec3, e2: Vec3, material: usize) -> Mesh {
    Mesh {
        material,
        ..penumbra_scene::primitives::quad(c, e1, e2)
    }
}

/// Adds a mesh with an identity transform.
pub fn add(scene: &mut Scene, mesh: Mesh) {
    scene.add_mesh(mesh, Mat4::IDENTITY);
}

/// Orthographic camera looking straight down −y at `target`, view height `h`.
pub fn top_down_camera(target: Vec3, h: f32) -> Camera {
    Camera::look_at(
        target + Vec3::Y * 10.0,
        target,
        Vec3::Z,
        Projection::Orthographic { height: h },
    )
}

pub fn lambert(scene: &mut Scene, albedo: f32) -> usize {
    scene.add_material(Material::lambert("m", Rgb::splat(albedo)))
}

/// Render settings for a test: `w`×`h`, `spp`, `max_depth`, fixed seed 3.
pub fn settings(
    integrator: IntegratorKind,
    w: u32,
    h: u32,
    spp: u32,
    max_depth: u32,
) -> RenderSettings {
    RenderSettings {
        width: w,
        height: h,
        spp,
        max_depth,
        integrator,
        seed: 3,
        ao_distance: f32::INFINITY,
    }
}

/// A one-sided analytic area light of grey radiance `le`.
pub fn area_light(name: &str, shape: Shape, le: f32) -> SceneAreaLight {
    SceneAreaLight {
        name: name.into(),
        light: AreaLight {
            shape,
            radiance: Rgb::splat(le),
            two_sided: false,
        },
    }
}
