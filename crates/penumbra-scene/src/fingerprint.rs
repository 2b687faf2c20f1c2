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
/// settings beside this). The `Debug` text of each part is hashed, which
/// prints every float exactly (shortest round-trip form) and in a fixed
/// order, so equal scenes hash equally on every machine.
pub fn fingerprint(scene: &Scene) -> String {
    use fmt::Write;
    let mut h = Fnv1a::default();
    // Writing into the hasher cannot fail.
    let _ = write!(
        h,
        "{:?}{:?}{:?}{:?}{:?}{:?}{:?}{:?}",
        scene.meshes,
        scene.instances,
        scene.materials,
        scene.textures,
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
    }
}
