//! Native TOML scene loader. The format is specified, with an example per
//! feature, in `docs/scene-format.md`.
//!
//! Sections: `background`, `[environment]`, `[camera]`, `[render]`, `[[materials]]`,
//! `[[lights]]`, `[[objects]]`. Unknown keys are errors. Every error names
//! the file and either the line:column (syntax and type errors, which also
//! name the key path) or the key path such as `objects[2].radius` (value
//! errors, which also give the line), the value and the allowed range.

mod camera;
mod diag;
mod environment;
mod lights;
mod materials;
mod objects;
mod raw;
mod transform;
mod values;

use super::LoadOptions;
use crate::{Scene, SceneError};
use diag::Doc;
use penumbra_shading::Rgb;
use raw::RawScene;
use std::path::Path;
use values::ColorRange;

/// Loads a `.toml` scene file.
pub fn load_toml(path: &Path, options: &LoadOptions) -> Result<Scene, SceneError> {
    let bytes = super::read_file(path)?;
    let text =
        String::from_utf8(bytes).map_err(|_| SceneError::in_file(path, "not valid UTF-8"))?;
    load_toml_str(&text, path, options)
}

/// Parses TOML scene text; `path` names it in errors and anchors relative paths.
pub fn load_toml_str(text: &str, path: &Path, options: &LoadOptions) -> Result<Scene, SceneError> {
    let doc = Doc::parse(text, path)?;
    let raw: RawScene = doc.deserialize()?;
    build(&doc, options, &raw)
}

fn build(doc: &Doc<'_>, options: &LoadOptions, raw: &RawScene) -> Result<Scene, SceneError> {
    let mut scene = Scene::default();
    if let Some(bg) = &raw.background {
        scene.background = doc.rgb("background", bg, ColorRange::NonNegative)?;
    } else {
        scene.background = Rgb::ZERO;
    }
    if let Some(env) = &raw.environment {
        if raw.background.is_some() {
            return Err(doc.err(
                "environment",
                "give either background = ... or an [environment] table, not both",
            ));
        }
        environment::environment(doc, options, env, &mut scene)?;
    }
    if let Some(c) = &raw.camera {
        scene.camera = Some(camera::camera(doc, c)?);
    }
    if let Some(r) = &raw.render {
        scene.settings = camera::render(doc, r)?;
    }
    let (materials, by_name) = materials::materials(doc, &raw.materials)?;
    scene.materials = materials;
    (scene.lights, scene.area_lights) = lights::lights(doc, &raw.lights)?;
    if raw.objects.is_empty() {
        return Err(doc.whole(
            "the scene has no objects: add at least one [[objects]] table with a shape or a mesh (see docs/scene-format.md)",
        ));
    }
    objects::objects(doc, options, &raw.objects, &by_name, &mut scene)?;
    warn_unused_materials(doc, raw, &mut scene);
    Ok(scene)
}

/// A material defined in the file but used by no object is probably a typo.
fn warn_unused_materials(doc: &Doc<'_>, raw: &RawScene, scene: &mut Scene) {
    let mut used = vec![false; scene.materials.len()];
    for inst in &scene.instances {
        used[inst.material.unwrap_or(scene.meshes[inst.mesh].material)] = true;
    }
    for (i, m) in raw.materials.iter().enumerate() {
        if !used[i] {
            scene.warnings.push(format!(
                "{}: materials[{i}] '{}' is not used by any object",
                doc.file.display(),
                m.name.as_deref().unwrap_or("")
            ));
        }
    }
}
