//! [`Film`] and [`FilmTile`]: per-pixel sums of radiance samples, from which
//! the mean and the variance of the mean follow.
//!
//! Each pixel keeps its sample count `n`, the sum `Σv` and the sum of
//! squares `Σv²` per channel. The mean is `μ = Σv / n`; the unbiased sample
//! variance is `s² = (Σv² − n μ²) / (n − 1)`, and the variance of the pixel
//! estimate (the mean of n samples) is `s² / n`.
//!
//! **Exact sums.** `Σv` is kept in fixed point: each sample is rounded once
//! to a multiple of 2⁻⁴⁸ ([`FIXED_POINT_BITS`]) and the multiples are added
//! as 128-bit integers, which is exact, so the sum does not depend on the
//! order in which samples or films are added. A render split by sample range
//! or by image window and merged gives the same bits as a render in one
//! piece, whatever the thread count or the merge order. Samples of magnitude
//! 2⁴⁶ (≈ 7·10¹³) or more are rejected like non-finite ones, so 2³² samples
//! can never overflow the sum. `Σv²` is kept in f64 (the square of an f32 is
//! exact in f64; the additions round), so the variance estimate may differ
//! in its last bits with the order of merges; the mean never does.
//!
//! The pixel filter is a 1-pixel box: a sample only counts for the pixel it
//! was taken in. A film covers a window `x0..x0+width` × `y0..y0+height` of
//! an image ([`Film::new`] starts at the origin); threads accumulate into
//! disjoint [`FilmTile`]s that are added with [`Film::merge_tile`], and whole
//! films add with [`Film::merge`]. Coordinates are always absolute pixels.

use std::fmt;

use glam::DVec3;

use crate::buffer::pixel_count;
use crate::{Image, Rgb};

/// Fractional bits of the fixed-point sums: samples are rounded to
/// multiples of 2⁻⁴⁸ ≈ 3.6·10⁻¹⁵.
pub const FIXED_POINT_BITS: i32 = 48;

/// Samples with `|v| ≥ 2⁴⁶` in any channel are rejected, so that 2³²
/// samples (the largest count) cannot overflow a 128-bit sum.
pub const MAX_SAMPLE_MAGNITUDE: f64 = (1u64 << 46) as f64;

/// Sums of one pixel's samples.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct PixelStats {
    pub(crate) n: u32,
    /// `Σv` per channel, in units of 2⁻⁴⁸.
    pub(crate) sum: [i128; 3],
    /// `Σv²` per channel.
    pub(crate) sum_sq: DVec3,
}

/// `v` in units of 2⁻⁴⁸, rounded to the nearest integer, ties away from
/// zero (the one rounding of a sample; f32 values of magnitude 2⁻²⁴ or more
/// are exact): `round(v · 2⁴⁸)`, computed on the bits. With `v = ±m ·
/// 2^(e − 150)` (m the 24-bit significand, e the biased exponent; e = 1
/// with no implicit bit for subnormals), `v · 2⁴⁸ = ±m · 2^(e − 102)`: a
/// shift left, or right with the half added first. No float rounding and
/// no 128-bit conversion call, which cost 1.4 % of a path sample. `v`
/// must be accepted ([`accepted`]: finite, |v| < 2⁴⁶).
fn to_fixed(v: f32) -> i128 {
    let bits = v.to_bits();
    let biased = (bits >> 23) & 0xff;
    let fraction = bits & 0x7f_ffff;
    let (m, e) = if biased == 0 {
        (fraction, 1)
    } else {
        (fraction | 0x80_0000, biased)
    };
    debug_assert!(e < 127 + 46, "{v} is not an accepted sample");
    let shift = e as i32 - (150 - FIXED_POINT_BITS);
    let magnitude = if shift >= 0 {
        i128::from(m) << shift
    } else {
        // Past a right shift of 24, m < 2²⁴ ≤ half: the result is 0.
        let right = shift.unsigned_abs();
        if right > 24 {
            0
        } else {
            i128::from((m + (1 << (right - 1))) >> right)
        }
    };
    if bits >> 31 == 0 {
        magnitude
    } else {
        -magnitude
    }
}

fn from_fixed(v: i128) -> f64 {
    v as f64 * f64::powi(2.0, -FIXED_POINT_BITS)
}

/// Whether a sample can be accumulated: finite and below [`MAX_SAMPLE_MAGNITUDE`].
fn accepted(value: Rgb) -> bool {
    value.is_finite() && (value.abs().max_element() as f64) < MAX_SAMPLE_MAGNITUDE
}

impl PixelStats {
    fn push(&mut self, v: Rgb) {
        self.n += 1;
        for c in 0..3 {
            self.sum[c] += to_fixed(v[c]);
        }
        let d = v.as_dvec3();
        self.sum_sq += d * d;
    }

    /// Adds another pixel's sums (exact for `n` and `Σv`).
    fn merge(&mut self, other: &PixelStats) {
        self.n = self.n.saturating_add(other.n);
        for c in 0..3 {
            self.sum[c] += other.sum[c];
        }
        self.sum_sq += other.sum_sq;
    }

    /// `μ = Σv / n`; zero for n = 0.
    fn mean(&self) -> DVec3 {
        if self.n == 0 {
            return DVec3::ZERO;
        }
        let n = f64::from(self.n);
        DVec3::new(
            from_fixed(self.sum[0]),
            from_fixed(self.sum[1]),
            from_fixed(self.sum[2]),
        ) / n
    }

    /// Variance of the mean estimator, `s²/n = (Σv² − n μ²) / ((n − 1) n)`,
    /// clamped at zero against rounding; zero for n < 2.
    fn variance_of_mean(&self) -> DVec3 {
        if self.n < 2 {
            return DVec3::ZERO;
        }
        let n = f64::from(self.n);
        let mean = self.mean();
        ((self.sum_sq - n * mean * mean) / ((n - 1.0) * n)).max(DVec3::ZERO)
    }
}

/// A rectangle of absolute pixels and the statistics of each, row-major.
#[derive(Clone, PartialEq)]
struct Window {
    x0: u32,
    y0: u32,
    width: u32,
    height: u32,
    stats: Vec<PixelStats>,
    rejected: u64,
}

impl Window {
    fn new(x0: u32, y0: u32, width: u32, height: u32) -> Self {
        Self {
            x0,
            y0,
            width,
            height,
            stats: vec![PixelStats::default(); pixel_count(width, height)],
            rejected: 0,
        }
    }

    /// Index of absolute pixel (x, y), if it lies inside.
    fn index(&self, x: u32, y: u32) -> Option<usize> {
        let (tx, ty) = (x.checked_sub(self.x0)?, y.checked_sub(self.y0)?);
        (tx < self.width && ty < self.height)
            .then(|| ty as usize * self.width as usize + tx as usize)
    }

    fn add_sample(&mut self, x: u32, y: u32, value: Rgb) {
        let Some(i) = self.index(x, y) else {
            return;
        };
        if !accepted(value) {
            self.rejected += 1;
            return;
        }
        self.stats[i].push(value);
    }

    fn sample_count(&self, x: u32, y: u32) -> u32 {
        self.index(x, y).map_or(0, |i| self.stats[i].n)
    }

    /// Adds the statistics of `other` where the two windows overlap.
    fn merge(&mut self, other: &Window) {
        self.rejected += other.rejected;
        for oy in 0..other.height {
            let y = other.y0 + oy;
            for ox in 0..other.width {
                if let Some(i) = self.index(other.x0 + ox, y) {
                    let j = oy as usize * other.width as usize + ox as usize;
                    self.stats[i].merge(&other.stats[j]);
                }
            }
        }
    }
}

/// Per-pixel sample sums over a window of an image: the mean image and the
/// variance of each pixel's mean (see the module docs).
///
/// Non-finite samples (NaN or ±∞) and samples of magnitude ≥ 2⁴⁶ are not
/// accumulated; they are counted in [`Film::rejected_samples`] so a caller
/// can report them. Samples outside the film are ignored.
#[derive(Clone, PartialEq)]
pub struct Film {
    w: Window,
}

impl fmt::Debug for Film {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Film")
            .field("x0", &self.w.x0)
            .field("y0", &self.w.y0)
            .field("width", &self.w.width)
            .field("height", &self.w.height)
            .field("total_samples", &self.total_samples())
            .field("rejected_samples", &self.w.rejected)
            .finish()
    }
}

impl Film {
    /// An empty film of `width` × `height` pixels at the image's origin.
    pub fn new(width: u32, height: u32) -> Self {
        Self::window(0, 0, width, height)
    }

    /// An empty film covering pixels `x0..x0+width` × `y0..y0+height` of an image.
    pub fn window(x0: u32, y0: u32, width: u32, height: u32) -> Self {
        Self {
            w: Window::new(x0, y0, width, height),
        }
    }

    /// Left column of the window.
    pub fn x0(&self) -> u32 {
        self.w.x0
    }

    /// Top row of the window.
    pub fn y0(&self) -> u32 {
        self.w.y0
    }

    /// Width in pixels.
    pub fn width(&self) -> u32 {
        self.w.width
    }

    /// Height in pixels.
    pub fn height(&self) -> u32 {
        self.w.height
    }

    /// Adds one radiance sample taken inside absolute pixel (x, y) (1-pixel
    /// box filter). Pixels outside the window are ignored; rejected values
    /// are counted.
    pub fn add_sample(&mut self, x: u32, y: u32, value: Rgb) {
        self.w.add_sample(x, y, value);
    }

    /// The per-pixel sample mean `μ` over the window (black where a pixel
    /// has no samples).
    pub fn mean(&self) -> Image {
        self.to_image(PixelStats::mean)
    }

    /// The variance of each pixel's mean estimator, `s²/n` (zero where a
    /// pixel has fewer than 2 samples).
    pub fn variance(&self) -> Image {
        self.to_image(PixelStats::variance_of_mean)
    }

    /// Number of accepted samples in absolute pixel (x, y); 0 outside the film.
    pub fn sample_count(&self, x: u32, y: u32) -> u32 {
        self.w.sample_count(x, y)
    }

    /// Total number of accepted samples over all pixels.
    pub fn total_samples(&self) -> u64 {
        self.w.stats.iter().map(|s| u64::from(s.n)).sum()
    }

    /// Number of samples that were rejected (including those of merged tiles
    /// and films).
    pub fn rejected_samples(&self) -> u64 {
        self.w.rejected
    }

    /// Splits the film into empty tiles of at most `tile_size`² pixels, row-major,
    /// covering every pixel exactly once (`tile_size` 0 is treated as 1).
    pub fn tiles(&self, tile_size: u32) -> Vec<FilmTile> {
        let size = tile_size.max(1);
        let (x0, y0, w, h) = (self.w.x0, self.w.y0, self.w.width, self.w.height);
        let mut tiles = Vec::new();
        for ty in (0..h).step_by(size as usize) {
            for tx in (0..w).step_by(size as usize) {
                tiles.push(FilmTile::new(
                    x0 + tx,
                    y0 + ty,
                    size.min(w - tx),
                    size.min(h - ty),
                ));
            }
        }
        tiles
    }

    /// Adds the statistics of a tile to the film. Sums add exactly, so the
    /// result does not depend on how samples were split into tiles or on the
    /// merge order. Parts of the tile outside the film are ignored.
    pub fn merge_tile(&mut self, tile: &FilmTile) {
        self.w.merge(&tile.w);
    }

    /// Adds the statistics of another film where the windows overlap (exact
    /// and order-independent, as [`Film::merge_tile`]).
    pub fn merge(&mut self, other: &Film) {
        self.w.merge(&other.w);
    }

    /// The statistics of every pixel, row-major over the window.
    pub(crate) fn stats(&self) -> &[PixelStats] {
        &self.w.stats
    }

    /// A film from its window and statistics (`stats.len()` must be
    /// `width × height`).
    pub(crate) fn from_stats(
        (x0, y0, width, height): (u32, u32, u32, u32),
        stats: Vec<PixelStats>,
        rejected: u64,
    ) -> Option<Self> {
        (stats.len() == pixel_count(width, height)).then_some(Self {
            w: Window {
                x0,
                y0,
                width,
                height,
                stats,
                rejected,
            },
        })
    }

    fn to_image(&self, f: impl Fn(&PixelStats) -> DVec3) -> Image {
        Image {
            width: self.w.width,
            height: self.w.height,
            pixels: self.w.stats.iter().map(|s| f(s).as_vec3()).collect(),
        }
    }
}

/// A rectangle of film statistics that one thread can fill independently;
/// add it to the [`Film`] with [`Film::merge_tile`].
///
/// Coordinates are absolute film pixels: the tile covers
/// `x0..x0+width` × `y0..y0+height`.
#[derive(Clone)]
pub struct FilmTile {
    w: Window,
}

impl fmt::Debug for FilmTile {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("FilmTile")
            .field("x0", &self.w.x0)
            .field("y0", &self.w.y0)
            .field("width", &self.w.width)
            .field("height", &self.w.height)
            .field("rejected_samples", &self.w.rejected)
            .finish()
    }
}

impl FilmTile {
    /// An empty tile covering `x0..x0+width` × `y0..y0+height`.
    pub fn new(x0: u32, y0: u32, width: u32, height: u32) -> Self {
        Self {
            w: Window::new(x0, y0, width, height),
        }
    }

    /// Left column (absolute).
    pub fn x0(&self) -> u32 {
        self.w.x0
    }

    /// Top row (absolute).
    pub fn y0(&self) -> u32 {
        self.w.y0
    }

    /// Width in pixels.
    pub fn width(&self) -> u32 {
        self.w.width
    }

    /// Height in pixels.
    pub fn height(&self) -> u32 {
        self.w.height
    }

    /// Adds a sample for absolute pixel (x, y). Pixels outside the tile are
    /// ignored; rejected values are counted.
    pub fn add_sample(&mut self, x: u32, y: u32, value: Rgb) {
        self.w.add_sample(x, y, value);
    }

    /// Number of accepted samples in absolute pixel (x, y); 0 outside the tile.
    pub fn sample_count(&self, x: u32, y: u32) -> u32 {
        self.w.sample_count(x, y)
    }

    /// `true` when `(x, y)` (absolute) lies inside the tile.
    pub fn contains(&self, x: u32, y: u32) -> bool {
        self.w.index(x, y).is_some()
    }
}
#[cfg(test)]
mod tests {
    use super::*;

    /// `to_fixed` on the bits against its definition in f64 (`round(v ·
    /// 2⁴⁸)`, exact in f64 for an f32 v): every exponent an accepted
    /// sample can have, both signs, zeros, subnormals, the largest
    /// accepted magnitude, and values that fall exactly halfway between
    /// two multiples of 2⁻⁴⁸ (rounded away from zero).
    #[test]
    fn fixed_point_matches_rounding_in_f64() {
        let by_f64 = |v: f32| (f64::from(v) * f64::powi(2.0, FIXED_POINT_BITS)).round() as i128;
        let mut x = 12345u32;
        let mut next = || {
            x ^= x << 13;
            x ^= x >> 17;
            x ^= x << 5;
            x
        };
        let mut values = vec![
            0.0f32,
            -0.0,
            f32::MIN_POSITIVE,
            f32::from_bits(1),
            -f32::from_bits(1),
        ];
        values.push(f32::from_bits((127 + 46) << 23).next_down());
        for biased in 0..(127 + 46) {
            for _ in 0..200 {
                let bits = (biased << 23) | (next() & 0x7f_ffff) | (next() & 1) << 31;
                values.push(f32::from_bits(bits));
            }
        }
        // Halfway cases: k + ½ units of 2⁻⁴⁸ for small k (exponents where
        // the last significand bit is worth ½ unit).
        for k in [0u32, 1, 2, 3, 1000, (1 << 22) + 7] {
            let v = (k as f32 + 0.5) * f32::powi(2.0, -FIXED_POINT_BITS);
            assert_eq!(
                f64::from(v) * f64::powi(2.0, FIXED_POINT_BITS),
                k as f64 + 0.5
            );
            values.push(v);
            values.push(-v);
        }
        for v in values {
            assert!(accepted(Rgb::splat(v)), "{v}");
            assert_eq!(to_fixed(v), by_f64(v), "{v:e} ({:#010x})", v.to_bits());
        }
    }

    fn close(a: f32, b: f64, tol: f64) -> bool {
        (f64::from(a) - b).abs() <= tol * b.abs().max(1e-12)
    }

    #[test]
    fn mean_and_variance_closed_form() {
        // Samples 1..=n in pixel (1, 0): mean (n+1)/2, s² = n(n+1)/12, var of mean = (n+1)/12.
        let n = 100u32;
        let mut film = Film::new(2, 2);
        for k in 1..=n {
            let v = k as f32;
            film.add_sample(1, 0, Rgb::new(v, 2.0 * v, 5.0));
        }
        let mean = film.mean();
        let var = film.variance();
        let nf = f64::from(n);
        assert!(close(mean.get(1, 0).x, (nf + 1.0) / 2.0, 1e-12));
        assert!(close(mean.get(1, 0).y, nf + 1.0, 1e-12));
        assert!(close(mean.get(1, 0).z, 5.0, 1e-12));
        assert!(close(var.get(1, 0).x, (nf + 1.0) / 12.0, 1e-6));
        assert!(close(var.get(1, 0).y, 4.0 * (nf + 1.0) / 12.0, 1e-6));
        assert_eq!(var.get(1, 0).z, 0.0);
        assert_eq!(film.sample_count(1, 0), n);
        assert_eq!(film.sample_count(0, 0), 0);
        assert_eq!(mean.get(0, 0), Rgb::ZERO);
        assert_eq!(var.get(0, 0), Rgb::ZERO);
    }

    #[test]
    fn two_point_variance() {
        // {0, 1}: s² = 0.5, var of mean = 0.25.
        let mut film = Film::new(1, 1);
        film.add_sample(0, 0, Rgb::ZERO);
        film.add_sample(0, 0, Rgb::ONE);
        assert_eq!(film.variance().get(0, 0), Rgb::splat(0.25));
        assert_eq!(film.mean().get(0, 0), Rgb::splat(0.5));
    }

    #[test]
    fn box_filter_and_bounds() {
        let mut film = Film::new(2, 1);
        film.add_sample(0, 0, Rgb::ONE);
        film.add_sample(5, 0, Rgb::ONE); // outside: ignored
        film.add_sample(1, 0, Rgb::new(f32::NAN, 0.0, 0.0)); // rejected
        assert_eq!(film.mean().pixels, vec![Rgb::ONE, Rgb::ZERO]);
        assert_eq!(film.rejected_samples(), 1);
        assert_eq!(film.total_samples(), 1);
    }

    /// Deterministic pseudo-random values (xorshift) for the tests.
    fn sequence(len: usize) -> Vec<f32> {
        let mut s = 0x2545_f491_4f6c_dd1du64;
        (0..len)
            .map(|_| {
                s ^= s << 13;
                s ^= s >> 7;
                s ^= s << 17;
                (s >> 40) as f32 / (1u64 << 24) as f32 * 10.0
            })
            .collect()
    }

    #[test]
    fn merge_tile_matches_direct_adds() {
        let (w, h) = (7u32, 5u32);
        let values = sequence(3 * 7 * 5 * 9);
        let mut direct = Film::new(w, h);
        let mut tiled = Film::new(w, h);
        // Samples split over two passes of tiles, so pixels merge into non-empty stats.
        let mut it = values.chunks(3);
        for pass in 0..3 {
            let mut tiles = tiled.tiles(3);
            assert_eq!(
                tiles.iter().map(|t| t.width() * t.height()).sum::<u32>(),
                w * h
            );
            for _ in 0..(pass + 1) {
                for y in 0..h {
                    for x in 0..w {
                        let Some(c) = it.next() else { continue };
                        let v = Rgb::new(c[0], c[1], c[2]);
                        direct.add_sample(x, y, v);
                        let tile = tiles.iter_mut().find(|t| t.contains(x, y));
                        tile.expect("tiles cover the film").add_sample(x, y, v);
                    }
                }
            }
            // One rejected sample in every tile, counted once each.
            for t in &mut tiles {
                let (x, y) = (t.x0(), t.y0());
                t.add_sample(x, y, Rgb::new(f32::NAN, 0.0, 0.0));
                direct.add_sample(x, y, Rgb::new(f32::NAN, 0.0, 0.0));
            }
            for t in &tiles {
                tiled.merge_tile(t);
            }
        }
        assert_eq!(tiled.rejected_samples(), direct.rejected_samples());
        assert_eq!(direct.rejected_samples(), 3 * 6);
        for y in 0..h {
            for x in 0..w {
                assert_eq!(direct.sample_count(x, y), tiled.sample_count(x, y));
                assert!(direct.sample_count(x, y) >= 2);
            }
        }
        let (dm, tm) = (direct.mean(), tiled.mean());
        let (dv, tv) = (direct.variance(), tiled.variance());
        for i in 0..dm.pixels.len() {
            assert!((dm.pixels[i] - tm.pixels[i]).abs().max_element() < 1e-5);
            assert!((dv.pixels[i] - tv.pixels[i]).abs().max_element() < 1e-5);
            assert!(dv.pixels[i].min_element() > 0.0);
        }
    }

    #[test]
    fn tile_ignores_outside_samples() {
        let mut tile = FilmTile::new(2, 2, 2, 2);
        tile.add_sample(1, 2, Rgb::ONE);
        tile.add_sample(4, 2, Rgb::ONE);
        tile.add_sample(3, 3, Rgb::ONE);
        tile.add_sample(3, 3, Rgb::splat(3.0));
        assert_eq!(tile.sample_count(3, 3), 2);
        assert_eq!(tile.sample_count(2, 3), 0);
        let mut film = Film::new(3, 3); // tile partly outside the film
        film.merge_tile(&tile);
        assert_eq!(film.total_samples(), 0);
        tile.add_sample(2, 2, Rgb::splat(2.0));
        film.merge_tile(&tile);
        assert_eq!(film.mean().get(2, 2), Rgb::splat(2.0));
        assert_eq!(film.total_samples(), 1);
    }

    #[test]
    fn split_and_merged_in_any_order_gives_the_same_bits() {
        // Values spanning 12 decades, so f64 or Welford accumulation would
        // depend on the order of the additions.
        let v = sequence(3 * 4 * 40);
        let sample = |i: usize, k: usize| {
            let c = &v[3 * (i * 40 + k)..3 * (i * 40 + k) + 3];
            Rgb::new(c[0] * 1e6, c[1] * 1e-6, c[2] - 5.0)
        };
        let mut whole = Film::new(2, 2);
        for k in 0..40 {
            for i in 0..4 {
                whole.add_sample(i as u32 % 2, i as u32 / 2, sample(i, k));
            }
        }
        // Four sample ranges, each a film, merged in reverse order; and two
        // windows of one range.
        let ranges = [0..7, 7..19, 19..20, 20..40];
        let parts: Vec<Film> = ranges
            .iter()
            .map(|r| {
                let mut f = Film::new(2, 2);
                for k in r.clone() {
                    for i in 0..4 {
                        f.add_sample(i as u32 % 2, i as u32 / 2, sample(i, k));
                    }
                }
                f
            })
            .collect();
        let mut merged = Film::new(2, 2);
        for p in parts.iter().rev() {
            merged.merge(p);
        }
        assert_eq!(merged.mean(), whole.mean());
        assert_eq!(merged.total_samples(), whole.total_samples());
        for (a, b) in merged
            .variance()
            .pixels
            .iter()
            .zip(&whole.variance().pixels)
        {
            assert!((*a - *b).abs().max_element() <= 1e-9 * b.abs().max_element());
        }
        let mut left = Film::window(0, 0, 1, 2);
        let mut right = Film::window(1, 0, 1, 2);
        for k in 0..40 {
            for i in 0..4 {
                let (x, y) = (i as u32 % 2, i as u32 / 2);
                left.add_sample(x, y, sample(i, k));
                right.add_sample(x, y, sample(i, k));
            }
        }
        assert_eq!(left.total_samples() + right.total_samples(), 160);
        let mut windows = Film::new(2, 2);
        windows.merge(&right);
        windows.merge(&left);
        assert_eq!(windows.mean(), whole.mean());
    }

    #[test]
    fn fixed_point_sum_is_within_one_rounding_per_sample() {
        // 1000 samples of 0.1 + 1e-9: the mean is exact to f32 precision.
        let mut film = Film::new(1, 1);
        let v = 0.1f32 + 1e-9;
        for _ in 0..1000 {
            film.add_sample(0, 0, Rgb::new(v, 1e-12, 3e9));
        }
        let m = film.mean().get(0, 0);
        assert_eq!(m.x, v);
        assert!((m.y / 1e-12 - 1.0).abs() < 1e-2, "{}", m.y);
        assert_eq!(m.z, 3e9);
    }

    #[test]
    fn huge_samples_are_rejected_not_wrapped() {
        let mut film = Film::new(1, 1);
        film.add_sample(0, 0, Rgb::new(1.0, 0.0, 0.0));
        film.add_sample(0, 0, Rgb::new(0.0, 7.1e13, 0.0));
        film.add_sample(0, 0, Rgb::new(0.0, 0.0, -f32::MAX));
        film.add_sample(0, 0, Rgb::new(0.0, 7.0e13, 0.0));
        assert_eq!(film.rejected_samples(), 2);
        assert_eq!(film.sample_count(0, 0), 2);
        assert_eq!(film.mean().get(0, 0), Rgb::new(0.5, 3.5e13, 0.0));
        // Exactly 2⁴⁶ (an f32) is rejected, the float below it is not.
        film.add_sample(0, 0, Rgb::new(0.0, 0.0, 70_368_744_177_664.0));
        assert_eq!(film.rejected_samples(), 3);
        film.add_sample(0, 0, Rgb::new(0.0, 0.0, 70_368_739_983_360.0));
        assert_eq!(film.rejected_samples(), 3);
        assert_eq!(film.sample_count(0, 0), 3);
    }

    #[test]
    fn window_films_use_absolute_coordinates() {
        let mut film = Film::window(3, 2, 2, 1);
        film.add_sample(0, 0, Rgb::ONE); // outside
        film.add_sample(4, 2, Rgb::splat(2.0));
        assert_eq!(film.total_samples(), 1);
        assert_eq!(film.sample_count(4, 2), 1);
        assert_eq!(film.mean().pixels, vec![Rgb::ZERO, Rgb::splat(2.0)]);
        let tiles = film.tiles(1);
        assert_eq!((tiles[1].x0(), tiles[1].y0()), (4, 2));
    }
}
