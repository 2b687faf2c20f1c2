//! The notes' unified light: a homogeneous position (y, w) and a power
//! density M. At a point x the light arrives from `l = normalize(y − x·w)`
//! with irradiance on a surface perpendicular to l
//! `E⊥ = M / |y − x·w|²` (SEEDS.md, Light sources), so a Lambertian surface
//! receives `E = E⊥ (l·n)⁺`.
//!
//! * w = 1: a point light at y; M = Φ/4π is its intensity I [W/sr] and the
//!   formula is the inverse-square law `I / r²`.
//! * w = 0: a light at infinity in direction y (unit); |y − x·0|² = 1 and M
//!   is the irradiance [W/m²] everywhere (a directional light).

use super::LightSample;
use crate::Rgb;
use glam::{Vec3, Vec4};

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HomogeneousLight {
    /// (y, w): w = 1 point at y, w = 0 direction y towards the light.
    pub position: Vec4,
    /// Power density M per band: intensity [W/sr] for w = 1, irradiance
    /// [W/m²] for w = 0.
    pub m: Rgb,
}

impl HomogeneousLight {
    /// Point light at `position` with intensity I = M.
    pub fn point(position: Vec3, intensity: Rgb) -> Self {
        Self {
            position: position.extend(1.0),
            m: intensity,
        }
    }

    /// Light at infinity whose light *travels* along `direction`; M = E.
    pub fn directional(direction: Vec3, irradiance: Rgb) -> Self {
        Self {
            position: (-direction.normalize_or_zero()).extend(0.0),
            m: irradiance,
        }
    }

    /// Incident light at `x`: `wi = normalize(y − x·w)`,
    /// `value = E⊥ = M / |y − x·w|²`. `None` at the light itself.
    pub fn sample_li(&self, x: Vec3) -> Option<LightSample> {
        let w = self.position.w;
        let d = self.position.truncate() - x * w;
        let r2 = d.length_squared();
        if r2 == 0.0 || !r2.is_finite() {
            return None;
        }
        let len = r2.sqrt();
        Some(LightSample {
            wi: d / len,
            // The affine point is y/w, at distance |y − x w| / w from x.
            distance: if w == 0.0 { f32::INFINITY } else { len / w },
            value: self.m / r2,
            pdf: 1.0,
            is_delta: true,
        })
    }
}
