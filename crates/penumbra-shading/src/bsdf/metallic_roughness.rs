//! The glTF 2.0 metallic–roughness material (with KHR_materials_ior,
//! _transmission and _specular), built from the Lambert and GGX lobes.

use crate::Rgb;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MetallicRoughness {
    pub base_color: Rgb,
    pub metallic: f32,
    /// Perceptual roughness; GGX α = roughness².
    pub roughness: f32,
    /// KHR_materials_ior (default 1.5).
    pub ior: f32,
    /// KHR_materials_transmission factor (default 0).
    pub transmission: f32,
    /// KHR_materials_specular `specularFactor` (default 1).
    pub specular: f32,
    /// KHR_materials_specular `specularColorFactor` (default 1).
    pub specular_color: Rgb,
}
