//! Analytic area lights: spheres, disks and quads emitting a constant
//! radiance Le. Few per scene, so the tracer intersects them with a linear
//! loop beside the triangle BVH.
//!
//! Power and radiance: a surface of area A emitting Le uniformly into the
//! hemisphere on one side radiates `Φ = π Le A` (twice that if it emits on
//! both sides); so `Le = Φ / (π A)` (or `Φ / (2π A)` when two-sided). A
//! sphere emits outwards: `Φ = π Le · 4π r²`.
//!
//! Sampling, as seen from a shading point p, with pdfs in solid angle:
//! sphere from outside — uniform in the cone of directions it subtends,
//! `pdf = 1 / (2π (1 − cos θmax))`, `sin θmax = r / |c − p|`; sphere from
//! inside, disk and quad — uniform in area, `pdf = d² / (A |cos θl|)`.

use super::LightSample;
use crate::Rgb;
use crate::frame::Frame;
use crate::sampling::{square_to_disk_concentric, square_to_uniform_sphere};
use glam::Vec3;
use std::f32::consts::PI;

/// The geometry of an area light, in world space.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Shape {
    /// Emits outwards (and inwards too when the light is two-sided).
    Sphere { center: Vec3, radius: f32 },
    /// Front side = `normal` (unit).
    Disk {
        center: Vec3,
        normal: Vec3,
        radius: f32,
    },
    /// Parallelogram `corner + a·edge1 + b·edge2`, a, b ∈ [0,1]; front side =
    /// `edge1 × edge2`.
    Quad {
        corner: Vec3,
        edge1: Vec3,
        edge2: Vec3,
    },
}

/// A ray hit on a [`Shape`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShapeHit {
    pub t: f32,
    pub p: Vec3,
    /// Unit front normal (outwards for spheres).
    pub n: Vec3,
}

impl Shape {
    /// An axis-aligned box (min, max) that contains the shape (for a disk,
    /// the box of the sphere around it).
    pub fn bounds(&self) -> (Vec3, Vec3) {
        match *self {
            Shape::Sphere { center, radius } | Shape::Disk { center, radius, .. } => {
                (center - Vec3::splat(radius), center + Vec3::splat(radius))
            }
            Shape::Quad {
                corner,
                edge1,
                edge2,
            } => {
                let far = corner + edge1 + edge2;
                let (a, b) = (corner + edge1, corner + edge2);
                (corner.min(far).min(a).min(b), corner.max(far).max(a).max(b))
            }
        }
    }

    pub fn area(&self) -> f32 {
        match *self {
            Shape::Sphere { radius, .. } => 4.0 * PI * radius * radius,
            Shape::Disk { radius, .. } => PI * radius * radius,
            Shape::Quad { edge1, edge2, .. } => edge1.cross(edge2).length(),
        }
    }

    /// Closest hit with `0 < t < tmax` along the ray `o + t d` (`d` unit).
    pub fn intersect(&self, o: Vec3, d: Vec3, tmax: f32) -> Option<ShapeHit> {
        match *self {
            Shape::Sphere { center, radius } => {
                let oc = o - center;
                let b = oc.dot(d);
                // |oc − b d|² is the squared distance of the line to the
                // centre; more accurate than b² − c for small spheres.
                let h = oc - b * d;
                let disc = radius * radius - h.length_squared();
                if disc < 0.0 {
                    return None;
                }
                let s = disc.sqrt();
                let t = if -b - s > 0.0 { -b - s } else { -b + s };
                if t <= 0.0 || t >= tmax {
                    return None;
                }
                let p = o + t * d;
                Some(ShapeHit {
                    t,
                    p,
                    n: (p - center) / radius,
                })
            }
            Shape::Disk {
                center,
                normal,
                radius,
            } => {
                let t = plane_t(o, d, center, normal)?;
                if t >= tmax {
                    return None;
                }
                let p = o + t * d;
                ((p - center).length_squared() <= radius * radius).then_some(ShapeHit {
                    t,
                    p,
                    n: normal,
                })
            }
            Shape::Quad {
                corner,
                edge1,
                edge2,
            } => {
                let nr = edge1.cross(edge2);
                let n2 = nr.length_squared();
                if n2 == 0.0 {
                    return None;
                }
                let n = nr / n2.sqrt();
                let t = plane_t(o, d, corner, n)?;
                if t >= tmax {
                    return None;
                }
                let p = o + t * d;
                let q = p - corner;
                // q = a e1 + b e2 ⇒ q × e2 = a (e1 × e2), e1 × q = b (e1 × e2).
                let a = q.cross(edge2).dot(nr) / n2;
                let b = edge1.cross(q).dot(nr) / n2;
                ((0.0..=1.0).contains(&a) && (0.0..=1.0).contains(&b)).then_some(ShapeHit {
                    t,
                    p,
                    n,
                })
            }
        }
    }

    /// Uniform point on the surface and its unit front normal (pdf 1/A).
    fn sample_area(&self, u: [f32; 2]) -> (Vec3, Vec3) {
        match *self {
            Shape::Sphere { center, radius } => {
                let n = square_to_uniform_sphere(u);
                (center + radius * n, n)
            }
            Shape::Disk {
                center,
                normal,
                radius,
            } => {
                let d = square_to_disk_concentric(u) * radius;
                let f = Frame::from_normal(normal);
                (center + f.s * d.x + f.t * d.y, normal)
            }
            Shape::Quad {
                corner,
                edge1,
                edge2,
            } => (
                corner + u[0] * edge1 + u[1] * edge2,
                edge1.cross(edge2).normalize_or_zero(),
            ),
        }
    }
}

/// Ray parameter of the plane through `q` with unit normal `n`, if positive.
fn plane_t(o: Vec3, d: Vec3, q: Vec3, n: Vec3) -> Option<f32> {
    let denom = d.dot(n);
    if denom == 0.0 {
        return None;
    }
    let t = (q - o).dot(n) / denom;
    (t > 0.0 && t.is_finite()).then_some(t)
}

/// An emitting shape with constant radiance.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AreaLight {
    pub shape: Shape,
    /// Emitted radiance Le [W/(sr·m²)] per band.
    pub radiance: Rgb,
    /// Emit from the back side too (for spheres: inwards too).
    pub two_sided: bool,
}

impl AreaLight {
    /// Number of emitting sides counted in the power: 2 for two-sided disks
    /// and quads, 1 otherwise (light emitted inside a sphere stays inside).
    fn sides(&self) -> f32 {
        match self.shape {
            Shape::Sphere { .. } => 1.0,
            _ if self.two_sided => 2.0,
            _ => 1.0,
        }
    }

    /// From radiant power Φ [W] per band: `Le = Φ / (π A sides)`.
    pub fn from_power(shape: Shape, power: Rgb, two_sided: bool) -> Self {
        let mut l = Self {
            shape,
            radiance: Rgb::ZERO,
            two_sided,
        };
        l.radiance = power / (PI * shape.area() * l.sides());
        l
    }

    /// Emitted power `Φ = π Le A` (× 2 when two-sided, spheres excepted).
    pub fn power(&self) -> Rgb {
        self.radiance * (PI * self.shape.area() * self.sides())
    }

    /// Radiance leaving the surface with front normal `n` towards `wo`.
    pub fn emitted(&self, n: Vec3, wo: Vec3) -> Rgb {
        if self.two_sided || n.dot(wo) > 0.0 {
            self.radiance
        } else {
            Rgb::ZERO
        }
    }

    /// Samples a direction from `p` towards the light (see the module docs
    /// for the densities). `value` = Le / pdf. `None` when the sampled point
    /// does not emit towards `p`.
    pub fn sample_li(&self, p: Vec3, u: [f32; 2]) -> Option<LightSample> {
        if let Shape::Sphere { center, radius } = self.shape {
            let to_c = center - p;
            let d2 = to_c.length_squared();
            if d2 > radius * radius {
                return self.sample_sphere_cone(p, center, radius, d2, u);
            }
        }
        let (q, n) = self.shape.sample_area(u);
        let d = q - p;
        let dist2 = d.length_squared();
        if dist2 == 0.0 {
            return None;
        }
        let dist = dist2.sqrt();
        let wi = d / dist;
        let le = self.emitted(n, -wi);
        let cos = wi.dot(n).abs();
        if le == Rgb::ZERO || cos <= 1e-7 {
            return None;
        }
        let pdf = dist2 / (self.shape.area() * cos);
        Some(LightSample {
            wi,
            distance: dist,
            value: le / pdf,
            pdf,
            is_delta: false,
        })
    }

    fn sample_sphere_cone(
        &self,
        p: Vec3,
        center: Vec3,
        radius: f32,
        d2: f32,
        u: [f32; 2],
    ) -> Option<LightSample> {
        let dc = d2.sqrt();
        let axis = (center - p) / dc;
        let sin2_max = radius * radius / d2;
        let cos_max = (1.0 - sin2_max).max(0.0).sqrt();
        // 1 − cos θmax without cancellation for small, distant spheres.
        let one_minus = sin2_max / (1.0 + cos_max);
        let one_minus_cos = u[0] * one_minus;
        let cos = 1.0 - one_minus_cos;
        let sin = (one_minus_cos * (2.0 - one_minus_cos)).max(0.0).sqrt();
        let phi = 2.0 * PI * u[1];
        let f = Frame::from_normal(axis);
        let wi = (f.s * (sin * phi.cos()) + f.t * (sin * phi.sin()) + f.n * cos).normalize();
        // Distance to the near side of the sphere along wi.
        let disc = (radius * radius - d2 * sin * sin).max(0.0);
        let dist = (dc * cos - disc.sqrt()).max(0.0);
        let pdf = 1.0 / (2.0 * PI * one_minus);
        Some(LightSample {
            wi,
            distance: dist,
            value: self.radiance / pdf,
            pdf,
            is_delta: false,
        })
    }

    /// Solid-angle density with which [`AreaLight::sample_li`] produces `wi`
    /// from `p` (0 if the ray misses the light).
    pub fn pdf_li(&self, p: Vec3, wi: Vec3) -> f32 {
        if let Shape::Sphere { center, radius } = self.shape {
            let d2 = (center - p).length_squared();
            if d2 > radius * radius {
                if self.shape.intersect(p, wi, f32::INFINITY).is_none() {
                    return 0.0;
                }
                let sin2_max = radius * radius / d2;
                let cos_max = (1.0 - sin2_max).max(0.0).sqrt();
                return (1.0 + cos_max) / (2.0 * PI * sin2_max);
            }
        }
        let Some(h) = self.shape.intersect(p, wi, f32::INFINITY) else {
            return 0.0;
        };
        let cos = wi.dot(h.n).abs();
        if cos <= 1e-7 || self.emitted(h.n, -wi) == Rgb::ZERO {
            return 0.0;
        }
        h.t * h.t / (self.shape.area() * cos)
    }
}
