//! glTF materials → penumbra materials (Lambertian for now), and textures.
//!
//! Exact: `baseColorFactor` (× `baseColorTexture` on TEXCOORD_0, sRGB-decoded)
//! as Lambertian albedo when the glTF BRDF has no specular part, i.e.
//! `metallicFactor = 0` and the dielectric layer is switched off by
//! `KHR_materials_specular.specularFactor = 0` (or by `ior = 1`, F0 = 0);
//! emission = `emissiveFactor × KHR_materials_emissive_strength`;
//! `doubleSided`. Everything else is approximated, and each material that
//! needed approximating gets ONE warning listing what was dropped.

use super::Loader;
use super::container::decode_data_uri;
use super::texture::decode_texture;
use crate::error::{Location, SceneError};
use crate::material::{Material, MaterialId};
use crate::paths::resolve_uri;
use crate::texture::TextureId;
use ::gltf::json::material::AlphaMode;
use ::gltf::json::texture::WrappingMode;
use ::gltf::json::validation::Checked;
use penumbra_shading::Rgb;
use penumbra_shading::bsdf::{Bsdf, Lambert};
use std::borrow::Cow;

/// Material extensions whose parameters are read (exactly or approximated
/// with a specific note); any other material extension is listed as ignored.
const READ_MATERIAL_EXTENSIONS: &[&str] = &[
    "KHR_materials_emissive_strength",
    "KHR_materials_specular",
    "KHR_materials_ior",
    "KHR_materials_transmission",
];

fn wrap_name(w: &Checked<WrappingMode>) -> &'static str {
    match w {
        Checked::Valid(WrappingMode::ClampToEdge) => "CLAMP_TO_EDGE",
        Checked::Valid(WrappingMode::MirroredRepeat) => "MIRRORED_REPEAT",
        Checked::Valid(WrappingMode::Repeat) => "REPEAT",
        Checked::Invalid => "invalid",
    }
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
        let [r, g, b, alpha] = pbr.base_color_factor.0;
        let base = Rgb::new(r, g, b);
        if !base.is_finite() || !alpha.is_finite() {
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

        // Metal part: F0 = baseColor, no diffuse.
        if metallic > 0.0 {
            notes.push(format!(
                "metallicFactor {metallic} (metal reflection dropped, baseColor used as diffuse albedo)"
            ));
        }
        // Dielectric specular layer: F0 = ((ior−1)/(ior+1))² · specularColor ·
        // specularFactor; absent when that product is 0.
        let f0 = ((ior - 1.0) / (ior + 1.0)).powi(2);
        let spec_max = spec_color[0].max(spec_color[1]).max(spec_color[2]);
        let specular_layer = metallic < 1.0 && spec_factor * spec_max * f0 > 0.0;
        if specular_layer {
            let mut s =
                format!("dielectric specular layer dropped (roughness {roughness}, ior {ior}");
            if specular.is_some() {
                s.push_str(&format!(", specularFactor {spec_factor}"));
            }
            s.push(')');
            notes.push(s);
        }
        if pbr.metallic_roughness_texture.is_some() && (metallic > 0.0 || specular_layer) {
            notes.push("metallicRoughnessTexture ignored".into());
        }
        if trans_factor > 0.0 {
            let tex = if transmission.is_some_and(|t| t.transmission_texture.is_some()) {
                " and transmissionTexture"
            } else {
                ""
            };
            notes.push(format!(
                "transmission {trans_factor}{tex} ignored (opaque; ior {ior} has no effect)"
            ));
        }
        match &m.alpha_mode {
            Checked::Valid(AlphaMode::Opaque) => {}
            Checked::Valid(mode) => {
                if alpha < 1.0 || pbr.base_color_texture.is_some() {
                    let mode = if *mode == AlphaMode::Mask {
                        "MASK"
                    } else {
                        "BLEND"
                    };
                    notes.push(format!("alphaMode {mode} ignored (rendered opaque)"));
                }
            }
            Checked::Invalid => {}
        }
        if m.normal_texture.is_some() {
            notes.push("normalTexture ignored".into());
        }
        if m.occlusion_texture.is_some() {
            notes.push("occlusionTexture ignored".into());
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
        if m.emissive_texture.is_some() && emission.max_element() > 0.0 {
            notes.push("emissiveTexture ignored (uniform emissiveFactor used)".into());
        }
        // Extensions the typed model does not carry: look at the raw JSON.
        let raw = &self.value["materials"][i];
        if let Some(obj) = raw["extensions"].as_object() {
            for key in obj.keys() {
                if !READ_MATERIAL_EXTENSIONS.contains(&key.as_str()) {
                    notes.push(format!("{key} ignored"));
                }
            }
        }

        let albedo_texture = match &pbr.base_color_texture {
            Some(info) => {
                if info.tex_coord != 0 {
                    notes.push(format!(
                        "baseColorTexture uses TEXCOORD_{} (TEXCOORD_0 used)",
                        info.tex_coord
                    ));
                }
                if let Some(obj) =
                    raw["pbrMetallicRoughness"]["baseColorTexture"]["extensions"].as_object()
                {
                    for key in obj.keys() {
                        notes.push(format!("{key} on baseColorTexture ignored"));
                    }
                }
                Some(self.texture(info.index.value(), &mut notes)?)
            }
            None => None,
        };

        if !notes.is_empty() {
            self.scene.warnings.push(format!(
                "{}: material '{name}' ({path}) approximated as Lambertian: {}",
                self.file.display(),
                notes.join("; ")
            ));
        }
        let id = self.scene.add_material(Material {
            name,
            bsdf: Bsdf::Lambert(Lambert::new(albedo)),
            albedo_texture,
            emission,
            double_sided: m.double_sided,
        });
        self.materials.insert(i, id);
        Ok(id)
    }

    /// The scene texture for glTF `textures[t]`, decoded on first use.
    /// Sampler settings that cannot be honoured are added to `notes`.
    fn texture(&mut self, t: usize, notes: &mut Vec<String>) -> Result<TextureId, SceneError> {
        let tpath = format!("textures[{t}]");
        let tex = self.root.textures.get(t).ok_or_else(|| {
            SceneError::at_path(
                self.file,
                tpath.clone(),
                format!("texture {t} does not exist"),
            )
        })?;
        if let Some(s) = tex.sampler.and_then(|s| self.root.samplers.get(s.value())) {
            for (axis, w) in [("wrapS", &s.wrap_s), ("wrapT", &s.wrap_t)] {
                if *w != Checked::Valid(WrappingMode::Repeat) {
                    notes.push(format!(
                        "{tpath} sampler {axis} {} treated as REPEAT",
                        wrap_name(w)
                    ));
                }
            }
        }
        if let Some(&id) = self.textures.get(&t) {
            return Ok(id);
        }
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
        let texture = decode_texture(&bytes, name).map_err(|e| {
            SceneError::at_path(self.file, ipath, format!("cannot decode image: {e}"))
        })?;
        self.scene.textures.push(texture);
        let id = self.scene.textures.len() - 1;
        self.textures.insert(t, id);
        Ok(id)
    }
}
