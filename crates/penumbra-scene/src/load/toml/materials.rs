//! `[[materials]]`: named materials, one `type` each.
//!
//! Keys shared by every type: `name`, `type`, `emission`, `double_sided`.
//! Each type adds its own parameters (`lambert`: `albedo` or `kd`). New
//! types (phong, blinn, mirror, dielectric, conductor, ggx) add a match arm
//! and their keys; existing files keep meaning the same thing.

use super::diag::Doc;
use super::raw::RawMaterial;
use super::values::ColorRange;
use crate::error::SceneError;
use crate::material::Material;
use penumbra_shading::Rgb;
use penumbra_shading::bsdf::{Bsdf, Lambert};
use std::collections::HashMap;
use std::f32::consts::PI;

/// Material types this version reads.
pub(super) const SUPPORTED: &[&str] = &["lambert"];
/// Types reserved for later versions of the format.
const PLANNED: &[&str] = &["phong", "blinn", "mirror", "dielectric", "conductor", "ggx"];

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
    let bsdf = match kind {
        "lambert" => lambert(doc, path, raw)?,
        k if PLANNED.contains(&k) => {
            return Err(doc.err(
                &format!("{path}.type"),
                format!(
                    "material type '{k}' is not supported yet (supported: {})",
                    SUPPORTED.join(", ")
                ),
            ));
        }
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
    // Emitters are front-side only unless told otherwise (as in the
    // reference scenes and glTF's emissive, doubleSided = false, materials).
    let double_sided = raw.double_sided.unwrap_or(emission.max_element() <= 0.0);
    Ok(Material {
        name,
        bsdf,
        albedo_texture: None,
        emission,
        double_sided,
    })
}

/// `type = "lambert"`: `albedo` ρ ∈ [0,1]³, or the notes' `kd` = ρ/π.
fn lambert(doc: &Doc<'_>, path: &str, raw: &RawMaterial) -> Result<Bsdf, SceneError> {
    doc.only_keys(
        path,
        "a lambert material",
        &raw.present_keys(),
        &["albedo", "kd"],
    )?;
    let lambert = match (&raw.albedo, &raw.kd) {
        (Some(_), Some(_)) => {
            return Err(doc.err(
                &format!("{path}.kd"),
                "give either albedo or kd (= albedo/π), not both",
            ));
        }
        (Some(a), None) => {
            Lambert::new(doc.rgb(&format!("{path}.albedo"), a, ColorRange::Reflectance)?)
        }
        (None, Some(kd)) => {
            let kp = format!("{path}.kd");
            let k = doc.rgb(&kp, kd, ColorRange::NonNegative)?;
            // kd = ρ/π with ρ ≤ 1 (a tiny tolerance for kd written as 1/π).
            if k.max_element() > (1.0 / PI) * (1.0 + 1e-6) {
                return Err(doc.err(
                    &kp,
                    format!(
                        "kd must be in [0, 1/π ≈ 0.31831] in every channel (albedo = π·kd is a reflectance in [0, 1]), got {kd}"
                    ),
                ));
            }
            let mut l = Lambert::from_kd(k);
            l.albedo = l.albedo.min(Rgb::ONE);
            l
        }
        (None, None) => {
            return Err(doc.err(
                path,
                "a lambert material needs albedo = [r, g, b] (reflectance in [0, 1]) or kd = [r, g, b] (= albedo/π)",
            ));
        }
    };
    Ok(Bsdf::Lambert(lambert))
}
