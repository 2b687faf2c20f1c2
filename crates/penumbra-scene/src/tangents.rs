//! Tangent frames for normal maps: MikkTSpace (Mikkelsen 2008, the
//! convention glTF and the tools that bake normal maps use), computed by the
//! `bevy_mikktspace` crate from a mesh's positions, normals and the UV set
//! of its normal map.

use crate::mesh::Mesh;
use glam::Vec4;

/// The mesh as MikkTSpace reads it; the tangents it writes, one per vertex.
struct Frames<'a> {
    mesh: &'a Mesh,
    normals: &'a [glam::Vec3],
    uvs: &'a [glam::Vec2],
    tangents: Vec<Vec4>,
}

impl Frames<'_> {
    fn vertex(&self, face: usize, vert: usize) -> usize {
        self.mesh.indices[face][vert] as usize
    }
}

impl bevy_mikktspace::Geometry for Frames<'_> {
    fn num_faces(&self) -> usize {
        self.mesh.indices.len()
    }

    fn num_vertices_of_face(&self, _face: usize) -> usize {
        3
    }

    fn position(&self, face: usize, vert: usize) -> [f32; 3] {
        self.mesh.positions[self.vertex(face, vert)].to_array()
    }

    fn normal(&self, face: usize, vert: usize) -> [f32; 3] {
        self.normals[self.vertex(face, vert)].to_array()
    }

    /// glTF's v runs down the image; normal maps' +y (green) points up it,
    /// so the frame is built on (u, 1 − v), as the tools that bake them do.
    fn tex_coord(&self, face: usize, vert: usize) -> [f32; 2] {
        let uv = self.uvs[self.vertex(face, vert)];
        [uv.x, 1.0 - uv.y]
    }

    fn set_tangent(
        &mut self,
        tangent_space: Option<bevy_mikktspace::TangentSpace>,
        face: usize,
        vert: usize,
    ) {
        if let Some(t) = tangent_space {
            let v = self.vertex(face, vert);
            self.tangents[v] = Vec4::from_array(t.tangent_encoded());
        }
    }
}

/// Per-vertex MikkTSpace tangents (xyz, w = handedness) of a mesh with
/// normals and UV set `uv_set` (else none: `+x`, w = 1 everywhere). MikkTSpace
/// gives each triangle corner its own frame; a vertex shared by corners
/// whose frames differ (a mirrored UV seam that shares vertices) keeps the
/// last one.
pub fn mikktspace_tangents(mesh: &Mesh, uv_set: usize) -> Vec<Vec4> {
    let n = mesh.positions.len();
    let mut frames = Frames {
        mesh,
        normals: mesh.normals.as_deref().unwrap_or(&[]),
        uvs: mesh.uv_set(uv_set).unwrap_or(&[]),
        tangents: vec![Vec4::new(1.0, 0.0, 0.0, 1.0); n],
    };
    if frames.normals.len() == n && frames.uvs.len() == n {
        // An error only means some faces got the default frame.
        let _ = bevy_mikktspace::generate_tangents(&mut frames);
    }
    frames.tangents
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::{Vec2, Vec3};

    /// A quad in the xy plane facing +z, u along +x and v along +y: the
    /// image's top row (v = 0) lies at y = 0, so a normal map's +y (up the
    /// image) is −y in the world. The tangent follows +u and w makes the
    /// bitangent w · n × t point up the image; mirrored in u, the tangent
    /// turns and w with it, the bitangent stays.
    #[test]
    fn tangents_follow_u_and_the_bitangent_points_up_the_image() {
        let layout = |u: [f32; 4]| {
            vec![
                Vec2::new(u[0], 0.0),
                Vec2::new(u[1], 0.0),
                Vec2::new(u[2], 1.0),
                Vec2::new(u[3], 1.0),
            ]
        };
        let (plain, mirrored) = ([0.0, 1.0, 1.0, 0.0], [1.0, 0.0, 0.0, 1.0]);
        // Each layout once as set 0 and once as set 1 (the other layout in
        // the other set): the frame follows the set asked for.
        let quad = |uv0: [f32; 4], uv1: [f32; 4]| Mesh {
            positions: vec![Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.0), Vec3::Y],
            normals: Some(vec![Vec3::Z; 4]),
            uv0: Some(layout(uv0)),
            uv1: Some(layout(uv1)),
            indices: vec![[0, 1, 2], [0, 2, 3]],
            ..Default::default()
        };
        for (mesh, set, tangent) in [
            (quad(plain, mirrored), 0, Vec4::new(1.0, 0.0, 0.0, -1.0)),
            (quad(mirrored, plain), 0, Vec4::new(-1.0, 0.0, 0.0, 1.0)),
            (quad(mirrored, plain), 1, Vec4::new(1.0, 0.0, 0.0, -1.0)),
            (quad(plain, mirrored), 1, Vec4::new(-1.0, 0.0, 0.0, 1.0)),
        ] {
            for t in mikktspace_tangents(&mesh, set) {
                assert!((t - tangent).length() < 1e-5, "set {set}: {t} vs {tangent}");
                let b = Vec3::Z.cross(t.truncate()) * t.w;
                assert!((b + Vec3::Y).length() < 1e-5, "bitangent {b}");
            }
        }
    }
}
