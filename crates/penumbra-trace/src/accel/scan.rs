//! Every triangle of a tiny scene tested against one ray, sixteen
//! triangles per AVX-512 instruction (or two AVX2 ones), without a tree: for scenes of at
//! most [`MAX_TRIANGLES`] triangles (a Cornell box has 32), where a tree
//! walk costs more in branches and setup than the tests it saves.
//!
//! The triangles are grouped by object into chunks of up to sixteen, each
//! with its padded bounds; a ray tests only the chunks whose bounds it
//! passes ([`TriangleScan::chunks_passed`], a slab test of sixteen rays
//! at once). Objects are merged into one chunk where that lowers the sum
//! of the chunks' surface areas (the surface area heuristic's proxy for
//! how many rays pass them): a Cornell box's ceiling with its light, but
//! not two walls, nor a wall and a block.
//!
//! Inside a scalar path loop such a scan is no faster than the tree walk,
//! which the next step waits for (measured on 2026-12-06); it pays where
//! many independent rays are in flight, as in the wavefront path tracer
//! (`integrator/wavefront.rs`), whose lanes' scans overlap.
//!
//! The test is the watertight one of `watertight.rs` (Woop et al. 2013)
//! with the same operations per triangle; lanes whose edge functions are
//! 0 take that module's scalar test with its f64 fallback. Of equal
//! distances the lowest triangle index wins.
//!
//! One of the crate's modules with `unsafe` code: its calls of the
//! sixteen-lane operations (`lanes16.rs`), which need the CPU's features.
#![allow(unsafe_code)]
// Lane loops index several structure-of-arrays fields by lane: the form
// that vectorises plainly.
#![allow(clippy::needless_range_loop)]

use super::collapse::area as half_area;
use super::lanes16::Simd16;
use super::watertight::{TriangleHit, WatertightRay};
use glam::{Vec3, Vec3A};
use obvhs::aabb::Aabb;

/// Triangles per chunk: one 16-lane register.
pub(super) const LANES: usize = 16;

/// The largest scene the scan takes.
pub const MAX_TRIANGLES: usize = 64;

pub(super) type Lanes = [f32; LANES];

/// Up to [`LANES`] triangles in structure-of-arrays form: corners
/// (`[corner][axis][lane]`), unit front normals (read only for the
/// triangles that cull back faces: zeros in a cluster scan's chunks,
/// which cull none), the triangles' indices in the scan's input (ids in
/// a cluster scan's), whether rays that cull back faces pass through
/// their back and which lanes hold a triangle (bit masks); 64-byte
/// aligned, so that each array is one aligned load. A lane without a
/// triangle has its three corners at the origin: its edge functions are
/// x·y − y·x = 0 (or NaN) for every ray, its determinant too, so
/// [`accepts`] never takes it.
#[derive(Clone, Copy, Debug)]
#[repr(C, align(64))]
pub(super) struct Chunk {
    corners: [[Lanes; 3]; 3],
    normal: [Lanes; 3],
    pub index: [u32; LANES],
    culls: u16,
    pub used: u16,
}

impl Chunk {
    /// A chunk of up to [`LANES`] triangles, each with its unit front
    /// normal, whether it culls back faces and the index hits name it by.
    pub(super) fn new(triangles: impl Iterator<Item = ([Vec3; 3], Vec3, bool, u32)>) -> Chunk {
        let mut chunk = Chunk {
            corners: [[[0.0; LANES]; 3]; 3],
            normal: [[0.0; LANES]; 3],
            index: [0; LANES],
            culls: 0,
            used: 0,
        };
        for (lane, (t, n, culls, index)) in triangles.enumerate() {
            assert!(lane < LANES, "a chunk holds {LANES} triangles");
            for (c, p) in t.iter().enumerate() {
                for a in 0..3 {
                    chunk.corners[c][a][lane] = p[a];
                }
            }
            for a in 0..3 {
                chunk.normal[a][lane] = n[a];
            }
            chunk.index[lane] = index;
            chunk.culls |= u16::from(culls) << lane;
            chunk.used |= 1 << lane;
        }
        chunk
    }
}

/// The most chunks: one bit each in a ray's mask.
const MAX_CHUNKS: usize = 16;

/// The scene's triangles in chunks, with each chunk's padded bounds.
#[derive(Clone, Debug)]
pub struct TriangleScan {
    chunks: Vec<Chunk>,
    bounds: Vec<[[f32; 3]; 2]>,
}

/// The watertight test's quantities of a chunk's triangles for one ray,
/// one lane a triangle.
pub(super) struct Edges<S: Simd16> {
    pub u: S::V,
    pub v: S::V,
    pub w: S::V,
    pub t_scaled: S::V,
    pub det: S::V,
}

impl TriangleScan {
    /// The scan of `triangles` (world-space corners), with their unit front
    /// normals, whether each culls back faces and the object each belongs
    /// to; `None` beyond [`MAX_TRIANGLES`]. Hits name triangles by their
    /// place in `triangles`.
    pub fn new(
        triangles: &[[Vec3; 3]],
        normals: &[Vec3],
        culls: &[bool],
        objects: &[u32],
    ) -> Option<Self> {
        if triangles.len() > MAX_TRIANGLES {
            return None;
        }
        let groups = chunk_groups(triangles, objects);
        let mut chunks = Vec::with_capacity(groups.len());
        let mut bounds = Vec::with_capacity(groups.len());
        for group in groups {
            let chunk = Chunk::new(
                group
                    .iter()
                    .map(|&k| (triangles[k], normals[k], culls[k], k as u32)),
            );
            chunks.push(chunk);
            let ([lo, hi], _) = padded(group.iter().flat_map(|&k| triangles[k]));
            bounds.push([lo.to_array(), hi.to_array()]);
        }
        Some(TriangleScan { chunks, bounds })
    }

    /// For each lane's ray `o + t d` in (0, `tmax`), with `inv` = 1 / d
    /// (see [`reciprocals`]), the chunks whose bounds it may pass (bit `c`
    /// for chunk `c`).
    #[inline(always)]
    pub fn chunks_passed(&self, o: &[Lanes; 3], inv: &[Lanes; 3], tmax: &Lanes) -> [u16; LANES] {
        let mut masks = [0u16; LANES];
        for (c, b) in self.bounds.iter().enumerate() {
            let pass = slabs(o, inv, tmax, b);
            for i in 0..LANES {
                masks[i] |= u16::from(pass[i]) << c;
            }
        }
        masks
    }

    /// Chunk `c` (a bit of a mask from [`Self::chunks_passed`]).
    #[inline(always)]
    fn chunk(&self, c: usize) -> &Chunk {
        &self.chunks[c]
    }

    /// Triangle `lane` of `chunk`.
    fn triangle(chunk: &Chunk, lane: usize) -> [Vec3A; 3] {
        [0, 1, 2].map(|c| {
            Vec3A::new(
                chunk.corners[c][0][lane],
                chunk.corners[c][1][lane],
                chunk.corners[c][2][lane],
            )
        })
    }

    /// The edge functions and scaled distances of a chunk's triangles for
    /// `ray`, with the f64 fallback's lanes done by the scalar test: the
    /// operations of `WatertightRay::intersect_a`, in its order (no fused
    /// multiply-adds, so the same roundings), sixteen lanes at once.
    ///
    /// # Safety
    /// The CPU must support `S`.
    #[inline(always)]
    pub(super) unsafe fn edges<S: Simd16>(
        chunk: &Chunk,
        ray: &WatertightRay,
        tmax: f32,
    ) -> Edges<S> {
        let [kx, ky, kz] = ray.permutation();
        let [ox, oy, oz] = ray.origin_permuted();
        let [sx, sy, sz] = ray.shear();
        // SAFETY: `S`'s features (the caller's contract); every load
        // reads one aligned 16-lane array of the chunk.
        unsafe {
            let o = [S::splat(ox), S::splat(oy), S::splat(oz)];
            let s = [S::splat(sx), S::splat(sy), S::splat(sz)];
            let [kx, ky, kz] =
                [kx, ky, kz].map(|a| [0, 1, 2].map(|c| chunk.corners[c][a].as_ptr()));
            let (ax, ay, az) = sheared::<S>(kx[0], ky[0], kz[0], o, s);
            let (bx, by, bz) = sheared::<S>(kx[1], ky[1], kz[1], o, s);
            let (cx, cy, cz) = sheared::<S>(kx[2], ky[2], kz[2], o, s);
            let u = S::sub(S::mul(cx, by), S::mul(cy, bx));
            let v = S::sub(S::mul(ax, cy), S::mul(ay, cx));
            let w = S::sub(S::mul(bx, ay), S::mul(by, ax));
            let t_scaled = S::add(S::add(S::mul(u, az), S::mul(v, bz)), S::mul(w, cz));
            let det = S::add(S::add(u, v), w);
            let e = Edges {
                u,
                v,
                w,
                t_scaled,
                det,
            };
            let z = S::splat(0.0);
            let zero =
                S::bits(S::or(S::or(S::eq(e.u, z), S::eq(e.v, z)), S::eq(e.w, z))) & chunk.used;
            if zero == 0 {
                e
            } else {
                Self::edges_by_scalar_test(chunk, ray, tmax, e, zero)
            }
        }
    }

    /// `e` with the lanes of `zero` (edge functions with a 0) decided by
    /// the scalar test: a hit as edge functions (1, b1, b2) with det 1 (so
    /// t_scaled = t), a miss as det 0.
    ///
    /// # Safety
    /// The CPU must support `S`.
    #[cold]
    #[inline(never)]
    unsafe fn edges_by_scalar_test<S: Simd16>(
        chunk: &Chunk,
        ray: &WatertightRay,
        tmax: f32,
        e: Edges<S>,
        zero: u16,
    ) -> Edges<S> {
        #[repr(C, align(64))]
        struct Aligned([Lanes; 5]);
        let mut lanes = Aligned([[0.0f32; LANES]; 5]);
        for (out, x) in lanes.0.iter_mut().zip([e.u, e.v, e.w, e.t_scaled, e.det]) {
            for (l, y) in out.iter_mut().enumerate() {
                // SAFETY: `S`'s features (the caller's contract).
                *y = unsafe { S::lane(x, l as u32) };
            }
        }
        for l in (0..LANES).filter(|&l| zero & (1 << l) != 0) {
            let [a, b, c] = Self::triangle(chunk, l);
            let decided = match ray.intersect_a(a, b, c, tmax) {
                Some(h) => [1.0, h.b1, h.b2, h.t, 1.0],
                None => [0.0; 5],
            };
            for (out, x) in lanes.0.iter_mut().zip(decided) {
                out[l] = x;
            }
        }
        // SAFETY: as above; aligned 16-lane arrays.
        unsafe {
            let [u, v, w, t_scaled, det] = &lanes.0;
            Edges {
                u: S::load(u.as_ptr()),
                v: S::load(v.as_ptr()),
                w: S::load(w.as_ptr()),
                t_scaled: S::load(t_scaled.as_ptr()),
                det: S::load(det.as_ptr()),
            }
        }
    }

    /// The closest hit of `ray` (direction `d`) in (0, `tmax`) among the
    /// triangles of the chunks of `chunks` (bits, as from
    /// [`Self::chunks_passed`]): triangle index and hit, of equal
    /// distances the lowest index. With `camera`, the back faces of
    /// triangles that cull them are passed through (glTF single-sided
    /// materials seen by a camera ray).
    ///
    /// # Safety
    /// The CPU must support `S`.
    #[inline(always)]
    pub unsafe fn closest<S: Simd16>(
        &self,
        ray: &WatertightRay,
        d: Vec3,
        tmax: f32,
        camera: bool,
        chunks: u16,
    ) -> Option<(u32, TriangleHit)> {
        // SAFETY: `S`'s features (the caller's contract); the loads read
        // the chunks' aligned 16-lane arrays.
        unsafe {
            // Per lane, the nearest hit among that lane's triangles of all
            // chunks: no distance is carried from chunk to chunk, so their
            // tests overlap; one reduction at the end.
            let mut near = S::splat(f32::INFINITY);
            let mut near_index = S::splat_u32(0);
            let mut near_v = S::splat(0.0);
            let mut near_w = S::splat(0.0);
            let mut near_det = S::splat(1.0);
            let (dx, dy, dz) = (S::splat(d.x), S::splat(d.y), S::splat(d.z));
            let vtmax = S::splat(tmax);
            // The lanes that hold a hit.
            let mut hit_lanes = 0u16;
            let mut todo = chunks;
            while todo != 0 {
                let chunk = self.chunk(todo.trailing_zeros() as usize);
                todo &= todo - 1;
                let e = Self::edges::<S>(chunk, ray, tmax);
                // 1/det within about an ulp: it only ranks the hits (the
                // chosen one's barycentrics are divided exactly below).
                let inv = S::recip_fast(e.det);
                let mut ok = accepts::<S>(&e, vtmax);
                if camera {
                    let [nx, ny, nz] = &chunk.normal;
                    let facing = S::add(
                        S::add(
                            S::mul(S::load(nx.as_ptr()), dx),
                            S::mul(S::load(ny.as_ptr()), dy),
                        ),
                        S::mul(S::load(nz.as_ptr()), dz),
                    );
                    let culled = S::and(S::mask(chunk.culls), S::gt(facing, S::splat(0.0)));
                    ok = S::and_not(culled, ok);
                }
                let t = S::mul(e.t_scaled, inv);
                let closer = S::and(ok, S::lt(t, near));
                hit_lanes |= S::bits(closer);
                near = S::blend(closer, near, t);
                near_index = S::blend_u32(closer, near_index, S::load_u32(chunk.index.as_ptr()));
                near_v = S::blend(closer, near_v, e.v);
                near_w = S::blend(closer, near_w, e.w);
                near_det = S::blend(closer, near_det, e.det);
            }
            if hit_lanes == 0 {
                return None;
            }
            let (t, k, lane) = if hit_lanes & (hit_lanes - 1) == 0 {
                // One lane with hits (most rays): its nearest, without
                // the reductions.
                let lane = hit_lanes.trailing_zeros();
                (S::lane(near, lane), S::lane_u32(near_index, lane), lane)
            } else {
                let t = S::reduce_min(hit_lanes, near);
                // Of equal distances, the lowest triangle index.
                let lanes = hit_lanes & S::bits(S::eq(near, S::splat(t)));
                let k = S::reduce_min_u32(lanes, near_index);
                let winner = lanes & S::bits(S::eq_u32(near_index, S::splat_u32(k)));
                (t, k, winner.trailing_zeros())
            };
            if t.is_nan() || t >= tmax {
                return None;
            }
            let inv = 1.0 / S::lane(near_det, lane);
            Some((
                k,
                TriangleHit {
                    t,
                    b1: S::lane(near_v, lane) * inv,
                    b2: S::lane(near_w, lane) * inv,
                },
            ))
        }
    }

    /// Whether `ray` meets a triangle of the chunks of `chunks` in (0,
    /// `tmax`) (back faces included): chunk by chunk, stopping at the
    /// first that holds one.
    ///
    /// # Safety
    /// The CPU must support `S`.
    #[inline(always)]
    pub unsafe fn occluded<S: Simd16>(&self, ray: &WatertightRay, tmax: f32, chunks: u16) -> bool {
        // SAFETY: `S`'s features (the caller's contract).
        unsafe {
            let vtmax = S::splat(tmax);
            let mut todo = chunks;
            while todo != 0 {
                let chunk = self.chunk(todo.trailing_zeros() as usize);
                todo &= todo - 1;
                if S::bits(accepts::<S>(&Self::edges::<S>(chunk, ray, tmax), vtmax)) != 0 {
                    return true;
                }
            }
            false
        }
    }
}

/// The padding of a box around scene geometry: a thousandth of its
/// extent and of its coordinates, far beyond the rounding of the slab
/// test and of a watertight hit's distance.
fn padding([lo, hi]: [Vec3; 2]) -> f32 {
    1e-3 * ((hi - lo).max_element() + lo.abs().max(hi.abs()).max_element())
}

/// The bounds of `points`.
pub(super) fn bounds(points: impl Iterator<Item = Vec3>) -> [Vec3; 2] {
    points.fold([Vec3::INFINITY, Vec3::NEG_INFINITY], |[lo, hi], p| {
        [lo.min(p), hi.max(p)]
    })
}

/// The bounds of `points` padded by [`padding`], and the padding.
pub fn padded(points: impl Iterator<Item = Vec3>) -> ([Vec3; 2], f32) {
    let [lo, hi] = bounds(points);
    let pad = padding([lo, hi]);
    ([lo - pad, hi + pad], pad)
}

/// The triangles of each chunk (indices into `triangles`). The large
/// objects (a box diagonal at least half the whole's: a room's walls,
/// whose bounds rays from inside pass anyway) share chunks; each small
/// object has its own, in runs of [`LANES`]. Then the pair of groups that
/// fit one chunk and whose merged padded bounds save the most surface
/// area are merged, while that saves any (a light into its room), or
/// while there are more than [`MAX_CHUNKS`] groups.
fn chunk_groups(triangles: &[[Vec3; 3]], objects: &[u32]) -> Vec<Vec<usize>> {
    let mut by_object = std::collections::BTreeMap::<u32, Vec<usize>>::new();
    for (k, &o) in objects.iter().enumerate() {
        by_object.entry(o).or_default().push(k);
    }
    let diagonal = |[lo, hi]: [Vec3; 2]| (hi - lo).length();
    let whole = diagonal(bounds(triangles.iter().flatten().copied()));
    let (mut large, mut groups) = (Vec::new(), Vec::<Vec<usize>>::new());
    for ks in by_object.values() {
        let size = diagonal(bounds(ks.iter().flat_map(|&k| triangles[k])));
        if size >= 0.5 * whole {
            large.extend(ks);
        } else {
            groups.extend(ks.chunks(LANES).map(<[usize]>::to_vec));
        }
    }
    large.sort_unstable();
    groups.extend(large.chunks(LANES).map(<[usize]>::to_vec));
    let area = |g: &[usize]| {
        let ([lo, hi], _) = padded(g.iter().flat_map(|&k| triangles[k]));
        half_area(&Aabb::new(lo.into(), hi.into()))
    };
    loop {
        let mut best: Option<(f64, usize, usize)> = None;
        for a in 0..groups.len() {
            for b in a + 1..groups.len() {
                if groups[a].len() + groups[b].len() > LANES {
                    continue;
                }
                let merged: Vec<usize> = groups[a].iter().chain(&groups[b]).copied().collect();
                let saving = area(&groups[a]) + area(&groups[b]) - area(&merged);
                if best.is_none_or(|(s, _, _)| saving > s) {
                    best = Some((saving, a, b));
                }
            }
        }
        match best {
            Some((saving, a, b)) if saving > 0.0 || groups.len() > MAX_CHUNKS => {
                let merged = groups.swap_remove(b);
                groups[a].extend(merged);
                groups[a].sort_unstable();
            }
            // (More than MAX_CHUNKS groups of at most 64 triangles always
            // hold two that fit one chunk.)
            _ => break,
        }
    }
    assert!(groups.len() <= MAX_CHUNKS, "a ray's chunk mask has 16 bits");
    groups
}

/// 1 / d of each lane's direction `d`, for [`slabs`] (computed once for
/// the boxes a set of rays is tested against).
#[inline(always)]
pub fn reciprocals(d: &[Lanes; 3]) -> [Lanes; 3] {
    d.map(|a| a.map(|x| 1.0 / x))
}

/// The lanes whose ray `o + t d` may meet the box `[lo, hi]` in (0,
/// `tmax`), by the slab test with `inv` = 1 / d ([`reciprocals`]);
/// conservative where the box is padded by [`padded`], far beyond the
/// test's rounding. (A NaN slab distance, 0 ×
/// ∞, comes only from a ray parallel to a padded face that starts in its
/// plane, outside every triangle; `min` and `max` pass over it.)
#[inline(always)]
pub fn slabs(
    o: &[Lanes; 3],
    inv: &[Lanes; 3],
    tmax: &Lanes,
    [lo, hi]: &[[f32; 3]; 2],
) -> [bool; LANES] {
    let mut maybe = [false; LANES];
    for i in 0..LANES {
        let mut enter = 0.0f32;
        let mut exit = tmax[i];
        for a in 0..3 {
            let t0 = (lo[a] - o[a][i]) * inv[a][i];
            let t1 = (hi[a] - o[a][i]) * inv[a][i];
            enter = enter.max(t0.min(t1));
            exit = exit.min(t0.max(t1));
        }
        maybe[i] = enter <= exit;
    }
    maybe
}

/// A corner of sixteen triangles (its coordinates on the permuted axes
/// kx, ky, kz) relative to the ray origin `o` and sheared by `s`, as
/// `WatertightRay::intersect_a`: (x - sx z, y - sy z, sz z).
///
/// # Safety
/// The CPU must support `S`, and each pointer must point at 16 f32
/// aligned to 64 bytes. (A function, not a closure, so that it is inlined
/// into the caller compiled for `S` before its intrinsics are.)
#[inline(always)]
unsafe fn sheared<S: Simd16>(
    x: *const f32,
    y: *const f32,
    z: *const f32,
    o: [S::V; 3],
    s: [S::V; 3],
) -> (S::V, S::V, S::V) {
    // SAFETY: the caller's contract.
    unsafe {
        let z = S::sub(S::load(z), o[2]);
        let x = S::sub(S::sub(S::load(x), o[0]), S::mul(s[0], z));
        let y = S::sub(S::sub(S::load(y), o[1]), S::mul(s[1], z));
        (x, y, S::mul(s[2], z))
    }
}

/// The lanes whose edge functions, scaled distance and determinant make a
/// hit in (0, tmax): one sign for u, v, w, and t = t_scaled / det
/// compared without dividing, as `WatertightRay::intersect_a` does (it
/// then also checks t < tmax after its division). A mask, not lane bits:
/// the closest-hit scan blends with it (on AVX2 lane bits cost a
/// `movemask` per register, and a mask made again from them six more
/// instructions).
///
/// # Safety
/// The CPU must support `S`.
#[inline(always)]
pub(super) unsafe fn accepts<S: Simd16>(e: &Edges<S>, tmax: S::V) -> S::M {
    // SAFETY: `S`'s features (the caller's contract).
    unsafe {
        let z = S::splat(0.0);
        // (Written out: intrinsics in closures would not be inlined.)
        let negative = S::or(S::or(S::lt(e.u, z), S::lt(e.v, z)), S::lt(e.w, z));
        let positive = S::or(S::or(S::gt(e.u, z), S::gt(e.v, z)), S::gt(e.w, z));
        let bound = S::mul(tmax, e.det);
        let ahead = S::and(
            S::and(S::gt(e.det, z), S::gt(e.t_scaled, z)),
            S::lt(e.t_scaled, bound),
        );
        let behind = S::and(
            S::and(S::lt(e.det, z), S::lt(e.t_scaled, z)),
            S::gt(e.t_scaled, bound),
        );
        S::and_not(S::and(negative, positive), S::or(ahead, behind))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::accel::lanes16::{Avx2, Avx512, test_avx512_too};
    use penumbra_shading::stats::TestRng;

    fn point(rng: &mut TestRng, scale: f32) -> Vec3 {
        Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * 2.0 * scale - scale
    }

    /// A soup of 40 triangles (several chunks, some partly used), some
    /// sharing an edge so that rays through it meet the f64 fallback's
    /// lanes, with their front normals, a culling flag on every third and
    /// their objects: six compact clusters of five, and ten scattered
    /// over the whole (a large object).
    fn soup(rng: &mut TestRng) -> (Vec<[Vec3; 3]>, Vec<Vec3>, Vec<bool>, Vec<u32>) {
        let mut tris = Vec::new();
        let mut centre = Vec3::ZERO;
        for k in 0..40 {
            let compact = k < 30;
            if k % 5 == 0 {
                centre = point(rng, 0.8);
            }
            let (a, size) = if compact {
                (centre + point(rng, 0.2), 0.2)
            } else {
                (point(rng, 1.0), 0.6)
            };
            let t = if k % 5 == 4 {
                // Shares the previous triangle's edge (b, c).
                let [_, b, c] = tris[k - 1];
                [c, b, b + point(rng, size)]
            } else {
                [a, a + point(rng, size), a + point(rng, size)]
            };
            tris.push(t);
        }
        let normals = tris
            .iter()
            .map(|[a, b, c]| (*b - *a).cross(*c - *a).normalize())
            .collect();
        let culls = (0..tris.len()).map(|k| k % 3 == 0).collect();
        let objects = (0..tris.len() as u32).map(|k| (k / 5).min(6)).collect();
        (tris, normals, culls, objects)
    }

    /// The closest hit and occlusion of random rays (some aimed at shared
    /// edges and corners) against the scalar watertight test of every
    /// triangle, the reference: the same triangle (of equal distances the
    /// lowest index), the same distance within an ulp or two (the scan
    /// ranks by a reciprocal estimate), the same barycentrics; camera
    /// rays pass the back faces of culling triangles.
    #[test]
    fn scan_matches_scalar_test_of_every_triangle() {
        scan_matches_scalar_test_with::<Avx2>();
        if test_avx512_too() {
            scan_matches_scalar_test_with::<Avx512>();
        }
    }

    fn scan_matches_scalar_test_with<S: Simd16>() {
        let mut rng = TestRng::new(11);
        let (tris, normals, culls, objects) = soup(&mut rng);
        let scan = TriangleScan::new(&tris, &normals, &culls, &objects).unwrap();
        let mut skipped = 0;
        let (mut hits, mut edge_rays) = (0, 0);
        for n in 0..20_000 {
            let o = point(&mut rng, 2.5);
            let target = if n % 4 == 0 {
                // A point of a shared edge or a corner.
                let [_, b, c] = tris[5 * (n / 4 % 8) + 4];
                edge_rays += 1;
                if n % 8 == 0 {
                    b
                } else {
                    b + (c - b) * rng.next_f32()
                }
            } else {
                point(&mut rng, 1.0)
            };
            let d = (target - o).normalize();
            let tmax = if n % 3 == 0 { 2.0 } else { f32::INFINITY };
            let camera = n % 2 == 0;
            let ray = WatertightRay::new(o, d);
            let mut expected: Option<(u32, TriangleHit)> = None;
            for (k, t) in tris.iter().enumerate() {
                let [a, b, c] = t.map(Vec3A::from);
                if camera && culls[k] && normals[k].dot(d) > 0.0 {
                    continue;
                }
                if let Some(h) = ray.intersect_a(a, b, c, tmax)
                    && expected.is_none_or(|(_, e)| h.t < e.t)
                {
                    expected = Some((k as u32, h));
                }
            }
            // SAFETY: `S` checked by the caller.
            let lanes = |v: Vec3| [[v.x; LANES], [v.y; LANES], [v.z; LANES]];
            let chunks = scan.chunks_passed(&lanes(o), &lanes(d.recip()), &[tmax; LANES])[0];
            skipped += usize::from(chunks.count_ones() < scan.chunks.len() as u32);
            let got = unsafe { scan.closest::<S>(&ray, d, tmax, camera, chunks) };
            match (expected, got) {
                (None, None) => {}
                (Some((k, e)), Some((j, g))) => {
                    hits += 1;
                    let close = |x: f32, y: f32| {
                        (x - y).abs() <= 4.0 * f32::EPSILON * x.abs().max(y.abs()).max(1e-3)
                    };
                    if j != k {
                        // Only a tie within the ranking's error may differ:
                        // triangle j is hit there too.
                        let [a, b, c] = tris[j as usize].map(Vec3A::from);
                        let own = ray.intersect_a(a, b, c, tmax).map(|h| h.t);
                        assert!(
                            close(e.t, g.t) && own.is_some_and(|t| close(t, g.t)),
                            "ray {n}: triangle {j} at {} ({own:?}) for {k} at {}",
                            g.t,
                            e.t
                        );
                        continue;
                    }
                    assert!(close(e.t, g.t), "ray {n}: t {} for {}", g.t, e.t);
                    assert!(
                        close(e.b1, g.b1) && close(e.b2, g.b2),
                        "ray {n}: {g:?} for {e:?}"
                    );
                }
                _ => panic!("ray {n}: {got:?} for {expected:?}"),
            }
            let blocked = tris.iter().any(|t| {
                let [a, b, c] = t.map(Vec3A::from);
                ray.intersect_a(a, b, c, tmax).is_some()
            });
            // SAFETY: `S` checked by the caller.
            assert_eq!(
                unsafe { scan.occluded::<S>(&ray, tmax, chunks) },
                blocked,
                "ray {n}"
            );
        }
        assert!(hits > 4_000 && edge_rays == 5_000, "{hits} hits");
        // The chunks' bounds kept many rays out of some.
        assert!(
            scan.chunks.len() >= 4 && skipped > 10_000,
            "{skipped} rays skipped chunks"
        );
    }

    /// Beyond [`MAX_TRIANGLES`] the scan is refused.
    #[test]
    fn refuses_large_scenes() {
        let t = [[Vec3::ZERO, Vec3::X, Vec3::Y]; MAX_TRIANGLES + 1];
        let n = [Vec3::Z; MAX_TRIANGLES + 1];
        let c = [false; MAX_TRIANGLES + 1];
        let o: Vec<u32> = (0..=MAX_TRIANGLES as u32).collect();
        assert!(TriangleScan::new(&t, &n, &c, &o).is_none());
        let m = MAX_TRIANGLES;
        let scan = TriangleScan::new(&t[..m], &n[..m], &c[..m], &o[..m]).unwrap();
        // Sixty-four one-triangle objects at one place: merged to the
        // fewest chunks.
        assert_eq!(scan.chunks.len(), MAX_TRIANGLES / LANES);
    }

    /// A Cornell box's objects: the five walls share a chunk with the
    /// light (inside their bounds), and each block has its own.
    #[test]
    fn a_room_shares_a_chunk_and_its_blocks_have_their_own() {
        let quad = |a: Vec3, b: Vec3, c: Vec3| [[a, b, c], [a, c, b + c - a]];
        let s = 550.0;
        let walls = [
            quad(Vec3::ZERO, Vec3::X * s, Vec3::Z * s),
            quad(
                Vec3::Y * s,
                Vec3::X * s + Vec3::Y * s,
                Vec3::Z * s + Vec3::Y * s,
            ),
            quad(
                Vec3::Z * s,
                Vec3::X * s + Vec3::Z * s,
                Vec3::Y * s + Vec3::Z * s,
            ),
            quad(Vec3::ZERO, Vec3::Y * s, Vec3::Z * s),
            quad(
                Vec3::X * s,
                Vec3::X * s + Vec3::Y * s,
                Vec3::X * s + Vec3::Z * s,
            ),
        ];
        let light = quad(
            Vec3::new(200.0, 549.0, 200.0),
            Vec3::new(330.0, 549.0, 200.0),
            Vec3::new(200.0, 549.0, 330.0),
        );
        // A block of five faces (ten triangles) at `o`, of size `e`.
        let block = |o: Vec3, e: f32| {
            let (x, y, z) = (Vec3::X * e, Vec3::Y * e, Vec3::Z * e);
            [
                quad(o + y, o + y + x, o + y + z),
                quad(o, o + x, o + y),
                quad(o + z, o + z + x, o + z + y),
                quad(o, o + z, o + y),
                quad(o + x, o + x + z, o + x + y),
            ]
        };
        let mut tris = Vec::new();
        let mut objects = Vec::new();
        let mut add = |quads: &[[[Vec3; 3]; 2]], object: u32| {
            for q in quads {
                tris.extend(q);
                objects.extend([object; 2]);
            }
        };
        add(&block(Vec3::new(80.0, 0.0, 60.0), 160.0), 0);
        for (k, w) in walls.iter().enumerate() {
            add(std::slice::from_ref(w), 1 + k as u32);
        }
        add(&[light], 6);
        add(&block(Vec3::new(300.0, 0.0, 250.0), 200.0), 7);
        let groups = chunk_groups(&tris, &objects);
        let mut sizes: Vec<_> = groups.iter().map(Vec::len).collect();
        sizes.sort_unstable();
        assert_eq!(sizes, [10, 10, 12], "{groups:?}");
        // The blocks' triangles: 0..10 and 22..32.
        let first_block: Vec<usize> = (0..10).collect();
        let second_block: Vec<usize> = (22..32).collect();
        assert!(groups.contains(&first_block) && groups.contains(&second_block));
    }
}
