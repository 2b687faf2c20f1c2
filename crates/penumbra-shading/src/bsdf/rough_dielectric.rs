//! Rough dielectric: GGX microfacet reflection and transmission (Walter et al. 2007).

use crate::Rgb;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RoughDielectric {
    /// Relative index η = n_inside / n_outside.
    pub eta: f32,
    /// GGX α (= perceptual roughness²).
    pub alpha: f32,
    /// Colour multiplying transmitted light.
    pub tint: Rgb,
}
