//! [`Film`] and [`FilmTile`]: per-pixel running mean and variance of radiance samples.
//!
//! Each pixel keeps Welford's running statistics (Welford 1962):
//! for the n-th sample `v`, `δ = v − μ`, `μ += δ / n`, `M₂ += δ · (v − μ)`.
//! The sample variance is `s² = M₂ / (n − 1)` and the variance of the pixel
//! estimate (the mean of n samples) is `s² / n`.
//!
//! The pixel filter is a 1-pixel box: a sample only counts for the pixel it was
//! taken in. Threads accumulate into disjoint [`FilmTile`]s that are combined
//! with Chan et al.'s (1979) pairwise update (see [`Film::merge_tile`]).
//! Statistics are kept in f64.

use std::fmt;

use glam::DVec3;

use crate::buffer::pixel_count;
use crate::{Image, Rgb};

/// Welford statistics of one pixel.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct PixelStats {
    n: u32,
    mean: DVec3,
    m2: DVec3,
}

impl PixelStats {
    /// Welford update: `δ = v − μ`, `μ += δ/n`, `M₂ += δ·(v − μ)`.
    fn push(&mut self, v: DVec3) {
        self.n += 1;
        let delta = v - self.mean;
        self.mean += delta / f64::from(self.n);
        self.m2 += delta * (v - self.mean);
    }

    /// Chan et al. merge: `n = nₐ + n_b`, `δ = μ_b − μₐ`, `μ = μₐ + δ·n_b/n`,
    /// `M₂ = M₂ₐ + M₂_b + δ²·nₐ·n_b/n`.
    fn merge(&mut self, other: &PixelStats) {
        if other.n == 0 {
            return;
        }
        if self.n == 0 {
            *self = *other;
            return;
        }
        let na = f64::from(self.n);
        let nb = f64::from(other.n);
        let n = na + nb;
        let delta = other.mean - self.mean;
        self.mean += delta * (nb / n);
        self.m2 += other.m2 + delta * delta * (na * nb / n);
        self.n = self.n.saturating_add(other.n);
    }

    /// Variance of the mean estimator, `s²/n = M₂ / ((n − 1) n)`; zero for n < 2.
    fn variance_of_mean(&self) -> DVec3 {
        if self.n < 2 {
            return DVec3::ZERO;
        }
        let n = f64::from(self.n);
        self.m2 / ((n - 1.0) * n)
    }
}

/// Per-pixel running mean and variance (Welford), for the final image and for variance estimates.
///
/// Non-finite samples (NaN or ±∞) are not accumulated; they are counted in
/// [`Film::rejected_samples`] so a caller can report them. Samples outside the
/// film are ignored.
#[derive(Clone)]
pub struct Film {
    width: u32,
    height: u32,
    stats: Vec<PixelStats>,
    rejected: u64,
}

impl fmt::Debug for Film {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Film")
            .field("width", &self.width)
            .field("height", &self.height)
            .field("total_samples", &self.total_samples())
            .field("rejected_samples", &self.rejected)
            .finish()
    }
}

impl Film {
    /// An empty film (no samples in any pixel).
    pub fn new(width: u32, height: u32) -> Self {
        Self {
            width,
            height,
            stats: vec![PixelStats::default(); pixel_count(width, height)],
            rejected: 0,
        }
    }

    /// Width in pixels.
    pub fn width(&self) -> u32 {
        self.width
    }

    /// Height in pixels.
    pub fn height(&self) -> u32 {
        self.height
    }

    /// Adds one radiance sample taken inside pixel (x, y) (1-pixel box filter).
    /// Out-of-range pixels are ignored; non-finite values are rejected and counted.
    pub fn add_sample(&mut self, x: u32, y: u32, value: Rgb) {
        if x >= self.width || y >= self.height {
            return;
        }
        if !value.is_finite() {
            self.rejected += 1;
            return;
        }
        let i = y as usize * self.width as usize + x as usize;
        self.stats[i].push(value.as_dvec3());
    }

    /// The per-pixel sample mean `μ` (black where a pixel has no samples).
    pub fn mean(&self) -> Image {
        self.to_image(|s| s.mean)
    }

    /// The variance of each pixel's mean estimator, `s²/n` with `s² = M₂/(n−1)`
    /// the unbiased sample variance (zero where a pixel has fewer than 2 samples).
    pub fn variance(&self) -> Image {
        self.to_image(PixelStats::variance_of_mean)
    }

    /// Number of accepted samples in pixel (x, y); 0 outside the film.
    pub fn sample_count(&self, x: u32, y: u32) -> u32 {
        if x >= self.width || y >= self.height {
            return 0;
        }
        self.stats[y as usize * self.width as usize + x as usize].n
    }

    /// Total number of accepted samples over all pixels.
    pub fn total_samples(&self) -> u64 {
        self.stats.iter().map(|s| u64::from(s.n)).sum()
    }

    /// Number of non-finite samples that were rejected (including those of merged tiles).
    pub fn rejected_samples(&self) -> u64 {
        self.rejected
    }

    /// Splits the film into empty tiles of at most `tile_size`² pixels, row-major,
    /// covering every pixel exactly once (`tile_size` 0 is treated as 1).
    pub fn tiles(&self, tile_size: u32) -> Vec<FilmTile> {
        let size = tile_size.max(1);
        let mut tiles = Vec::new();
        for y0 in (0..self.height).step_by(size as usize) {
            for x0 in (0..self.width).step_by(size as usize) {
                let w = size.min(self.width - x0);
                let h = size.min(self.height - y0);
                tiles.push(FilmTile::new(x0, y0, w, h));
            }
        }
        tiles
    }

    /// Merges the statistics of a tile into the film (Chan et al. pairwise
    /// update per pixel), so adding samples to tiles and merging them gives
    /// the same result as adding them directly, up to rounding. Parts of the
    /// tile outside the film are ignored.
    pub fn merge_tile(&mut self, tile: &FilmTile) {
        self.rejected += tile.rejected;
        for ty in 0..tile.height {
            let Some(y) = tile.y0.checked_add(ty).filter(|&y| y < self.height) else {
                break;
            };
            for tx in 0..tile.width {
                let Some(x) = tile.x0.checked_add(tx).filter(|&x| x < self.width) else {
                    break;
                };
                let ti = ty as usize * tile.width as usize + tx as usize;
                if let Some(s) = tile.stats.get(ti) {
                    self.stats[y as usize * self.width as usize + x as usize].merge(s);
                }
            }
        }
    }

    fn to_image(&self, f: impl Fn(&PixelStats) -> DVec3) -> Image {
        Image {
            width: self.width,
            height: self.height,
            pixels: self.stats.iter().map(|s| f(s).as_vec3()).collect(),
        }
    }
}

/// A rectangle of film statistics that one thread can fill independently;
/// combine it into the [`Film`] with [`Film::merge_tile`].
///
/// Coordinates are absolute film pixels: the tile covers
/// `x0..x0+width` × `y0..y0+height`.
#[derive(Clone)]
pub struct FilmTile {
    /// Left column (absolute).
    pub x0: u32,
    /// Top row (absolute).
    pub y0: u32,
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    stats: Vec<PixelStats>,
    rejected: u64,
}

impl fmt::Debug for FilmTile {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("FilmTile")
            .field("x0", &self.x0)
            .field("y0", &self.y0)
            .field("width", &self.width)
            .field("height", &self.height)
            .field("rejected_samples", &self.rejected)
            .finish()
    }
}

impl FilmTile {
    /// An empty tile covering `x0..x0+width` × `y0..y0+height`.
    pub fn new(x0: u32, y0: u32, width: u32, height: u32) -> Self {
        Self {
            x0,
            y0,
            width,
            height,
            stats: vec![PixelStats::default(); pixel_count(width, height)],
            rejected: 0,
        }
    }

    /// Adds a sample for absolute pixel (x, y). Pixels outside the tile are
    /// ignored; non-finite values are rejected and counted.
    pub fn add_sample(&mut self, x: u32, y: u32, value: Rgb) {
        let (Some(tx), Some(ty)) = (x.checked_sub(self.x0), y.checked_sub(self.y0)) else {
            return;
        };
        if tx >= self.width || ty >= self.height {
            return;
        }
        if !value.is_finite() {
            self.rejected += 1;
            return;
        }
        let i = ty as usize * self.width as usize + tx as usize;
        if let Some(s) = self.stats.get_mut(i) {
            s.push(value.as_dvec3());
        }
    }

    /// Number of accepted samples in absolute pixel (x, y); 0 outside the tile.
    pub fn sample_count(&self, x: u32, y: u32) -> u32 {
        let (Some(tx), Some(ty)) = (x.checked_sub(self.x0), y.checked_sub(self.y0)) else {
            return 0;
        };
        if tx >= self.width || ty >= self.height {
            return 0;
        }
        self.stats
            .get(ty as usize * self.width as usize + tx as usize)
            .map_or(0, |s| s.n)
    }

    /// `true` when `(x, y)` (absolute) lies inside the tile.
    pub fn contains(&self, x: u32, y: u32) -> bool {
        x >= self.x0 && y >= self.y0 && (x - self.x0) < self.width && (y - self.y0) < self.height
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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
            assert_eq!(tiles.iter().map(|t| t.width * t.height).sum::<u32>(), w * h);
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
            for t in &tiles {
                tiled.merge_tile(t);
            }
        }
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
        assert_eq!(tile.sample_count(3, 3), 1);
        let mut film = Film::new(3, 3); // tile partly outside the film
        film.merge_tile(&tile);
        assert_eq!(film.total_samples(), 0);
        tile.add_sample(2, 2, Rgb::splat(2.0));
        film.merge_tile(&tile);
        assert_eq!(film.mean().get(2, 2), Rgb::splat(2.0));
        assert_eq!(film.total_samples(), 1);
    }
}
