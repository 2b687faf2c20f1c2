//! The Phong–Blinn family of the notes (SEEDS.md, BRDF): a Lambertian part
//! `kd` plus a specular lobe around the halfway vector, in four variants.
//!
//! `f(wo, wi) = kd + ks · s(wo, wi)` with `h = normalize(wi + wo)`,
//! `cos δ = h.z`, γ = shininess and `s` one of the [`PhongVariant`] lobes.
//! `wi` is the light direction l, `wo` the view direction v. Reflection only.
//!
//! Sampling: the diffuse lobe by the cosine-weighted hemisphere, the specular
//! lobe by drawing `h` with `pdf_h = (γ+1)/(2π) cos^γ δ` and reflecting `wo`
//! about it (`pdf = pdf_h / (4 wo·h)`); the lobe is chosen with the
//! probability of its share of [`PhongBlinn::albedo`] (see
//! [`PhongBlinn::specular_probability`]).

use super::optics::reflect;
use super::{BsdfFlags, BsdfSample, SpecularSet};
use crate::Rgb;
use crate::sampling::{cosine_hemisphere_pdf, square_to_cosine_hemisphere};
use glam::Vec3;
use std::f32::consts::{FRAC_1_PI, PI};

/// Which Phong–Blinn specular lobe (h = normalize(l + v), cos δ = n·h, γ = shininess).
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum PhongVariant {
    /// The notes exactly: `fr = ks (cos⁺δ)^γ / cos⁺θin` (not reciprocal).
    Notes,
    /// Reciprocal max-Blinn: `fr = ks (cos δ)^γ / max(cos θ, cos θ')`.
    MaxBlinn,
    /// Reciprocal `fr = ks (cos δ)^γ / |l + v|²` (notes 003).
    HalfwaySquared,
    /// Energy-conserving normalised Blinn–Phong: `fr = ks (γ + 8)/(8π) (cos δ)^γ`.
    Normalized,
}

impl PhongVariant {
    /// All four variants, for tests and tools.
    pub const ALL: [PhongVariant; 4] = [
        PhongVariant::Notes,
        PhongVariant::MaxBlinn,
        PhongVariant::HalfwaySquared,
        PhongVariant::Normalized,
    ];

    /// Whether `s(wo, wi) = s(wi, wo)` (Helmholtz reciprocity).
    pub fn is_reciprocal(self) -> bool {
        self != PhongVariant::Notes
    }

    /// The specular lobe per unit `ks`, `s(wo, wi)` [1/sr], for `wo`, `wi`
    /// unit and both above the surface.
    #[inline]
    fn lobe(self, wo: Vec3, wi: Vec3, shininess: f32) -> f32 {
        let sum = wi + wo;
        let len2 = sum.length_squared();
        if len2 <= 0.0 {
            return 0.0;
        }
        // cos δ = n·h = (wi + wo).z / |wi + wo|
        let cos_delta = (sum.z / len2.sqrt()).clamp(0.0, 1.0);
        let d = cos_delta.powf(shininess);
        match self {
            PhongVariant::Notes => d / wi.z,
            PhongVariant::MaxBlinn => d / wo.z.max(wi.z),
            PhongVariant::HalfwaySquared => d / len2,
            PhongVariant::Normalized => d * (shininess + 8.0) / (8.0 * PI),
        }
    }

    /// Directional albedo ∫ s(z, wi) cos θi dωi of the lobe per unit `ks` at
    /// normal incidence (wo = n), in closed form. With wo = n, θh = θi/2;
    /// substituting c = cos(θi/2) ∈ [s, 1], s = 1/√2, and
    /// `I(k) = ∫_s^1 c^k dc`:
    /// - Notes: `∫ cos^γ(θi/2) dωi = 8π I(γ+1)`;
    /// - MaxBlinn (max = 1): `A(γ) = ∫ cos^γ(θi/2) cos θi dωi = 8π (2 I(γ+3) − I(γ+1))`;
    /// - HalfwaySquared (`|n + wi|² = 4 cos²(θi/2)`): `A(γ − 2) / 4`;
    /// - Normalized: `(γ+8)/(8π) A(γ)`.
    pub fn normal_incidence_albedo(self, shininess: f32) -> f32 {
        let g = shininess.max(0.0) as f64;
        let s = std::f64::consts::FRAC_1_SQRT_2;
        let int = |k: f64| -> f64 {
            if (k + 1.0).abs() < 1e-9 {
                -s.ln()
            } else {
                (1.0 - s.powf(k + 1.0)) / (k + 1.0)
            }
        };
        let eight_pi = 8.0 * std::f64::consts::PI;
        let a = |g: f64| eight_pi * (2.0 * int(g + 3.0) - int(g + 1.0));
        let value = match self {
            PhongVariant::Notes => eight_pi * int(g + 1.0),
            PhongVariant::MaxBlinn => a(g),
            PhongVariant::HalfwaySquared => a(g - 2.0) / 4.0,
            PhongVariant::Normalized => (g + 8.0) / eight_pi * a(g),
        };
        value as f32
    }
}

/// Diffuse `kd` + specular `ks` lobe (linearity: a material is a sum of lobes).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PhongBlinn {
    /// The notes' diffuse coefficient kd [1/sr] (= ρ/π).
    pub kd: Rgb,
    /// Specular coefficient (units as the variant's formula).
    pub ks: Rgb,
    /// Shininess γ ≥ 0.
    pub shininess: f32,
    pub variant: PhongVariant,
}

impl PhongBlinn {
    /// From the notes' coefficients: kd [1/sr], ks, γ ≥ 0.
    pub fn new(kd: Rgb, ks: Rgb, shininess: f32, variant: PhongVariant) -> Self {
        debug_assert!(shininess >= 0.0, "shininess must be ≥ 0");
        Self {
            kd,
            ks,
            shininess: shininess.max(0.0),
            variant,
        }
    }

    /// From the diffuse albedo ρ: kd = ρ/π.
    pub fn from_albedo(rho: Rgb, ks: Rgb, shininess: f32, variant: PhongVariant) -> Self {
        Self::new(rho * FRAC_1_PI, ks, shininess, variant)
    }

    /// f(wo, wi) = kd + ks s(wo, wi) if both are above the surface, else 0.
    #[inline]
    pub fn eval(&self, wo: Vec3, wi: Vec3) -> Rgb {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return Rgb::ZERO;
        }
        self.kd + self.ks * self.variant.lobe(wo, wi, self.shininess)
    }

    /// Probability of sampling the specular lobe: its share
    /// `a_s / (a_d + a_s)` of the approximate albedo, with `a_d` = mean of
    /// π kd and `a_s` = mean of ks × the lobe's albedo at normal incidence
    /// ([`PhongVariant::normal_incidence_albedo`]). ½ if both are 0.
    pub fn specular_probability(&self) -> f32 {
        let mean = |c: Rgb| (c.x.max(0.0) + c.y.max(0.0) + c.z.max(0.0)) / 3.0;
        let a_d = PI * mean(self.kd);
        let a_s = mean(self.ks) * self.variant.normal_incidence_albedo(self.shininess);
        let total = a_d + a_s;
        if total > 0.0 && total.is_finite() {
            (a_s / total).clamp(0.0, 1.0)
        } else {
            0.5
        }
    }

    /// Density of a halfway vector with `cos δ = cos_h`: (γ+1)/(2π) cos^γ δ.
    #[inline]
    fn halfway_pdf(&self, cos_h: f32) -> f32 {
        if cos_h <= 0.0 {
            return 0.0;
        }
        (self.shininess + 1.0) * 0.5 * FRAC_1_PI * cos_h.powf(self.shininess)
    }

    /// Mixture pdf `(1 − p) cos θi/π + p pdf_h(h) / (4 wo·h)`, p =
    /// [`Self::specular_probability`]; 0 below the surface.
    #[inline]
    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return 0.0;
        }
        let p = self.specular_probability();
        let sum = wi + wo;
        let len = sum.length();
        let spec = if len > 0.0 {
            let h = sum / len;
            let wo_h = wo.dot(h);
            if wo_h > 0.0 {
                self.halfway_pdf(h.z) / (4.0 * wo_h)
            } else {
                0.0
            }
        } else {
            0.0
        };
        (1.0 - p) * cosine_hemisphere_pdf(wi.z) + p * spec
    }

    /// Picks the specular lobe if `u_lobe < p`, else the diffuse one; the
    /// specular lobe draws `cos δ = u^(1/(γ+1))`, `φ = 2π u'` and reflects
    /// `wo` about `h`. `None` if the reflection falls below the surface.
    /// weight = f cos θi / pdf with the mixture pdf.
    pub fn sample(&self, wo: Vec3, u_lobe: f32, u: [f32; 2]) -> Option<BsdfSample> {
        if wo.z <= 0.0 {
            return None;
        }
        let p = self.specular_probability();
        let wi = if u_lobe < p {
            let cos_h = u[0].powf(1.0 / (self.shininess + 1.0)).min(1.0);
            let sin_h = (1.0 - cos_h * cos_h).max(0.0).sqrt();
            let phi = 2.0 * PI * u[1];
            let h = Vec3::new(sin_h * phi.cos(), sin_h * phi.sin(), cos_h);
            if wo.dot(h) <= 0.0 {
                return None;
            }
            reflect(wo, h).normalize()
        } else {
            square_to_cosine_hemisphere(u)
        };
        if wi.z <= 0.0 {
            return None;
        }
        let pdf = self.pdf(wo, wi);
        if pdf <= 0.0 || !pdf.is_finite() {
            return None;
        }
        Some(BsdfSample {
            wi,
            weight: self.eval(wo, wi) * (wi.z / pdf),
            pdf,
            delta: false,
            eta: 1.0,
        })
    }

    /// Non-delta reflection only.
    pub fn flags(&self) -> BsdfFlags {
        BsdfFlags::DIFFUSE
    }

    /// No delta part.
    pub fn specular(&self, _wo: Vec3) -> SpecularSet {
        SpecularSet::default()
    }

    /// Directional albedo at normal incidence, exact: π kd + ks a(γ) with a(γ)
    /// of [`PhongVariant::normal_incidence_albedo`]. At other angles the
    /// lecture variants differ from it (see the energy tests).
    pub fn albedo(&self) -> Rgb {
        self.kd * PI + self.ks * self.variant.normal_incidence_albedo(self.shininess)
    }

    /// Diffuse colour multiplied by a texture colour.
    pub fn tinted(self, t: Rgb) -> Self {
        Self {
            kd: self.kd * t,
            ..self
        }
    }
}
