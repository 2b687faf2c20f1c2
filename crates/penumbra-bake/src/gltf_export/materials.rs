//! Materials: penumbra's BSDFs as glTF metallic–roughness, exactly where
//! glTF can express the model and approximated (with a warning) otherwise.

use super::*;

/// A colour clamped to [0, 1], with a note when that changed it.
pub(super) fn unit_color(c: Rgb, what: &str, notes: &mut Vec<String>) -> Rgb {
    let c = if c.is_finite() { c } else { Rgb::ZERO };
    let d = c.clamp(Rgb::ZERO, Rgb::ONE);
    if d != c {
        notes.push(format!("{what} {c} clamped to [0, 1]"));
    }
    d
}

/// Full `KHR_materials_transmission`, noted as thin-walled (no
/// `KHR_materials_volume`); returns true (the material transmits).
fn thin_transmission(what: &str, ext: &mut Map<String, Value>, notes: &mut Vec<String>) -> bool {
    ext.insert(
        "KHR_materials_transmission".into(),
        json!({"transmissionFactor": 1.0}),
    );
    notes.push(format!(
        "{what} dielectric as KHR_materials_transmission (without KHR_materials_volume viewers treat it as thin-walled: no refraction offset)"
    ));
    true
}

impl Builder<'_> {
    pub(super) fn material(
        &mut self,
        id: usize,
        page: Option<u32>,
        uv0: bool,
    ) -> Result<usize, BakeError> {
        if let Some(&m) = self.material_index.get(&(id, page, uv0)) {
            return Ok(m);
        }
        let scene = self.scene;
        let mat = &scene.materials[id];
        let (mut m, notes) = self.convert(mat, page, uv0)?;
        // Once per material (it may be converted for several pages).
        let warning = format!("material '{}': {}", mat.name, notes.join("; "));
        if !notes.is_empty() && !self.warnings.contains(&warning) {
            self.warnings.push(warning);
        }
        let name = match page {
            Some(p) if self.bake.atlas.pages > 1 => format!("{} (atlas page {p})", mat.name),
            _ => mat.name.clone(),
        };
        m.insert("name".into(), json!(name));
        self.materials.push(Value::Object(m));
        let index = self.materials.len() - 1;
        self.material_index.insert((id, page, uv0), index);
        Ok(index)
    }

    /// The glTF material of `mat` (no name), with the occlusion of `page`;
    /// textures only when the primitive has TEXCOORD_0 (`uv0`). Returns the
    /// approximations made.
    pub(super) fn convert(
        &mut self,
        mat: &Material,
        page: Option<u32>,
        uv0: bool,
    ) -> Result<(Map<String, Value>, Vec<String>), BakeError> {
        let mut notes = Vec::new();
        let mut pbr = Map::new();
        let mut ext = Map::new();
        let mut transmissive = false;
        // Parameters of glTF's metallic–roughness model.
        let mut set = |base: Rgb, metallic: f32, roughness: f32, notes: &mut Vec<String>| {
            let base = unit_color(base, "base colour", notes);
            pbr.insert("baseColorFactor".into(), rgba(base));
            pbr.insert("metallicFactor".into(), num(metallic.clamp(0.0, 1.0)));
            pbr.insert("roughnessFactor".into(), num(roughness.clamp(0.0, 1.0)));
        };
        // The dielectric layer as KHR_materials_ior (+ transmission).
        let ior_ext = |ior: f32, ext: &mut Map<String, Value>, notes: &mut Vec<String>| {
            let ior = if ior.is_finite() && ior >= 1.0 {
                ior
            } else {
                notes.push(format!(
                    "index of refraction {ior} below 1 raised to 1 (glTF's ior is ≥ 1)"
                ));
                1.0
            };
            if ior != 1.5 {
                ext.insert("KHR_materials_ior".into(), json!({"ior": num(ior)}));
            }
        };
        let fresnel_note = |f: FresnelModel, notes: &mut Vec<String>| {
            if f == FresnelModel::Exact {
                notes.push(
                    "the exact conductor Fresnel of n + iκ is replaced by glTF's Schlick approximation from F0 (the base colour)".into(),
                );
            }
        };
        match mat.bsdf {
            Bsdf::Lambert(l) => {
                // specularFactor 0 switches glTF's dielectric layer off:
                // exactly Lambertian (and read back as Lambert by penumbra).
                set(l.albedo, 0.0, 1.0, &mut notes);
                ext.insert(
                    "KHR_materials_specular".into(),
                    json!({"specularFactor": 0.0}),
                );
            }
            Bsdf::MetallicRoughness(m) => {
                set(m.base_color, m.metallic, m.roughness, &mut notes);
                ior_ext(m.ior, &mut ext, &mut notes);
                if m.transmission > 0.0 {
                    ext.insert(
                        "KHR_materials_transmission".into(),
                        json!({"transmissionFactor": num(m.transmission.min(1.0))}),
                    );
                    transmissive = true;
                }
                if m.specular != 1.0 || m.specular_color != Rgb::ONE {
                    let mut s = Map::new();
                    if m.specular != 1.0 {
                        s.insert("specularFactor".into(), num(m.specular.clamp(0.0, 1.0)));
                    }
                    if m.specular_color != Rgb::ONE {
                        s.insert(
                            "specularColorFactor".into(),
                            rgb(m.specular_color.max(Rgb::ZERO)),
                        );
                    }
                    ext.insert("KHR_materials_specular".into(), Value::Object(s));
                }
            }
            Bsdf::PhongBlinn(p) => {
                let diffuse = p.kd * std::f32::consts::PI;
                let gamma = p.shininess.max(0.0);
                let spec = p.ks * p.variant.normal_incidence_albedo(gamma);
                // Blinn–Phong exponent ↔ microfacet width (Walter et al.
                // 2007): α = √(2 / (γ + 2)); roughness = √α.
                let alpha = (2.0 / (gamma + 2.0)).sqrt();
                let roughness = alpha.sqrt();
                set(diffuse, 0.0, roughness, &mut notes);
                let f0 = spec.max_element().clamp(0.0, 0.9);
                if f0 > 0.0 && spec.is_finite() {
                    // F0 through the index, its colour as specularColor.
                    let s = f0.sqrt();
                    let ior = (1.0 + s) / (1.0 - s);
                    ior_ext(ior, &mut ext, &mut notes);
                    let color = (spec / f0).clamp(Rgb::ZERO, Rgb::ONE);
                    if color != Rgb::ONE {
                        ext.insert(
                            "KHR_materials_specular".into(),
                            json!({"specularColorFactor": rgb(color)}),
                        );
                    }
                    notes.push(format!(
                        "Phong–Blinn ({:?}, γ = {gamma}) approximated by glTF metallic–roughness: base colour π·kd, roughness {roughness:.3} (GGX α = √(2/(γ+2))), specular F0 = ks·a(γ) = {spec} as ior {ior:.3}{}; glTF's diffuse part is weakened by the Fresnel term and its lobe is GGX, not Blinn–Phong",
                        p.variant,
                        if color != Rgb::ONE {
                            " and specularColorFactor"
                        } else {
                            ""
                        }
                    ));
                } else {
                    // No specular lobe: exactly Lambertian.
                    ext.insert(
                        "KHR_materials_specular".into(),
                        json!({"specularFactor": 0.0}),
                    );
                }
            }
            Bsdf::Mirror(m) => {
                set(m.reflectance, 1.0, 0.0, &mut notes);
                if m.reflectance != Rgb::ONE {
                    notes.push(
                        "ideal mirror as a smooth glTF metal with F0 = reflectance (Schlick: brighter towards grazing angles)".into(),
                    );
                }
            }
            Bsdf::Conductor(c) => {
                set(f0_from_ior(c.eta, c.k), 1.0, 0.0, &mut notes);
                fresnel_note(c.fresnel, &mut notes);
            }
            Bsdf::RoughConductor(c) => {
                set(
                    f0_from_ior(c.eta, c.k),
                    1.0,
                    c.alpha.max(0.0).sqrt(),
                    &mut notes,
                );
                fresnel_note(c.fresnel, &mut notes);
            }
            Bsdf::Dielectric(d) => {
                set(d.tint, 0.0, 0.0, &mut notes);
                ior_ext(d.eta, &mut ext, &mut notes);
                transmissive = thin_transmission("smooth", &mut ext, &mut notes);
            }
            Bsdf::RoughDielectric(d) => {
                set(d.tint, 0.0, d.alpha.max(0.0).sqrt(), &mut notes);
                ior_ext(d.eta, &mut ext, &mut notes);
                transmissive = thin_transmission("rough", &mut ext, &mut notes);
            }
        }
        // Textures (UV set 0): the colour texture multiplies every model's
        // base colour (penumbra's `tinted`), metallic–roughness data only
        // that model.
        let wants_textures =
            mat.albedo_texture.is_some() || mat.metallic_roughness_texture.is_some();
        if wants_textures && !uv0 {
            notes.push("textures dropped on meshes without TEXCOORD_0".into());
        } else {
            if let Some(t) = mat.albedo_texture
                && let Some(index) = self.scene_texture(t, true)?
            {
                pbr.insert("baseColorTexture".into(), json!({"index": index}));
            }
            if let (Some(t), Bsdf::MetallicRoughness(_)) =
                (mat.metallic_roughness_texture, mat.bsdf)
                && let Some(index) = self.scene_texture(t, false)?
            {
                pbr.insert("metallicRoughnessTexture".into(), json!({"index": index}));
            }
        }
        let mut m = Map::new();
        m.insert("pbrMetallicRoughness".into(), Value::Object(pbr));
        let e = if mat.emission.is_finite() {
            mat.emission.max(Rgb::ZERO)
        } else {
            Rgb::ZERO
        };
        let strength = e.max_element();
        if strength > 1.0 {
            m.insert("emissiveFactor".into(), rgb(e / strength));
            ext.insert(
                "KHR_materials_emissive_strength".into(),
                json!({"emissiveStrength": num(strength)}),
            );
        } else if strength > 0.0 {
            m.insert("emissiveFactor".into(), rgb(e));
        }
        if let Some(p) = page {
            let index = self.page_texture(p)?;
            m.insert(
                "occlusionTexture".into(),
                json!({"index": index, "texCoord": 1}),
            );
        }
        // penumbra shades transmissive surfaces from both sides.
        if mat.double_sided || transmissive {
            m.insert("doubleSided".into(), json!(true));
        }
        self.extensions_used.extend(ext.keys().cloned());
        if !ext.is_empty() {
            m.insert("extensions".into(), Value::Object(ext));
        }
        Ok((m, notes))
    }
}
