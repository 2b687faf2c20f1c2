//! Owen-scrambled Sobol sequence with per-pixel hashed scrambles.
//!
//! Burley 2020, "Practical Hash-based Owen Scrambling" (JCGT 9(4)): each
//! 2-D dimension pair uses the first two Sobol dimensions (van der Corput and
//! Sobol's second), Owen-scrambled with a seed hashed from (pixel, dimension,
//! render seed), and the sample index is itself shuffled by an Owen scramble so
//! that pairs of dimensions are decorrelated. The sequence depends only on
//! (pixel, sample index, dimension, seed), never on the thread that asks.

use super::sobol_block::{Avx2, BLOCK, GROUP, SeedBlock};

/// A fast 32-bit integer hash (Wellons' "lowbias32").
#[inline]
pub fn hash_u32(mut x: u32) -> u32 {
    let [m1, m2] = LOWBIAS_MULTIPLIERS;
    x ^= x >> 16;
    x = x.wrapping_mul(m1);
    x ^= x >> 15;
    x = x.wrapping_mul(m2);
    x ^= x >> 16;
    x
}

/// The multipliers of [`hash_u32`].
pub(super) const LOWBIAS_MULTIPLIERS: [u32; 2] = [0x7feb_352d, 0x846c_a68b];

/// The constant [`hash_combine`] adds: 2³² divided by the golden ratio.
pub(super) const GOLDEN: u32 = 0x9e37_79b9;

/// Combines a hash with another value (boost-style, then rehashed).
#[inline]
pub fn hash_combine(seed: u32, v: u32) -> u32 {
    hash_u32(
        seed ^ v
            .wrapping_add(GOLDEN)
            .wrapping_add(seed << 6)
            .wrapping_add(seed >> 2),
    )
}

/// Laine–Karras style nested uniform scramble in reversed-bit order
/// (Burley 2020, listing 2).
#[inline]
fn laine_karras_permutation(mut x: u32, seed: u32) -> u32 {
    x = x.wrapping_add(seed);
    for m in LK_MULTIPLIERS {
        x ^= x.wrapping_mul(m);
    }
    x
}

/// The multipliers of [`laine_karras_permutation`]'s four `x ^= x * m`
/// steps (even, so each step is a bijection that only carries bits upward).
pub(super) const LK_MULTIPLIERS: [u32; 4] = [0x6c50_b47c, 0xb82f_1e52, 0xc7af_e638, 0x8d22_f6e6];

/// Owen scramble of a 32-bit fixed-point value (the definition the tests
/// check the sampler against).
#[cfg(test)]
fn nested_uniform_scramble(x: u32, seed: u32) -> u32 {
    laine_karras_permutation(x.reverse_bits(), seed).reverse_bits()
}

/// Direction numbers of Sobol dimension 1 (dimension 0 is the bit reversal).
const SOBOL_DIM1: [u32; 32] = {
    let mut v = [0u32; 32];
    // Primitive polynomial x + 1, m_1 = 1: v_i = v_{i-1} ^ (v_{i-1} >> 1).
    v[0] = 1 << 31;
    let mut i = 1;
    while i < 32 {
        v[i] = v[i - 1] ^ (v[i - 1] >> 1);
        i += 1;
    }
    v
};

/// Sobol dimension 1 by the bit loop (the definition; used to build tables).
const fn sobol_dim1_by_bits(index: u32) -> u32 {
    let mut r = 0;
    let mut i = index;
    let mut k = 0;
    while i != 0 {
        if i & 1 != 0 {
            r ^= SOBOL_DIM1[k];
        }
        i >>= 1;
        k += 1;
    }
    r
}

/// Sobol dimension 1 in the bit-reversed domain, one table per byte:
/// `reverse(sobol_dim1(reverse(y)))` = `R0[y0] ^ R1[y1] ^ R2[y2] ^ R3[y3]`
/// (bit reversal is linear over GF(2) too). The sampler's index shuffle
/// and the Owen scramble both work on reversed bits, so this saves two
/// reversals a point.
const SOBOL_DIM1_REVERSED_BYTE_TABLES: [[u32; 256]; 4] = {
    let mut t = [[0u32; 256]; 4];
    let mut byte = 0;
    while byte < 4 {
        let mut v = 0;
        while v < 256 {
            let y = (v as u32) << (8 * byte);
            t[byte][v] = sobol_dim1_by_bits(y.reverse_bits()).reverse_bits();
            v += 1;
        }
        byte += 1;
    }
    t
};

#[inline]
fn sobol_dim1_reversed(y: u32) -> u32 {
    let t = &SOBOL_DIM1_REVERSED_BYTE_TABLES;
    t[0][(y & 0xff) as usize]
        ^ t[1][((y >> 8) & 0xff) as usize]
        ^ t[2][((y >> 16) & 0xff) as usize]
        ^ t[3][(y >> 24) as usize]
}

#[inline]
fn to_unit_float(x: u32) -> f32 {
    // 24 high bits → [0, 1) exactly representable.
    (x >> 8) as f32 * (1.0 / (1u32 << 24) as f32)
}

/// Dimension pairs whose scramble seeds a [`Sampler`] keeps for the next
/// sample of its pixel (a depth-8 path draws at most 29: one for the
/// camera ray, four a bounce), in blocks of [`BLOCK`].
const CACHED_BLOCKS: usize = 4;
const CACHED_PAIRS: usize = CACHED_BLOCKS * BLOCK;
/// The pairs a depth-8 path draws at most: the camera ray's, then for each
/// of the seven bounces the light's and lobe's choice, the light point,
/// the BSDF direction and Russian roulette's number.
const DEPTH_8_PAIRS: usize = 1 + 4 * 7;
// A sample's points are computed a group of blocks at a time (sixteen
// pairs: most paths draw more than eight).
const _: () = assert!(
    CACHED_BLOCKS.is_multiple_of(GROUP),
    "blocks are computed in whole groups"
);
const _: () = assert!(
    CACHED_PAIRS >= DEPTH_8_PAIRS,
    "a depth-8 path's pairs are kept"
);

/// Per-pixel, per-sample stream of 2-D points in [0,1)².
///
/// `next_2d` draws successive dimension pairs; `next_1d` uses the first half of
/// a pair. Deterministic in (pixel, sample index, seed).
///
/// A pair's three scramble seeds depend on the pixel and the dimension only,
/// so the sampler keeps them: [`Sampler::start_sample`] moves to another
/// sample of the same pixel without hashing them again. On a CPU with AVX2
/// it computes a sample's points sixteen pairs at a time (`sobol_block.rs`:
/// two AVX2 blocks, or one AVX-512 register for
/// [`Sampler::for_pixel_avx512`]), the same points as one at a time.
#[derive(Clone, Debug)]
pub struct Sampler {
    pixel_seed: u32,
    /// The sample index, bit-reversed (the shuffle scrambles reversed bits).
    index_reversed: u32,
    dimension: u32,
    /// Pairs `0..cached` have their seeds in `seeds`.
    cached: u32,
    /// Pairs `0..ready` of this sample have their points in `points`.
    ready: u32,
    blocks: Option<Avx2>,
    seeds: [SeedBlock; CACHED_BLOCKS],
    points: [[[f32; 2]; BLOCK]; CACHED_BLOCKS],
}

/// One dimension pair's scramble seeds: the index shuffle's, then each
/// coordinate's (Burley 2020, listing 3).
#[derive(Clone, Copy, Debug)]
struct PairSeeds {
    shuffle: u32,
    first: u32,
    second: u32,
}

impl PairSeeds {
    #[inline]
    fn new(pixel_seed: u32, dimension: u32) -> Self {
        let shuffle = hash_combine(pixel_seed, dimension);
        PairSeeds {
            shuffle,
            first: hash_combine(shuffle, 1),
            second: hash_combine(shuffle, 2),
        }
    }
}

impl SeedBlock {
    /// The seeds of the block's pair `lane`.
    #[inline(always)]
    fn pair(&self, lane: usize) -> PairSeeds {
        PairSeeds {
            shuffle: self.shuffle[lane],
            first: self.first[lane],
            second: self.second[lane],
        }
    }

    #[inline(always)]
    fn set_pair(&mut self, lane: usize, seeds: PairSeeds) {
        self.shuffle[lane] = seeds.shuffle;
        self.first[lane] = seeds.first;
        self.second[lane] = seeds.second;
    }
}

impl Sampler {
    /// Starts the stream of sample `index` of pixel (`x`, `y`) for render `seed`.
    pub fn new(x: u32, y: u32, index: u32, seed: u32) -> Self {
        let mut sampler = Self::for_pixel(x, y, seed);
        sampler.start_sample(index);
        sampler
    }

    /// The sampler of pixel (`x`, `y`) for render `seed`, to be moved from
    /// sample to sample with [`Sampler::start_sample`]: its samples share
    /// the pixel's scramble seeds (it starts at sample 0).
    pub fn for_pixel(x: u32, y: u32, seed: u32) -> Self {
        Self::with_blocks(x, y, seed, Avx2::detect())
    }

    /// As [`Sampler::for_pixel`] (the same points), for code that runs in
    /// AVX-512 registers anyway: it computes sixteen pairs in one AVX-512
    /// register where the CPU has it.
    pub fn for_pixel_avx512(x: u32, y: u32, seed: u32) -> Self {
        Self::with_blocks(x, y, seed, Avx2::detect_avx512())
    }

    fn with_blocks(x: u32, y: u32, seed: u32, blocks: Option<Avx2>) -> Self {
        let pixel_seed = hash_combine(hash_combine(hash_u32(seed), x), y);
        Self {
            pixel_seed,
            index_reversed: 0,
            dimension: 0,
            cached: 0,
            ready: 0,
            blocks,
            seeds: [SeedBlock::default(); CACHED_BLOCKS],
            points: [[[0.0; 2]; BLOCK]; CACHED_BLOCKS],
        }
    }

    /// Restarts the stream at dimension 0 of sample `index` of the same
    /// pixel: the points are [`Sampler::new`]'s for that index.
    #[inline]
    pub fn start_sample(&mut self, index: u32) {
        self.index_reversed = index.reverse_bits();
        self.dimension = 0;
        self.ready = 0;
    }

    /// Next point of the scrambled (0, 2)-sequence in [0,1)².
    ///
    /// With LK the Laine–Karras permutation and R bit reversal: the index is
    /// shuffled, `i' = R(LK(R(i)))`; dimension 0 is `R(i')`, scrambled to
    /// `R(LK(i'))`; dimension 1 is Sobol's, scrambled to
    /// `R(LK(R(sobol1(i'))))`. Computed on `y = LK(R(i))` = `R(i')`
    /// with reversed tables, so only three reversals remain (one pair at a
    /// time; `sobol_block.rs` computes the same points sixteen at a time).
    #[inline]
    pub fn next_2d(&mut self) -> [f32; 2] {
        self.next_pair(true)
    }

    /// Next value in [0,1): the first coordinate of the next 2-D point.
    #[inline]
    pub fn next_1d(&mut self) -> f32 {
        self.next_pair(false)[0]
    }

    /// The next pair's point: ready in its block, or computed (the second
    /// coordinate only if `second`).
    #[inline(always)]
    fn next_pair(&mut self, second: bool) -> [f32; 2] {
        let d = self.dimension as usize;
        self.dimension += 1;
        if d < self.ready as usize {
            return self.points.as_flattened()[d];
        }
        self.compute(d, second)
    }

    /// Pair `d`'s point when it is not ready: the block it starts, or on
    /// its own (the second coordinate only if `second`, else 0).
    #[inline(never)]
    fn compute(&mut self, d: usize, second: bool) -> [f32; 2] {
        if d >= CACHED_PAIRS {
            return self.point(PairSeeds::new(self.pixel_seed, d as u32), second);
        }
        // Dimensions are drawn in order, so a block is computed when its
        // first pair is drawn, and a pair alone after the one before it.
        let (b, lane) = (d / BLOCK, d % BLOCK);
        match self.blocks {
            Some(kernel) => {
                debug_assert_eq!((d, lane, b % GROUP), (self.ready as usize, 0, 0));
                let g = b / GROUP;
                let seeds = &mut self.seeds.as_chunks_mut::<GROUP>().0[g];
                if self.cached as usize <= d {
                    kernel.seeds(self.pixel_seed, d as u32, seeds);
                    self.cached += (GROUP * BLOCK) as u32;
                }
                let points = &mut self.points.as_chunks_mut::<GROUP>().0[g];
                kernel.points(self.index_reversed, seeds, points);
                self.ready += (GROUP * BLOCK) as u32;
                self.points[b][0]
            }
            None => {
                let seeds = if self.cached as usize <= d {
                    debug_assert_eq!(d, self.cached as usize);
                    let pair = PairSeeds::new(self.pixel_seed, d as u32);
                    self.seeds[b].set_pair(lane, pair);
                    self.cached += 1;
                    pair
                } else {
                    self.seeds[b].pair(lane)
                };
                self.point(seeds, second)
            }
        }
    }

    /// One pair's point, computed alone.
    #[inline(always)]
    fn point(&self, seeds: PairSeeds, second: bool) -> [f32; 2] {
        let y = laine_karras_permutation(self.index_reversed, seeds.shuffle);
        let a = laine_karras_permutation(y.reverse_bits(), seeds.first).reverse_bits();
        if !second {
            return [to_unit_float(a), 0.0];
        }
        let b = laine_karras_permutation(sobol_dim1_reversed(y), seeds.second).reverse_bits();
        [to_unit_float(a), to_unit_float(b)]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sobol_dimension_one_is_a_0_2_sequence_prefix() {
        // The first 4 points of (vdC, sobol1) are stratified in each 2x2 cell.
        let pts: Vec<(u32, u32)> = (0..4)
            .map(|i: u32| (i.reverse_bits() >> 30, sobol_dim1_by_bits(i) >> 30))
            .collect();
        let mut cells = pts.clone();
        cells.sort();
        cells.dedup();
        assert_eq!(cells.len(), 4);
    }

    /// Owen scrambling keeps the (0,2) net property: every elementary interval
    /// of area 1/N holds exactly one point for N = 2^k.
    #[test]
    fn scrambled_points_are_stratified() {
        let n = 256u32;
        for k in 0..=8u32 {
            let xs = 1u32 << k;
            let ys = n / xs;
            let mut grid = vec![0u32; n as usize];
            for i in 0..n {
                let mut s = Sampler::new(3, 7, i, 42);
                let [u, v] = s.next_2d();
                let cx = ((u * xs as f32) as u32).min(xs - 1);
                let cy = ((v * ys as f32) as u32).min(ys - 1);
                grid[(cy * xs + cx) as usize] += 1;
            }
            assert!(grid.iter().all(|&c| c == 1), "k={k}: {grid:?}");
        }
    }

    #[test]
    fn mean_is_unbiased_across_pixels() {
        let mut sum = [0.0f64; 2];
        let n = 200_000;
        for p in 0..n {
            let mut s = Sampler::new(p % 512, p / 512, 5, 1);
            s.next_2d();
            let [u, v] = s.next_2d();
            sum[0] += u as f64;
            sum[1] += v as f64;
        }
        assert!((sum[0] / n as f64 - 0.5).abs() < 0.003);
        assert!((sum[1] / n as f64 - 0.5).abs() < 0.003);
    }

    #[test]
    fn table_sobol_matches_definition() {
        let by_definition = |y: u32| sobol_dim1_by_bits(y.reverse_bits()).reverse_bits();
        let mut x = 1u32;
        for _ in 0..100_000 {
            x = hash_u32(x);
            assert_eq!(sobol_dim1_reversed(x), by_definition(x));
        }
        for i in 0..4096u32 {
            assert_eq!(sobol_dim1_reversed(i), by_definition(i));
            assert_eq!(
                sobol_dim1_reversed(i.reverse_bits()),
                by_definition(i.reverse_bits())
            );
        }
    }

    /// The point by the definition: shuffle the index with a nested uniform
    /// scramble, then scramble dimension 0 (the reversed index) and Sobol's
    /// dimension 1 each with its own seed (Burley 2020, listing 3).
    fn next_2d_by_definition(pixel_seed: u32, index: u32, dimension: u32) -> [f32; 2] {
        let dim_seed = hash_combine(pixel_seed, dimension);
        let shuffled = nested_uniform_scramble(index, dim_seed);
        let a = nested_uniform_scramble(shuffled.reverse_bits(), hash_combine(dim_seed, 1));
        let b = nested_uniform_scramble(sobol_dim1_by_bits(shuffled), hash_combine(dim_seed, 2));
        [to_unit_float(a), to_unit_float(b)]
    }

    #[test]
    fn points_match_the_definition() {
        let mut x = 7u32;
        for _ in 0..20_000 {
            x = hash_u32(x);
            let (px, py, index, seed) = (x & 1023, (x >> 10) & 1023, hash_u32(x ^ 5), x >> 28);
            let mut s = Sampler::new(px, py, index, seed);
            for d in 0..6 {
                assert_eq!(s.next_2d(), next_2d_by_definition(s.pixel_seed, index, d));
            }
        }
        for index in 0..4096 {
            let mut s = Sampler::new(3, 9, index, 1);
            assert_eq!(s.next_2d(), next_2d_by_definition(s.pixel_seed, index, 0));
        }
    }

    /// Wellons' lowbias32 and the boost-style combine, against values
    /// computed from their published definitions in Python (arbitrary
    /// precision, masked to 32 bits). A changed hash still samples well but
    /// changes every image: renders are reproducible across versions only
    /// while these stay fixed.
    #[test]
    fn hashes_match_their_definitions() {
        for (x, h) in [
            (0, 0),
            (1, 0x6889_90c0),
            (2, 0xd113_2181),
            (0xdead_beef, 0xe628_c683),
            (0xffff_ffff, 0x6768_824a),
            (123_456_789, 0xa8f1_db88),
        ] {
            assert_eq!(hash_u32(x), h, "lowbias32({x:#x})");
        }
        for (seed, v, h) in [
            (0, 0, 0x01fc_e552),
            (1, 2, 0xa7bd_535e),
            (0xdead_beef, 7, 0x33e8_088a),
            (0xffff_ffff, 0xffff_ffff, 0x927c_ba85),
            (12345, 678, 0x2ece_ad34),
        ] {
            assert_eq!(hash_combine(seed, v), h, "combine({seed:#x}, {v})");
        }
    }

    /// `next_1d` is the first coordinate of the next 2-D point (and uses up
    /// that dimension), so over 16 samples of one pixel it falls once in
    /// each sixteenth of [0, 1), as a scrambled (0, 2)-sequence's first
    /// coordinate must.
    #[test]
    fn next_1d_is_the_first_coordinate_and_stratified() {
        let mut strata = [0; 16];
        for index in 0..16 {
            let (mut one, mut two) = (Sampler::new(3, 5, index, 9), Sampler::new(3, 5, index, 9));
            for _ in 0..3 {
                let x = one.next_1d();
                assert_eq!(x, two.next_2d()[0]);
                assert!((0.0..1.0).contains(&x), "{x}");
            }
            let x = Sampler::new(3, 5, index, 9).next_1d();
            strata[(x * 16.0) as usize] += 1;
        }
        assert_eq!(strata, [1; 16]);
    }

    /// A sampler moved on with `start_sample` draws exactly the points a
    /// new sampler of that pixel and index draws: the kept seeds belong to
    /// the pixel, not to a sample. Past the kept pairs too, with streams of
    /// different lengths (a path that ends early keeps fewer).
    #[test]
    fn restarted_samples_match_new_ones() {
        let pairs = CACHED_PAIRS as u32 + 8;
        let mut reused = Sampler::for_pixel(12, 34, 77);
        for index in 0..40u32 {
            reused.start_sample(index);
            let mut fresh = Sampler::new(12, 34, index, 77);
            let drawn = (index * 7) % pairs + 1;
            for d in 0..drawn {
                if d % 3 == 0 {
                    assert_eq!(reused.next_1d(), fresh.next_1d(), "index {index}, pair {d}");
                } else {
                    assert_eq!(reused.next_2d(), fresh.next_2d(), "index {index}, pair {d}");
                }
            }
        }
        // And against the definition, pair by pair, for a sampler that has
        // kept every pair's seeds.
        let mut s = Sampler::new(5, 6, 0, 8);
        for _ in 0..pairs {
            s.next_2d();
        }
        for index in [1u32, 2, 1000, 123_456] {
            s.start_sample(index);
            for d in 0..pairs {
                assert_eq!(s.next_2d(), next_2d_by_definition(s.pixel_seed, index, d));
            }
        }
    }

    /// The blocks (sixteen pairs in one AVX-512 register, and as two AVX2
    /// blocks) draw the points that the pairs computed one at a time draw:
    /// the same bits, through blocks, past the kept pairs, with first
    /// coordinates alone, and after a restart mid-block. Fails on an
    /// x86-64 CPU without AVX2 (the blocks would go untested); the AVX-512
    /// kernel is tested where the CPU has it; other architectures have no
    /// blocks.
    #[test]
    #[cfg(target_arch = "x86_64")]
    fn blocks_match_pairs_computed_alone() {
        let kernel = Avx2::detect_avx512().expect("this test needs an x86-64 CPU with AVX2");
        if !kernel.has_avx512() {
            eprintln!("no AVX-512 here: only the AVX2 kernel is tested");
        }
        for kernel in [kernel, kernel.without_avx512()] {
            blocks_match_pairs_computed_alone_with(kernel);
        }
    }

    fn blocks_match_pairs_computed_alone_with(kernel: Avx2) {
        let pairs = CACHED_PAIRS as u32 + 12;
        let mut x = 3u32;
        for _ in 0..300 {
            x = hash_u32(x);
            let (px, py, seed) = (x & 1023, (x >> 10) & 1023, x >> 27);
            let mut blocks = Sampler::with_blocks(px, py, seed, Some(kernel));
            let mut alone = Sampler::with_blocks(px, py, seed, None);
            let mut most = 0;
            for s in 0..6 {
                let index = hash_u32(x ^ s);
                blocks.start_sample(index);
                alone.start_sample(index);
                let drawn = hash_u32(index) % pairs + 1;
                for d in 0..drawn {
                    if (d + s) % 3 == 0 {
                        let (b, a) = (blocks.next_1d(), alone.next_1d());
                        assert_eq!(b.to_bits(), a.to_bits(), "pair {d} of sample {index}");
                    } else {
                        let (b, a) = (blocks.next_2d(), alone.next_2d());
                        assert_eq!(b.map(f32::to_bits), a.map(f32::to_bits), "pair {d}");
                    }
                }
                // Seeds are hashed once per pixel: for every pair drawn so
                // far (whole groups of blocks at a time), up to the kept
                // pairs.
                most = most.max(drawn as usize).min(CACHED_PAIRS);
                assert_eq!(alone.cached as usize, most);
                let group = GROUP * BLOCK;
                assert_eq!(blocks.cached as usize, most.div_ceil(group) * group);
            }
        }
    }

    #[test]
    fn deterministic() {
        let mut a = Sampler::new(1, 2, 3, 4);
        let mut b = Sampler::new(1, 2, 3, 4);
        for _ in 0..10 {
            assert_eq!(a.next_2d(), b.next_2d());
        }
        let mut c = Sampler::new(1, 2, 3, 5);
        assert_ne!(Sampler::new(1, 2, 3, 4).next_2d(), c.next_2d());
    }
}
