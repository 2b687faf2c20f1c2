//! Rough dielectric: GGX microfacet reflection and transmission (Walter et al. 2007).
//!
//! With ωo outside (index 1) and η = n_inside / n_outside:
//! - reflection (ωi.z > 0): `D G2 F(ωo·m) / (4 cos θo cos θi)`, m ∝ ωo + ωi;
//! - transmission (ωi.z < 0): `tint · D G2 (1 − F(ωo·m)) |ωo·m| |ωi·m| /
//!   (|cos θo| |cos θi| (ωo·m + η ωi·m)²)`, m ∝ ωo + η ωi (the generalised
//!   half vector, Walter eqs. 16 and 21). This is the radiance form: light
//!   crossing from the inside carries (n_o/n_i)² = 1/η², and generalised
//!   reciprocity is f(ωo, ωi)/n_o² = f(ωi, ωo)/n_i² (Veach 1997, ch. 5),
//!   n_o, n_i the indices on the sides of ωo and ωi;
//! - F is the exact dielectric Fresnel reflectance at the microfacet.
//!
//! Sampling draws m from the visible normals and reflects with probability
//! F(ωo·m), else refracts, so the pdf is
//! `D_ωo(m) F / (4 ωo·m)` (reflection) or `D_ωo(m) (1 − F) η² |ωi·m| /
//! (ωo·m + η ωi·m)²` (transmission), and the weights are `G2/G1(ωo)` and
//! `tint G2 / (G1(ωo) η²)`.

use super::microfacet::{
    Ggx, reflection_core, reflection_half_vector, transmission_core, transmission_half_vector,
    transmission_jacobian,
};
use super::optics::{fresnel_dielectric, reflect, refract};
use super::{BsdfFlags, BsdfSample, SpecularSet};
use crate::Rgb;
use glam::Vec3;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RoughDielectric {
    /// Relative index η = n_inside / n_outside.
    pub eta: f32,
    /// GGX α (= perceptual roughness²).
    pub alpha: f32,
    /// Colour multiplying transmitted light.
    pub tint: Rgb,
}

impl RoughDielectric {
    /// A clear rough dielectric (tint 1).
    pub fn new(eta: f32, alpha: f32) -> Self {
        Self {
            eta,
            alpha,
            tint: Rgb::ONE,
        }
    }

    /// The same interface seen from the inside: η → 1/η.
    pub fn inverted(self) -> Self {
        Self {
            eta: 1.0 / self.eta,
            ..self
        }
    }

    /// The microfacet distribution (α clamped to [`super::microfacet::MIN_ALPHA`]).
    #[inline]
    pub fn ggx(&self) -> Ggx {
        Ggx::new(self.alpha)
    }

    /// f(ωo, ωi): reflection above, transmission below (radiance form).
    #[inline]
    pub fn eval(&self, wo: Vec3, wi: Vec3) -> Rgb {
        if wo.z <= 0.0 {
            return Rgb::ZERO;
        }
        let ggx = self.ggx();
        if wi.z > 0.0 {
            let Some(m) = reflection_half_vector(wo, wi) else {
                return Rgb::ZERO;
            };
            Rgb::splat(fresnel_dielectric(wo.dot(m), self.eta) * reflection_core(&ggx, wo, wi, m))
        } else if wi.z < 0.0 {
            let Some(m) = transmission_half_vector(wo, wi, self.eta) else {
                return Rgb::ZERO;
            };
            let t = 1.0 - fresnel_dielectric(wo.dot(m), self.eta);
            self.tint * (t * transmission_core(&ggx, wo, wi, m, self.eta))
        } else {
            Rgb::ZERO
        }
    }

    /// Both lobes' densities, each with its Jacobian and selection probability.
    #[inline]
    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        if wo.z <= 0.0 {
            return 0.0;
        }
        let ggx = self.ggx();
        if wi.z > 0.0 {
            let Some(m) = reflection_half_vector(wo, wi) else {
                return 0.0;
            };
            let c = wo.dot(m);
            if c <= 0.0 {
                return 0.0;
            }
            ggx.pdf_visible(wo, m) * fresnel_dielectric(c, self.eta) / (4.0 * c)
        } else if wi.z < 0.0 {
            let Some(m) = transmission_half_vector(wo, wi, self.eta) else {
                return 0.0;
            };
            let t = 1.0 - fresnel_dielectric(wo.dot(m), self.eta);
            ggx.pdf_visible(wo, m) * t * transmission_jacobian(wo, wi, m, self.eta)
        } else {
            0.0
        }
    }

    /// m from the visible normals; reflect if `u_lobe` < F(ωo·m), else refract.
    #[inline]
    pub fn sample(&self, wo: Vec3, u_lobe: f32, u: [f32; 2]) -> Option<BsdfSample> {
        if wo.z <= 0.0 {
            return None;
        }
        let ggx = self.ggx();
        let m = ggx.sample_visible(wo, u);
        let c = wo.dot(m);
        if c <= 0.0 {
            return None;
        }
        let f = fresnel_dielectric(c, self.eta);
        let d_vis = ggx.pdf_visible(wo, m);
        let (wi, pdf, weight, eta) = if u_lobe < f {
            let wi = reflect(wo, m);
            if wi.z <= 0.0 {
                return None;
            }
            let w = ggx.g2(wo, wi) / ggx.g1(wo);
            (wi, d_vis * f / (4.0 * c), Rgb::splat(w), 1.0)
        } else {
            let wi = refract(wo, m, self.eta)?.normalize();
            if wi.z >= 0.0 {
                return None;
            }
            let pdf = d_vis * (1.0 - f) * transmission_jacobian(wo, wi, m, self.eta);
            let w = ggx.g2(wo, wi) / (ggx.g1(wo) * self.eta * self.eta);
            (wi, pdf, self.tint * w, self.eta)
        };
        if !(pdf > 0.0 && pdf.is_finite()) {
            return None;
        }
        Some(BsdfSample {
            wi,
            weight,
            pdf,
            delta: false,
            eta,
        })
    }

    /// Glossy reflection and transmission.
    pub fn flags(&self) -> BsdfFlags {
        BsdfFlags {
            non_delta: true,
            delta: false,
            transmission: true,
        }
    }

    /// No delta lobe (α is clamped away from 0).
    pub fn specular(&self, _wo: Vec3) -> SpecularSet {
        SpecularSet::default()
    }

    /// The transmission tint, as a colour summary.
    pub fn albedo(&self) -> Rgb {
        self.tint
    }

    /// Tint multiplied by `t`.
    pub fn tinted(self, t: Rgb) -> Self {
        Self {
            tint: self.tint * t,
            ..self
        }
    }
}
