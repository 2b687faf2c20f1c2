//! `[[materials]]`: named materials, one `type` each.
//!
//! Keys shared by every type: `name`, `type`, `emission`, `double_sided`.
//! Each type adds its own parameters, and a key of another type is an
//! error naming the keys the type takes:
//!
//! | type | keys | model |
//! |---|---|---|
//! | `lambert` | `albedo` \| `kd` | `Lambert` |
//! | `phong` | `albedo` \| `kd`, `ks`, `shininess`, `variant` | `PhongBlinn` |
//! | `mirror` | `reflectance` | `Mirror` |
//! | `conductor` | `preset` \| `eta` + `k`, `roughness`, `fresnel` | `Conductor` (roughness 0) / `RoughConductor` (α = roughness²) |
//! | `dielectric` | `ior`, `tint`, `roughness`, `fresnel` | `Dielectric` (roughness 0) / `RoughDielectric` |
//! | `metallic-roughness` | `base_color`, `metallic`, `roughness`, `ior`, `transmission`, `specular`, `specular_color` | `MetallicRoughness` |
//!
//! Transmissive materials (dielectrics, metallic–roughness with
//! `transmission` > 0) are always two-sided: light has to cross them both
//! ways; `double_sided = false` on one is an error.

use super::diag::Doc;
use super::raw::{Floats, RawMaterial, num};
use super::values::ColorRange;
use crate::error::SceneError;
use crate::material::Material;
use penumbra_shading::Rgb;
use penumbra_shading::bsdf::{
    Bsdf, CONDUCTOR_PRESETS, Conductor, Dielectric, FresnelModel, Lambert, MetallicRoughness,
    Mirror, PhongBlinn, PhongVariant, RoughConductor, RoughDielectric, conductor_preset,
};
use std::collections::HashMap;
use std::f32::consts::PI;

/// Material types this version reads.
pub(super) const SUPPORTED: &[&str] = &[
    "lambert",
    "phong",
    "mirror",
    "conductor",
    "dielectric",
    "metallic-roughness",
];

/// `variant = "..."` of a phong material.
const PHONG_VARIANTS: &[(&str, PhongVariant)] = &[
    ("notes", PhongVariant::Notes),
    ("max-blinn", PhongVariant::MaxBlinn),
    ("halfway-squared", PhongVariant::HalfwaySquared),
    ("normalized", PhongVariant::Normalized),
];

/// Builds every material; returns them (in file order, so index = id) and
/// the name → id map.
pub(super) fn materials(
    doc: &Doc<'_>,
    raws: &[RawMaterial],
) -> Result<(Vec<Material>, HashMap<String, usize>), SceneError> {
    let mut out = Vec::with_capacity(raws.len());
    let mut by_name: HashMap<String, usize> = HashMap::new();
    for (i, raw) in raws.iter().enumerate() {
        let path = format!("materials[{i}]");
        let m = material(doc, &path, raw)?;
        if let Some(first) = by_name.get(&m.name) {
            return Err(doc.err(
                &format!("{path}.name"),
                format!(
                    "duplicate material name '{}' (already defined by materials[{first}]); names must be unique",
                    m.name
                ),
            ));
        }
        by_name.insert(m.name.clone(), i);
        out.push(m);
    }
    Ok((out, by_name))
}

fn material(doc: &Doc<'_>, path: &str, raw: &RawMaterial) -> Result<Material, SceneError> {
    let name = match raw.name.as_deref() {
        Some(n) if !n.trim().is_empty() => n.to_string(),
        Some(_) => return Err(doc.err(&format!("{path}.name"), "material name is empty")),
        None => {
            return Err(doc.err(
                path,
                "a material needs a name (objects refer to it by material = \"name\")",
            ));
        }
    };
    let kind = raw.kind.as_deref().ok_or_else(|| {
        doc.err(
            path,
            format!(
                "material '{name}' needs a type (supported: {})",
                SUPPORTED.join(", ")
            ),
        )
    })?;
    let p = P { doc, path, raw };
    let bsdf = match kind {
        "lambert" => p.lambert()?,
        "phong" => p.phong()?,
        "mirror" => p.mirror()?,
        "conductor" => p.conductor()?,
        "dielectric" => p.dielectric()?,
        "metallic-roughness" => p.metallic_roughness()?,
        k => {
            return Err(doc.err(
                &format!("{path}.type"),
                format!(
                    "unknown material type '{k}' (supported: {})",
                    SUPPORTED.join(", ")
                ),
            ));
        }
    };
    let emission = match &raw.emission {
        Some(e) => doc.rgb(&format!("{path}.emission"), e, ColorRange::NonNegative)?,
        None => Rgb::ZERO,
    };
    let transmissive = match &bsdf {
        Bsdf::Dielectric(_) | Bsdf::RoughDielectric(_) => true,
        Bsdf::MetallicRoughness(m) => m.transmission > 0.0,
        _ => false,
    };
    let double_sided = if transmissive {
        if raw.double_sided == Some(false) {
            return Err(doc.err(
                &format!("{path}.double_sided"),
                "a transmissive material (dielectric, or transmission > 0) is always two-sided: light crosses it both ways; remove double_sided = false",
            ));
        }
        true
    } else {
        // Emitters are front-side only unless told otherwise (as in the
        // reference scenes and glTF's emissive, doubleSided = false, materials).
        raw.double_sided.unwrap_or(emission.max_element() <= 0.0)
    };
    Ok(Material {
        name,
        bsdf,
        albedo_texture: None,
        metallic_roughness_texture: None,
        emission,
        emission_texture: None,
        double_sided,
        cull_back_faces: false,
        normal_map: None,
        occlusion_map: None,
        alpha: None,
    })
}

/// One `[[materials]]` table being read: the document, its key path and keys.
struct P<'a, 'd> {
    doc: &'a Doc<'d>,
    path: &'a str,
    raw: &'a RawMaterial,
}

impl P<'_, '_> {
    fn key(&self, k: &str) -> String {
        format!("{}.{k}", self.path)
    }

    fn only(&self, what: &str, allowed: &[&str]) -> Result<(), SceneError> {
        self.doc
            .only_keys(self.path, what, &self.raw.present_keys(), allowed)
    }

    /// An optional colour, `default` when absent.
    fn colour(
        &self,
        k: &str,
        v: &Option<Floats>,
        range: ColorRange,
        default: Rgb,
    ) -> Result<Rgb, SceneError> {
        match v {
            Some(v) => self.doc.rgb(&self.key(k), v, range),
            None => Ok(default),
        }
    }

    /// An optional number in `[lo, hi]`, `default` when absent.
    fn number(
        &self,
        k: &str,
        v: Option<f64>,
        lo: f64,
        hi: f64,
        default: f32,
    ) -> Result<f32, SceneError> {
        match v {
            Some(x) => self.doc.in_range(&self.key(k), x, lo, hi),
            None => Ok(default),
        }
    }

    /// `roughness` ∈ [0, 1] (default 0).
    fn roughness(&self) -> Result<f32, SceneError> {
        self.number("roughness", self.raw.roughness, 0.0, 1.0, 0.0)
    }

    /// `ior` finite and > 0 (default 1.5).
    fn ior(&self) -> Result<f32, SceneError> {
        match self.raw.ior {
            Some(x) => self.doc.positive(&self.key("ior"), x),
            None => Ok(1.5),
        }
    }

    /// `fresnel = "exact" | "schlick"` (default exact).
    fn fresnel(&self) -> Result<FresnelModel, SceneError> {
        match self.raw.fresnel.as_deref() {
            None | Some("exact") => Ok(FresnelModel::Exact),
            Some("schlick") => Ok(FresnelModel::Schlick),
            Some(f) => Err(self.doc.err(
                &self.key("fresnel"),
                format!("unknown fresnel '{f}' (allowed: exact, schlick)"),
            )),
        }
    }

    /// The diffuse part as (albedo ρ, the notes' kd = ρ/π), from `albedo`
    /// ρ ∈ [0,1] or `kd` ∈ [0, 1/π]; `None` if neither is given.
    fn diffuse(&self) -> Result<Option<(Rgb, Rgb)>, SceneError> {
        match (&self.raw.albedo, &self.raw.kd) {
            (Some(_), Some(_)) => Err(self.doc.err(
                &self.key("kd"),
                "give either albedo or kd (= albedo/π), not both",
            )),
            (Some(a), None) => {
                let albedo = self
                    .doc
                    .rgb(&self.key("albedo"), a, ColorRange::Reflectance)?;
                Ok(Some((albedo, albedo / PI)))
            }
            (None, Some(kd)) => {
                let kp = self.key("kd");
                let k = self.doc.rgb(&kp, kd, ColorRange::NonNegative)?;
                // kd = ρ/π with ρ ≤ 1 (a tiny tolerance for kd written as 1/π).
                if k.max_element() > (1.0 / PI) * (1.0 + 1e-6) {
                    return Err(self.doc.err(
                        &kp,
                        format!(
                            "kd must be in [0, 1/π ≈ 0.31831] in every channel (albedo = π·kd is a reflectance in [0, 1]), got {kd}"
                        ),
                    ));
                }
                Ok(Some(((k * PI).min(Rgb::ONE), k)))
            }
            (None, None) => Ok(None),
        }
    }

    /// `type = "lambert"`: `albedo` ρ ∈ [0,1]³, or the notes' `kd` = ρ/π.
    fn lambert(&self) -> Result<Bsdf, SceneError> {
        self.only("a lambert material", &["albedo", "kd"])?;
        let Some((albedo, _)) = self.diffuse()? else {
            return Err(self.doc.err(
                self.path,
                "a lambert material needs albedo = [r, g, b] (reflectance in [0, 1]) or kd = [r, g, b] (= albedo/π)",
            ));
        };
        Ok(Bsdf::Lambert(Lambert::new(albedo)))
    }

    /// `type = "phong"`: the notes' Phong–Blinn family. Diffuse `albedo` or
    /// `kd` (default 0), `ks` ≥ 0 (default 0; ≤ 1 for `normalized`, where it
    /// is the lobe's reflectance), `shininess` γ ≥ 0 (required), `variant`
    /// (default `normalized`).
    fn phong(&self) -> Result<Bsdf, SceneError> {
        self.only(
            "a phong material",
            &["albedo", "kd", "ks", "shininess", "variant"],
        )?;
        let variant = match self.raw.variant.as_deref() {
            None => PhongVariant::Normalized,
            Some(v) => match PHONG_VARIANTS.iter().find(|(n, _)| *n == v) {
                Some((_, variant)) => *variant,
                None => {
                    let names: Vec<&str> = PHONG_VARIANTS.iter().map(|(n, _)| *n).collect();
                    return Err(self.doc.err(
                        &self.key("variant"),
                        format!(
                            "unknown phong variant '{v}' (allowed: {})",
                            names.join(", ")
                        ),
                    ));
                }
            },
        };
        let kd = self.diffuse()?.map_or(Rgb::ZERO, |(_, kd)| kd);
        let range = if variant == PhongVariant::Normalized {
            ColorRange::Reflectance
        } else {
            ColorRange::NonNegative
        };
        let ks = self.colour("ks", &self.raw.ks, range, Rgb::ZERO)?;
        let Some(shininess) = self.raw.shininess else {
            return Err(self.doc.err(
                self.path,
                "a phong material needs shininess = γ (the exponent of cos δ, finite and >= 0)",
            ));
        };
        let shininess = non_negative(self.doc, &self.key("shininess"), shininess)?;
        Ok(Bsdf::PhongBlinn(PhongBlinn {
            kd,
            ks,
            shininess,
            variant,
        }))
    }

    /// `type = "mirror"`: `reflectance` ∈ [0,1]³ (default 1).
    fn mirror(&self) -> Result<Bsdf, SceneError> {
        self.only("a mirror material", &["reflectance"])?;
        let reflectance = self.colour(
            "reflectance",
            &self.raw.reflectance,
            ColorRange::Reflectance,
            Rgb::ONE,
        )?;
        Ok(Bsdf::Mirror(Mirror { reflectance }))
    }

    /// `type = "conductor"`: `preset` or `eta` + `k`, `roughness`, `fresnel`.
    fn conductor(&self) -> Result<Bsdf, SceneError> {
        self.only(
            "a conductor material",
            &["preset", "eta", "k", "roughness", "fresnel"],
        )?;
        let (eta, k) = match (&self.raw.preset, &self.raw.eta, &self.raw.k) {
            (Some(_), Some(_), _) | (Some(_), _, Some(_)) => {
                let k = if self.raw.eta.is_some() { "eta" } else { "k" };
                return Err(self
                    .doc
                    .err(&self.key(k), "give either preset or eta and k, not both"));
            }
            (Some(name), None, None) => conductor_preset(name).ok_or_else(|| {
                self.doc.err(
                    &self.key("preset"),
                    format!(
                        "unknown conductor preset '{name}' (known: {})",
                        CONDUCTOR_PRESETS.join(", ")
                    ),
                )
            })?,
            (None, Some(eta), Some(k)) => {
                let ep = self.key("eta");
                let e = self.doc.rgb(&ep, eta, ColorRange::NonNegative)?;
                if e.min_element() <= 0.0 {
                    return Err(self.doc.err(
                        &ep,
                        format!("eta must be finite and > 0 in every channel, got {eta}"),
                    ));
                }
                (e, self.doc.rgb(&self.key("k"), k, ColorRange::NonNegative)?)
            }
            (None, _, _) => {
                return Err(self.doc.err(
                    self.path,
                    format!(
                        "a conductor material needs preset = \"name\" ({}) or both eta = [r, g, b] (> 0) and k = [r, g, b] (>= 0)",
                        CONDUCTOR_PRESETS.join(", ")
                    ),
                ));
            }
        };
        let roughness = self.roughness()?;
        let fresnel = self.fresnel()?;
        Ok(if roughness == 0.0 {
            Bsdf::Conductor(Conductor { eta, k, fresnel })
        } else {
            Bsdf::RoughConductor(RoughConductor {
                eta,
                k,
                alpha: roughness * roughness,
                fresnel,
            })
        })
    }

    /// `type = "dielectric"`: `ior` (default 1.5), `tint` (default 1),
    /// `roughness` (default 0), `fresnel` (smooth only).
    fn dielectric(&self) -> Result<Bsdf, SceneError> {
        self.only(
            "a dielectric material",
            &["ior", "tint", "roughness", "fresnel"],
        )?;
        let eta = self.ior()?;
        let tint = self.colour("tint", &self.raw.tint, ColorRange::Reflectance, Rgb::ONE)?;
        let roughness = self.roughness()?;
        let fresnel = self.fresnel()?;
        if roughness == 0.0 {
            return Ok(Bsdf::Dielectric(Dielectric { eta, tint, fresnel }));
        }
        if self.raw.fresnel.is_some() {
            return Err(self.doc.err(
                &self.key("fresnel"),
                "fresnel applies only to a smooth dielectric (roughness = 0); a rough dielectric always uses the exact Fresnel equations",
            ));
        }
        Ok(Bsdf::RoughDielectric(RoughDielectric {
            eta,
            alpha: roughness * roughness,
            tint,
        }))
    }

    /// `type = "metallic-roughness"`: the glTF 2.0 model, glTF's defaults.
    fn metallic_roughness(&self) -> Result<Bsdf, SceneError> {
        self.only(
            "a metallic-roughness material",
            &[
                "base_color",
                "metallic",
                "roughness",
                "ior",
                "transmission",
                "specular",
                "specular_color",
            ],
        )?;
        Ok(Bsdf::MetallicRoughness(MetallicRoughness {
            base_color: self.colour(
                "base_color",
                &self.raw.base_color,
                ColorRange::Reflectance,
                Rgb::ONE,
            )?,
            metallic: self.number("metallic", self.raw.metallic, 0.0, 1.0, 1.0)?,
            roughness: self.number("roughness", self.raw.roughness, 0.0, 1.0, 1.0)?,
            ior: self.ior()?,
            transmission: self.number("transmission", self.raw.transmission, 0.0, 1.0, 0.0)?,
            specular: self.number("specular", self.raw.specular, 0.0, 1.0, 1.0)?,
            specular_color: self.colour(
                "specular_color",
                &self.raw.specular_color,
                ColorRange::NonNegative,
                Rgb::ONE,
            )?,
        }))
    }
}

/// A finite number ≥ 0.
fn non_negative(doc: &Doc<'_>, path: &str, x: f64) -> Result<f32, SceneError> {
    let y = x as f32;
    if y.is_finite() && y >= 0.0 {
        Ok(y)
    } else {
        let key = path.rsplit('.').next().unwrap_or(path);
        Err(doc.err(
            path,
            format!("{key} must be finite and >= 0, got {}", num(x)),
        ))
    }
}
