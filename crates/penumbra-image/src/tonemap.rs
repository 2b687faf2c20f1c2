//! Display transform: exposure → tone operator → sRGB OETF → 8 bit.
//!
//! For a linear value `L` (per channel):
//! 1. exposure: `x = L · 2^EV` (NaN and negative values become 0);
//! 2. operator: [`ToneOperator::Clamp`] `y = min(x, 1)`, or
//!    [`ToneOperator::Filmic`] `y = clamp(x(2.51x + 0.03) / (x(2.43x + 0.59) + 0.14), 0, 1)`
//!    (Narkowicz 2015, "ACES Filmic Tone Mapping Curve", applied per channel, no
//!    pre-exposure factor);
//! 3. sRGB OETF (IEC 61966-2-1): `V = 12.92 y` for `y ≤ 0.0031308`, else
//!    `V = 1.055 y^(1/2.4) − 0.055`;
//! 4. quantisation: `⌊255 V + 0.5⌋` (round half up).

use std::fmt;
use std::str::FromStr;

use crate::metrics::nearest_rank;
use crate::{Image, Rgb};

/// Tone curve applied after exposure.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum ToneOperator {
    /// `y = clamp(x, 0, 1)`: exact for values already in [0, 1] (e.g. heatmaps, albedo).
    Clamp,
    /// ACES filmic fit (Narkowicz 2015), per channel:
    /// `y = clamp(x(2.51x + 0.03) / (x(2.43x + 0.59) + 0.14), 0, 1)`.
    /// Mid grey 0.18 maps to 0.267 (sRGB 141/255); the curve saturates at x ≈ 7.24.
    #[default]
    Filmic,
}

impl ToneOperator {
    /// Applies the operator to one exposed linear value `x` (NaN → 0, negative → 0).
    pub fn apply(self, x: f32) -> f32 {
        if x.is_nan() || x <= 0.0 {
            return 0.0;
        }
        match self {
            ToneOperator::Clamp => x.min(1.0),
            ToneOperator::Filmic => aces_filmic(x),
        }
    }

    /// Lower-case name, as accepted by [`FromStr`]: `"clamp"` or `"filmic"`.
    pub fn name(self) -> &'static str {
        match self {
            ToneOperator::Clamp => "clamp",
            ToneOperator::Filmic => "filmic",
        }
    }
}

impl fmt::Display for ToneOperator {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for ToneOperator {
    type Err = String;

    /// Parses `"clamp"` or `"filmic"` (case-insensitive).
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s.to_ascii_lowercase().as_str() {
            "clamp" => Ok(ToneOperator::Clamp),
            "filmic" | "aces" => Ok(ToneOperator::Filmic),
            _ => Err(format!(
                "unknown tone operator {s:?} (expected \"clamp\" or \"filmic\")"
            )),
        }
    }
}

/// The exposure of a PNG: automatic (from the image) or fixed, in stops.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum Exposure {
    /// [`auto_exposure_ev`] of the image.
    #[default]
    Auto,
    /// This many stops.
    Stops(f32),
}

impl Exposure {
    /// The exposure in stops for `img`, metering the pixels `metered` marks
    /// (all pixels without a mask; see [`auto_exposure_ev`]).
    pub fn resolve(self, img: &Image, metered: Option<&[bool]>) -> f32 {
        match self {
            Exposure::Auto => auto_exposure_ev(img, metered),
            Exposure::Stops(ev) => ev,
        }
    }
}

impl FromStr for Exposure {
    type Err = String;

    /// `"auto"` or a finite number of stops.
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        if s.trim().eq_ignore_ascii_case("auto") {
            return Ok(Exposure::Auto);
        }
        match s.trim().parse::<f32>() {
            Ok(ev) if ev.is_finite() => Ok(Exposure::Stops(ev)),
            _ => Err(format!(
                "'{s}' is not an exposure (auto, or a number of stops such as -1.5)"
            )),
        }
    }
}

/// The key value of [`auto_exposure_ev`]: the log-average luminance is
/// exposed to mid grey.
pub const AUTO_EXPOSURE_KEY: f32 = 0.18;
/// Most stops [`auto_exposure_ev`] applies either way.
pub const AUTO_EXPOSURE_LIMIT: f32 = 20.0;

/// The exposure that brings the image's log-average luminance to
/// [`AUTO_EXPOSURE_KEY`] (Reinhard et al. 2002, "Photographic Tone
/// Reproduction for Digital Images", eq. 1 and 2):
/// `L̄ = exp( (1/N) Σ ln L )`, `EV = log₂(0.18 / L̄)`.
///
/// - `L` is the Rec. 709 luminance of each pixel.
/// - Only the pixels `metered` marks count, when it marks any (the renderer
///   marks the pixels whose camera rays hit a surface, so a model is exposed
///   for itself, not for the environment behind it).
/// - Black pixels (L ≤ 0, or not finite) are left out, so a model on a black
///   background is exposed for the model.
/// - The others are clamped to their own 1st and 99th percentiles (nearest
///   rank), so a few emitters or a sun do not darken the image and a few
///   dark cracks do not brighten it.
/// - An image with no lit pixel gets EV 0; the result is limited to ±20 stops.
pub fn auto_exposure_ev(img: &Image, metered: Option<&[bool]>) -> f32 {
    let mask = metered.filter(|m| m.len() == img.pixels.len() && m.contains(&true));
    let mut lum: Vec<f64> = img
        .pixels
        .iter()
        .enumerate()
        .filter(|(i, _)| mask.is_none_or(|m| m[*i]))
        .map(|(_, p)| f64::from(penumbra_shading::color::luminance(*p)))
        .filter(|l| l.is_finite() && *l > 0.0)
        .collect();
    if lum.is_empty() {
        return 0.0;
    }
    lum.sort_by(f64::total_cmp);
    let (lo, hi) = (nearest_rank(&lum, 0.01), nearest_rank(&lum, 0.99));
    let mean_log = lum.iter().map(|l| l.clamp(lo, hi).ln()).sum::<f64>() / lum.len() as f64;
    let ev = (f64::from(AUTO_EXPOSURE_KEY).ln() - mean_log) / std::f64::consts::LN_2;
    (ev as f32).clamp(-AUTO_EXPOSURE_LIMIT, AUTO_EXPOSURE_LIMIT)
}

/// Exposure plus tone operator. Default: EV 0, [`ToneOperator::Filmic`].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ToneMapping {
    /// Exposure in stops: values are multiplied by `2^exposure_ev` before the operator.
    pub exposure_ev: f32,
    /// The tone curve.
    pub operator: ToneOperator,
}

impl ToneMapping {
    /// EV 0 with [`ToneOperator::Clamp`]: writes values in [0, 1] unchanged
    /// except for the sRGB OETF (use it for heatmaps and other display-ready data).
    pub const CLAMP: ToneMapping = ToneMapping {
        exposure_ev: 0.0,
        operator: ToneOperator::Clamp,
    };

    /// A tone mapping with the given exposure and operator.
    pub fn new(exposure_ev: f32, operator: ToneOperator) -> Self {
        Self {
            exposure_ev,
            operator,
        }
    }

    /// Display-referred linear value in [0, 1]: `operator(L · 2^EV)` per channel.
    pub fn map(&self, linear: Rgb) -> Rgb {
        let scale = self.exposure_ev.exp2();
        let op = self.operator;
        Rgb::new(
            op.apply(linear.x * scale),
            op.apply(linear.y * scale),
            op.apply(linear.z * scale),
        )
    }

    /// The 8-bit sRGB code values of one linear pixel.
    pub fn to_srgb8(&self, linear: Rgb) -> [u8; 3] {
        let y = self.map(linear);
        [
            quantize(srgb_oetf(y.x)),
            quantize(srgb_oetf(y.y)),
            quantize(srgb_oetf(y.z)),
        ]
    }
}

/// ACES filmic curve fit (Narkowicz 2015):
/// `clamp(x(2.51x + 0.03) / (x(2.43x + 0.59) + 0.14), 0, 1)`; NaN → 0.
pub fn aces_filmic(x: f32) -> f32 {
    if x.is_nan() || x <= 0.0 {
        return 0.0;
    }
    // Beyond x ≈ 7.24 the curve exceeds 1 and is clamped; bounding x avoids inf/inf.
    let x = x.min(1.0e4);
    ((x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14)).clamp(0.0, 1.0)
}

/// sRGB OETF (IEC 61966-2-1), linear → encoded; the shading crate's.
pub use penumbra_shading::color::linear_to_srgb as srgb_oetf;
/// sRGB EOTF, encoded → linear; the shading crate's.
pub use penumbra_shading::color::srgb_to_linear as srgb_eotf;

/// `⌊255 · clamp(v, 0, 1) + 0.5⌋`; NaN → 0.
pub(crate) fn quantize(v: f32) -> u8 {
    if v.is_nan() {
        return 0;
    }
    (v.clamp(0.0, 1.0) * 255.0 + 0.5) as u8
}

/// Tone-maps a linear image to interleaved 8-bit sRGB, `3 · width · height`
/// bytes, row-major from the top-left: `L · 2^EV` → operator → sRGB OETF → 8 bit.
pub fn tonemap_to_srgb8(img: &Image, tm: &ToneMapping) -> Vec<u8> {
    img.pixels.iter().flat_map(|&p| tm.to_srgb8(p)).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn code(v: f32, tm: ToneMapping) -> u8 {
        tm.to_srgb8(Rgb::splat(v))[0]
    }

    #[test]
    fn clamp_known_values() {
        let tm = ToneMapping::CLAMP;
        assert_eq!(code(0.0, tm), 0);
        assert_eq!(code(0.5, tm), 188); // sRGB(0.5) = 0.73536 → 187.52
        assert_eq!(code(0.18, tm), 118); // 0.46135 → 117.65
        assert_eq!(code(0.001, tm), 3); // linear segment: 12.92e-3 · 255 = 3.29
        assert_eq!(code(1.0, tm), 255);
        assert_eq!(code(7.0, tm), 255);
        assert_eq!(code(-1.0, tm), 0);
        assert_eq!(code(f32::NAN, tm), 0);
        assert_eq!(code(f32::INFINITY, tm), 255);
        // NaN and negative values are black, even huge negative ones (where
        // the rational function is near 1).
        for x in [f32::NAN, -1.0e3, f32::NEG_INFINITY] {
            assert_eq!(aces_filmic(x), 0.0, "f({x})");
        }
    }

    #[test]
    fn exposure_scales_by_power_of_two() {
        let tm = ToneMapping::new(1.0, ToneOperator::Clamp);
        assert_eq!(code(0.25, tm), 188);
        let tm = ToneMapping::new(-2.0, ToneOperator::Clamp);
        assert_eq!(code(2.0, tm), 188);
    }

    #[test]
    fn filmic_known_values() {
        let tm = ToneMapping::default();
        assert_eq!(tm.operator, ToneOperator::Filmic);
        assert_eq!(tm.exposure_ev, 0.0);
        // f(1) = 2.54 / 3.16 = 0.80380 → sRGB 0.9082 → 231.6
        assert!((aces_filmic(1.0) - 2.54 / 3.16).abs() < 1e-6);
        assert_eq!(code(1.0, tm), 232);
        // f(0.5) = 0.64 / 1.0385 = 0.61631 → 206
        assert_eq!(code(0.5, tm), 206);
        assert_eq!(code(0.18, tm), 141);
        assert_eq!(code(0.0, tm), 0);
        assert_eq!(code(1.0e30, tm), 255);
        assert_eq!(code(f32::INFINITY, tm), 255);
        // NaN and negative values are black, even huge negative ones (where
        // the rational function is near 1).
        for x in [f32::NAN, -1.0e3, f32::NEG_INFINITY] {
            assert_eq!(aces_filmic(x), 0.0, "f({x})");
        }
    }

    #[test]
    fn srgb_round_trip() {
        for i in 0..=255u32 {
            let v = i as f32 / 255.0;
            assert_eq!(quantize(srgb_oetf(srgb_eotf(v))), i as u8);
        }
    }

    #[test]
    fn buffer_layout() {
        let img = Image::from_pixels(2, 1, vec![Rgb::new(0.0, 0.5, 1.0), Rgb::new(1.0, 0.0, 0.5)])
            .expect("valid");
        assert_eq!(
            tonemap_to_srgb8(&img, &ToneMapping::CLAMP),
            vec![0, 188, 255, 255, 0, 188]
        );
    }

    #[test]
    fn parse_operator() {
        assert_eq!("Filmic".parse::<ToneOperator>(), Ok(ToneOperator::Filmic));
        assert_eq!("clamp".parse::<ToneOperator>(), Ok(ToneOperator::Clamp));
        assert!("reinhard".parse::<ToneOperator>().is_err());
        // The names printed are the names parsed.
        assert_eq!(ToneOperator::Clamp.name(), "clamp");
        assert_eq!(ToneOperator::Filmic.to_string(), "filmic");
        for op in [ToneOperator::Clamp, ToneOperator::Filmic] {
            assert_eq!(op.name().parse::<ToneOperator>(), Ok(op));
        }
    }

    #[test]
    fn auto_exposure_brings_the_log_average_to_mid_grey() {
        // Constant luminance 0.045 (two stops below 0.18): +2 EV.
        let grey = Image::filled(10, 10, Rgb::splat(0.045));
        assert!((auto_exposure_ev(&grey, None) - 2.0).abs() < 1e-5);
        // Half the pixels at 0.09, half at 0.36: geometric mean 0.18, EV 0;
        // black pixels do not count, one bright outlier is clamped.
        let mut img = Image::from_fn(20, 10, |x, _| Rgb::splat(if x < 10 { 0.09 } else { 0.36 }));
        assert!(auto_exposure_ev(&img, None).abs() < 1e-5);
        img.pixels.extend(vec![Rgb::ZERO; 200]);
        img.height = 20;
        assert!(auto_exposure_ev(&img, None).abs() < 1e-5);
        img.pixels[0] = Rgb::splat(1e9);
        let ev = auto_exposure_ev(&img, None);
        assert!(ev.abs() < 0.02, "{ev}");
        // Metering only the 0.36 half: −1 EV.
        let mask: Vec<bool> = (0..400).map(|i| i < 200 && i % 20 >= 10).collect();
        assert!((auto_exposure_ev(&img, Some(&mask)) + 1.0).abs() < 1e-5);
        // A mask that marks nothing meters everything.
        assert!(auto_exposure_ev(&img, Some(&[false; 400])).abs() < 0.02);
        assert_eq!(auto_exposure_ev(&Image::new(4, 4), None), 0.0);
        let dim = Image::filled(2, 2, Rgb::splat(1e-30));
        assert_eq!(auto_exposure_ev(&dim, None), AUTO_EXPOSURE_LIMIT);
    }

    #[test]
    fn exposure_parses_auto_and_stops() {
        assert_eq!("auto".parse::<Exposure>(), Ok(Exposure::Auto));
        assert_eq!("-1.5".parse::<Exposure>(), Ok(Exposure::Stops(-1.5)));
        assert!("bright".parse::<Exposure>().is_err());
        assert!("inf".parse::<Exposure>().is_err());
    }

    /// A fixed exposure is its stops; `auto` meters the image (constant
    /// luminance 0.0225, three stops below 0.18: +3 EV) or the pixels asked for.
    #[test]
    fn exposure_resolves_to_stops() {
        let grey = Image::filled(4, 4, Rgb::splat(0.0225));
        assert_eq!(Exposure::Stops(2.5).resolve(&grey, None), 2.5);
        assert!((Exposure::Auto.resolve(&grey, None) - 3.0).abs() < 1e-5);
        let mut half = grey.clone();
        for p in &mut half.pixels[8..] {
            *p = Rgb::splat(0.72);
        }
        let bright: Vec<bool> = (0..16).map(|i| i >= 8).collect();
        assert!((Exposure::Auto.resolve(&half, Some(&bright)) + 2.0).abs() < 1e-5);
        // A mask that marks nothing, or does not fit the image, is ignored:
        // both halves are metered, geometric mean √(0.0225 · 0.72) = 0.18/√2,
        // +0.5 EV.
        for mask in [&[false; 16][..], &[true; 3][..]] {
            let ev = Exposure::Auto.resolve(&half, Some(mask));
            assert!((ev - 0.5).abs() < 1e-5, "{ev}");
        }
    }
}
