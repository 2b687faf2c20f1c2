//! Acceleration structure: an 8-wide BVH of uncompressed fp32 nodes
//! (`wide.rs`), collapsed with the least SAH cost (`collapse.rs`) from a
//! binary BVH that `obvhs` builds with PLOC + reinsertion, over
//! world-space triangles (many identical boxes grouped first,
//! `identical_boxes.rs`); traversed one ray at a time with
//! 8-lane box tests (`traverse.rs`, AVX2 where the CPU has it), several
//! rays' walks interleaved, or rays in packets (`packet.rs`), with our
//! watertight triangle test.

mod block;
pub(crate) mod cluster_scan;
mod collapse;
mod frustum;
mod huge_pages;
mod identical_boxes;
pub(crate) mod lanes16;
mod packet;
pub(crate) mod scan;
mod traverse;
mod watertight;
mod wide;

pub use huge_pages::HugePageAllocator;
pub use traverse::Kernel;
pub use watertight::{TriangleHit, WatertightRay};

use crate::ray::Ray;
use block::{LANES, TriangleBlock};
use glam::{Vec3, Vec3A};
use obvhs::BvhBuildParams;
use obvhs::aabb::Aabb;
use rayon::prelude::*;
use std::time::Duration;
use wide::{LEAF_BIT, LEAF_MAX, Wide, leaf_range};

/// The primitive index of a block's unused lanes.
const PAD: u32 = u32::MAX;

/// Relative padding of primitive boxes (≈ 32 ulps of the largest coordinate).
const BOX_PAD_RELATIVE: f32 = 4.0e-6;

/// Closest hit: triangle index (in the order given to [`Accel::build`]),
/// distance and barycentrics.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    pub triangle: u32,
    pub t: f32,
    pub b1: f32,
    pub b2: f32,
}

/// BVH over a triangle soup.
#[derive(Debug)]
pub struct Accel {
    wide: Wide,
    /// The leaves' triangles, one block per leaf, in node order.
    blocks: Vec<TriangleBlock>,
    /// Input index of each triangle slot (`LANES` per block; [`PAD`] for
    /// the lanes past a leaf's count).
    primitive_indices: Vec<u32>,
    triangle_count: usize,
    kernel: Kernel,
    /// Whether the traversal prefetches the children it enters.
    prefetch: bool,
}

/// The size of tree (nodes and leaf triangles, in bytes) above which the
/// traversal prefetches: about a core's L2 cache. Below it the tree stays
/// in cache and the prefetches only cost instructions (measured: a 5 %
/// slower Cornell box, 32 triangles); on the 1M-triangle bench sphere
/// (56 MB) they made random rays 1.4–1.5× faster (medians of runs
/// alternating the builds).
const PREFETCH_ABOVE_BYTES: usize = 2 << 20;

/// BVH build quality preset.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum BuildQuality {
    Fast,
    #[default]
    Medium,
}

impl Accel {
    /// The most triangles a BVH holds: 2²⁷ − 1, the range of a leaf
    /// code's first-triangle field. `SceneGeometry::build` checks scenes
    /// against it before building.
    pub const MAX_TRIANGLES: usize = wide::MAX_TRIANGLES;

    /// Builds over `triangles` (world space). An empty list gives an
    /// accelerator that misses every ray.
    ///
    /// # Panics
    /// With more than [`Self::MAX_TRIANGLES`] triangles.
    pub fn build(triangles: &[[Vec3; 3]], quality: BuildQuality) -> Self {
        assert!(
            triangles.len() <= Self::MAX_TRIANGLES,
            "{} triangles: the BVH holds at most {}",
            triangles.len(),
            Self::MAX_TRIANGLES
        );
        let kernel = Kernel::best();
        if triangles.is_empty() {
            return Self {
                wide: Wide::default(),
                blocks: Vec::new(),
                primitive_indices: Vec::new(),
                triangle_count: 0,
                kernel,
                prefetch: false,
            };
        }
        let mut params = match quality {
            BuildQuality::Fast => BvhBuildParams::fast_build(),
            BuildQuality::Medium => BvhBuildParams::medium_build(),
        };
        params.max_prims_per_leaf = LEAF_MAX;
        // Boxes padded by a few ulps of their coordinates make the float slab
        // test conservative (cf. Ize 2013, "Robust BVH Ray Traversal"): a ray
        // through a vertex on a box corner must not skip the box, or the
        // watertight triangle test cannot do its job.
        let boxes: Vec<Aabb> = triangles
            .par_iter()
            .map(|t| {
                let (lo, hi) = (t[0].min(t[1]).min(t[2]), t[0].max(t[1]).max(t[2]));
                let pad =
                    lo.abs().max(hi.abs()).max_element() * BOX_PAD_RELATIVE + f32::MIN_POSITIVE;
                Aabb::new((lo - pad).into(), (hi + pad).into())
            })
            .collect();
        let bvh2 = match identical_boxes::group_identical(&boxes) {
            None => obvhs::bvh2::builder::build_bvh2(&boxes, params, &mut Duration::default()),
            Some(grouped) => grouped.expand(
                &obvhs::bvh2::builder::build_bvh2(&grouped.boxes, params, &mut Duration::default()),
                LEAF_MAX as usize,
                &boxes,
            ),
        };
        let (mut wide, leaf_primitives) = collapse::collapse(&bvh2);
        // The nodes copied onto huge pages (before the blocks are
        // allocated: afterwards glibc served the copy from memory already
        // touched, with no huge pages, measured), the leaf blocks and
        // primitive indices filled in place on them.
        wide.nodes = huge_pages::on_huge_pages(wide.nodes);
        let block_count: usize = wide.leaf_counts().map(|n| n.div_ceil(LANES)).sum();
        let mut blocks = huge_pages::with_capacity(block_count);
        let mut primitive_indices = huge_pages::with_capacity(block_count * LANES);
        // Each leaf's primitives in whole blocks of lanes (PAD in the
        // unused ones), in node order...
        wide.renumber_leaves(|first, count| {
            let start = (primitive_indices.len() / LANES) as u32;
            for lanes in leaf_primitives[first..first + count].chunks(LANES) {
                primitive_indices.extend_from_slice(lanes);
                primitive_indices.extend(std::iter::repeat_n(PAD, LANES - lanes.len()));
            }
            start
        });
        // ...then the blocks' triangles gathered from them on every thread,
        // written in place (an indexed `par_extend` fills the reserved
        // room). Serial, this was about a tenth of the 1M-triangle build.
        let reserved = blocks.as_ptr();
        blocks.par_extend(primitive_indices.par_chunks(LANES).map(|lanes| {
            let mut block = TriangleBlock::EMPTY;
            for (lane, &i) in lanes.iter().enumerate() {
                if i != PAD {
                    block.set(lane, triangles[i as usize].map(Vec3A::from));
                }
            }
            block
        }));
        debug_assert_eq!(blocks.len(), block_count);
        debug_assert_eq!(blocks.as_ptr(), reserved, "no regrowth off the huge pages");
        let bytes = wide.nodes.len() * size_of::<wide::Node8>() + size_of_val(&blocks[..]);
        Self {
            wide,
            blocks,
            primitive_indices,
            triangle_count: triangles.len(),
            kernel,
            prefetch: bytes > PREFETCH_ABOVE_BYTES,
        }
    }

    pub fn triangle_count(&self) -> usize {
        self.triangle_count
    }

    /// The traversal kernel in use (the fastest the CPU runs, unless set).
    pub fn kernel(&self) -> Kernel {
        self.kernel
    }

    /// Chooses the traversal kernel; an error if this CPU cannot run it.
    pub fn set_kernel(&mut self, kernel: Kernel) -> Result<(), String> {
        if !kernel.is_supported() {
            return Err(format!("this CPU cannot run the {kernel:?} kernel"));
        }
        self.kernel = kernel;
        Ok(())
    }

    /// Whether the traversal prefetches the children it enters (chosen at
    /// build from the tree's size).
    pub fn prefetch(&self) -> bool {
        self.prefetch
    }

    /// Turns prefetching on or off; hits are the same either way.
    pub fn set_prefetch(&mut self, on: bool) {
        self.prefetch = on;
    }

    /// Closest hit along `ray` in (0, ray.tmax).
    #[inline]
    pub fn intersect(&self, ray: &Ray) -> Option<Hit> {
        self.intersect_where(ray, |_, _, _| true)
    }

    /// Closest hit along `ray` in (0, ray.tmax) among the triangle hits
    /// that `keep(triangle, b1, b2)` accepts (an any-hit filter: alpha
    /// masks); rejected hits are passed through.
    #[inline]
    pub fn intersect_where(&self, ray: &Ray, keep: impl Fn(u32, f32, f32) -> bool) -> Option<Hit> {
        if self.blocks.is_empty() {
            return None;
        }
        let keep = |i: usize, b1, b2| keep(self.primitive_indices[i], b1, b2);
        let (slot, h) = traverse::closest_hit(self.kernel, &self.query(ray), &keep)?;
        Some(self.hit(slot, h))
    }

    /// The hit of triangle slot `slot` (leaf order) as the caller sees it.
    #[inline]
    fn hit(&self, slot: usize, h: TriangleHit) -> Hit {
        Hit {
            triangle: self.primitive_indices[slot],
            t: h.t,
            b1: h.b1,
            b2: h.b2,
        }
    }

    /// Closest hits of many rays: `hits[i]` is [`Accel::intersect`] of
    /// `rays[i]`. The walks of a few rays are interleaved, so that one
    /// ray's cache misses overlap the others' (faster on trees larger than
    /// the caches, with incoherent rays).
    ///
    /// # Panics
    /// If `hits` and `rays` differ in length.
    pub fn intersect_many(&self, rays: &[Ray], hits: &mut [Option<Hit>]) {
        self.intersect_batch(rays, hits, false);
    }

    /// Closest hits of many rays traced in packets of consecutive rays:
    /// `hits[i]` is `rays[i]`'s closest hit, as [`Accel::intersect`] finds
    /// it (of two triangles at exactly the same distance, either may be
    /// reported). Fast where consecutive rays are coherent, such as the
    /// camera rays of neighbouring pixels (a packet of one octant takes the
    /// frustum walk); where they are not, the rays soon go on alone, and
    /// packets cost about 1.3× what [`Accel::intersect_many`] does.
    ///
    /// # Panics
    /// If `hits` and `rays` differ in length.
    pub fn intersect_packets(&self, rays: &[Ray], hits: &mut [Option<Hit>]) {
        self.intersect_batch(rays, hits, true);
    }

    /// [`Accel::intersect_packets`] if `packets`, else
    /// [`Accel::intersect_many`].
    fn intersect_batch(&self, rays: &[Ray], hits: &mut [Option<Hit>], packets: bool) {
        assert_eq!(rays.len(), hits.len(), "one hit per ray");
        if self.blocks.is_empty() {
            hits.fill(None);
            return;
        }
        let query = |i: usize| self.query(&rays[i]);
        let mut found = |i: usize, hit: Option<(usize, TriangleHit)>| {
            hits[i] = hit.map(|(slot, h)| self.hit(slot, h));
        };
        let (kernel, count) = (self.kernel, rays.len());
        if packets {
            packet::closest_hits_packets(kernel, self.wide.depth, count, &query, &mut found);
        } else if traverse::closest_hits(kernel, &self.wide, count, &query, &mut found).is_none() {
            // Too deep for the interleaved walks' inline stacks.
            for (hit, ray) in hits.iter_mut().zip(rays) {
                *hit = self.intersect(ray);
            }
        }
    }

    /// True if anything lies along `ray` in (0, ray.tmax) (shadow rays).
    #[inline]
    pub fn occluded(&self, ray: &Ray) -> bool {
        self.occluded_where(ray, |_, _, _| true)
    }

    /// True if a triangle hit that `keep(triangle, b1, b2)` accepts lies
    /// along `ray` in (0, ray.tmax).
    #[inline]
    pub fn occluded_where(&self, ray: &Ray, keep: impl Fn(u32, f32, f32) -> bool) -> bool {
        if self.blocks.is_empty() {
            return false;
        }
        let keep = |i: usize, b1, b2| keep(self.primitive_indices[i], b1, b2);
        traverse::any_hit(self.kernel, &self.query(ray), &keep)
    }

    /// `ray` set up for the traversal.
    #[inline]
    fn query(&self, ray: &Ray) -> traverse::Query<'_> {
        traverse::Query::new(
            &self.wide,
            &self.blocks,
            ray.origin,
            ray.direction,
            ray.tmax,
            self.prefetch,
        )
    }

    /// The triangle in leaf-order slot `slot`.
    fn slot_triangle(&self, slot: usize) -> [Vec3A; 3] {
        self.blocks[slot / LANES].triangle(slot % LANES)
    }

    /// Checks the BVH structure: every triangle is in exactly one leaf of
    /// at most `LEAF_MAX` triangles, every node is reached once, each box
    /// holds its children's boxes and its triangles, no path is longer
    /// than the recorded depth (the stack bound), and the lanes past each
    /// leaf's count are padding. Returns a description of the first problem.
    pub fn validate(&self) -> Result<(), String> {
        if self.triangle_count == 0 {
            return Ok(());
        }
        if self.primitive_indices.len() != self.blocks.len() * LANES {
            return Err(format!(
                "{} primitive indices for {} blocks",
                self.primitive_indices.len(),
                self.blocks.len()
            ));
        }
        let mut seen = vec![false; self.triangle_count];
        for &i in self.primitive_indices.iter().filter(|&&i| i != PAD) {
            match seen.get_mut(i as usize) {
                Some(s) => *s = true,
                None => return Err(format!("primitive index {i} out of range")),
            }
        }
        if let Some(missing) = seen.iter().position(|s| !s) {
            return Err(format!("triangle {missing} is not in the BVH"));
        }
        let inside = |p: [f32; 3], lo: [f32; 3], hi: [f32; 3]| {
            (0..3).all(|a| lo[a] <= p[a] && p[a] <= hi[a])
        };
        let mut in_leaf = vec![false; self.primitive_indices.len()];
        let mut node_seen = vec![false; self.wide.nodes.len()];
        let everything = ([f32::NEG_INFINITY; 3], [f32::INFINITY; 3]);
        let mut todo = vec![(0u32, everything, 1usize)];
        while let Some((n, (plo, phi), depth)) = todo.pop() {
            if depth > self.wide.depth {
                return Err(format!(
                    "node {n} lies deeper than the recorded depth {}",
                    self.wide.depth
                ));
            }
            match node_seen.get_mut(n as usize) {
                Some(s) if !*s => *s = true,
                Some(_) => return Err(format!("node {n} is reached twice")),
                None => return Err(format!("node index {n} out of range")),
            }
            let node = &self.wide.nodes[n as usize];
            for slot in (0..wide::WIDTH).filter(|&s| node.used(s)) {
                let (lo, hi) = node.slot_box(slot);
                if !inside(lo, plo, phi) || !inside(hi, plo, phi) {
                    return Err(format!("node {n} slot {slot}: box outside its parent's"));
                }
                let code = node.child[slot];
                if code & LEAF_BIT == 0 {
                    todo.push((code, (lo, hi), depth + 1));
                    continue;
                }
                let range = leaf_range(code);
                if range.is_empty()
                    || range.len() > LEAF_MAX as usize
                    || range.end > self.primitive_indices.len()
                {
                    return Err(format!("node {n} slot {slot}: bad leaf {range:?}"));
                }
                for i in range {
                    if std::mem::replace(&mut in_leaf[i], true) {
                        return Err(format!("triangle slot {i} is in two leaves"));
                    }
                    if self.primitive_indices[i] == PAD {
                        return Err(format!("triangle slot {i} is padding but in a leaf"));
                    }
                    if !self
                        .slot_triangle(i)
                        .iter()
                        .all(|v| inside(v.to_array(), lo, hi))
                    {
                        return Err(format!("triangle slot {i} lies outside its leaf's box"));
                    }
                }
            }
        }
        let stray = (0..in_leaf.len()).find(|&i| in_leaf[i] != (self.primitive_indices[i] != PAD));
        if let Some(i) = stray {
            return Err(format!("triangle slot {i} is in no leaf"));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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

    fn random_soup(count: usize, seed: u32) -> (Vec<[Vec3; 3]>, Vec<Ray>) {
        let mut s = penumbra_shading::sampling::Sampler::new(0, 0, 0, seed);
        let mut rnd = || {
            let [a, b] = s.next_2d();
            let [c, _] = s.next_2d();
            Vec3::new(a, b, c) * 10.0
        };
        let tris: Vec<[Vec3; 3]> = (0..count)
            .map(|_| {
                let c = rnd();
                [c, c + rnd() * 0.1, c + rnd() * 0.1]
            })
            .collect();
        let rays = (0..3000)
            .map(|_| {
                let o = rnd() - Vec3::splat(2.0);
                let d = (rnd() - Vec3::splat(5.0)).normalize();
                Ray::new(o, d)
            })
            .collect();
        (tris, rays)
    }

    /// Hundreds of copies of two large triangles among a random soup (the
    /// copies grouped before PLOC, `identical_boxes.rs`): the tree holds
    /// every triangle, and every kernel finds the brute-force closest
    /// distance on a triangle equal to the brute force's (among copies
    /// either may be named), and occlusion agrees.
    #[test]
    fn repeated_triangles_match_brute_force() {
        let (mut tris, rays) = random_soup(1000, 3);
        let big = [
            [
                Vec3::new(0.0, 0.0, 5.0),
                Vec3::new(10.0, 0.0, 5.0),
                Vec3::new(0.0, 10.0, 5.0),
            ],
            [
                Vec3::new(10.0, 10.0, 2.0),
                Vec3::new(0.0, 10.0, 2.0),
                Vec3::new(10.0, 0.0, 2.0),
            ],
        ];
        for k in 0..700 {
            let at = 7 * k % (tris.len() + 1);
            tris.insert(at, big[k % 2]);
        }
        for quality in [BuildQuality::Fast, BuildQuality::Medium] {
            let mut accel = Accel::build(&tris, quality);
            accel.validate().unwrap();
            for kernel in Kernel::available() {
                accel.set_kernel(kernel).unwrap();
                let mut on_copies = 0;
                for ray in &rays {
                    let b = brute_force(&tris, ray);
                    let a = accel.intersect(ray).map(|h| (h.triangle, h.t));
                    let why = format!("{kernel:?} {quality:?} {ray:?}");
                    assert_eq!(a.map(|h| h.1), b.map(|h| h.1), "{why}");
                    if let (Some(a), Some(b)) = (a, b) {
                        assert_eq!(tris[a.0 as usize], tris[b.0 as usize], "{why}");
                        on_copies += big.contains(&tris[b.0 as usize]) as u32;
                    }
                    assert_eq!(accel.occluded(ray), b.is_some(), "{why}");
                }
                assert!(on_copies > 100, "the copies should be hit, got {on_copies}");
            }
        }
    }

    /// Every kernel finds the brute-force closest hit (same triangle, same
    /// distance), with and without an any-hit filter, and occlusion agrees.
    #[test]
    fn every_kernel_matches_brute_force_on_random_soup() {
        for quality in [BuildQuality::Fast, BuildQuality::Medium] {
            let (tris, rays) = random_soup(2000, 1);
            let mut accel = Accel::build(&tris, quality);
            accel.validate().unwrap();
            let odd_rejected = |i: u32, _: f32, _: f32| i.is_multiple_of(2);
            let even_tris: Vec<[Vec3; 3]> = tris
                .iter()
                .enumerate()
                .map(|(i, t)| if i % 2 == 0 { *t } else { [Vec3::ZERO; 3] })
                .collect();
            // 2000 triangles fit in the caches: no prefetching by default.
            assert!(!accel.prefetch());
            for (kernel, prefetch) in Kernel::available()
                .into_iter()
                .flat_map(|k| [(k, false), (k, true)])
            {
                accel.set_kernel(kernel).unwrap();
                accel.set_prefetch(prefetch);
                let mut hits = 0;
                for ray in &rays {
                    let b = brute_force(&tris, ray);
                    let a = accel.intersect(ray).map(|h| (h.triangle, h.t));
                    assert_eq!(a, b, "{kernel:?} {prefetch} {quality:?} {ray:?}");
                    assert_eq!(accel.occluded(ray), b.is_some(), "{kernel:?}");
                    let b = brute_force(&even_tris, ray);
                    let a = accel
                        .intersect_where(ray, odd_rejected)
                        .map(|h| (h.triangle, h.t));
                    assert_eq!(a, b, "{kernel:?} {prefetch} {quality:?} filtered {ray:?}");
                    assert_eq!(accel.occluded_where(ray, odd_rejected), b.is_some());
                    hits += b.is_some() as u32;
                }
                assert!(hits > 100, "test should exercise hits, got {hits}");
            }
        }
    }

    /// The batch calls: rays interleaved, and rays in packets.
    type Batch = fn(&Accel, &[Ray], &mut [Option<Hit>]);
    const BATCHES: [(&str, Batch); 2] = [
        ("interleaved", Accel::intersect_many),
        ("packets", Accel::intersect_packets),
    ];

    /// `intersect_many` and `intersect_packets` find each ray's
    /// brute-force closest hit and exactly `intersect`'s hit (barycentrics
    /// too), for every kernel, with and without prefetching, whatever the
    /// number of rays (fewer than the walks in flight or a packet's lanes,
    /// and not a multiple of them), and with rays cut short by their tmax
    /// mixed in. The soup's random rays make packets whose rays part at
    /// once and point every way.
    #[test]
    fn batches_match_one_at_a_time() {
        let (tris, mut rays) = random_soup(2000, 4);
        for i in (0..rays.len()).step_by(3) {
            if let Some((_, t)) = brute_force(&tris, &rays[i]) {
                rays[i].tmax = t * 0.5;
            }
        }
        let expected: Vec<_> = rays.iter().map(|r| brute_force(&tris, r)).collect();
        assert!(expected.iter().filter(|e| e.is_some()).count() > 100);
        let mut accel = Accel::build(&tris, BuildQuality::Medium);
        for (kernel, prefetch) in Kernel::available()
            .into_iter()
            .flat_map(|k| [(k, false), (k, true)])
        {
            accel.set_kernel(kernel).unwrap();
            accel.set_prefetch(prefetch);
            for (name, batch) in BATCHES {
                for n in [0, 1, 2, 3, 5, 9, 15, 16, 17, 33, rays.len()] {
                    let stale = Hit {
                        triangle: 7,
                        t: 1.0,
                        b1: 0.0,
                        b2: 0.0,
                    };
                    let mut hits = vec![Some(stale); n];
                    batch(&accel, &rays[..n], &mut hits);
                    for (i, (hit, ray)) in hits.iter().zip(&rays).enumerate() {
                        let found = hit.map(|h| (h.triangle, h.t));
                        let why = format!("{name} {kernel:?} {prefetch} n {n} ray {i}");
                        assert_eq!(found, expected[i], "{why}");
                        assert_eq!(*hit, accel.intersect(ray), "{why}");
                    }
                }
            }
        }
    }

    /// Rays with a short tmax see only hits before it.
    #[test]
    fn hits_stop_at_tmax() {
        let (tris, rays) = random_soup(2000, 2);
        let accel = Accel::build(&tris, BuildQuality::Medium);
        let mut cut = 0;
        for ray in &rays {
            let Some((_, t)) = brute_force(&tris, ray) else {
                continue;
            };
            let short = Ray { tmax: t, ..*ray };
            let before = brute_force(&tris, &short);
            assert_eq!(accel.intersect(&short).map(|h| (h.triangle, h.t)), before);
            assert_eq!(accel.occluded(&short), before.is_some());
            cut += before.is_none() as u32;
        }
        assert!(cut > 50, "test should cut hits off, got {cut}");
    }

    /// A tree deeper than the inline stack holds traverses on the heap with
    /// the same results.
    #[test]
    fn heap_stack_gives_the_same_hits() {
        let (tris, rays) = random_soup(2000, 3);
        let mut accel = Accel::build(&tris, BuildQuality::Medium);
        let inline: Vec<_> = rays.iter().map(|r| accel.intersect(r)).collect();
        accel.wide.depth = 1000;
        for (r, h) in rays.iter().zip(&inline) {
            assert_eq!(accel.intersect(r), *h);
            assert_eq!(accel.occluded(r), h.is_some());
        }
        for (name, batch) in BATCHES {
            let mut many = vec![None; rays.len()];
            batch(&accel, &rays, &mut many);
            assert_eq!(many, inline, "{name}");
        }
        assert!(inline.iter().any(Option::is_some));
    }

    /// A genuinely deep tree (triangles at geometrically growing distances
    /// along x make a caterpillar-like BVH, deeper than the inline stacks
    /// hold): one ray at a time and both batch calls traverse it with heap
    /// stacks and find the brute-force hits.
    #[test]
    fn deep_trees_use_heap_stacks() {
        let tris: Vec<[Vec3; 3]> = (0..3000)
            .map(|i| {
                let x = 1.025f32.powi(i);
                let s = x * 0.01;
                [
                    Vec3::new(x, -s, -s),
                    Vec3::new(x, s, -s),
                    Vec3::new(x, 0.0, s),
                ]
            })
            .collect();
        let accel = Accel::build(&tris, BuildQuality::Medium);
        accel.validate().unwrap();
        let depth = accel.wide.depth;
        assert!(
            (wide::WIDTH - 1) * depth + 1 > 256,
            "not deep enough: {depth}"
        );
        let rays: Vec<Ray> = (0..42)
            .map(|i| {
                let o = Vec3::new(0.5 * 1.025f32.powi(i * 20), 0.001, 0.0);
                let d = if i % 2 == 0 { Vec3::X } else { -Vec3::X };
                Ray::new(o, d)
            })
            .collect();
        let expected: Vec<_> = rays.iter().map(|r| brute_force(&tris, r)).collect();
        for (ray, e) in rays.iter().zip(&expected) {
            assert_eq!(accel.intersect(ray).map(|h| (h.triangle, h.t)), *e);
        }
        for (name, batch) in BATCHES {
            let mut many = vec![None; rays.len()];
            batch(&accel, &rays, &mut many);
            for (hit, e) in many.iter().zip(&expected) {
                assert_eq!(hit.map(|h| (h.triangle, h.t)), *e, "{name}");
            }
        }
        let hits = expected.iter().filter(|e| e.is_some()).count();
        assert!(hits >= 40, "{hits} hits");
    }

    /// `validate` reports a box that no longer holds what is below it.
    #[test]
    fn validate_finds_a_shrunk_box() {
        let (tris, _) = random_soup(500, 4);
        let mut accel = Accel::build(&tris, BuildQuality::Medium);
        accel.validate().unwrap();
        let node = accel.wide.nodes.len() - 1;
        let slot = (0..wide::WIDTH)
            .find(|&s| accel.wide.nodes[node].used(s))
            .unwrap();
        accel.wide.nodes[node].bounds[1][slot] = accel.wide.nodes[node].bounds[0][slot];
        let err = accel.validate().unwrap_err();
        assert!(err.contains("outside"), "{err}");
    }

    /// Every slot of the tree as (node, slot, code), and the longest
    /// root-to-leaf path in nodes, found by a walk of the test's own.
    fn slots_and_depth(accel: &Accel) -> (Vec<(usize, usize, u32)>, usize) {
        let (mut slots, mut deepest) = (Vec::new(), 0);
        let mut todo = vec![(0usize, 1usize)];
        while let Some((n, depth)) = todo.pop() {
            deepest = deepest.max(depth);
            for s in 0..wide::WIDTH {
                let node = &accel.wide.nodes[n];
                if node.bounds[0][s] > node.bounds[1][s] {
                    continue;
                }
                slots.push((n, s, node.child[s]));
                if node.child[s] & LEAF_BIT == 0 {
                    todo.push((node.child[s] as usize, depth + 1));
                }
            }
        }
        (slots, deepest)
    }

    /// Four triangles with one bounding box (one leaf), crossing the z
    /// axis at different heights, hit by rays from above and below:
    /// whichever lane order the leaf has, each kernel reports the nearest
    /// one (a later lane's closer hit replaces an earlier one, a farther
    /// one does not), with its exact distance and barycentrics.
    #[test]
    fn the_nearest_of_a_leafs_triangles_wins() {
        // At (x, y) = (0, 0), b = (½, ¼, ¼): z = ½ z₀ + ¼ z₁ + ¼ z₂.
        let tri = |[z0, z1, z2]: [f32; 3]| {
            [
                Vec3::new(-1.0, -1.0, z0),
                Vec3::new(3.0, -1.0, z1),
                Vec3::new(-1.0, 3.0, z2),
            ]
        };
        let heights = [2.125, 2.875, 2.5, 2.0];
        let mut tris = [
            [1.0, 4.0, 2.5],
            [4.0, 2.5, 1.0],
            [2.5, 1.0, 4.0],
            [1.5, 4.0, 1.0],
        ]
        .map(tri)
        .to_vec();
        // Small trees keep a leaf per triangle: others far off make the
        // build collapse leaves.
        let (far, _) = random_soup(300, 9);
        tris.extend(far.iter().map(|t| t.map(|v| v + Vec3::X * 100.0)));
        let mut accel = Accel::build(&tris, BuildQuality::Medium);
        let block_of = |i: u32| {
            let slot = accel.primitive_indices.iter().position(|&p| p == i);
            slot.unwrap() / LANES
        };
        assert!((1..4).all(|i| block_of(i) == block_of(0)), "one leaf");
        for kernel in Kernel::available() {
            accel.set_kernel(kernel).unwrap();
            // From above: triangle 1 (z = 2.875), then 2; from below: 3, then 0.
            for (z, dir, [first, second]) in [(10.0, -1.0, [1, 2]), (-10.0, 1.0, [3, 0])] {
                let ray = Ray::new(Vec3::new(0.0, 0.0, z), Vec3::new(0.0, 0.0, dir));
                let t = |i: usize| (heights[i] - z) * dir;
                let hit = accel.intersect(&ray).unwrap();
                assert_eq!(
                    (hit.triangle, hit.t),
                    (first as u32, t(first)),
                    "{kernel:?} z {z}"
                );
                assert_eq!((hit.b1, hit.b2), (0.25, 0.25), "{kernel:?}");
                // Up to the nearest hit, none; with it filtered out, the next.
                let short = Ray::segment(ray.origin, ray.direction, t(first));
                assert!(accel.intersect(&short).is_none(), "{kernel:?}");
                let next = accel
                    .intersect_where(&ray, |i, _, _| i != first as u32)
                    .unwrap();
                assert_eq!(
                    (next.triangle, next.t),
                    (second as u32, t(second)),
                    "{kernel:?}"
                );
            }
        }
    }

    /// Moves vertex `k` of the triangle in slot `slot` to `p`.
    fn set_vertex(a: &mut Accel, slot: usize, k: usize, p: [f32; 3]) {
        for (axis, &x) in p.iter().enumerate() {
            a.blocks[slot / LANES].v[k][axis][slot % LANES] = x;
        }
    }

    /// `validate` accepts a sound tree, also one whose triangles touch
    /// their boxes and whose recorded depth is exact, and names each kind
    /// of broken tree.
    #[test]
    fn validate_names_each_kind_of_broken_tree() {
        assert_eq!(Accel::build(&[], BuildQuality::Fast).validate(), Ok(()));
        let (tris, _) = random_soup(500, 4);
        let sound = Accel::build(&tris, BuildQuality::Medium);
        let (slots, deepest) = slots_and_depth(&sound);
        assert!(deepest >= 3, "the test needs a deeper tree: {deepest}");
        let is_leaf = |&&(_, _, code): &&(usize, usize, u32)| code & LEAF_BIT != 0;
        let leaves: Vec<_> = slots.iter().filter(is_leaf).copied().collect();
        let inner: Vec<_> = slots.iter().filter(|s| !is_leaf(s)).copied().collect();
        let count = |code: u32| leaf_range(code).len();
        assert!(
            leaves.iter().any(|l| count(l.2) > LANES),
            "the test needs a leaf of two blocks"
        );
        let expect = |accel: &Accel, what: &str| {
            let err = accel.validate().expect_err(what);
            assert!(err.contains(what), "expected “{what}”, got “{err}”");
        };
        let broken = |change: &dyn Fn(&mut Accel)| {
            let mut accel = Accel::build(&tris, BuildQuality::Medium);
            change(&mut accel);
            accel
        };

        // The recorded depth is the longest path; one less is too shallow.
        assert_eq!(sound.wide.depth, deepest);
        sound.validate().unwrap();
        expect(
            &broken(&|a| a.wide.depth -= 1),
            "deeper than the recorded depth",
        );

        // Closed boxes: a vertex moved exactly onto its leaf box's faces
        // still lies inside; moved just past one, it does not.
        let (n, s, code) = leaves[0];
        let i = leaf_range(code).start;
        let (lo, hi) = sound.wide.nodes[n].slot_box(s);
        let on_faces = broken(&|a| {
            set_vertex(a, i, 0, lo);
            set_vertex(a, i, 1, hi);
        });
        on_faces.validate().unwrap();
        for axis in 0..3 {
            for (corner, past) in [(lo, lo[axis].next_down()), (hi, hi[axis].next_up())] {
                let mut out = corner;
                out[axis] = past;
                let a = broken(&|a| set_vertex(a, i, 2, out));
                expect(&a, "lies outside its leaf's box");
            }
        }

        expect(
            &broken(&|a| a.primitive_indices[0] = tris.len() as u32),
            "primitive index 500 out of range",
        );
        let pair = leaves
            .iter()
            .map(|l| leaf_range(l.2))
            .find(|r| r.len() >= 2)
            .expect("a leaf of two triangles");
        expect(
            &broken(&|a| a.primitive_indices[pair.start + 1] = a.primitive_indices[pair.start]),
            "is not in the BVH",
        );
        // The slot list must be one block's lanes per block.
        expect(
            &broken(&|a| {
                a.primitive_indices.pop();
            }),
            "primitive indices for",
        );
        // A leaf's count raised into its block's padding.
        let (n, s, code) = *leaves
            .iter()
            .find(|l| count(l.2) % LANES != 0)
            .expect("a leaf with padding");
        expect(
            &broken(&|a| a.wide.nodes[n].child[s] = code + (1 << wide::COUNT_SHIFT)),
            "is padding but in a leaf",
        );
        // A leaf slot emptied: its triangles are in no leaf.
        let (n, s, code) = *leaves
            .iter()
            .find(|l| leaves.iter().any(|m| m.0 == l.0 && m.1 != l.1))
            .expect("a node with two leaves");
        expect(
            &broken(&|a| a.wide.nodes[n].bounds[0][s] = f32::INFINITY),
            "is in no leaf",
        );
        // Leaf codes with no triangles, too many, or past the end.
        let empty = code & !(15 << wide::COUNT_SHIFT);
        let too_many = empty | ((LEAF_MAX + 1) << wide::COUNT_SHIFT);
        let past_end = wide::leaf_code(sound.blocks.len() as u32, 1);
        for bad in [empty, too_many, past_end] {
            expect(&broken(&|a| a.wide.nodes[n].child[s] = bad), "bad leaf");
        }
        // One leaf copied over another of the same node (box and code).
        let copy_slot = |a: &mut Accel, n: usize, from: usize, to: usize| {
            for plane in 0..6 {
                a.wide.nodes[n].bounds[plane][to] = a.wide.nodes[n].bounds[plane][from];
            }
            a.wide.nodes[n].child[to] = a.wide.nodes[n].child[from];
        };
        let (_, s2, _) = *leaves.iter().find(|l| l.0 == n && l.1 != s).unwrap();
        expect(&broken(&|a| copy_slot(a, n, s, s2)), "is in two leaves");
        // An inner child pointing outside the node list, or reached twice.
        let (n, s, _) = *inner
            .iter()
            .find(|c| inner.iter().any(|d| d.0 == c.0 && d.1 != c.1))
            .expect("a node with two inner children");
        expect(
            &broken(&|a| a.wide.nodes[n].child[s] = a.wide.nodes.len() as u32),
            "node index",
        );
        let (_, s3, _) = *inner.iter().find(|c| c.0 == n && c.1 != s).unwrap();
        expect(&broken(&|a| copy_slot(a, n, s, s3)), "is reached twice");
        // A child box grown just past its parent's, on either side.
        let (n, s, child) = inner[0];
        let (lo, hi) = sound.wide.nodes[n].slot_box(s);
        let k = (0..wide::WIDTH)
            .find(|&k| sound.wide.nodes[child as usize].used(k))
            .unwrap();
        for axis in 0..3 {
            let c = child as usize;
            let low = broken(&|a| a.wide.nodes[c].bounds[2 * axis][k] = lo[axis].next_down());
            expect(&low, "box outside its parent's");
            let high = broken(&|a| a.wide.nodes[c].bounds[2 * axis + 1][k] = hi[axis].next_up());
            expect(&high, "box outside its parent's");
        }
    }

    /// Leaf boxes are their triangles' bounds padded by a few ulps (4·10⁻⁶
    /// of the largest coordinate, ≈ 32 ulps), no more: looser boxes would
    /// send rays into leaves they miss.
    #[test]
    fn leaf_boxes_are_padded_by_ulps() {
        let (tris, _) = random_soup(500, 8);
        let accel = Accel::build(&tris, BuildQuality::Medium);
        let (slots, _) = slots_and_depth(&accel);
        for (n, s, code) in slots.into_iter().filter(|s| s.2 & LEAF_BIT != 0) {
            let (lo, hi) = accel.wide.nodes[n].slot_box(s);
            let vertices = || leaf_range(code).flat_map(|i| accel.slot_triangle(i));
            let tlo = vertices().fold(Vec3A::INFINITY, |a, v| a.min(v));
            let thi = vertices().fold(Vec3A::NEG_INFINITY, |a, v| a.max(v));
            let slack = tlo.abs().max(thi.abs()).max_element() * 8e-6;
            for a in 0..3 {
                assert!(
                    lo[a] < tlo[a] && lo[a] > tlo[a] - slack,
                    "leaf {n}/{s} axis {a}"
                );
                assert!(
                    hi[a] > thi[a] && hi[a] < thi[a] + slack,
                    "leaf {n}/{s} axis {a}"
                );
            }
        }
    }

    /// The settings read back what was set; a kernel this CPU cannot run
    /// is refused and leaves the kernel as it was.
    #[test]
    fn settings_read_back() {
        let (tris, _) = random_soup(300, 5);
        let mut accel = Accel::build(&tris, BuildQuality::Fast);
        assert_eq!(accel.triangle_count(), 300);
        assert_eq!(
            Accel::build(&tris[..7], BuildQuality::Fast).triangle_count(),
            7
        );
        for on in [true, false, true] {
            accel.set_prefetch(on);
            assert_eq!(accel.prefetch(), on);
        }
        for kernel in [
            Kernel::Avx2,
            Kernel::Portable,
            Kernel::Avx512,
            Kernel::best(),
        ] {
            let before = accel.kernel();
            match accel.set_kernel(kernel) {
                Ok(()) => {
                    assert!(kernel.is_supported());
                    assert_eq!(accel.kernel(), kernel);
                }
                Err(e) => {
                    assert!(!kernel.is_supported() && e.contains("cannot run"), "{e}");
                    assert_eq!(accel.kernel(), before);
                }
            }
        }
        assert_eq!(accel.kernel(), Kernel::best());
    }

    /// Prefetching turns on when the nodes and triangle blocks together
    /// pass 2 MiB: for 42 000 triangles the blocks alone stay below it
    /// and the nodes take the sum past it; 10 000 stay below.
    #[test]
    fn prefetch_counts_nodes_and_triangles() {
        let tris = |n: usize| random_soup(n, 6).0;
        let accel = Accel::build(&tris(42_000), BuildQuality::Fast);
        let block_bytes = accel.blocks.len() * size_of::<TriangleBlock>();
        let node_bytes = accel.wide.nodes.len() * size_of::<wide::Node8>();
        assert!(
            block_bytes < 2 << 20 && block_bytes + node_bytes > 2 << 20,
            "{block_bytes} + {node_bytes} bytes"
        );
        assert!(accel.prefetch());
        assert!(!Accel::build(&tris(10_000), BuildQuality::Fast).prefetch());
    }

    /// Triangles collapsed onto the origin (degenerate glTF triangles) get
    /// boxes that hold them: a zero coordinate is padded by a positive
    /// amount too.
    #[test]
    fn triangles_at_the_origin_are_boxed() {
        Accel::build(&[[Vec3::ZERO; 3]], BuildQuality::Medium)
            .validate()
            .unwrap();
        let (mut tris, rays) = random_soup(200, 7);
        tris.extend([[Vec3::ZERO; 3]; 3]);
        tris.push([Vec3::ZERO, Vec3::X * 1e-30, Vec3::Y * 1e-30]);
        let accel = Accel::build(&tris, BuildQuality::Medium);
        accel.validate().unwrap();
        for ray in &rays {
            let a = accel.intersect(ray).map(|h| (h.triangle, h.t));
            assert_eq!(a, brute_force(&tris, ray));
        }
    }

    #[test]
    fn empty_misses() {
        let a = Accel::build(&[], BuildQuality::Fast);
        assert!(a.intersect(&Ray::new(Vec3::ZERO, Vec3::X)).is_none());
        assert!(!a.occluded(&Ray::new(Vec3::ZERO, Vec3::X)));
        for (name, batch) in BATCHES {
            let mut hits = [Some(Hit {
                triangle: 0,
                t: 1.0,
                b1: 0.0,
                b2: 0.0,
            })];
            batch(&a, &[Ray::new(Vec3::ZERO, Vec3::X)], &mut hits);
            assert_eq!(hits, [None], "{name}");
        }
    }
}

#[cfg(test)]
mod signed_zero_tests {
    use super::*;

    /// Axis-parallel rays hit a flat quad whatever the sign of their zero
    /// direction components (−0.0 makes 1/d = −∞ in slab tests).
    #[test]
    fn axis_parallel_rays_with_negative_zero_components_hit() {
        let (a, b, c, d) = (
            Vec3::new(-5.0, 0.0, -5.0),
            Vec3::new(5.0, 0.0, -5.0),
            Vec3::new(5.0, 0.0, 5.0),
            Vec3::new(-5.0, 0.0, 5.0),
        );
        let mut accel = Accel::build(&[[a, b, c], [a, c, d]], BuildQuality::Medium);
        for (kernel, o) in Kernel::available().into_iter().flat_map(|k| {
            [
                Vec3::new(3.0, 1.0, 0.0),
                Vec3::new(0.0, 1.0, 0.0),
                Vec3::new(-2.0, 1.0, 4.0),
            ]
            .map(|o| (k, o))
        }) {
            accel.set_kernel(kernel).unwrap();
            for dir in [
                -Vec3::Y,
                Vec3::new(0.0, -1.0, 0.0),
                Vec3::new(-0.0, -1.0, 0.0),
            ] {
                let ray = Ray::new(o, dir);
                let hit = accel.intersect(&ray);
                assert!(
                    hit.is_some_and(|h| (h.t - 1.0).abs() < 1e-6),
                    "{kernel:?} {o} {dir:?}"
                );
                assert!(accel.occluded(&ray), "{kernel:?} {o} {dir:?}");
            }
            // The three directions in one packet.
            let rays = [
                -Vec3::Y,
                Vec3::new(0.0, -1.0, 0.0),
                Vec3::new(-0.0, -1.0, 0.0),
            ]
            .map(|d| Ray::new(o, d));
            let mut hits = [None; 3];
            accel.intersect_packets(&rays, &mut hits);
            for h in hits {
                assert!(
                    h.is_some_and(|h| (h.t - 1.0).abs() < 1e-6),
                    "{kernel:?} {o}"
                );
            }
        }
    }
}
