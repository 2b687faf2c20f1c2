//! The errors of a row: the same functions `penumbra compare` uses
//! (relMSE, HDR-FLIP mean), plus the FLIP 99th percentile and the mean
//! ratio per channel.

use crate::row::Errors;
use penumbra_image::{Image, ImageError, hdr_flip, percentile, rel_mse};

/// The errors of `test` against `truth`, and the per-pixel FLIP map.
pub fn errors(truth: &Image, test: &Image) -> Result<(Errors, Image), ImageError> {
    let (flip_mean, map) = hdr_flip(truth, test)?;
    let errors = Errors {
        rel_mse: rel_mse(truth, test),
        flip_mean,
        flip_p99: percentile(map.pixels.iter().map(|p| f64::from(p[0])).collect(), 0.99),
        mean_ratio: mean_ratio(truth, test),
    };
    Ok((errors, map))
}

/// mean(test) / mean(truth) per channel, summed in f64; NaN where the
/// truth's channel is black.
pub fn mean_ratio(truth: &Image, test: &Image) -> [f64; 3] {
    let sum = |img: &Image, c: usize| -> f64 { img.pixels.iter().map(|p| f64::from(p[c])).sum() };
    std::array::from_fn(|c| {
        let r = sum(truth, c);
        if r > 0.0 { sum(test, c) / r } else { f64::NAN }
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use penumbra_image::Rgb;

    #[test]
    fn mean_ratio_per_channel() {
        let truth = Image::filled(4, 2, Rgb::new(1.0, 2.0, 0.0));
        let mut test = Image::filled(4, 2, Rgb::new(1.5, 1.0, 1.0));
        test.set(0, 0, Rgb::new(0.5, 1.0, 1.0));
        let r = mean_ratio(&truth, &test);
        // red: (7·1.5 + 0.5)/8 = 1.375; green 0.5; blue: black truth.
        assert!((r[0] - 1.375).abs() < 1e-12);
        assert!((r[1] - 0.5).abs() < 1e-12);
        assert!(r[2].is_nan());
    }

    #[test]
    fn identical_images_have_no_error() {
        let img = Image::from_fn(8, 8, |x, y| Rgb::new(x as f32 * 0.1, y as f32 * 0.2, 0.5));
        let (e, _) = errors(&img, &img).unwrap();
        assert_eq!(e.rel_mse, 0.0);
        assert_eq!(e.flip_mean, 0.0);
        assert_eq!(e.flip_p99, 0.0);
        assert_eq!(e.mean_ratio, [1.0; 3]);
    }
}
