//! `[environment]`: what rays that leave the scene see, and a light.
//!
//! `type = "constant"` takes `radiance` [W/(sr·m²)] or `luminance_nits`
//! [cd/m²] (÷ 683), times `color`. `type = "map"` takes `file` (a
//! latitude–longitude `.hdr` or `.exr`, relative to the scene file),
//! `scale` (number or `[r, g, b]`, default 1) and `rotate_deg` about +y
//! (default 0); the convention is in `penumbra_shading::light::Environment`
//! and docs/scene-format.md.

use super::diag::Doc;
use super::lights::{ENVIRONMENT_UNITS, pick_quantity};
use super::raw::RawEnvironment;
use super::values::ColorRange;
use crate::environment::environment_from_image;
use crate::error::{Location, SceneError};
use crate::load::LoadOptions;
use crate::paths::resolve_uri;
use crate::scene::Scene;
use penumbra_shading::Rgb;
use std::sync::Arc;

const KINDS: &str = "constant, map";

pub(super) fn environment(
    doc: &Doc<'_>,
    options: &LoadOptions,
    raw: &RawEnvironment,
    scene: &mut Scene,
) -> Result<(), SceneError> {
    let path = "environment";
    let kind = raw
        .kind
        .as_deref()
        .ok_or_else(|| doc.err(path, format!("[environment] needs a type ({KINDS})")))?;
    match kind {
        "constant" => {
            let keys = ["radiance", "luminance_nits", "color"];
            doc.only_keys(path, "a constant environment", &raw.present_keys(), &keys)?;
            let value = |k: &str| match k {
                "radiance" => raw.radiance.as_ref(),
                "luminance_nits" => raw.luminance_nits.as_ref(),
                _ => None,
            };
            let (_, l) = pick_quantity(doc, path, ENVIRONMENT_UNITS, value, raw.color.as_ref())?;
            scene.background = l;
            Ok(())
        }
        "map" => {
            let keys = ["file", "scale", "rotate_deg"];
            doc.only_keys(path, "an environment map", &raw.present_keys(), &keys)?;
            let fp = "environment.file";
            let uri = raw.file.as_deref().ok_or_else(|| {
                doc.err(
                    path,
                    "an environment map needs file = \"sky.hdr\" (.hdr or .exr)",
                )
            })?;
            let scale = match &raw.scale {
                Some(s) => doc.rgb("environment.scale", s, ColorRange::NonNegative)?,
                None => Rgb::ONE,
            };
            let rotate = match raw.rotate_deg {
                Some(r) => doc.in_range("environment.rotate_deg", r, -360.0, 360.0)?,
                None => 0.0,
            };
            let resolved = resolve_uri(
                doc.file,
                uri,
                &options.allowed_absolute_paths,
                Location::Path(fp.into()),
            )
            .map_err(|e| doc.reanchor(fp, e))?;
            let map = image::open(&resolved)
                .map_err(|e| e.to_string())
                .and_then(|image| environment_from_image(image, scale, rotate.to_radians()))
                .map_err(|e| {
                    doc.err(
                        fp,
                        format!(
                            "cannot read environment map '{uri}' ({}): {e}",
                            resolved.display()
                        ),
                    )
                })?;
            scene.environment_map = Some(Arc::new(map));
            Ok(())
        }
        other => Err(doc.err(
            "environment.type",
            format!("unknown environment type '{other}' (expected one of: {KINDS})"),
        )),
    }
}
