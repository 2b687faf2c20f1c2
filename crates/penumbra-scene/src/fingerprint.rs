//! Fingerprints of scene content: FNV-1a (64-bit; Fowler, Noll and Vo) over
//! a canonical byte stream, so that a file written for one scene (a bake, a
//! partial render) is never used with another.

use std::fmt;

use crate::Scene;

const OFFSET: u64 = 0xcbf2_9ce4_8422_2325;
const PRIME: u64 = 0x0000_0100_0000_01b3;

/// The FNV-1a 64-bit hash: for each byte `b`, `h = (h ⊕ b) · 1099511628211`,
/// starting from 14695981039346656037. Also a [`fmt::Write`], so that a
/// value's `Debug` text can be hashed without being held in memory.
#[derive(Clone, Copy, Debug)]
pub struct Fnv1a(u64);

impl Default for Fnv1a {
    fn default() -> Self {
        Self(OFFSET)
    }
}

impl Fnv1a {
    /// Hashes `b`.
    pub fn bytes(&mut self, b: &[u8]) {
        for &x in b {
            self.0 = (self.0 ^ u64::from(x)).wrapping_mul(PRIME);
        }
    }

    /// Hashes `v` as 4 little-endian bytes.
    pub fn u32(&mut self, v: u32) {
        self.bytes(&v.to_le_bytes());
    }

    /// Hashes the bits of each value.
    pub fn f32s(&mut self, v: impl IntoIterator<Item = f32>) {
        for x in v {
            self.u32(x.to_bits());
        }
    }

    /// The hash so far, as written in files: `fnv1a64:` and 16 hex digits.
    pub fn finish(&self) -> String {
        format!("fnv1a64:{:016x}", self.0)
    }

    /// The hash so far.
    pub fn value(&self) -> u64 {
        self.0
    }
}

impl fmt::Write for Fnv1a {
    fn write_str(&mut self, s: &str) -> fmt::Result {
        self.bytes(s.as_bytes());
        Ok(())
    }
}

/// A fingerprint of everything in `scene` that can change a rendered pixel:
/// meshes, instances, materials, textures, lights, area lights, camera,
/// background and the environment map's texels and rotation. Render
/// settings and load warnings are left out (a partial render records its
/// settings beside this). The bulk arrays (vertex attributes, indices,
/// texels) are hashed as their bits, each with its length; everything
/// else as its `Debug` text, which prints every float exactly (shortest
/// round-trip form) and in a fixed order. Equal scenes hash equally on
/// every machine.
pub fn fingerprint(scene: &Scene) -> String {
    use fmt::Write;
    let mut h = Fnv1a::default();
    for mesh in &scene.meshes {
        hash_mesh(&mut h, mesh);
    }
    for texture in &scene.textures {
        let crate::Texture {
            name,
            width,
            height,
            texels,
            wrap,
            uv_transform,
            uv_set,
        } = texture;
        // Writing into the hasher cannot fail.
        let _ = write!(
            h,
            "{name:?}{width}x{height}{wrap:?}{uv_transform:?}{uv_set}"
        );
        h.u32(texels.len() as u32);
        h.f32s(texels.iter().flat_map(|t| t.to_array()));
    }
    let _ = write!(
        h,
        "{:?}{:?}{:?}{:?}{:?}{:?}",
        scene.instances,
        scene.materials,
        scene.lights,
        scene.area_lights,
        scene.camera,
        scene.background
    );
    match &scene.environment_map {
        Some(map) => {
            h.u32(1);
            h.u32(map.width() as u32);
            h.u32(map.height() as u32);
            h.f32s(map.rotation().to_array());
            h.f32s(map.texels().iter().flat_map(|t| t.to_array()));
        }
        None => h.u32(0),
    }
    h.finish()
}

/// Hashes every field of `mesh` (a new field fails to compile here until
/// it is hashed).
fn hash_mesh(h: &mut Fnv1a, mesh: &crate::Mesh) {
    use fmt::Write;
    let crate::Mesh {
        name,
        positions,
        normals,
        uv0,
        uv1,
        colors,
        tangents,
        indices,
        material,
    } = mesh;
    let _ = write!(h, "mesh {name:?} material {material}");
    attribute(h, Some(positions), glam::Vec3::to_array);
    attribute(h, normals.as_ref(), glam::Vec3::to_array);
    attribute(h, uv0.as_ref(), glam::Vec2::to_array);
    attribute(h, uv1.as_ref(), glam::Vec2::to_array);
    attribute(h, colors.as_ref(), glam::Vec3::to_array);
    attribute(h, tangents.as_ref(), glam::Vec4::to_array);
    h.u32(indices.len() as u32);
    for t in indices {
        t.iter().for_each(|&i| h.u32(i));
    }
}

/// Hashes an optional vertex attribute: a presence flag, then its length
/// and the bits of its values.
fn attribute<T, const N: usize>(
    h: &mut Fnv1a,
    values: Option<&Vec<T>>,
    floats: fn(&T) -> [f32; N],
) {
    match values {
        Some(v) => {
            h.u32(1);
            h.u32(v.len() as u32);
            h.f32s(v.iter().flat_map(floats));
        }
        None => h.u32(0),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Material, primitives};
    use glam::{Mat4, Vec3};

    #[test]
    fn fnv1a_matches_the_published_test_vectors() {
        // FNV-1a 64 of "" and "a" (Fowler, Noll, Vo).
        assert_eq!(Fnv1a::default().value(), 0xcbf2_9ce4_8422_2325);
        let mut h = Fnv1a::default();
        h.bytes(b"a");
        assert_eq!(h.value(), 0xaf63_dc4c_8601_ec8c);
    }

    #[test]
    fn fingerprint_changes_with_anything_that_changes_pixels() {
        let mut scene = Scene::default();
        scene.add_mesh(primitives::sphere(Vec3::ZERO, 1.0, 4), Mat4::IDENTITY);
        let a = fingerprint(&scene);
        assert_eq!(a, fingerprint(&scene.clone()));
        let mut settings_only = scene.clone();
        settings_only.settings.spp += 1;
        settings_only.warnings.push("x".into());
        assert_eq!(a, fingerprint(&settings_only));
        let mut material = scene.clone();
        material.add_material(Material::lambert("x", Vec3::ONE));
        assert_ne!(a, fingerprint(&material));
        let mut moved = scene.clone();
        moved.instances[0].transform = Mat4::from_translation(Vec3::X * 1e-6);
        assert_ne!(a, fingerprint(&moved));
        let mut background = scene.clone();
        background.background = Vec3::splat(1e-7);
        assert_ne!(a, fingerprint(&background));
        let mut vertex = scene.clone();
        vertex.meshes[0].positions[3].y += 1e-6;
        assert_ne!(a, fingerprint(&vertex));
        let mut uv = scene.clone();
        uv.meshes[0].uv1 = uv.meshes[0].uv0.clone();
        assert_ne!(a, fingerprint(&uv));
        let mut texel = scene.clone();
        texel.textures.push(crate::Texture {
            name: "t".into(),
            width: 1,
            height: 1,
            texels: vec![Vec3::ONE].into(),
            wrap: Default::default(),
            uv_transform: glam::Affine2::IDENTITY,
            uv_set: 0,
        });
        let b = fingerprint(&texel);
        assert_ne!(a, b);
        let mut other_set = texel.clone();
        other_set.textures[0].uv_set = 1;
        assert_ne!(b, fingerprint(&other_set));
        texel.textures[0].texels = vec![Vec3::new(0.5, 1.0, 1.0)].into();
        assert_ne!(b, fingerprint(&texel));
    }
}
