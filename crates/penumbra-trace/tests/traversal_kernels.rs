//! Every traversal kernel the CPU runs finds the same closest hit as a
//! brute-force loop over all triangles, with and without prefetching, one
//! ray at a time, with walks interleaved and in packets, on the benchmark
//! mesh, for coherent (camera) rays, of one octant or several, and
//! incoherent (random directions from surface points) rays.

use glam::Vec3;
use penumbra_shading::sampling::{Sampler, square_to_uniform_sphere};
use penumbra_trace::accel::{Accel, BuildQuality, Hit, Kernel, WatertightRay};
use penumbra_trace::ray::{Ray, offset_ray_origin};

/// Closest hit by testing every triangle: (triangle, t).
fn brute_force(tris: &[[Vec3; 3]], ray: &Ray) -> Option<(u32, f32)> {
    let wt = WatertightRay::new(ray.origin, ray.direction);
    let mut best: Option<(u32, f32)> = None;
    for (i, t) in tris.iter().enumerate() {
        if let Some(h) = wt.intersect(t[0], t[1], t[2], best.map_or(ray.tmax, |b| b.1)) {
            best = Some((i as u32, h.t));
        }
    }
    best
}

#[test]
fn kernels_match_brute_force_on_the_bench_mesh() {
    let mesh = penumbra_trace::bench::bench_mesh(100_000);
    let tris: Vec<[Vec3; 3]> = mesh
        .indices
        .iter()
        .map(|t| t.map(|i| mesh.positions[i as usize]))
        .collect();
    let mut accel = Accel::build(&tris, BuildQuality::Medium);
    accel.validate().unwrap();

    // Coherent: a fan of rays from outside through the mesh's bounds.
    let mut rays: Vec<Ray> = (0..400)
        .map(|i| {
            let (x, y) = ((i % 20) as f32 / 19.0 - 0.5, (i / 20) as f32 / 19.0 - 0.5);
            let o = Vec3::new(0.1, 0.2, 4.0);
            Ray::new(o, (Vec3::new(x * 2.6, y * 2.6, 0.0) - o).normalize())
        })
        .collect();
    // Coherent in one octant (packets take the frustum walk): a fan from
    // a corner, every direction with the signs (+, +, −).
    rays.extend((0..400).map(|i| {
        let (x, y) = ((i % 20) as f32 / 19.0 - 0.5, (i / 20) as f32 / 19.0 - 0.5);
        let o = Vec3::new(-3.0, -2.5, 4.0);
        Ray::new(o, (Vec3::new(x * 2.6, y * 2.6, 0.0) - o).normalize())
    }));
    // Incoherent: from points on triangles, uniform directions.
    for i in 0..400u32 {
        let mut s = Sampler::new(i, 0, 0, 5);
        let [u, v] = s.next_2d();
        let t = tris[(u * tris.len() as f32) as usize % tris.len()];
        let p = (t[0] + t[1] + t[2]) / 3.0;
        let n = (t[1] - t[0]).cross(t[2] - t[0]).normalize();
        let d = square_to_uniform_sphere([v, s.next_2d()[0]]);
        let side = if d.dot(n) >= 0.0 { n } else { -n };
        rays.push(Ray::new(offset_ray_origin(p, side), d));
    }
    let expected: Vec<_> = rays.iter().map(|r| brute_force(&tris, r)).collect();
    let coherent_hits = expected[..800].iter().filter(|e| e.is_some()).count();
    let incoherent_hits = expected[800..].iter().filter(|e| e.is_some()).count();
    assert!(
        coherent_hits > 200 && coherent_hits < 800,
        "{coherent_hits}"
    );
    assert!(
        incoherent_hits > 50 && incoherent_hits < 400,
        "{incoherent_hits}"
    );
    // 100k triangles (5.6 MB of nodes and triangles) are more than the
    // caches hold: the traversal prefetches by default. Hits must be the
    // same without.
    assert!(accel.prefetch());
    for kernel in Kernel::available() {
        accel.set_kernel(kernel).unwrap();
        for prefetch in [true, false] {
            accel.set_prefetch(prefetch);
            for (ray, e) in rays.iter().zip(&expected) {
                let got = accel.intersect(ray).map(|h| (h.triangle, h.t));
                assert_eq!(got, *e, "{kernel:?} prefetch {prefetch} {ray:?}");
                assert_eq!(
                    accel.occluded(ray),
                    e.is_some(),
                    "{kernel:?} prefetch {prefetch} {ray:?}"
                );
            }
            // The same rays with their walks interleaved, and in packets
            // (coherent ones first: packets of mixed octants, then of one,
            // which take the frustum walk; then packets of incoherent rays).
            type Batch = fn(&Accel, &[Ray], &mut [Option<Hit>]);
            let batches: [(&str, Batch); 2] = [
                ("interleaved", Accel::intersect_many),
                ("packets", Accel::intersect_packets),
            ];
            for (name, batch) in batches {
                let mut hits = vec![None; rays.len()];
                batch(&accel, &rays, &mut hits);
                for ((hit, e), ray) in hits.iter().zip(&expected).zip(&rays) {
                    let got = hit.map(|h| (h.triangle, h.t));
                    assert_eq!(got, *e, "{kernel:?} prefetch {prefetch} {name} {ray:?}");
                }
            }
        }
    }
}
