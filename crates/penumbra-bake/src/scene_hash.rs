//! A fingerprint of a scene's geometry, stored in every bake so that a bake
//! is never shown on another scene: FNV-1a (64-bit) over the bits of every
//! mesh's positions, triangles and light-map UVs, and every instance's mesh
//! and transform. Materials and lights are left out: they change the values
//! of a light map, not where its texels lie.

use penumbra_scene::{Fnv1a, Scene};

/// The geometry hash of `scene`, as written in manifests (`fnv1a64:` and
/// 16 hex digits).
pub fn geometry_hash(scene: &Scene) -> String {
    let mut h = Fnv1a::default();
    h.u32(scene.meshes.len() as u32);
    for m in &scene.meshes {
        h.u32(m.positions.len() as u32);
        h.f32s(m.positions.iter().flat_map(|p| p.to_array()));
        h.u32(m.indices.len() as u32);
        for t in &m.indices {
            t.iter().for_each(|&i| h.u32(i));
        }
        match &m.uv1 {
            Some(uv) => {
                h.u32(1);
                h.f32s(uv.iter().flat_map(|p| p.to_array()));
            }
            None => h.u32(0),
        }
    }
    h.u32(scene.instances.len() as u32);
    for inst in &scene.instances {
        h.u32(inst.mesh as u32);
        h.f32s(inst.transform.to_cols_array());
    }
    h.finish()
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::{Mat4, Vec3};
    use penumbra_scene::primitives;

    #[test]
    fn changes_with_geometry_not_with_materials() {
        let mut scene = Scene::default();
        scene.add_mesh(primitives::sphere(Vec3::ZERO, 1.0, 4), Mat4::IDENTITY);
        let a = geometry_hash(&scene);
        scene.add_material(penumbra_scene::Material::lambert("x", Vec3::ONE));
        assert_eq!(a, geometry_hash(&scene));
        scene.instances[0].transform = Mat4::from_translation(Vec3::X * 1e-3);
        assert_ne!(a, geometry_hash(&scene));
    }
}
