//! Sixteen dimension pairs of one Sobol sample at once: in one AVX-512
//! register, or as two blocks of eight in AVX2 registers.
//!
//! The pairs of a sample are independent (each has its own scramble seeds
//! and reads the same index), so a [`super::Sampler`] computes them sixteen
//! at a time: one lane per pair, the same operations as the scalar
//! `next_2d`, so the same points to the bit. The lane arithmetic is written
//! once, over [`Lanes`] of either width. Two steps differ in form only:
//! - Sobol's dimension 1 in the reversed domain is computed, instead of
//!   looked up in byte tables, as the superset-sum (zeta) transform over
//!   GF(2) of the bit positions of `z = R(y)`: the direction numbers of the
//!   polynomial x + 1 are Pascal's triangle mod 2, and by Lucas's theorem
//!   C(k, m) is odd exactly when m's bits are a subset of k's, so output
//!   bit m is the XOR of the input bits k ⊇ m: five shift-mask-XOR steps.
//! - Bit reversal swaps the bytes of each lane, then reverses each byte's
//!   nibbles through a 16-entry table (`pshufb`).
//!
//! The module's `unsafe` code: the intrinsics, the unaligned loads and
//! stores, and calling the AVX2 and AVX-512 functions, which [`Avx2`]
//! allows only on a CPU that has them.
#![allow(unsafe_code)]

use super::sobol::{GOLDEN, LK_MULTIPLIERS, LOWBIAS_MULTIPLIERS};

/// Pairs of a block (one AVX2 register of lanes).
pub const BLOCK: usize = 8;

/// Blocks computed together (one AVX-512 register of lanes).
pub const GROUP: usize = 2;

/// Scramble seeds of [`BLOCK`] consecutive dimension pairs, one array per
/// seed (Burley 2020, listing 3): the index shuffle's, then each
/// coordinate's.
#[derive(Clone, Copy, Debug, Default)]
pub struct SeedBlock {
    pub shuffle: [u32; BLOCK],
    pub first: [u32; BLOCK],
    pub second: [u32; BLOCK],
}

/// Proof that this CPU runs AVX2: made only by [`Avx2::detect`] and
/// [`Avx2::detect_avx512`]; with whether to compute a group of blocks in
/// one AVX-512 register instead of two AVX2 ones.
#[derive(Clone, Copy, Debug)]
pub struct Avx2 {
    avx512: bool,
}

impl Avx2 {
    /// `Some` if this CPU runs AVX2: the AVX2 kernel.
    pub fn detect() -> Option<Avx2> {
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2") {
            return Some(Avx2 { avx512: false });
        }
        None
    }

    /// As [`Avx2::detect`], with the AVX-512 kernel where the CPU runs
    /// AVX-512 F and BW: for code that runs in AVX-512 registers anyway.
    /// Elsewhere its occasional wide instructions cost more than they
    /// save (the scalar path tracer ran 6 % slower on the glass scene
    /// with it, measured 2026-12-07, presumably from the CPU's switches
    /// between register widths).
    pub fn detect_avx512() -> Option<Avx2> {
        let kernel = Self::detect()?;
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx512f")
            && std::arch::is_x86_feature_detected!("avx512bw")
        {
            return Some(Avx2 { avx512: true });
        }
        Some(kernel)
    }

    /// The same kernel without AVX-512: two AVX2 blocks a group.
    #[cfg(test)]
    pub fn without_avx512(self) -> Avx2 {
        Avx2 { avx512: false }
    }

    /// Whether a group is computed in one AVX-512 register.
    #[cfg(test)]
    pub fn has_avx512(self) -> bool {
        self.avx512
    }

    /// The scramble seeds of the [`GROUP`] × [`BLOCK`] pairs from
    /// `first_dimension` on, for the pixel whose seed is `pixel_seed` (as
    /// `PairSeeds::new`).
    #[inline]
    pub fn seeds(self, pixel_seed: u32, first_dimension: u32, out: &mut [SeedBlock; GROUP]) {
        #[cfg(target_arch = "x86_64")]
        // SAFETY: an `Avx2` exists only where the CPU runs AVX2, and says
        // AVX-512 only where it runs that.
        unsafe {
            if self.avx512 {
                seeds_avx512(pixel_seed, first_dimension, out)
            } else {
                for (b, block) in out.iter_mut().enumerate() {
                    seeds_avx2(pixel_seed, first_dimension + (b * BLOCK) as u32, block)
                }
            }
        }
        #[cfg(not(target_arch = "x86_64"))]
        unreachable!("no Avx2 value exists off x86-64: {pixel_seed} {first_dimension} {out:?}")
    }

    /// The points of sample `index_reversed` (its index, bit-reversed) in
    /// the group's pairs, in [0, 1)².
    #[inline]
    pub fn points(
        self,
        index_reversed: u32,
        seeds: &[SeedBlock; GROUP],
        out: &mut [[[f32; 2]; BLOCK]; GROUP],
    ) {
        #[cfg(target_arch = "x86_64")]
        // SAFETY: as in `seeds`.
        unsafe {
            if self.avx512 {
                points_avx512(index_reversed, seeds, out)
            } else {
                for (seeds, out) in seeds.iter().zip(out) {
                    points_avx2(index_reversed, seeds, out)
                }
            }
        }
        #[cfg(not(target_arch = "x86_64"))]
        unreachable!("no Avx2 value exists off x86-64: {index_reversed} {seeds:?} {out:?}")
    }
}

#[cfg(target_arch = "x86_64")]
use std::arch::x86_64::*;

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn points_avx2(index_reversed: u32, seeds: &SeedBlock, out: &mut [[f32; 2]; BLOCK]) {
    // SAFETY: AVX2 (this function's feature); each load reads eight u32,
    // and `out` (eight [f32; 2], 64 bytes) is written by two unaligned
    // 32-byte stores.
    unsafe {
        let [shuffle, first, second] = [&seeds.shuffle, &seeds.first, &seeds.second]
            .map(|a| _mm256_loadu_si256(a.as_ptr().cast()));
        let (a, b) = pair_points::<__m256i>(index_reversed, shuffle, first, second);
        // Interleave to (a0 b0 a1 b1 …): unpack within each 128-bit half,
        // then put the halves in order.
        let lo = _mm256_unpacklo_ps(a, b);
        let hi = _mm256_unpackhi_ps(a, b);
        let out: *mut f32 = out.as_mut_ptr().cast();
        _mm256_storeu_ps(out, _mm256_permute2f128_ps(lo, hi, 0x20));
        _mm256_storeu_ps(out.add(8), _mm256_permute2f128_ps(lo, hi, 0x31));
    }
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn seeds_avx2(pixel_seed: u32, first_dimension: u32, out: &mut SeedBlock) {
    let d = _mm256_add_epi32(
        _mm256_set1_epi32(first_dimension as i32),
        _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7),
    );
    // SAFETY: AVX2 (this function's feature); each store writes eight u32.
    unsafe {
        let seeds = pair_seeds::<__m256i>(pixel_seed, d);
        for (x, a) in seeds
            .into_iter()
            .zip([&mut out.shuffle, &mut out.first, &mut out.second])
        {
            _mm256_storeu_si256(a.as_mut_ptr().cast(), x);
        }
    }
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f,avx512bw")]
fn points_avx512(
    index_reversed: u32,
    seeds: &[SeedBlock; GROUP],
    out: &mut [[[f32; 2]; BLOCK]; GROUP],
) {
    let [s0, s1] = seeds;
    // SAFETY: AVX-512 F and BW (this function's features); each load
    // reads eight u32, and `out` (sixteen [f32; 2], 128 bytes) is written
    // by two unaligned 64-byte stores.
    unsafe {
        let both = |a: &[u32; BLOCK], b: &[u32; BLOCK]| {
            _mm512_inserti64x4::<1>(
                _mm512_castsi256_si512(_mm256_loadu_si256(a.as_ptr().cast())),
                _mm256_loadu_si256(b.as_ptr().cast()),
            )
        };
        let (a, b) = pair_points::<__m512i>(
            index_reversed,
            both(&s0.shuffle, &s1.shuffle),
            both(&s0.first, &s1.first),
            both(&s0.second, &s1.second),
        );
        // Interleave to (a0 b0 a1 b1 …): output lane k of the first half
        // takes lane k/2 of a (k even) or of b (index 16 + k/2); of the
        // second half lane 8 + k/2.
        let first = _mm512_setr_epi32(0, 16, 1, 17, 2, 18, 3, 19, 4, 20, 5, 21, 6, 22, 7, 23);
        let second = _mm512_add_epi32(first, _mm512_set1_epi32(8));
        let out: *mut f32 = out.as_mut_ptr().cast();
        _mm512_storeu_ps(out, _mm512_permutex2var_ps(a, first, b));
        _mm512_storeu_ps(out.add(16), _mm512_permutex2var_ps(a, second, b));
    }
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f,avx512bw")]
fn seeds_avx512(pixel_seed: u32, first_dimension: u32, out: &mut [SeedBlock; GROUP]) {
    let d = _mm512_add_epi32(
        _mm512_set1_epi32(first_dimension as i32),
        _mm512_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15),
    );
    let [b0, b1] = out;
    // SAFETY: AVX-512 F and BW (this function's features); each store
    // writes eight u32.
    unsafe {
        let seeds = pair_seeds::<__m512i>(pixel_seed, d);
        let halves = [
            (&mut b0.shuffle, &mut b1.shuffle),
            (&mut b0.first, &mut b1.first),
            (&mut b0.second, &mut b1.second),
        ];
        for (x, (lo, hi)) in seeds.into_iter().zip(halves) {
            _mm256_storeu_si256(lo.as_mut_ptr().cast(), _mm512_castsi512_si256(x));
            _mm256_storeu_si256(hi.as_mut_ptr().cast(), _mm512_extracti64x4_epi64::<1>(x));
        }
    }
}

/// The points of one pair per lane, `(R(LK(z)), R(LK(sobol1(z))))` with
/// `z = R(LK(index))`, as the scalar `Sampler::point`.
///
/// # Safety
/// The CPU must run `V`'s instructions.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
unsafe fn pair_points<V: Lanes>(
    index_reversed: u32,
    shuffle: V,
    first: V,
    second: V,
) -> (V::F, V::F) {
    // SAFETY: the caller's contract.
    unsafe {
        let z = reverse_bits(laine_karras(V::splat(index_reversed), shuffle));
        let a = reverse_bits(laine_karras(z, first)).unit();
        let b = reverse_bits(laine_karras(sobol_dim1_of_reversed(z), second)).unit();
        (a, b)
    }
}

/// Per lane the three scramble seeds of the dimension pair in
/// `dimension`, as `PairSeeds::new`.
///
/// # Safety
/// The CPU must run `V`'s instructions.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
unsafe fn pair_seeds<V: Lanes>(pixel_seed: u32, dimension: V) -> [V; 3] {
    // SAFETY: the caller's contract.
    unsafe {
        let shuffle = hash_combine(V::splat(pixel_seed), dimension);
        [
            shuffle,
            hash_combine(shuffle, V::splat(1)),
            hash_combine(shuffle, V::splat(2)),
        ]
    }
}

/// `hash_combine`, lane by lane: `hash_u32(seed ^ (v + φ + (seed << 6) +
/// (seed >> 2)))`, with `hash_u32` Wellons' lowbias32.
///
/// # Safety
/// The CPU must run `V`'s instructions.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
unsafe fn hash_combine<V: Lanes>(seed: V, v: V) -> V {
    // SAFETY: the caller's contract.
    unsafe {
        let sum = v
            .add(V::splat(GOLDEN))
            .add(seed.shl32(6).add(seed.shr32(2)));
        let mut x = seed.xor(sum);
        let [m1, m2] = LOWBIAS_MULTIPLIERS;
        x = x.xor(x.shr32(16));
        x = x.mullo(V::splat(m1));
        x = x.xor(x.shr32(15));
        x = x.mullo(V::splat(m2));
        x.xor(x.shr32(16))
    }
}

/// `x + seed`, then `x ^= x * m` for each Laine–Karras multiplier.
///
/// # Safety
/// The CPU must run `V`'s instructions.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
unsafe fn laine_karras<V: Lanes>(x: V, seed: V) -> V {
    // SAFETY: the caller's contract.
    unsafe {
        let mut x = x.add(seed);
        for m in LK_MULTIPLIERS {
            x = x.xor(x.mullo(V::splat(m)));
        }
        x
    }
}

/// Each lane's 32 bits in reverse order: its bytes swapped, then each
/// byte's nibbles reversed through a 16-entry table (`pshufb`).
///
/// # Safety
/// The CPU must run `V`'s instructions.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
unsafe fn reverse_bits<V: Lanes>(x: V) -> V {
    const SWAP: [i8; 16] = [3, 2, 1, 0, 7, 6, 5, 4, 11, 10, 9, 8, 15, 14, 13, 12];
    const NIBBLE: [i8; 16] = [
        0x0, 0x8, 0x4, 0xc, 0x2, 0xa, 0x6, 0xe, 0x1, 0x9, 0x5, 0xd, 0x3, 0xb, 0x7, 0xf,
    ];
    // SAFETY: the caller's contract.
    unsafe {
        let low = V::splat(0x0f0f_0f0f);
        let x = x.shuffle_bytes(V::bytes(SWAP));
        let lo = V::bytes(NIBBLE).shuffle_bytes(x.and(low));
        let hi = V::bytes(NIBBLE).shuffle_bytes(x.shr16(4).and(low));
        // Each reversed nibble is below 16, so the 16-bit shift keeps it
        // in its byte.
        lo.shl16(4).or(hi)
    }
}

/// Sobol dimension 1 in the reversed domain, from `z = R(y)`: bit m of the
/// result is the XOR of the bits k ⊇ m of `z` (one step per bit of m).
///
/// # Safety
/// The CPU must run `V`'s instructions.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
unsafe fn sobol_dim1_of_reversed<V: Lanes>(z: V) -> V {
    // SAFETY: the caller's contract.
    unsafe {
        let z = z.xor(z.shr32(1).and(V::splat(0x5555_5555)));
        let z = z.xor(z.shr32(2).and(V::splat(0x3333_3333)));
        let z = z.xor(z.shr32(4).and(V::splat(0x0f0f_0f0f)));
        let z = z.xor(z.shr32(8).and(V::splat(0x00ff_00ff)));
        z.xor(z.shr32(16).and(V::splat(0x0000_ffff)))
    }
}

/// 32-bit lanes of an AVX2 or AVX-512 register, with the operations the
/// sampler's kernels need. Every method is `#[inline(always)]`, so that
/// it is inlined into the kernel compiled for its instructions before
/// the intrinsic it calls is (a function without those features could
/// not inline it).
///
/// # Safety
/// The methods may be called only on a CPU that runs the type's
/// instructions.
#[cfg(target_arch = "x86_64")]
trait Lanes: Copy {
    /// As many f32 lanes.
    type F;
    unsafe fn splat(x: u32) -> Self;
    /// 16 bytes in every 128-bit part.
    unsafe fn bytes(b: [i8; 16]) -> Self;
    unsafe fn add(self, o: Self) -> Self;
    unsafe fn xor(self, o: Self) -> Self;
    unsafe fn and(self, o: Self) -> Self;
    unsafe fn or(self, o: Self) -> Self;
    /// The low 32 bits of each lane's product.
    unsafe fn mullo(self, o: Self) -> Self;
    /// Shifts by a constant `count` (one immediate shift once inlined).
    unsafe fn shr32(self, count: i32) -> Self;
    unsafe fn shl32(self, count: i32) -> Self;
    unsafe fn shr16(self, count: i32) -> Self;
    unsafe fn shl16(self, count: i32) -> Self;
    /// In every 128-bit part, the bytes of `self` at the indices in the
    /// bytes of `index` (`pshufb`).
    unsafe fn shuffle_bytes(self, index: Self) -> Self;
    /// The top 24 bits as a float in [0, 1), exactly as `to_unit_float`.
    unsafe fn unit(self) -> Self::F;
}

#[cfg(target_arch = "x86_64")]
impl Lanes for __m256i {
    type F = __m256;
    #[inline(always)]
    unsafe fn splat(x: u32) -> Self {
        unsafe { _mm256_set1_epi32(x as i32) }
    }
    #[inline(always)]
    unsafe fn bytes(b: [i8; 16]) -> Self {
        unsafe { _mm256_broadcastsi128_si256(_mm_loadu_si128(b.as_ptr().cast())) }
    }
    #[inline(always)]
    unsafe fn add(self, o: Self) -> Self {
        unsafe { _mm256_add_epi32(self, o) }
    }
    #[inline(always)]
    unsafe fn xor(self, o: Self) -> Self {
        unsafe { _mm256_xor_si256(self, o) }
    }
    #[inline(always)]
    unsafe fn and(self, o: Self) -> Self {
        unsafe { _mm256_and_si256(self, o) }
    }
    #[inline(always)]
    unsafe fn or(self, o: Self) -> Self {
        unsafe { _mm256_or_si256(self, o) }
    }
    #[inline(always)]
    unsafe fn mullo(self, o: Self) -> Self {
        unsafe { _mm256_mullo_epi32(self, o) }
    }
    #[inline(always)]
    unsafe fn shr32(self, count: i32) -> Self {
        unsafe { _mm256_srl_epi32(self, _mm_cvtsi32_si128(count)) }
    }
    #[inline(always)]
    unsafe fn shl32(self, count: i32) -> Self {
        unsafe { _mm256_sll_epi32(self, _mm_cvtsi32_si128(count)) }
    }
    #[inline(always)]
    unsafe fn shr16(self, count: i32) -> Self {
        unsafe { _mm256_srl_epi16(self, _mm_cvtsi32_si128(count)) }
    }
    #[inline(always)]
    unsafe fn shl16(self, count: i32) -> Self {
        unsafe { _mm256_sll_epi16(self, _mm_cvtsi32_si128(count)) }
    }
    #[inline(always)]
    unsafe fn shuffle_bytes(self, index: Self) -> Self {
        unsafe { _mm256_shuffle_epi8(self, index) }
    }
    #[inline(always)]
    unsafe fn unit(self) -> __m256 {
        unsafe {
            _mm256_mul_ps(
                _mm256_cvtepi32_ps(_mm256_srli_epi32::<8>(self)),
                _mm256_set1_ps(1.0 / (1u32 << 24) as f32),
            )
        }
    }
}

#[cfg(target_arch = "x86_64")]
impl Lanes for __m512i {
    type F = __m512;
    #[inline(always)]
    unsafe fn splat(x: u32) -> Self {
        unsafe { _mm512_set1_epi32(x as i32) }
    }
    #[inline(always)]
    unsafe fn bytes(b: [i8; 16]) -> Self {
        unsafe { _mm512_broadcast_i32x4(_mm_loadu_si128(b.as_ptr().cast())) }
    }
    #[inline(always)]
    unsafe fn add(self, o: Self) -> Self {
        unsafe { _mm512_add_epi32(self, o) }
    }
    #[inline(always)]
    unsafe fn xor(self, o: Self) -> Self {
        unsafe { _mm512_xor_si512(self, o) }
    }
    #[inline(always)]
    unsafe fn and(self, o: Self) -> Self {
        unsafe { _mm512_and_si512(self, o) }
    }
    #[inline(always)]
    unsafe fn or(self, o: Self) -> Self {
        unsafe { _mm512_or_si512(self, o) }
    }
    #[inline(always)]
    unsafe fn mullo(self, o: Self) -> Self {
        unsafe { _mm512_mullo_epi32(self, o) }
    }
    #[inline(always)]
    unsafe fn shr32(self, count: i32) -> Self {
        unsafe { _mm512_srl_epi32(self, _mm_cvtsi32_si128(count)) }
    }
    #[inline(always)]
    unsafe fn shl32(self, count: i32) -> Self {
        unsafe { _mm512_sll_epi32(self, _mm_cvtsi32_si128(count)) }
    }
    #[inline(always)]
    unsafe fn shr16(self, count: i32) -> Self {
        unsafe { _mm512_srl_epi16(self, _mm_cvtsi32_si128(count)) }
    }
    #[inline(always)]
    unsafe fn shl16(self, count: i32) -> Self {
        unsafe { _mm512_sll_epi16(self, _mm_cvtsi32_si128(count)) }
    }
    #[inline(always)]
    unsafe fn shuffle_bytes(self, index: Self) -> Self {
        unsafe { _mm512_shuffle_epi8(self, index) }
    }
    #[inline(always)]
    unsafe fn unit(self) -> __m512 {
        unsafe {
            _mm512_mul_ps(
                _mm512_cvtepi32_ps(_mm512_srli_epi32::<8>(self)),
                _mm512_set1_ps(1.0 / (1u32 << 24) as f32),
            )
        }
    }
}
