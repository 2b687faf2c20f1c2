//! HDR-FLIP (Andersson, Nilsson, Shirley, Akenine-Möller 2021, "Visualizing
//! Errors in Rendered High Dynamic Range Images"), as computed by NVIDIA's
//! `flip` tool with its default ACES tone mapper.
//!
//! 1. Exposure range from the reference ([`flip_exposure_range`]): with FLIP's
//!    ACES curve `T(x) = (0.9036x² + 0.018x) / (0.8748x² + 0.354x + 0.14)`
//!    (Narkowicz's fit with its 0.6 pre-exposure folded in), let `x₀.₈₅` solve
//!    `T(x) = 0.85` (≈ 2.1189); with luminance `Y = 0.2126R + 0.7152G + 0.0722B`,
//!    `start = log2(x₀.₈₅ / Y_max)`, `stop = log2(x₀.₈₅ / Y_median)`,
//!    `count = max(2, ⌈stop − start⌉)`, exposures evenly spaced from start to stop.
//! 2. For each exposure `e`, both images: `x = L · 2^e` → `T` → clamp [0, 1] →
//!    sRGB OETF → LDR-FLIP at 67 pixels per degree.
//! 3. The HDR-FLIP error of a pixel is the maximum over exposures; the
//!    reported number is the mean over pixels.
//!
//! LDR-FLIP backends ([`FlipBackend`]): the `nv-flip` crate wraps NVIDIA's C++
//! LDR-FLIP but only accepts 8-bit input, and quantising the tone-mapped
//! images to 8 bits adds an error floor (scaling the Cornell reference by
//! 1.001 scores 0.0098 through 8-bit input, 0.0059 in float; with σ = 6 %
//! Gaussian noise 0.0481 vs 0.0473).
//! The default backend, [`FlipBackend::Float`], is a Rust port of the same
//! C++ code that takes float input like NVIDIA's tool; it is tested to agree
//! with `nv-flip` on 8-bit input. [`FlipBackend::NvFlip8Bit`] runs `nv-flip`.
//!
//! Deviations from NVIDIA's tool:
//! * non-finite values are ignored when choosing the exposure range and
//!   NaN/negative values are mapped to 0 before tone mapping (the tool's
//!   rational curve sends large negative values to white);
//! * if the median luminance is 0 (more than half of the reference is black)
//!   the median of the positive luminances is used, and an all-black reference
//!   uses `start = stop = 0`, where the tool would run an unbounded number of
//!   exposures; the count is capped at [`MAX_EXPOSURES`];
//! * the mean is accumulated in f64 (the tool sums in f32).

use crate::flip_ldr::ldr_flip;
use crate::metrics::check_pair;
use crate::tonemap::quantize;
use crate::{Image, ImageError, Rgb, srgb_eotf, srgb_oetf};

/// FLIP's default pixels per degree of visual angle (0.7 m from a 0.7 m wide 4K monitor).
pub const DEFAULT_PIXELS_PER_DEGREE: f32 = 67.0;

/// Upper bound on the number of exposures evaluated.
pub const MAX_EXPOSURES: usize = 64;

/// FLIP's ACES coefficients: `T(x) = (c₀x² + c₁x + c₂) / (c₃x² + c₄x + c₅)`.
const ACES: [f32; 6] = [
    0.6 * 0.6 * 2.51,
    0.6 * 0.03,
    0.0,
    0.6 * 0.6 * 2.43,
    0.6 * 0.59,
    0.14,
];

/// The exposures HDR-FLIP evaluates: `count` values evenly spaced from `start` to `stop` (in stops).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ExposureRange {
    /// First exposure (EV), chosen so the brightest reference pixel maps to 0.85.
    pub start: f32,
    /// Last exposure (EV), chosen so the median reference luminance maps to 0.85.
    pub stop: f32,
    /// Number of exposures (at least 2).
    pub count: usize,
}

impl ExposureRange {
    /// The exposures `start + i (stop − start) / (count − 1)`, i = 0..count.
    pub fn exposures(&self) -> Vec<f32> {
        let count = self.count.clamp(2, MAX_EXPOSURES);
        let step = (self.stop - self.start) / (count - 1) as f32;
        (0..count).map(|i| self.start + i as f32 * step).collect()
    }
}

/// Which LDR-FLIP implementation [`hdr_flip_with`] runs per exposure.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum FlipBackend {
    /// Rust port of NVIDIA's C++ LDR-FLIP on unquantised float sRGB values
    /// (what NVIDIA's `flip` tool does for HDR input).
    #[default]
    Float,
    /// `nv_flip::flip` on tone-mapped values quantised to 8-bit sRGB
    /// (`⌊255 V + 0.5⌋`); adds a quantisation error floor.
    NvFlip8Bit,
}

/// Options for [`hdr_flip_with`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FlipOptions {
    /// Pixels per degree of visual angle; default [`DEFAULT_PIXELS_PER_DEGREE`].
    pub pixels_per_degree: f32,
    /// Exposures to evaluate; `None` = [`flip_exposure_range`] of the reference.
    pub exposures: Option<ExposureRange>,
    /// Worker threads; 0 = available parallelism.
    pub threads: usize,
    /// LDR-FLIP implementation; default [`FlipBackend::Float`].
    pub backend: FlipBackend,
}

impl Default for FlipOptions {
    fn default() -> Self {
        Self {
            pixels_per_degree: DEFAULT_PIXELS_PER_DEGREE,
            exposures: None,
            threads: 0,
            backend: FlipBackend::Float,
        }
    }
}

/// FLIP's tone curve `T(x)` clamped to [0, 1], with NaN/negative → 0.
fn flip_aces(x: f32) -> f32 {
    if x.is_nan() || x <= 0.0 {
        return 0.0;
    }
    let x = x.min(1.0e4);
    let [a, b, c, d, e, f] = ACES;
    ((a * x * x + b * x + c) / (d * x * x + e * x + f)).clamp(0.0, 1.0)
}

/// Larger root of `(c₀ − 0.85c₃)x² + (c₁ − 0.85c₄)x + (c₂ − 0.85c₅) = 0`, i.e. `T(x) = 0.85`.
fn x_at_085() -> f32 {
    let t = 0.85;
    let a = ACES[0] - t * ACES[3];
    let b = ACES[1] - t * ACES[4];
    let c = ACES[2] - t * ACES[5];
    let d1 = -0.5 * (b / a);
    let d2 = (d1 * d1 - c / a).sqrt();
    d1 + d2
}

/// HDR-FLIP's automatic exposure range for a reference image (see the module docs).
pub fn flip_exposure_range(reference: &Image) -> ExposureRange {
    let mut lum: Vec<f32> = reference
        .pixels
        .iter()
        .map(|&p| penumbra_shading::color::luminance(p))
        .filter(|y| y.is_finite())
        .collect();
    lum.sort_by(f32::total_cmp);
    let y_max = lum.last().copied().unwrap_or(0.0);
    if y_max <= 0.0 {
        return ExposureRange {
            start: 0.0,
            stop: 0.0,
            count: 2,
        };
    }
    let mut y_median = median_sorted(&lum);
    if y_median <= 0.0 {
        let first_positive = lum.partition_point(|&y| y <= 0.0);
        y_median = median_sorted(&lum[first_positive..]);
    }
    let x = x_at_085();
    let start = (x / y_max).log2();
    let stop = (x / y_median).log2();
    let count = ((stop - start).ceil().max(2.0) as usize).min(MAX_EXPOSURES);
    ExposureRange { start, stop, count }
}

/// Median as in FLIP: mean of elements n/2 − 1 and n/2 (the element itself for n = 1).
fn median_sorted(v: &[f32]) -> f32 {
    match v.len() {
        0 => 0.0,
        1 => v[0],
        n => 0.5 * (v[n / 2 - 1] + v[n / 2]),
    }
}

/// HDR-FLIP with default options: returns the mean error and the per-pixel
/// error map (grey: the error in all three channels, values in [0, 1]).
/// Errors if the sizes differ or an image is empty/malformed.
pub fn hdr_flip(r: &Image, t: &Image) -> Result<(f64, Image), ImageError> {
    hdr_flip_with(r, t, &FlipOptions::default())
}

/// HDR-FLIP with explicit options (see [`hdr_flip`] and the module docs).
pub fn hdr_flip_with(
    r: &Image,
    t: &Image,
    options: &FlipOptions,
) -> Result<(f64, Image), ImageError> {
    check_pair(r, t)?;
    let range = options.exposures.unwrap_or_else(|| flip_exposure_range(r));
    let exposures = range.exposures();
    let threads = match options.threads {
        0 => std::thread::available_parallelism().map_or(1, |n| n.get()),
        n => n,
    }
    .clamp(1, exposures.len());
    let ppd = options.pixels_per_degree;
    let backend = options.backend;

    let partial_maps: Vec<Result<Vec<f32>, ImageError>> = std::thread::scope(|scope| {
        let handles: Vec<_> = (0..threads)
            .map(|k| {
                let mine: Vec<f32> = exposures.iter().copied().skip(k).step_by(threads).collect();
                scope.spawn(move || {
                    let mut max = vec![0.0f32; r.pixels.len()];
                    for e in mine {
                        let errors = ldr_flip_at_exposure(r, t, e, ppd, backend);
                        for (m, v) in max.iter_mut().zip(errors) {
                            *m = m.max(v);
                        }
                    }
                    max
                })
            })
            .collect();
        handles
            .into_iter()
            .map(|h| {
                h.join().map_err(|_| ImageError::InvalidImage {
                    what: "FLIP input".into(),
                    message: "FLIP worker thread panicked".into(),
                })
            })
            .collect()
    });

    let mut error = vec![0.0f32; r.pixels.len()];
    for map in partial_maps {
        for (e, v) in error.iter_mut().zip(map?) {
            *e = e.max(v);
        }
    }
    let mean = error.iter().map(|&v| f64::from(v)).sum::<f64>() / error.len() as f64;
    let map = Image {
        width: r.width,
        height: r.height,
        pixels: error.into_iter().map(Rgb::splat).collect(),
    };
    Ok((mean, map))
}

/// LDR-FLIP of both images exposed by `2^e`, tone-mapped with FLIP's ACES and sRGB-encoded.
fn ldr_flip_at_exposure(
    r: &Image,
    t: &Image,
    exposure: f32,
    ppd: f32,
    backend: FlipBackend,
) -> Vec<f32> {
    let scale = exposure.exp2();
    let display = |v: f32| srgb_oetf(flip_aces(v * scale));
    match backend {
        FlipBackend::Float => {
            let encode = |img: &Image| -> Vec<Rgb> {
                img.pixels
                    .iter()
                    .map(|p| Rgb::new(display(p.x), display(p.y), display(p.z)))
                    .collect()
            };
            ldr_flip(
                &encode(r),
                &encode(t),
                r.width as usize,
                r.height as usize,
                ppd,
            )
        }
        FlipBackend::NvFlip8Bit => {
            let encode = |img: &Image| -> Vec<u8> {
                img.pixels
                    .iter()
                    .flat_map(|p| p.to_array())
                    .map(|v| quantize(display(v)))
                    .collect()
            };
            let reference = nv_flip::FlipImageRgb8::with_data(r.width, r.height, &encode(r));
            let test = nv_flip::FlipImageRgb8::with_data(t.width, t.height, &encode(t));
            nv_flip::flip(reference, test, ppd).to_vec()
        }
    }
}

/// Colours a FLIP error map (the red channel is used; values in [0, 1]) with
/// FLIP's 256-entry magma colour map, `lut[round(255 · clamp(v, 0, 1))]`.
///
/// The result is linear RGB (the map's sRGB colours decoded with the sRGB
/// EOTF), so writing it as PNG with [`crate::ToneMapping::CLAMP`] reproduces
/// the exact magma 8-bit colours.
pub fn flip_heatmap(error_map: &Image) -> Image {
    let lut = nv_flip::magma_lut().to_vec();
    let colour = |v: f32| -> Rgb {
        let i = if v.is_nan() {
            0
        } else {
            (v.clamp(0.0, 1.0) * 255.0).round() as usize
        };
        match lut.get(3 * i..3 * i + 3) {
            Some(&[r, g, b]) => Rgb::new(
                srgb_eotf(f32::from(r) / 255.0),
                srgb_eotf(f32::from(g) / 255.0),
                srgb_eotf(f32::from(b) / 255.0),
            ),
            _ => Rgb::ZERO,
        }
    };
    Image {
        width: error_map.width,
        height: error_map.height,
        pixels: error_map.pixels.iter().map(|p| colour(p.x)).collect(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ToneMapping;

    #[test]
    fn aces_threshold() {
        let x = x_at_085();
        assert!((x - 2.1189).abs() < 1e-3, "{x}");
        assert!((flip_aces(x) - 0.85).abs() < 1e-5);
    }

    /// FLIP's tone curve at hand-computed points: T(1) = (0.36·2.51 + 0.6·0.03)
    /// / (0.36·2.43 + 0.6·0.59 + 0.14) = 0.9216 / 1.3688 (T(0.5) likewise);
    /// NaN and negative
    /// values (even huge ones, where the rational function is near 1) give 0.
    #[test]
    fn aces_curve_values() {
        assert!((flip_aces(1.0) - 0.9216 / 1.3688).abs() < 1e-6);
        assert!((flip_aces(0.5) - 0.2349 / 0.5357).abs() < 1e-6);
        for x in [f32::NAN, -1.0e3, f32::NEG_INFINITY, -0.0] {
            assert_eq!(flip_aces(x), 0.0, "T({x})");
        }
        assert_eq!(flip_aces(f32::INFINITY), 1.0);
    }

    /// FLIP's median: the mean of elements n/2 − 1 and n/2 of the sorted
    /// values, also for odd n (its reference code's choice).
    #[test]
    fn median_is_flips() {
        assert_eq!(median_sorted(&[]), 0.0);
        assert_eq!(median_sorted(&[7.0]), 7.0);
        assert_eq!(median_sorted(&[1.0, 2.0, 3.0, 4.0]), 2.5);
        assert_eq!(median_sorted(&[1.0, 2.0, 3.0, 4.0, 5.0, 6.0]), 3.5);
        assert_eq!(median_sorted(&[1.0, 2.0, 3.0]), 1.5);
    }

    /// An exposure of e stops scales the images by 2^e before the tone
    /// curve: FLIP at exposure e equals FLIP at exposure 0 of the images
    /// scaled by 2^e (here by 2^±5, where the curve is far from linear).
    #[test]
    fn exposure_scales_the_images() {
        let r = Image::from_fn(24, 16, |x, y| {
            Rgb::new(x as f32 / 24.0, y as f32 / 16.0, 0.3) * 0.05
        });
        let t = Image::from_fn(24, 16, |x, y| {
            r.get(x, y) * if (x + 2 * y) % 3 == 0 { 1.8 } else { 1.0 }
        });
        let at = |r: &Image, t: &Image, e: f32| {
            let options = FlipOptions {
                exposures: Some(ExposureRange {
                    start: e,
                    stop: e,
                    count: 2,
                }),
                ..FlipOptions::default()
            };
            hdr_flip_with(r, t, &options).expect("flip").0
        };
        let scaled =
            |img: &Image, k: f32| Image::from_fn(img.width, img.height, |x, y| img.get(x, y) * k);
        for e in [5.0f32, -5.0] {
            let k = e.exp2();
            let (exposed, prescaled) = (at(&r, &t, e), at(&scaled(&r, k), &scaled(&t, k), 0.0));
            assert!(
                (exposed - prescaled).abs() < 1e-9,
                "e = {e}: {exposed} vs {prescaled}"
            );
        }
        // The two exposures really differ (bright errors are seen, dark ones hidden).
        assert!(at(&r, &t, 5.0) > 4.0 * at(&r, &t, -5.0));
    }

    #[test]
    fn exposure_range_of_constant_image() {
        let r = flip_exposure_range(&Image::filled(4, 4, Rgb::ONE));
        assert!((r.start - x_at_085().log2()).abs() < 1e-6);
        assert_eq!(r.start, r.stop);
        assert_eq!(r.count, 2);
    }

    #[test]
    fn exposure_range_spans_max_to_median() {
        // Luminances 1 (×3) and 64 (×1): max 64, median 1 → 6 stops → 6 exposures.
        let mut img = Image::filled(2, 2, Rgb::ONE);
        img.set(0, 0, Rgb::splat(64.0));
        let r = flip_exposure_range(&img);
        assert!((r.stop - r.start - 6.0).abs() < 1e-5, "{r:?}");
        assert_eq!(r.count, 6);
        let e = r.exposures();
        assert_eq!(e.len(), 6);
        assert!((e[5] - r.stop).abs() < 1e-5);
    }

    #[test]
    fn exposure_range_degenerate() {
        let r = flip_exposure_range(&Image::new(4, 4));
        assert_eq!(
            r,
            ExposureRange {
                start: 0.0,
                stop: 0.0,
                count: 2
            }
        );
        // Mostly black: the median of the positive luminances is used.
        let mut img = Image::new(3, 3);
        img.set(0, 0, Rgb::splat(4.0));
        img.set(1, 0, Rgb::splat(1.0));
        let r = flip_exposure_range(&img);
        assert!(r.stop.is_finite() && r.stop > r.start);
    }

    /// The Rust LDR-FLIP port agrees with nv-flip (NVIDIA's C++) on 8-bit input.
    #[test]
    fn float_port_matches_nv_flip() {
        let (w, h) = (61u32, 47u32);
        let mut s = 0x9e37_79b9_7f4a_7c15u64;
        let mut next = move || {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            (s >> 56) as u8
        };
        // Smooth pattern plus noise, so colour and feature terms both matter.
        let make = |next: &mut dyn FnMut() -> u8, amp: u8| -> Vec<u8> {
            (0..w * h * 3)
                .map(|i| {
                    let p = i / 3;
                    let base = ((p % w) * 3 + (p / w) * 2 + (i % 3) * 40) as u8;
                    base.wrapping_add(next() % amp.max(1))
                })
                .collect()
        };
        for amp in [2u8, 8, 64, 255] {
            let a = make(&mut next, amp);
            let b = make(&mut next, amp);
            let expected = nv_flip::flip(
                nv_flip::FlipImageRgb8::with_data(w, h, &a),
                nv_flip::FlipImageRgb8::with_data(w, h, &b),
                DEFAULT_PIXELS_PER_DEGREE,
            )
            .to_vec();
            let to_rgb = |v: &[u8]| -> Vec<Rgb> {
                v.chunks(3)
                    .map(|c| Rgb::new(f32::from(c[0]), f32::from(c[1]), f32::from(c[2])) / 255.0)
                    .collect()
            };
            let ours = ldr_flip(
                &to_rgb(&a),
                &to_rgb(&b),
                w as usize,
                h as usize,
                DEFAULT_PIXELS_PER_DEGREE,
            );
            assert_eq!(ours.len(), expected.len());
            let max_diff = ours
                .iter()
                .zip(&expected)
                .map(|(x, y)| (x - y).abs())
                .fold(0.0, f32::max);
            let mean: f32 = expected.iter().sum::<f32>() / expected.len() as f32;
            eprintln!("amp {amp}: max diff {max_diff}, mean FLIP {mean}");
            assert!(
                max_diff < 1e-5,
                "amp {amp}: max diff {max_diff}, mean FLIP {mean}"
            );
            assert!(mean > 0.0);
        }
    }

    /// Both backends agree closely when the error is well above the 8-bit floor.
    #[test]
    fn backends_agree_on_large_errors() {
        let r = Image::from_fn(40, 30, |x, y| {
            Rgb::new(x as f32 / 40.0, y as f32 / 30.0, 0.3)
        });
        let t = Image::from_fn(40, 30, |x, y| {
            r.get(x, y) * if (x * 7 + y * 3) % 5 == 0 { 1.5 } else { 1.0 }
        });
        let float = hdr_flip(&r, &t).expect("float").0;
        let options = FlipOptions {
            backend: FlipBackend::NvFlip8Bit,
            ..FlipOptions::default()
        };
        let nv = hdr_flip_with(&r, &t, &options).expect("nv").0;
        assert!(
            (float - nv).abs() < 0.02 * float,
            "float {float} vs nv-flip {nv}"
        );
    }

    #[test]
    fn heatmap_reproduces_magma_bytes() {
        let lut = nv_flip::magma_lut().to_vec();
        let errors = Image::from_fn(256, 1, |x, _| Rgb::splat(x as f32 / 255.0));
        let bytes = crate::tonemap_to_srgb8(&flip_heatmap(&errors), &ToneMapping::CLAMP);
        assert_eq!(bytes, lut);
        // Magma goes from near-black to near-white.
        assert!(lut[0] < 10 && lut[765] > 240);
    }
}
