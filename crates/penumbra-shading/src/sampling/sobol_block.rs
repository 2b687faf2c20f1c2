//! Eight dimension pairs of one Sobol sample at once, in AVX2 lanes.
//!
//! The pairs of a sample are independent (each has its own scramble seeds
//! and reads the same index), so a [`super::Sampler`] computes them eight
//! at a time: one lane per pair, the same operations as the scalar
//! `next_2d`, so the same points to the bit. Two steps differ in form only:
//! - Sobol's dimension 1 in the reversed domain is computed, instead of
//!   looked up in byte tables, as the superset-sum (zeta) transform over
//!   GF(2) of the bit positions of `z = R(y)`: the direction numbers of the
//!   polynomial x + 1 are Pascal's triangle mod 2, and by Lucas's theorem
//!   C(k, m) is odd exactly when m's bits are a subset of k's, so output
//!   bit m is the XOR of the input bits k ⊇ m: five shift-mask-XOR steps.
//! - Bit reversal swaps the bytes of each lane, then reverses each byte's
//!   nibbles through a 16-entry table (`pshufb`).
//!
//! The module's `unsafe` code: the unaligned loads and stores, and calling
//! the AVX2 function, which [`Avx2`] allows only on a CPU that has it.
#![allow(unsafe_code)]

use super::sobol::{GOLDEN, LK_MULTIPLIERS, LOWBIAS_MULTIPLIERS};

/// Pairs computed at once.
pub const BLOCK: usize = 8;

/// Scramble seeds of [`BLOCK`] consecutive dimension pairs, one array per
/// seed (Burley 2020, listing 3): the index shuffle's, then each
/// coordinate's.
#[derive(Clone, Copy, Debug, Default)]
pub struct SeedBlock {
    pub shuffle: [u32; BLOCK],
    pub first: [u32; BLOCK],
    pub second: [u32; BLOCK],
}

/// Proof that this CPU runs AVX2: made only by [`Avx2::detect`].
#[derive(Clone, Copy, Debug)]
pub struct Avx2(());

impl Avx2 {
    /// `Some` if this CPU runs AVX2.
    pub fn detect() -> Option<Avx2> {
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2") {
            return Some(Avx2(()));
        }
        None
    }

    /// The scramble seeds of the eight pairs from `first_dimension` on, for
    /// the pixel whose seed is `pixel_seed` (as `PairSeeds::new`).
    #[inline]
    pub fn seeds(self, pixel_seed: u32, first_dimension: u32, out: &mut SeedBlock) {
        #[cfg(target_arch = "x86_64")]
        // SAFETY: an `Avx2` exists only where the CPU runs AVX2.
        unsafe {
            seeds_avx2(pixel_seed, first_dimension, out)
        }
        #[cfg(not(target_arch = "x86_64"))]
        unreachable!("no Avx2 value exists off x86-64: {pixel_seed} {first_dimension} {out:?}")
    }

    /// The points of sample `index_reversed` (its index, bit-reversed) in
    /// the block's eight pairs, in [0, 1)².
    #[inline]
    pub fn points(self, index_reversed: u32, seeds: &SeedBlock, out: &mut [[f32; 2]; BLOCK]) {
        #[cfg(target_arch = "x86_64")]
        // SAFETY: an `Avx2` exists only where the CPU runs AVX2.
        unsafe {
            points_avx2(index_reversed, seeds, out)
        }
        #[cfg(not(target_arch = "x86_64"))]
        unreachable!("no Avx2 value exists off x86-64: {index_reversed} {seeds:?} {out:?}")
    }
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn points_avx2(index_reversed: u32, seeds: &SeedBlock, out: &mut [[f32; 2]; BLOCK]) {
    use std::arch::x86_64::*;
    let y = laine_karras(
        _mm256_set1_epi32(index_reversed as i32),
        load(&seeds.shuffle),
    );
    let z = reverse_bits(y);
    let a = unit(reverse_bits(laine_karras(z, load(&seeds.first))));
    let b = unit(reverse_bits(laine_karras(
        sobol_dim1_of_reversed(z),
        load(&seeds.second),
    )));
    // Interleave to (a0 b0 a1 b1 …): unpack within each 128-bit half, then
    // put the halves in order.
    let lo = _mm256_unpacklo_ps(a, b);
    let hi = _mm256_unpackhi_ps(a, b);
    let out: *mut f32 = out.as_mut_ptr().cast();
    // SAFETY: `out` is eight [f32; 2], 64 bytes, written by two unaligned
    // 32-byte stores.
    unsafe {
        _mm256_storeu_ps(out, _mm256_permute2f128_ps(lo, hi, 0x20));
        _mm256_storeu_ps(out.add(8), _mm256_permute2f128_ps(lo, hi, 0x31));
    }
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn seeds_avx2(pixel_seed: u32, first_dimension: u32, out: &mut SeedBlock) {
    use std::arch::x86_64::*;
    let d = _mm256_add_epi32(
        _mm256_set1_epi32(first_dimension as i32),
        _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7),
    );
    let shuffle = hash_combine(_mm256_set1_epi32(pixel_seed as i32), d);
    let first = hash_combine(shuffle, _mm256_set1_epi32(1));
    let second = hash_combine(shuffle, _mm256_set1_epi32(2));
    store(shuffle, &mut out.shuffle);
    store(first, &mut out.first);
    store(second, &mut out.second);
}

#[cfg(target_arch = "x86_64")]
use std::arch::x86_64::{__m256, __m256i};

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
#[inline]
fn store(x: __m256i, a: &mut [u32; BLOCK]) {
    // SAFETY: eight u32, written with one unaligned 32-byte store.
    unsafe { std::arch::x86_64::_mm256_storeu_si256(a.as_mut_ptr().cast(), x) }
}

/// `hash_combine`, lane by lane: `hash_u32(seed ^ (v + φ + (seed << 6) +
/// (seed >> 2)))`, with `hash_u32` Wellons' lowbias32.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
#[inline]
fn hash_combine(seed: __m256i, v: __m256i) -> __m256i {
    use std::arch::x86_64::*;
    let sum = _mm256_add_epi32(
        _mm256_add_epi32(v, _mm256_set1_epi32(GOLDEN as i32)),
        _mm256_add_epi32(_mm256_slli_epi32(seed, 6), _mm256_srli_epi32(seed, 2)),
    );
    let mut x = _mm256_xor_si256(seed, sum);
    let [m1, m2] = LOWBIAS_MULTIPLIERS;
    x = _mm256_xor_si256(x, _mm256_srli_epi32(x, 16));
    x = _mm256_mullo_epi32(x, _mm256_set1_epi32(m1 as i32));
    x = _mm256_xor_si256(x, _mm256_srli_epi32(x, 15));
    x = _mm256_mullo_epi32(x, _mm256_set1_epi32(m2 as i32));
    _mm256_xor_si256(x, _mm256_srli_epi32(x, 16))
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
#[inline]
fn load(a: &[u32; BLOCK]) -> __m256i {
    // SAFETY: eight u32, read with one unaligned 32-byte load.
    unsafe { std::arch::x86_64::_mm256_loadu_si256(a.as_ptr().cast()) }
}

/// `x + seed`, then `x ^= x * m` for each Laine–Karras multiplier.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
#[inline]
fn laine_karras(x: __m256i, seed: __m256i) -> __m256i {
    use std::arch::x86_64::*;
    let mut x = _mm256_add_epi32(x, seed);
    for m in LK_MULTIPLIERS {
        x = _mm256_xor_si256(x, _mm256_mullo_epi32(x, _mm256_set1_epi32(m as i32)));
    }
    x
}

/// Each lane's 32 bits in reverse order.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
#[inline]
fn reverse_bits(x: __m256i) -> __m256i {
    use std::arch::x86_64::*;
    let swap = _mm256_setr_epi8(
        3, 2, 1, 0, 7, 6, 5, 4, 11, 10, 9, 8, 15, 14, 13, 12, //
        3, 2, 1, 0, 7, 6, 5, 4, 11, 10, 9, 8, 15, 14, 13, 12,
    );
    let nibble = _mm256_setr_epi8(
        0x0, 0x8, 0x4, 0xc, 0x2, 0xa, 0x6, 0xe, 0x1, 0x9, 0x5, 0xd, 0x3, 0xb, 0x7, 0xf, //
        0x0, 0x8, 0x4, 0xc, 0x2, 0xa, 0x6, 0xe, 0x1, 0x9, 0x5, 0xd, 0x3, 0xb, 0x7, 0xf,
    );
    let low = _mm256_set1_epi8(0x0f);
    let x = _mm256_shuffle_epi8(x, swap);
    let lo = _mm256_shuffle_epi8(nibble, _mm256_and_si256(x, low));
    let hi = _mm256_shuffle_epi8(nibble, _mm256_and_si256(_mm256_srli_epi16(x, 4), low));
    // Each reversed nibble is below 16, so the 16-bit shift keeps it in
    // its byte.
    _mm256_or_si256(_mm256_slli_epi16(lo, 4), hi)
}

/// Sobol dimension 1 in the reversed domain, from `z = R(y)`: bit m of the
/// result is the XOR of the bits k ⊇ m of `z` (one step per bit of m).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
#[inline]
fn sobol_dim1_of_reversed(mut z: __m256i) -> __m256i {
    use std::arch::x86_64::*;
    macro_rules! step {
        ($shift:literal, $mask:literal) => {
            z = _mm256_xor_si256(
                z,
                _mm256_and_si256(_mm256_srli_epi32(z, $shift), _mm256_set1_epi32($mask)),
            );
        };
    }
    step!(1, 0x5555_5555);
    step!(2, 0x3333_3333);
    step!(4, 0x0f0f_0f0f);
    step!(8, 0x00ff_00ff);
    step!(16, 0x0000_ffff);
    z
}

/// The top 24 bits as a float in [0, 1), exactly as `to_unit_float`.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
#[inline]
fn unit(x: __m256i) -> __m256 {
    use std::arch::x86_64::*;
    _mm256_mul_ps(
        _mm256_cvtepi32_ps(_mm256_srli_epi32(x, 8)),
        _mm256_set1_ps(1.0 / (1u32 << 24) as f32),
    )
}
