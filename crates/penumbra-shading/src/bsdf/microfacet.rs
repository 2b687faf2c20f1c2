//! GGX / Trowbridge–Reitz microfacet distribution with Smith
//! masking–shadowing and visible-normal sampling.
//!
//! Isotropic, in the local shading frame (z = macro normal). Formulas:
//! - D(m) = α² / (π cos⁴θm (α² + tan²θm)²) (Walter et al. 2007, eq. 33),
//!   evaluated as `1 / (π α² (cos²θm + sin²θm/α²)²)`, which stays finite at
//!   grazing m and for tiny α;
//! - Λ(ω) = (√(1 + α² tan²θ) − 1) / 2, G1 = 1 / (1 + Λ) (Smith; Heitz 2014,
//!   "Understanding the Masking-Shadowing Function", eqs. 72 and 43);
//! - height-correlated G2(ωo, ωi) = 1 / (1 + Λ(ωo) + Λ(ωi)) (Heitz 2014,
//!   eq. 99), used for reflection and, as in pbrt-v4, for transmission;
//! - visible normals D_ωo(m) = G1(ωo) max(0, ωo·m) D(m) / cos θo (Heitz 2014,
//!   eq. 38), sampled exactly with the spherical caps of Dupuy & Benyoub 2023
//!   ("Sampling Visible GGX Normals with Spherical Caps").

use glam::Vec3;
use std::f32::consts::PI;

/// Smallest α a [`Ggx`] uses. Below it the peak of D, 1/(πα²) ≥ 3·10⁷, and
/// the half vectors of nearly mirror directions lose their f32 precision
/// relative to α; a lobe this narrow (≈ 0.01° wide) renders like a mirror.
pub const MIN_ALPHA: f32 = 1e-4;

/// The isotropic GGX (Trowbridge–Reitz) distribution of microfacet normals.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ggx {
    alpha: f32,
}

impl Ggx {
    /// GGX with roughness α, clamped to at least [`MIN_ALPHA`] (NaN → minimum).
    pub fn new(alpha: f32) -> Self {
        let alpha = if alpha.is_nan() {
            MIN_ALPHA
        } else {
            alpha.max(MIN_ALPHA)
        };
        Self { alpha }
    }

    /// From perceptual roughness r (glTF, Disney): α = r².
    pub fn from_roughness(roughness: f32) -> Self {
        Self::new(roughness * roughness)
    }

    /// The (clamped) α.
    pub fn alpha(&self) -> f32 {
        self.alpha
    }

    /// D(m) [1/sr] for a unit microfacet normal m; 0 below the surface.
    /// Normalised so that ∫ D(m) cos θm dωm = 1.
    #[inline]
    pub fn d(&self, m: Vec3) -> f32 {
        if m.z <= 0.0 {
            return 0.0;
        }
        let a2 = self.alpha * self.alpha;
        let sin2 = m.x * m.x + m.y * m.y;
        let t = m.z * m.z + sin2 / a2;
        1.0 / (PI * a2 * t * t)
    }

    /// Smith's Λ(ω) = (√(1 + α² tan²θ) − 1) / 2 (∞ at θ = 90°).
    #[inline]
    pub fn lambda(&self, w: Vec3) -> f32 {
        let cos2 = w.z * w.z;
        if cos2 == 0.0 {
            return f32::INFINITY;
        }
        let a2_tan2 = self.alpha * self.alpha * (w.x * w.x + w.y * w.y) / cos2;
        // (√(1+x) − 1)/2 = x / (2(√(1+x) + 1)), no cancellation for small x.
        a2_tan2 / (2.0 * ((1.0 + a2_tan2).sqrt() + 1.0))
    }

    /// Smith masking G1(ω) = 1 / (1 + Λ(ω)).
    #[inline]
    pub fn g1(&self, w: Vec3) -> f32 {
        1.0 / (1.0 + self.lambda(w))
    }

    /// Height-correlated masking–shadowing G2 = 1 / (1 + Λ(ωo) + Λ(ωi)).
    #[inline]
    pub fn g2(&self, wo: Vec3, wi: Vec3) -> f32 {
        1.0 / (1.0 + self.lambda(wo) + self.lambda(wi))
    }

    /// Density of visible normals D_ωo(m) = G1(ωo) max(0, ωo·m) D(m) / cos θo
    /// [1/sr, over m], for `wo.z > 0`.
    #[inline]
    pub fn pdf_visible(&self, wo: Vec3, m: Vec3) -> f32 {
        if wo.z <= 0.0 {
            return 0.0;
        }
        self.g1(wo) * wo.dot(m).max(0.0) * self.d(m) / wo.z
    }

    /// Samples m ~ D_ωo (Dupuy & Benyoub 2023): stretch ωo to the α = 1
    /// configuration, sample the spherical cap {c : c·z ≥ −ωh.z} uniformly,
    /// add ωh, and unstretch. Requires `wo.z > 0`.
    #[inline]
    pub fn sample_visible(&self, wo: Vec3, u: [f32; 2]) -> Vec3 {
        let a = self.alpha;
        let wh = Vec3::new(a * wo.x, a * wo.y, wo.z).normalize();
        let phi = 2.0 * PI * u[0];
        let z = (1.0 - u[1]) * (1.0 + wh.z) - wh.z;
        let s = (1.0 - z * z).max(0.0).sqrt();
        let (sp, cp) = phi.sin_cos();
        let h = Vec3::new(s * cp, s * sp, z) + wh;
        Vec3::new(a * h.x, a * h.y, h.z.max(1e-7)).normalize()
    }
}

/// Walter et al. 2007's generalised half vector of a transmission pair:
/// `wo` above the surface (outside, index 1), `wi` below (inside, relative
/// index `eta`): m ∝ ωo + η ωi, oriented to +z. `None` if degenerate or if
/// either direction sees the microfacet from the wrong side (ωo·m ≤ 0 or
/// ωi·m ≥ 0), where the microfacet cannot refract ωo into ωi.
#[inline]
pub(crate) fn transmission_half_vector(wo: Vec3, wi: Vec3, eta: f32) -> Option<Vec3> {
    let h = wo + eta * wi;
    let len = h.length();
    if len.is_nan() || len <= 1e-6 {
        return None;
    }
    let m = if h.z < 0.0 { -h / len } else { h / len };
    (m.z > 0.0 && wo.dot(m) > 0.0 && wi.dot(m) < 0.0).then_some(m)
}

/// Jacobian of refraction |dωm/dωi| = η² |ωi·m| / (ωo·m + η ωi·m)²
/// (Walter et al. 2007, eq. 17, with the outside index 1).
#[inline]
pub(crate) fn transmission_jacobian(wo: Vec3, wi: Vec3, m: Vec3, eta: f32) -> f32 {
    let denom = wo.dot(m) + eta * wi.dot(m);
    eta * eta * wi.dot(m).abs() / (denom * denom)
}

/// The transmission BTDF without Fresnel and colour, radiance form
/// (Walter et al. 2007, eq. 21, outside index 1, inside η):
/// `D(m) G2 |ωo·m| |ωi·m| / (|cos θo| |cos θi| (ωo·m + η ωi·m)²)`.
/// Light leaving the inside carries the factor (n_o/n_i)² = 1/η² relative to
/// the importance-symmetric form; generalised reciprocity reads
/// f(ωo, ωi) / n_o² = f(ωi, ωo) / n_i² with n the index on each side.
#[inline]
pub(crate) fn transmission_core(ggx: &Ggx, wo: Vec3, wi: Vec3, m: Vec3, eta: f32) -> f32 {
    let denom = wo.dot(m) + eta * wi.dot(m);
    ggx.d(m) * ggx.g2(wo, wi) * (wo.dot(m) * wi.dot(m)).abs()
        / ((wo.z * wi.z).abs() * denom * denom)
}

/// The reflection BRDF without Fresnel: `D(m) G2 / (4 cos θo cos θi)`,
/// m = normalize(ωo + ωi) (Walter et al. 2007, eq. 20).
#[inline]
pub(crate) fn reflection_core(ggx: &Ggx, wo: Vec3, wi: Vec3, m: Vec3) -> f32 {
    ggx.d(m) * ggx.g2(wo, wi) / (4.0 * wo.z * wi.z)
}

/// Half vector of a reflection pair, `None` when ωo + ωi vanishes.
#[inline]
pub(crate) fn reflection_half_vector(wo: Vec3, wi: Vec3) -> Option<Vec3> {
    let h = wo + wi;
    let len = h.length();
    (len > 1e-6).then(|| h / len)
}
