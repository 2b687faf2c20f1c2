//! BSDFs. A closed set, so an enum over one struct per model (pbrt-v4 style).
//!
//! Every function works in the **local shading frame** (z = shading normal,
//! on the side of `wo` for two-sided materials) with unit directions pointing
//! away from the surface. `eval` returns f(wo, wi) in 1/sr **without** the
//! cosine; `pdf` is with respect to solid angle; `sample` returns the
//! weight f·cos θi / pdf.

mod lambert;

pub use lambert::Lambert;

use crate::Rgb;
use glam::Vec3;

/// One sampled direction of a BSDF.
#[derive(Clone, Copy, Debug)]
pub struct BsdfSample {
    /// Sampled incident direction (local frame).
    pub wi: Vec3,
    /// f(wo, wi) · |cos θi| / pdf.
    pub weight: Rgb,
    /// Solid-angle density of `wi`.
    pub pdf: f32,
}

/// The BSDF models penumbra knows.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Bsdf {
    Lambert(Lambert),
}

impl Bsdf {
    /// f(wo, wi) [1/sr], cosine not included.
    #[inline]
    pub fn eval(&self, wo: Vec3, wi: Vec3) -> Rgb {
        match self {
            Bsdf::Lambert(m) => m.eval(wo, wi),
        }
    }

    /// Solid-angle pdf of [`Bsdf::sample`] choosing `wi`.
    #[inline]
    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        match self {
            Bsdf::Lambert(m) => m.pdf(wo, wi),
        }
    }

    /// Samples `wi` from `u` ∈ [0,1)²; `None` if no direction is possible.
    #[inline]
    pub fn sample(&self, wo: Vec3, u: [f32; 2]) -> Option<BsdfSample> {
        match self {
            Bsdf::Lambert(m) => m.sample(wo, u),
        }
    }

    /// Hemispherical-directional reflectance used for the albedo AOV.
    pub fn albedo(&self) -> Rgb {
        match self {
            Bsdf::Lambert(m) => m.albedo,
        }
    }
}
