//! Helpers shared by the integration tests.
#![allow(dead_code)]

use penumbra_image::{Image, Rgb};

/// Deterministic xorshift64* generator.
pub struct Rng(u64);

impl Rng {
    pub fn new(seed: u64) -> Self {
        Self(seed.max(1))
    }

    /// Uniform in [0, 1).
    pub fn uniform(&mut self) -> f32 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        let v = self.0.wrapping_mul(0x2545_f491_4f6c_dd1d);
        (v >> 40) as f32 / (1u64 << 24) as f32
    }

    /// Standard normal (Box–Muller).
    pub fn normal(&mut self) -> f32 {
        let u1 = self.uniform().max(1e-7);
        let u2 = self.uniform();
        (-2.0 * u1.ln()).sqrt() * (std::f32::consts::TAU * u2).cos()
    }
}

/// `r · (1 + σ n)` per channel with independent standard normal n.
pub fn add_relative_noise(r: &Image, sigma: f32, seed: u64) -> Image {
    let mut rng = Rng::new(seed);
    Image {
        width: r.width,
        height: r.height,
        pixels: r
            .pixels
            .iter()
            .map(|p| {
                let n = Rgb::new(rng.normal(), rng.normal(), rng.normal());
                (*p * (Rgb::ONE + sigma * n)).max(Rgb::ZERO)
            })
            .collect(),
    }
}

/// A smooth HDR test scene: gradient background, a bright square, a dark corner.
pub fn synthetic_scene(w: u32, h: u32) -> Image {
    Image::from_fn(w, h, |x, y| {
        let u = x as f32 / w as f32;
        let v = y as f32 / h as f32;
        let mut c = Rgb::new(0.2 + 0.6 * u, 0.3 + 0.4 * v, 0.5 * (1.0 - u));
        if (w / 4..w / 2).contains(&x) && (h / 4..h / 2).contains(&y) {
            c = Rgb::new(8.0, 7.0, 6.0);
        }
        if x < w / 8 && y > h - h / 8 {
            c *= 0.01;
        }
        c
    })
}

/// Path to a file under `/work/shared/reference`, relative to this crate.
pub fn reference_path(rel: &str) -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../../shared/reference")
        .join(rel)
}
