//! Error metrics between a reference and a test image.
//!
//! All sums run over every pixel and all three channels (N = 3 · width · height)
//! in f64. The per-value functions ([`rmse`], [`rel_mse`], [`psnr`]) return NaN
//! when the images differ in size or are malformed; [`compare`] reports an
//! error instead.

use std::fmt;

use crate::{Image, ImageError};

pub use crate::flip::{flip_heatmap, hdr_flip};

/// The error of a test image against a reference.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Metrics {
    /// Root mean squared error, see [`rmse`].
    pub rmse: f64,
    /// Relative mean squared error, see [`rel_mse`].
    pub rel_mse: f64,
    /// Peak signal-to-noise ratio in dB, see [`psnr`].
    pub psnr: f64,
    /// Mean HDR-FLIP error, see [`hdr_flip`].
    pub flip: f64,
}

impl fmt::Display for Metrics {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "RMSE {:.6}  relMSE {:.6}  PSNR {:.2} dB  FLIP {:.4}",
            self.rmse, self.rel_mse, self.psnr, self.flip
        )
    }
}

/// Checks both images are well-formed, non-empty and of equal size.
pub(crate) fn check_pair(reference: &Image, test: &Image) -> Result<(), ImageError> {
    reference.validate("reference image")?;
    test.validate("test image")?;
    if (reference.width, reference.height) != (test.width, test.height) {
        return Err(ImageError::SizeMismatch {
            reference: (reference.width, reference.height),
            test: (test.width, test.height),
        });
    }
    if reference.is_empty() {
        return Err(ImageError::InvalidImage {
            what: "reference image".into(),
            message: format!(
                "{}x{} image has no pixels",
                reference.width, reference.height
            ),
        });
    }
    Ok(())
}

/// Computes all metrics. Errors if the sizes differ (naming both) or an image is empty/malformed.
pub fn compare(reference: &Image, test: &Image) -> Result<Metrics, ImageError> {
    check_pair(reference, test)?;
    let (flip, _) = hdr_flip(reference, test)?;
    Ok(Metrics {
        rmse: rmse(reference, test),
        rel_mse: rel_mse(reference, test),
        psnr: psnr(reference, test),
        flip,
    })
}

/// Mean over pixels and channels of `f(r, t)`, in f64; NaN for mismatched or empty images.
fn mean_over_channels(reference: &Image, test: &Image, f: impl Fn(f64, f64) -> f64) -> f64 {
    if check_pair(reference, test).is_err() {
        return f64::NAN;
    }
    let sum: f64 = reference
        .pixels
        .iter()
        .zip(&test.pixels)
        .flat_map(|(r, t)| (0..3).map(move |c| (f64::from(r[c]), f64::from(t[c]))))
        .map(|(r, t)| f(r, t))
        .sum();
    sum / (3 * reference.pixels.len()) as f64
}

/// Mean squared error, `MSE = (1/N) Σ (t − r)²`.
pub fn mse(r: &Image, t: &Image) -> f64 {
    mean_over_channels(r, t, |r, t| (t - r) * (t - r))
}

/// Root mean squared error, `RMSE = sqrt((1/N) Σ (t − r)²)`.
pub fn rmse(r: &Image, t: &Image) -> f64 {
    mse(r, t).sqrt()
}

/// Relative mean squared error, `relMSE = (1/N) Σ (t − r)² / (r² + 0.01)`
/// (the definition used in the reference README).
pub fn rel_mse(r: &Image, t: &Image) -> f64 {
    mean_over_channels(r, t, |r, t| (t - r) * (t - r) / (r * r + 0.01))
}

/// Peak signal-to-noise ratio in dB, `PSNR = 20 log10(peak / RMSE)`, with
/// `peak` = the largest finite channel value of the reference (1.0 if that is
/// not positive). +∞ for identical images.
pub fn psnr(r: &Image, t: &Image) -> f64 {
    let e = rmse(r, t);
    if e.is_nan() {
        return f64::NAN;
    }
    let max = f64::from(r.max_value());
    let peak = if max > 0.0 { max } else { 1.0 };
    20.0 * (peak / e).log10()
}

/// The relMSE of an estimate of the mean from its variance:
/// `(1/N) Σ Var[mean] / (r² + 0.01)` over pixels and channels, the
/// expected relMSE of the image against its own limit.
pub fn noise_rel_mse(mean: &Image, variance: &Image) -> f64 {
    let n = 3 * mean.pixels.len();
    let sum: f64 = mean
        .pixels
        .iter()
        .zip(&variance.pixels)
        .flat_map(|(m, v)| (0..3).map(move |c| (f64::from(m[c]), f64::from(v[c]))))
        .map(|(m, v)| v / (m * m + 0.01))
        .sum();
    sum / n.max(1) as f64
}

/// The `q`-quantile of `values` by the nearest-rank rule (the smallest value
/// with at least ⌈qN⌉ values at or below it); NaN for no values.
pub fn percentile(mut values: Vec<f64>, q: f64) -> f64 {
    values.sort_by(f64::total_cmp);
    nearest_rank(&values, q)
}

/// [`percentile`] of values already sorted ascending.
pub fn nearest_rank(sorted: &[f64], q: f64) -> f64 {
    if sorted.is_empty() {
        return f64::NAN;
    }
    let rank = ((q * sorted.len() as f64).ceil() as usize).clamp(1, sorted.len());
    sorted[rank - 1]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Rgb;

    fn pair() -> (Image, Image) {
        // Reference: (1,0,0), (0,0,2); test: (1,1,0), (0,0,0)
        let r = Image::from_pixels(2, 1, vec![Rgb::new(1.0, 0.0, 0.0), Rgb::new(0.0, 0.0, 2.0)])
            .expect("valid");
        let t = Image::from_pixels(2, 1, vec![Rgb::new(1.0, 1.0, 0.0), Rgb::new(0.0, 0.0, 0.0)])
            .expect("valid");
        (r, t)
    }

    #[test]
    fn hand_computed_values() {
        let (r, t) = pair();
        // Squared errors: 0,1,0, 0,0,4 → MSE = 5/6.
        assert!((mse(&r, &t) - 5.0 / 6.0).abs() < 1e-12);
        assert!((rmse(&r, &t) - (5.0f64 / 6.0).sqrt()).abs() < 1e-12);
        // relMSE: 1/(0+0.01) + 4/(4+0.01) over 6 = (100 + 0.997506…)/6.
        let expected = (1.0 / 0.01 + 4.0 / 4.01) / 6.0;
        assert!(
            (rel_mse(&r, &t) - expected).abs() < 1e-9,
            "{}",
            rel_mse(&r, &t)
        );
        // PSNR with peak 2: 20 log10(2 / sqrt(5/6)).
        let expected = 20.0 * (2.0 / (5.0f64 / 6.0).sqrt()).log10();
        assert!((psnr(&r, &t) - expected).abs() < 1e-9);
        // A black reference has no peak: 1.0 is used, so an error of 0.1
        // everywhere reads 20 log10(1 / 0.1) = 20 dB.
        let black = Image::new(3, 2);
        let grey = Image::filled(3, 2, Rgb::splat(0.1));
        assert!(
            (psnr(&black, &grey) - 20.0).abs() < 1e-5,
            "{}",
            psnr(&black, &grey)
        );
    }

    #[test]
    fn identical_images() {
        let (r, _) = pair();
        assert_eq!(rmse(&r, &r), 0.0);
        assert_eq!(rel_mse(&r, &r), 0.0);
        assert_eq!(psnr(&r, &r), f64::INFINITY);
    }

    #[test]
    fn size_mismatch() {
        let (r, _) = pair();
        let t = Image::new(1, 2);
        assert!(rmse(&r, &t).is_nan());
        let e = compare(&r, &t).expect_err("sizes differ");
        let msg = e.to_string();
        assert!(msg.contains("2x1") && msg.contains("1x2"), "{msg}");
    }

    #[test]
    fn compare_fills_all_fields() {
        let r = Image::from_fn(16, 16, |x, y| Rgb::splat(0.1 + 0.01 * (x + y) as f32));
        let t = Image::from_fn(16, 16, |x, y| {
            r.get(x, y) * if (x + y) % 2 == 0 { 1.2 } else { 0.8 }
        });
        let m = compare(&r, &t).expect("compare");
        assert!((m.rmse - rmse(&r, &t)).abs() < 1e-15);
        assert!((m.rel_mse - rel_mse(&r, &t)).abs() < 1e-15);
        assert!(m.flip > 0.0 && m.flip < 1.0);
        assert!(m.psnr.is_finite());
    }

    #[test]
    fn noise_estimate_matches_the_formula() {
        let mean = Image::filled(2, 2, Rgb::new(0.3, 0.0, 1.0));
        let var = Image::filled(2, 2, Rgb::new(0.001, 0.002, 0.004));
        let want = (0.001 / (0.09 + 0.01) + 0.002 / 0.01 + 0.004 / 1.01) / 3.0;
        assert!((noise_rel_mse(&mean, &var) / want - 1.0).abs() < 1e-6);
    }

    #[test]
    fn nearest_rank_percentile() {
        let v: Vec<f64> = (1..=100).map(f64::from).collect();
        assert_eq!(percentile(v.clone(), 0.99), 99.0);
        assert_eq!(percentile(v.clone(), 1.0), 100.0);
        assert_eq!(percentile(v, 0.5), 50.0);
        assert_eq!(percentile(vec![3.0, 1.0, 2.0], 0.0), 1.0);
        assert!(percentile(Vec::new(), 0.5).is_nan());
    }
}
