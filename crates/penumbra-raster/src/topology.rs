//! Mesh adjacency for stencil shadow volumes: every edge with the triangles
//! on either side, found by welding vertices at bit-identical positions (so
//! meshes split along UV or normal seams still count as closed).
//!
//! An edge record `[a, b, t1, t2]` says that triangle `t1` runs a → b and
//! triangle `t2` runs b → a (`t2` = [`NO_TRIANGLE`] on a boundary). With
//! f(t) ∈ {−1, 0, +1} the signed "casts towards the light" value of each
//! triangle for one light (see `shadow_volume.wgsl`), the edge carries
//! `f(t1) − f(t2)` side quads from a → b: zero inside a region that faces
//! the light uniformly, ±1 on a silhouette of a closed mesh, up to ±2 on
//! open meshes. Edges used by more than two triangles are paired a → b with
//! b → a as far as they go; the rest become boundary records.

use glam::Vec3;
use std::collections::HashMap;

/// `t2` of an edge with one triangle.
pub const NO_TRIANGLE: u32 = u32::MAX;

/// The edges of a mesh and whether it is closed.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MeshTopology {
    /// `[a, b, t1, t2]`: vertex indices a → b as they appear in t1.
    pub edges: Vec<[u32; 4]>,
    /// Every edge has exactly one triangle on each side, oppositely wound
    /// (a closed, consistently oriented 2-manifold).
    pub closed: bool,
    /// Edges left with one triangle (after pairing).
    pub boundary_edges: usize,
    /// Undirected edges used by more than two triangles.
    pub non_manifold_edges: usize,
}

/// Builds the edge records of a triangle mesh.
pub fn mesh_topology(positions: &[Vec3], indices: &[[u32; 3]]) -> MeshTopology {
    // Weld: one id per distinct position bit pattern.
    let mut weld: HashMap<[u32; 3], u32> = HashMap::with_capacity(positions.len());
    let welded: Vec<u32> = positions
        .iter()
        .map(|p| {
            let key = [p.x.to_bits(), p.y.to_bits(), p.z.to_bits()];
            let next = weld.len() as u32;
            *weld.entry(key).or_insert(next)
        })
        .collect();
    // Per undirected welded edge: triangles running low → high, and high → low.
    type Sides = (Vec<(u32, u32, u32)>, Vec<(u32, u32, u32)>);
    let mut edges: HashMap<(u32, u32), Sides> = HashMap::with_capacity(indices.len() * 3 / 2);
    let mut order = Vec::new();
    for (t, tri) in indices.iter().enumerate() {
        for k in 0..3 {
            let (a, b) = (tri[k], tri[(k + 1) % 3]);
            let (wa, wb) = (welded[a as usize], welded[b as usize]);
            if wa == wb {
                continue; // collapsed edge of a degenerate triangle
            }
            let key = (wa.min(wb), wa.max(wb));
            let entry = edges.entry(key).or_insert_with(|| {
                order.push(key);
                Default::default()
            });
            if wa < wb {
                entry.0.push((a, b, t as u32));
            } else {
                entry.1.push((a, b, t as u32));
            }
        }
    }
    let mut out = MeshTopology::default();
    for key in order {
        let (forward, backward) = &edges[&key];
        if forward.len() + backward.len() > 2 {
            out.non_manifold_edges += 1;
        }
        let pairs = forward.len().min(backward.len());
        for i in 0..pairs {
            let (a, b, t1) = forward[i];
            out.edges.push([a, b, t1, backward[i].2]);
        }
        for &(a, b, t) in forward[pairs..].iter().chain(&backward[pairs..]) {
            out.edges.push([a, b, t, NO_TRIANGLE]);
            out.boundary_edges += 1;
        }
    }
    out.closed = out.boundary_edges == 0 && !indices.is_empty();
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use penumbra_scene::primitives;

    /// For every record, t1 really runs a → b and t2 runs b → a.
    fn check_orientation(indices: &[[u32; 3]], positions: &[Vec3], topo: &MeshTopology) {
        let runs = |t: u32, a: Vec3, b: Vec3| {
            let tri = indices[t as usize];
            (0..3).any(|k| {
                positions[tri[k] as usize] == a && positions[tri[(k + 1) % 3] as usize] == b
            })
        };
        for &[a, b, t1, t2] in &topo.edges {
            let (pa, pb) = (positions[a as usize], positions[b as usize]);
            assert!(runs(t1, pa, pb));
            if t2 != NO_TRIANGLE {
                assert!(runs(t2, pb, pa));
            }
        }
    }

    #[test]
    fn a_cube_with_split_faces_is_closed_after_welding() {
        let m = primitives::cuboid(Vec3::ZERO, Vec3::ONE);
        // 6 faces with their own vertices: indices alone would not close it.
        assert!(m.positions.len() > 8);
        let topo = mesh_topology(&m.positions, &m.indices);
        assert!(topo.closed, "{topo:?}");
        assert_eq!(topo.edges.len(), 18); // 12 cube edges + 6 face diagonals
        assert_eq!((topo.boundary_edges, topo.non_manifold_edges), (0, 0));
        check_orientation(&m.indices, &m.positions, &topo);
    }

    #[test]
    fn a_sphere_is_closed_and_a_quad_is_open() {
        let s = primitives::sphere(Vec3::ZERO, 1.0, 8);
        let topo = mesh_topology(&s.positions, &s.indices);
        assert!(topo.closed, "{topo:?}");
        check_orientation(&s.indices, &s.positions, &topo);

        let q = primitives::quad(Vec3::ZERO, Vec3::X, Vec3::Z);
        let topo = mesh_topology(&q.positions, &q.indices);
        assert!(!topo.closed);
        // 4 rim edges with one triangle, the diagonal with two.
        assert_eq!((topo.edges.len(), topo.boundary_edges), (5, 4));
        check_orientation(&q.indices, &q.positions, &topo);
    }

    #[test]
    fn edges_of_three_triangles_pair_what_they_can() {
        // Three triangles on one edge (0, 1): two run 0 → 1, one 1 → 0.
        let p = vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::NEG_Y, Vec3::Z];
        let idx = vec![[0, 1, 2], [1, 0, 3], [0, 1, 4]];
        let topo = mesh_topology(&p, &idx);
        assert_eq!(topo.non_manifold_edges, 1);
        assert!(!topo.closed);
        let shared: Vec<_> = topo
            .edges
            .iter()
            .filter(|e| {
                let (a, b) = (e[0].min(e[1]), e[0].max(e[1]));
                (a, b) == (0, 1)
            })
            .collect();
        // One pair (0→1 in t0, 1→0 in t1) and one boundary record (t2).
        assert_eq!(shared.len(), 2);
        assert!(shared.iter().any(|e| e[3] == NO_TRIANGLE && e[2] == 2));
        check_orientation(&idx, &p, &topo);
    }
}
