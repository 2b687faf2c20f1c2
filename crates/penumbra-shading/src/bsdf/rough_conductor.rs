//! Rough conductor: GGX microfacets with conductor Fresnel.
//!
//! `f(ωo, ωi) = D(m) G2(ωo, ωi) F(ωo·m) / (4 cos θo cos θi)`, m the half
//! vector (Walter et al. 2007, eq. 20), with the height-correlated Smith G2.
//! Sampled by visible normals (see [`super::microfacet`]): the pdf is
//! `D_ωo(m) / (4 ωo·m)` and the weight `F(ωo·m) G2 / G1(ωo)`. Single
//! scattering only: energy reflected more than once between microfacets is
//! lost: with F ≡ 1, 0.3 % at α = 0.05 and normal incidence, 69 % at α = 1
//! (normal incidence), 33 % at α = 1 and θo = 80° (the furnace test).

use super::microfacet::{Ggx, reflection_core, reflection_half_vector};
use super::optics::{f0_from_ior, fresnel_conductor, reflect, schlick};
use super::{BsdfFlags, BsdfSample, FresnelModel, SpecularSet};
use crate::Rgb;
use glam::Vec3;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RoughConductor {
    pub eta: Rgb,
    pub k: Rgb,
    /// GGX α (= perceptual roughness²).
    pub alpha: f32,
    pub fresnel: FresnelModel,
}

impl RoughConductor {
    /// A rough conductor with the exact Fresnel equations.
    pub fn new(eta: Rgb, k: Rgb, alpha: f32) -> Self {
        Self {
            eta,
            k,
            alpha,
            fresnel: FresnelModel::Exact,
        }
    }

    /// The microfacet distribution (α clamped to [`super::microfacet::MIN_ALPHA`]).
    #[inline]
    pub fn ggx(&self) -> Ggx {
        Ggx::new(self.alpha)
    }

    /// F at the microfacet: exact conductor Fresnel or Schlick with
    /// F0 = ((n−1)² + κ²) / ((n+1)² + κ²).
    #[inline]
    pub fn fresnel_at(&self, cos_theta: f32) -> Rgb {
        match self.fresnel {
            FresnelModel::Exact => fresnel_conductor(cos_theta, self.eta, self.k),
            FresnelModel::Schlick => schlick(f0_from_ior(self.eta, self.k), cos_theta),
        }
    }

    /// D G2 F / (4 cos θo cos θi) for both directions above the surface.
    #[inline]
    pub fn eval(&self, wo: Vec3, wi: Vec3) -> Rgb {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return Rgb::ZERO;
        }
        let Some(m) = reflection_half_vector(wo, wi) else {
            return Rgb::ZERO;
        };
        let ggx = self.ggx();
        self.fresnel_at(wo.dot(m)) * reflection_core(&ggx, wo, wi, m)
    }

    /// `D_ωo(m) / (4 ωo·m)` (Jacobian of reflection, Walter et al. eq. 14).
    #[inline]
    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return 0.0;
        }
        let Some(m) = reflection_half_vector(wo, wi) else {
            return 0.0;
        };
        let c = wo.dot(m);
        if c <= 0.0 {
            return 0.0;
        }
        self.ggx().pdf_visible(wo, m) / (4.0 * c)
    }

    /// Visible-normal sample, mirror about m; weight F G2 / G1(ωo).
    #[inline]
    pub fn sample(&self, wo: Vec3, _u_lobe: f32, u: [f32; 2]) -> Option<BsdfSample> {
        if wo.z <= 0.0 {
            return None;
        }
        let ggx = self.ggx();
        let m = ggx.sample_visible(wo, u);
        let c = wo.dot(m);
        let wi = reflect(wo, m);
        if wi.z <= 0.0 || c <= 0.0 {
            return None;
        }
        let pdf = ggx.pdf_visible(wo, m) / (4.0 * c);
        if !(pdf > 0.0 && pdf.is_finite()) {
            return None;
        }
        let weight = self.fresnel_at(c) * (ggx.g2(wo, wi) / ggx.g1(wo));
        Some(BsdfSample {
            wi,
            weight,
            pdf,
            delta: false,
            eta: 1.0,
        })
    }

    /// Glossy reflection only.
    pub fn flags(&self) -> BsdfFlags {
        BsdfFlags::DIFFUSE
    }

    /// No delta lobe (α is clamped away from 0).
    pub fn specular(&self, _wo: Vec3) -> SpecularSet {
        SpecularSet::default()
    }

    /// The reflectance at normal incidence F(1), as a colour summary.
    pub fn albedo(&self) -> Rgb {
        self.fresnel_at(1.0)
    }

    /// Normal-incidence reflectance multiplied by `t`: per band, the index is
    /// solved from F0' = F0·t = ((n'−1)² + κ'²)/((n'+1)² + κ'²), i.e.
    /// n'² − 2c n' + 1 + κ'² = 0 with c = (1+F0')/(1−F0'): κ is kept and the
    /// root nearest the old n taken; if no real root exists, κ'² = c² − 1, n' = c.
    pub fn tinted(self, t: Rgb) -> Self {
        let f0 = f0_from_ior(self.eta, self.k) * t;
        let mut eta = self.eta;
        let mut k = self.k;
        for b in 0..3 {
            let f = f0[b].clamp(0.0, 0.9999);
            let c = (1.0 + f) / (1.0 - f);
            let disc = c * c - 1.0 - k[b] * k[b];
            if disc < 0.0 {
                eta[b] = c;
                k[b] = (c * c - 1.0).max(0.0).sqrt();
            } else {
                let (lo, hi) = (c - disc.sqrt(), c + disc.sqrt());
                eta[b] = if (lo - self.eta[b]).abs() <= (hi - self.eta[b]).abs() {
                    lo
                } else {
                    hi
                };
            }
        }
        Self { eta, k, ..self }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tinted_scales_normal_incidence_reflectance() {
        let m = RoughConductor::new(Rgb::new(0.2, 0.9, 1.1), Rgb::new(3.9, 2.4, 1.8), 0.3);
        let t = Rgb::new(0.5, 0.9, 0.1);
        let f0 = f0_from_ior(m.eta, m.k);
        let tinted = m.tinted(t);
        let f0t = f0_from_ior(tinted.eta, tinted.k);
        assert!(
            (f0t - f0 * t).abs().max_element() < 1e-4,
            "{f0t} vs {}",
            f0 * t
        );
        let same = m.tinted(Rgb::ONE);
        assert!((same.eta - m.eta).abs().max_element() < 1e-3);
    }
}
