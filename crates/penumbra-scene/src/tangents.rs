//! Tangent frames for normal maps: MikkTSpace (Mikkelsen 2008, the
//! convention glTF and the tools that bake normal maps use), computed by the
//! `bevy_mikktspace` crate from a mesh's positions, normals and the UV set
//! of its normal map.
//!
//! MikkTSpace runs on one thread and costs about 2 µs a triangle, so a large
//! mesh is split into parts run in parallel. A vertex's frame depends only
//! on the triangles that touch it or a vertex MikkTSpace welds to it (equal
//! position, normal and UV): its *fan*. Each vertex is given to one part,
//! and that part's run holds the whole fan of each of its vertices, in the
//! mesh's order, so it computes the frame one run over the whole mesh does
//! (tested bit for bit). The one exception is MikkTSpace's own order
//! dependency: a triangle with no UV area takes its orientation from the
//! first group that reaches it, which a part may see differently when its
//! neighbours' orientations differ.

use crate::mesh::Mesh;
use glam::{Vec2, Vec3, Vec4};
use rayon::prelude::*;

/// Triangles a part owns when a large mesh is split (beyond this, one run).
const FACES_PER_PART: usize = 1 << 15;

/// Faces of the mesh MikkTSpace reads (all of them, or a part's, in the
/// mesh's order); the frames it writes, as (vertex, tangent) in the order
/// written, for the vertices `keep` accepts.
struct Frames<'a, K> {
    mesh: &'a Mesh,
    normals: &'a [Vec3],
    uvs: &'a [Vec2],
    faces: Option<&'a [u32]>,
    keep: K,
    written: Vec<(u32, Vec4)>,
}

impl<K: Fn(u32) -> bool> Frames<'_, K> {
    fn vertex(&self, face: usize, vert: usize) -> usize {
        let face = self.faces.map_or(face, |f| f[face] as usize);
        self.mesh.indices[face][vert] as usize
    }
}

impl<K: Fn(u32) -> bool> bevy_mikktspace::Geometry for Frames<'_, K> {
    fn num_faces(&self) -> usize {
        self.faces.map_or(self.mesh.indices.len(), <[u32]>::len)
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

    fn tex_coord(&self, face: usize, vert: usize) -> [f32; 2] {
        tex_coord(self.uvs[self.vertex(face, vert)])
    }

    fn set_tangent(
        &mut self,
        tangent_space: Option<bevy_mikktspace::TangentSpace>,
        face: usize,
        vert: usize,
    ) {
        let v = self.vertex(face, vert) as u32;
        if let Some(t) = tangent_space
            && (self.keep)(v)
        {
            self.written
                .push((v, Vec4::from_array(t.tangent_encoded())));
        }
    }
}

/// The UV MikkTSpace is given. glTF's v runs down the image; normal maps'
/// +y (green) points up it, so the frame is built on (u, 1 − v), as the
/// tools that bake them do.
fn tex_coord(uv: Vec2) -> [f32; 2] {
    [uv.x, 1.0 - uv.y]
}

/// Per-vertex MikkTSpace tangents (xyz, w = handedness) of a mesh with
/// normals and UV set `uv_set` (else none: `+x`, w = 1 everywhere). MikkTSpace
/// gives each triangle corner its own frame; a vertex shared by corners
/// whose frames differ (a mirrored UV seam that shares vertices) keeps the
/// last one.
pub fn mikktspace_tangents(mesh: &Mesh, uv_set: usize) -> Vec<Vec4> {
    // One worker gains nothing from parts and would pay for their overlap.
    let per_part = match rayon::current_num_threads() {
        1 => usize::MAX,
        _ => FACES_PER_PART,
    };
    tangents_in_parts(mesh, uv_set, per_part, 2)
}

/// [`mikktspace_tangents`] with parts of `faces_per_part` triangles, unless
/// the parts would hold more than `max_repeat` times the mesh's triangles
/// together (a mesh whose triangle order is so scattered that each part
/// would hold most of it runs whole).
fn tangents_in_parts(
    mesh: &Mesh,
    uv_set: usize,
    faces_per_part: usize,
    max_repeat: usize,
) -> Vec<Vec4> {
    let n = mesh.positions.len();
    let mut tangents = vec![Vec4::new(1.0, 0.0, 0.0, 1.0); n];
    let normals = mesh.normals.as_deref().unwrap_or(&[]);
    let uvs = mesh.uv_set(uv_set).unwrap_or(&[]);
    if normals.len() != n || uvs.len() != n {
        return tangents;
    }
    let run = |faces: Option<&[u32]>, keep: &(dyn Fn(u32) -> bool + Sync)| {
        let mut frames = Frames {
            mesh,
            normals,
            uvs,
            faces,
            keep,
            written: Vec::new(),
        };
        // An error only means some faces got the default frame.
        let _ = bevy_mikktspace::generate_tangents(&mut frames);
        frames.written
    };
    let parts = mesh.indices.len().div_ceil(faces_per_part.max(1));
    let split = (parts > 1).then(|| {
        let fans = fans(mesh, normals, uvs, faces_per_part);
        let faces: Vec<Vec<u32>> = (0..parts)
            .into_par_iter()
            .map(|p| fans.part_faces(mesh, p))
            .collect();
        (fans, faces)
    });
    let written = match split {
        Some((fans, faces))
            if faces.iter().map(Vec::len).sum::<usize>()
                <= max_repeat.saturating_mul(mesh.indices.len()) =>
        {
            faces
                .par_iter()
                .enumerate()
                .map(|(part, faces)| run(Some(faces), &|v| fans.owner(v) == part))
                .collect()
        }
        _ => vec![run(None, &|_| true)],
    };
    for (v, t) in written.into_iter().flatten() {
        tangents[v as usize] = t;
    }
    tangents
}

/// Which triangles touch each weld class (vertices equal in position,
/// normal and MikkTSpace UV). A class belongs to the part of the last
/// triangle that touches it (any part would do: a part holds the whole fan
/// of each class it owns).
struct Fans {
    /// Weld class of each vertex.
    class: Vec<u32>,
    /// Triangles of class c, in the mesh's order: `faces[start[c]..start[c + 1]]`.
    start: Vec<u32>,
    faces: Vec<u32>,
    faces_per_part: usize,
}

fn fans(mesh: &Mesh, normals: &[Vec3], uvs: &[Vec2], faces_per_part: usize) -> Fans {
    let n = mesh.positions.len();
    // Weld classes: MikkTSpace compares the floats with ==, which adding
    // +0.0 (−0 becomes +0) makes a comparison of bits.
    let key = |v: usize| {
        let (p, nn, t) = (mesh.positions[v], normals[v], tex_coord(uvs[v]));
        [p.x, p.y, p.z, nn.x, nn.y, nn.z, t[0], t[1]].map(|x| (x + 0.0).to_bits())
    };
    let mut sorted: Vec<([u32; 8], u32)> = (0..n).map(|v| (key(v), v as u32)).collect();
    sorted.par_sort_unstable();
    let mut class = vec![0u32; n];
    let mut classes = 0u32;
    for (i, (k, v)) in sorted.iter().enumerate() {
        if i > 0 && *k != sorted[i - 1].0 {
            classes += 1;
        }
        class[*v as usize] = classes;
    }
    let classes = (classes + 1) as usize;
    drop(sorted);
    // Each class's triangles, in the mesh's order (a triangle with two
    // corners in one class is listed twice; parts remove repeats).
    let mut start = vec![0u32; classes + 1];
    for tri in &mesh.indices {
        for &v in tri {
            start[class[v as usize] as usize + 1] += 1;
        }
    }
    for c in 0..classes {
        start[c + 1] += start[c];
    }
    let mut fill = start.clone();
    let mut faces = vec![0u32; mesh.indices.len() * 3];
    for (f, tri) in mesh.indices.iter().enumerate() {
        for &v in tri {
            let c = class[v as usize] as usize;
            faces[fill[c] as usize] = f as u32;
            fill[c] += 1;
        }
    }
    Fans {
        class,
        start,
        faces,
        faces_per_part,
    }
}

impl Fans {
    fn fan(&self, class: u32) -> &[u32] {
        let c = class as usize;
        &self.faces[self.start[c] as usize..self.start[c + 1] as usize]
    }

    /// The part that owns `vertex` (which some triangle touches).
    fn owner(&self, vertex: u32) -> usize {
        let fan = self.fan(self.class[vertex as usize]);
        fan[fan.len() - 1] as usize / self.faces_per_part
    }

    /// The triangles of every fan `part` owns, in the mesh's order: the
    /// fans of the classes whose last triangle is one of the part's.
    fn part_faces(&self, mesh: &Mesh, part: usize) -> Vec<u32> {
        let first = part * self.faces_per_part;
        let last = (first + self.faces_per_part).min(mesh.indices.len());
        let mut faces: Vec<u32> = (first..last)
            .flat_map(|f| mesh.indices[f].map(|v| (f, self.class[v as usize])))
            .filter(|&(f, c)| *self.fan(c).last().unwrap() as usize == f)
            .flat_map(|(_, c)| self.fan(c).iter().copied())
            .collect();
        faces.sort_unstable();
        faces.dedup();
        faces
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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

    /// A bumpy grid whose UVs are mirrored in u on the right half (the
    /// frames turn there). Two columns are given twice with equal values,
    /// which MikkTSpace welds: the mirror seam, and a column a quarter of the
    /// way across whose copy writes y = 0 as −0. A few triangles are
    /// collapsed to a segment.
    fn seamed_grid(cells: usize) -> Mesh {
        let mut m = Mesh::default();
        let (quarter, half) = (cells / 4, cells / 2);
        let push = |m: &mut Mesh, i: usize, j: usize, copy: bool| {
            let (x, y) = (i as f32 / cells as f32, j as f32 / cells as f32);
            let h = 0.1 * (7.0 * x).sin() * (5.0 * y).cos();
            let n = Vec3::new(
                -0.7 * (7.0 * x).cos() * (5.0 * y).cos(),
                0.5 * (7.0 * x).sin() * (5.0 * y).sin(),
                1.0,
            );
            let u = if i <= half {
                x
            } else {
                2.0 * half as f32 / cells as f32 - x
            };
            let y_written = if copy && y == 0.0 { -0.0 } else { y };
            m.positions.push(Vec3::new(x, y_written, h));
            m.normals.get_or_insert_with(Vec::new).push(n.normalize());
            m.uv0.get_or_insert_with(Vec::new).push(Vec2::new(u, y * y));
            (m.positions.len() - 1) as u32
        };
        let mut index = Vec::new();
        let mut copies = Vec::new();
        for j in 0..=cells {
            index.push(
                (0..=cells)
                    .map(|i| push(&mut m, i, j, false))
                    .collect::<Vec<_>>(),
            );
            copies.push([push(&mut m, quarter, j, true), push(&mut m, half, j, true)]);
        }
        for j in 0..cells {
            for i in 0..cells {
                // Cells right of a copied column use the copies.
                let at = |ii: usize, jj: usize| match (ii, i) {
                    (c, i) if c == quarter && i >= quarter && i < half => copies[jj][0],
                    (c, i) if c == half && i >= half => copies[jj][1],
                    _ => index[jj][ii],
                };
                let (a, b, c, d) = (at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
                m.indices.push([a, b, c]);
                m.indices.push([a, c, d]);
            }
        }
        // Collapsed triangles: two corners on one vertex.
        for k in [3usize, 40, 77] {
            let [a, b, _] = m.indices[k];
            m.indices.push([a, b, b]);
        }
        m
    }

    fn bits(t: &[Vec4]) -> Vec<[u32; 4]> {
        t.iter().map(|v| v.to_array().map(f32::to_bits)).collect()
    }

    /// Parts give each vertex the frame one run over the whole mesh gives,
    /// bit for bit: with the triangles in grid order and shuffled (each
    /// part's fans then scattered over the mesh), and in parts as small as
    /// a few triangles.
    #[test]
    fn parts_give_the_frames_of_one_run() {
        let grid = seamed_grid(12);
        let mut shuffled = grid.clone();
        let mut state = 0x9e37_79b9_u32;
        for i in (1..shuffled.indices.len()).rev() {
            state ^= state << 13;
            state ^= state >> 17;
            state ^= state << 5;
            shuffled.indices.swap(i, state as usize % (i + 1));
        }
        for mesh in [&grid, &shuffled] {
            let whole = tangents_in_parts(mesh, 0, usize::MAX, 1);
            // The mirrored half has the other handedness.
            assert!(whole.iter().any(|t| t.w > 0.0) && whole.iter().any(|t| t.w < 0.0));
            for per_part in [5, 37, 100] {
                let parts = tangents_in_parts(mesh, 0, per_part, usize::MAX);
                assert_eq!(bits(&parts), bits(&whole), "{per_part} triangles a part");
            }
        }
    }

    /// The same on a real model, DamagedHelmet (15k triangles, no tangents in
    /// the file, UV islands and seams everywhere).
    #[test]
    fn parts_give_the_frames_of_one_run_on_a_real_model() {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../../../shared/gltf-samples/DamagedHelmet/glTF-Binary/DamagedHelmet.glb");
        let scene = crate::load::load_scene(&path, &Default::default())
            .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let mesh = &scene.meshes[0];
        assert!(mesh.indices.len() > 15_000);
        let whole = tangents_in_parts(mesh, 0, usize::MAX, 1);
        let parts = tangents_in_parts(mesh, 0, 1000, usize::MAX);
        assert_eq!(bits(&parts), bits(&whole));
    }
}
