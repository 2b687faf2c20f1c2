//! LDR-FLIP on float sRGB input: a line-by-line Rust port of the C++ reference
//! implementation shipped in `nv-flip-sys` (NVIDIA FLIP, `image.h` /
//! `color.h` / `sharedflip.h`, BSD-3-Clause), Andersson et al. 2020,
//! "FLIP: A Difference Evaluator for Alternating Images".
//!
//! The `nv-flip` bindings only accept 8-bit input; this port takes f32 sRGB
//! values in [0, 1] so HDR-FLIP can run on unquantised tone-mapped images, as
//! NVIDIA's `flip` tool does. On 8-bit input it matches `nv_flip::flip` (tested).
//!
//! Per pixel: sRGB → linear → XYZ → YCxCz; separable CSF filtering (Gaussians
//! with FLIP's a/b constants, sum of two for Cz); back to linear RGB, clamp,
//! → CIELab with Hunt adjustment; colour error `ΔE = HyAB^0.7`, remapped so
//! `0.4·cmax ↦ 0.95`; feature error from 1st/2nd Gaussian derivatives of the
//! normalised luminance, `Δf = (max(|Δedge|, |Δpoint|)/√2)^0.5`; final error
//! `ΔE^(1 − Δf)`.

// Constants are copied digit for digit from the C++ source so both agree.
#![allow(clippy::excessive_precision)]

use glam::Vec3;

use crate::srgb_eotf;

const GQC: f32 = 0.7;
const GPC: f32 = 0.4;
const GPT: f32 = 0.95;
const GW: f32 = 0.082;
const GQF: f32 = 0.5;
/// The C++ `3.14159265358979f` rounds to this same f32.
const PI: f32 = std::f32::consts::PI;

/// CSF Gaussian constants (Y, Cx, Cz): `a₁, b₁, a₂, b₂`.
const A1: [f32; 3] = [1.0, 1.0, 34.1];
const B1: [f32; 3] = [0.0047, 0.0053, 0.04];
const A2: [f32; 3] = [0.0, 0.0, 13.5];
const B2: [f32; 3] = [1.0e-5, 1.0e-5, 0.025];

const ILLUMINANT: Vec3 = Vec3::new(0.950428545, 1.000000000, 1.088900371);
const INV_ILLUMINANT: Vec3 = Vec3::new(1.052156925, 1.000000000, 0.918357670);

/// `exp(−π² x² / b)`: the shape of the CSF Gaussian `a √(π/b) exp(−π² x² / b)`
/// of Y and Cx, whose amplitude `a √(π/b)` cancels when its filter is
/// normalised to sum 1.
fn gaussian_shape(x2: f32, b: f32) -> f32 {
    (-(PI * PI) * x2 / b).exp()
}

/// `√(a √(π/b)) exp(−π² x² / b)`: separable factor of a sum of Gaussians.
fn gaussian_sqrt(x2: f32, a: f32, b: f32) -> f32 {
    (a * (PI / b).sqrt()).sqrt() * (-(PI * PI) * x2 / b).exp()
}

fn linear_rgb_to_xyz(c: Vec3) -> Vec3 {
    let a11 = 10_135_552.0f32 / 24_577_794.0;
    let a12 = 8_788_810.0f32 / 24_577_794.0;
    let a13 = 4_435_075.0f32 / 24_577_794.0;
    let a21 = 2_613_072.0f32 / 12_288_897.0;
    let a22 = 8_788_810.0f32 / 12_288_897.0;
    let a23 = 887_015.0f32 / 12_288_897.0;
    let a31 = 1_425_312.0f32 / 73_733_382.0;
    let a32 = 8_788_810.0f32 / 73_733_382.0;
    let a33 = 70_074_185.0f32 / 73_733_382.0;
    Vec3::new(
        a11 * c.x + a12 * c.y + a13 * c.z,
        a21 * c.x + a22 * c.y + a23 * c.z,
        a31 * c.x + a32 * c.y + a33 * c.z,
    )
}

fn xyz_to_linear_rgb(c: Vec3) -> Vec3 {
    let (a11, a12, a13) = (3.241003275f32, -1.537398934f32, -0.498615861f32);
    let (a21, a22, a23) = (-0.969224334f32, 1.875930071f32, 0.041554224f32);
    let (a31, a32, a33) = (0.055639423f32, -0.204011202f32, 1.057148933f32);
    Vec3::new(
        a11 * c.x + a12 * c.y + a13 * c.z,
        a21 * c.x + a22 * c.y + a23 * c.z,
        a31 * c.x + a32 * c.y + a33 * c.z,
    )
}

fn xyz_to_ycxcz(c: Vec3) -> Vec3 {
    let c = c * INV_ILLUMINANT;
    Vec3::new(116.0 * c.y - 16.0, 500.0 * (c.x - c.y), 200.0 * (c.y - c.z))
}

fn ycxcz_to_xyz(c: Vec3) -> Vec3 {
    let y = (c.x + 16.0) / 116.0;
    let cx = c.y / 500.0;
    let cz = c.z / 200.0;
    Vec3::new(y + cx, y, y - cz) * ILLUMINANT
}

fn xyz_to_cielab(c: Vec3) -> Vec3 {
    let delta = 6.0f32 / 29.0;
    let delta_square = delta * delta;
    let delta_cube = delta * delta_square;
    let factor = 1.0 / (3.0 * delta_square);
    let term = 4.0f32 / 29.0;
    let f = |v: f32| {
        if v > delta_cube {
            v.powf(1.0 / 3.0)
        } else {
            factor * v + term
        }
    };
    let c = c * INV_ILLUMINANT;
    let (x, y, z) = (f(c.x), f(c.y), f(c.z));
    Vec3::new(116.0 * y - 16.0, 500.0 * (x - y), 200.0 * (y - z))
}

fn hunt(luminance: f32, chrominance: f32) -> f32 {
    0.01 * luminance * chrominance
}

fn hyab(a: Vec3, b: Vec3) -> f32 {
    let l = (a.x - b.x).abs();
    let ab = ((a.y - b.y) * (a.y - b.y) + (a.z - b.z) * (a.z - b.z)).sqrt();
    l + ab
}

/// `cmax = HyAB(Hunt(Lab(green)), Hunt(Lab(blue)))^0.7`.
fn max_distance() -> f32 {
    let lab_hunt = |rgb: Vec3| {
        let lab = xyz_to_cielab(linear_rgb_to_xyz(rgb));
        Vec3::new(lab.x, hunt(lab.x, lab.y), hunt(lab.x, lab.z))
    };
    hyab(lab_hunt(Vec3::Y), lab_hunt(Vec3::Z)).powf(GQC)
}

/// `⌈3 √(max b / (2π²)) · ppd⌉`.
fn spatial_filter_radius(ppd: f32) -> usize {
    let max_b = B1.iter().chain(B2.iter()).copied().fold(f32::MIN, f32::max);
    (3.0 * (max_b / (2.0 * (PI * PI))).sqrt() * ppd)
        .ceil()
        .max(0.0) as usize
}

/// Normalised separable CSF filters: (Y, Cx) weights and the two Cz factors.
fn spatial_filters(ppd: f32) -> (Vec<[f32; 2]>, Vec<[f32; 2]>) {
    let radius = spatial_filter_radius(ppd);
    let width = 2 * radius + 1;
    let delta_x = 1.0 / ppd;
    let mut ycx = Vec::with_capacity(width);
    let mut cz = Vec::with_capacity(width);
    let (mut sum_y, mut sum_cx, mut sum_cz1, mut sum_cz2) = (0.0f32, 0.0f32, 0.0f32, 0.0f32);
    for i in 0..width {
        let ix = (i as f32 - radius as f32) * delta_x;
        let ix2 = ix * ix;
        let g_y = gaussian_shape(ix2, B1[0]);
        let g_cx = gaussian_shape(ix2, B1[1]);
        let g_cz1 = gaussian_sqrt(ix2, A1[2], B1[2]);
        let g_cz2 = gaussian_sqrt(ix2, A2[2], B2[2]);
        ycx.push([g_y, g_cx]);
        cz.push([g_cz1, g_cz2]);
        sum_y += g_y;
        sum_cx += g_cx;
        sum_cz1 += g_cz1;
        sum_cz2 += g_cz2;
    }
    let norm_cz = 1.0 / (sum_cz1 * sum_cz1 + sum_cz2 * sum_cz2).sqrt();
    for w in &mut ycx {
        *w = [w[0] * (1.0 / sum_y), w[1] * (1.0 / sum_cx)];
    }
    for w in &mut cz {
        *w = [w[0] * norm_cz, w[1] * norm_cz];
    }
    (ycx, cz)
}

/// Feature filter (Gaussian, 1st and 2nd derivative), σ = ½ · 0.082 · ppd,
/// normalised so the Gaussian sums to 1 and the positive/negative lobes of
/// the derivatives to ±1.
fn feature_filter(ppd: f32) -> Vec<[f32; 3]> {
    let std_dev = 0.5 * GW * ppd;
    let radius = (3.0 * std_dev).ceil().max(0.0) as i64;
    let mut filter = Vec::with_capacity(2 * radius as usize + 1);
    let (mut g_sum, mut dg_neg, mut dg_pos, mut ddg_neg, mut ddg_pos) =
        (0.0f32, 0.0f32, 0.0f32, 0.0f32, 0.0f32);
    for xx in -radius..=radius {
        let x = xx as f32;
        let g = (-(x * x) / (2.0 * std_dev * std_dev)).exp();
        g_sum += g;
        let dg = -x * g;
        if dg > 0.0 {
            dg_pos += dg;
        } else {
            dg_neg -= dg;
        }
        let ddg = (x * x / (std_dev * std_dev) - 1.0) * g;
        if ddg > 0.0 {
            ddg_pos += ddg;
        } else {
            ddg_neg -= ddg;
        }
        filter.push([g, dg, ddg]);
    }
    for w in &mut filter {
        *w = [
            w[0] / g_sum,
            w[1] / if w[1] > 0.0 { dg_pos } else { dg_neg },
            w[2] / if w[2] > 0.0 { ddg_pos } else { ddg_neg },
        ];
    }
    filter
}

/// LDR-FLIP error map of two sRGB-encoded images (values in [0, 1], row-major,
/// `width · height` pixels each) at `ppd` pixels per degree. Returns one error
/// in [0, 1] per pixel. The caller guarantees equal, consistent sizes.
pub(crate) fn ldr_flip(
    reference: &[Vec3],
    test: &[Vec3],
    width: usize,
    height: usize,
    ppd: f32,
) -> Vec<f32> {
    let n = width * height;
    debug_assert!(reference.len() == n && test.len() == n);
    if n == 0 || reference.len() != n || test.len() != n {
        return Vec::new();
    }
    let to_ycxcz = |c: &Vec3| {
        xyz_to_ycxcz(linear_rgb_to_xyz(Vec3::new(
            srgb_eotf(c.x),
            srgb_eotf(c.y),
            srgb_eotf(c.z),
        )))
    };
    let r: Vec<Vec3> = reference.iter().map(to_ycxcz).collect();
    let t: Vec<Vec3> = test.iter().map(to_ycxcz).collect();
    let clamp_x = |x: usize, i: usize, half: usize| (x + i).saturating_sub(half).min(width - 1);
    let clamp_y = |y: usize, i: usize, half: usize| (y + i).saturating_sub(half).min(height - 1);

    // --- Colour pipeline: separable CSF filtering, then Hunt-adjusted HyAB. ---
    let (filter_ycx, filter_cz) = spatial_filters(ppd);
    let half = filter_ycx.len() / 2;
    // Per pixel: [ref YCx (2), test YCx (2), ref Cz (2), test Cz (2)].
    let mut tmp = vec![[0.0f32; 8]; n];
    for y in 0..height {
        for x in 0..width {
            let mut acc = [0.0f32; 8];
            for (i, (wycx, wcz)) in filter_ycx.iter().zip(&filter_cz).enumerate() {
                let xx = clamp_x(x, i, half);
                let rc = r[y * width + xx];
                let tc = t[y * width + xx];
                acc[0] += wycx[0] * rc.x;
                acc[1] += wycx[1] * rc.y;
                acc[2] += wycx[0] * tc.x;
                acc[3] += wycx[1] * tc.y;
                acc[4] += wcz[0] * rc.z;
                acc[5] += wcz[1] * rc.z;
                acc[6] += wcz[0] * tc.z;
                acc[7] += wcz[1] * tc.z;
            }
            tmp[y * width + x] = acc;
        }
    }
    let cmax = max_distance();
    let pccmax = GPC * cmax;
    let to_lab_hunt = |c: Vec3| {
        let rgb = xyz_to_linear_rgb(ycxcz_to_xyz(c)).clamp(Vec3::ZERO, Vec3::ONE);
        let lab = xyz_to_cielab(linear_rgb_to_xyz(rgb));
        Vec3::new(lab.x, hunt(lab.x, lab.y), hunt(lab.x, lab.z))
    };
    let mut error = vec![0.0f32; n];
    for y in 0..height {
        for x in 0..width {
            let mut acc = [0.0f32; 8];
            for (i, (wycx, wcz)) in filter_ycx.iter().zip(&filter_cz).enumerate() {
                let v = tmp[clamp_y(y, i, half) * width + x];
                acc[0] += wycx[0] * v[0];
                acc[1] += wycx[1] * v[1];
                acc[2] += wycx[0] * v[2];
                acc[3] += wycx[1] * v[3];
                acc[4] += wcz[0] * v[4];
                acc[5] += wcz[1] * v[5];
                acc[6] += wcz[0] * v[6];
                acc[7] += wcz[1] * v[7];
            }
            let rf = to_lab_hunt(Vec3::new(acc[0], acc[1], acc[4] + acc[5]));
            let tf = to_lab_hunt(Vec3::new(acc[2], acc[3], acc[6] + acc[7]));
            let mut d = hyab(rf, tf).powf(GQC);
            d = if d < pccmax {
                d * (GPT / pccmax)
            } else {
                GPT + ((d - pccmax) / (cmax - pccmax)) * (1.0 - GPT)
            };
            error[y * width + x] = d;
        }
    }

    // --- Feature pipeline: edges and points on normalised luminance. ---
    let filter = feature_filter(ppd);
    let half = filter.len() / 2;
    let one_over_116 = 1.0f32 / 116.0;
    let sixteen_over_116 = 16.0f32 / 116.0;
    // Per pixel: [ref dx, ref ddx, ref g, test dx, test ddx, test g].
    let mut tmp = vec![[0.0f32; 6]; n];
    for y in 0..height {
        for x in 0..width {
            let mut acc = [0.0f32; 6];
            for (i, w) in filter.iter().enumerate() {
                let xx = clamp_x(x, i, half);
                let yr = r[y * width + xx].x * one_over_116 + sixteen_over_116;
                let yt = t[y * width + xx].x * one_over_116 + sixteen_over_116;
                acc[0] += w[1] * yr;
                acc[3] += w[1] * yt;
                acc[1] += w[2] * yr;
                acc[4] += w[2] * yt;
                acc[2] += w[0] * yr;
                acc[5] += w[0] * yt;
            }
            tmp[y * width + x] = acc;
        }
    }
    let normalization = 1.0 / 2.0f32.sqrt();
    for y in 0..height {
        for x in 0..width {
            // [ref dx, test dx, ref ddx, test ddx, ref dy, test dy, ref ddy, test ddy]
            let mut acc = [0.0f32; 8];
            for (i, w) in filter.iter().enumerate() {
                let v = tmp[clamp_y(y, i, half) * width + x];
                acc[0] += w[0] * v[0];
                acc[1] += w[0] * v[3];
                acc[2] += w[0] * v[1];
                acc[3] += w[0] * v[4];
                acc[4] += w[1] * v[2];
                acc[5] += w[1] * v[5];
                acc[6] += w[2] * v[2];
                acc[7] += w[2] * v[5];
            }
            let edge_r = (acc[0] * acc[0] + acc[4] * acc[4]).sqrt();
            let edge_t = (acc[1] * acc[1] + acc[5] * acc[5]).sqrt();
            let point_r = (acc[2] * acc[2] + acc[6] * acc[6]).sqrt();
            let point_t = (acc[3] * acc[3] + acc[7] * acc[7]).sqrt();
            let feature =
                (normalization * (edge_r - edge_t).abs().max((point_r - point_t).abs())).powf(GQF);
            let i = y * width + x;
            error[i] = error[i].powf(1.0 - feature);
        }
    }
    error
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn filter_sizes_at_default_ppd() {
        let (ycx, cz) = spatial_filters(67.0);
        assert_eq!(ycx.len(), 21);
        assert_eq!(cz.len(), 21);
        assert_eq!(feature_filter(67.0).len(), 19);
        // Y and Cx filters sum to 1 (a sign flip of one would cancel over
        // the two separable passes in ldr_flip, so only this sees it); the
        // 2-D Cz filter g₁⊗g₁ + g₂⊗g₂ sums to (Σg₁)² + (Σg₂)² = 1.
        for channel in 0..2 {
            let sum: f32 = ycx.iter().map(|w| w[channel]).sum();
            assert!((sum - 1.0).abs() < 1e-5, "channel {channel}: {sum}");
        }
        let (s1, s2): (f32, f32) = (cz.iter().map(|w| w[0]).sum(), cz.iter().map(|w| w[1]).sum());
        assert!((s1 * s1 + s2 * s2 - 1.0).abs() < 1e-5);
    }

    /// The feature filter's three kernels as FLIP defines them, at the
    /// default 67 ppd (σ = ½ · 0.082 · 67 = 2.747, radius 9): the Gaussian
    /// sums to 1; its first derivative −x·g is positive left of the centre,
    /// 0 at it and negative right of it, each lobe summing to ±1; the
    /// second derivative (x²/σ² − 1)·g is negative inside |x| < σ and
    /// positive outside, its lobes summing to ±1.
    #[test]
    fn feature_kernels_by_hand() {
        let f = feature_filter(67.0);
        let sigma = 0.5 * 0.082 * 67.0;
        let sum = |k: usize, keep: fn(f32) -> bool| -> f32 {
            f.iter().map(|w| w[k]).filter(|&v| keep(v)).sum()
        };
        assert!((sum(0, |_| true) - 1.0).abs() < 1e-6);
        for k in [1, 2] {
            assert!((sum(k, |v| v > 0.0) - 1.0).abs() < 1e-6, "kernel {k}");
            assert!((sum(k, |v| v < 0.0) + 1.0).abs() < 1e-6, "kernel {k}");
        }
        for (i, w) in f.iter().enumerate() {
            let x = i as f32 - 9.0;
            assert!(w[0] > 0.0);
            if x != 0.0 {
                assert_eq!(w[1].signum(), -x.signum(), "x = {x}");
            }
            assert_eq!(w[2] > 0.0, x.abs() > sigma, "x = {x}: {}", w[2]);
        }
        assert_eq!(f[9][1], 0.0);
        // Symmetry: g and ddg even, dg odd.
        for d in 1..=9 {
            let (l, r) = (f[9 - d], f[9 + d]);
            assert!((l[0] - r[0]).abs() < 1e-7 && (l[1] + r[1]).abs() < 1e-7);
            assert!((l[2] - r[2]).abs() < 1e-7);
        }
    }

    #[test]
    fn identical_is_zero() {
        let img: Vec<Vec3> = (0..64).map(|i| Vec3::splat(i as f32 / 63.0)).collect();
        assert!(ldr_flip(&img, &img, 8, 8, 67.0).iter().all(|&e| e == 0.0));
    }
}
