//! The TOML document as serde reads it, before validation.
//!
//! Every table denies unknown keys. Keys whose meaning depends on a `type`
//! or `shape` live in one flat struct per section and are checked against
//! that type afterwards (so a later `type` adds fields without breaking
//! files, and the error can say which keys the type takes). Numbers are read
//! as `f64`/`i64` so that range errors can quote the value as written.

use serde::Deserialize;
use serde::de::{self, Deserializer, SeqAccess, Visitor};
use std::fmt;

/// The whole file.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawScene {
    /// Constant background radiance.
    pub background: Option<Floats>,
    pub environment: Option<RawEnvironment>,
    pub camera: Option<RawCamera>,
    pub render: Option<RawRender>,
    #[serde(default)]
    pub materials: Vec<RawMaterial>,
    #[serde(default)]
    pub lights: Vec<RawLight>,
    #[serde(default)]
    pub objects: Vec<RawObject>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawCamera {
    #[serde(rename = "type")]
    pub kind: Option<String>,
    pub position: Option<Floats>,
    pub look_at: Option<Floats>,
    pub up: Option<Floats>,
    pub fov_y_deg: Option<f64>,
    pub height: Option<f64>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawRender {
    pub resolution: Option<Vec<i64>>,
    pub spp: Option<i64>,
    pub max_depth: Option<i64>,
    pub integrator: Option<String>,
    pub seed: Option<i64>,
    pub ao_distance: Option<f64>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawMaterial {
    pub name: Option<String>,
    #[serde(rename = "type")]
    pub kind: Option<String>,
    pub emission: Option<Floats>,
    pub double_sided: Option<bool>,
    // Type parameters (each type takes a subset, see `present_keys`).
    pub albedo: Option<Floats>,
    pub kd: Option<Floats>,
    pub ks: Option<Floats>,
    pub shininess: Option<f64>,
    pub variant: Option<String>,
    pub reflectance: Option<Floats>,
    pub preset: Option<String>,
    pub eta: Option<Floats>,
    pub k: Option<Floats>,
    pub roughness: Option<f64>,
    pub fresnel: Option<String>,
    pub ior: Option<f64>,
    pub tint: Option<Floats>,
    pub base_color: Option<Floats>,
    pub metallic: Option<f64>,
    pub transmission: Option<f64>,
    pub specular: Option<f64>,
    pub specular_color: Option<Floats>,
}

impl RawMaterial {
    /// The type-specific keys present, for checking them against the type.
    pub fn present_keys(&self) -> Vec<&'static str> {
        present(&[
            ("albedo", self.albedo.is_some()),
            ("kd", self.kd.is_some()),
            ("ks", self.ks.is_some()),
            ("shininess", self.shininess.is_some()),
            ("variant", self.variant.is_some()),
            ("reflectance", self.reflectance.is_some()),
            ("preset", self.preset.is_some()),
            ("eta", self.eta.is_some()),
            ("k", self.k.is_some()),
            ("roughness", self.roughness.is_some()),
            ("fresnel", self.fresnel.is_some()),
            ("ior", self.ior.is_some()),
            ("tint", self.tint.is_some()),
            ("base_color", self.base_color.is_some()),
            ("metallic", self.metallic.is_some()),
            ("transmission", self.transmission.is_some()),
            ("specular", self.specular.is_some()),
            ("specular_color", self.specular_color.is_some()),
        ])
    }
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawLight {
    pub name: Option<String>,
    #[serde(rename = "type")]
    pub kind: Option<String>,
    pub position: Option<Floats>,
    pub direction: Option<Floats>,
    pub color: Option<Floats>,
    pub intensity: Option<Floats>,
    pub power: Option<Floats>,
    pub intensity_cd: Option<Floats>,
    pub power_lm: Option<Floats>,
    pub irradiance: Option<Floats>,
    pub illuminance_lux: Option<Floats>,
    pub inner_cone_deg: Option<f64>,
    pub outer_cone_deg: Option<f64>,
    pub range: Option<f64>,
    // Area lights.
    pub center: Option<Floats>,
    pub radius: Option<f64>,
    pub normal: Option<Floats>,
    pub corner: Option<Floats>,
    pub edge1: Option<Floats>,
    pub edge2: Option<Floats>,
    pub radiance: Option<Floats>,
    pub luminance_nits: Option<Floats>,
    pub two_sided: Option<bool>,
}

/// `[environment]`: a constant radiance or an equirectangular map.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawEnvironment {
    #[serde(rename = "type")]
    pub kind: Option<String>,
    pub radiance: Option<Floats>,
    pub luminance_nits: Option<Floats>,
    pub color: Option<Floats>,
    pub file: Option<String>,
    pub scale: Option<Floats>,
    pub rotate_deg: Option<f64>,
}

impl RawEnvironment {
    pub fn present_keys(&self) -> Vec<&'static str> {
        present(&[
            ("radiance", self.radiance.is_some()),
            ("luminance_nits", self.luminance_nits.is_some()),
            ("color", self.color.is_some()),
            ("file", self.file.is_some()),
            ("scale", self.scale.is_some()),
            ("rotate_deg", self.rotate_deg.is_some()),
        ])
    }
}

impl RawLight {
    pub fn present_keys(&self) -> Vec<&'static str> {
        present(&[
            ("position", self.position.is_some()),
            ("direction", self.direction.is_some()),
            ("intensity", self.intensity.is_some()),
            ("power", self.power.is_some()),
            ("intensity_cd", self.intensity_cd.is_some()),
            ("power_lm", self.power_lm.is_some()),
            ("irradiance", self.irradiance.is_some()),
            ("illuminance_lux", self.illuminance_lux.is_some()),
            ("inner_cone_deg", self.inner_cone_deg.is_some()),
            ("outer_cone_deg", self.outer_cone_deg.is_some()),
            ("range", self.range.is_some()),
            ("center", self.center.is_some()),
            ("radius", self.radius.is_some()),
            ("normal", self.normal.is_some()),
            ("corner", self.corner.is_some()),
            ("edge1", self.edge1.is_some()),
            ("edge2", self.edge2.is_some()),
            ("radiance", self.radiance.is_some()),
            ("luminance_nits", self.luminance_nits.is_some()),
            ("two_sided", self.two_sided.is_some()),
        ])
    }
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawObject {
    pub name: Option<String>,
    pub material: Option<String>,
    pub mesh: Option<String>,
    pub shape: Option<String>,
    /// Raster planar shadows fall on this object.
    pub planar_receiver: Option<bool>,
    // Shape parameters.
    pub center: Option<Floats>,
    pub radius: Option<f64>,
    pub subdivisions: Option<i64>,
    pub corner: Option<Floats>,
    pub edge1: Option<Floats>,
    pub edge2: Option<Floats>,
    pub vertices: Option<Vec<Floats>>,
    pub size: Option<Floats>,
    pub min: Option<Floats>,
    pub max: Option<Floats>,
    pub normal: Option<Floats>,
    pub segments: Option<i64>,
    // Transform.
    pub translate: Option<Floats>,
    pub rotate_deg: Option<Floats>,
    pub rotate_axis_angle: Option<RawAxisAngle>,
    pub scale: Option<Floats>,
    pub matrix: Option<Vec<Vec<f64>>>,
}

impl RawObject {
    /// Shape parameters present (each shape takes a subset).
    pub fn shape_keys(&self) -> Vec<&'static str> {
        present(&[
            ("center", self.center.is_some()),
            ("radius", self.radius.is_some()),
            ("subdivisions", self.subdivisions.is_some()),
            ("corner", self.corner.is_some()),
            ("edge1", self.edge1.is_some()),
            ("edge2", self.edge2.is_some()),
            ("vertices", self.vertices.is_some()),
            ("size", self.size.is_some()),
            ("min", self.min.is_some()),
            ("max", self.max.is_some()),
            ("normal", self.normal.is_some()),
            ("segments", self.segments.is_some()),
        ])
    }
}

/// `rotate_axis_angle = { axis = [x, y, z], angle_deg = a }`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawAxisAngle {
    pub axis: Floats,
    pub angle_deg: f64,
}

fn present(keys: &[(&'static str, bool)]) -> Vec<&'static str> {
    keys.iter().filter(|(_, p)| *p).map(|(k, _)| *k).collect()
}

/// A number or an array of numbers (integers are accepted as floats):
/// `albedo = 0.5` or `albedo = [0.8, 0.7, 0.6]`. The validator decides which
/// lengths a key takes.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct Floats {
    pub values: Vec<f64>,
    /// Written as a single number rather than an array.
    pub scalar: bool,
}

/// A number as a person would write it: `0.5`, `-3`, `1e39`, `NaN`, `inf`.
pub(super) fn num(x: f64) -> String {
    let a = x.abs();
    if a.is_finite() && a != 0.0 && !(1e-4..1e7).contains(&a) {
        format!("{x:e}")
    } else {
        format!("{x}")
    }
}

impl fmt::Display for Floats {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.scalar {
            return f.write_str(&num(self.values[0]));
        }
        f.write_str("[")?;
        for (i, v) in self.values.iter().enumerate() {
            if i > 0 {
                f.write_str(", ")?;
            }
            f.write_str(&num(*v))?;
        }
        f.write_str("]")
    }
}

impl<'de> Deserialize<'de> for Floats {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl<'de> Visitor<'de> for V {
            type Value = Floats;
            fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str("a number or an array of numbers")
            }
            fn visit_i64<E: de::Error>(self, v: i64) -> Result<Floats, E> {
                Ok(Floats {
                    values: vec![v as f64],
                    scalar: true,
                })
            }
            fn visit_u64<E: de::Error>(self, v: u64) -> Result<Floats, E> {
                Ok(Floats {
                    values: vec![v as f64],
                    scalar: true,
                })
            }
            fn visit_f64<E: de::Error>(self, v: f64) -> Result<Floats, E> {
                Ok(Floats {
                    values: vec![v],
                    scalar: true,
                })
            }
            fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Floats, A::Error> {
                let mut values = Vec::new();
                while let Some(v) = seq.next_element::<f64>()? {
                    values.push(v);
                }
                Ok(Floats {
                    values,
                    scalar: false,
                })
            }
        }
        d.deserialize_any(V)
    }
}
