//! Lambertian (ideal diffuse) reflection.
//!
//! `f = ρ / π` (notes 000, `c_dif / π`), equivalently the notes 002/003 `kd`
//! with `kd = ρ / π`. Reflection only: f = 0 when wo and wi are on opposite
//! sides of the surface.

use super::{BsdfFlags, BsdfSample, SpecularSet};
use crate::Rgb;
use crate::sampling::{cosine_hemisphere_pdf, square_to_cosine_hemisphere};
use glam::Vec3;
use std::f32::consts::FRAC_1_PI;

/// Lambertian BRDF with albedo ρ ∈ [0,1]³.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Lambert {
    pub albedo: Rgb,
}

impl Lambert {
    /// From the albedo ρ: f = ρ/π.
    pub fn new(albedo: Rgb) -> Self {
        Self { albedo }
    }

    /// From the notes' diffuse coefficient kd [1/sr]: ρ = π kd.
    pub fn from_kd(kd: Rgb) -> Self {
        Self {
            albedo: kd * std::f32::consts::PI,
        }
    }

    /// The notes' kd = ρ/π [1/sr].
    pub fn kd(&self) -> Rgb {
        self.albedo * FRAC_1_PI
    }

    /// f(wo, wi) = ρ/π if both are above the surface, else 0.
    #[inline]
    pub fn eval(&self, wo: Vec3, wi: Vec3) -> Rgb {
        if wo.z > 0.0 && wi.z > 0.0 {
            self.kd()
        } else {
            Rgb::ZERO
        }
    }

    /// cos θi / π on the upper hemisphere.
    #[inline]
    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        if wo.z > 0.0 {
            cosine_hemisphere_pdf(wi.z)
        } else {
            0.0
        }
    }

    /// Cosine-weighted sampling; weight = f cos / pdf = ρ.
    #[inline]
    pub fn sample(&self, wo: Vec3, _u_lobe: f32, u: [f32; 2]) -> Option<BsdfSample> {
        if wo.z <= 0.0 {
            return None;
        }
        let wi = square_to_cosine_hemisphere(u);
        let pdf = cosine_hemisphere_pdf(wi.z);
        if pdf <= 0.0 {
            return None;
        }
        Some(BsdfSample {
            wi,
            weight: self.albedo,
            pdf,
            delta: false,
            eta: 1.0,
        })
    }

    /// Diffuse reflection has no delta part.
    pub fn flags(&self) -> BsdfFlags {
        BsdfFlags::DIFFUSE
    }

    /// No delta part.
    pub fn specular(&self, _wo: Vec3) -> SpecularSet {
        SpecularSet::default()
    }

    /// ρ, the directional albedo at every angle.
    pub fn albedo(&self) -> Rgb {
        self.albedo
    }

    /// Albedo multiplied by a texture colour.
    pub fn tinted(self, t: Rgb) -> Self {
        Self::new(self.albedo * t)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::Sampler;

    #[test]
    fn notes_quiz_lambert_is_2_4() {
        // SEEDS.md quiz 2: n = (0,0,1), light from (0,3,4), Lin = 5, kd = 0.6.
        let m = Lambert::from_kd(Rgb::splat(0.6));
        let l = Vec3::new(0.0, 3.0, 4.0).normalize();
        for v in [
            Vec3::Z,
            Vec3::new(0.5, 0.1, 0.3).normalize(),
            Vec3::new(-0.9, 0.0, 0.1).normalize(),
        ] {
            let radiance = m.eval(v, l) * 5.0 * l.z;
            assert!((radiance - Rgb::splat(2.4)).abs().max_element() < 1e-5);
        }
    }

    /// f = ρ/π only with both directions strictly above the surface; the
    /// pdf is 0 for a view at or below it; no delta part; a tint scales ρ.
    #[test]
    fn hemisphere_boundaries_tint_and_no_delta_part() {
        let rho = Rgb::new(0.8, 0.5, 0.2);
        let m = Lambert::new(rho);
        let up = Vec3::new(0.3, 0.2, 0.9).normalize();
        let down = Vec3::new(0.3, 0.2, -0.9).normalize();
        let horizon = Vec3::X;
        assert!(
            (m.eval(up, up) - rho / std::f32::consts::PI)
                .abs()
                .max_element()
                < 1e-7
        );
        for (wo, wi) in [
            (up, down),
            (down, up),
            (down, down),
            (horizon, up),
            (up, horizon),
        ] {
            assert_eq!(m.eval(wo, wi), Rgb::ZERO, "{wo} {wi}");
        }
        assert!((m.pdf(up, up) - up.z / std::f32::consts::PI).abs() < 1e-7);
        assert_eq!(m.pdf(down, up), 0.0);
        assert_eq!(m.pdf(horizon, up), 0.0);
        assert!(m.specular(up).is_empty());
        assert_eq!(m.albedo(), rho);
        let t = m.tinted(Rgb::new(0.5, 2.0, 1.0)).albedo();
        assert!(
            (t - Rgb::new(0.4, 1.0, 0.2)).abs().max_element() < 1e-7,
            "{t}"
        );
    }

    #[test]
    fn kd_and_albedo_agree() {
        let m = Lambert::new(Rgb::new(0.5, 0.25, 1.0));
        assert!(
            (m.kd() * std::f32::consts::PI - m.albedo)
                .abs()
                .max_element()
                < 1e-6
        );
    }

    #[test]
    fn reciprocal_and_white_furnace() {
        let m = Lambert::new(Rgb::ONE);
        let mut s = Sampler::new(0, 0, 0, 9);
        let wo = Vec3::new(0.3, 0.2, 0.9).normalize();
        let n = 100_000;
        let mut est = Rgb::ZERO;
        for i in 0..n {
            s = Sampler::new(i, 0, 0, 9);
            let smp = m.sample(wo, 0.5, s.next_2d()).unwrap();
            assert!(
                (m.eval(wo, smp.wi) * smp.wi.z / smp.pdf - smp.weight)
                    .abs()
                    .max_element()
                    < 1e-4
            );
            assert_eq!(m.eval(wo, smp.wi), m.eval(smp.wi, wo));
            est += smp.weight;
        }
        assert!((est / n as f32 - Rgb::ONE).abs().max_element() < 1e-5);
        assert!(m.sample(-wo, 0.5, s.next_2d()).is_none());
    }

    #[test]
    fn chi_square_sample_against_pdf() {
        use crate::stats::{SphereBins, TestRng, chi_square_sphere};
        // Sampling ignores wo, but the family covers normal to grazing views.
        let m = Lambert::new(Rgb::new(0.9, 0.5, 0.1));
        let views = [0.0f32, 45.0, 80.0, 89.0];
        for (k, deg) in views.iter().enumerate() {
            let t = deg.to_radians();
            let wo = Vec3::new(t.sin() * 0.3f32.cos(), t.sin() * 0.3f32.sin(), t.cos());
            let mut rng = TestRng::new(40 + k as u64);
            let mut bad = None;
            let res = chi_square_sphere(
                200_000,
                SphereBins::default(),
                || {
                    let s = m.sample(wo, rng.next_f32(), rng.next_2d())?;
                    let expect = m.eval(wo, s.wi) * s.wi.z / m.pdf(wo, s.wi);
                    if s.delta || (s.weight - expect).abs().max_element() > 1e-4 {
                        bad.get_or_insert(s);
                    }
                    Some(s.wi)
                },
                |wi| m.pdf(wo, wi),
            );
            assert!(bad.is_none(), "θo = {deg}: {bad:?}");
            assert!(res.passes(0.01, views.len()), "θo = {deg}: {res:?}");
            assert!((res.pdf_integral - 1.0).abs() < 5e-3 && res.sampled_fraction == 1.0);
        }
    }
}
