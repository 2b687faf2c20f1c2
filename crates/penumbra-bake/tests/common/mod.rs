//! Scenes and helpers shared by the bake tests.
#![allow(dead_code)]

use glam::{Mat4, Vec3};
use penumbra_bake::{Bake, Texel};
use penumbra_scene::{Material, Mesh, Scene, primitives};
use penumbra_trace::accel::BuildQuality;
use penumbra_trace::geometry::SceneGeometry;

/// Adds `mesh` with a new Lambertian material of albedo `albedo`.
pub fn add(scene: &mut Scene, mut mesh: Mesh, material: Material) -> usize {
    mesh.material = scene.add_material(material);
    scene.add_mesh(mesh, Mat4::IDENTITY)
}

/// `mesh` with every triangle's winding reversed (front faces flipped).
pub fn flipped(mut mesh: Mesh) -> Mesh {
    for t in &mut mesh.indices {
        t.swap(1, 2);
    }
    mesh
}

/// A quad floor y = 0 over x ∈ [x0, x1], z ∈ [z0, z1], facing +y.
pub fn floor(x0: f32, x1: f32, z0: f32, z1: f32) -> Mesh {
    // edge1 × edge2 = (0,0,dz) × (dx,0,0) = +y·dz·dx.
    primitives::quad(
        Vec3::new(x0, 0.0, z0),
        Vec3::new(0.0, 0.0, z1 - z0),
        Vec3::new(x1 - x0, 0.0, 0.0),
    )
}

/// The wall x = 0 over z ∈ [z0, z1], y ∈ [0, h], facing +x.
pub fn wall_x(z0: f32, z1: f32, h: f32) -> Mesh {
    // (0,h,0) × (0,0,dz) = +x·h·dz.
    primitives::quad(
        Vec3::new(0.0, 0.0, z0),
        Vec3::new(0.0, h, 0.0),
        Vec3::new(0.0, 0.0, z1 - z0),
    )
}

/// The wall z = 0 over x ∈ [x0, x1], y ∈ [0, h], facing +z.
pub fn wall_z(x0: f32, x1: f32, h: f32) -> Mesh {
    // (dx,0,0) × (0,h,0) = +z·dx·h.
    primitives::quad(
        Vec3::new(x0, 0.0, 0.0),
        Vec3::new(x1 - x0, 0.0, 0.0),
        Vec3::new(0.0, h, 0.0),
    )
}

/// Every baked texel with its world point and front normal.
pub fn baked_points(scene: &Scene, bake: &Bake) -> Vec<(Texel, Vec3, Vec3)> {
    let geometry = SceneGeometry::build(scene, BuildQuality::default()).unwrap();
    bake.texels
        .texels
        .iter()
        .filter(|t| bake.coverage[t.page as usize].get(t.x, t.y).x == 1.0)
        .map(|t| {
            let h = geometry.surface_point(scene, t.triangle, t.b1, t.b2);
            (*t, h.p, h.ng)
        })
        .collect()
}

/// The value of map `m` (0 = total) at a texel.
pub fn value(bake: &Bake, m: usize, t: &Texel) -> Vec3 {
    bake.maps[m].pages[t.page as usize].get(t.x, t.y)
}

/// The variance of the estimate of map `m` at a texel.
pub fn variance(bake: &Bake, m: usize, t: &Texel) -> Vec3 {
    bake.maps[m].variance[t.page as usize].get(t.x, t.y)
}
