//! The Phong–Blinn family of the notes (SEEDS.md, BRDF): a Lambertian part
//! `kd` plus a specular lobe around the halfway vector, in four variants.

use crate::Rgb;

/// Which Phong–Blinn specular lobe (h = normalize(l + v), cos δ = n·h, γ = shininess).
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum PhongVariant {
    /// The notes exactly: `fr = ks (cos⁺δ)^γ / cos⁺θin` (not reciprocal).
    Notes,
    /// Reciprocal max-Blinn: `fr = ks (cos δ)^γ / max(cos θ, cos θ')`.
    MaxBlinn,
    /// Reciprocal `fr = ks (cos δ)^γ / |l + v|²` (notes 003).
    HalfwaySquared,
    /// Energy-conserving normalised Blinn–Phong: `fr = ks (γ + 8)/(8π) (cos δ)^γ`.
    Normalized,
}

/// Diffuse `kd` + specular `ks` lobe (linearity: a material is a sum of lobes).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PhongBlinn {
    /// The notes' diffuse coefficient kd [1/sr] (= ρ/π).
    pub kd: Rgb,
    /// Specular coefficient (units as the variant's formula).
    pub ks: Rgb,
    /// Shininess γ ≥ 0.
    pub shininess: f32,
    pub variant: PhongVariant,
}
