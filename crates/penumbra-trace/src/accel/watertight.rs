//! Watertight ray–triangle intersection.
//!
//! Woop, Benthin & Wald 2013, "Watertight Ray/Triangle Intersection" (JCGT
//! 2(1)): translate the vertices to the ray origin, permute so the dominant
//! direction axis is z, shear so the ray is +z, and evaluate the 2-D edge
//! functions U, V, W. A hit needs U, V, W of one sign; edges shared by two
//! triangles give exactly opposite values, so a ray through an edge or vertex
//! hits at least one of them. Zero edge functions fall back to f64.

use glam::{Vec3, Vec3A};

/// Per-ray precomputation: the axes (kx, ky, kz), kz the direction's
/// dominant one (kx, ky swapped for a negative d_kz, keeping the winding),
/// and the shear (sx, sy, sz) = (d_kx / d_kz, d_ky / d_kz, 1 / d_kz): the
/// sheared vertex is `(a_kx − sx·a_kz, a_ky − sy·a_kz, sz·a_kz)` with
/// `a = p − o`, so the same vertex gives the same values in every
/// triangle that shares it.
#[derive(Clone, Copy, Debug)]
pub struct WatertightRay {
    /// The origin's coordinates in the order (kx, ky, kz).
    origin_k: [f32; 3],
    k: [usize; 3],
    s: [f32; 3],
}

/// A hit: distance and barycentrics (b1 for v1, b2 for v2).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TriangleHit {
    pub t: f32,
    pub b1: f32,
    pub b2: f32,
}

/// The axis after each: (kz + 1, kz + 2) mod 3 without a division.
const NEXT_AXIS: [usize; 3] = [1, 2, 0];

impl WatertightRay {
    pub fn new(origin: Vec3, dir: Vec3) -> Self {
        let a = dir.abs();
        let kz = if a.x > a.y {
            if a.x > a.z { 0 } else { 2 }
        } else if a.y > a.z {
            1
        } else {
            2
        };
        let d = dir.to_array();
        let (kx, ky) = (NEXT_AXIS[kz], NEXT_AXIS[NEXT_AXIS[kz]]);
        let (kx, ky) = if d[kz] < 0.0 { (ky, kx) } else { (kx, ky) };
        let sz = 1.0 / d[kz];
        let o = origin.to_array();
        Self {
            origin_k: [o[kx], o[ky], o[kz]],
            k: [kx, ky, kz],
            s: [d[kx] * sz, d[ky] * sz, sz],
        }
    }

    /// The origin's coordinates along the axes (kx, ky, kz).
    #[inline(always)]
    pub(super) fn origin_permuted(&self) -> [f32; 3] {
        self.origin_k
    }

    /// The axes (kx, ky, kz): kz the direction's dominant one.
    #[inline(always)]
    pub(super) fn permutation(&self) -> [usize; 3] {
        self.k
    }

    /// The shear (sx, sy, sz) = (d_kx / d_kz, d_ky / d_kz, 1 / d_kz).
    #[inline(always)]
    pub(super) fn shear(&self) -> [f32; 3] {
        self.s
    }

    /// Intersects triangle (p0, p1, p2) within (0, tmax).
    #[inline]
    pub fn intersect(&self, p0: Vec3, p1: Vec3, p2: Vec3, tmax: f32) -> Option<TriangleHit> {
        self.intersect_a(p0.into(), p1.into(), p2.into(), tmax)
    }

    /// [`WatertightRay::intersect`] on SIMD-aligned vertices.
    #[inline(always)]
    pub fn intersect_a(&self, p0: Vec3A, p1: Vec3A, p2: Vec3A, tmax: f32) -> Option<TriangleHit> {
        let [kx, ky, kz] = self.k;
        let [sx, sy, sz] = self.s;
        let [okx, oky, okz] = self.origin_k;
        let sheared = |p: Vec3A| {
            let p = p.to_array();
            let (ax, ay, az) = (p[kx] - okx, p[ky] - oky, p[kz] - okz);
            (ax - sx * az, ay - sy * az, sz * az)
        };
        let (ax, ay, az) = sheared(p0);
        let (bx, by, bz) = sheared(p1);
        let (cx, cy, cz) = sheared(p2);
        let mut u = cx * by - cy * bx;
        let mut v = ax * cy - ay * cx;
        let mut w = bx * ay - by * ax;
        if u == 0.0 || v == 0.0 || w == 0.0 {
            u = (cx as f64 * by as f64 - cy as f64 * bx as f64) as f32;
            v = (ax as f64 * cy as f64 - ay as f64 * cx as f64) as f32;
            w = (bx as f64 * ay as f64 - by as f64 * ax as f64) as f32;
        }
        if (u < 0.0 || v < 0.0 || w < 0.0) && (u > 0.0 || v > 0.0 || w > 0.0) {
            return None;
        }
        let det = u + v + w;
        if det == 0.0 {
            return None;
        }
        let t_scaled = u * az + v * bz + w * cz;
        // t = t_scaled / det must lie in (0, tmax); compare without dividing
        // by the sign of det.
        if det < 0.0 && (t_scaled >= 0.0 || t_scaled < tmax * det) {
            return None;
        }
        if det > 0.0 && (t_scaled <= 0.0 || t_scaled > tmax * det) {
            return None;
        }
        let inv = 1.0 / det;
        let t = t_scaled * inv;
        if !(t > 0.0 && t < tmax) {
            return None;
        }
        Some(TriangleHit {
            t,
            b1: v * inv,
            b2: w * inv,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hits_centre_with_barycentrics() {
        let r = WatertightRay::new(Vec3::new(0.25, 0.25, 1.0), -Vec3::Z);
        let h = r
            .intersect(Vec3::ZERO, Vec3::X, Vec3::Y, f32::INFINITY)
            .unwrap();
        assert!((h.t - 1.0).abs() < 1e-6);
        assert!((h.b1 - 0.25).abs() < 1e-6 && (h.b2 - 0.25).abs() < 1e-6);
        // Behind the origin, or beyond tmax: no hit.
        assert!(
            r.intersect(
                Vec3::new(0.0, 0.0, 2.0),
                Vec3::new(1.0, 0.0, 2.0),
                Vec3::new(0.0, 1.0, 2.0),
                f32::INFINITY
            )
            .is_none()
        );
        assert!(r.intersect(Vec3::ZERO, Vec3::X, Vec3::Y, 0.5).is_none());
        // Both windings hit.
        assert!(
            r.intersect(Vec3::ZERO, Vec3::Y, Vec3::X, f32::INFINITY)
                .is_some()
        );
        // Outside.
        let r2 = WatertightRay::new(Vec3::new(0.8, 0.8, 1.0), -Vec3::Z);
        assert!(
            r2.intersect(Vec3::ZERO, Vec3::X, Vec3::Y, f32::INFINITY)
                .is_none()
        );
    }

    #[test]
    fn shared_edge_is_never_missed() {
        // Two triangles sharing the diagonal of the unit square.
        let (p0, p1, p2, p3) = (Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.0), Vec3::Y);
        for i in 0..10_000 {
            let s = i as f32 / 10_000.0;
            let target = Vec3::new(s, s, 0.0);
            let o = Vec3::new(0.3 + s, -0.7, 2.1 - s);
            let r = WatertightRay::new(o, (target - o).normalize());
            let h = r.intersect(p0, p1, p2, f32::INFINITY).is_some()
                || r.intersect(p0, p2, p3, f32::INFINITY).is_some();
            assert!(h, "missed at s = {s}");
        }
    }

    /// Rays exactly through the shared diagonal of a square (an edge
    /// function exactly 0, the others of one sign) or through its corner
    /// (two zeros) hit one of its triangles, with either winding (the
    /// nonzero edge functions positive, or negative).
    #[test]
    fn rays_exactly_on_an_edge_hit() {
        let (p0, p1, p2, p3) = (Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.0), Vec3::Y);
        for s in [0.0, 0.125, 0.25, 0.5, 0.8125] {
            let r = WatertightRay::new(Vec3::new(s, s, 1.0), -Vec3::Z);
            for [a, b, c, d] in [[p0, p1, p2, p3], [p0, p3, p2, p1]] {
                // Each rotation puts the zero in another of U, V, W.
                let rotations = |[x, y, z]: [Vec3; 3]| [[x, y, z], [y, z, x], [z, x, y]];
                for (t1, t2) in rotations([a, b, c]).into_iter().zip(rotations([a, c, d])) {
                    let hit = r
                        .intersect(t1[0], t1[1], t1[2], f32::INFINITY)
                        .or_else(|| r.intersect(t2[0], t2[1], t2[2], f32::INFINITY));
                    let h = hit.unwrap_or_else(|| panic!("missed the edge at s = {s}"));
                    assert_eq!(h.t, 1.0);
                }
            }
        }
    }

    /// A ray that passes beside a triangle's edge by less than f32 can
    /// resolve: along −z from the origin the sheared plane is (y, x), and
    /// with ε = 2⁻²³ the edge function of b = (1, 1 + ε), c = (−(1 + ε),
    /// −(1 + 2ε)) is (1 + 2ε) − (1 + ε)², which is 0 in f32 (the product
    /// rounds to 1 + 2ε) but −ε² exactly, while the other two are
    /// positive for a = (−1, 1): the origin is outside, a miss. Rotating
    /// the vertices puts the vanishing edge function in each of U, V and
    /// W: each one alone must send the test to the exact f64 path.
    #[test]
    fn single_zero_edge_functions_are_recomputed_exactly() {
        let e = f32::EPSILON;
        assert_eq!((1.0 + e) * (1.0 + e) - (1.0 + 2.0 * e), 0.0);
        // World points (x, y) = (sheared y, sheared x), one unit below.
        let at = |sx: f32, sy: f32| Vec3::new(sy, sx, -1.0);
        let a = at(-1.0, 1.0);
        let b = at(1.0, 1.0 + e);
        let c = at(-(1.0 + e), -(1.0 + 2.0 * e));
        let r = WatertightRay::new(Vec3::ZERO, -Vec3::Z);
        for (p0, p1, p2) in [(a, b, c), (b, c, a), (c, a, b)] {
            assert_eq!(r.intersect(p0, p1, p2, f32::INFINITY), None);
        }
        // With c moved so that the origin is inside (U = ½ − ε), it is
        // hit whatever the order.
        let c = at(-1.0, -1.5);
        for (p0, p1, p2) in [(a, b, c), (b, c, a), (c, a, b)] {
            assert!(r.intersect(p0, p1, p2, f32::INFINITY).is_some());
        }
    }
}
