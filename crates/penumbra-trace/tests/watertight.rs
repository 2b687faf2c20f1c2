//! Watertightness: rays from inside a closed mesh aimed exactly at its shared
//! edges and vertices never escape, with every traversal kernel the CPU
//! runs, one ray at a time, interleaved and in packets.

use glam::Vec3;
use penumbra_shading::sampling::Sampler;
use penumbra_trace::accel::{Accel, BuildQuality, Kernel};
use penumbra_trace::bench::bench_mesh;
use penumbra_trace::ray::Ray;

#[test]
fn a_million_rays_at_edges_and_vertices_never_pass_through() {
    let mesh = bench_mesh(20_000);
    let tris: Vec<[Vec3; 3]> = mesh
        .indices
        .iter()
        .map(|t| t.map(|i| mesh.positions[i as usize] * 7.3 + Vec3::new(100.0, -20.0, 3.0)))
        .collect();
    let mut accel = Accel::build(&tris, BuildQuality::Medium);
    accel.validate().unwrap();
    let rays = rays_at_edges_and_vertices(&tris);
    for kernel in Kernel::available() {
        accel.set_kernel(kernel).unwrap();
        let alone = rays.iter().filter(|r| accel.intersect(r).is_none()).count();
        assert_eq!(alone, 0, "{kernel:?}");
        let mut hits = vec![None; rays.len()];
        accel.intersect_many(&rays, &mut hits);
        assert_eq!(
            hits.iter().filter(|h| h.is_none()).count(),
            0,
            "{kernel:?} interleaved"
        );
        hits.fill(None);
        accel.intersect_packets(&rays, &mut hits);
        assert_eq!(
            hits.iter().filter(|h| h.is_none()).count(),
            0,
            "{kernel:?} packets"
        );
    }
}

/// A million rays from inside aimed at the edges and vertices of `tris`.
fn rays_at_edges_and_vertices(tris: &[[Vec3; 3]]) -> Vec<Ray> {
    let centre = Vec3::new(100.0, -20.0, 3.0);
    let n_rays = 1_000_000u32;
    let mut rays = Vec::with_capacity(n_rays as usize);
    for i in 0..n_rays {
        let mut s = Sampler::new(i, 0, 0, 11);
        let [u, v] = s.next_2d();
        let [w, _] = s.next_2d();
        let t = &tris[((u * tris.len() as f32) as usize).min(tris.len() - 1)];
        let e = ((v * 3.0) as usize).min(2);
        // Half the rays at a vertex, half at a point on an edge.
        let target = if i % 2 == 0 {
            t[e]
        } else {
            t[e] + (t[(e + 1) % 3] - t[e]) * w
        };
        // Origins scattered inside the (star-shaped) mesh around its centre.
        let o = centre + (Vec3::new(u, v, w) - 0.5) * 2.0;
        let d = target - o;
        if d.length_squared() == 0.0 {
            continue;
        }
        rays.push(Ray::new(o, d.normalize()));
    }
    rays
}
