//! Isotropic point light: intensity I [W/sr] (or power Φ with I = Φ/4π).

use super::{HomogeneousLight, LightSample};
use crate::{Rgb, radiometry};
use glam::Vec3;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PointLight {
    pub position: Vec3,
    /// Radiant intensity I [W/sr] per band.
    pub intensity: Rgb,
}

impl PointLight {
    /// From radiant power Φ [W]: `I = Φ / 4π`.
    pub fn from_power(position: Vec3, power: Rgb) -> Self {
        Self {
            position,
            intensity: power.map(radiometry::point_intensity_from_power),
        }
    }

    /// Irradiance on a perpendicular surface `E⊥ = I / r²` (notes:
    /// `M = Φ / 4π r²`); the caller multiplies by cos θ.
    pub fn sample_li(&self, p: Vec3) -> Option<LightSample> {
        self.homogeneous().sample_li(p)
    }

    /// The unified form: (y, w) = (position, 1), M = I.
    pub fn homogeneous(&self) -> HomogeneousLight {
        HomogeneousLight::point(self.position, self.intensity)
    }

    /// Φ = 4π I.
    pub fn power(&self) -> Rgb {
        self.intensity.map(radiometry::point_power_from_intensity)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn irradiance_on_plane_is_i_cos_over_r2() {
        let l = PointLight {
            position: Vec3::new(1.0, 2.0, 3.0),
            intensity: Rgb::splat(10.0),
        };
        let p = Vec3::new(0.0, 0.0, 0.0);
        let s = l.sample_li(p).unwrap();
        let r2 = 14.0f32;
        let cos = 3.0 / r2.sqrt();
        let e = s.value.x * s.wi.z;
        assert!((e - 10.0 * cos / r2).abs() < 1e-5);
        let from_power = PointLight::from_power(l.position, l.power());
        assert!((from_power.intensity - l.intensity).abs().max_element() < 1e-4);
    }
}
