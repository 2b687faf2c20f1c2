//! One object's triangles for one ray at a time, sixteen boxes or
//! sixteen triangles per AVX-512 instruction (or two AVX2 ones), in a
//! tree of fixed shape: clusters of up to sixteen chunks of up to sixteen
//! triangles (the scan's chunks, `scan.rs`), each with its padded bounds,
//! clusters in one or two groups of sixteen. A ray tests a group's sixteen
//! clusters' bounds at once (the nearer group first), enters the clusters
//! it passes nearest first, tests their sixteen chunks' bounds at once, and
//! the chunks it passes nearest first, until the next box begins beyond
//! the closest hit so far. For objects of a few thousand triangles (the
//! spheres of the glass and metal scenes: 1,280 and 5,120), where the
//! 8-wide BVH's walk spends more in its steps than in its tests.
//!
//! The triangles are split in two, recursively, in the order of their
//! centroids along one axis, in counts that fill whole chunks (and whole
//! clusters and groups): the axis and count whose parts' bounds have the
//! least surface area heuristic cost (half area times count).
//!
//! The triangle test is the scan's: the operations of
//! `WatertightRay::intersect_a` in its order, sixteen lanes at once, with
//! its scalar f64 fallback, so the hits, distances and barycentrics are
//! the scalar test's to the bit. Of equal distances the hit found first
//! wins (the one of the nearer box, then the lowest triangle index).
//!
//! One of the crate's modules with `unsafe` code: its calls of the
//! sixteen-lane operations (`lanes16.rs`), which need the CPU's features.
#![allow(unsafe_code)]

use super::lanes16::Simd16;
use super::scan::{Chunk, LANES, Lanes, TriangleScan, accepts, bounds, padded};
use super::watertight::{TriangleHit, WatertightRay};
use glam::Vec3;

/// Triangles of the largest object taken: two groups of sixteen clusters
/// (beyond that a BVH's walk is the better search).
pub const MAX_TRIANGLES: usize = 2 * LANES * LANES * LANES;

/// Up to sixteen padded boxes in structure-of-arrays form and which lanes
/// hold one; 64-byte aligned, so that each array is one aligned load.
#[derive(Clone, Copy, Debug)]
#[repr(C, align(64))]
struct Boxes {
    lo: [Lanes; 3],
    hi: [Lanes; 3],
    used: u16,
}

impl Boxes {
    /// Up to sixteen bounds, each padded ([`padded`]).
    fn new(groups: impl Iterator<Item = [Vec3; 2]>) -> Boxes {
        let mut b = Boxes {
            lo: [[0.0; LANES]; 3],
            hi: [[0.0; LANES]; 3],
            used: 0,
        };
        for (lane, [lo, hi]) in groups.enumerate() {
            assert!(lane < LANES, "sixteen boxes at most");
            let ([lo, hi], _) = padded([lo, hi].into_iter());
            for a in 0..3 {
                b.lo[a][lane] = lo[a];
                b.hi[a][lane] = hi[a];
            }
            b.used |= 1 << lane;
        }
        b
    }
}

/// An object's triangles as clusters of chunks, clusters in groups of
/// sixteen: `tops[r]` bounds the clusters of group r, which begin at
/// `first_cluster[r]`; `clusters[c]` bounds the chunks of cluster c,
/// which begin at `first_chunk[c]`.
#[derive(Clone, Debug)]
pub struct ClusterScan {
    tops: Vec<Boxes>,
    first_cluster: Vec<usize>,
    clusters: Vec<Boxes>,
    first_chunk: Vec<usize>,
    chunks: Vec<Chunk>,
}

/// The bounds of nothing: the identity of [`union`].
const EMPTY: [Vec3; 2] = [Vec3::INFINITY, Vec3::NEG_INFINITY];

/// The bounds of two bounds.
fn union([a, b]: [Vec3; 2], [c, d]: [Vec3; 2]) -> [Vec3; 2] {
    [a.min(c), b.max(d)]
}

/// `items` split into groups of at most `size` (all full but the last),
/// recursively in two: along the axis and at the multiple of `size`, in
/// the order of their centroids, where the two parts' bounds (of the
/// triangles' `boxes`) have the least sum of half area times count (the
/// surface area heuristic's estimate of the triangle tests).
fn split(
    mut items: Vec<usize>,
    centroids: &[Vec3],
    boxes: &[[Vec3; 2]],
    size: usize,
    out: &mut Vec<Vec<usize>>,
) {
    if items.len() <= size {
        out.push(items);
        return;
    }
    let half_area = |[lo, hi]: [Vec3; 2]| {
        let e = hi - lo;
        e.x * e.y + e.y * e.z + e.z * e.x
    };
    let order = |items: &mut Vec<usize>, axis: usize| {
        items.sort_by(|&a, &b| {
            centroids[a][axis]
                .total_cmp(&centroids[b][axis])
                .then(a.cmp(&b))
        })
    };
    let n = items.len();
    let mut best = (f32::INFINITY, 0, size);
    for axis in 0..3 {
        order(&mut items, axis);
        let mut suffix = vec![EMPTY; n + 1];
        for i in (0..n).rev() {
            suffix[i] = union(suffix[i + 1], boxes[items[i]]);
        }
        let mut prefix = EMPTY;
        for (i, &k) in items.iter().enumerate() {
            prefix = union(prefix, boxes[k]);
            let left = i + 1;
            if left % size == 0 && left < n {
                let cost =
                    half_area(prefix) * left as f32 + half_area(suffix[left]) * (n - left) as f32;
                if cost < best.0 {
                    best = (cost, axis, left);
                }
            }
        }
    }
    order(&mut items, best.1);
    let right = items.split_off(best.2);
    split(items, centroids, boxes, size, out);
    split(right, centroids, boxes, size, out);
}

impl ClusterScan {
    /// The search of an object's `triangles` (world-space corners, at
    /// most [`MAX_TRIANGLES`]), whose hits name them by `ids`.
    ///
    /// # Panics
    /// Beyond [`MAX_TRIANGLES`] triangles, or if `ids` is not one per
    /// triangle.
    pub fn new(triangles: &[[Vec3; 3]], ids: &[u32]) -> ClusterScan {
        assert!(triangles.len() <= MAX_TRIANGLES, "too many triangles");
        assert_eq!(triangles.len(), ids.len(), "one id per triangle");
        let centroids: Vec<Vec3> = triangles
            .iter()
            .map(|[a, b, c]| (*a + *b + *c) / 3.0)
            .collect();
        let boxes: Vec<[Vec3; 2]> = triangles
            .iter()
            .map(|t| bounds(t.iter().copied()))
            .collect();
        // A group's bounds: its triangles' bounds together.
        let corners = |ks: &[usize]| ks.iter().fold(EMPTY, |b, &k| union(b, boxes[k]));
        let mut scan = ClusterScan {
            tops: Vec::new(),
            first_cluster: Vec::new(),
            clusters: Vec::new(),
            first_chunk: Vec::new(),
            chunks: Vec::new(),
        };
        let mut groups = Vec::new();
        split(
            (0..triangles.len()).collect(),
            &centroids,
            &boxes,
            LANES * LANES * LANES,
            &mut groups,
        );
        for group in groups {
            let mut clusters = Vec::new();
            split(group, &centroids, &boxes, LANES * LANES, &mut clusters);
            scan.tops
                .push(Boxes::new(clusters.iter().map(|c| corners(c))));
            scan.first_cluster.push(scan.clusters.len());
            for cluster in clusters {
                let mut chunks = Vec::new();
                split(cluster, &centroids, &boxes, LANES, &mut chunks);
                scan.clusters
                    .push(Boxes::new(chunks.iter().map(|c| corners(c))));
                scan.first_chunk.push(scan.chunks.len());
                scan.chunks.extend(chunks.iter().map(|c| {
                    Chunk::new(c.iter().map(|&k| (triangles[k], Vec3::ZERO, false, ids[k])))
                }));
            }
        }
        scan
    }

    /// The closest hit of `ray` (from `o`, with 1 / direction `inv`) in
    /// (0, `tmax`): the triangle's id and the hit.
    ///
    /// # Safety
    /// The CPU must support `S`.
    #[inline(always)]
    pub unsafe fn closest<S: Simd16>(
        &self,
        ray: &WatertightRay,
        o: Vec3,
        inv: Vec3,
        tmax: f32,
    ) -> Option<(u32, TriangleHit)> {
        // SAFETY: `S`'s features (the caller's contract); the loads read
        // the boxes' and chunks' aligned 16-lane arrays, and clusters and
        // chunks are indexed by lanes of boxes in use.
        unsafe {
            let (o, inv) = (splat::<S>(o), splat::<S>(inv));
            let mut best: Option<(u32, TriangleHit)> = None;
            let mut best_t = tmax;
            // The groups of clusters (at most two), the nearer first.
            let mut groups = [(0u16, S::splat(0.0)); 2];
            for (r, top) in self.tops.iter().enumerate() {
                groups[r] = entered::<S>(top, &o, &inv, best_t);
            }
            let swap = self.tops.len() == 2
                && S::reduce_min(groups[1].0, groups[1].1)
                    < S::reduce_min(groups[0].0, groups[0].1);
            for r in 0..self.tops.len() {
                let r = if swap { 1 - r } else { r };
                let (mut clusters, enter) = groups[r];
                while let Some(j) = nearest::<S>(&mut clusters, enter, best_t) {
                    let c = self.first_cluster[r] + j;
                    let (mut chunks, enter) = entered::<S>(&self.clusters[c], &o, &inv, best_t);
                    while let Some(k) = nearest::<S>(&mut chunks, enter, best_t) {
                        let chunk = &self.chunks[self.first_chunk[c] + k];
                        if let Some(hit) = chunk_closest::<S>(chunk, ray, best_t) {
                            best_t = hit.1.t;
                            best = Some(hit);
                        }
                    }
                }
            }
            best
        }
    }

    /// Whether `ray` (from `o`, with 1 / direction `inv`) meets a triangle
    /// in (0, `tmax`): boxes in lane order, stopping at the first hit.
    ///
    /// # Safety
    /// The CPU must support `S`.
    #[inline(always)]
    pub unsafe fn occluded<S: Simd16>(
        &self,
        ray: &WatertightRay,
        o: Vec3,
        inv: Vec3,
        tmax: f32,
    ) -> bool {
        // SAFETY: as in `closest`.
        unsafe {
            let (o, inv) = (splat::<S>(o), splat::<S>(inv));
            let vtmax = S::splat(tmax);
            for (r, top) in self.tops.iter().enumerate() {
                let mut clusters = entered::<S>(top, &o, &inv, tmax).0;
                while clusters != 0 {
                    let c = self.first_cluster[r] + clusters.trailing_zeros() as usize;
                    clusters &= clusters - 1;
                    let mut chunks = entered::<S>(&self.clusters[c], &o, &inv, tmax).0;
                    while chunks != 0 {
                        let chunk =
                            &self.chunks[self.first_chunk[c] + chunks.trailing_zeros() as usize];
                        chunks &= chunks - 1;
                        let e = TriangleScan::edges::<S>(chunk, ray, tmax);
                        if S::bits(accepts::<S>(&e, vtmax)) != 0 {
                            return true;
                        }
                    }
                }
            }
            false
        }
    }
}

/// `v` in three 16-lane registers. (A function, not a closure, so that
/// its intrinsics are inlined into the caller compiled for `S`.)
///
/// # Safety
/// The CPU must support `S`.
#[inline(always)]
unsafe fn splat<S: Simd16>(v: Vec3) -> [S::V; 3] {
    // SAFETY: `S`'s features (the caller's contract).
    unsafe { [S::splat(v.x), S::splat(v.y), S::splat(v.z)] }
}

/// The boxes of `b` that the ray from `o` (1 / direction `inv`) may meet
/// in (0, `tmax`), by the slab test, and where it enters each (0 for a
/// box it starts in). Conservative: the boxes are padded far beyond the
/// test's rounding. (A NaN slab distance, 0 × ∞, comes only from a ray
/// parallel to a padded face that starts in its plane, which meets no
/// triangle inside; the box is then missed.)
///
/// # Safety
/// The CPU must support `S`.
#[inline(always)]
unsafe fn entered<S: Simd16>(b: &Boxes, o: &[S::V; 3], inv: &[S::V; 3], tmax: f32) -> (u16, S::V) {
    // SAFETY: `S`'s features (the caller's contract); aligned 16-lane
    // loads.
    unsafe {
        let mut enter = S::splat(0.0);
        let mut exit = S::splat(tmax);
        for a in 0..3 {
            let t0 = S::mul(S::sub(S::load(b.lo[a].as_ptr()), o[a]), inv[a]);
            let t1 = S::mul(S::sub(S::load(b.hi[a].as_ptr()), o[a]), inv[a]);
            enter = S::max(enter, S::min(t0, t1));
            exit = S::min(exit, S::max(t0, t1));
        }
        (b.used & S::bits(S::le(enter, exit)), enter)
    }
}

/// The lane of `left` with the nearest entry in `enter`, taken out of
/// `left`; `None` when none is left or the nearest begins beyond `t`
/// (as do all the others then). Of equal entries the lowest lane.
///
/// # Safety
/// The CPU must support `S`.
#[inline(always)]
unsafe fn nearest<S: Simd16>(left: &mut u16, enter: S::V, t: f32) -> Option<usize> {
    if *left == 0 {
        return None;
    }
    // SAFETY: `S`'s features (the caller's contract).
    unsafe {
        let lane = if *left & (*left - 1) == 0 {
            // One lane: its entry alone (no reduction).
            let lane = left.trailing_zeros();
            if S::lane(enter, lane) > t {
                return None;
            }
            lane
        } else {
            let near = S::reduce_min(*left, enter);
            if near > t {
                return None;
            }
            (*left & S::bits(S::eq(enter, S::splat(near)))).trailing_zeros()
        };
        *left &= !(1 << lane);
        Some(lane as usize)
    }
}

/// The closest hit of `ray` in (0, `tmax`) among `chunk`'s triangles, of
/// equal distances the lowest index: its id and the hit, with the scalar
/// test's operations (t = t_scaled · (1 / det), b = (v, w) / det).
///
/// # Safety
/// The CPU must support `S`.
#[inline(always)]
unsafe fn chunk_closest<S: Simd16>(
    chunk: &Chunk,
    ray: &WatertightRay,
    tmax: f32,
) -> Option<(u32, TriangleHit)> {
    // SAFETY: `S`'s features (the caller's contract); aligned 16-lane
    // loads.
    unsafe {
        let vtmax = S::splat(tmax);
        let e = TriangleScan::edges::<S>(chunk, ray, tmax);
        let ok = S::bits(accepts::<S>(&e, vtmax));
        if ok == 0 {
            return None;
        }
        if ok & (ok - 1) == 0 {
            // One lane (most chunks a ray hits): its values alone, in
            // the scalar test's order.
            let lane = ok.trailing_zeros();
            let inv = 1.0 / S::lane(e.det, lane);
            let t = S::lane(e.t_scaled, lane) * inv;
            if !(t > 0.0 && t < tmax) {
                return None;
            }
            let hit = TriangleHit {
                t,
                b1: S::lane(e.v, lane) * inv,
                b2: S::lane(e.w, lane) * inv,
            };
            return Some((chunk.index[lane as usize], hit));
        }
        let inv = S::recip(e.det);
        let t = S::mul(e.t_scaled, inv);
        let ok = ok & S::bits(S::and(S::gt(t, S::splat(0.0)), S::lt(t, vtmax)));
        if ok == 0 {
            return None;
        }
        let near = S::reduce_min(ok, t);
        let lanes = ok & S::bits(S::eq(t, S::splat(near)));
        let index = S::load_u32(chunk.index.as_ptr());
        let id = S::reduce_min_u32(lanes, index);
        let lane = (lanes & S::bits(S::eq_u32(index, S::splat_u32(id)))).trailing_zeros();
        let inv = S::lane(inv, lane);
        Some((
            id,
            TriangleHit {
                t: near,
                b1: S::lane(e.v, lane) * inv,
                b2: S::lane(e.w, lane) * inv,
            },
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::accel::lanes16::{Avx2, Avx512, test_avx512_too};
    use glam::Vec3A;
    use penumbra_shading::stats::TestRng;

    fn point(rng: &mut TestRng, scale: f32) -> Vec3 {
        Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * 2.0 * scale - scale
    }

    /// A closed latitude-longitude sphere of `2 n²` triangles about `c`,
    /// its corners shared between neighbours.
    fn sphere(c: Vec3, r: f32, n: usize) -> Vec<[Vec3; 3]> {
        let at = |i: usize, j: usize| {
            let (theta, phi) = (
                std::f32::consts::PI * i as f32 / n as f32,
                std::f32::consts::TAU * (j % n) as f32 / n as f32,
            );
            c + r * Vec3::new(
                theta.sin() * phi.cos(),
                theta.sin() * phi.sin(),
                theta.cos(),
            )
        };
        let mut t = Vec::new();
        for i in 0..n {
            for j in 0..n {
                t.push([at(i, j), at(i + 1, j), at(i + 1, j + 1)]);
                t.push([at(i, j), at(i + 1, j + 1), at(i, j + 1)]);
            }
        }
        t
    }

    /// The closest hit and occlusion of random rays, from outside, from
    /// inside and from the surface (some aimed at corners and edges,
    /// where the scalar test's f64 fallback decides), against the scalar
    /// watertight test of every triangle: the same distance and
    /// barycentrics to the bit, the same triangle but for exact ties. On a
    /// sphere of 1,800 triangles (eight clusters) and a soup of 6,000
    /// (two rounds of clusters' bounds).
    #[test]
    fn cluster_scan_matches_scalar_test_of_every_triangle() {
        cluster_scan_matches_scalar_test_with::<Avx2>();
        if test_avx512_too() {
            cluster_scan_matches_scalar_test_with::<Avx512>();
        }
    }

    fn cluster_scan_matches_scalar_test_with<S: Simd16>() {
        let mut rng = TestRng::new(5);
        let soup: Vec<[Vec3; 3]> = (0..6_000)
            .map(|_| {
                let a = point(&mut rng, 1.0);
                [a, a + point(&mut rng, 0.1), a + point(&mut rng, 0.1)]
            })
            .collect();
        for tris in [sphere(Vec3::new(0.3, -0.2, 0.1), 0.9, 30), soup] {
            let ids: Vec<u32> = (0..tris.len() as u32).map(|k| 7 * k + 3).collect();
            let scan = ClusterScan::new(&tris, &ids);
            assert_eq!(scan.tops.len(), tris.len().div_ceil(LANES * LANES * LANES));
            assert_eq!(scan.chunks.len(), tris.len().div_ceil(LANES));
            let mut hits = 0;
            for n in 0..4_000 {
                let (o, target) = match n % 4 {
                    0 => (point(&mut rng, 3.0), point(&mut rng, 1.0)),
                    1 => (point(&mut rng, 0.3), point(&mut rng, 3.0)),
                    // From a corner, or to one.
                    2 => (tris[n % tris.len()][0], point(&mut rng, 3.0)),
                    _ => {
                        let [a, b, _] = tris[n % tris.len()];
                        let on_edge = if n % 8 == 3 { a } else { a + (b - a) * 0.5 };
                        (point(&mut rng, 3.0), on_edge)
                    }
                };
                let d = (target - o).normalize();
                let tmax = if n % 5 == 0 { 1.0 } else { f32::INFINITY };
                let ray = WatertightRay::new(o, d);
                let mut expected: Option<(u32, TriangleHit)> = None;
                let mut equal = 0;
                for (k, t) in tris.iter().enumerate() {
                    let [a, b, c] = t.map(Vec3A::from);
                    if let Some(h) = ray.intersect_a(a, b, c, tmax) {
                        match expected {
                            Some((_, e)) if h.t == e.t => equal += 1,
                            Some((_, e)) if h.t > e.t => {}
                            _ => {
                                expected = Some((ids[k], h));
                                equal = 0;
                            }
                        }
                    }
                }
                // SAFETY: `S` checked by the caller.
                let got = unsafe { scan.closest::<S>(&ray, o, d.recip(), tmax) };
                match (expected, got) {
                    (None, None) => {}
                    (Some((k, e)), Some((j, g))) if equal > 0 => {
                        assert_eq!(e.t, g.t, "ray {n}: {j} for {k}");
                    }
                    (Some(e), Some(g)) => {
                        hits += 1;
                        assert_eq!(e, g, "ray {n}");
                    }
                    _ => panic!("ray {n}: {got:?} for {expected:?}"),
                }
                // SAFETY: `S` checked by the caller.
                let blocked = unsafe { scan.occluded::<S>(&ray, o, d.recip(), tmax) };
                assert_eq!(blocked, expected.is_some(), "ray {n}");
            }
            assert!(hits > 1_500, "{hits} hits");
        }
    }
}
