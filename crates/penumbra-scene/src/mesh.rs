//! Triangle meshes and their instances.

use crate::material::MaterialId;
use glam::{Mat3, Mat4, Vec2, Vec3};
use penumbra_shading::Rgb;

/// Index of a mesh in [`crate::Scene::meshes`].
pub type MeshId = usize;

/// An indexed triangle mesh in object space. Invariants (checked by loaders
/// through [`Mesh::validate`]): every attribute has one entry per vertex, every
/// index is in range, positions are finite, and no triangle is degenerate.
#[derive(Clone, Debug, Default)]
pub struct Mesh {
    pub name: String,
    pub positions: Vec<Vec3>,
    /// Per-vertex shading normals; `None` = flat shading with face normals.
    pub normals: Option<Vec<Vec3>>,
    /// First UV set (glTF TEXCOORD_0).
    pub uv0: Option<Vec<Vec2>>,
    /// Second UV set (glTF TEXCOORD_1; light and AO maps use it).
    pub uv1: Option<Vec<Vec2>>,
    /// Per-vertex colours (glTF COLOR_0, linear RGB, alpha dropped):
    /// they multiply the material's base colour.
    pub colors: Option<Vec<Rgb>>,
    /// Per-vertex tangents of the normal map's UV set (glTF TANGENT, or
    /// MikkTSpace): xyz along +u, w = ±1 the handedness (bitangent =
    /// w · normal × tangent).
    pub tangents: Option<Vec<glam::Vec4>>,
    /// Counter-clockwise triangles: front = geometric normal (v1−v0)×(v2−v0).
    pub indices: Vec<[u32; 3]>,
    pub material: MaterialId,
}

/// What [`Mesh::remove_degenerate`] dropped.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct CleanupReport {
    pub degenerate_triangles: usize,
}

impl Mesh {
    /// UV set `set` (0: [`Mesh::uv0`], 1: [`Mesh::uv1`]), if the mesh has it.
    pub fn uv_set(&self, set: usize) -> Option<&[Vec2]> {
        match set {
            0 => self.uv0.as_deref(),
            1 => self.uv1.as_deref(),
            _ => None,
        }
    }

    /// Checks the invariants; returns a description of the first violation.
    pub fn validate(&self) -> Result<(), String> {
        let n = self.positions.len();
        if let Some((i, p)) = self
            .positions
            .iter()
            .enumerate()
            .find(|(_, p)| !p.is_finite())
        {
            return Err(format!("vertex {i} has a non-finite position {p}"));
        }
        for (name, len) in [
            ("normals", self.normals.as_ref().map(Vec::len)),
            ("uv0", self.uv0.as_ref().map(Vec::len)),
            ("uv1", self.uv1.as_ref().map(Vec::len)),
            ("colors", self.colors.as_ref().map(Vec::len)),
            ("tangents", self.tangents.as_ref().map(Vec::len)),
        ] {
            if let Some(len) = len
                && len != n
            {
                return Err(format!(
                    "{name} has {len} entries but there are {n} vertices"
                ));
            }
        }
        if let Some(normals) = &self.normals
            && let Some((i, _)) = normals.iter().enumerate().find(|(_, v)| !v.is_finite())
        {
            return Err(format!("vertex {i} has a non-finite normal"));
        }
        for (t, tri) in self.indices.iter().enumerate() {
            for &i in tri {
                if i as usize >= n {
                    return Err(format!(
                        "triangle {t} uses vertex {i}, but there are only {n} vertices"
                    ));
                }
            }
        }
        Ok(())
    }

    /// Removes triangles of zero area (repeated or collinear vertices).
    /// Call after [`Mesh::validate`] succeeded.
    pub fn remove_degenerate(&mut self) -> CleanupReport {
        let before = self.indices.len();
        let p = &self.positions;
        self.indices.retain(|t| {
            let (a, b, c) = (p[t[0] as usize], p[t[1] as usize], p[t[2] as usize]);
            let area2 = (b - a).cross(c - a).length_squared();
            area2 > 0.0 && area2.is_finite()
        });
        CleanupReport {
            degenerate_triangles: before - self.indices.len(),
        }
    }

    /// Object-space bounds (min, max).
    pub fn bounds(&self) -> (Vec3, Vec3) {
        self.positions.iter().fold(
            (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
            |(lo, hi), &p| (lo.min(p), hi.max(p)),
        )
    }
}

/// A mesh placed in the world by an object-to-world transform.
#[derive(Clone, Debug)]
pub struct Instance {
    pub mesh: MeshId,
    pub transform: Mat4,
    /// Optional per-instance material override.
    pub material: Option<MaterialId>,
    /// Marked as a receiver of the raster engine's planar projected shadows
    /// (TOML `planar_receiver = true`); without any mark, the largest
    /// planar instance receives them.
    pub planar_receiver: bool,
}

impl Instance {
    pub fn new(mesh: MeshId, transform: Mat4) -> Self {
        Self {
            mesh,
            transform,
            material: None,
            planar_receiver: false,
        }
    }

    /// Matrix that maps object-space normals to world space: the inverse
    /// transpose of the linear part (SEEDS.md, Planes and normals).
    pub fn normal_matrix(&self) -> Mat3 {
        Mat3::from_mat4(self.transform).inverse().transpose()
    }

    /// True if the transform mirrors (negative determinant): winding flips.
    pub fn flips_winding(&self) -> bool {
        Mat3::from_mat4(self.transform).determinant() < 0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn normals_transform_by_inverse_transpose() {
        // A plane z = 0 with normal +z, sheared and scaled non-uniformly.
        let m = Mat4::from_cols_array(&[
            2.0, 0.0, 0.0, 0.0, 1.0, 0.5, 0.0, 0.0, 0.3, 0.0, 4.0, 0.0, 1.0, 2.0, 3.0, 1.0,
        ]);
        let inst = Instance::new(0, m);
        let n = (inst.normal_matrix() * Vec3::Z).normalize();
        for t in [Vec3::X, Vec3::Y, Vec3::new(0.3, 0.7, 0.0)] {
            let tw = Mat3::from_mat4(m) * t;
            assert!(n.dot(tw).abs() < 1e-5);
        }
    }

    #[test]
    fn validate_and_degenerate() {
        let mut m = Mesh {
            positions: vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::new(2.0, 0.0, 0.0)],
            indices: vec![[0, 1, 2], [0, 1, 3]],
            ..Default::default()
        };
        assert!(m.validate().is_ok());
        assert_eq!(m.remove_degenerate().degenerate_triangles, 1);
        m.indices.push([0, 1, 7]);
        assert!(m.validate().unwrap_err().contains("vertex 7"));
        m.positions[1] = Vec3::new(f32::NAN, 0.0, 0.0);
        assert!(m.validate().unwrap_err().contains("non-finite"));
    }
}
