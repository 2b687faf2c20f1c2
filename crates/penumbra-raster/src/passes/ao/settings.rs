//! What a user chooses of screen-space ambient occlusion: the method, the
//! radius R (world units, the `ao` integrator's `--ao-distance`) and a
//! quality preset; and the CPU-side data the passes upload (the hemisphere
//! kernel, the 4×4 jitter tile).

use glam::Vec3;
use penumbra_shading::sampling::square_to_cosine_hemisphere;

/// How the raster engine estimates kA from the depth buffer.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum AoMethod {
    /// No screen-space AO (kA = 1, unless a bake gives it).
    #[default]
    None,
    /// The notes' hemisphere kernel, cosine-weighted (`hemisphere.wgsl`).
    Hemisphere,
    /// Ground-truth AO, horizon-based (`gtao.wgsl`).
    Gtao,
}

impl AoMethod {
    pub fn name(self) -> &'static str {
        match self {
            AoMethod::None => "none",
            AoMethod::Hemisphere => "hemisphere",
            AoMethod::Gtao => "gtao",
        }
    }
}

/// Sample counts of the AO passes.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum AoQuality {
    Low,
    #[default]
    Medium,
    High,
}

impl AoQuality {
    pub fn name(self) -> &'static str {
        match self {
            AoQuality::Low => "low",
            AoQuality::Medium => "medium",
            AoQuality::High => "high",
        }
    }

    /// Points of the hemisphere kernel: 8, 16, 32 (each pixel turns them by
    /// its tile angle, so the denoised result has seen 16× as many).
    pub fn hemisphere_samples(self) -> u32 {
        match self {
            AoQuality::Low => 8,
            AoQuality::Medium => 16,
            AoQuality::High => 32,
        }
    }

    /// GTAO (slices, steps per side of a slice): (2, 4), (3, 6), (4, 8);
    /// XeGTAO's "High" is (3, 3). Low had 3 steps: Cornell box MAE 0.062
    /// against 0.051 with 4 (docs/raster.md).
    pub fn gtao_slices_steps(self) -> (u32, u32) {
        match self {
            AoQuality::Low => (2, 4),
            AoQuality::Medium => (3, 6),
            AoQuality::High => (4, 8),
        }
    }
}

/// Screen-space AO of a raster frame.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct AoSettings {
    pub method: AoMethod,
    /// R [world units]: occluders farther than R from the point do not
    /// occlude, as rays longer than `--ao-distance` in the `ao` integrator.
    /// `None`: [`DEFAULT_RADIUS_FRACTION`] of the scene's bounding radius.
    pub radius: Option<f32>,
    pub quality: AoQuality,
    /// GTAO's thin-occluder compensation c ≥ 0 (0: off, the height-field
    /// assumption): a horizon point q nearer the camera than p by t along
    /// the view vector fades out as if its distance were
    /// √(|q − p|² + ((1 + c)² − 1) t²). The depth buffer cannot tell a thin
    /// post from a wall: c > 0 removes the false occlusion behind thin
    /// objects and also fades true occluders that rise towards the camera
    /// (docs/raster.md gives the measured trade).
    pub thin_occluders: f32,
}

impl AoSettings {
    pub fn enabled(&self) -> bool {
        self.method != AoMethod::None
    }

    /// R for a scene with bounds `(lo, hi)`.
    pub fn radius_for(&self, bounds: (Vec3, Vec3)) -> f32 {
        self.radius.unwrap_or_else(|| default_radius(bounds))
    }
}

/// Default R as a fraction of the radius of the scene's bounding sphere.
pub const DEFAULT_RADIUS_FRACTION: f32 = 0.1;

/// Width of GTAO's falloff band as a fraction of R (centred on R).
pub const GTAO_FALLOFF: f32 = 0.2;

/// [`DEFAULT_RADIUS_FRACTION`] × the bounding-sphere radius of `bounds`.
pub fn default_radius(bounds: (Vec3, Vec3)) -> f32 {
    let (lo, hi) = bounds;
    (DEFAULT_RADIUS_FRACTION * 0.5 * (hi - lo).length()).max(1e-6)
}

/// The hemisphere kernel: `n` points on the hemisphere of radius R about
/// +z, directions cosine-distributed (Malley's method on a Hammersley set:
/// the i-th direction from the cell centres ((i + ½)/n, radical inverse of
/// i + ½/n)), so the fraction of open points estimates the cosine-weighted
/// kA; w is padding (0): every point sits at distance R. A point
/// at distance r that lies behind a surface the depth buffer sees means the
/// ray towards it was blocked before r, so the point at R finds every
/// occluder within R that a nearer point finds, and more (measured on the
/// Cornell box at R = 100: MAE 0.052 against 0.062 with lengths spread over
/// [R/2, R]).
pub fn hemisphere_kernel(n: u32) -> Vec<[f32; 4]> {
    (0..n)
        .map(|i| {
            // Both coordinates at cell centres (a point on the square's edge
            // would map to the rim, z = 0).
            let u = [
                (i as f32 + 0.5) / n as f32,
                (radical_inverse(2, i) + 0.5 / n as f32).fract(),
            ];
            let d = square_to_cosine_hemisphere(u);
            [d.x, d.y, d.z, 0.0]
        })
        .collect()
}

fn radical_inverse(base: u32, mut i: u32) -> f32 {
    let mut inv = 1.0 / base as f64;
    let mut out = 0.0f64;
    let scale = inv;
    while i > 0 {
        out += (i % base) as f64 * inv;
        i /= base;
        inv *= scale;
    }
    out as f32
}

/// 4×4 Bayer matrix: each value 0..15 once, neighbours far apart.
const BAYER4: [u32; 16] = [0, 8, 2, 10, 12, 4, 14, 6, 3, 11, 1, 9, 15, 7, 13, 5];

/// The 4×4 jitter tile, row-major: x = (Bayer(k) + ½)/16 (the kernel's
/// rotation / the GTAO slice offset), y = the same matrix transposed and
/// shifted by 5 (the GTAO step offset), so each takes every sixteenth once
/// within a tile and the two are not aligned.
pub fn jitter_tile() -> [[f32; 4]; 16] {
    let mut tile = [[0.0; 4]; 16];
    for (k, t) in tile.iter_mut().enumerate() {
        let (x, y) = (k % 4, k / 4);
        let a = BAYER4[k];
        let b = (BAYER4[x * 4 + y] + 5) % 16;
        *t = [(a as f32 + 0.5) / 16.0, (b as f32 + 0.5) / 16.0, 0.0, 0.0];
    }
    tile
}

/// Rust twin of WGSL `gtao_slice_visibility` (slice.wgsl): the
/// cosine-weighted visibility of one slice (Jimenez et al. 2016, eq. 10)
/// with projected-normal angle `n` and horizons `h0 ≤ 0 ≤ h1`, all measured
/// from the view vector in the slice plane:
/// `â = ¼(−cos(2h0 − n) + cos n + 2h0 sin n) + ¼(−cos(2h1 − n) + cos n + 2h1 sin n)`.
pub fn gtao_slice_visibility(n: f32, h0: f32, h1: f32) -> f32 {
    let (sn, cn) = n.sin_cos();
    let a0 = -(2.0 * h0 - n).cos() + cn + 2.0 * h0 * sn;
    let a1 = -(2.0 * h1 - n).cos() + cn + 2.0 * h1 * sn;
    0.25 * (a0 + a1)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    #[test]
    fn kernel_directions_are_cosine_distributed() {
        // Under p(ω) = cos θ / π: E[cos θ] = 2/3, E[cos² θ] = 1/2, E[x] = E[y] = 0.
        let k = hemisphere_kernel(256);
        let n = k.len() as f64;
        let mean = |f: &dyn Fn(&[f32; 4]) -> f64| k.iter().map(f).sum::<f64>() / n;
        let m1 = mean(&|p| p[2] as f64);
        // (z = √(1 − r²) is steep at the rim: 256 points integrate it to ~3e-3.)
        assert!((m1 - 2.0 / 3.0).abs() < 5e-3, "E[cos] {m1}");
        assert!((mean(&|p| (p[2] * p[2]) as f64) - 0.5).abs() < 5e-3);
        assert!(mean(&|p| p[0] as f64).abs() < 1e-2);
        assert!(mean(&|p| p[1] as f64).abs() < 1e-2);
        for p in &k {
            let len = (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt();
            assert!((len - 1.0).abs() < 1e-5 && p[2] > 0.0);
            assert_eq!(p[3], 0.0);
        }
    }

    #[test]
    fn the_tile_takes_every_sixteenth_once() {
        let t = jitter_tile();
        for c in 0..2 {
            let mut v: Vec<u32> = t
                .iter()
                .map(|e| (e[c] * 16.0 - 0.5).round() as u32)
                .collect();
            v.sort();
            assert_eq!(v, (0..16).collect::<Vec<_>>());
        }
    }

    /// kA of a normal at angle `tilt` from the view vector v = +z, with the
    /// horizons of every slice at ±`horizon` from v (clamped to the
    /// hemisphere), by GTAO's slice average (slices over φ ∈ [0, π)).
    fn gtao_estimate(tilt: f64, horizon: f64, slices: usize) -> f64 {
        let nrm = [tilt.sin(), 0.0, tilt.cos()];
        let mut sum = 0.0;
        for i in 0..slices {
            let phi = PI * (i as f64 + 0.5) / slices as f64;
            let dir = [phi.cos(), phi.sin(), 0.0];
            // axis = dir × v (v = z): (dir.y, −dir.x, 0)
            let axis = [dir[1], -dir[0], 0.0];
            let d = nrm[0] * axis[0] + nrm[1] * axis[1];
            let pn = [nrm[0] - axis[0] * d, nrm[1] - axis[1] * d, nrm[2]];
            let len = (pn[0] * pn[0] + pn[1] * pn[1] + pn[2] * pn[2]).sqrt();
            let n =
                (pn[0] * dir[0] + pn[1] * dir[1]).signum() * (pn[2] / len).clamp(-1.0, 1.0).acos();
            let h1 = n + (horizon - n).min(PI / 2.0);
            let h0 = n + (-horizon - n).max(-PI / 2.0);
            sum += len * gtao_slice_visibility(n as f32, h0 as f32, h1 as f32) as f64;
        }
        sum / slices as f64
    }

    /// The same kA by brute force: (1/π) ∫ v(ω) cos θ_n dω over a fine grid
    /// of the sphere, ω visible when it is above the surface and within
    /// `horizon` of the view vector (+z).
    fn brute_force(tilt: f64, horizon: f64) -> f64 {
        let nrm = [tilt.sin(), 0.0, tilt.cos()];
        let (nt, np) = (800, 1600);
        let mut sum = 0.0;
        for i in 0..nt {
            let theta = PI * (i as f64 + 0.5) / nt as f64;
            for j in 0..np {
                let phi = 2.0 * PI * (j as f64 + 0.5) / np as f64;
                let w = [
                    theta.sin() * phi.cos(),
                    theta.sin() * phi.sin(),
                    theta.cos(),
                ];
                let c = w[0] * nrm[0] + w[1] * nrm[1] + w[2] * nrm[2];
                if c > 0.0 && theta <= horizon {
                    sum += c * theta.sin();
                }
            }
        }
        sum * (PI / nt as f64) * (2.0 * PI / np as f64) / PI
    }

    #[test]
    fn slice_integral_averages_to_the_cosine_weighted_visibility() {
        // Unoccluded (horizons at the tangent plane): kA = 1 for any normal.
        for tilt in [0.0, 0.4, 0.9, 1.3] {
            let k = gtao_estimate(tilt, PI, 512);
            assert!((k - 1.0).abs() < 2e-3, "tilt {tilt}: {k}");
        }
        // A cone of visibility about v: against a brute-force integral.
        for (tilt, horizon) in [(0.0, 1.0), (0.5, 1.0), (0.8, 0.6), (0.3, 1.4)] {
            let g = gtao_estimate(tilt, horizon, 512);
            let b = brute_force(tilt, horizon);
            assert!(
                (g - b).abs() < 3e-3,
                "tilt {tilt} horizon {horizon}: {g} vs {b}"
            );
        }
        // Normal facing the viewer, horizons at h: 1 − cos² h... closed
        // form: (1/π)∫ cos θ over the cone of half-angle h = sin² h.
        let h = 0.7f64;
        assert!((gtao_estimate(0.0, h, 64) - h.sin().powi(2)).abs() < 1e-4);
    }
}
