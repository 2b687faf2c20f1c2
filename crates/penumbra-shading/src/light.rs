//! Lights. Abstract (delta) lights: directional, point and spot (SEEDS.md,
//! Light sources), evaluated through the notes' unified homogeneous form
//! ([`HomogeneousLight`]). Analytic area lights ([`AreaLight`]: sphere, disk,
//! quad) and the [`Environment`]; emissive triangles live in the tracer,
//! which owns the geometry. All share [`LightSample`].

mod area;
mod directional;
mod environment;
mod far_field;
mod homogeneous;
mod point;
mod spherical_harmonics;
mod spot;

pub use area::{AreaLight, Shape, ShapeHit};
pub use directional::DirectionalLight;
pub use environment::{Environment, EnvironmentMap};
pub use far_field::FarField;
pub use homogeneous::HomogeneousLight;
pub use point::{PointLight, range_window};
pub use spherical_harmonics::{SH_BAND, SH_COSINE_BANDS, Sh9, sh9_basis};
pub use spot::SpotLight;

use crate::Rgb;
use glam::Vec3;

/// Incident light at a shading point from one light sample.
#[derive(Clone, Copy, Debug)]
pub struct LightSample {
    /// Unit direction from the shading point towards the light.
    pub wi: Vec3,
    /// Distance to the light sample (∞ for directional lights).
    pub distance: f32,
    /// For delta lights: the irradiance on a surface *perpendicular* to `wi`
    /// [W/m²] (so the reflected radiance is `f · value · cos θ`). For area
    /// lights: emitted radiance divided by the solid-angle pdf.
    pub value: Rgb,
    /// Solid-angle pdf of `wi` (meaningless, set to 1, for delta lights).
    pub pdf: f32,
    /// True for lights with no extent (no MIS with BSDF sampling possible).
    pub is_delta: bool,
}

/// The abstract lights of the notes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Light {
    Point(PointLight),
    Directional(DirectionalLight),
    Spot(SpotLight),
}

impl Light {
    /// Incident light at `p`. `None` if the light cannot reach `p`.
    pub fn sample_li(&self, p: Vec3) -> Option<LightSample> {
        match self {
            Light::Point(l) => l.sample_li(p),
            Light::Directional(l) => l.sample_li(p),
            Light::Spot(l) => l.sample_li(p),
        }
    }

    /// Total emitted power Φ [W] per band. Directional lights need the scene
    /// radius `r`: the power crossing a disk of radius r, `π r² E`.
    pub fn power(&self, scene_radius: f32) -> Rgb {
        match self {
            Light::Point(l) => l.power(),
            Light::Directional(l) => {
                l.irradiance * std::f32::consts::PI * scene_radius * scene_radius
            }
            Light::Spot(l) => l.power(),
        }
    }

    /// Range cut-off distance (`f32::INFINITY` for none; directional
    /// lights have none).
    pub fn range(&self) -> f32 {
        match self {
            Light::Point(l) => l.range,
            Light::Directional(_) => f32::INFINITY,
            Light::Spot(l) => l.range,
        }
    }

    /// The unified homogeneous light (for spot lights without the cone
    /// falloff and range window).
    pub fn homogeneous(&self) -> HomogeneousLight {
        match self {
            Light::Point(l) => l.homogeneous(),
            Light::Directional(l) => l.homogeneous(),
            Light::Spot(l) => HomogeneousLight::point(l.position, l.intensity),
        }
    }

    /// The notes' homogeneous light position (y, w): w = 1 for point and spot
    /// lights, w = 0 for directional ones (y = direction *towards* the light).
    pub fn homogeneous_position(&self) -> glam::Vec4 {
        self.homogeneous().position
    }
}
