//! Rough conductor: GGX microfacets with conductor Fresnel.

use super::FresnelModel;
use crate::Rgb;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RoughConductor {
    pub eta: Rgb,
    pub k: Rgb,
    /// GGX α (= perceptual roughness²).
    pub alpha: f32,
    pub fresnel: FresnelModel,
}
