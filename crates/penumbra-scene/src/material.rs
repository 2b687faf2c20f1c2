//! Materials: a BSDF plus emission, as the loaders produce them.

use crate::texture::TextureId;
use penumbra_shading::Rgb;
use penumbra_shading::bsdf::{Bsdf, Lambert};

/// Index of a material in [`crate::Scene::materials`].
pub type MaterialId = usize;

/// A surface material.
#[derive(Clone, Debug, PartialEq)]
pub struct Material {
    pub name: String,
    /// The reflection model with its constant parameters.
    pub bsdf: Bsdf,
    /// Texture multiplying the base colour / albedo (linear RGB, UV set 0).
    pub albedo_texture: Option<TextureId>,
    /// glTF `metallicRoughnessTexture` (linear; roughness in G, metallic in
    /// B) multiplying `roughness` and `metallic` of a
    /// [`Bsdf::MetallicRoughness`] (UV set 0).
    pub metallic_roughness_texture: Option<TextureId>,
    /// Emitted radiance Le [W/(sr·m²)] from the front side (and the back if
    /// `double_sided`), times `emission_texture` where there is one.
    pub emission: Rgb,
    /// Texture multiplying `emission` (glTF `emissiveTexture`, sRGB-decoded,
    /// UV set 0).
    pub emission_texture: Option<TextureId>,
    /// Two-sided shading, and emission from both sides.
    pub double_sided: bool,
    /// Camera rays pass through the back faces (glTF `doubleSided: false`:
    /// back-face culling). Other rays still meet them, one-sided.
    pub cull_back_faces: bool,
}

impl Material {
    /// A two-sided Lambertian material with albedo ρ.
    pub fn lambert(name: impl Into<String>, albedo: Rgb) -> Self {
        Self {
            name: name.into(),
            bsdf: Bsdf::Lambert(Lambert::new(albedo)),
            albedo_texture: None,
            metallic_roughness_texture: None,
            emission: Rgb::ZERO,
            emission_texture: None,
            double_sided: true,
            cull_back_faces: false,
        }
    }

    /// The default material for objects that name none: grey ρ = 0.8.
    pub fn default_grey() -> Self {
        Self::lambert("default", Rgb::splat(0.8))
    }

    /// A front-side emitter with radiance `le` (black otherwise).
    pub fn emitter(name: impl Into<String>, le: Rgb) -> Self {
        Self {
            emission: le,
            double_sided: false,
            ..Self::lambert(name, Rgb::ZERO)
        }
    }

    /// Emitted radiance at texture coordinates `uv`: `emission`, times the
    /// emission texture (looked up in `textures`) where there is one.
    pub fn emission_at(&self, textures: &[crate::Texture], uv: glam::Vec2) -> Rgb {
        match self.emission_texture {
            Some(t) => self.emission * textures[t].sample(uv),
            None => self.emission,
        }
    }

    /// Power emitted by `area` m² of this material: Φ = π Le A per emitting
    /// side (a Lambertian emitter's exitance is π Le).
    pub fn emitted_power(&self, area: f32) -> Rgb {
        self.emission * (std::f32::consts::PI * area * if self.double_sided { 2.0 } else { 1.0 })
    }

    pub fn is_emissive(&self) -> bool {
        self.emission.max_element() > 0.0
    }
}
