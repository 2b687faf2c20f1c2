//! Directional light: irradiance E [W/m²] on a surface perpendicular to the
//! light, the same everywhere (the sun).

use super::{HomogeneousLight, LightSample};
use crate::Rgb;
use glam::Vec3;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DirectionalLight {
    /// Unit direction in which the light *travels*.
    pub direction: Vec3,
    /// Irradiance on a perpendicular surface [W/m²].
    pub irradiance: Rgb,
}

impl DirectionalLight {
    pub fn sample_li(&self, p: Vec3) -> Option<LightSample> {
        self.homogeneous().sample_li(p)
    }

    /// The unified form: (y, w) = (−direction, 0), M = E.
    pub fn homogeneous(&self) -> HomogeneousLight {
        HomogeneousLight::directional(self.direction, self.irradiance)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn notes_quiz_setup_gives_e_cos() {
        // light from (0,3,4) (towards the light): travels along -(0,3,4)/5.
        let l = DirectionalLight {
            direction: -Vec3::new(0.0, 3.0, 4.0).normalize(),
            irradiance: Rgb::splat(5.0),
        };
        let s = l.sample_li(Vec3::ZERO).unwrap();
        assert!((s.value.x * s.wi.dot(Vec3::Z) - 4.0).abs() < 1e-5);
    }
}
