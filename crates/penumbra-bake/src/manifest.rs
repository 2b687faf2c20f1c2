//! The manifest of a bake directory (`manifest.json`): what was baked, in
//! which units, with which settings, for which scene, and where each
//! instance's texels lie. Version 1; readers refuse other versions.

use crate::error::BakeError;
use serde::{Deserialize, Serialize};
use std::path::Path;

/// `format` of every manifest.
pub const FORMAT: &str = "penumbra-bake";
/// The manifest version this build writes and reads.
pub const VERSION: u32 = 1;
/// File name of the manifest in a bake directory.
pub const MANIFEST_FILE: &str = "manifest.json";

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Manifest {
    pub format: String,
    pub version: u32,
    /// `ao`, `lightmap` or `radiosity`.
    pub kind: String,
    pub quantity: String,
    /// `1` (kA) or `W/m^2` (E).
    pub units: String,
    pub scene: SceneInfo,
    pub settings: SettingsInfo,
    pub atlas: AtlasInfo,
    pub instances: Vec<InstanceInfo>,
    /// `total` first, then the per-light maps.
    pub maps: Vec<MapInfo>,
    pub texels: TexelInfo,
    pub timing: TimingInfo,
    /// Radiosity: the convergence record (CSV) and its plot (SVG).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub convergence: Option<ConvergenceInfo>,
    #[serde(default)]
    pub warnings: Vec<String>,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SceneInfo {
    /// The scene file as given on the command line (informative).
    pub file: Option<String>,
    /// [`crate::geometry_hash`] of the scene baked.
    pub geometry_hash: String,
    pub instances: usize,
    pub triangles: usize,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SettingsInfo {
    /// Samples per texel (AO, light map) or rays per patch (radiosity).
    pub samples: u32,
    pub seed: u32,
    /// AO ray length; `null` = unlimited.
    #[serde(default)]
    pub ao_distance: Option<f32>,
    #[serde(default)]
    pub bounces: Option<u32>,
    #[serde(default)]
    pub indirect_only: bool,
    #[serde(default)]
    pub per_light: bool,
    #[serde(default)]
    pub patches: Option<u32>,
    #[serde(default)]
    pub tolerance: Option<f32>,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct AtlasInfo {
    pub width: u32,
    pub height: u32,
    pub pages: u32,
    pub texels_per_unit: f32,
    pub padding: u32,
    pub charts: u32,
    pub utilization: f32,
    /// The per-mesh layouts (see `bake_dir.rs`), and its size in bytes.
    pub uvs: String,
    pub uvs_bytes: u64,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct InstanceInfo {
    pub instance: usize,
    pub mesh: usize,
    pub name: String,
    pub page: u32,
    /// The instance's rectangle in page coordinates: the page coordinate of
    /// layout coordinate uv is `uv_min + uv (uv_max − uv_min)`.
    pub uv_min: [f32; 2],
    pub uv_max: [f32; 2],
    /// `generated` or `texcoord1`.
    pub uv_source: String,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MapInfo {
    pub name: String,
    #[serde(default)]
    pub light: Option<String>,
    /// One EXR file per page: the value in R, G, B; layers `variance` and
    /// `coverage` (1 baked, 0.5 inside geometry, 0 not covered).
    pub pages: Vec<String>,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct TexelInfo {
    pub covered: u64,
    pub valid: u64,
    pub invalid: u64,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct TimingInfo {
    pub prepare_seconds: f64,
    pub bake_seconds: f64,
    pub rays: u64,
    pub rays_per_second: f64,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ConvergenceInfo {
    pub csv: String,
    pub plot: String,
    pub iterations: u32,
    pub final_unshot_fraction: f64,
}

impl AtlasInfo {
    /// The manifest's record of `atlas`, whose layouts are the file `uvs`
    /// of `uvs_bytes` bytes.
    pub fn of(atlas: &crate::atlas::Atlas, uvs: &str, uvs_bytes: u64) -> Self {
        Self {
            width: atlas.width,
            height: atlas.height,
            pages: atlas.pages,
            texels_per_unit: atlas.texels_per_unit,
            padding: atlas.padding,
            charts: atlas.charts,
            utilization: atlas.utilization,
            uvs: uvs.into(),
            uvs_bytes,
        }
    }

    /// The atlas this record describes, with the layouts and rectangles
    /// read beside it.
    pub fn atlas(
        &self,
        meshes: Vec<Option<crate::atlas::MeshLayout>>,
        instances: Vec<Option<crate::atlas::InstanceRect>>,
    ) -> crate::atlas::Atlas {
        crate::atlas::Atlas {
            width: self.width,
            height: self.height,
            pages: self.pages,
            texels_per_unit: self.texels_per_unit,
            padding: self.padding,
            charts: self.charts,
            utilization: self.utilization,
            meshes,
            instances,
        }
    }
}

impl Manifest {
    /// Parses a manifest, refusing other formats and versions first (so an
    /// old or new manifest says so instead of naming a missing field).
    pub fn parse(path: &Path, text: &str) -> Result<Self, BakeError> {
        let err = |m: String| BakeError::file(path, m);
        let value: serde_json::Value =
            serde_json::from_str(text).map_err(|e| err(format!("not valid JSON: {e}")))?;
        let format = value.get("format").and_then(|v| v.as_str());
        if format != Some(FORMAT) {
            return Err(err(format!(
                "not a penumbra bake manifest (\"format\" is {}, expected \"{FORMAT}\")",
                format.map_or("missing".to_string(), |f| format!("\"{f}\""))
            )));
        }
        match value.get("version").and_then(|v| v.as_u64()) {
            Some(v) if v == VERSION as u64 => {}
            Some(v) => {
                return Err(err(format!(
                    "manifest version {v} is not supported (this penumbra reads version {VERSION}); bake the scene again"
                )));
            }
            None => return Err(err("\"version\" is missing or not a whole number".into())),
        }
        serde_json::from_value(value).map_err(|e| err(format!("malformed manifest: {e}")))
    }
}
