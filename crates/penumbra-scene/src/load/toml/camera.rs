//! `[camera]` and `[render]`.

use super::diag::Doc;
use super::raw::{RawCamera, RawRender, num};
use crate::camera::{Camera, Projection};
use crate::error::SceneError;
use crate::settings::{IntegratorKind, RenderSettings};
use glam::Vec3;

/// Largest accepted image side [pixels].
const MAX_RESOLUTION: i64 = 65_536;

/// `[camera]`: a look-at camera, perspective (`fov_y_deg`) or orthographic
/// (`height`).
pub(super) fn camera(doc: &Doc<'_>, c: &RawCamera) -> Result<Camera, SceneError> {
    let kind = c.kind.as_deref().unwrap_or("perspective");
    let projection = match kind {
        "perspective" => {
            if c.height.is_some() {
                return Err(doc.err(
                    "camera.height",
                    "`height` is for orthographic cameras; a perspective camera takes fov_y_deg",
                ));
            }
            let fov = c.fov_y_deg.ok_or_else(|| {
                doc.err(
                    "camera",
                    "a perspective camera needs fov_y_deg (vertical field of view in degrees, in (0, 180))",
                )
            })?;
            if !(fov > 0.0 && fov < 180.0) {
                return Err(doc.err(
                    "camera.fov_y_deg",
                    format!("fov_y_deg must be in (0, 180) degrees, got {}", num(fov)),
                ));
            }
            Projection::Perspective {
                fov_y: (fov as f32).to_radians(),
            }
        }
        "orthographic" => {
            if c.fov_y_deg.is_some() {
                return Err(doc.err(
                    "camera.fov_y_deg",
                    "`fov_y_deg` is for perspective cameras; an orthographic camera takes height",
                ));
            }
            let h = c.height.ok_or_else(|| {
                doc.err(
                    "camera",
                    "an orthographic camera needs height (world-space height of the view, > 0)",
                )
            })?;
            Projection::Orthographic {
                height: doc.positive("camera.height", h)?,
            }
        }
        other => {
            return Err(doc.err(
                "camera.type",
                format!("unknown camera type '{other}' (expected perspective or orthographic)"),
            ));
        }
    };
    let position = c
        .position
        .as_ref()
        .ok_or_else(|| doc.err("camera", "the camera needs position = [x, y, z]"))?;
    let position = doc.vec3("camera.position", position)?;
    let look_at = c
        .look_at
        .as_ref()
        .ok_or_else(|| doc.err("camera", "the camera needs look_at = [x, y, z]"))?;
    let look_at = doc.vec3("camera.look_at", look_at)?;
    let up = match &c.up {
        Some(u) => doc.direction("camera.up", u)?,
        None => Vec3::Y,
    };
    let forward = look_at - position;
    if forward.length_squared() == 0.0 || !forward.is_finite() {
        return Err(doc.err(
            "camera.look_at",
            format!("look_at must differ from position, both are {position}"),
        ));
    }
    if forward.normalize().cross(up).length() < 1e-6 {
        return Err(doc.err(
            "camera.up",
            format!(
                "up {up} is parallel to the viewing direction {}",
                forward.normalize()
            ),
        ));
    }
    Ok(Camera::look_at(position, look_at, up, projection))
}

/// `[render]`; missing keys keep [`RenderSettings::default`].
pub(super) fn render(doc: &Doc<'_>, r: &RawRender) -> Result<RenderSettings, SceneError> {
    let mut s = RenderSettings::default();
    if let Some(res) = &r.resolution {
        let ok = res.len() == 2 && res.iter().all(|v| (1..=MAX_RESOLUTION).contains(v));
        if !ok {
            return Err(doc.err(
                "render.resolution",
                format!(
                    "resolution must be [width, height] with each in [1, {MAX_RESOLUTION}], got {res:?}"
                ),
            ));
        }
        s.width = res[0] as u32;
        s.height = res[1] as u32;
    }
    if let Some(spp) = r.spp {
        s.spp = doc.int_in("render.spp", spp, 1, 1 << 24)?;
    }
    if let Some(d) = r.max_depth {
        s.max_depth = doc.int_in("render.max_depth", d, 1, 1024)?;
    }
    if let Some(name) = &r.integrator {
        s.integrator = name
            .parse::<IntegratorKind>()
            .map_err(|m| doc.err("render.integrator", m))?;
    }
    if let Some(seed) = r.seed {
        s.seed = doc.int_in("render.seed", seed, 0, u32::MAX as i64)?;
    }
    if let Some(d) = r.ao_distance {
        if d.is_nan() || d <= 0.0 {
            return Err(doc.err(
                "render.ao_distance",
                format!("ao_distance must be > 0 (inf allowed), got {}", num(d)),
            ));
        }
        s.ao_distance = d as f32;
    }
    Ok(s)
}
