//! Ideal mirror: all light leaves in `R = v − 2n(n·v)`, scaled by a constant
//! reflectance (no Fresnel variation; see `Conductor` for that).
//!
//! | quantity            | value                                        |
//! |---------------------|----------------------------------------------|
//! | `eval`, `pdf`       | 0 (a pure delta lobe)                        |
//! | direction           | `wi = reflect(wo, z) = (−wo.x, −wo.y, wo.z)` |
//! | throughput          | `ρ` (reflectance, per band)                  |
//! | `sample` weight/pdf | `ρ` / 1, `delta = true`                      |
//! | `albedo`            | `ρ`                                          |

use super::optics::reflect;
use super::{BsdfFlags, BsdfSample, SpecularSet};
use crate::Rgb;
use glam::Vec3;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Mirror {
    /// Fraction reflected per band, in `[0, 1]`.
    pub reflectance: Rgb,
}

impl Mirror {
    /// A mirror reflecting the fraction `reflectance` per band.
    pub fn new(reflectance: Rgb) -> Self {
        Self { reflectance }
    }

    /// Purely specular: no density anywhere.
    #[inline]
    pub fn eval(&self, _wo: Vec3, _wi: Vec3) -> Rgb {
        Rgb::ZERO
    }

    /// Purely specular: no density anywhere.
    #[inline]
    pub fn pdf(&self, _wo: Vec3, _wi: Vec3) -> f32 {
        0.0
    }

    /// The mirror direction with weight ρ (selection probability 1).
    #[inline]
    pub fn sample(&self, wo: Vec3, _u_lobe: f32, _u: [f32; 2]) -> Option<BsdfSample> {
        if wo.z <= 0.0 {
            return None;
        }
        Some(BsdfSample {
            wi: reflect(wo, Vec3::Z),
            weight: self.reflectance,
            pdf: 1.0,
            delta: true,
            eta: 1.0,
        })
    }

    /// One lobe: (reflect(wo), ρ).
    pub fn specular(&self, wo: Vec3) -> SpecularSet {
        let mut set = SpecularSet::default();
        if wo.z > 0.0 {
            set.push(reflect(wo, Vec3::Z), self.reflectance);
        }
        set
    }

    /// Delta reflection only.
    pub fn flags(&self) -> BsdfFlags {
        BsdfFlags::SPECULAR_REFLECTION
    }

    /// ρ, the reflectance at every angle.
    pub fn albedo(&self) -> Rgb {
        self.reflectance
    }

    /// Reflectance multiplied by a texture colour.
    pub fn tinted(self, t: Rgb) -> Self {
        Self::new(self.reflectance * t)
    }
}
