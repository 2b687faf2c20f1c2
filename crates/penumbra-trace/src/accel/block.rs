//! Leaf triangles four to a block, in structure-of-arrays form, a leaf in
//! one block or two consecutive ones, so that one ray tests a whole leaf
//! with 8-lane instructions (the leaves of Fuetterling et al. 2017 and of
//! tinybvh's `BVH8_CPU`, two blocks wide).
//!
//! The 8-lane test makes, in each lane, the IEEE operations of
//! [`WatertightRay::intersect_a`] in the same order, so it finds the same
//! hits with the same distances and barycentrics to the bit. Where an edge
//! function is exactly 0 the scalar test recomputes it in f64; a block
//! with such a lane hands its leaf to the scalar test whole.
#![allow(unsafe_code)]

use super::watertight::{TriangleHit, WatertightRay};
use glam::Vec3A;

/// Triangles per block.
pub(super) const LANES: usize = 4;

/// Lanes of a leaf's test: a leaf has one or two consecutive blocks
/// ([`super::wide::LEAF_MAX`] triangles).
pub(super) const LEAF_LANES: usize = 2 * LANES;

/// Up to four triangles: `v[vertex][axis][lane]`. Lanes past a leaf's
/// count hold NaN, which no ray hits.
#[derive(Clone, Copy, Debug)]
#[repr(C, align(16))]
pub(super) struct TriangleBlock {
    pub v: [[[f32; LANES]; 3]; 3],
}

impl TriangleBlock {
    pub const EMPTY: TriangleBlock = TriangleBlock {
        v: [[[f32::NAN; LANES]; 3]; 3],
    };

    /// The triangle in `lane`.
    #[inline(always)]
    pub fn triangle(&self, lane: usize) -> [Vec3A; 3] {
        let v = &self.v;
        [0, 1, 2].map(|k| Vec3A::new(v[k][0][lane], v[k][1][lane], v[k][2][lane]))
    }

    pub fn set(&mut self, lane: usize, tri: [Vec3A; 3]) {
        for (k, p) in tri.iter().enumerate() {
            for a in 0..3 {
                self.v[k][a][lane] = p[a];
            }
        }
    }
}

/// What the 8-lane test leaves for each lane that passed it with its
/// `tmax`: the scaled distance and determinant (to test again against a
/// closer `tmax`), and the hit.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct BlockHits {
    /// Lanes that hit within (0, tmax).
    pub mask: u32,
    pub t_scaled: [f32; LEAF_LANES],
    pub det: [f32; LEAF_LANES],
    pub t: [f32; LEAF_LANES],
    pub b1: [f32; LEAF_LANES],
    pub b2: [f32; LEAF_LANES],
}

impl BlockHits {
    /// The hit of `lane` (in `mask`) if it also lies within (0, `tmax`) for
    /// a `tmax` at most the block test's: the scalar test's checks that
    /// depend on `tmax`, in its order.
    #[inline(always)]
    pub fn within(&self, lane: usize, tmax: f32) -> Option<TriangleHit> {
        let (ts, det, t) = (self.t_scaled[lane], self.det[lane], self.t[lane]);
        if det < 0.0 && (ts >= 0.0 || ts < tmax * det) {
            return None;
        }
        if det > 0.0 && (ts <= 0.0 || ts > tmax * det) {
            return None;
        }
        if !(t > 0.0 && t < tmax) {
            return None;
        }
        Some(TriangleHit {
            t,
            b1: self.b1[lane],
            b2: self.b2[lane],
        })
    }
}

/// Tests the first `count` lanes of a leaf's triangles (`count` ≤
/// [`LEAF_LANES`]: lanes 0–3 in `blocks[0]`, lanes 4–7 in `blocks[1]`)
/// against `ray` within (0, `tmax`), eight lanes at a time. `None` when a
/// lane needs the scalar test's f64 fallback.
///
/// # Safety
/// The CPU must support AVX. Not a `#[target_feature]` function, so that
/// it inlines into the AVX2 kernel, whose features encode it.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
pub(super) unsafe fn intersect_leaf(
    ray: &WatertightRay,
    blocks: &[TriangleBlock],
    count: usize,
    tmax: f32,
) -> Option<BlockHits> {
    use std::arch::x86_64::*;
    let [kx, ky, kz] = ray.permutation();
    let [sx, sy, sz] = ray.shear();
    let [okx, oky, okz] = ray.origin_permuted();
    let lo = &blocks[0];
    // A leaf of one block reads it twice: its upper lanes are masked off.
    let hi = if count > LANES { &blocks[1] } else { lo };
    // SAFETY: the caller ensures AVX; `block.v` rows are 4 aligned f32 and
    // the stores go to 8-f32 arrays.
    unsafe {
        // Macros, not closures: closures do not inherit the caller's target
        // features, so the AVX intrinsics would not inline into them.
        macro_rules! row {
            ($k:expr, $axis:expr) => {
                _mm256_set_m128(
                    _mm_load_ps(hi.v[$k][$axis].as_ptr()),
                    _mm_load_ps(lo.v[$k][$axis].as_ptr()),
                )
            };
        }
        let (sx, sy, sz) = (_mm256_set1_ps(sx), _mm256_set1_ps(sy), _mm256_set1_ps(sz));
        let (ox, oy, oz) = (
            _mm256_set1_ps(okx),
            _mm256_set1_ps(oky),
            _mm256_set1_ps(okz),
        );
        // Vertex k sheared: (x, y, z) = (a_kx − sx·a_kz, a_ky − sy·a_kz, sz·a_kz).
        macro_rules! sheared {
            ($k:expr) => {{
                let px = _mm256_sub_ps(row!($k, kx), ox);
                let py = _mm256_sub_ps(row!($k, ky), oy);
                let pz = _mm256_sub_ps(row!($k, kz), oz);
                (
                    _mm256_sub_ps(px, _mm256_mul_ps(sx, pz)),
                    _mm256_sub_ps(py, _mm256_mul_ps(sy, pz)),
                    _mm256_mul_ps(pz, sz),
                )
            }};
        }
        let (ax, ay, az) = sheared!(0);
        let (bx, by, bz) = sheared!(1);
        let (cx, cy, cz) = sheared!(2);
        let u = _mm256_sub_ps(_mm256_mul_ps(cx, by), _mm256_mul_ps(cy, bx));
        let v = _mm256_sub_ps(_mm256_mul_ps(ax, cy), _mm256_mul_ps(ay, cx));
        let w = _mm256_sub_ps(_mm256_mul_ps(bx, ay), _mm256_mul_ps(by, ax));
        let lanes = (1u32 << count) - 1;
        let zero = _mm256_setzero_ps();
        macro_rules! cmp_eq {
            ($a:expr, $b:expr) => {
                _mm256_cmp_ps::<_CMP_EQ_OQ>($a, $b)
            };
        }
        macro_rules! cmp_lt {
            ($a:expr, $b:expr) => {
                _mm256_cmp_ps::<_CMP_LT_OQ>($a, $b)
            };
        }
        macro_rules! cmp_le {
            ($a:expr, $b:expr) => {
                _mm256_cmp_ps::<_CMP_LE_OQ>($a, $b)
            };
        }
        let zeros = _mm256_or_ps(
            _mm256_or_ps(cmp_eq!(u, zero), cmp_eq!(v, zero)),
            cmp_eq!(w, zero),
        );
        if _mm256_movemask_ps(zeros) as u32 & lanes != 0 {
            return None;
        }
        let any_neg = _mm256_or_ps(
            _mm256_or_ps(cmp_lt!(u, zero), cmp_lt!(v, zero)),
            cmp_lt!(w, zero),
        );
        let any_pos = _mm256_or_ps(
            _mm256_or_ps(cmp_lt!(zero, u), cmp_lt!(zero, v)),
            cmp_lt!(zero, w),
        );
        let det = _mm256_add_ps(_mm256_add_ps(u, v), w);
        let t_scaled = _mm256_add_ps(
            _mm256_add_ps(_mm256_mul_ps(u, az), _mm256_mul_ps(v, bz)),
            _mm256_mul_ps(w, cz),
        );
        let tmax_v = _mm256_set1_ps(tmax);
        let bound = _mm256_mul_ps(tmax_v, det);
        // det < 0 && (ts >= 0 || ts < tmax·det), det > 0 && (ts <= 0 || ts > tmax·det)
        let behind_neg = _mm256_and_ps(
            cmp_lt!(det, zero),
            _mm256_or_ps(cmp_le!(zero, t_scaled), cmp_lt!(t_scaled, bound)),
        );
        let behind_pos = _mm256_and_ps(
            cmp_lt!(zero, det),
            _mm256_or_ps(cmp_le!(t_scaled, zero), cmp_lt!(bound, t_scaled)),
        );
        let inv = _mm256_div_ps(_mm256_set1_ps(1.0), det);
        let t = _mm256_mul_ps(t_scaled, inv);
        let in_range = _mm256_and_ps(cmp_lt!(zero, t), cmp_lt!(t, tmax_v));
        let rejected = _mm256_or_ps(
            _mm256_or_ps(_mm256_and_ps(any_neg, any_pos), cmp_eq!(det, zero)),
            _mm256_or_ps(behind_neg, behind_pos),
        );
        let hit = _mm256_andnot_ps(rejected, in_range);
        let mut out = BlockHits {
            mask: _mm256_movemask_ps(hit) as u32 & lanes,
            ..BlockHits::default()
        };
        if out.mask != 0 {
            _mm256_storeu_ps(out.t_scaled.as_mut_ptr(), t_scaled);
            _mm256_storeu_ps(out.det.as_mut_ptr(), det);
            _mm256_storeu_ps(out.t.as_mut_ptr(), t);
            _mm256_storeu_ps(out.b1.as_mut_ptr(), _mm256_mul_ps(v, inv));
            _mm256_storeu_ps(out.b2.as_mut_ptr(), _mm256_mul_ps(w, inv));
        }
        Some(out)
    }
}

#[cfg(test)]
#[cfg(target_arch = "x86_64")]
mod tests {
    use super::*;
    use glam::Vec3;
    use penumbra_shading::stats::TestRng;

    fn bits(h: Option<TriangleHit>) -> Option<[u32; 3]> {
        h.map(|h| [h.t.to_bits(), h.b1.to_bits(), h.b2.to_bits()])
    }

    /// The 8-lane test, on a CPU that has it (the tests fail on one that
    /// does not, rather than pass without testing).
    fn intersect(
        ray: &WatertightRay,
        blocks: &[TriangleBlock],
        count: usize,
        tmax: f32,
    ) -> Option<BlockHits> {
        assert!(
            std::arch::is_x86_feature_detected!("avx"),
            "the 8-lane test needs AVX"
        );
        // SAFETY: AVX is present (checked above).
        unsafe { intersect_leaf(ray, blocks, count, tmax) }
    }

    /// Each lane of the 8-lane test (leaves of one and two blocks) against the scalar test on the same
    /// triangle, to the bit, for rays along every axis and sign
    /// (permutations), axis-parallel rays, fans of triangles sharing a vertex
    /// (hits on shared edges), both windings and a range of `tmax`; then
    /// `within` against the scalar test with a closer `tmax`.
    #[test]
    fn lanes_match_the_scalar_test_to_the_bit() {
        let mut rng = TestRng::new(3);
        let mut vec = |scale: f32| {
            Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * 2.0 * scale - scale
        };
        let (mut compared, mut hits, mut fallbacks, mut closer) = (0, 0, 0, 0);
        for case in 0..4000 {
            let origin = vec(3.0);
            let dir = match case % 8 {
                0 => Vec3::X,
                1 => -Vec3::Y,
                2 => Vec3::new(0.0, 0.0, -1.0),
                _ => vec(1.0).normalize(),
            };
            // Triangles around a point near the ray: a fan (shared edges) or
            // a random soup, either winding.
            let centre = origin + dir * 2.0 + vec(0.05);
            let mut tris = [[Vec3A::ZERO; 3]; LEAF_LANES];
            for (lane, tri) in tris.iter_mut().enumerate() {
                *tri = if case % 3 == 0 {
                    let a = lane as f32 * std::f32::consts::FRAC_PI_4;
                    let b = a + std::f32::consts::FRAC_PI_4;
                    let (u, v) = (dir.any_orthonormal_pair().0, dir.any_orthonormal_pair().1);
                    let rim = |x: f32| centre + (u * x.cos() + v * x.sin()) * 0.3;
                    [centre, rim(a), rim(b)].map(Vec3A::from)
                } else {
                    [centre + vec(0.4), centre + vec(0.4), centre + vec(0.4)].map(Vec3A::from)
                };
                if case % 2 == 1 {
                    tri.swap(1, 2);
                }
            }
            let count = 1 + case % LEAF_LANES;
            let mut blocks = [TriangleBlock::EMPTY; 2];
            for (lane, tri) in tris.iter().enumerate().take(count) {
                let block = &mut blocks[lane / LANES];
                block.set(lane % LANES, *tri);
                assert_eq!(block.triangle(lane % LANES), *tri);
            }
            // A leaf of one block is all the test may read.
            let blocks = &blocks[..count.div_ceil(LANES)];
            let ray = WatertightRay::new(origin, dir);
            let tmax = [f32::INFINITY, 2.0, 1.9, 2.1][case % 4];
            let scalar = |lane: usize, tmax: f32| {
                let [a, b, c] = tris[lane];
                ray.intersect_a(a, b, c, tmax)
            };
            let Some(got) = intersect(&ray, blocks, count, tmax) else {
                // Only where a lane's edge function is exactly zero.
                fallbacks += 1;
                continue;
            };
            for lane in 0..LEAF_LANES {
                let expected = if lane < count {
                    scalar(lane, tmax)
                } else {
                    None
                };
                let from_block = (got.mask >> lane & 1 == 1)
                    .then(|| got.within(lane, tmax))
                    .flatten();
                assert_eq!(bits(from_block), bits(expected), "case {case} lane {lane}");
                assert_eq!(got.mask >> lane & 1 == 1, expected.is_some());
                compared += 1;
                hits += expected.is_some() as u32;
                // A closer tmax, as after an earlier lane's hit.
                if let Some(h) = expected {
                    for closer_t in [h.t, h.t.next_up(), h.t.next_down(), h.t * 0.5] {
                        let want = scalar(lane, closer_t);
                        assert_eq!(bits(got.within(lane, closer_t)), bits(want));
                        // And the 8-lane test itself with that tmax.
                        let again = intersect(&ray, blocks, count, closer_t).unwrap();
                        assert_eq!(again.mask >> lane & 1 == 1, want.is_some());
                        closer += want.is_some() as u32;
                    }
                }
            }
        }
        assert!(
            compared == LEAF_LANES * (4000 - fallbacks) && hits > 1000,
            "{compared} lanes, {hits} hits"
        );
        assert!(closer > 1000 && fallbacks < 40, "{closer} {fallbacks}");
    }

    /// A lane whose edge function is exactly zero (a ray through a vertex
    /// shared by a fan), in either block of a leaf, sends the leaf to the
    /// scalar test; padding lanes never do.
    #[test]
    fn zero_edge_functions_fall_back_to_the_scalar_test() {
        let ray = WatertightRay::new(Vec3::new(0.0, 0.0, 1.0), -Vec3::Z);
        let mut block = TriangleBlock::EMPTY;
        let fan = [Vec3A::ZERO, Vec3A::X, Vec3A::Y];
        block.set(
            0,
            [
                Vec3A::new(0.2, 0.2, 0.0),
                Vec3A::new(1.0, 0.2, 0.0),
                Vec3A::new(0.2, 1.0, 0.0),
            ],
        );
        let miss = intersect(&ray, &[block], 1, f32::INFINITY).unwrap();
        assert_eq!(miss.mask, 0);
        block.set(1, fan);
        assert!(intersect(&ray, &[block], 2, f32::INFINITY).is_none());
        // The same triangle in a padding lane is not looked at.
        assert!(intersect(&ray, &[block], 1, f32::INFINITY).is_some());
        let hit = intersect(
            &WatertightRay::new(Vec3::new(0.25, 0.25, 1.0), -Vec3::Z),
            &[block],
            2,
            f32::INFINITY,
        )
        .unwrap();
        assert_eq!(hit.mask, 0b11);
        assert_eq!(hit.within(1, f32::INFINITY).unwrap().t, 1.0);
        // The fan in the second block's lanes: in lane 5, it is tested; in
        // lane 4 of a five-lane leaf, padding lanes 5–7 are not.
        let mut second = TriangleBlock::EMPTY;
        second.set(1, fan);
        assert!(intersect(&ray, &[block, second], 6, f32::INFINITY).is_none());
        let mut first = block;
        first.set(1, block.triangle(0));
        assert!(intersect(&ray, &[first, second], 5, f32::INFINITY).is_some());
    }
}
