//! glTF materials → penumbra materials, and textures.
//!
//! Every material maps to the glTF metallic–roughness model
//! (`Bsdf::MetallicRoughness`): `baseColorFactor` (× `baseColorTexture`,
//! sRGB-decoded), `metallicFactor`, `roughnessFactor`
//! (× `metallicRoughnessTexture`, linear, roughness in G and metallic in B),
//! `KHR_materials_ior` (`ior`, default 1.5), `KHR_materials_transmission`
//! (`transmissionFactor`), `KHR_materials_specular` (`specularFactor`,
//! `specularColorFactor`); emission = `emissiveFactor ×
//! KHR_materials_emissive_strength` (× `emissiveTexture`, sRGB-decoded); `doubleSided` (forced on for
//! transmission > 0: light crosses the surface both ways; off, back faces
//! are culled for camera rays). `KHR_materials_unlit`: an emitter of the
//! base colour (× its texture) that reflects nothing.
//!
//! Exactly-Lambertian materials stay `Bsdf::Lambert` (base colour as albedo):
//! `metallicFactor = 0`, no transmission, and the dielectric layer switched
//! off (F0 = ((ior−1)/(ior+1))² · specularFactor · max specularColorFactor =
//! 0, i.e. `specularFactor = 0` or `ior = 1`).
//!
//! Samplers' wrap modes (REPEAT, CLAMP_TO_EDGE, MIRRORED_REPEAT) are kept
//! per texture; filters are not (the CPU's lookups are bilinear, the
//! raster engine's trilinear between its own mip levels).
//!
//! `normalTexture` with its `scale` (tangents: TANGENT, else MikkTSpace;
//! see [`crate::tangents`]).
//!
//! `occlusionTexture` with its strength (used by the raster engine's
//! environment term).
//!
//! Every texture reads the UV set its textureInfo names (`texCoord`, or
//! `KHR_texture_transform`'s `texCoord` override): TEXCOORD_0 or
//! TEXCOORD_1, with the extension's transform; normal maps use the tangent
//! frame of their own set.
//!
//! `alphaMode` MASK (with `alphaCutoff`, default 0.5) and BLEND: coverage
//! α = `baseColorFactor.a` × the base colour texture's alpha (linear), as
//! [`AlphaCoverage`]; a material that is everywhere covered stays opaque.
//! COLOR_0's alpha is not read (the loader drops it).
//!
//! Still ignored, with ONE warning per material listing it:
//! `transmissionTexture`, `specularTexture`, `specularColorTexture`,
//! TEXCOORD sets past 1 (set 0 read instead) and other extensions;
//! factors outside
//! [0, 1] are clamped (noted).

use super::Loader;
use super::container::decode_data_uri;
use super::texture::{decode_texture, is_eight_bit};
use crate::error::{Location, SceneError};
use crate::material::{AlphaCoverage, Material, MaterialId, NormalMap, OcclusionMap};
use crate::paths::resolve_uri;
use crate::texture::{Texels, Texture};
use crate::texture::{TextureId, Wrap};
use ::gltf::json::material::AlphaMode;
use ::gltf::json::texture::WrappingMode;
use ::gltf::json::validation::Checked;
use glam::{Affine2, Vec2};
use penumbra_shading::Rgb;
use penumbra_shading::bsdf::{Bsdf, Lambert, MetallicRoughness};
use std::borrow::Cow;

/// Material extensions whose parameters are read; any other material
/// extension is listed as ignored.
const READ_MATERIAL_EXTENSIONS: &[&str] = &[
    "KHR_materials_unlit",
    "KHR_materials_emissive_strength",
    "KHR_materials_specular",
    "KHR_materials_ior",
    "KHR_materials_transmission",
];

/// How a textureInfo maps a surface point to its texture: the UV set it
/// reads and its `KHR_texture_transform`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct UvMapping {
    /// 0 (`TEXCOORD_0`) or 1 (`TEXCOORD_1`).
    pub set: usize,
    pub transform: Affine2,
}

/// The UV set and `KHR_texture_transform` of a textureInfo (identity
/// without one): `uv' = T(offset) · R(rotation) · S(scale) · uv`, with R the
/// matrix of columns (cos r, −sin r) and (sin r, cos r): `u' = u cos r +
/// v sin r`, `v' = −u sin r + v cos r`. (Read as column-major GLSL, the
/// extension's own listing gives the transpose; Khronos'
/// TextureTransformTest, whose red marker shows a rotation the wrong way.)
/// The set is `tex_coord`, or the extension's `texCoord` override when it
/// has one (the extension says the override wins). Sets past 1, other
/// extensions on the textureInfo and malformed values are noted (set 0 and
/// identity used).
fn uv_mapping(
    info: &::gltf::json::Value,
    tex_coord: u32,
    what: &str,
    notes: &mut Vec<String>,
) -> UvMapping {
    let set = |asked: u64, notes: &mut Vec<String>| -> usize {
        if asked > 1 {
            notes.push(format!(
                "{what} uses TEXCOORD_{asked} (only TEXCOORD_0 and TEXCOORD_1 are read; TEXCOORD_0 used)"
            ));
            0
        } else {
            asked as usize
        }
    };
    let mut mapping = UvMapping {
        set: set(tex_coord.into(), notes),
        transform: Affine2::IDENTITY,
    };
    let Some(exts) = info["extensions"].as_object() else {
        return mapping;
    };
    for key in exts.keys().filter(|k| *k != "KHR_texture_transform") {
        notes.push(format!("{key} on {what} ignored"));
    }
    let Some(t) = exts.get("KHR_texture_transform") else {
        return mapping;
    };
    let pair = |key: &str, default: [f32; 2]| -> Option<Vec2> {
        match &t[key] {
            ::gltf::json::Value::Null => Some(Vec2::from(default)),
            v => {
                let a = v.as_array().filter(|a| a.len() == 2)?;
                let x = a[0].as_f64()? as f32;
                let y = a[1].as_f64()? as f32;
                (x.is_finite() && y.is_finite()).then_some(Vec2::new(x, y))
            }
        }
    };
    let rotation = match &t["rotation"] {
        ::gltf::json::Value::Null => Some(0.0),
        v => v.as_f64().map(|r| r as f32).filter(|r| r.is_finite()),
    };
    let (Some(offset), Some(scale), Some(rotation)) = (
        pair("offset", [0.0, 0.0]),
        pair("scale", [1.0, 1.0]),
        rotation,
    ) else {
        notes.push(format!("malformed KHR_texture_transform on {what} ignored"));
        return mapping;
    };
    if let Some(asked) = t["texCoord"].as_u64() {
        mapping.set = set(asked, notes);
    }
    let (sin, cos) = rotation.sin_cos();
    let r = glam::Mat2::from_cols(Vec2::new(cos, -sin), Vec2::new(sin, cos));
    mapping.transform =
        Affine2::from_mat2_translation(r * glam::Mat2::from_diagonal(scale), offset);
    mapping
}

impl Loader<'_> {
    /// The scene material for glTF `materials[i]`, converted on first use.
    pub(super) fn material(&mut self, i: usize) -> Result<MaterialId, SceneError> {
        if let Some(&id) = self.materials.get(&i) {
            return Ok(id);
        }
        let path = format!("materials[{i}]");
        let m = self.root.materials.get(i).ok_or_else(|| {
            SceneError::at_path(
                self.file,
                path.clone(),
                format!(
                    "material {i} does not exist (there are {})",
                    self.root.materials.len()
                ),
            )
        })?;
        let name = m.name.clone().unwrap_or_else(|| path.clone());
        let mut notes: Vec<String> = Vec::new();

        let pbr = &m.pbr_metallic_roughness;
        let [r, g, b, alpha_factor] = pbr.base_color_factor.0;
        let base = Rgb::new(r, g, b);
        if !base.is_finite() || !alpha_factor.is_finite() {
            return Err(SceneError::at_path(
                self.file,
                format!("{path}.pbrMetallicRoughness.baseColorFactor"),
                "baseColorFactor is not finite",
            ));
        }
        let albedo = base.clamp(Rgb::ZERO, Rgb::ONE);
        if albedo != base {
            notes.push(format!("baseColorFactor {base} clamped to [0, 1]"));
        }
        let metallic = pbr.metallic_factor.0;
        let roughness = pbr.roughness_factor.0;
        let ext = m.extensions.as_ref();
        let specular = ext.and_then(|e| e.specular.as_ref());
        let spec_factor = specular.map_or(1.0, |s| s.specular_factor.0);
        let spec_color = specular.map_or([1.0; 3], |s| s.specular_color_factor.0);
        let ior = ext.and_then(|e| e.ior.as_ref()).map_or(1.5, |x| x.ior.0);
        let transmission = ext.and_then(|e| e.transmission.as_ref());
        let trans_factor = transmission.map_or(0.0, |t| t.transmission_factor.0);
        let strength = ext
            .and_then(|e| e.emissive_strength.as_ref())
            .map_or(1.0, |s| s.emissive_strength.0);

        let ext_path = |e: &str, k: &str| format!("{path}.extensions.{e}.{k}");
        if !ior.is_finite() || ior <= 0.0 {
            return Err(SceneError::at_path(
                self.file,
                ext_path("KHR_materials_ior", "ior"),
                format!("ior must be finite and > 0, got {ior}"),
            ));
        }
        let file = self.file;
        let mut unit = |what: &str, x: f32| -> Result<f32, SceneError> {
            if !x.is_finite() {
                return Err(SceneError::at_path(
                    file,
                    path.clone(),
                    format!("{what} is not finite"),
                ));
            }
            let c = x.clamp(0.0, 1.0);
            if c != x {
                notes.push(format!("{what} {x} clamped to [0, 1]"));
            }
            Ok(c)
        };
        let metallic = unit("metallicFactor", metallic)?;
        let roughness = unit("roughnessFactor", roughness)?;
        let spec_factor = unit("specularFactor", spec_factor)?;
        let trans_factor = unit("transmissionFactor", trans_factor)?;
        let specular_color = Rgb::from(spec_color);
        if !specular_color.is_finite() || specular_color.min_element() < 0.0 {
            return Err(SceneError::at_path(
                self.file,
                ext_path("KHR_materials_specular", "specularColorFactor"),
                format!("specularColorFactor {specular_color} must be finite and >= 0"),
            ));
        }
        // The dielectric layer reflects F0 = ((ior−1)/(ior+1))² ·
        // specularColor · specularFactor; with that 0, no metal and no
        // transmission the glTF BRDF is exactly Lambertian.
        let f0 = ((ior - 1.0) / (ior + 1.0)).powi(2);
        let specular_layer = spec_factor * specular_color.max_element() * f0 > 0.0;
        let lambertian = metallic == 0.0 && !specular_layer && trans_factor == 0.0;
        if !lambertian {
            if let Some(t) = transmission.and_then(|t| t.transmission_texture.as_ref()) {
                notes.push(format!(
                    "transmissionTexture (textures[{}]) ignored (transmissionFactor used)",
                    t.index.value()
                ));
            }
            if let Some(s) = specular {
                if s.specular_texture.is_some() {
                    notes.push("specularTexture ignored (specularFactor used)".into());
                }
                if s.specular_color_texture.is_some() {
                    notes.push("specularColorTexture ignored (specularColorFactor used)".into());
                }
            }
        }
        let emission = Rgb::from(m.emissive_factor.0) * strength;
        if !emission.is_finite() || emission.min_element() < 0.0 {
            return Err(SceneError::at_path(
                self.file,
                format!("{path}.emissiveFactor"),
                format!(
                    "emission {emission} (emissiveFactor × emissiveStrength) must be finite and non-negative"
                ),
            ));
        }
        // Extensions the typed model does not carry: look at the raw JSON.
        let raw = &self.value["materials"][i];
        // emissiveTexture (sRGB colour) multiplies the emission; without
        // emission it has nothing to multiply.
        let emission_texture = match &m.emissive_texture {
            Some(info) if emission.max_element() > 0.0 => {
                let info_json = &raw["emissiveTexture"];
                let mapping = uv_mapping(info_json, info.tex_coord, "emissiveTexture", &mut notes);
                Some(self.texture(info.index.value(), mapping, &mut notes)?)
            }
            _ => None,
        };
        if let Some(obj) = raw["extensions"].as_object() {
            for key in obj.keys() {
                if !READ_MATERIAL_EXTENSIONS.contains(&key.as_str()) {
                    notes.push(format!("{key} ignored"));
                }
            }
        }

        // The base colour texture and its UV mapping (shared with alpha).
        let base_texture = pbr.base_color_texture.as_ref().map(|info| {
            let info_json = &raw["pbrMetallicRoughness"]["baseColorTexture"];
            let mapping = uv_mapping(info_json, info.tex_coord, "baseColorTexture", &mut notes);
            (info.index.value(), mapping)
        });
        let albedo_texture = match base_texture {
            Some((t, mapping)) => Some(self.texture(t, mapping, &mut notes)?),
            None => None,
        };

        // alphaMode: coverage α = baseColorFactor.a × the base colour
        // texture's alpha (linear, on its UV set and transform).
        let alpha_mode = match &m.alpha_mode {
            Checked::Valid(AlphaMode::Mask) => {
                let cutoff = m.alpha_cutoff.map_or(0.5, |c| c.0);
                if !cutoff.is_finite() {
                    return Err(SceneError::at_path(
                        self.file,
                        format!("{path}.alphaCutoff"),
                        "alphaCutoff is not finite",
                    ));
                }
                Some(crate::material::AlphaMode::Mask { cutoff })
            }
            Checked::Valid(AlphaMode::Blend) => Some(crate::material::AlphaMode::Blend),
            _ => None,
        };
        let alpha = match alpha_mode {
            Some(mode) => {
                let texture = match base_texture {
                    Some((t, mapping)) => self.alpha_texture(t, mapping, &mut notes)?,
                    None => None,
                };
                let coverage = AlphaCoverage {
                    mode,
                    factor: alpha_factor.clamp(0.0, 1.0),
                    texture,
                };
                // Everywhere present (α ≥ cutoff, or α = 1 for BLEND): opaque.
                let always = texture.is_none()
                    && match mode {
                        crate::material::AlphaMode::Mask { cutoff } => coverage.factor >= cutoff,
                        crate::material::AlphaMode::Blend => coverage.factor >= 1.0,
                    };
                (!always).then_some(coverage)
            }
            None => None,
        };

        // metallicRoughnessTexture (linear data: roughness in G, metallic in
        // B): only where the model has a specular part for it to modulate.
        let metallic_roughness_texture = match &pbr.metallic_roughness_texture {
            Some(info) if !lambertian => {
                let info_json = &raw["pbrMetallicRoughness"]["metallicRoughnessTexture"];
                let mapping = uv_mapping(
                    info_json,
                    info.tex_coord,
                    "metallicRoughnessTexture",
                    &mut notes,
                );
                Some(self.data_texture(info.index.value(), mapping, &mut notes)?)
            }
            _ => None,
        };

        // normalTexture (linear data, in the tangent frame of its UV set).
        let normal_map = match &m.normal_texture {
            Some(info) => {
                let info_json = &raw["normalTexture"];
                let mapping = uv_mapping(info_json, info.tex_coord, "normalTexture", &mut notes);
                let scale = info.scale;
                if !scale.is_finite() {
                    return Err(SceneError::at_path(
                        self.file,
                        format!("{path}.normalTexture.scale"),
                        "scale is not finite",
                    ));
                }
                Some(NormalMap {
                    texture: self.data_texture(info.index.value(), mapping, &mut notes)?,
                    scale,
                })
            }
            None => None,
        };
        // occlusionTexture (linear data, R).
        let occlusion_map = match &m.occlusion_texture {
            Some(info) => {
                let info_json = &raw["occlusionTexture"];
                let mapping = uv_mapping(info_json, info.tex_coord, "occlusionTexture", &mut notes);
                let strength = info.strength.0;
                if !strength.is_finite() {
                    return Err(SceneError::at_path(
                        self.file,
                        format!("{path}.occlusionTexture.strength"),
                        "strength is not finite",
                    ));
                }
                Some(OcclusionMap {
                    texture: self.data_texture(info.index.value(), mapping, &mut notes)?,
                    strength: strength.clamp(0.0, 1.0),
                })
            }
            None => None,
        };
        if !notes.is_empty() {
            self.scene.warnings.push(format!(
                "{}: material '{name}' ({path}): {}",
                self.file.display(),
                notes.join("; ")
            ));
        }
        let bsdf = if lambertian {
            Bsdf::Lambert(Lambert::new(albedo))
        } else {
            Bsdf::MetallicRoughness(MetallicRoughness {
                base_color: albedo,
                metallic,
                roughness,
                ior,
                transmission: trans_factor,
                specular: spec_factor,
                specular_color,
            })
        };
        // KHR_materials_unlit: the surface shows its base colour (× the
        // base colour texture) as it is, whatever the light: an emitter of
        // that radiance that reflects nothing.
        if raw["extensions"]["KHR_materials_unlit"].is_object() {
            let id = self.scene.add_material(Material {
                name,
                bsdf: Bsdf::Lambert(Lambert::new(Rgb::ZERO)),
                albedo_texture: None,
                metallic_roughness_texture: None,
                emission: albedo,
                emission_texture: albedo_texture,
                double_sided: m.double_sided,
                cull_back_faces: !m.double_sided,
                normal_map: None,
                occlusion_map: None,
                alpha,
            });
            self.materials.insert(i, id);
            return Ok(id);
        }
        let id = self.scene.add_material(Material {
            name,
            bsdf,
            normal_map,
            occlusion_map,
            alpha,
            albedo_texture,
            metallic_roughness_texture,
            emission,
            emission_texture,
            // Transmitted light crosses the surface both ways.
            double_sided: m.double_sided || trans_factor > 0.0,
            // glTF culls the back faces of single-sided materials.
            cull_back_faces: !m.double_sided && trans_factor <= 0.0,
        });
        self.materials.insert(i, id);
        Ok(id)
    }

    /// The scene texture for glTF `textures[t]` as colour (sRGB-decoded),
    /// decoded on first use. Sampler settings that cannot be honoured are
    /// added to `notes`.
    fn texture(
        &mut self,
        t: usize,
        mapping: UvMapping,
        notes: &mut Vec<String>,
    ) -> Result<TextureId, SceneError> {
        let key = (
            t,
            mapping.set,
            mapping.transform.to_cols_array().map(f32::to_bits),
        );
        if let Some(&id) = self.textures.get(&key) {
            self.sampler_wrap(t, notes)?;
            return Ok(id);
        }
        let wrap = self.sampler_wrap(t, notes)?;
        let (bytes, name, ipath) = self.image_bytes(t)?;
        let mut texture = decode_texture(&bytes, name).map_err(|e| {
            SceneError::at_path(self.file, ipath, format!("cannot decode image: {e}"))
        })?;
        texture.wrap = wrap;
        texture.uv_transform = mapping.transform;
        texture.uv_set = mapping.set;
        self.scene.textures.push(texture);
        let id = self.scene.textures.len() - 1;
        self.textures.insert(key, id);
        Ok(id)
    }

    /// The scene texture for glTF `textures[t]` as linear data (no transfer
    /// function: metallicRoughnessTexture). Not shared with colour uses.
    fn data_texture(
        &mut self,
        t: usize,
        mapping: UvMapping,
        notes: &mut Vec<String>,
    ) -> Result<TextureId, SceneError> {
        let id = self.linear_texture(t, mapping, notes, [0, 1, 2], false)?;
        // `linear_texture` gives `None` only when asked for alpha.
        id.ok_or_else(|| {
            SceneError::at_path(
                self.file,
                format!("textures[{t}]"),
                "the image has no channels",
            )
        })
    }

    /// The alpha channel of glTF `textures[t]` (linear, in every channel of
    /// a scene texture), or `None` when its image has no alpha channel.
    fn alpha_texture(
        &mut self,
        t: usize,
        mapping: UvMapping,
        notes: &mut Vec<String>,
    ) -> Result<Option<TextureId>, SceneError> {
        self.linear_texture(t, mapping, notes, [3, 3, 3], true)
    }

    /// A scene texture over glTF `textures[t]`'s image whose r, g, b are
    /// the image's RGBA channels `channels`, read as linear values in
    /// [0, 1] (8-bit images keep their bytes, [`Texels::Unorm8`]); `None`
    /// when `needs_alpha` and the image has no alpha channel.
    fn linear_texture(
        &mut self,
        t: usize,
        mapping: UvMapping,
        notes: &mut Vec<String>,
        channels: [usize; 3],
        needs_alpha: bool,
    ) -> Result<Option<TextureId>, SceneError> {
        let wrap = self.sampler_wrap(t, notes)?;
        let (bytes, name, ipath) = self.image_bytes(t)?;
        let img = image::load_from_memory(&bytes).map_err(|e| {
            SceneError::at_path(self.file, ipath, format!("cannot decode image: {e}"))
        })?;
        if needs_alpha && !img.color().has_alpha() {
            return Ok(None);
        }
        let [r, g, b] = channels;
        let texels = if is_eight_bit(&img) {
            let rgba = img.to_rgba8();
            Texels::Unorm8(rgba.pixels().map(|p| [p[r], p[g], p[b], 0]).collect())
        } else {
            let rgba = img.to_rgba32f();
            Texels::Linear(rgba.pixels().map(|p| Rgb::new(p[r], p[g], p[b])).collect())
        };
        let texture = Texture {
            name,
            width: img.width(),
            height: img.height(),
            texels,
            wrap,
            uv_transform: mapping.transform,
            uv_set: mapping.set,
        };
        self.scene.textures.push(texture);
        Ok(Some(self.scene.textures.len() - 1))
    }

    /// The wrap modes of `textures[t]`'s sampler (REPEAT without one); an
    /// invalid mode is noted and read as REPEAT.
    fn sampler_wrap(&self, t: usize, notes: &mut Vec<String>) -> Result<[Wrap; 2], SceneError> {
        let tpath = format!("textures[{t}]");
        let tex = self.root.textures.get(t).ok_or_else(|| {
            SceneError::at_path(
                self.file,
                tpath.clone(),
                format!("texture {t} does not exist"),
            )
        })?;
        let mut wrap = [Wrap::Repeat; 2];
        if let Some(s) = tex.sampler.and_then(|s| self.root.samplers.get(s.value())) {
            for (slot, (axis, w)) in [("wrapS", &s.wrap_s), ("wrapT", &s.wrap_t)]
                .into_iter()
                .enumerate()
            {
                wrap[slot] = match w {
                    Checked::Valid(WrappingMode::Repeat) => Wrap::Repeat,
                    Checked::Valid(WrappingMode::ClampToEdge) => Wrap::ClampToEdge,
                    Checked::Valid(WrappingMode::MirroredRepeat) => Wrap::MirroredRepeat,
                    Checked::Invalid => {
                        notes.push(format!("{tpath} sampler {axis} is invalid, read as REPEAT"));
                        Wrap::Repeat
                    }
                };
            }
        }
        Ok(wrap)
    }

    /// The encoded bytes of `textures[t]`'s image, a name for it, and its
    /// key path.
    fn image_bytes(&self, t: usize) -> Result<(Vec<u8>, String, String), SceneError> {
        let tpath = format!("textures[{t}]");
        let tex = &self.root.textures[t];
        let src = tex.source.value();
        let ipath = format!("images[{src}]");
        let img = self.root.images.get(src).ok_or_else(|| {
            SceneError::at_path(
                self.file,
                format!("{tpath}.source"),
                format!("image {src} does not exist"),
            )
        })?;
        let (bytes, label): (Cow<[u8]>, String) = if let Some(uri) = &img.uri {
            if uri.starts_with("data:") {
                let data = decode_data_uri(uri)
                    .map_err(|e| SceneError::at_path(self.file, format!("{ipath}.uri"), e))?;
                (data.into(), format!("{ipath} (data URI)"))
            } else {
                let file = resolve_uri(
                    self.file,
                    uri,
                    &self.options.allowed_absolute_paths,
                    Location::Path(format!("{ipath}.uri")),
                )?;
                let data = std::fs::read(&file).map_err(|e| {
                    SceneError::at_path(
                        self.file,
                        format!("{ipath}.uri"),
                        format!("cannot read image file '{}': {e}", file.display()),
                    )
                })?;
                (data.into(), uri.clone())
            }
        } else if let Some(v) = img.buffer_view {
            let data = self.view_bytes(v.value())?.to_vec();
            (data.into(), format!("{ipath} (bufferView {})", v.value()))
        } else {
            return Err(SceneError::at_path(
                self.file,
                ipath,
                "image has neither a uri nor a bufferView",
            ));
        };
        let name = img.name.clone().unwrap_or(label);
        Ok((bytes.into_owned(), name, ipath))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn texture_transform_is_offset_after_rotation_after_scale() {
        let json: ::gltf::json::Value = ::gltf::json::deserialize::from_str(
            r#"{"index": 0, "extensions": {"KHR_texture_transform":
                {"offset": [0.5, 0.25], "rotation": 1.5707963, "scale": [2, 3]}}}"#,
        )
        .unwrap();
        let mut notes = Vec::new();
        let m = uv_mapping(&json, 0, "baseColorTexture", &mut notes);
        assert!(notes.is_empty(), "{notes:?}");
        assert_eq!(m.set, 0);
        let t = m.transform;
        // (u, v) = (1, 0): scaled (2, 0); rotated by 90° with
        // u' = u cos r + v sin r, v' = −u sin r + v cos r: (0, −2); offset: (0.5, −1.75).
        let p = t.transform_point2(Vec2::new(1.0, 0.0));
        assert!((p - Vec2::new(0.5, -1.75)).length() < 1e-5, "{p}");
        // (0, 1): scaled (0, 3); rotated (3, 0); offset (3.5, 0.25).
        let q = t.transform_point2(Vec2::new(0.0, 1.0));
        assert!((q - Vec2::new(3.5, 0.25)).length() < 1e-5, "{q}");
        let plain: ::gltf::json::Value =
            ::gltf::json::deserialize::from_str(r#"{"index": 0}"#).unwrap();
        let identity = |set| UvMapping {
            set,
            transform: Affine2::IDENTITY,
        };
        assert_eq!(uv_mapping(&plain, 0, "x", &mut notes), identity(0));
        assert_eq!(uv_mapping(&plain, 1, "x", &mut notes), identity(1));
        assert!(notes.is_empty(), "{notes:?}");
        let bad: ::gltf::json::Value = ::gltf::json::deserialize::from_str(
            r#"{"extensions": {"KHR_texture_transform": {"scale": [1]}, "EXT_other": {}}}"#,
        )
        .unwrap();
        assert_eq!(uv_mapping(&bad, 0, "x", &mut notes), identity(0));
        assert_eq!(notes.len(), 2, "{notes:?}");
    }

    /// The extension's `texCoord` overrides the textureInfo's; sets past 1
    /// are noted and read as set 0.
    #[test]
    fn uv_sets_follow_tex_coord_and_its_override() {
        let json =
            |s: &str| -> ::gltf::json::Value { ::gltf::json::deserialize::from_str(s).unwrap() };
        let mut notes = Vec::new();
        let overridden = json(r#"{"extensions": {"KHR_texture_transform": {"texCoord": 1}}}"#);
        assert_eq!(uv_mapping(&overridden, 0, "x", &mut notes).set, 1);
        let back = json(r#"{"extensions": {"KHR_texture_transform": {"texCoord": 0}}}"#);
        assert_eq!(uv_mapping(&back, 1, "x", &mut notes).set, 0);
        assert!(notes.is_empty(), "{notes:?}");
        assert_eq!(
            uv_mapping(&json("{}"), 2, "occlusionTexture", &mut notes).set,
            0
        );
        assert_eq!(notes.len(), 1, "{notes:?}");
        assert!(notes[0].contains("TEXCOORD_2"), "{notes:?}");
    }
}
