//! `[[lights]]`: point, directional and spot lights, and the analytic area
//! lights sphere, disk and quad, in radiometric or photometric units
//! (converted with 683 lm/W, as glTF does). Area lights take a radiance or a
//! power, `Le = Φ / (π A)` (÷ 2 more when two-sided).
//!
//! Every quantity is one number or `[r, g, b]`, and is multiplied by the
//! optional `color` (default white).

use super::diag::Doc;
use super::raw::{Floats, RawLight};
use super::values::ColorRange;
use crate::error::SceneError;
use crate::scene::{SceneAreaLight, SceneLight};
use penumbra_shading::Rgb;
use penumbra_shading::light::{AreaLight, DirectionalLight, Light, PointLight, Shape, SpotLight};
use penumbra_shading::radiometry::{
    candela_to_watts_per_sr, lumens_to_watts, lux_to_watts_per_m2, point_intensity_from_power,
};

const KINDS: &str = "point, directional, spot, sphere, disk, quad";

/// A parsed `[[lights]]` table.
enum Parsed {
    Abstract(SceneLight),
    Area(SceneAreaLight),
}

/// The abstract and the area lights, each in file order.
pub(super) fn lights(
    doc: &Doc<'_>,
    raws: &[RawLight],
) -> Result<(Vec<SceneLight>, Vec<SceneAreaLight>), SceneError> {
    let (mut abstract_lights, mut area) = (Vec::new(), Vec::new());
    for (i, raw) in raws.iter().enumerate() {
        match light(doc, &format!("lights[{i}]"), raw)? {
            Parsed::Abstract(l) => abstract_lights.push(l),
            Parsed::Area(l) => area.push(l),
        }
    }
    Ok((abstract_lights, area))
}

/// One light quantity key: its name and how to turn its value into the
/// light's radiometric quantity.
type Unit = (&'static str, fn(f32) -> f32);

const POINT_UNITS: &[Unit] = &[
    ("intensity", |x| x),
    ("power", point_intensity_from_power),
    ("intensity_cd", candela_to_watts_per_sr),
    ("power_lm", |lm| {
        point_intensity_from_power(lumens_to_watts(lm))
    }),
];
const SPOT_UNITS: &[Unit] = &[
    ("intensity", |x| x),
    ("intensity_cd", candela_to_watts_per_sr),
];
/// Area lights: radiance directly, or a power turned into radiance later.
const AREA_UNITS: &[Unit] = &[
    ("radiance", |x| x),
    ("luminance_nits", candela_to_watts_per_sr),
    ("power", |x| x),
    ("power_lm", lumens_to_watts),
];
pub(super) const ENVIRONMENT_UNITS: &[Unit] = &[
    ("radiance", |x| x),
    ("luminance_nits", candela_to_watts_per_sr),
];
const DIRECTIONAL_UNITS: &[Unit] = &[
    ("irradiance", |x| x),
    ("illuminance_lux", lux_to_watts_per_m2),
];

fn light(doc: &Doc<'_>, path: &str, raw: &RawLight) -> Result<Parsed, SceneError> {
    let kind = raw
        .kind
        .as_deref()
        .ok_or_else(|| doc.err(path, format!("a light needs a type ({KINDS})")))?;
    let name = raw.name.clone().unwrap_or_else(|| path.to_string());
    let at = |k: &str| format!("{path}.{k}");
    let light = match kind {
        "point" => {
            let keys = [
                "position",
                "intensity",
                "power",
                "intensity_cd",
                "power_lm",
                "color",
                "range",
            ];
            doc.only_keys(path, "a point light", &raw.present_keys(), &keys)?;
            let position = doc.vec3(
                &at("position"),
                required(doc, path, "position", &raw.position)?,
            )?;
            Light::Point(PointLight {
                position,
                intensity: quantity(doc, path, raw, POINT_UNITS)?.1,
                range: range(doc, path, raw)?,
            })
        }
        "directional" => {
            let keys = ["direction", "irradiance", "illuminance_lux", "color"];
            doc.only_keys(path, "a directional light", &raw.present_keys(), &keys)?;
            let d = required(doc, path, "direction", &raw.direction)?;
            Light::Directional(DirectionalLight {
                direction: doc.direction(&at("direction"), d)?,
                irradiance: quantity(doc, path, raw, DIRECTIONAL_UNITS)?.1,
            })
        }
        "spot" => {
            let keys = [
                "position",
                "direction",
                "intensity",
                "intensity_cd",
                "inner_cone_deg",
                "outer_cone_deg",
                "color",
                "range",
            ];
            doc.only_keys(path, "a spot light", &raw.present_keys(), &keys)?;
            let p = required(doc, path, "position", &raw.position)?;
            let d = required(doc, path, "direction", &raw.direction)?;
            let (cos_inner, cos_outer) = cone(doc, path, raw)?;
            Light::Spot(SpotLight {
                position: doc.vec3(&at("position"), p)?,
                direction: doc.direction(&at("direction"), d)?,
                intensity: quantity(doc, path, raw, SPOT_UNITS)?.1,
                cos_inner,
                cos_outer,
                range: range(doc, path, raw)?,
            })
        }
        "sphere" | "disk" | "quad" => {
            let light = area_light(doc, path, kind, raw)?;
            return Ok(Parsed::Area(SceneAreaLight { name, light }));
        }
        other => {
            return Err(doc.err(
                &at("type"),
                format!("unknown light type '{other}' (expected one of: {KINDS})"),
            ));
        }
    };
    Ok(Parsed::Abstract(SceneLight { name, light }))
}

/// `range = d`: the distance at which a point or spot light is cut off
/// (glTF's smooth window); absent = no cut-off.
fn range(doc: &Doc<'_>, path: &str, raw: &RawLight) -> Result<f32, SceneError> {
    match raw.range {
        None => Ok(f32::INFINITY),
        Some(r) => doc.positive(&format!("{path}.range"), r),
    }
}

/// `type = "sphere" | "disk" | "quad"`.
fn area_light(
    doc: &Doc<'_>,
    path: &str,
    kind: &str,
    raw: &RawLight,
) -> Result<AreaLight, SceneError> {
    let at = |k: &str| format!("{path}.{k}");
    let units = [
        "radiance",
        "luminance_nits",
        "power",
        "power_lm",
        "color",
        "two_sided",
    ];
    let geometry: &[&str] = match kind {
        "sphere" => &["center", "radius"],
        "disk" => &["center", "normal", "radius"],
        _ => &["corner", "edge1", "edge2"],
    };
    let keys: Vec<&str> = geometry.iter().chain(units.iter()).copied().collect();
    doc.only_keys(path, &format!("a {kind} light"), &raw.present_keys(), &keys)?;
    let point = |key: &str, v: &Option<Floats>| -> Result<glam::Vec3, SceneError> {
        doc.vec3(&at(key), required(doc, path, key, v)?)
    };
    let radius = || -> Result<f32, SceneError> {
        let r = raw
            .radius
            .ok_or_else(|| doc.err(path, format!("a {kind} light needs radius = r")))?;
        doc.positive(&at("radius"), r)
    };
    let shape = match kind {
        "sphere" => Shape::Sphere {
            center: point("center", &raw.center)?,
            radius: radius()?,
        },
        "disk" => Shape::Disk {
            center: point("center", &raw.center)?,
            normal: doc.direction(&at("normal"), required(doc, path, "normal", &raw.normal)?)?,
            radius: radius()?,
        },
        _ => {
            let (corner, edge1, edge2) = (
                point("corner", &raw.corner)?,
                point("edge1", &raw.edge1)?,
                point("edge2", &raw.edge2)?,
            );
            let area = edge1.cross(edge2).length();
            if area.is_nan() || area <= 0.0 {
                return Err(doc.err(
                    &at("edge2"),
                    format!(
                        "edge1 {edge1} and edge2 {edge2} are parallel or zero: the quad light has no area"
                    ),
                ));
            }
            Shape::Quad {
                corner,
                edge1,
                edge2,
            }
        }
    };
    let two_sided = raw.two_sided.unwrap_or(false);
    let (key, q) = quantity(doc, path, raw, AREA_UNITS)?;
    Ok(if key.starts_with("power") {
        AreaLight::from_power(shape, q, two_sided)
    } else {
        AreaLight {
            shape,
            radiance: q,
            two_sided,
        }
    })
}

fn required<'r>(
    doc: &Doc<'_>,
    path: &str,
    key: &str,
    v: &'r Option<Floats>,
) -> Result<&'r Floats, SceneError> {
    v.as_ref()
        .ok_or_else(|| doc.err(path, format!("this light needs {key} = [x, y, z]")))
}

/// The one quantity key among `units` that is present, converted to the
/// radiometric unit and multiplied by `color`; with the key used.
fn quantity(
    doc: &Doc<'_>,
    path: &str,
    raw: &RawLight,
    units: &[Unit],
) -> Result<(&'static str, Rgb), SceneError> {
    let value = |k: &str| match k {
        "radiance" => raw.radiance.as_ref(),
        "luminance_nits" => raw.luminance_nits.as_ref(),
        "intensity" => raw.intensity.as_ref(),
        "power" => raw.power.as_ref(),
        "intensity_cd" => raw.intensity_cd.as_ref(),
        "power_lm" => raw.power_lm.as_ref(),
        "irradiance" => raw.irradiance.as_ref(),
        "illuminance_lux" => raw.illuminance_lux.as_ref(),
        _ => None,
    };
    pick_quantity(doc, path, units, value, raw.color.as_ref())
}

/// Shared by lights and the environment: exactly one of `units` present.
pub(super) fn pick_quantity<'r>(
    doc: &Doc<'_>,
    path: &str,
    units: &[Unit],
    value: impl Fn(&str) -> Option<&'r Floats>,
    color: Option<&Floats>,
) -> Result<(&'static str, Rgb), SceneError> {
    let given: Vec<&Unit> = units.iter().filter(|(k, _)| value(k).is_some()).collect();
    let names = || units.iter().map(|(k, _)| *k).collect::<Vec<_>>().join(", ");
    let (key, convert) = match given.as_slice() {
        [one] => **one,
        [] => {
            return Err(doc.err(
                path,
                format!("this light needs exactly one of: {}", names()),
            ));
        }
        [_, second, ..] => {
            return Err(doc.err(
                &format!("{path}.{}", second.0),
                format!("give only one of: {} (the others follow from it)", names()),
            ));
        }
    };
    let v = value(key).ok_or_else(|| doc.err(path, "internal: missing quantity"))?;
    let q = doc.rgb(&format!("{path}.{key}"), v, ColorRange::NonNegative)?;
    let color = match color {
        Some(c) => doc.rgb(&format!("{path}.color"), c, ColorRange::NonNegative)?,
        None => Rgb::ONE,
    };
    Ok((
        key,
        Rgb::new(convert(q.x), convert(q.y), convert(q.z)) * color,
    ))
}

/// glTF cone half-angles: `0 ≤ inner ≤ outer ≤ 90°`, `outer > 0`; defaults
/// inner 0°, outer 45°. Returns (cos inner, cos outer).
fn cone(doc: &Doc<'_>, path: &str, raw: &RawLight) -> Result<(f32, f32), SceneError> {
    let inner = raw.inner_cone_deg.unwrap_or(0.0);
    let outer = raw.outer_cone_deg.unwrap_or(45.0);
    let ip = format!("{path}.inner_cone_deg");
    let op = format!("{path}.outer_cone_deg");
    let outer = doc.in_range(&op, outer, 0.0, 90.0)?;
    if outer <= 0.0 {
        return Err(doc.err(&op, "outer_cone_deg must be in (0, 90], got 0"));
    }
    let inner = doc.in_range(&ip, inner, 0.0, 90.0)?;
    if inner > outer {
        return Err(doc.err(
            &ip,
            format!(
                "inner_cone_deg ({inner}) must not exceed outer_cone_deg ({outer}); allowed: 0 <= inner <= outer <= 90"
            ),
        ));
    }
    Ok((inner.to_radians().cos(), outer.to_radians().cos()))
}
