//! Irradiance environment maps by nine spherical-harmonic coefficients per
//! channel (Ramamoorthi & Hanrahan 2001, "An Efficient Representation for
//! Irradiance Environment Maps").
//!
//! The environment radiance is projected onto the real spherical harmonics
//! of order l ≤ 2, `L_lm = ∫ L(ω) Y_lm(ω) dω`, and the irradiance on a
//! surface of unit normal n is their convolution with the clamped cosine:
//!
//! `E(n) = Σ_{l ≤ 2, |m| ≤ l} Â_l L_lm Y_lm(n)`, `Â0 = π`, `Â1 = 2π/3`,
//! `Â2 = π/4` (R&H 2001, eqs. 7–9). The clamped cosine's higher bands are
//! small (Â3 = 0, Â4 = −π/24): for the clamped-cosine environment
//! `L(ω) = max(0, ω·a)` the truncation error is at most 0.0164 (0.8 % of
//! the peak irradiance 2π/3), at n = ±a.
//!
//! Directions are world directions (x, y, z), +y up. R&H write the basis
//! with z up; it is used here as written, in the world's x, y, z, which is
//! as good as any frame since the projection and the evaluation share it.
//! Units: `L_lm` in W/(sr·m²)·sr, E in W/m².

use super::{Environment, EnvironmentMap};
use crate::Rgb;
use glam::{DVec3, Vec3};
use std::f64::consts::PI;

/// Clamped-cosine convolution constants Â_l of bands 0, 1, 2 (R&H 2001).
pub const SH_COSINE_BANDS: [f32; 3] = [
    std::f32::consts::PI,
    2.0 * std::f32::consts::PI / 3.0,
    std::f32::consts::FRAC_PI_4,
];

/// Band l of the coefficient with index i (0; 1–3; 4–8).
pub const SH_BAND: [usize; 9] = [0, 1, 1, 1, 2, 2, 2, 2, 2];

/// The nine real spherical harmonics of order ≤ 2 at unit `d`, in the order
/// `Y00, Y1−1 (y), Y10 (z), Y11 (x), Y2−2 (xy), Y2−1 (yz), Y20 (3z²−1),
/// Y21 (xz), Y22 (x²−y²)`, with R&H 2001's normalisations
/// 0.282095, 0.488603, 1.092548, 0.315392, 0.546274.
#[inline]
pub fn sh9_basis(d: Vec3) -> [f32; 9] {
    let (x, y, z) = (d.x, d.y, d.z);
    [
        0.282_094_8,
        0.488_602_5 * y,
        0.488_602_5 * z,
        0.488_602_5 * x,
        1.092_548_4 * x * y,
        1.092_548_4 * y * z,
        0.315_391_57 * (3.0 * z * z - 1.0),
        1.092_548_4 * x * z,
        0.546_274_2 * (x * x - y * y),
    ]
}

/// Integrals over a band of polar angle [θ0, θ1] of the functions of
/// c = cos θ the basis needs (dω = dc dφ).
struct Polar {
    /// ∫ dc, ∫ c dc, ∫ s dc, ∫ c s dc, ∫ s² dc, ∫ c² dc, s = sin θ = √(1 − c²).
    one: f64,
    c: f64,
    s: f64,
    cs: f64,
    ss: f64,
    cc: f64,
}

impl Polar {
    fn new(theta0: f64, theta1: f64) -> Self {
        let (c0, c1) = (theta0.cos(), theta1.cos());
        // Antiderivatives in c; the band runs from c1 (below) to c0.
        let s_int = |c: f64| 0.5 * (c * (1.0 - c * c).max(0.0).sqrt() + c.clamp(-1.0, 1.0).asin());
        let cs_int = |c: f64| -(1.0 - c * c).max(0.0).powf(1.5) / 3.0;
        Self {
            one: c0 - c1,
            c: 0.5 * (c0 * c0 - c1 * c1),
            s: s_int(c0) - s_int(c1),
            cs: cs_int(c0) - cs_int(c1),
            ss: (c0 - c0.powi(3) / 3.0) - (c1 - c1.powi(3) / 3.0),
            cc: (c0.powi(3) - c1.powi(3)) / 3.0,
        }
    }
}

/// Integrals over an azimuth interval [a, b] of 1, sin, cos, sin², cos²,
/// sin·cos.
struct Azimuth {
    one: f64,
    s: f64,
    c: f64,
    ss: f64,
    cc: f64,
    sc: f64,
}

impl Azimuth {
    fn new(a: f64, b: f64) -> Self {
        let d2 = ((2.0 * b).sin() - (2.0 * a).sin()) / 4.0;
        Self {
            one: b - a,
            s: a.cos() - b.cos(),
            c: b.sin() - a.sin(),
            ss: 0.5 * (b - a) - d2,
            cc: 0.5 * (b - a) + d2,
            sc: 0.5 * (b.sin().powi(2) - a.sin().powi(2)),
        }
    }
}

/// `∫ Y_lm dω` over the texel θ ∈ [θ0, θ1], world azimuth φ ∈ [a, b], for
/// directions d = (sin θ sin φ, cos θ, −sin θ cos φ), in the order of
/// [`sh9_basis`], exactly (the basis is polynomial in c = cos θ, sin θ,
/// sin φ and cos φ).
fn texel_integrals(p: &Polar, a: &Azimuth) -> [f64; 9] {
    // √(1/4π), √(3/4π), √(15/4π), √(5/16π), √(15/16π).
    let c0 = (1.0 / (4.0 * PI)).sqrt();
    let c1 = (3.0 / (4.0 * PI)).sqrt();
    let c2 = (15.0 / (4.0 * PI)).sqrt();
    let c3 = (5.0 / (16.0 * PI)).sqrt();
    let c4 = (15.0 / (16.0 * PI)).sqrt();
    // x = s·sin φ, y = c, z = −s·cos φ.
    let x = p.s * a.s;
    let y = p.c * a.one;
    let z = -p.s * a.c;
    let xy = p.cs * a.s;
    let yz = -p.cs * a.c;
    let zz = p.ss * a.cc;
    let xz = -p.ss * a.sc;
    let xx = p.ss * a.ss;
    let yy = p.cc * a.one;
    let one = p.one * a.one;
    [
        c0 * one,
        c1 * y,
        c1 * z,
        c1 * x,
        c2 * xy,
        c2 * yz,
        c3 * (3.0 * zz - one),
        c2 * xz,
        c4 * (xx - yy),
    ]
}

/// Nine SH coefficients per channel of an environment's radiance,
/// `L_lm = ∫ L(ω) Y_lm(ω) dω` (order as [`sh9_basis`]).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Sh9 {
    pub coefficients: [Rgb; 9],
}

impl Sh9 {
    /// Projection of an environment: exact for a constant one
    /// (`L00 = √(4π) L`, the rest 0); for a map see [`Sh9::from_map`].
    pub fn from_environment(env: &Environment) -> Self {
        match env {
            Environment::Constant(l) => {
                let mut coefficients = [Rgb::ZERO; 9];
                coefficients[0] = *l * (4.0 * PI).sqrt() as f32;
                Self { coefficients }
            }
            Environment::Map(m) => Self::from_map(m),
        }
    }

    /// Projection of a lat-long map's piecewise-constant radiance (as
    /// [`EnvironmentMap::eval`] returns it), texel by texel:
    /// `L_lm = Σ_texels L_t ∫_texel Y_lm dω`, each basis function integrated
    /// exactly over the texel ([`texel_integrals`]); so every texel counts
    /// with its exact solid angle `(2π/W)(cos θ0 − cos θ1)` and a constant
    /// map projects to exactly √(4π) L in band 0 and nothing else. The
    /// map's rotation turns texel columns' azimuths. Sums in f64.
    pub fn from_map(map: &EnvironmentMap) -> Self {
        let (w, h) = (map.width(), map.height());
        let texels = map.texels();
        // R_y(α) turns map azimuth φ into world azimuth φ − α (module doc of
        // environment.rs: d = (sin θ sin φ, cos θ, −sin θ cos φ)).
        let x = map.rotation().as_dquat() * DVec3::X;
        let alpha = (-x.z).atan2(x.x);
        let columns: Vec<Azimuth> = (0..w)
            .map(|i| {
                let phi = |i: usize| 2.0 * PI * (i as f64 / w as f64 - 0.5) - alpha;
                Azimuth::new(phi(i), phi(i + 1))
            })
            .collect();
        let mut sums = [DVec3::ZERO; 9];
        for y in 0..h {
            let polar = Polar::new(PI * y as f64 / h as f64, PI * (y + 1) as f64 / h as f64);
            for (x, a) in columns.iter().enumerate() {
                let l = texels[y * w + x].as_dvec3();
                if l == DVec3::ZERO {
                    continue;
                }
                for (s, b) in sums.iter_mut().zip(texel_integrals(&polar, a)) {
                    *s += l * b;
                }
            }
        }
        Self {
            coefficients: sums.map(|s| s.as_vec3()),
        }
    }

    /// Irradiance on a surface of unit normal `n` from the whole sphere
    /// (unoccluded): `E(n) = Σ Â_l L_lm Y_lm(n)` (R&H 2001, eq. 7), clamped
    /// at 0 against ringing. W/m².
    pub fn irradiance(&self, n: Vec3) -> Rgb {
        let y = sh9_basis(n);
        let mut e = Rgb::ZERO;
        for i in 0..9 {
            e += self.coefficients[i] * (SH_COSINE_BANDS[SH_BAND[i]] * y[i]);
        }
        e.max(Rgb::ZERO)
    }

    /// The radiance the projection represents, `Σ L_lm Y_lm(d)` (a smooth
    /// band-limited approximation of L; for tests and plots).
    pub fn radiance(&self, d: Vec3) -> Rgb {
        let y = sh9_basis(d);
        (0..9).map(|i| self.coefficients[i] * y[i]).sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::square_to_uniform_sphere;

    fn directions(n: usize) -> impl Iterator<Item = Vec3> {
        (0..n).map(move |i| {
            let u = [
                (i as f32 + 0.5) / n as f32,
                ((i as u64 * 2_654_435_769) % 1_000_003) as f32 / 1_000_003.0,
            ];
            square_to_uniform_sphere(u)
        })
    }

    /// A lat-long map (texel centres) of `f`, rotated by `rotation` about +y.
    fn map_of(w: usize, h: usize, rotation: f32, f: impl Fn(Vec3) -> Rgb) -> EnvironmentMap {
        let probe = EnvironmentMap::new(w, h, vec![Rgb::ONE; w * h], Rgb::ONE, rotation);
        let mut texels = Vec::with_capacity(w * h);
        for y in 0..h {
            for x in 0..w {
                let uv = glam::Vec2::new((x as f32 + 0.5) / w as f32, (y as f32 + 0.5) / h as f32);
                texels.push(f(probe.uv_to_direction(uv)));
            }
        }
        EnvironmentMap::new(w, h, texels, Rgb::ONE, rotation)
    }

    #[test]
    fn constant_environment_gives_pi_l_exactly() {
        let l = Rgb::new(0.25, 1.0, 3.5);
        let sh = Sh9::from_environment(&Environment::Constant(l));
        for n in directions(200) {
            let e = sh.irradiance(n);
            let want = l * std::f32::consts::PI;
            assert!(
                ((e - want) / want).abs().max_element() < 1e-5,
                "n {n}: {e} vs {want}"
            );
            // Band 0 alone: L00 Y00 = √(4π) L / √(4π) = L.
            let r = sh.radiance(n);
            assert!(((r - l) / l).abs().max_element() < 1e-5, "{r} vs {l}");
        }
        // A constant map projects to the same (the texel integrals are exact).
        let map = map_of(64, 32, 0.3, |_| l);
        let sh = Sh9::from_map(&map);
        for n in directions(50) {
            let e = sh.irradiance(n);
            let want = l * std::f32::consts::PI;
            assert!(
                ((e - want) / want).abs().max_element() < 1e-5,
                "{e} vs {want}"
            );
        }
    }

    #[test]
    fn basis_functions_project_to_their_coefficient() {
        // Texels are clamped at 0, so each basis function rides on a
        // constant: f = 1 + ½ Y_i, whose coefficients are √(4π) at 00 and
        // ½ at i (orthonormality); the rotation must not matter for Y00 and
        // is applied to the others through the world directions.
        for i in 0..9 {
            let map = map_of(512, 256, 0.0, |d| Rgb::splat(1.0 + 0.5 * sh9_basis(d)[i]));
            let c = Sh9::from_map(&map).coefficients;
            for (j, cj) in c.iter().enumerate() {
                let want = 0.5 * (i == j) as u32 as f32
                    + if j == 0 {
                        (4.0 * std::f32::consts::PI).sqrt()
                    } else {
                        0.0
                    };
                assert!(
                    (cj.x - want).abs() < 2e-3,
                    "basis {i}: coefficient {j} = {} (want {want})",
                    cj.x
                );
            }
        }
    }

    #[test]
    fn rotation_of_the_map_rotates_the_irradiance() {
        // A lobe towards +x in map space, the map turned 90° about +y: the
        // lobe points along R_y(90°)(+x) = −z in the world.
        let lobe = |d: Vec3| Rgb::splat(d.x.max(0.0));
        let turned = map_of(256, 128, std::f32::consts::FRAC_PI_2, |d| {
            // d is a world direction; the map value is the lobe of the map
            // direction R_y(−90°) d.
            lobe(glam::Quat::from_rotation_y(-std::f32::consts::FRAC_PI_2) * d)
        });
        let sh = Sh9::from_map(&turned);
        let towards = sh.irradiance(-Vec3::Z).x;
        let away = sh.irradiance(Vec3::Z).x;
        assert!(towards > 2.0 && away < 0.1, "{towards} {away}");
    }

    /// Closed form: the environment `L(ω) = max(0, ω·a)` gives, on a normal
    /// at angle γ from a, `E(γ) = ∫ max(0, ω·a) max(0, ω·n) dω =
    /// (2/3)((π − γ) cos γ + sin γ)` (the overlap of two clamped cosines; 2π/3
    /// at γ = 0, 2/3 at γ = π/2, 0 at γ = π). SH9 truncates it by at most
    /// 0.0164 (see the module doc); the map's discretisation adds little.
    #[test]
    fn clamped_cosine_environment_matches_its_closed_form() {
        let a = Vec3::new(0.3, 0.8, -0.52).normalize();
        let map = map_of(512, 256, 0.7, |d| Rgb::splat(d.dot(a).max(0.0)));
        let sh = Sh9::from_map(&map);
        let mut worst = 0.0f32;
        for n in directions(500) {
            let g = n.dot(a).clamp(-1.0, 1.0).acos();
            let want = (2.0 / 3.0) * ((std::f32::consts::PI - g) * g.cos() + g.sin());
            let e = sh.irradiance(n);
            worst = worst.max((e.x - want).abs());
            assert!(
                (e.x - want).abs() < 0.02,
                "γ = {g}: SH9 {} vs closed form {want}",
                e.x
            );
        }
        // The truncation is visible (the test is not vacuous).
        assert!(worst > 5e-3, "worst {worst}");
    }
}
