//! What a study records: one [`Row`] per technique that ran, one
//! [`Skipped`] per technique that could not, and the truths they were
//! judged against. `study.json`, `study.csv` and `index.html` are all
//! written from these values.

use serde::{Deserialize, Serialize};

/// The errors of one image against one truth (the metrics of `penumbra
/// compare`, plus the FLIP 99th percentile and the mean ratio).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Errors {
    /// `(1/N) Σ (t − r)² / (r² + 0.01)` over pixels and channels.
    pub rel_mse: f64,
    /// Mean HDR-FLIP.
    pub flip_mean: f64,
    /// 99th percentile of the per-pixel HDR-FLIP error.
    pub flip_p99: f64,
    /// mean(test) / mean(truth) per channel (1 = same energy).
    pub mean_ratio: [f64; 3],
}

/// What a row cost.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Cost {
    /// Precomputation (bakes) [s]; `None` for techniques without one.
    pub bake_seconds: Option<f64>,
    /// Frame time (raster: submit to finish of the frame's GPU work) or
    /// render time (ray tracer, BVH build excluded) [s].
    pub seconds: f64,
    /// How far the process's resident memory rose above its size at the
    /// row's start, at its peak [MiB] (`None` where the OS does not tell).
    /// On a software rasteriser (lavapipe) GPU memory is host memory and is
    /// included.
    pub peak_memory_mib: Option<f64>,
}

/// One technique that ran.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Row {
    /// Stable name, as `--techniques` takes it (e.g. `raster-map-1024-pcf3`).
    pub id: String,
    /// Human-readable name (e.g. "shadow map 1024², PCF 3").
    pub label: String,
    /// Family: "ray tracing", "shadows", "environment", "ambient occlusion",
    /// "bakes".
    pub group: String,
    /// `trace` or `raster`.
    pub engine: String,
    /// What was run, as command-line flags a user can repeat.
    pub command: String,
    /// Id of the truth this technique approximates (`path`, `direct`,
    /// `ao`).
    pub approximates: String,
    /// The image, tone-mapped (relative to the report directory).
    pub image: String,
    /// The image, linear float EXR.
    pub image_exr: String,
    /// The HDR-FLIP error map against full GI, colour-mapped on FLIP's own
    /// fixed [0, 1] scale.
    pub error_map: String,
    /// The image compared with the approximated quantity's truth, when that
    /// is not the full-GI image itself (AO rows: the kA image).
    pub quantity_image: Option<String>,
    /// Errors against the approximated quantity (equal to `full` when it is
    /// `path`).
    pub quantity: Errors,
    /// Errors against full global illumination (the `path` truth).
    pub full: Errors,
    /// `path` stopped after the same time as this row, against full GI
    /// (`None` for the `path` rows themselves).
    pub equal_time_path: Option<EqualTime>,
    pub cost: Cost,
    /// Remarks of the engines (approximations, warnings).
    pub notes: Vec<String>,
}

/// `path` given the time of a row.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct EqualTime {
    pub spp: u32,
    pub seconds: f64,
    pub full: Errors,
}

/// A technique that did not run, and why.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Skipped {
    pub id: String,
    pub label: String,
    pub reason: String,
}

/// A reference image a row is judged against.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Truth {
    /// `path` (full GI), `direct` or `ao`.
    pub id: String,
    pub label: String,
    /// How it was made ("path, 1024 spp, seed 7" or "reference FILE").
    pub source: String,
    /// Tone-mapped image (relative path).
    pub image: String,
    /// Linear EXR (relative path).
    pub image_exr: String,
    /// The truth's own noise: relMSE of its mean estimated from the film's
    /// variance, `(1/N) Σ Var[mean] / (r² + 0.01)`; `None` for a given
    /// reference file.
    pub noise_rel_mse: Option<f64>,
    pub spp: Option<u32>,
    pub seconds: f64,
}

/// A whole study.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Study {
    /// The scene as given on the command line.
    pub scene: String,
    pub width: u32,
    pub height: u32,
    /// The GPU adapter the raster rows ran on (`None` without raster rows).
    pub adapter: Option<String>,
    /// penumbra's version.
    pub version: String,
    /// `truths[0]` is full GI (`path`); then the approximated quantities.
    pub truths: Vec<Truth>,
    pub rows: Vec<Row>,
    pub skipped: Vec<Skipped>,
    /// Wall time of the whole study [s].
    pub total_seconds: f64,
}
