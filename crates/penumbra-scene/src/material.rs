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
    /// Tangent-space normal map on UV set 0 (glTF `normalTexture`).
    pub normal_map: Option<NormalMap>,
    /// Baked ambient occlusion on UV set 0 (glTF `occlusionTexture`): the
    /// raster engine's environment term only (the tracer finds occlusion
    /// itself).
    pub occlusion_map: Option<OcclusionMap>,
    /// Coverage of the surface (glTF `alphaMode` MASK or BLEND); `None`:
    /// opaque.
    pub alpha: Option<AlphaCoverage>,
}

/// How a surface's coverage α acts (glTF `alphaMode`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum AlphaMode {
    /// Present where α ≥ `cutoff`, absent elsewhere (glTF MASK).
    Mask { cutoff: f32 },
    /// Present with probability α: a ray meets the surface, or passes
    /// through it, at random (stochastic transparency, Enderton et al.
    /// 2010), so that on average the surface contributes α of its
    /// radiance and what lies behind it 1 − α (glTF BLEND's
    /// `α · C_surface + (1 − α) · C_behind`).
    Blend,
}

/// A surface's coverage α = `factor` × the texture's R channel (glTF:
/// `baseColorFactor.a` × `baseColorTexture.a`, on the base colour's UV
/// set and transform; the vertex colour's alpha is not read).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AlphaCoverage {
    pub mode: AlphaMode,
    pub factor: f32,
    pub texture: Option<TextureId>,
}

impl AlphaCoverage {
    /// α at texture coordinates `uv` (in the UV set of the alpha texture,
    /// [`crate::Texture::uv_set`]).
    pub fn alpha_at(&self, textures: &[crate::Texture], uv: glam::Vec2) -> f32 {
        match self.texture {
            Some(t) => self.factor * textures[t].sample(uv).x,
            None => self.factor,
        }
    }

    /// Whether the surface is present where its coverage is `alpha`, for a
    /// uniform random number `u` in [0, 1) (used by BLEND only).
    pub fn covers(&self, alpha: f32, u: f32) -> bool {
        match self.mode {
            AlphaMode::Mask { cutoff } => alpha >= cutoff,
            AlphaMode::Blend => u < alpha,
        }
    }
}

/// glTF `occlusionTexture`: ambient occlusion in the texture's R channel,
/// applied to ambient (environment) light only, as
/// `1 + strength · (R − 1)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OcclusionMap {
    pub texture: TextureId,
    pub strength: f32,
}

/// A tangent-space normal map (glTF `normalTexture`, linear data): the
/// shading normal is `normalize(T x + B y + N z)` with `(x, y, z) =
/// (2 texel − 1) · (scale, scale, 1)`, T the mesh tangent, B = w · N × T,
/// N the interpolated normal (OpenGL's convention: +y along +v's tangent
/// frame, green up).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NormalMap {
    pub texture: TextureId,
    pub scale: f32,
}

impl NormalMap {
    /// The shading normal for a texel `texel` (in [0, 1]³) in the frame of
    /// unit normal `n` and tangent `t` (xyz, w = handedness); `n` itself
    /// when the frame is degenerate.
    pub fn perturb(&self, texel: glam::Vec3, n: glam::Vec3, t: glam::Vec4) -> glam::Vec3 {
        let m = (2.0 * texel - 1.0) * glam::Vec3::new(self.scale, self.scale, 1.0);
        // Gram–Schmidt: the tangent made orthogonal to n.
        let tangent = (t.truncate() - n * n.dot(t.truncate())).normalize_or_zero();
        if tangent == glam::Vec3::ZERO {
            return n;
        }
        let bitangent = n.cross(tangent) * if t.w < 0.0 { -1.0 } else { 1.0 };
        let mapped = (tangent * m.x + bitangent * m.y + n * m.z).normalize_or_zero();
        if mapped == glam::Vec3::ZERO {
            n
        } else {
            mapped
        }
    }
}

impl Material {
    /// Every texture the material reads (a texture may appear twice).
    pub fn textures(&self) -> impl Iterator<Item = TextureId> {
        [
            self.albedo_texture,
            self.metallic_roughness_texture,
            self.emission_texture,
            self.normal_map.map(|m| m.texture),
            self.occlusion_map.map(|m| m.texture),
            self.alpha.and_then(|a| a.texture),
        ]
        .into_iter()
        .flatten()
    }

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
            normal_map: None,
            occlusion_map: None,
            alpha: None,
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

    /// Emitted radiance at a point whose UV sets 0 and 1 are `uvs`:
    /// `emission`, times the emission texture (looked up in `textures`)
    /// where there is one.
    pub fn emission_at(&self, textures: &[crate::Texture], uvs: [glam::Vec2; 2]) -> Rgb {
        match self.emission_texture {
            Some(t) => self.emission * textures[t].lookup(uvs),
            None => self.emission,
        }
    }

    /// Power emitted by `area` m² of this material: Φ = π Le A per emitting
    /// side (a Lambertian emitter's exitance is π Le).
    pub fn emitted_power(&self, area: f32) -> Rgb {
        self.emission * (std::f32::consts::PI * area * if self.double_sided { 2.0 } else { 1.0 })
    }

    /// Whether the material has an alpha mask (glTF MASK).
    pub fn is_masked(&self) -> bool {
        matches!(self.alpha.map(|a| a.mode), Some(AlphaMode::Mask { .. }))
    }

    /// Whether the material blends (glTF BLEND).
    pub fn is_blended(&self) -> bool {
        matches!(self.alpha.map(|a| a.mode), Some(AlphaMode::Blend))
    }

    pub fn is_emissive(&self) -> bool {
        self.emission.max_element() > 0.0
    }
}

#[cfg(test)]
mod normal_map_tests {
    use super::*;
    use glam::{Vec3, Vec4};

    #[test]
    fn perturb_follows_tangent_bitangent_and_normal() {
        let map = |scale| NormalMap { texture: 0, scale };
        let n = Vec3::Z;
        let t = Vec4::new(2.0, 0.0, 0.5, 1.0); // not unit, not orthogonal to n
        let close = |a: Vec3, b: Vec3| (a - b).length() < 1e-6;
        // The flat texel (½, ½, 1) keeps n.
        assert!(close(map(1.0).perturb(Vec3::new(0.5, 0.5, 1.0), n, t), n));
        // Red full: along the tangent (x after Gram–Schmidt); green full:
        // along w · n × t = +y, or −y when w = −1.
        assert!(close(
            map(1.0).perturb(Vec3::new(1.0, 0.5, 0.5), n, t),
            Vec3::X
        ));
        assert!(close(
            map(1.0).perturb(Vec3::new(0.5, 1.0, 0.5), n, t),
            Vec3::Y
        ));
        let left = Vec4::new(2.0, 0.0, 0.5, -1.0);
        assert!(close(
            map(1.0).perturb(Vec3::new(0.5, 1.0, 0.5), n, left),
            -Vec3::Y
        ));
        // scale multiplies x and y: (0.25 · 2, 0, 0.5) → 45° towards x.
        let m = map(2.0).perturb(Vec3::new(0.625, 0.5, 0.75), n, t);
        assert!(close(m, Vec3::new(1.0, 0.0, 1.0).normalize()), "{m}");
        // A tangent along n gives no frame: n.
        assert!(close(
            map(1.0).perturb(Vec3::new(1.0, 0.5, 0.5), n, Vec4::new(0.0, 0.0, 1.0, 1.0)),
            n
        ));
    }
}
