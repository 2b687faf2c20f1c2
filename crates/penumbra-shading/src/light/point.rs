//! Isotropic point light: intensity I [W/sr] (or power Φ with I = Φ/4π),
//! optionally cut off at a finite range with glTF `KHR_lights_punctual`'s
//! smooth window ([`range_window`]).

use super::{HomogeneousLight, LightSample};
use crate::{Rgb, radiometry};
use glam::Vec3;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PointLight {
    pub position: Vec3,
    /// Radiant intensity I [W/sr] per band.
    pub intensity: Rgb,
    /// Distance beyond which the light contributes nothing
    /// (`f32::INFINITY`: the plain inverse-square law everywhere).
    pub range: f32,
}

/// glTF `KHR_lights_punctual`'s recommended range cut-off, multiplied onto
/// the inverse-square law: `W(d) = clamp(1 − (d / range)⁴, 0, 1)²`. W = 1
/// for an infinite range, falls smoothly (with zero slope) to exactly 0 at
/// d = range, so a light can be culled beyond its range without changing
/// the image. Not physical: it removes energy from the far field.
#[inline]
pub fn range_window(distance: f32, range: f32) -> f32 {
    if range == f32::INFINITY {
        return 1.0;
    }
    let x = distance / range;
    let x2 = x * x;
    let t = (1.0 - x2 * x2).clamp(0.0, 1.0);
    t * t
}

impl PointLight {
    /// From radiant power Φ [W]: `I = Φ / 4π`.
    pub fn from_power(position: Vec3, power: Rgb) -> Self {
        Self {
            position,
            intensity: power.map(radiometry::point_intensity_from_power),
            range: f32::INFINITY,
        }
    }

    /// A light of intensity I with no range cut-off.
    pub fn new(position: Vec3, intensity: Rgb) -> Self {
        Self {
            position,
            intensity,
            range: f32::INFINITY,
        }
    }

    /// Irradiance on a perpendicular surface `E⊥ = I / r²` (notes:
    /// `M = Φ / 4π r²`) times [`range_window`]; the caller multiplies by
    /// cos θ. `None` at and beyond the range.
    pub fn sample_li(&self, p: Vec3) -> Option<LightSample> {
        let mut s = self.homogeneous().sample_li(p)?;
        let w = range_window(s.distance, self.range);
        if w <= 0.0 {
            return None;
        }
        s.value *= w;
        Some(s)
    }

    /// The unified form: (y, w) = (position, 1), M = I.
    pub fn homogeneous(&self) -> HomogeneousLight {
        HomogeneousLight::point(self.position, self.intensity)
    }

    /// Φ = 4π I (without the range window).
    pub fn power(&self) -> Rgb {
        self.intensity.map(radiometry::point_power_from_intensity)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn irradiance_on_plane_is_i_cos_over_r2() {
        let l = PointLight::new(Vec3::new(1.0, 2.0, 3.0), Rgb::splat(10.0));
        let p = Vec3::new(0.0, 0.0, 0.0);
        let s = l.sample_li(p).unwrap();
        let r2 = 14.0f32;
        let cos = 3.0 / r2.sqrt();
        let e = s.value.x * s.wi.z;
        assert!((e - 10.0 * cos / r2).abs() < 1e-5);
        let from_power = PointLight::from_power(l.position, l.power());
        assert!((from_power.intensity - l.intensity).abs().max_element() < 1e-4);
    }

    #[test]
    fn range_window_is_smooth_and_zero_at_the_range() {
        assert_eq!(range_window(5.0, f32::INFINITY), 1.0);
        assert_eq!(range_window(0.0, 2.0), 1.0);
        assert_eq!(range_window(2.0, 2.0), 0.0);
        assert_eq!(range_window(3.0, 2.0), 0.0);
        // (1 − 0.5⁴)² at half the range.
        assert!((range_window(1.0, 2.0) - (1.0f32 - 0.0625).powi(2)).abs() < 1e-6);
        // Monotone between.
        let mut last = 1.0;
        for i in 0..=100 {
            let w = range_window(i as f32 * 0.02, 2.0);
            assert!(w <= last);
            last = w;
        }
        let l = PointLight {
            range: 2.0,
            ..PointLight::new(Vec3::ZERO, Rgb::splat(4.0))
        };
        let s = l.sample_li(Vec3::new(1.0, 0.0, 0.0)).unwrap();
        assert!((s.value.x - 4.0 * range_window(1.0, 2.0)).abs() < 1e-6);
        assert!(l.sample_li(Vec3::new(0.0, 2.0, 0.0)).is_none());
        assert!(l.sample_li(Vec3::new(0.0, 0.0, -7.0)).is_none());
    }
}
