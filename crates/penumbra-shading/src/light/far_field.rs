//! The point-light limit of an analytic area light, for renderers that
//! shade with point lights only (the raster engine): all of the light's
//! flux leaves its centre with the shape's far-field intensity
//!
//! * sphere of radius r: `I = π r² Le` in every direction (its projected
//!   area times Le). For a receiver outside the sphere that sees all of it
//!   (the sphere entirely above the receiver's horizon) this is **exact**:
//!   the sphere's irradiance `π Le (r/d)² cos θ` is `I cos θ / d²`;
//! * disk or quad of area A and front normal n: `I(ω) = Le A (ω·n)⁺`
//!   (`|ω·n|` when two-sided), the Lambertian emitter's intensity. Exact as
//!   d ≫ the size: on the axis of a disk the true irradiance is
//!   `π Le r² / (r² + d²)`, so the far field overestimates by `r²/d²` (1 %
//!   at d = 10 r) and near the emitter it can be far off; soft shadows and
//!   highlights of the extent are lost.

use super::{AreaLight, HomogeneousLight, LightSample, Shape};
use crate::Rgb;
use glam::Vec3;
use std::f32::consts::PI;

/// A point light with the far-field intensity of an area light.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FarField {
    /// The shape's centre.
    pub position: Vec3,
    /// Unit front normal of a disk or quad; zero for a sphere (isotropic).
    pub axis: Vec3,
    /// Intensity along the axis (every direction for a sphere) [W/sr].
    pub intensity: Rgb,
    /// Disks and quads: emits on both sides.
    pub two_sided: bool,
}

impl FarField {
    /// Intensity towards direction `w` (unit, leaving the light) per unit
    /// axis intensity: 1, `(w·n)⁺` or `|w·n|`.
    pub fn lobe(&self, w: Vec3) -> f32 {
        if self.axis == Vec3::ZERO {
            return 1.0;
        }
        let c = w.dot(self.axis);
        if self.two_sided { c.abs() } else { c.max(0.0) }
    }

    /// Irradiance on a surface perpendicular to `wi` at `p`: the point
    /// light's `E⊥ = I / d²` ([`HomogeneousLight`]) times the lobe towards
    /// `−wi`; `None` where the lobe is zero or at the centre.
    pub fn sample_li(&self, p: Vec3) -> Option<LightSample> {
        let mut s = HomogeneousLight::point(self.position, self.intensity).sample_li(p)?;
        let lobe = self.lobe(-s.wi);
        if lobe <= 0.0 {
            return None;
        }
        s.value *= lobe;
        Some(s)
    }
}

impl AreaLight {
    /// The light's point-light limit (see the module documentation).
    pub fn far_field(&self) -> FarField {
        // A sphere's projected area is π r²; a flat emitter's, A cos θ.
        let (position, axis, area) = match self.shape {
            Shape::Sphere { center, radius } => (center, Vec3::ZERO, PI * radius * radius),
            Shape::Disk { center, normal, .. } => (center, normal, self.shape.area()),
            Shape::Quad {
                corner,
                edge1,
                edge2,
            } => (
                corner + 0.5 * (edge1 + edge2),
                edge1.cross(edge2).normalize_or_zero(),
                self.shape.area(),
            ),
        };
        FarField {
            position,
            axis,
            intensity: self.radiance * area,
            two_sided: self.two_sided,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_sphere_far_field_gives_its_exact_irradiance_above_the_horizon() {
        let light = AreaLight {
            shape: Shape::Sphere {
                center: Vec3::new(0.0, 3.0, 0.0),
                radius: 0.5,
            },
            radiance: Rgb::splat(2.0),
            two_sided: false,
        };
        let f = light.far_field();
        for p in [
            Vec3::ZERO,
            Vec3::new(1.0, 0.0, 0.5),
            Vec3::new(-2.0, 0.5, 1.0),
        ] {
            let s = f.sample_li(p).unwrap();
            let d = (Vec3::new(0.0, 3.0, 0.0) - p).length();
            let exact = PI * 2.0 * (0.5 / d) * (0.5 / d);
            assert!(
                (s.value.x - exact).abs() < 1e-5 * exact,
                "{} vs {exact}",
                s.value.x
            );
        }
    }

    #[test]
    fn disk_and_quad_far_fields_are_lambertian_emitters() {
        let disk = AreaLight {
            shape: Shape::Disk {
                center: Vec3::ZERO,
                normal: Vec3::NEG_Y,
                radius: 0.1,
            },
            radiance: Rgb::ONE,
            two_sided: false,
        };
        let f = disk.far_field();
        // Below, on the axis at d = 10 r: π Le r²/(r² + d²) within 1 %.
        let d = 1.0;
        let s = f.sample_li(Vec3::new(0.0, -d, 0.0)).unwrap();
        let exact = PI * 0.01 / (0.01 + d * d);
        assert!(
            (s.value.x / exact - 1.0).abs() < 0.011,
            "{}",
            s.value.x / exact
        );
        // 60° off the axis: half; above the disk (its back): nothing.
        let w = Vec3::new(60f32.to_radians().sin(), -60f32.to_radians().cos(), 0.0);
        let s = f.sample_li(2.0 * w).unwrap();
        assert!((s.value.x - 0.5 * PI * 0.01 / 4.0).abs() < 1e-6);
        assert!(f.sample_li(Vec3::Y).is_none());
        let both = AreaLight {
            two_sided: true,
            ..disk
        }
        .far_field();
        assert!(both.sample_li(Vec3::Y).is_some());
        // A quad: centre, area and normal of the parallelogram.
        let q = AreaLight {
            shape: Shape::Quad {
                corner: Vec3::new(1.0, 2.0, 0.0),
                edge1: Vec3::new(2.0, 0.0, 0.0),
                edge2: Vec3::new(0.0, 0.0, -1.0),
            },
            radiance: Rgb::splat(3.0),
            two_sided: false,
        }
        .far_field();
        assert_eq!(q.position, Vec3::new(2.0, 2.0, -0.5));
        assert_eq!(q.axis, Vec3::Y);
        assert_eq!(q.intensity, Rgb::splat(6.0));
    }
}
