//! Shared command-line value parsers and helpers.

use anyhow::{Context, Result, anyhow, bail};
use penumbra_image::available_memory;
use penumbra_scene::{IntegratorKind, LoadOptions, RenderSettings, Scene};
use penumbra_trace::geometry::SceneGeometry;
use std::path::Path;

/// Largest image edge accepted.
pub const MAX_EDGE: u32 = 65_536;

/// Whether the environment variable `PENUMBRA_SCALAR_PATHS` (set, not
/// empty, not `0`) asks for the scalar path tracer where the 16-lane one
/// applies (`RenderOptions::scalar_paths`: the benchmark scripts'
/// baseline). Read here, not in the library, whose callers and tests say
/// what they want in the options alone.
pub fn scalar_paths_requested() -> bool {
    std::env::var_os("PENUMBRA_SCALAR_PATHS").is_some_and(|v| !v.is_empty() && v != "0")
}

/// Parses `WxH` (e.g. `1920x1080`).
pub fn parse_resolution(s: &str) -> Result<(u32, u32), String> {
    let (w, h) = s
        .split_once(['x', 'X'])
        .ok_or_else(|| format!("'{s}' is not WIDTHxHEIGHT (e.g. 512x512)"))?;
    let parse = |v: &str, what: &str| -> Result<u32, String> {
        let n: u32 = v
            .trim()
            .parse()
            .map_err(|_| format!("{what} '{v}' is not a whole number"))?;
        if n == 0 || n > MAX_EDGE {
            return Err(format!("{what} {n} is out of range (1 to {MAX_EDGE})"));
        }
        Ok(n)
    };
    Ok((parse(w, "width")?, parse(h, "height")?))
}

/// Parses a whole number ≥ 1.
pub fn parse_positive(s: &str) -> Result<u32, String> {
    let n: i64 = s
        .trim()
        .parse()
        .map_err(|_| format!("'{s}' is not a whole number"))?;
    if n < 1 || n > u32::MAX as i64 {
        return Err(format!("{n} is out of range (must be at least 1)"));
    }
    Ok(n as u32)
}

/// `s` as a finite number that `accepts` takes; the errors say that `s` is
/// not `noun`, or `v: rule`.
pub fn parse_number(
    s: &str,
    noun: &str,
    accepts: impl Fn(f64) -> bool,
    rule: &str,
) -> Result<f64, String> {
    let v: f64 = s
        .trim()
        .parse()
        .map_err(|_| format!("'{s}' is not {noun}"))?;
    if !(v.is_finite() && accepts(v)) {
        return Err(format!("{v}: {rule}"));
    }
    Ok(v)
}

/// Parses seconds > 0.
pub fn parse_seconds(s: &str) -> Result<f64, String> {
    parse_number(
        s,
        "a number of seconds",
        |v| v > 0.0,
        "must be a positive number of seconds",
    )
}

/// A positive, finite length in scene units (`--ao-radius`, `--ao-distance`).
pub fn parse_length(s: &str) -> Result<f64, String> {
    parse_number(
        s,
        "a length",
        |v| v > 0.0,
        "must be a positive length in scene units",
    )
}

/// Loads a scene file; absolute paths the user typed are allowed inside it.
/// A scene with more triangles (instances counted) than the ray tracer's
/// BVH holds is refused here, before any work, with the count.
pub fn load_scene(path: &Path) -> Result<Scene> {
    let mut options = LoadOptions::default();
    if let Ok(abs) = std::path::absolute(path) {
        options.allowed_absolute_paths.push(abs);
    }
    let scene = penumbra_scene::load_scene(path, &options)?;
    SceneGeometry::check_size(&scene).map_err(|e| anyhow!("{}: {e}", path.display()))?;
    Ok(scene)
}

/// The scene file, or the built-in Cornell box without one; prints the
/// loader's warnings.
pub fn scene_or_builtin(path: Option<&Path>) -> Result<Scene> {
    let scene = match path {
        Some(p) => load_scene(p)?,
        None => penumbra_scene::builtin::cornell_box(),
    };
    for w in &scene.warnings {
        eprintln!("penumbra: warning: {w}");
    }
    Ok(scene)
}

/// Parses an MSAA sample count of the raster engine (1 or 4).
pub fn parse_msaa(s: &str) -> Result<u32, String> {
    match s.trim() {
        "1" => Ok(1),
        "4" => Ok(4),
        _ => Err(format!(
            "'{s}' is not a supported MSAA sample count (1 or 4)"
        )),
    }
}

/// Refuses image sizes whose buffers would not fit in memory.
pub fn check_image_memory(width: u32, height: u32, bytes_per_pixel: u64) -> Result<()> {
    let need = width as u64 * height as u64 * bytes_per_pixel;
    if let Some(avail) = available_memory()
        && need > avail
    {
        bail!(
            "resolution {width}x{height} needs about {:.1} GiB for its image buffers, more than the {:.1} GiB of memory available",
            need as f64 / (1u64 << 30) as f64,
            avail as f64 / (1u64 << 30) as f64
        );
    }
    Ok(())
}

/// Builds the rayon pool for `--threads` (None = all cores).
pub fn thread_pool(threads: Option<u32>) -> Result<rayon::ThreadPool> {
    let mut b = rayon::ThreadPoolBuilder::new();
    if let Some(n) = threads {
        b = b.num_threads(n as usize);
    }
    b.build().context("cannot start worker threads")
}

/// The flags that set a render's [`RenderSettings`] (`render`, `farm`).
#[derive(clap::Args, Clone, Debug, Default)]
pub struct SettingsArgs {
    /// local | direct | whitted | path | ao (default: the scene's, else path).
    #[arg(long, value_parser = |s: &str| s.parse::<IntegratorKind>())]
    pub integrator: Option<IntegratorKind>,
    /// Samples per pixel.
    #[arg(long, value_parser = parse_positive, allow_negative_numbers = true)]
    pub spp: Option<u32>,
    /// Maximum path segments from the camera (Mitsuba's max_depth: 1 = emitters only, 2 = direct light).
    #[arg(long, value_parser = parse_positive, allow_negative_numbers = true)]
    pub max_depth: Option<u32>,
    /// Image size WIDTHxHEIGHT.
    #[arg(long, value_parser = parse_resolution)]
    pub resolution: Option<(u32, u32)>,
    /// Random seed; the same seed gives the same image for any thread count.
    #[arg(long)]
    pub seed: Option<u32>,
    /// Ambient-occlusion ray length in scene units (default: unlimited).
    #[arg(long, value_parser = parse_length, allow_negative_numbers = true)]
    pub ao_distance: Option<f64>,
}

impl SettingsArgs {
    /// Overrides the scene's settings with the flags given.
    pub fn apply(&self, settings: &mut RenderSettings) {
        if let Some(i) = self.integrator {
            settings.integrator = i;
        }
        if let Some(s) = self.spp {
            settings.spp = s;
        }
        if let Some(d) = self.max_depth {
            settings.max_depth = d;
        }
        if let Some((w, h)) = self.resolution {
            settings.width = w;
            settings.height = h;
        }
        if let Some(s) = self.seed {
            settings.seed = s;
        }
        if let Some(d) = self.ao_distance {
            settings.ao_distance = d as f32;
        }
    }

    /// The flags given, as `penumbra render` arguments.
    pub fn to_args(&self) -> Vec<String> {
        let mut out = Vec::new();
        let mut flag = |name: &str, value: Option<String>| {
            if let Some(v) = value {
                out.extend([name.to_string(), v]);
            }
        };
        flag("--integrator", self.integrator.map(|i| i.to_string()));
        flag("--spp", self.spp.map(|s| s.to_string()));
        flag("--max-depth", self.max_depth.map(|d| d.to_string()));
        flag(
            "--resolution",
            self.resolution.map(|(w, h)| format!("{w}x{h}")),
        );
        flag("--seed", self.seed.map(|s| s.to_string()));
        flag("--ao-distance", self.ao_distance.map(|d| d.to_string()));
        out
    }
}
