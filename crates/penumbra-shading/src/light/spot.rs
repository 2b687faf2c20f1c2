//! Spot light with glTF `KHR_lights_punctual` semantics: intensity I [W/sr]
//! on the axis, full inside the inner cone, smoothly to 0 at the outer cone:
//! `t = clamp((cos θ − cos θo) / (cos θi − cos θo), 0, 1)`, attenuation `t²`,
//! and the same optional range cut-off as point lights ([`range_window`]).

use super::{HomogeneousLight, LightSample, range_window};
use crate::Rgb;
use glam::Vec3;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpotLight {
    pub position: Vec3,
    /// Unit direction the spot points to (direction of travel on the axis).
    pub direction: Vec3,
    /// Intensity on the axis [W/sr].
    pub intensity: Rgb,
    pub cos_inner: f32,
    pub cos_outer: f32,
    /// Distance beyond which the light contributes nothing
    /// (`f32::INFINITY`: no cut-off).
    pub range: f32,
}

impl SpotLight {
    /// Angular falloff in [0, 1] for a direction `w` leaving the light.
    pub fn falloff(&self, w: Vec3) -> f32 {
        let c = w.dot(self.direction);
        let span = (self.cos_inner - self.cos_outer).max(1e-6);
        let t = ((c - self.cos_outer) / span).clamp(0.0, 1.0);
        t * t
    }

    /// The unified point-light form (w = 1, M = I) times the cone falloff
    /// and the range window.
    pub fn sample_li(&self, p: Vec3) -> Option<LightSample> {
        let mut s = HomogeneousLight::point(self.position, self.intensity).sample_li(p)?;
        let f = self.falloff(-s.wi) * range_window(s.distance, self.range);
        if f <= 0.0 {
            return None;
        }
        s.value *= f;
        Some(s)
    }

    /// Φ = ∫ I(ω) dω with the t² falloff, integrated in closed form over
    /// cos θ: 2π I [(1 − cos θi) + ∫_{cos θo}^{cos θi} t(c)² dc]
    /// = 2π I [(1 − cos θi) + (cos θi − cos θo)/3].
    pub fn power(&self) -> Rgb {
        let ci = self.cos_inner;
        let co = self.cos_outer;
        self.intensity * (2.0 * std::f32::consts::PI * ((1.0 - ci) + (ci - co) / 3.0))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::square_to_uniform_sphere;

    #[test]
    fn power_matches_numerical_integral() {
        let s = SpotLight {
            position: Vec3::ZERO,
            direction: Vec3::Z,
            intensity: Rgb::ONE,
            cos_inner: 0.9,
            cos_outer: 0.6,
            range: f32::INFINITY,
        };
        let n = 1024;
        let mut sum = 0.0f64;
        for i in 0..n * n {
            let u = [
                ((i % n) as f32 + 0.5) / n as f32,
                ((i / n) as f32 + 0.5) / n as f32,
            ];
            sum += s.falloff(square_to_uniform_sphere(u)) as f64;
        }
        let phi = sum / (n * n) as f64 * 4.0 * std::f64::consts::PI;
        assert!(
            (phi as f32 - s.power().x).abs() / s.power().x < 2e-3,
            "{phi} vs {}",
            s.power().x
        );
    }
}
