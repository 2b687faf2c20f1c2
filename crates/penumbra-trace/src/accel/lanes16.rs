//! Sixteen f32 lanes, in one AVX-512 register ([`Avx512`]) or two AVX2
//! ones ([`Avx2`]): the operations the scans (`scan.rs`,
//! `cluster_scan.rs`) and the wavefront path tracer are written with, so
//! that one algorithm serves both kinds of CPU. Each is one instruction
//! per register, but for the lane reads and reductions (a few per ray);
//! comparisons give a mask ([`Simd16::M`]: AVX-512's mask register, a
//! lane-wide mask on AVX2), turned into lane bits (bit i for lane i) where
//! control flow needs them.
//!
//! The functions are `unsafe`: the CPU must support the kind's features
//! (the callers check them once, with [`Simd16::supported`]), and they
//! are inlined into the callers compiled for those features. (No
//! closures around them: a closure's body would not be inlined before
//! its intrinsics are, and they would stay calls.)
//!
//! One of the crate's modules with `unsafe` code: its intrinsics.
#![allow(unsafe_code)]

use std::arch::x86_64::*;

/// Sixteen lanes of f32 and u32 with their masks.
///
/// # Safety
/// Every function needs the CPU features [`Simd16::supported`] checks;
/// `load` and `load_u32` need a pointer to sixteen values aligned to 64
/// bytes.
pub(crate) trait Simd16: Copy {
    /// Sixteen f32.
    type V: Copy;
    /// Sixteen u32.
    type I: Copy;
    /// A mask of sixteen lanes.
    type M: Copy;
    /// Whether this is the AVX-512 kind (for code with an AVX-512 form of
    /// its own).
    const AVX512: bool;

    /// Whether this CPU runs the kind's instructions, and those its
    /// callers are compiled with beside them (the wavefront tracer's
    /// entry points).
    fn supported() -> bool;

    unsafe fn splat(x: f32) -> Self::V;
    unsafe fn load(p: *const f32) -> Self::V;
    unsafe fn load_u32(p: *const u32) -> Self::I;
    unsafe fn splat_u32(x: u32) -> Self::I;
    unsafe fn add(a: Self::V, b: Self::V) -> Self::V;
    unsafe fn sub(a: Self::V, b: Self::V) -> Self::V;
    unsafe fn mul(a: Self::V, b: Self::V) -> Self::V;
    unsafe fn min(a: Self::V, b: Self::V) -> Self::V;
    unsafe fn max(a: Self::V, b: Self::V) -> Self::V;
    /// 1 / a, correctly rounded.
    unsafe fn recip(a: Self::V) -> Self::V;
    /// 1 / a within about an ulp (for ranking distances): AVX-512's
    /// 14-bit estimate with one Newton step; AVX2's division.
    unsafe fn recip_fast(a: Self::V) -> Self::V;
    /// a < b, ordered (false where either is NaN), and so on.
    unsafe fn lt(a: Self::V, b: Self::V) -> Self::M;
    unsafe fn gt(a: Self::V, b: Self::V) -> Self::M;
    unsafe fn le(a: Self::V, b: Self::V) -> Self::M;
    unsafe fn eq(a: Self::V, b: Self::V) -> Self::M;
    unsafe fn eq_u32(a: Self::I, b: Self::I) -> Self::M;
    unsafe fn and(a: Self::M, b: Self::M) -> Self::M;
    unsafe fn or(a: Self::M, b: Self::M) -> Self::M;
    /// `b` and not `a`.
    unsafe fn and_not(a: Self::M, b: Self::M) -> Self::M;
    /// The lane bits of `m`.
    unsafe fn bits(m: Self::M) -> u16;
    /// The mask of the lane bits `b`.
    unsafe fn mask(b: u16) -> Self::M;
    /// `b` where `m` holds, else `a`.
    unsafe fn blend(m: Self::M, a: Self::V, b: Self::V) -> Self::V;
    unsafe fn blend_u32(m: Self::M, a: Self::I, b: Self::I) -> Self::I;
    /// Lane `i` (below 16).
    unsafe fn lane(v: Self::V, i: u32) -> f32;
    unsafe fn lane_u32(v: Self::I, i: u32) -> u32;
    /// The least of the lanes of the bits `b` (not 0).
    unsafe fn reduce_min(b: u16, v: Self::V) -> f32;
    unsafe fn reduce_min_u32(b: u16, v: Self::I) -> u32;
}

/// One AVX-512 register (F; the wavefront tracer's callers also use VL,
/// DQ and BW).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Avx512;

/// Two AVX2 registers, lanes 0–7 in the first.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Avx2;

impl Simd16 for Avx512 {
    type V = __m512;
    type I = __m512i;
    type M = __mmask16;
    const AVX512: bool = true;

    fn supported() -> bool {
        Avx2::supported()
            && is_x86_feature_detected!("avx512f")
            && is_x86_feature_detected!("avx512vl")
            && is_x86_feature_detected!("avx512dq")
            && is_x86_feature_detected!("avx512bw")
    }

    #[inline(always)]
    unsafe fn splat(x: f32) -> __m512 {
        unsafe { _mm512_set1_ps(x) }
    }
    #[inline(always)]
    unsafe fn load(p: *const f32) -> __m512 {
        unsafe { _mm512_load_ps(p) }
    }
    #[inline(always)]
    unsafe fn load_u32(p: *const u32) -> __m512i {
        unsafe { _mm512_load_si512(p.cast()) }
    }
    #[inline(always)]
    unsafe fn splat_u32(x: u32) -> __m512i {
        unsafe { _mm512_set1_epi32(x as i32) }
    }
    #[inline(always)]
    unsafe fn add(a: __m512, b: __m512) -> __m512 {
        unsafe { _mm512_add_ps(a, b) }
    }
    #[inline(always)]
    unsafe fn sub(a: __m512, b: __m512) -> __m512 {
        unsafe { _mm512_sub_ps(a, b) }
    }
    #[inline(always)]
    unsafe fn mul(a: __m512, b: __m512) -> __m512 {
        unsafe { _mm512_mul_ps(a, b) }
    }
    #[inline(always)]
    unsafe fn min(a: __m512, b: __m512) -> __m512 {
        unsafe { _mm512_min_ps(a, b) }
    }
    #[inline(always)]
    unsafe fn max(a: __m512, b: __m512) -> __m512 {
        unsafe { _mm512_max_ps(a, b) }
    }
    #[inline(always)]
    unsafe fn recip(a: __m512) -> __m512 {
        unsafe { _mm512_div_ps(_mm512_set1_ps(1.0), a) }
    }
    #[inline(always)]
    unsafe fn recip_fast(a: __m512) -> __m512 {
        unsafe {
            let r = _mm512_rcp14_ps(a);
            _mm512_mul_ps(r, _mm512_fnmadd_ps(a, r, _mm512_set1_ps(2.0)))
        }
    }
    #[inline(always)]
    unsafe fn lt(a: __m512, b: __m512) -> u16 {
        unsafe { _mm512_cmp_ps_mask::<_CMP_LT_OQ>(a, b) }
    }
    #[inline(always)]
    unsafe fn gt(a: __m512, b: __m512) -> u16 {
        unsafe { _mm512_cmp_ps_mask::<_CMP_GT_OQ>(a, b) }
    }
    #[inline(always)]
    unsafe fn le(a: __m512, b: __m512) -> u16 {
        unsafe { _mm512_cmp_ps_mask::<_CMP_LE_OQ>(a, b) }
    }
    #[inline(always)]
    unsafe fn eq(a: __m512, b: __m512) -> u16 {
        unsafe { _mm512_cmp_ps_mask::<_CMP_EQ_OQ>(a, b) }
    }
    #[inline(always)]
    unsafe fn eq_u32(a: __m512i, b: __m512i) -> u16 {
        unsafe { _mm512_cmpeq_epi32_mask(a, b) }
    }
    #[inline(always)]
    unsafe fn and(a: u16, b: u16) -> u16 {
        a & b
    }
    #[inline(always)]
    unsafe fn or(a: u16, b: u16) -> u16 {
        a | b
    }
    #[inline(always)]
    unsafe fn and_not(a: u16, b: u16) -> u16 {
        !a & b
    }
    #[inline(always)]
    unsafe fn bits(m: u16) -> u16 {
        m
    }
    #[inline(always)]
    unsafe fn mask(b: u16) -> u16 {
        b
    }
    #[inline(always)]
    unsafe fn blend(m: u16, a: __m512, b: __m512) -> __m512 {
        unsafe { _mm512_mask_blend_ps(m, a, b) }
    }
    #[inline(always)]
    unsafe fn blend_u32(m: u16, a: __m512i, b: __m512i) -> __m512i {
        unsafe { _mm512_mask_blend_epi32(m, a, b) }
    }
    #[inline(always)]
    unsafe fn lane(v: __m512, i: u32) -> f32 {
        unsafe { _mm512_cvtss_f32(_mm512_permutexvar_ps(_mm512_set1_epi32(i as i32), v)) }
    }
    #[inline(always)]
    unsafe fn lane_u32(v: __m512i, i: u32) -> u32 {
        unsafe {
            _mm512_cvtsi512_si32(_mm512_permutexvar_epi32(_mm512_set1_epi32(i as i32), v)) as u32
        }
    }
    #[inline(always)]
    unsafe fn reduce_min(b: u16, v: __m512) -> f32 {
        unsafe { _mm512_mask_reduce_min_ps(b, v) }
    }
    #[inline(always)]
    unsafe fn reduce_min_u32(b: u16, v: __m512i) -> u32 {
        unsafe { _mm512_mask_reduce_min_epu32(b, v) }
    }
}

impl Simd16 for Avx2 {
    type V = [__m256; 2];
    type I = [__m256i; 2];
    type M = [__m256; 2];
    const AVX512: bool = false;

    fn supported() -> bool {
        is_x86_feature_detected!("avx2")
            && is_x86_feature_detected!("fma")
            && is_x86_feature_detected!("bmi1")
            && is_x86_feature_detected!("bmi2")
            && is_x86_feature_detected!("lzcnt")
            && is_x86_feature_detected!("popcnt")
    }

    #[inline(always)]
    unsafe fn splat(x: f32) -> [__m256; 2] {
        unsafe { [_mm256_set1_ps(x); 2] }
    }
    #[inline(always)]
    unsafe fn load(p: *const f32) -> [__m256; 2] {
        unsafe { [_mm256_load_ps(p), _mm256_load_ps(p.add(8))] }
    }
    #[inline(always)]
    unsafe fn load_u32(p: *const u32) -> [__m256i; 2] {
        unsafe {
            [
                _mm256_load_si256(p.cast()),
                _mm256_load_si256(p.add(8).cast()),
            ]
        }
    }
    #[inline(always)]
    unsafe fn splat_u32(x: u32) -> [__m256i; 2] {
        unsafe { [_mm256_set1_epi32(x as i32); 2] }
    }
    #[inline(always)]
    unsafe fn add(a: [__m256; 2], b: [__m256; 2]) -> [__m256; 2] {
        unsafe { [_mm256_add_ps(a[0], b[0]), _mm256_add_ps(a[1], b[1])] }
    }
    #[inline(always)]
    unsafe fn sub(a: [__m256; 2], b: [__m256; 2]) -> [__m256; 2] {
        unsafe { [_mm256_sub_ps(a[0], b[0]), _mm256_sub_ps(a[1], b[1])] }
    }
    #[inline(always)]
    unsafe fn mul(a: [__m256; 2], b: [__m256; 2]) -> [__m256; 2] {
        unsafe { [_mm256_mul_ps(a[0], b[0]), _mm256_mul_ps(a[1], b[1])] }
    }
    #[inline(always)]
    unsafe fn min(a: [__m256; 2], b: [__m256; 2]) -> [__m256; 2] {
        unsafe { [_mm256_min_ps(a[0], b[0]), _mm256_min_ps(a[1], b[1])] }
    }
    #[inline(always)]
    unsafe fn max(a: [__m256; 2], b: [__m256; 2]) -> [__m256; 2] {
        unsafe { [_mm256_max_ps(a[0], b[0]), _mm256_max_ps(a[1], b[1])] }
    }
    #[inline(always)]
    unsafe fn recip(a: [__m256; 2]) -> [__m256; 2] {
        unsafe {
            let one = _mm256_set1_ps(1.0);
            [_mm256_div_ps(one, a[0]), _mm256_div_ps(one, a[1])]
        }
    }
    #[inline(always)]
    unsafe fn recip_fast(a: [__m256; 2]) -> [__m256; 2] {
        // (AVX2's 12-bit estimate with one Newton step is a few ulps off;
        // the division is within budget here.)
        unsafe { Self::recip(a) }
    }
    #[inline(always)]
    unsafe fn lt(a: [__m256; 2], b: [__m256; 2]) -> [__m256; 2] {
        unsafe {
            [
                _mm256_cmp_ps::<_CMP_LT_OQ>(a[0], b[0]),
                _mm256_cmp_ps::<_CMP_LT_OQ>(a[1], b[1]),
            ]
        }
    }
    #[inline(always)]
    unsafe fn gt(a: [__m256; 2], b: [__m256; 2]) -> [__m256; 2] {
        unsafe {
            [
                _mm256_cmp_ps::<_CMP_GT_OQ>(a[0], b[0]),
                _mm256_cmp_ps::<_CMP_GT_OQ>(a[1], b[1]),
            ]
        }
    }
    #[inline(always)]
    unsafe fn le(a: [__m256; 2], b: [__m256; 2]) -> [__m256; 2] {
        unsafe {
            [
                _mm256_cmp_ps::<_CMP_LE_OQ>(a[0], b[0]),
                _mm256_cmp_ps::<_CMP_LE_OQ>(a[1], b[1]),
            ]
        }
    }
    #[inline(always)]
    unsafe fn eq(a: [__m256; 2], b: [__m256; 2]) -> [__m256; 2] {
        unsafe {
            [
                _mm256_cmp_ps::<_CMP_EQ_OQ>(a[0], b[0]),
                _mm256_cmp_ps::<_CMP_EQ_OQ>(a[1], b[1]),
            ]
        }
    }
    #[inline(always)]
    unsafe fn eq_u32(a: [__m256i; 2], b: [__m256i; 2]) -> [__m256; 2] {
        unsafe {
            [
                _mm256_castsi256_ps(_mm256_cmpeq_epi32(a[0], b[0])),
                _mm256_castsi256_ps(_mm256_cmpeq_epi32(a[1], b[1])),
            ]
        }
    }
    #[inline(always)]
    unsafe fn and(a: [__m256; 2], b: [__m256; 2]) -> [__m256; 2] {
        unsafe { [_mm256_and_ps(a[0], b[0]), _mm256_and_ps(a[1], b[1])] }
    }
    #[inline(always)]
    unsafe fn or(a: [__m256; 2], b: [__m256; 2]) -> [__m256; 2] {
        unsafe { [_mm256_or_ps(a[0], b[0]), _mm256_or_ps(a[1], b[1])] }
    }
    #[inline(always)]
    unsafe fn and_not(a: [__m256; 2], b: [__m256; 2]) -> [__m256; 2] {
        unsafe { [_mm256_andnot_ps(a[0], b[0]), _mm256_andnot_ps(a[1], b[1])] }
    }
    #[inline(always)]
    unsafe fn bits(m: [__m256; 2]) -> u16 {
        unsafe { (_mm256_movemask_ps(m[0]) | (_mm256_movemask_ps(m[1]) << 8)) as u16 }
    }
    #[inline(always)]
    unsafe fn mask(b: u16) -> [__m256; 2] {
        // (Written out: intrinsics in a closure would not be inlined.)
        unsafe {
            let lanes = _mm256_setr_epi32(1, 2, 4, 8, 16, 32, 64, 128);
            let low = _mm256_and_si256(_mm256_set1_epi32(i32::from(b & 0xff)), lanes);
            let high = _mm256_and_si256(_mm256_set1_epi32(i32::from(b >> 8)), lanes);
            [
                _mm256_castsi256_ps(_mm256_cmpeq_epi32(low, lanes)),
                _mm256_castsi256_ps(_mm256_cmpeq_epi32(high, lanes)),
            ]
        }
    }
    #[inline(always)]
    unsafe fn blend(m: [__m256; 2], a: [__m256; 2], b: [__m256; 2]) -> [__m256; 2] {
        unsafe {
            [
                _mm256_blendv_ps(a[0], b[0], m[0]),
                _mm256_blendv_ps(a[1], b[1], m[1]),
            ]
        }
    }
    #[inline(always)]
    unsafe fn blend_u32(m: [__m256; 2], a: [__m256i; 2], b: [__m256i; 2]) -> [__m256i; 2] {
        unsafe {
            [
                _mm256_blendv_epi8(a[0], b[0], _mm256_castps_si256(m[0])),
                _mm256_blendv_epi8(a[1], b[1], _mm256_castps_si256(m[1])),
            ]
        }
    }
    #[inline(always)]
    unsafe fn lane(v: [__m256; 2], i: u32) -> f32 {
        // SAFETY: two registers of eight f32 are sixteen f32 in order.
        unsafe { std::mem::transmute::<[__m256; 2], [f32; 16]>(v)[i as usize] }
    }
    #[inline(always)]
    unsafe fn lane_u32(v: [__m256i; 2], i: u32) -> u32 {
        // SAFETY: as in `lane`.
        unsafe { std::mem::transmute::<[__m256i; 2], [u32; 16]>(v)[i as usize] }
    }
    #[inline(always)]
    unsafe fn reduce_min(b: u16, v: [__m256; 2]) -> f32 {
        // SAFETY: as in `lane`.
        let v = unsafe { std::mem::transmute::<[__m256; 2], [f32; 16]>(v) };
        let (mut left, mut least) = (b, f32::INFINITY);
        while left != 0 {
            least = least.min(v[left.trailing_zeros() as usize]);
            left &= left - 1;
        }
        least
    }
    #[inline(always)]
    unsafe fn reduce_min_u32(b: u16, v: [__m256i; 2]) -> u32 {
        // SAFETY: as in `lane`.
        let v = unsafe { std::mem::transmute::<[__m256i; 2], [u32; 16]>(v) };
        let (mut left, mut least) = (b, u32::MAX);
        while left != 0 {
            least = least.min(v[left.trailing_zeros() as usize]);
            left &= left - 1;
        }
        least
    }
}

/// For tests of code written over [`Simd16`]: panics where the CPU lacks
/// AVX2 (every x86-64 CPU the lanes serve has it, so the code would go
/// untested), and says whether the AVX-512 kind can be tested too (with a
/// note on stderr where it cannot).
#[cfg(test)]
pub(crate) fn test_avx512_too() -> bool {
    assert!(Avx2::supported(), "this test needs an x86-64 CPU with AVX2");
    let here = Avx512::supported();
    if !here {
        eprintln!("no AVX-512 here: only the AVX2 kind is tested");
    }
    here
}

#[cfg(test)]
mod tests {
    use super::*;
    use penumbra_shading::stats::TestRng;

    /// Each operation against the same on plain arrays: the masks of every
    /// lane-bit pattern, the comparisons (NaN false), blends, lane reads
    /// and masked reductions of random values, for every kind the CPU
    /// runs.
    #[test]
    fn lanes_act_as_plain_arrays() {
        lanes_act_as_plain_arrays_with::<Avx2>();
        if test_avx512_too() {
            lanes_act_as_plain_arrays_with::<Avx512>();
        }
    }

    #[repr(C, align(64))]
    struct Aligned<T>([T; 16]);

    fn lanes_act_as_plain_arrays_with<S: Simd16>() {
        // SAFETY: `S` checked by the caller; aligned 16-lane loads.
        unsafe {
            for b in 0..=u16::MAX {
                assert_eq!(S::bits(S::mask(b)), b);
            }
            let mut rng = TestRng::new(3);
            for round in 0..200 {
                let mut x = Aligned([0.0f32; 16]);
                let mut y = Aligned([0.0f32; 16]);
                let mut k = Aligned([0u32; 16]);
                for i in 0..16 {
                    x.0[i] = (rng.next_f32() * 8.0).floor() - 4.0;
                    y.0[i] = (rng.next_f32() * 8.0).floor() - 4.0;
                    k.0[i] = (rng.next_f32() * 6.0) as u32;
                }
                x.0[round % 16] = f32::NAN;
                let (a, c, ki) = (
                    S::load(x.0.as_ptr()),
                    S::load(y.0.as_ptr()),
                    S::load_u32(k.0.as_ptr()),
                );
                let expect = |f: &dyn Fn(f32, f32) -> bool| {
                    (0..16).fold(0u16, |m, i| m | (u16::from(f(x.0[i], y.0[i])) << i))
                };
                assert_eq!(S::bits(S::lt(a, c)), expect(&|p, q| p < q));
                assert_eq!(S::bits(S::gt(a, c)), expect(&|p, q| p > q));
                assert_eq!(S::bits(S::le(a, c)), expect(&|p, q| p <= q));
                assert_eq!(S::bits(S::eq(a, c)), expect(&|p, q| p == q));
                let lt = S::lt(a, c);
                let gt = S::gt(a, c);
                assert_eq!(
                    S::bits(S::and(lt, S::mask(0x0ff0))),
                    expect(&|p, q| p < q) & 0x0ff0
                );
                assert_eq!(
                    S::bits(S::or(lt, gt)),
                    expect(&|p, q| p != q && !p.is_nan())
                );
                assert_eq!(
                    S::bits(S::and_not(lt, S::mask(0x0ff0))),
                    !expect(&|p, q| p < q) & 0x0ff0
                );
                let m = (rng.next_f32() * 65536.0) as u16;
                let blend = S::blend(S::mask(m), a, c);
                let picked = S::blend_u32(S::mask(m), ki, S::splat_u32(9));
                let two = S::eq_u32(ki, S::splat_u32(2));
                assert_eq!(
                    S::bits(two),
                    (0..16).fold(0, |b, i| b | (u16::from(k.0[i] == 2) << i))
                );
                for i in 0..16u32 {
                    let l = i as usize;
                    let want = if m & (1 << i) != 0 { y.0[l] } else { x.0[l] };
                    assert_eq!(S::lane(blend, i).to_bits(), want.to_bits());
                    let want = if m & (1 << i) != 0 { 9 } else { k.0[l] };
                    assert_eq!(S::lane_u32(picked, i), want);
                    assert_eq!(S::lane(S::add(c, c), i), y.0[l] + y.0[l]);
                    assert_eq!(S::lane(S::sub(c, S::splat(0.5)), i), y.0[l] - 0.5);
                    assert_eq!(S::lane(S::mul(c, S::splat(3.0)), i), y.0[l] * 3.0);
                    assert_eq!(S::lane(S::min(c, S::splat(0.0)), i), y.0[l].min(0.0));
                    assert_eq!(S::lane(S::max(c, S::splat(0.0)), i), y.0[l].max(0.0));
                    let r = S::lane(S::recip(S::splat(y.0[l] + 7.5)), i);
                    assert_eq!(r, 1.0 / (y.0[l] + 7.5));
                    let fast = S::lane(S::recip_fast(S::splat(y.0[l] + 7.5)), i);
                    assert!((fast - r).abs() <= 2.0 * f32::EPSILON * r, "{fast} {r}");
                }
                let m = m | 1;
                let least = (0..16)
                    .filter(|&i| m & (1 << i) != 0)
                    .map(|i| y.0[i])
                    .fold(f32::INFINITY, f32::min);
                assert_eq!(S::reduce_min(m, c), least);
                let least = (0..16)
                    .filter(|&i| m & (1 << i) != 0)
                    .map(|i| k.0[i])
                    .min()
                    .unwrap();
                assert_eq!(S::reduce_min_u32(m, ki), least);
            }
        }
    }
}
