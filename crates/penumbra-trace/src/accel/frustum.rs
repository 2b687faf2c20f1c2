//! Frustum traversal of a coherent packet: the packet's rays all point
//! into one octant, so one interval box test stands for all of them at
//! each inner node (Reshetov et al. 2005's multi-level ray tracing and
//! Embree's coherent packets cull by the packet's frustum in the same
//! way). A node costs one 8-slot test, as for a single ray, instead of
//! one 16-lane test per slot; the exact per-lane test is made only for
//! the leaves a node enters, so each ray still tests exactly the leaves
//! whose boxes it enters (and the leaf test, per ray, is the single-ray
//! one).
//!
//! The interval test is conservative to the bit: per axis the lanes'
//! origins lie in [o_min, o_max] and their reciprocal directions, all of
//! one sign, in [i_min, i_max]. IEEE rounding is monotone, so each lane's
//! `fl(fl(b − o)·inv)` lies between the values the interval's ends give:
//! for a positive reciprocal the smallest entry is at o_max and the
//! largest exit at o_min (the other way round for a negative one), and in
//! `inv` each product is monotone, so its extremes are at i_min or i_max.
//! A box that any lane enters (by the single-ray test's operations) is
//! therefore entered by the interval test.
#![allow(unsafe_code)]

use super::packet::{
    AVX2, AVX512, Entered, NodeEntry, PACKET, PORTABLE, PacketBoxes, defer_all_but_nearest,
};
use super::traverse::{Query, SetBits, insert_by_decreasing_t, prefetch};
use super::wide::{LEAF_BIT, Node8, WIDTH};

/// The interval form of a packet whose rays share an octant: per axis the
/// planes by which every ray enters and leaves a box, the origins that
/// give the lowest entry and the highest exit, and the reciprocal
/// directions' range.
pub(super) struct Frustum {
    near: [usize; 3],
    far: [usize; 3],
    o_near: [f32; 3],
    o_far: [f32; 3],
    inv_lo: [f32; 3],
    inv_hi: [f32; 3],
}

impl Frustum {
    /// The frustum of the packet's sixteen lanes (lanes without a ray of
    /// their own repeat another lane's, as `closest_packets` fills them),
    /// or `None` where they point into different octants or a value is
    /// not finite (a reciprocal of ±∞ or 0 could make a NaN, which the
    /// interval bounds would not hold).
    #[inline(always)]
    pub fn new(boxes: &PacketBoxes) -> Option<Self> {
        let mut f = Frustum {
            near: [0; 3],
            far: [0; 3],
            o_near: [0.0; 3],
            o_far: [0.0; 3],
            inv_lo: [0.0; 3],
            inv_hi: [0.0; 3],
        };
        for a in 0..3 {
            let negative = boxes.negative[a];
            if negative != 0 && negative != ALL {
                return None;
            }
            let (o, inv) = (&boxes.origin[a], &boxes.inv[a]);
            // Integer tests, which vectorise: an exponent of all ones is
            // ±∞ or NaN; a reciprocal of ±0 has no bits but the sign.
            const EXPONENT: u32 = 0x7f80_0000;
            let bad = o.iter().zip(inv).fold(0u32, |bad, (o, i)| {
                let (o, i) = (o.to_bits(), i.to_bits());
                bad | ((o & EXPONENT) == EXPONENT) as u32
                    | ((i & EXPONENT) == EXPONENT) as u32
                    | (i << 1 == 0) as u32
            });
            if bad != 0 {
                return None;
            }
            let o = min_max(o);
            let by_max = negative != 0;
            f.near[a] = 2 * a + by_max as usize;
            f.far[a] = 2 * a + 1 - by_max as usize;
            // Positive reciprocal: lowest entry from the largest origin.
            (f.o_near[a], f.o_far[a]) = if by_max { o } else { (o.1, o.0) };
            (f.inv_lo[a], f.inv_hi[a]) = min_max(inv);
        }
        Some(f)
    }

    /// Lower bounds of every lane's entry distance into `node`'s slots
    /// (clamped below by 0), and the slots that some lane with `tmax` at
    /// most `tmax` may enter.
    #[inline(always)]
    fn slab<const SIMD: u8>(&self, node: &Node8, tmax: f32, t: &mut [f32; WIDTH]) -> u32 {
        #[cfg(target_arch = "x86_64")]
        if SIMD != PORTABLE {
            // SAFETY: the SIMD kernels run only where AVX2 is supported
            // (checked in `Accel::set_kernel` and `Kernel::best`).
            return unsafe { self.slab_avx2(node, tmax, t) };
        }
        self.slab_portable(node, tmax, t)
    }

    #[inline(always)]
    fn slab_portable(&self, node: &Node8, tmax: f32, t: &mut [f32; WIDTH]) -> u32 {
        let b = &node.bounds;
        let lo = |x: f32, y: f32| if x < y { x } else { y };
        let hi = |x: f32, y: f32| if x > y { x } else { y };
        let mut t0 = [0.0f32; WIDTH];
        let mut t1 = [tmax; WIDTH];
        for a in 0..3 {
            let (il, ih) = (self.inv_lo[a], self.inv_hi[a]);
            for i in 0..WIDTH {
                let n = b[self.near[a]][i] - self.o_near[a];
                let f = b[self.far[a]][i] - self.o_far[a];
                t0[i] = hi(t0[i], lo(n * il, n * ih));
                t1[i] = lo(t1[i], hi(f * il, f * ih));
            }
        }
        let mut mask = 0;
        for i in 0..WIDTH {
            mask |= ((t0[i] <= t1[i]) as u32) << i;
        }
        *t = t0;
        mask
    }

    /// [`Frustum::slab_portable`] in AVX2: no value is NaN (`Frustum::new`
    /// refuses the packets that could make one), so `min`/`max` give the
    /// portable comparisons' results.
    ///
    /// # Safety
    /// The CPU must support AVX2 (inlined into the AVX2 and AVX-512 entry
    /// points).
    #[cfg(target_arch = "x86_64")]
    #[inline(always)]
    unsafe fn slab_avx2(&self, node: &Node8, tmax: f32, t: &mut [f32; WIDTH]) -> u32 {
        use std::arch::x86_64::*;
        let b = &node.bounds;
        // SAFETY: each plane and `t` are 8 f32 (unaligned loads and stores).
        unsafe {
            let mut t0 = _mm256_setzero_ps();
            let mut t1 = _mm256_set1_ps(tmax);
            for a in 0..3 {
                let (il, ih) = (
                    _mm256_set1_ps(self.inv_lo[a]),
                    _mm256_set1_ps(self.inv_hi[a]),
                );
                let near = _mm256_loadu_ps(b[self.near[a]].as_ptr());
                let far = _mm256_loadu_ps(b[self.far[a]].as_ptr());
                let n = _mm256_sub_ps(near, _mm256_set1_ps(self.o_near[a]));
                let f = _mm256_sub_ps(far, _mm256_set1_ps(self.o_far[a]));
                let entry = _mm256_min_ps(_mm256_mul_ps(n, il), _mm256_mul_ps(n, ih));
                let exit = _mm256_max_ps(_mm256_mul_ps(f, il), _mm256_mul_ps(f, ih));
                t0 = _mm256_max_ps(t0, entry);
                t1 = _mm256_min_ps(t1, exit);
            }
            _mm256_storeu_ps(t.as_mut_ptr(), t0);
            _mm256_movemask_ps(_mm256_cmp_ps::<_CMP_LE_OQ>(t0, t1)) as u32
        }
    }
}

/// Every lane of a packet.
const ALL: u32 = (1 << PACKET) - 1;

/// The least and the greatest of sixteen finite values, halving.
#[inline(always)]
fn min_max(v: &[f32; PACKET]) -> (f32, f32) {
    let (mut lo, mut hi) = (*v, *v);
    let mut w = PACKET / 2;
    while w > 0 {
        for i in 0..w {
            lo[i] = if lo[i + w] < lo[i] { lo[i + w] } else { lo[i] };
            hi[i] = if hi[i + w] > hi[i] { hi[i + w] } else { hi[i] };
        }
        w /= 2;
    }
    (lo[0], hi[0])
}

/// The lanes of `lanes` whose `best_t` is at least `t`.
#[inline(always)]
fn lanes_reaching<const SIMD: u8>(t: f32, best_t: &[f32; PACKET], lanes: u32) -> u32 {
    #[cfg(target_arch = "x86_64")]
    {
        use std::arch::x86_64::*;
        // SAFETY: the kernel's features are supported (checked in
        // `Accel::set_kernel` and `Kernel::best`); `best_t` holds 16 f32.
        unsafe {
            if SIMD == AVX512 {
                let b = _mm512_loadu_ps(best_t.as_ptr());
                return _mm512_cmp_ps_mask::<_CMP_LE_OQ>(_mm512_set1_ps(t), b) as u32 & lanes;
            }
            if SIMD == AVX2 {
                // Two halves; not a closure, which would not inherit the
                // caller's target features.
                let t = _mm256_set1_ps(t);
                let lo = _mm256_loadu_ps(best_t.as_ptr());
                let hi = _mm256_loadu_ps(best_t[8..].as_ptr());
                let lo = _mm256_movemask_ps(_mm256_cmp_ps::<_CMP_LE_OQ>(t, lo)) as u32;
                let hi = _mm256_movemask_ps(_mm256_cmp_ps::<_CMP_LE_OQ>(t, hi)) as u32;
                return (lo | hi << 8) & lanes;
            }
        }
    }
    let mut m = 0;
    for (l, &b) in best_t.iter().enumerate() {
        m |= ((t <= b) as u32) << l;
    }
    m & lanes
}

/// The largest `best_t` of the lanes of `lanes` (0 for none): distances
/// are ≥ 0, whose bits order as the values do.
#[inline(always)]
fn farthest(best_t: &[f32; PACKET], lanes: u32) -> f32 {
    let mut bits = [0u32; PACKET];
    for (l, (b, &t)) in bits.iter_mut().zip(best_t).enumerate() {
        *b = if lanes >> l & 1 != 0 { t.to_bits() } else { 0 };
    }
    let mut w = PACKET / 2;
    while w > 0 {
        for i in 0..w {
            bits[i] = bits[i].max(bits[i + w]);
        }
        w /= 2;
    }
    f32::from_bits(bits[0])
}

/// A deferred subtree of a frustum walk: its slot code, the lanes that
/// go into it, and a lower bound of their entry distances.
#[derive(Clone, Copy)]
pub(super) struct FrustumEntry {
    pub code: u32,
    pub mask: u32,
    pub t: f32,
}

/// The frustum walk: inner nodes entered by the frustum's interval test;
/// a leaf by the lanes whose own box test enters it.
pub(super) struct FrustumWalk<'a> {
    pub frustum: Frustum,
    pub boxes: &'a PacketBoxes,
}

impl NodeEntry for FrustumWalk<'_> {
    type Deferred = FrustumEntry;

    #[inline(always)]
    fn enter<const SIMD: u8>(
        &self,
        q0: &Query,
        node: &Node8,
        active: u32,
        best_t: &[f32; PACKET],
        stack: &mut [FrustumEntry],
    ) -> Option<Entered> {
        let tmax = farthest(best_t, active);
        let mut t = [0.0; WIDTH];
        let entered = self.frustum.slab::<SIMD>(node, tmax, &mut t);
        // Entered children, sorted by decreasing entry bound.
        let mut hits = [FrustumEntry {
            code: 0,
            mask: 0,
            t: 0.0,
        }; WIDTH];
        let mut n = 0;
        for slot in SetBits(entered) {
            let child = node.child[slot];
            let mask = if child & LEAF_BIT != 0 {
                let mut tl = [0.0; PACKET];
                self.boxes.slab::<SIMD>(node, slot, best_t, &mut tl) & active
            } else {
                active
            };
            if mask == 0 {
                continue;
            }
            if q0.prefetches() {
                prefetch(q0, child);
            }
            let e = FrustumEntry {
                code: child,
                mask,
                t: t[slot],
            };
            insert_by_decreasing_t(&mut hits, n, e, |e| e.t);
            n += 1;
        }
        defer_all_but_nearest(&hits[..n], stack, |&e| e, |e| (e.code, e.mask))
    }

    #[inline(always)]
    fn resume<const SIMD: u8>(e: &FrustumEntry, best_t: &[f32; PACKET]) -> (u32, u32) {
        (e.code, lanes_reaching::<SIMD>(e.t, best_t, e.mask))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::accel::traverse::Kernel;
    use crate::accel::wide::Wide;
    use glam::Vec3;

    /// A fixed stream of numbers in [0, 1) (a 32-bit LCG's high bits).
    struct Numbers(u32);

    impl Numbers {
        fn next(&mut self) -> f32 {
            self.0 = self.0.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            (self.0 >> 8) as f32 / (1u32 << 24) as f32
        }

        fn vec(&mut self, lo: f32, hi: f32) -> Vec3 {
            Vec3::new(self.next(), self.next(), self.next()) * (hi - lo) + Vec3::splat(lo)
        }
    }

    /// A packet of rays from around `centre` (spread `spread_origin`) into
    /// the octant of `signs`, their directions `spread_direction` apart,
    /// some with a finite `tmax`.
    fn packet<'a>(
        wide: &'a Wide,
        n: &mut Numbers,
        signs: Vec3,
        centre: Vec3,
        spread_origin: f32,
        spread_direction: f32,
    ) -> [Query<'a>; PACKET] {
        let base = n.vec(0.05, 1.0);
        std::array::from_fn(|l| {
            let o = centre + n.vec(-1.0, 1.0) * spread_origin;
            let d = (base + n.vec(0.0, 1.0) * spread_direction) * signs;
            let tmax = if l % 3 == 0 {
                2.0 + 8.0 * n.next()
            } else {
                f32::INFINITY
            };
            Query::new(wide, &[], o, d.normalize(), tmax, false)
        })
    }

    /// Eight random boxes around the origin, the fourth flat.
    fn random_node(n: &mut Numbers) -> Node8 {
        let boxes: Vec<([f32; 3], [f32; 3])> = (0..WIDTH)
            .map(|i| {
                let c = n.vec(-4.0, 4.0);
                let mut h = n.vec(0.0, 2.0);
                if i == 3 {
                    h.z = 0.0;
                }
                ((c - h).to_array(), (c + h).to_array())
            })
            .collect();
        Node8::with_boxes(&boxes)
    }

    /// Sixteen copies of one ray make a frustum that is the ray itself:
    /// its test gives the single-ray test's mask and entry distances to
    /// the bit (so a frustum that enters every box, or one built from the
    /// wrong values, is caught here, which the conservative test above
    /// cannot see).
    #[test]
    fn a_packet_of_one_ray_is_the_ray() {
        let wide = Wide::default();
        let mut n = Numbers(5);
        let mut entered = 0;
        for round in 0..300 {
            let node = random_node(&mut n);
            let o = n.vec(-9.0, 9.0);
            // Aimed at one of the boxes, so that most rays enter some.
            let (lo, hi) = node.slot_box(round % 7);
            let mut d = (Vec3::from(lo) + Vec3::from(hi)) / 2.0 - o + n.vec(-0.5, 0.5);
            if round % 10 == 0 {
                d.y = if round % 20 == 0 { 0.0 } else { -0.0 };
            }
            let tmax = if round % 3 == 0 { 6.0 } else { f32::INFINITY };
            let queries: [Query; PACKET] =
                std::array::from_fn(|_| Query::new(&wide, &[], o, d.normalize(), tmax, false));
            let f = Frustum::new(&PacketBoxes::new(&queries)).expect("one ray, one octant");
            let mut alone = [f32::NAN; WIDTH];
            let expected = queries[0].slab_alone(&node, &mut alone);
            let mut kernels = vec![PORTABLE];
            if Kernel::Avx2.is_supported() {
                kernels.push(AVX2);
            }
            for simd in kernels {
                let mut t = [f32::NAN; WIDTH];
                let mask = match simd {
                    PORTABLE => f.slab::<PORTABLE>(&node, tmax, &mut t),
                    _ => f.slab::<AVX2>(&node, tmax, &mut t),
                };
                assert_eq!(mask, expected, "round {round} kernel {simd}");
                for slot in (0..WIDTH).filter(|s| expected >> s & 1 != 0) {
                    assert_eq!(t[slot].to_bits(), alone[slot].to_bits(), "round {round}");
                }
            }
            entered += expected.count_ones();
        }
        assert!(entered > 300, "{entered}");
    }

    /// Packets of every octant, narrow and wide, from outside and among
    /// the boxes, against nodes of random boxes (some flat): every slot
    /// that a lane's own box test enters within its `tmax` is entered by
    /// the frustum test with at most the lane's entry distance, and the
    /// AVX2 test gives the portable one's mask and distances to the bit.
    #[test]
    fn the_frustum_enters_every_box_its_rays_enter() {
        let wide = Wide::default();
        let mut n = Numbers(7);
        let (mut entered, mut loose) = (0, 0);
        for round in 0..600 {
            let node = random_node(&mut n);
            let signs = Vec3::select(
                glam::BVec3::new(round & 1 != 0, round & 2 != 0, round & 4 != 0),
                Vec3::NEG_ONE,
                Vec3::ONE,
            );
            let outside = -signs * 9.0 + n.vec(-3.0, 3.0);
            let centre = if round % 3 == 0 {
                n.vec(-2.0, 2.0)
            } else {
                outside
            };
            let spread_origin = [0.0, 0.01, 0.5, 4.0][round / 8 % 4];
            let spread_direction = [0.001, 0.1, 1.0, 10.0][round / 32 % 4];
            let queries = packet(
                &wide,
                &mut n,
                signs,
                centre,
                spread_origin,
                spread_direction,
            );
            let lanes = PacketBoxes::new(&queries);
            let f = Frustum::new(&lanes).expect("one octant, finite");
            let tmax = queries.iter().map(Query::tmax).fold(0.0, f32::max);
            let mut t = [f32::NAN; WIDTH];
            let mask = f.slab::<PORTABLE>(&node, tmax, &mut t);
            #[cfg(target_arch = "x86_64")]
            if Kernel::Avx2.is_supported() {
                let mut t2 = [f32::NAN; WIDTH];
                assert_eq!(f.slab::<AVX2>(&node, tmax, &mut t2), mask, "round {round}");
                assert_eq!(t2.map(f32::to_bits), t.map(f32::to_bits), "round {round}");
            }
            let mut any = 0;
            for (l, q) in queries.iter().enumerate() {
                let mut alone = [f32::NAN; WIDTH];
                let m = q.slab_alone(&node, &mut alone);
                any |= m;
                for slot in (0..WIDTH).filter(|s| m >> s & 1 != 0) {
                    assert!(mask >> slot & 1 != 0, "round {round} lane {l} slot {slot}");
                    assert!(t[slot] <= alone[slot], "round {round} lane {l} slot {slot}");
                    entered += 1;
                }
            }
            loose += (mask & !any).count_ones();
        }
        // Many boxes entered; the test is conservative, not exact.
        assert!(entered > 1500, "{entered}");
        assert!(loose > 50, "{loose}");
    }

    /// Packets that point into two octants, or whose values could make a
    /// NaN (an origin of ±∞ or NaN, a direction whose reciprocal is ±∞ or
    /// 0), have no frustum; one with axis-parallel rays (zero components,
    /// of either sign) has one.
    #[test]
    fn only_one_octant_of_finite_rays_has_a_frustum() {
        let wide = Wide::default();
        let d = Vec3::new(0.3, 0.5, 0.8).normalize();
        let frustum_with = |lane: Option<(Vec3, Vec3)>| {
            let queries: [Query; PACKET] = std::array::from_fn(|l| {
                let (o, dir) = match lane {
                    Some(od) if l == 5 => od,
                    _ => (Vec3::new(0.1 * l as f32, 0.0, -5.0), d),
                };
                Query::new(&wide, &[], o, dir, f32::INFINITY, false)
            });
            Frustum::new(&PacketBoxes::new(&queries)).is_some()
        };
        assert!(frustum_with(None));
        assert!(frustum_with(Some((Vec3::ZERO, Vec3::new(0.0, -0.0, 1.0)))));
        assert!(!frustum_with(Some((Vec3::ZERO, Vec3::new(0.3, -0.5, 0.8)))));
        assert!(!frustum_with(Some((Vec3::ZERO, -d))));
        assert!(!frustum_with(Some((Vec3::new(f32::INFINITY, 0.0, 0.0), d))));
        assert!(!frustum_with(Some((Vec3::new(0.0, f32::NAN, 0.0), d))));
        // 1/1e-40 overflows to +∞; 1/∞ is 0.
        assert!(!frustum_with(Some((
            Vec3::ZERO,
            Vec3::new(1e-40, 0.6, 0.8)
        ))));
        assert!(!frustum_with(Some((
            Vec3::ZERO,
            Vec3::new(f32::INFINITY, 0.6, 0.8)
        ))));
    }

    /// The farthest closest-hit distance among the masked lanes only
    /// (unmasked lanes hold larger ones, +∞ included), 0 for no lane.
    #[test]
    fn farthest_takes_only_the_masked_lanes() {
        let mut n = Numbers(11);
        for _ in 0..200 {
            let lanes = (n.next() * 65536.0) as u32;
            let best_t: [f32; PACKET] = std::array::from_fn(|l| {
                if lanes >> l & 1 != 0 {
                    n.next() * 10.0
                } else if l % 2 == 0 {
                    f32::INFINITY
                } else {
                    20.0 + n.next()
                }
            });
            let expected = (0..PACKET)
                .filter(|&l| lanes >> l & 1 != 0)
                .map(|l| best_t[l])
                .fold(0.0, f32::max);
            assert_eq!(farthest(&best_t, lanes), expected, "lanes {lanes:#x}");
        }
        assert_eq!(farthest(&[f32::INFINITY; PACKET], 0), 0.0);
    }

    /// The lanes whose closest hit so far reaches a distance, with each
    /// kernel, ties included, against the plain comparison.
    #[test]
    fn lanes_reaching_matches_the_comparison() {
        let mut n = Numbers(3);
        for _ in 0..200 {
            let best_t: [f32; PACKET] = std::array::from_fn(|_| (n.next() * 8.0).floor());
            let t = (n.next() * 8.0).floor();
            let lanes = (n.next() * 65536.0) as u32;
            let expected = (0..PACKET)
                .filter(|&l| lanes >> l & 1 != 0 && t <= best_t[l])
                .fold(0, |m, l| m | 1 << l);
            assert_eq!(lanes_reaching::<PORTABLE>(t, &best_t, lanes), expected);
            #[cfg(target_arch = "x86_64")]
            {
                if Kernel::Avx2.is_supported() {
                    assert_eq!(lanes_reaching::<AVX2>(t, &best_t, lanes), expected);
                }
                if Kernel::Avx512.is_supported() {
                    assert_eq!(lanes_reaching::<AVX512>(t, &best_t, lanes), expected);
                }
            }
        }
    }
}
