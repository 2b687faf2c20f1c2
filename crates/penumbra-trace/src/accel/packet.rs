//! Packet traversal: up to [`PACKET`] rays walk the 8-wide BVH together,
//! in one of two ways.
//!
//! - **Frustum walk** (`frustum.rs`), for packets whose rays all point
//!   into one octant (camera rays of neighbouring pixels): one interval
//!   test of a node's eight boxes stands for every ray; each ray's own
//!   box test is made only for the leaves a node enters.
//! - **Per-lane walk** (here), for the others: at each node every child
//!   box is tested against all the packet's rays at once (one lane per
//!   ray), so the node is loaded, sorted and pushed once for the packet
//!   instead of once per ray; the rays that enter a child go on into it
//!   together.
//!
//! In both, a leaf's triangles are tested ray by ray with the single-ray
//! leaf test, and a subtree that at most [`SWITCH`] of the rays enter is
//! finished by each of them alone, their single-ray walks interleaved
//! (Embree's hybrid packets switch to single rays in the same way), so
//! packets of diverging rays cost little more than the rays alone.
//!
//! Each lane makes the single-ray box test's IEEE operations in the same
//! order (the near and far planes chosen per lane from the signs of its
//! direction), the frustum test enters every box that any of its rays
//! enters, and each ray is culled against its own closest hit, so each ray
//! gets the hit it gets alone; only the order of visits differs, which can
//! change which of two triangles at exactly the same distance is reported.
//!
//! `unsafe` for the AVX2 and AVX-512 box tests and to call their entry
//! points after the CPU check.
#![allow(unsafe_code)]

use super::frustum::{Frustum, FrustumEntry, FrustumWalk};
use super::traverse::{
    Entry, Kernel, Query, STACK_INLINE, SetBits, Walk, insert_by_decreasing_t, leaf_step, prefetch,
    stack_entries,
};
use super::watertight::TriangleHit;
use super::wide::{LEAF_BIT, Node8, WIDTH};
use std::mem::MaybeUninit;

/// Rays per packet.
pub(super) const PACKET: usize = 16;

/// Which compiled box test a packet runs (`SIMD` below).
pub(super) const PORTABLE: u8 = 0;
pub(super) const AVX2: u8 = 1;
pub(super) const AVX512: u8 = 2;

/// A deferred subtree: its slot code, the packet's rays that entered its
/// box, and each ray's entry distance.
#[derive(Clone, Copy)]
pub(super) struct PacketEntry {
    code: u32,
    mask: u32,
    t: [f32; PACKET],
}

/// The packet's rays as the box test sees them, one lane per ray: origin,
/// reciprocal direction and, per axis, the bit mask of the rays that enter
/// a box by its max plane (negative direction: the reciprocal's sign bit,
/// which AVX2's blends read directly: never −0 for a finite direction,
/// see `BoxRay::new`).
#[repr(C, align(64))]
pub(super) struct PacketBoxes {
    pub origin: [[f32; PACKET]; 3],
    pub inv: [[f32; PACKET]; 3],
    pub negative: [u32; 3],
}

impl PacketBoxes {
    pub fn new(queries: &[Query; PACKET]) -> Self {
        let mut p = PacketBoxes {
            origin: [[0.0; PACKET]; 3],
            inv: [[1.0; PACKET]; 3],
            negative: [0; 3],
        };
        for (l, q) in queries.iter().enumerate() {
            let (origin, inv, negative) = q.box_ray();
            for a in 0..3 {
                p.origin[a][l] = origin[a];
                p.inv[a][l] = inv[a];
                p.negative[a] |= (negative[a] as u32) << l;
            }
        }
        p
    }

    /// Entry distances of slot `slot` of `node` for every lane (clamped
    /// below by 0), and the mask of the lanes that enter it before their
    /// `tmax`: per lane, the operations of the single-ray slab test.
    #[inline(always)]
    pub fn slab<const SIMD: u8>(
        &self,
        node: &Node8,
        slot: usize,
        tmax: &[f32; PACKET],
        t: &mut [f32; PACKET],
    ) -> u32 {
        #[cfg(target_arch = "x86_64")]
        {
            // SAFETY: the SIMD entry points run only where their kernel is
            // supported (checked in `Accel::set_kernel` and `Kernel::best`).
            if SIMD == AVX512 {
                return unsafe { self.slab_avx512(node, slot, tmax, t) };
            }
            if SIMD == AVX2 {
                return unsafe { self.slab_avx2(node, slot, tmax, t) };
            }
        }
        self.slab_portable(node, slot, tmax, t)
    }

    #[inline(always)]
    fn slab_portable(
        &self,
        node: &Node8,
        slot: usize,
        tmax: &[f32; PACKET],
        t: &mut [f32; PACKET],
    ) -> u32 {
        let b = &node.bounds;
        let mut mask = 0;
        for l in 0..PACKET {
            let side = |a: usize| {
                let (lo, hi) = (b[2 * a][slot], b[2 * a + 1][slot]);
                let (near, far) = if self.negative[a] >> l & 1 != 0 {
                    (hi, lo)
                } else {
                    (lo, hi)
                };
                let (o, inv) = (self.origin[a][l], self.inv[a][l]);
                ((near - o) * inv, (far - o) * inv)
            };
            let (nx, fx) = side(0);
            let (ny, fy) = side(1);
            let (nz, fz) = side(2);
            let t0 = nx.max(ny).max(nz.max(0.0));
            let t1 = fx.min(fy).min(fz.min(tmax[l]));
            t[l] = t0;
            mask |= ((t0 <= t1) as u32) << l;
        }
        mask
    }

    /// [`PacketBoxes::slab_portable`] in AVX2, eight lanes at a time, with
    /// the single-ray AVX2 test's `max`/`min` instructions.
    ///
    /// # Safety
    /// The CPU must support AVX2 (inlined into the `target_feature` entry
    /// points, as `traverse.rs`'s `slab_avx2`).
    #[cfg(target_arch = "x86_64")]
    #[inline(always)]
    unsafe fn slab_avx2(
        &self,
        node: &Node8,
        slot: usize,
        tmax: &[f32; PACKET],
        t: &mut [f32; PACKET],
    ) -> u32 {
        use std::arch::x86_64::*;
        let b = &node.bounds;
        let mut mask = 0;
        // SAFETY: every array holds 16 f32, read and written 8 at a time
        // at offsets 0 and 8 with unaligned loads and stores.
        unsafe {
            for half in [0, 8] {
                // A macro, as in `slab_avx512`.
                macro_rules! side {
                    ($a:expr) => {{
                        let lo = _mm256_set1_ps(b[2 * $a][slot]);
                        let hi = _mm256_set1_ps(b[2 * $a + 1][slot]);
                        let inv = _mm256_loadu_ps(self.inv[$a][half..].as_ptr());
                        // The sign bit of `inv` chooses the max plane.
                        let near = _mm256_blendv_ps(lo, hi, inv);
                        let far = _mm256_blendv_ps(hi, lo, inv);
                        let o = _mm256_loadu_ps(self.origin[$a][half..].as_ptr());
                        (
                            _mm256_mul_ps(_mm256_sub_ps(near, o), inv),
                            _mm256_mul_ps(_mm256_sub_ps(far, o), inv),
                        )
                    }};
                }
                let (nx, fx) = side!(0);
                let (ny, fy) = side!(1);
                let (nz, fz) = side!(2);
                let t0 = _mm256_max_ps(
                    _mm256_max_ps(nx, ny),
                    _mm256_max_ps(nz, _mm256_setzero_ps()),
                );
                let t1 = _mm256_min_ps(
                    _mm256_min_ps(fx, fy),
                    _mm256_min_ps(fz, _mm256_loadu_ps(tmax[half..].as_ptr())),
                );
                _mm256_storeu_ps(t[half..].as_mut_ptr(), t0);
                let m = _mm256_movemask_ps(_mm256_cmp_ps::<_CMP_LE_OQ>(t0, t1)) as u32;
                mask |= m << half;
            }
        }
        mask
    }

    /// [`PacketBoxes::slab_portable`] in AVX-512, all sixteen lanes at once.
    ///
    /// # Safety
    /// The CPU must support AVX-512F (inlined into the `target_feature`
    /// entry point).
    #[cfg(target_arch = "x86_64")]
    #[inline(always)]
    unsafe fn slab_avx512(
        &self,
        node: &Node8,
        slot: usize,
        tmax: &[f32; PACKET],
        t: &mut [f32; PACKET],
    ) -> u32 {
        use std::arch::x86_64::*;
        let b = &node.bounds;
        // SAFETY: every array holds 16 f32 (unaligned loads and stores).
        unsafe {
            // A macro, not a closure: closures do not inherit the caller's
            // target features, so the intrinsics would not inline into one.
            macro_rules! side {
                ($a:expr) => {{
                    let lo = _mm512_set1_ps(b[2 * $a][slot]);
                    let hi = _mm512_set1_ps(b[2 * $a + 1][slot]);
                    let neg = self.negative[$a] as __mmask16;
                    let near = _mm512_mask_blend_ps(neg, lo, hi);
                    let far = _mm512_mask_blend_ps(neg, hi, lo);
                    let o = _mm512_loadu_ps(self.origin[$a].as_ptr());
                    let inv = _mm512_loadu_ps(self.inv[$a].as_ptr());
                    (
                        _mm512_mul_ps(_mm512_sub_ps(near, o), inv),
                        _mm512_mul_ps(_mm512_sub_ps(far, o), inv),
                    )
                }};
            }
            let (nx, fx) = side!(0);
            let (ny, fy) = side!(1);
            let (nz, fz) = side!(2);
            let t0 = _mm512_max_ps(
                _mm512_max_ps(nx, ny),
                _mm512_max_ps(nz, _mm512_setzero_ps()),
            );
            let t1 = _mm512_min_ps(
                _mm512_min_ps(fx, fy),
                _mm512_min_ps(fz, _mm512_loadu_ps(tmax.as_ptr())),
            );
            _mm512_storeu_ps(t.as_mut_ptr(), t0);
            _mm512_cmp_ps_mask::<_CMP_LE_OQ>(t0, t1) as u32
        }
    }
}

/// Walks the subtree `code` ray by ray for each lane of `lanes`, from the
/// lane's closest hit so far, the rays' walks interleaved one node or
/// leaf at a time (as `closest_many`'s) so that their cache misses
/// overlap. `stacks` holds [`SWITCH`] single-ray stacks end to end, one
/// for each lane of `lanes` (at most [`SWITCH`] lanes).
#[inline(always)]
pub(super) fn finish_alone<const SIMD: u8>(
    queries: &[Query; PACKET],
    lanes: u32,
    code: u32,
    best_t: &mut [f32; PACKET],
    best: &mut [Option<(usize, TriangleHit)>; PACKET],
    stacks: &mut [MaybeUninit<Entry>],
) {
    let stride = stacks.len() / SWITCH;
    let keep = |_, _, _| true;
    let mut walks: [(usize, Walk); SWITCH] =
        std::array::from_fn(|_| (0, Walk::subtree(code, 0.0, None)));
    let mut n = 0;
    for l in SetBits(lanes) {
        walks[n] = (l, Walk::subtree(code, best_t[l], best[l]));
        n += 1;
    }
    let mut running = (1u32 << n) - 1;
    while running != 0 {
        for k in SetBits(running) {
            let (l, walk) = &mut walks[k];
            let stack = &mut stacks[k * stride..(k + 1) * stride];
            let more = if SIMD == PORTABLE {
                walk.step::<false>(&queries[*l], &keep, stack)
            } else {
                walk.step::<true>(&queries[*l], &keep, stack)
            };
            if !more {
                running &= !(1 << k);
                best_t[*l] = walk.best_t;
                best[*l] = walk.best;
            }
        }
    }
}

/// Tests leaf `code`'s triangles for each lane of `lanes`, ray by ray
/// with the single-ray leaf test, against the lane's closest hit so far.
#[inline(always)]
pub(super) fn leaf_step_lanes<const SIMD: u8>(
    queries: &[Query; PACKET],
    lanes: u32,
    code: u32,
    best_t: &mut [f32; PACKET],
    best: &mut [Option<(usize, TriangleHit)>; PACKET],
) {
    let keep = |_, _, _| true;
    for l in SetBits(lanes) {
        let (q, t, b) = (&queries[l], &mut best_t[l], &mut best[l]);
        if SIMD == PORTABLE {
            leaf_step::<false>(q, code, &keep, t, b);
        } else {
            leaf_step::<true>(q, code, &keep, t, b);
        }
    }
}

/// A subtree that at most this many of a packet's rays enter is walked by
/// each of them alone ([`finish_alone`]), as Embree's hybrid packets do:
/// below a few rays, testing a node for the whole packet costs more than
/// the rays' own walks. Six was the best of 0, 2, 4, 6 and 8 on the
/// 1M-triangle mesh's random rays, one thread, 2026-12-06 (two rounds:
/// packets 0.41, 0.51–0.52, 0.59–0.64, 0.64–0.66 and 0.53–0.61 Mrays/s;
/// three more of 4 and 6: 0.57–0.69 and 0.72–0.76), and within the noise
/// of 2 and 4 on its camera rays.
pub(super) const SWITCH: usize = 6;

/// How a packet walk enters an inner node: each lane's own box test
/// ([`PacketBoxes`], here) or the interval test that stands for all of
/// them (`frustum.rs`).
pub(super) trait NodeEntry {
    /// A deferred subtree.
    type Deferred: Copy;

    /// Visits inner node `node` for the lanes of `active`, whose closest
    /// hits so far lie at `best_t`: writes every entered child but the
    /// nearest to `stack`, farthest first ([`defer_all_but_nearest`]).
    /// `None` if no child is entered.
    fn enter<const SIMD: u8>(
        &self,
        q0: &Query,
        node: &Node8,
        active: u32,
        best_t: &[f32; PACKET],
        stack: &mut [Self::Deferred],
    ) -> Option<Entered>;

    /// The code of deferred subtree `e` and its lanes that may still find
    /// a hit before their `best_t` there.
    fn resume<const SIMD: u8>(e: &Self::Deferred, best_t: &[f32; PACKET]) -> (u32, u32);
}

/// What [`NodeEntry::enter`] did: how many children it deferred to the
/// stack, and the nearest child's code and lanes, visited next.
pub(super) struct Entered {
    pub deferred: usize,
    pub code: u32,
    pub lanes: u32,
}

/// The end of both [`NodeEntry::enter`]s: of the entered children
/// `sorted` (decreasing entry distance, the nearest last), writes the
/// deferred form of every one but the nearest to `stack`, and returns
/// the nearest's code and lanes; `None` when `sorted` is empty.
#[inline(always)]
pub(super) fn defer_all_but_nearest<H, E>(
    sorted: &[H],
    stack: &mut [E],
    deferred: impl Fn(&H) -> E,
    code_and_lanes: impl Fn(&H) -> (u32, u32),
) -> Option<Entered> {
    let (nearest, farther) = sorted.split_last()?;
    debug_assert!(
        stack.len() >= farther.len(),
        "the stack holds every deferred child"
    );
    for (slot, h) in stack.iter_mut().zip(farther) {
        *slot = deferred(h);
    }
    let (code, lanes) = code_and_lanes(nearest);
    Some(Entered {
        deferred: farther.len(),
        code,
        lanes,
    })
}

/// Closest hits of the rays of `queries` in the lanes of `live`, each the
/// leaf-order triangle index and the hit (the one the single-ray walk
/// finds): the packet walks the tree together, entering inner nodes as
/// `nodes` says, until at most [`SWITCH`] lanes enter a subtree, which
/// they finish alone. `stack` must hold `(WIDTH − 1) · depth + 1`
/// entries, `singles` [`SWITCH`] times as many (the stacks of
/// [`finish_alone`]).
#[inline(always)]
pub(super) fn walk_packet<const SIMD: u8, N: NodeEntry>(
    queries: &[Query; PACKET],
    nodes: &N,
    live: u32,
    stack: &mut [N::Deferred],
    singles: &mut [MaybeUninit<Entry>],
) -> [Option<(usize, TriangleHit)>; PACKET] {
    let mut best = [None; PACKET];
    let mut best_t: [f32; PACKET] = std::array::from_fn(|l| queries[l].tmax());
    let q0 = &queries[0];
    let mut sp = 0;
    let mut code = 0u32;
    let mut active = live;
    loop {
        if code & LEAF_BIT != 0 {
            leaf_step_lanes::<SIMD>(queries, active, code, &mut best_t, &mut best);
        } else if active.count_ones() as usize <= SWITCH {
            finish_alone::<SIMD>(queries, active, code, &mut best_t, &mut best, singles);
        } else {
            let node = &q0.wide.nodes[code as usize];
            if let Some(e) = nodes.enter::<SIMD>(q0, node, active, &best_t, &mut stack[sp..]) {
                sp += e.deferred;
                code = e.code;
                active = e.lanes;
                continue;
            }
        }
        loop {
            if sp == 0 {
                return best;
            }
            sp -= 1;
            let (child, lanes) = N::resume::<SIMD>(&stack[sp], &best_t);
            if lanes != 0 {
                code = child;
                active = lanes;
                break;
            }
        }
    }
}

/// The per-lane walk: each child box tested against every active lane.
impl NodeEntry for PacketBoxes {
    type Deferred = PacketEntry;

    #[inline(always)]
    fn enter<const SIMD: u8>(
        &self,
        q0: &Query,
        node: &Node8,
        active: u32,
        best_t: &[f32; PACKET],
        stack: &mut [PacketEntry],
    ) -> Option<Entered> {
        // Entered children, each with the nearest entry among the lanes
        // that enter it, sorted by decreasing nearest entry.
        let mut hits = [(
            0.0,
            PacketEntry {
                code: 0,
                mask: 0,
                t: [0.0; PACKET],
            },
        ); WIDTH];
        let mut n = 0;
        for slot in 0..WIDTH {
            let mut t = [0.0; PACKET];
            let mask = self.slab::<SIMD>(node, slot, best_t, &mut t) & active;
            if mask == 0 {
                continue;
            }
            if q0.prefetches() {
                prefetch(q0, node.child[slot]);
            }
            // Entry distances are ≥ 0, whose bits order as the values do:
            // an integer min, which vectorises.
            let nearest = (0..PACKET)
                .map(|l| {
                    if mask >> l & 1 != 0 {
                        t[l].to_bits()
                    } else {
                        u32::MAX
                    }
                })
                .min()
                .map_or(f32::INFINITY, f32::from_bits);
            let e = PacketEntry {
                code: node.child[slot],
                mask,
                t,
            };
            insert_by_decreasing_t(&mut hits, n, (nearest, e), |h| h.0);
            n += 1;
        }
        defer_all_but_nearest(&hits[..n], stack, |h| h.1, |h| (h.1.code, h.1.mask))
    }

    #[inline(always)]
    fn resume<const SIMD: u8>(e: &PacketEntry, best_t: &[f32; PACKET]) -> (u32, u32) {
        let mut live = 0;
        for l in SetBits(e.mask) {
            live |= ((e.t[l] <= best_t[l]) as u32) << l;
        }
        (e.code, live)
    }
}

/// [`walk_packet`] over all `count` rays, [`PACKET`] consecutive rays
/// at a time; `found(i, hit)` receives each ray's hit.
#[inline(always)]
fn closest_packets<'a, const SIMD: u8>(
    count: usize,
    depth: usize,
    query: &impl Fn(usize) -> Query<'a>,
    found: &mut impl FnMut(usize, Option<(usize, TriangleHit)>),
) {
    let need = stack_entries(depth);
    let empty = PacketEntry {
        code: 0,
        mask: 0,
        t: [0.0; PACKET],
    };
    let mut inline = [empty; STACK_INLINE];
    let mut heap = Vec::new();
    let stack: &mut [PacketEntry] = if need <= STACK_INLINE {
        &mut inline
    } else {
        heap.resize(need, empty);
        &mut heap
    };
    let mut singles = vec![MaybeUninit::<Entry>::uninit(); SWITCH * need];
    let empty = FrustumEntry {
        code: 0,
        mask: 0,
        t: 0.0,
    };
    let mut frustum_stack = vec![empty; need];
    for first in (0..count).step_by(PACKET) {
        let n = PACKET.min(count - first);
        // A last, partial packet repeats its last ray in the unused lanes,
        // which are never active.
        let queries: [Query<'a>; PACKET] = std::array::from_fn(|l| query(first + l.min(n - 1)));
        let live = (1 << n) - 1;
        let boxes = PacketBoxes::new(&queries);
        // Packets of one octant take the frustum walk, others the per-lane one.
        let hits = match Frustum::new(&boxes) {
            Some(frustum) => {
                let nodes = FrustumWalk {
                    frustum,
                    boxes: &boxes,
                };
                walk_packet::<SIMD, _>(&queries, &nodes, live, &mut frustum_stack, &mut singles)
            }
            None => walk_packet::<SIMD, _>(&queries, &boxes, live, stack, &mut singles),
        };
        for (l, hit) in hits.into_iter().take(n).enumerate() {
            found(first + l, hit);
        }
    }
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn closest_packets_avx2<'a>(
    count: usize,
    depth: usize,
    query: &impl Fn(usize) -> Query<'a>,
    found: &mut impl FnMut(usize, Option<(usize, TriangleHit)>),
) {
    closest_packets::<AVX2>(count, depth, query, found)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,avx512f")]
fn closest_packets_avx512<'a>(
    count: usize,
    depth: usize,
    query: &impl Fn(usize) -> Query<'a>,
    found: &mut impl FnMut(usize, Option<(usize, TriangleHit)>),
) {
    closest_packets::<AVX512>(count, depth, query, found)
}

/// Closest hits of `count` rays in packets of [`PACKET`] consecutive rays
/// with `kernel` (which this CPU must support).
pub(super) fn closest_hits_packets<'a>(
    kernel: Kernel,
    depth: usize,
    count: usize,
    query: &impl Fn(usize) -> Query<'a>,
    found: &mut impl FnMut(usize, Option<(usize, TriangleHit)>),
) {
    match kernel {
        // SAFETY: `kernel` is supported (the caller's contract).
        #[cfg(target_arch = "x86_64")]
        Kernel::Avx2 => unsafe { closest_packets_avx2(count, depth, query, found) },
        #[cfg(target_arch = "x86_64")]
        Kernel::Avx512 => unsafe { closest_packets_avx512(count, depth, query, found) },
        _ => closest_packets::<PORTABLE>(count, depth, query, found),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::accel::wide::{TEST_BOXES, Wide};
    use glam::Vec3;

    /// Every lane of the packet box test gives the single-ray test's entry
    /// distance and hit bit for its ray, slot by slot, with each kernel:
    /// rays of all eight octants, with zero components of both signs, from
    /// inside and outside the boxes, each with its own `tmax`.
    #[test]
    fn lanes_match_the_single_ray_box_test() {
        let wide = Wide::default();
        let node = Node8::with_boxes(&TEST_BOXES);
        let mut queries = Vec::new();
        let centres = [
            Vec3::splat(1.5),
            Vec3::new(-2.5, 0.0, 0.0),
            Vec3::ZERO,
            Vec3::new(1.5, 5.5, 1.5),
            Vec3::splat(4.5),
            Vec3::new(0.5, -0.5, 0.0),
            Vec3::new(-1.5, 2.0, -3.5),
        ];
        for i in 0..PACKET {
            let f = i as f32;
            // Origins all around (every octant of directions), each ray
            // aimed near one box's centre.
            let o = Vec3::new(
                8.0 * (f * 2.4).cos(),
                6.0 * (f * 1.7).sin(),
                7.0 * (f * 0.9 + 1.0).cos(),
            );
            let target = centres[i % centres.len()] + Vec3::splat((f * 0.37).sin() * 0.3);
            let mut d = (target - o).normalize();
            let mut o = o;
            // Axis-parallel rays with zero components of either sign.
            match i {
                3 => (o, d) = (Vec3::new(1.5, 1.5, -9.0), Vec3::new(0.0, -0.0, 1.0)),
                11 => (o, d) = (Vec3::new(9.0, 0.2, 0.0), Vec3::new(-1.0, 0.0, -0.0)),
                _ => {}
            }
            let tmax = if i % 3 == 0 { 9.0 } else { f32::INFINITY };
            queries.push(Query::new(&wide, &[], o, d, tmax, false));
        }
        let queries: [Query; PACKET] = queries.try_into().ok().unwrap();
        let boxes = PacketBoxes::new(&queries);
        let tmax: [f32; PACKET] = std::array::from_fn(|l| queries[l].tmax());
        let mut kernels = vec![PORTABLE];
        if Kernel::Avx2.is_supported() {
            kernels.push(AVX2);
        }
        if Kernel::Avx512.is_supported() {
            kernels.push(AVX512);
        }
        let (mut hits, mut misses) = (0, 0);
        for simd in kernels {
            for slot in 0..WIDTH {
                let mut t = [f32::NAN; PACKET];
                let mask = match simd {
                    PORTABLE => boxes.slab::<PORTABLE>(&node, slot, &tmax, &mut t),
                    AVX2 => boxes.slab::<AVX2>(&node, slot, &tmax, &mut t),
                    _ => boxes.slab::<AVX512>(&node, slot, &tmax, &mut t),
                };
                for (l, q) in queries.iter().enumerate() {
                    let mut alone = [f32::NAN; WIDTH];
                    let alone_mask = q.slab_alone(&node, &mut alone);
                    let hit = alone_mask >> slot & 1;
                    assert_eq!(mask >> l & 1, hit, "kernel {simd} slot {slot} lane {l}");
                    if hit == 1 {
                        assert_eq!(t[l], alone[slot], "kernel {simd} slot {slot} lane {l}");
                        hits += 1;
                    } else {
                        misses += 1;
                    }
                }
            }
        }
        assert!(hits > 20 && misses > 20, "{hits} hits, {misses} misses");
    }
}
