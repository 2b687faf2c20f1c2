//! Single-ray traversal of the 8-wide BVH. Each step tests one node's eight
//! child boxes at once (the slab test with the near and far planes chosen
//! once per ray from the signs of its direction, so empty slots and the
//! min/max swap cost nothing), then visits the hit children nearest first:
//! it continues into the nearest and pushes the others, sorted, with their
//! entry distances, so that popped entries beyond the closest hit so far
//! are dropped. Occlusion rays push without sorting and stop at the first
//! hit. On trees larger than the caches, each node's entered children (an
//! only child too) are prefetched as soon as its box test finds them, so
//! that their cache misses overlap (memory-level parallelism) instead of
//! coming one after another. A
//! leaf's triangles (up to eight, in one or two blocks) are tested at once
//! by the 8-lane test of `block.rs` in the AVX2 kernel, which leaves the
//! lanes it hits to be visited (most leaves have none or one), and one by
//! one in the portable kernel. The same code is compiled twice: portable (LLVM picks
//! the vector width it may) and for AVX2, chosen at run time; both make
//! the same IEEE operations in the same order, so they find the same hits.
//! The traversal is a [`Walk`] advanced one node or leaf at a time, so that
//! [`closest_many`] can interleave several rays' walks on one thread.
//!
//! One of the crate's seven modules with `unsafe` code (the others are
//! `block.rs`, for its AVX intrinsics, `packet.rs` and `frustum.rs`, for
//! their AVX2 and AVX-512 box tests, `scan.rs`, for its AVX-512
//! triangle scan, `integrator/wavefront.rs`, for its AVX-512 lanes, and
//! `huge_pages.rs`, for `madvise`):
//! calling the AVX2 functions (after the CPU check) and the uninitialised
//! traversal stack (zeroing 2 KB per ray would cost more than a node
//! test).
#![allow(unsafe_code)]

use super::block::{LANES, TriangleBlock};
use super::watertight::{TriangleHit, WatertightRay};
use super::wide::{LEAF_BIT, Node8, WIDTH, Wide, leaf_parts};
use crate::stages::{Visit, visited};
use glam::Vec3;
use std::mem::MaybeUninit;

/// Which compiled traversal runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kernel {
    /// Plain Rust, for any CPU.
    Portable,
    /// 8-lane AVX2 box tests (x86-64 CPUs since 2013).
    Avx2,
    /// AVX2's single-ray traversal (an 8-wide node needs no more lanes),
    /// and packets of 16 rays tested with 16-lane AVX-512 instructions.
    Avx512,
}

impl Kernel {
    /// The fastest kernel this CPU runs.
    pub fn best() -> Kernel {
        [Kernel::Avx512, Kernel::Avx2]
            .into_iter()
            .find(|k| k.is_supported())
            .unwrap_or(Kernel::Portable)
    }

    /// True if this CPU can run the kernel.
    pub fn is_supported(self) -> bool {
        match self {
            Kernel::Portable => true,
            #[cfg(target_arch = "x86_64")]
            Kernel::Avx2 => std::arch::is_x86_feature_detected!("avx2"),
            #[cfg(target_arch = "x86_64")]
            Kernel::Avx512 => {
                std::arch::is_x86_feature_detected!("avx2")
                    && std::arch::is_x86_feature_detected!("avx512f")
            }
            #[cfg(not(target_arch = "x86_64"))]
            Kernel::Avx2 | Kernel::Avx512 => false,
        }
    }

    /// Every kernel this CPU runs.
    pub fn available() -> Vec<Kernel> {
        [Kernel::Portable, Kernel::Avx2, Kernel::Avx512]
            .into_iter()
            .filter(|k| k.is_supported())
            .collect()
    }
}

/// The ray as the box test sees it: origin, reciprocal direction, and for
/// each axis whether it enters a box by the max plane (its reciprocal is
/// negative) and leaves by the min one.
struct BoxRay {
    origin: [f32; 3],
    inv: [f32; 3],
    enters_by_max: [bool; 3],
}

impl BoxRay {
    /// Zero direction components (of either sign) become a tiny positive
    /// value: 1/(−0) = −∞ times a zero distance gives NaN, which would drop
    /// axis-parallel rays. The triangle test still uses the exact direction.
    pub fn new(origin: Vec3, direction: Vec3) -> Self {
        let safe = Vec3::select(direction.cmpeq(Vec3::ZERO), Vec3::splat(1e-30), direction);
        let inv = safe.recip();
        BoxRay {
            origin: origin.to_array(),
            inv: inv.to_array(),
            enters_by_max: inv.cmplt(Vec3::ZERO).into(),
        }
    }

    /// The index in [`Node8::bounds`] (min and max planes of x, y, z) of
    /// the plane by which the ray enters along `axis`. A bool's index, not
    /// a stored one, so that the compiler sees it is below 6.
    #[inline(always)]
    fn near(&self, axis: usize) -> usize {
        2 * axis + self.enters_by_max[axis] as usize
    }

    /// The plane by which the ray leaves along `axis`.
    #[inline(always)]
    fn far(&self, axis: usize) -> usize {
        2 * axis + 1 - self.enters_by_max[axis] as usize
    }
}

/// One ray's query: the tree, its leaves' triangle blocks, the ray as the
/// box test and the triangle test each see it, and the far end of the ray.
pub(super) struct Query<'a> {
    pub wide: &'a Wide,
    pub blocks: &'a [TriangleBlock],
    boxes: BoxRay,
    triangles: WatertightRay,
    tmax: f32,
    /// Prefetch the entered children of each node ([`prefetch`]).
    prefetch: bool,
}

impl<'a> Query<'a> {
    pub fn new(
        wide: &'a Wide,
        blocks: &'a [TriangleBlock],
        origin: Vec3,
        direction: Vec3,
        tmax: f32,
        prefetch: bool,
    ) -> Self {
        Query {
            wide,
            blocks,
            boxes: BoxRay::new(origin, direction),
            triangles: WatertightRay::new(origin, direction),
            tmax,
            prefetch,
        }
    }

    /// The far end of the ray.
    #[inline(always)]
    pub fn tmax(&self) -> f32 {
        self.tmax
    }

    /// Whether the traversal prefetches entered children.
    #[inline(always)]
    pub fn prefetches(&self) -> bool {
        self.prefetch
    }

    /// The portable single-ray box test of `node`'s eight slots (for
    /// tests that compare other box tests with it).
    #[cfg(test)]
    pub fn slab_alone(&self, node: &Node8, t: &mut [f32; WIDTH]) -> u32 {
        slab::<false>(node, &self.boxes, self.tmax, t)
    }

    /// The box test's view of the ray: origin, reciprocal direction, and
    /// per axis whether it enters a box by the max plane.
    #[inline(always)]
    pub fn box_ray(&self) -> ([f32; 3], [f32; 3], [bool; 3]) {
        let b = &self.boxes;
        (b.origin, b.inv, b.enters_by_max)
    }
}

/// A deferred subtree: its slot code and the distance at which the ray
/// enters its box.
#[derive(Clone, Copy)]
pub(super) struct Entry {
    code: u32,
    t: f32,
}

/// Entries a stack holds without going to the heap: enough for 36 levels
/// (each level defers at most seven children).
pub(super) const STACK_INLINE: usize = 256;

/// Entries a traversal stack needs for a tree `depth` nodes deep: each
/// level defers at most seven children.
#[inline(always)]
pub(super) fn stack_entries(depth: usize) -> usize {
    (WIDTH - 1) * depth + 1
}

/// The indices of a mask's set bits, lowest first: the slots a box test
/// entered, the lanes of a packet, the lanes a leaf test hit.
#[derive(Clone, Copy)]
pub(super) struct SetBits(pub u32);

impl Iterator for SetBits {
    type Item = usize;

    #[inline(always)]
    fn next(&mut self) -> Option<usize> {
        if self.0 == 0 {
            return None;
        }
        let i = self.0.trailing_zeros() as usize;
        self.0 &= self.0 - 1;
        Some(i)
    }
}

/// Inserts `e` into `sorted[..n]` (n < [`WIDTH`]), which stays in
/// decreasing order of `t`: the nearest entry last, to be visited first.
/// Of equal distances the later inserted goes nearer the end.
#[inline(always)]
pub(super) fn insert_by_decreasing_t<E: Copy>(
    sorted: &mut [E; WIDTH],
    n: usize,
    e: E,
    t: impl Fn(&E) -> f32,
) {
    // `min` lets the compiler see every index is in bounds.
    let mut j = n.min(WIDTH - 1);
    while j > 0 && t(&sorted[j - 1]) < t(&e) {
        sorted[j] = sorted[j - 1];
        j -= 1;
    }
    sorted[j] = e;
}

/// Evaluates `$body` with `$stack` bound to an uninitialised traversal
/// stack large enough for `$wide`: inline, or on the heap for very deep
/// trees. A macro, not a closure: closures do not inherit the caller's
/// target features, so the AVX2 box test would not inline into them.
macro_rules! with_stack {
    ($wide:expr, $stack:ident => $body:expr) => {{
        let need = stack_entries($wide.depth);
        if need <= STACK_INLINE {
            let mut buf = [const { MaybeUninit::<Entry>::uninit() }; STACK_INLINE];
            let $stack = &mut buf[..];
            $body
        } else {
            let mut buf = vec![MaybeUninit::<Entry>::uninit(); need];
            let $stack = &mut buf[..];
            $body
        }
    }};
}

/// Entry distances of the eight slots (clamped below by 0) and the mask of
/// the slots the ray enters before `tmax`: portable code.
#[inline(always)]
fn slab_portable(node: &Node8, r: &BoxRay, tmax: f32, t_enter: &mut [f32; WIDTH]) -> u32 {
    let b = &node.bounds;
    let [ox, oy, oz] = r.origin;
    let [ix, iy, iz] = r.inv;
    let mut mask = 0;
    for i in 0..WIDTH {
        let nx = (b[r.near(0)][i] - ox) * ix;
        let ny = (b[r.near(1)][i] - oy) * iy;
        let nz = (b[r.near(2)][i] - oz) * iz;
        let fx = (b[r.far(0)][i] - ox) * ix;
        let fy = (b[r.far(1)][i] - oy) * iy;
        let fz = (b[r.far(2)][i] - oz) * iz;
        let t0 = nx.max(ny).max(nz.max(0.0));
        let t1 = fx.min(fy).min(fz.min(tmax));
        t_enter[i] = t0;
        mask |= ((t0 <= t1) as u32) << i;
    }
    mask
}

/// [`slab_portable`] in AVX2: the same operations, eight lanes at a time.
///
/// # Safety
/// The CPU must support AVX2. Not a `#[target_feature]` function, which
/// could not be `inline(always)`: it inlines into the AVX2 entry points,
/// whose features the intrinsics then inline under.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
unsafe fn slab_avx2(node: &Node8, r: &BoxRay, tmax: f32, t_enter: &mut [f32; WIDTH]) -> u32 {
    use std::arch::x86_64::*;
    let b = &node.bounds;
    // SAFETY: each plane is 8 contiguous f32; unaligned loads need no
    // alignment, and `t_enter` holds 8 f32.
    unsafe {
        let plane = |p: usize, o: f32, inv: f32| {
            let v = _mm256_loadu_ps(b[p].as_ptr());
            _mm256_mul_ps(_mm256_sub_ps(v, _mm256_set1_ps(o)), _mm256_set1_ps(inv))
        };
        let [ox, oy, oz] = r.origin;
        let [ix, iy, iz] = r.inv;
        let nx = plane(r.near(0), ox, ix);
        let ny = plane(r.near(1), oy, iy);
        let nz = plane(r.near(2), oz, iz);
        let fx = plane(r.far(0), ox, ix);
        let fy = plane(r.far(1), oy, iy);
        let fz = plane(r.far(2), oz, iz);
        let t0 = _mm256_max_ps(
            _mm256_max_ps(nx, ny),
            _mm256_max_ps(nz, _mm256_setzero_ps()),
        );
        let t1 = _mm256_min_ps(
            _mm256_min_ps(fx, fy),
            _mm256_min_ps(fz, _mm256_set1_ps(tmax)),
        );
        _mm256_storeu_ps(t_enter.as_mut_ptr(), t0);
        _mm256_movemask_ps(_mm256_cmp_ps::<_CMP_LE_OQ>(t0, t1)) as u32
    }
}

/// Asks the memory system for the node or the leaf triangles that slot
/// code `code` names, so that the misses of a node's entered children
/// overlap instead of following one another as the traversal reaches
/// each (a hint: it changes no result).
#[inline(always)]
pub(super) fn prefetch(q: &Query, code: u32) {
    #[cfg(target_arch = "x86_64")]
    {
        use std::arch::x86_64::{_MM_HINT_T0, _mm_prefetch};
        if code & LEAF_BIT == 0 {
            let start = q.wide.nodes[code as usize..].as_ptr().cast::<i8>();
            let line = start.wrapping_sub(start as usize % 64);
            for k in 0..NODE_LINES {
                // SAFETY: a prefetch never faults; these are the lines
                // that hold the node's bytes.
                unsafe { _mm_prefetch::<_MM_HINT_T0>(line.wrapping_add(64 * k)) };
            }
            return;
        }
        let (block, count) = leaf_parts(code);
        let start = q.blocks[block..].as_ptr().cast::<i8>();
        let bytes = size_of::<TriangleBlock>() * count.div_ceil(LANES);
        // Every 64-byte line that holds a byte of [start, start + bytes):
        // from the line of the first byte on (a block is 144 bytes, so one
        // can start anywhere in a line).
        let mut line = start.wrapping_sub(start as usize % 64);
        let end = start.wrapping_add(bytes);
        while line < end {
            // SAFETY: a prefetch never faults; the addresses lie in the
            // lines of `q.blocks` (checked by the slicing).
            unsafe { _mm_prefetch::<_MM_HINT_T0>(line) };
            line = line.wrapping_add(64);
        }
    }
}

/// The 64-byte lines a node can span: it starts at most
/// `64 − align_of::<Node8>()` bytes into its first line.
const NODE_LINES: usize = (64 - align_of::<Node8>() + size_of::<Node8>()).div_ceil(64);

#[inline(always)]
fn slab<const AVX2: bool>(node: &Node8, r: &BoxRay, tmax: f32, t: &mut [f32; WIDTH]) -> u32 {
    #[cfg(target_arch = "x86_64")]
    if AVX2 {
        // SAFETY: the AVX2 entry points run only where `Kernel::Avx2` is
        // supported (checked in `Accel::set_kernel` and `Kernel::best`).
        return unsafe { slab_avx2(node, r, tmax, t) };
    }
    slab_portable(node, r, tmax, t)
}

/// The 8-lane test of a leaf (its first `count` triangles from
/// `blocks[0]` on) in the AVX2 kernel; `None` (the scalar test, lane by
/// lane) in the portable one, or where a lane needs the scalar test's f64
/// fallback.
#[inline(always)]
fn leaf_hits<const AVX2: bool>(
    q: &Query,
    blocks: &[TriangleBlock],
    count: usize,
    tmax: f32,
) -> Option<super::block::BlockHits> {
    #[cfg(target_arch = "x86_64")]
    if AVX2 {
        // SAFETY: the AVX2 entry points run only where `Kernel::Avx2` is
        // supported (checked in `Accel::set_kernel` and `Kernel::best`).
        return unsafe { super::block::intersect_leaf(&q.triangles, blocks, count, tmax) };
    }
    let _ = (q, blocks, count, tmax);
    None
}

/// Calls `visit(slot, hit)` for the triangles of leaf `code` that hit
/// within (0, `tmax()`), in lane order, until it returns false; `tmax` is
/// read again before each lane (a visit may bring it closer). The 8-lane
/// test tests all lanes with the `tmax` the leaf starts with and leaves
/// the lanes it hits, each checked again against the `tmax` of its turn
/// (a loop over the hit lanes only, not over all: fewer branches to
/// mispredict); the scalar test (portable kernel, or a lane needing the
/// f64 fallback) goes through every lane. Both visit the same hits.
#[inline(always)]
fn leaf_lanes<const AVX2: bool>(
    q: &Query,
    code: u32,
    tmax: impl Fn() -> f32,
    mut visit: impl FnMut(usize, TriangleHit) -> bool,
) {
    let (b, count) = leaf_parts(code);
    let blocks = &q.blocks[b..];
    match leaf_hits::<AVX2>(q, blocks, count, tmax()) {
        Some(hits) => {
            for lane in SetBits(hits.mask) {
                if let Some(h) = hits.within(lane, tmax())
                    && !visit(LANES * b + lane, h)
                {
                    return;
                }
            }
        }
        None => {
            for lane in 0..count {
                let [v0, v1, v2] = blocks[lane / LANES].triangle(lane % LANES);
                if let Some(h) = q.triangles.intersect_a(v0, v1, v2, tmax())
                    && !visit(LANES * b + lane, h)
                {
                    return;
                }
            }
        }
    }
}

/// Tests the triangles of leaf `code` for the closest accepted hit before
/// `best_t`, bringing `best_t` and `best` to it.
#[inline(always)]
pub(super) fn leaf_step<const AVX2: bool>(
    q: &Query,
    code: u32,
    keep: &impl Fn(usize, f32, f32) -> bool,
    best_t: &mut f32,
    best: &mut Option<(usize, TriangleHit)>,
) {
    let t = std::cell::Cell::new(*best_t);
    leaf_lanes::<AVX2>(
        q,
        code,
        || t.get(),
        |slot, h| {
            if keep(slot, h.b1, h.b2) {
                t.set(h.t);
                *best = Some((slot, h));
            }
            true
        },
    );
    *best_t = t.get();
}

/// A closest-hit traversal in progress: the node or leaf it visits next,
/// the depth of its stack, and the closest accepted hit so far. One
/// [`Walk::step`] visits one node or leaf, so several rays' walks can be
/// interleaved ([`closest_many`]).
pub(super) struct Walk {
    code: u32,
    sp: usize,
    pub best: Option<(usize, TriangleHit)>,
    pub best_t: f32,
}

impl Walk {
    /// A walk that starts at the root.
    #[inline(always)]
    fn new(q: &Query) -> Self {
        Walk {
            code: 0,
            sp: 0,
            best: None,
            best_t: q.tmax,
        }
    }

    /// A walk of the subtree `code` only, for a ray whose closest hit so
    /// far is `best` at `best_t` (a packet's ray going on alone).
    #[inline(always)]
    pub fn subtree(code: u32, best_t: f32, best: Option<(usize, TriangleHit)>) -> Self {
        Walk {
            code,
            sp: 0,
            best,
            best_t,
        }
    }

    /// Visits the node or leaf `self.code` and moves to the next one to
    /// visit: the nearest child entered, or the nearest deferred subtree
    /// not beyond the closest hit so far. False when none is left: `best`
    /// is then the closest accepted hit in (0, tmax).
    #[inline(always)]
    pub fn step<const AVX2: bool>(
        &mut self,
        q: &Query,
        keep: &impl Fn(usize, f32, f32) -> bool,
        stack: &mut [MaybeUninit<Entry>],
    ) -> bool {
        if self.code & LEAF_BIT != 0 {
            visited(Visit::Leaf, 1);
            visited(Visit::Triangles, leaf_parts(self.code).1 as u64);
            leaf_step::<AVX2>(q, self.code, keep, &mut self.best_t, &mut self.best);
        } else {
            visited(Visit::Node, 1);
            let node = &q.wide.nodes[self.code as usize];
            let mut t = [0.0; WIDTH];
            let mask = slab::<AVX2>(node, &q.boxes, self.best_t, &mut t);
            if mask != 0 {
                let first = mask.trailing_zeros() as usize;
                let rest = mask & (mask - 1);
                if rest == 0 {
                    self.code = node.child[first];
                    if q.prefetch {
                        // Interleaved walks reach it only after the other
                        // walks' steps: time for the lines to arrive.
                        prefetch(q, self.code);
                    }
                    return true;
                }
                if q.prefetch {
                    for i in SetBits(mask) {
                        prefetch(q, node.child[i]);
                    }
                }
                if rest & (rest - 1) == 0 {
                    // Two children (a third of the nodes a random ray
                    // visits): the nearer now, the other deferred; of equal
                    // entries the later slot goes first, as in the sort below.
                    let second = rest.trailing_zeros() as usize;
                    let (now, later) = if t[first] < t[second] {
                        (first, second)
                    } else {
                        (second, first)
                    };
                    stack[self.sp] = MaybeUninit::new(Entry {
                        code: node.child[later],
                        t: t[later],
                    });
                    self.sp += 1;
                    self.code = node.child[now];
                    return true;
                }
                // Hit slots sorted by decreasing entry distance.
                let mut hits = [Entry { code: 0, t: 0.0 }; WIDTH];
                let mut n = 0;
                for i in SetBits(mask) {
                    let e = Entry {
                        code: node.child[i],
                        t: t[i],
                    };
                    insert_by_decreasing_t(&mut hits, n, e, |e| e.t);
                    n += 1;
                }
                for &e in &hits[..n - 1] {
                    stack[self.sp] = MaybeUninit::new(e);
                    self.sp += 1;
                }
                self.code = hits[n - 1].code;
                return true;
            }
        }
        loop {
            if self.sp == 0 {
                return false;
            }
            self.sp -= 1;
            // SAFETY: entries below `sp` were written above.
            let e = unsafe { stack[self.sp].assume_init() };
            if e.t <= self.best_t {
                self.code = e.code;
                return true;
            }
        }
    }
}

/// Closest accepted hit in (0, tmax): the leaf-order triangle index and
/// the hit. `keep(i, b1, b2)` filters hits (any-hit test).
#[inline(always)]
fn closest<const AVX2: bool>(
    q: &Query,
    keep: &impl Fn(usize, f32, f32) -> bool,
    stack: &mut [MaybeUninit<Entry>],
) -> Option<(usize, TriangleHit)> {
    let mut walk = Walk::new(q);
    while walk.step::<AVX2>(q, keep, stack) {}
    walk.best
}

/// Rays whose walks [`closest_many`] interleaves on one thread: more walks
/// give each prefetched node longer to arrive. On the 1M-triangle mesh's
/// random rays, six beat four by about 8 % on an Intel Xeon of model 207
/// (2026-12-05; eight and ten were no better there); on the Xeon of model
/// 167 of 2026-12-06, twelve beat six by 7–12 % on two threads (medians
/// of two runs of 3–4 rounds alternating; 8, 10, 14 and 16 in between)
/// and by 5–7 % on one. PGO builds there, in two runs of
/// `scripts/bench-vs-embree.sh`: +8–11 % on the rays sorted by their
/// starting triangle, +7 % and none on the rays in random order.
const IN_FLIGHT: usize = 12;

/// Closest hits of `count` rays (`query(i)` sets up ray `i`), handed to
/// `found(i, hit)` in the order the walks end. Up to [`IN_FLIGHT`] walks
/// advance in turn, one node or leaf each: a walk's next node, prefetched
/// as it was entered, arrives from memory while the others take their
/// steps, so the rays' cache misses overlap instead of following one
/// another. Each ray's walk is the one [`closest`] makes, so its hit is
/// the same. The tree must fit [`STACK_INLINE`] (see `with_stack!`).
#[inline(always)]
fn closest_many<'a, const AVX2: bool>(
    count: usize,
    query: &impl Fn(usize) -> Query<'a>,
    found: &mut impl FnMut(usize, Option<(usize, TriangleHit)>),
) {
    let keep = |_, _, _| true;
    let mut stacks = [[const { MaybeUninit::<Entry>::uninit() }; STACK_INLINE]; IN_FLIGHT];
    let start = |i: usize| {
        let q = query(i);
        let walk = Walk::new(&q);
        (i, q, walk)
    };
    let mut lanes: [Option<(usize, Query<'a>, Walk)>; IN_FLIGHT] =
        std::array::from_fn(|k| (k < count).then(|| start(k)));
    let mut next = IN_FLIGHT.min(count);
    let mut live = next;
    while live > 0 {
        for (lane, stack) in lanes.iter_mut().zip(&mut stacks) {
            let Some((i, q, walk)) = lane else { continue };
            if walk.step::<AVX2>(q, &keep, stack) {
                continue;
            }
            found(*i, walk.best);
            if next < count {
                *lane = Some(start(next));
                next += 1;
            } else {
                *lane = None;
                live -= 1;
            }
        }
    }
}

/// True if an accepted hit lies in (0, tmax).
#[inline(always)]
fn any<const AVX2: bool>(
    q: &Query,
    keep: &impl Fn(usize, f32, f32) -> bool,
    stack: &mut [MaybeUninit<Entry>],
) -> bool {
    let mut sp = 0;
    let mut code = 0u32;
    loop {
        if code & LEAF_BIT != 0 {
            let mut found = false;
            leaf_lanes::<AVX2>(
                q,
                code,
                || q.tmax,
                |slot, h| {
                    found = keep(slot, h.b1, h.b2);
                    !found
                },
            );
            if found {
                return true;
            }
        } else {
            let node = &q.wide.nodes[code as usize];
            let mut t = [0.0; WIDTH];
            for i in SetBits(slab::<AVX2>(node, &q.boxes, q.tmax, &mut t)) {
                if q.prefetch {
                    prefetch(q, node.child[i]);
                }
                stack[sp] = MaybeUninit::new(Entry {
                    code: node.child[i],
                    t: 0.0,
                });
                sp += 1;
            }
        }
        if sp == 0 {
            return false;
        }
        sp -= 1;
        // SAFETY: entries below `sp` were written above.
        code = unsafe { stack[sp].assume_init() }.code;
    }
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn closest_avx2(
    q: &Query,
    keep: &impl Fn(usize, f32, f32) -> bool,
) -> Option<(usize, TriangleHit)> {
    with_stack!(q.wide, s => closest::<true>(q, keep, s))
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn any_avx2(q: &Query, keep: &impl Fn(usize, f32, f32) -> bool) -> bool {
    with_stack!(q.wide, s => any::<true>(q, keep, s))
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn closest_many_avx2<'a>(
    count: usize,
    query: &impl Fn(usize) -> Query<'a>,
    found: &mut impl FnMut(usize, Option<(usize, TriangleHit)>),
) {
    closest_many::<true>(count, query, found)
}

/// Closest hits of `count` rays with `kernel` (which this CPU must
/// support), several walks interleaved ([`closest_many`]); `None` (nothing
/// traced) where the tree is too deep for the walks' inline stacks.
pub(super) fn closest_hits<'a>(
    kernel: Kernel,
    wide: &Wide,
    count: usize,
    query: &impl Fn(usize) -> Query<'a>,
    found: &mut impl FnMut(usize, Option<(usize, TriangleHit)>),
) -> Option<()> {
    if stack_entries(wide.depth) > STACK_INLINE {
        return None;
    }
    match kernel {
        // SAFETY: `kernel` is supported (the caller's contract).
        #[cfg(target_arch = "x86_64")]
        Kernel::Avx2 | Kernel::Avx512 => unsafe { closest_many_avx2(count, query, found) },
        _ => closest_many::<false>(count, query, found),
    }
    Some(())
}

/// Closest accepted hit with `kernel` (which this CPU must support).
#[inline]
pub(super) fn closest_hit(
    kernel: Kernel,
    q: &Query,
    keep: &impl Fn(usize, f32, f32) -> bool,
) -> Option<(usize, TriangleHit)> {
    match kernel {
        // SAFETY: `kernel` is supported (the caller's contract).
        #[cfg(target_arch = "x86_64")]
        Kernel::Avx2 | Kernel::Avx512 => unsafe { closest_avx2(q, keep) },
        _ => with_stack!(q.wide, s => closest::<false>(q, keep, s)),
    }
}

/// True if an accepted hit lies in (0, tmax), with `kernel`.
#[inline]
pub(super) fn any_hit(kernel: Kernel, q: &Query, keep: &impl Fn(usize, f32, f32) -> bool) -> bool {
    match kernel {
        // SAFETY: `kernel` is supported (the caller's contract).
        #[cfg(target_arch = "x86_64")]
        Kernel::Avx2 | Kernel::Avx512 => unsafe { any_avx2(q, keep) },
        _ => with_stack!(q.wide, s => any::<false>(q, keep, s)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::accel::wide::TEST_BOXES;

    /// The walks visit entered children nearest first, so the insertion
    /// must keep decreasing entry distances, and of equal distances put
    /// the later inserted nearer the end (visited first), as the two-child
    /// shortcut of `Walk::step` assumes. A wrong order changes no hit, only
    /// the work, so no traversal test can see it. Against the standard
    /// library's stable sort by decreasing distance, on sequences with
    /// many ties (distances drawn from 0, 0.5, 1, 1.5).
    #[test]
    fn insertion_keeps_decreasing_distances_later_ties_last() {
        let mut rng = penumbra_shading::stats::TestRng::new(7);
        for _ in 0..500 {
            let n = 1 + (rng.next_u64() % WIDTH as u64) as usize;
            let items: Vec<(f32, usize)> = (0..n)
                .map(|id| ((rng.next_u64() % 4) as f32 * 0.5, id))
                .collect();
            let mut sorted = [(0.0, 0); WIDTH];
            for (k, &item) in items.iter().enumerate() {
                insert_by_decreasing_t(&mut sorted, k, item, |e| e.0);
            }
            let mut expected = items.clone();
            expected.sort_by(|a, b| b.0.total_cmp(&a.0));
            assert_eq!(sorted[..n], expected[..], "inserted {items:?}");
        }
    }

    /// The kernels offered are the CPU's: always the portable one, AVX2
    /// and AVX-512 exactly when the CPU reports them (tests that loop over the kernels
    /// would pass vacuously on an empty list).
    #[test]
    fn available_kernels_are_the_cpus() {
        let kernels = Kernel::available();
        assert!(kernels.contains(&Kernel::Portable));
        #[cfg(target_arch = "x86_64")]
        {
            let avx2 = std::arch::is_x86_feature_detected!("avx2");
            let avx512 = avx2 && std::arch::is_x86_feature_detected!("avx512f");
            assert_eq!(kernels.contains(&Kernel::Avx2), avx2);
            assert_eq!(kernels.contains(&Kernel::Avx512), avx512);
            let best = if avx512 {
                Kernel::Avx512
            } else if avx2 {
                Kernel::Avx2
            } else {
                Kernel::Portable
            };
            assert_eq!(Kernel::best(), best);
        }
    }

    /// Entry distances and hit masks against the closed form, along the
    /// diagonal both ways (so both plane choices are used): from the origin
    /// along +(1,1,1)/√3 the ray enters [1,2]³ at √3, starts inside
    /// [−1,1]³ (entry clamped to 0) and reaches [4,5]³ only at 4√3, beyond
    /// tmax = 5, and it starts on the flat box z = 0 (entry 0); from
    /// (3,3,3) along −(1,1,1)/√3 it enters [1,2]³ at √3 and [−1,1]³ at
    /// 2√3, and reaches z = 0 only at 3√3, beyond tmax. The other boxes lie
    /// off the diagonal.
    #[test]
    fn slab_gives_closed_form_entry_distances() {
        let n = Node8::with_boxes(&TEST_BOXES);
        let s3 = 3f32.sqrt();
        let d = Vec3::ONE / s3;
        let cases = [
            (Vec3::ZERO, d, 0b100101, vec![(0, s3), (2, 0.0), (5, 0.0)]),
            (Vec3::splat(3.0), -d, 0b000101, vec![(0, s3), (2, 2.0 * s3)]),
        ];
        for avx2 in [false, Kernel::Avx2.is_supported()] {
            for (o, dir, mask, entries) in &cases {
                let r = BoxRay::new(*o, *dir);
                let mut t = [f32::NAN; WIDTH];
                let m = if avx2 {
                    slab::<true>(&n, &r, 5.0, &mut t)
                } else {
                    slab::<false>(&n, &r, 5.0, &mut t)
                };
                assert_eq!(m, *mask, "avx2 {avx2} from {o}: {m:#b}");
                for &(slot, expected) in entries {
                    assert!(
                        (t[slot] - expected).abs() < 1e-5,
                        "avx2 {avx2} slot {slot}: {t:?}"
                    );
                }
            }
        }
    }
}
