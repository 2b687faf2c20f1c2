//! `penumbra render`.

use crate::commands::partial::{Checkpointer, PartArgs, RenderIdentity};
use crate::options::{
    SettingsArgs, check_image_memory, parse_length, parse_msaa, parse_number, parse_positive,
    parse_seconds, scene_or_builtin, thread_pool,
};
use anyhow::{Context, Result, bail};
use clap::{Args, ValueEnum};
use indicatif::{ProgressBar, ProgressStyle};
use penumbra_image::{Exposure, ToneMapping, ToneOperator, check_output_path, write_image};
use penumbra_raster::passes::ao::{AoMethod, AoQuality, AoSettings};
use penumbra_raster::{
    DEFAULT_SHADOW_MAP_SIZE, MAX_ENVIRONMENT_TAPS, MAX_PCF, RasterOptions, ShadowMode,
};
use penumbra_scene::{EnvironmentChoice, IntegratorKind, RenderSettings, Scene, apply_environment};
use penumbra_trace::{Progress, RenderOptions, Stop, render, scene_camera_for};
use std::io::IsTerminal;
use std::path::PathBuf;
use std::time::Duration;

#[derive(Args, Debug)]
pub struct RenderArgs {
    /// Scene file (.gltf, .glb, .obj, .toml). Default: the built-in Cornell box.
    pub scene: Option<PathBuf>,
    /// Output image: .png (tone-mapped sRGB) or .exr (linear float RGB).
    #[arg(short, long, default_value = "penumbra.png")]
    pub output: PathBuf,
    #[command(flatten)]
    pub settings: SettingsArgs,
    /// Worker threads (default: all cores).
    #[arg(long, value_parser = parse_positive, allow_negative_numbers = true)]
    pub threads: Option<u32>,
    /// Stop after this many seconds (at the end of a sample pass).
    #[arg(long, value_parser = parse_seconds, allow_negative_numbers = true)]
    pub time_limit: Option<f64>,
    /// Also write albedo, normal and depth layers (EXR only).
    #[arg(long)]
    pub aovs: bool,
    /// Exposure before tone mapping (PNG only): auto (the log-average
    /// luminance of the lit pixels exposed to 0.18) or a number of stops.
    #[arg(long, default_value = "auto", allow_negative_numbers = true)]
    pub exposure: Exposure,
    /// The environment: default (the scene's; the built-in studio
    /// environment if nothing lights the scene), none (the scene's, even if
    /// it is black), studio (the built-in studio replaces it), or an
    /// .hdr/.exr lat-long map that replaces it.
    #[arg(long, default_value = "default", value_parser = parse_environment)]
    pub environment: EnvironmentChoice,
    /// The file camera to render through, by name or index (`penumbra info`
    /// lists them) [default: the first; with none, one framing the scene].
    #[arg(long, value_name = "NAME|INDEX")]
    pub camera: Option<String>,
    /// Tone-mapping operator for PNG output.
    #[arg(long, value_enum, default_value_t = ToneArg::Filmic)]
    pub tonemap: ToneArg,
    /// trace: the CPU ray tracer; raster: the GPU renderer (wgpu),
    /// per-pixel shading of the abstract lights (the model of `--integrator
    /// local`), shadowed with `--shadows map|planar|volume`.
    #[arg(long, value_enum, default_value_t = Engine::Trace)]
    pub engine: Engine,
    /// Raster engine: samples per pixel of the colour and depth targets (1 or 4).
    #[arg(long, default_value_t = 1, value_parser = parse_msaa)]
    pub msaa: u32,
    /// Raster engine: shadows of the abstract lights. none (default): no
    /// shadows; map: shadow maps (directional: orthographic, spot:
    /// perspective, point: six cube faces); planar: projected onto the
    /// planar receiver(s) through the stencil buffer; volume: stencil shadow
    /// volumes (z-fail).
    #[arg(long, value_enum)]
    pub shadows: Option<ShadowArg>,
    /// Raster engine, --shadows map: edge of each shadow map in texels
    /// [default: 2048].
    #[arg(long, value_parser = parse_positive, allow_negative_numbers = true)]
    pub shadow_map_size: Option<u32>,
    /// Raster engine, --shadows map: PCF kernel N (N×N taps; 1 = hard
    /// shadows) [default: 1].
    #[arg(long, value_parser = parse_pcf, allow_negative_numbers = true)]
    pub pcf: Option<u32>,
    /// Raster engine: glossy environment reflections. 0 (default): the split
    /// sum, one lookup of the prefiltered map per pixel; N: N×N taps of each
    /// pixel's GGX lobe (N² lookups; more accurate, see docs/raster.md).
    #[arg(long, value_parser = parse_env_taps)]
    pub env_taps: Option<u32>,
    /// Raster engine: show a bake directory (`penumbra bake ...`): an AO
    /// bake multiplies the ambient light, a light map or radiosity bake
    /// gives the diffuse light. Repeat for an AO bake and an irradiance bake.
    #[arg(long)]
    pub bake: Vec<PathBuf>,
    #[command(flatten)]
    pub ao: AoArgs,
    #[command(flatten)]
    pub parts: PartArgs,
}

/// The screen-space AO flags of `render` and `bench` (raster engine).
#[derive(Args, Clone, Debug, Default)]
pub struct AoArgs {
    /// Raster engine: screen-space ambient occlusion of the environment
    /// (ambient) light: none (default), hemisphere (the notes' kernel,
    /// cosine-weighted) or gtao (horizon-based). Direct light is untouched.
    #[arg(long, value_enum)]
    pub ssao: Option<SsaoArg>,
    /// Raster engine, --ssao: radius R in scene units: occluders farther
    /// than R do not occlude, as with `--integrator ao --ao-distance R`
    /// [default: 0.1 × the scene's bounding radius].
    #[arg(long, value_parser = parse_length, allow_negative_numbers = true)]
    pub ao_radius: Option<f64>,
    /// Raster engine, --ssao: sample counts (hemisphere: 8/16/32 points;
    /// gtao: 2×4, 3×6, 4×8 slices × steps per side) [default: medium].
    #[arg(long, value_enum)]
    pub ao_quality: Option<AoQualityArg>,
    /// Raster engine, --ssao gtao: thin-occluder compensation c ≥ 0
    /// (horizon points towards the camera fade out sooner, as if their
    /// offset along the view were 1 + c times longer): less false
    /// occlusion behind thin objects, less true occlusion by walls that
    /// rise towards the camera [default: 0].
    #[arg(long, value_parser = parse_thin_occluders, allow_negative_numbers = true)]
    pub ao_thin: Option<f64>,
}

fn parse_thin_occluders(s: &str) -> Result<f64, String> {
    parse_number(
        s,
        "a number",
        |v| v >= 0.0,
        "the thin-occluder compensation is a number >= 0",
    )
}

impl AoArgs {
    /// Whether any of the flags was given.
    pub fn any(&self) -> bool {
        self.ssao.is_some()
            || self.ao_radius.is_some()
            || self.ao_quality.is_some()
            || self.ao_thin.is_some()
    }

    /// The raster path's screen-space AO (`--ao-radius` and `--ao-quality`
    /// need `--ssao`).
    pub fn settings(&self) -> Result<AoSettings> {
        let method = match self.ssao.unwrap_or(SsaoArg::None) {
            SsaoArg::None => AoMethod::None,
            SsaoArg::Hemisphere => AoMethod::Hemisphere,
            SsaoArg::Gtao => AoMethod::Gtao,
        };
        if method == AoMethod::None && (self.ao_radius.is_some() || self.ao_quality.is_some()) {
            bail!("--ao-radius and --ao-quality need --ssao hemisphere|gtao");
        }
        if method != AoMethod::Gtao && self.ao_thin.is_some() {
            bail!("--ao-thin needs --ssao gtao (the hemisphere kernel tests points, not horizons)");
        }
        Ok(AoSettings {
            method,
            radius: self.ao_radius.map(|r| r as f32),
            quality: match self.ao_quality.unwrap_or(AoQualityArg::Medium) {
                AoQualityArg::Low => AoQuality::Low,
                AoQualityArg::Medium => AoQuality::Medium,
                AoQualityArg::High => AoQuality::High,
            },
            thin_occluders: self.ao_thin.unwrap_or(0.0) as f32,
        })
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum SsaoArg {
    None,
    Hemisphere,
    Gtao,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum AoQualityArg {
    Low,
    Medium,
    High,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum ShadowArg {
    None,
    Map,
    Planar,
    Volume,
}

/// The raster path's shadow mode for a `--shadows` value.
pub fn shadow_mode(arg: ShadowArg) -> ShadowMode {
    match arg {
        ShadowArg::None => ShadowMode::None,
        ShadowArg::Map => ShadowMode::Map,
        ShadowArg::Planar => ShadowMode::Planar,
        ShadowArg::Volume => ShadowMode::Volume,
    }
}

fn parse_env_taps(s: &str) -> Result<u32, String> {
    match s.trim().parse::<u32>() {
        Ok(n) if n <= MAX_ENVIRONMENT_TAPS => Ok(n),
        _ => Err(format!(
            "'{s}' is not a number of environment taps (0 to {MAX_ENVIRONMENT_TAPS})"
        )),
    }
}

fn parse_pcf(s: &str) -> Result<u32, String> {
    match s.trim().parse::<u32>() {
        Ok(n) if (1..=MAX_PCF).contains(&n) => Ok(n),
        _ => Err(format!("'{s}' is not a PCF kernel size (1 to {MAX_PCF})")),
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Engine {
    Trace,
    Raster,
}

#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum ToneArg {
    Filmic,
    Clamp,
}

impl ToneArg {
    pub fn operator(self) -> ToneOperator {
        match self {
            ToneArg::Filmic => ToneOperator::Filmic,
            ToneArg::Clamp => ToneOperator::Clamp,
        }
    }
}

/// `penumbra render` as its own command line, for jobs that run a render
/// described by arguments (the farm's tasks).
#[derive(clap::Parser, Debug)]
#[command(name = "penumbra")]
struct RenderCommand {
    #[command(subcommand)]
    command: RenderOnly,
}

#[derive(clap::Subcommand, Debug)]
enum RenderOnly {
    Render(RenderArgs),
}

/// Runs `penumbra render ARGS...` (`args[0]` is `"render"`).
pub fn run_argv(args: &[String]) -> Result<()> {
    use clap::Parser;
    let argv = std::iter::once("penumbra".to_string()).chain(args.iter().cloned());
    let RenderOnly::Render(a) = RenderCommand::try_parse_from(argv)?.command;
    run(a)
}

pub fn run(args: RenderArgs) -> Result<()> {
    // Check the output before spending time on loading and rendering.
    check_output_path(&args.output)?;
    // Loading runs on the same workers as the render (MikkTSpace tangents
    // of large meshes are computed in parallel).
    let pool = thread_pool(args.threads)?;
    let mut scene = pool.install(|| scene_or_builtin(args.scene.as_deref()))?;
    if let Some(c) = &args.camera {
        scene
            .use_camera(c)
            .map_err(|e| anyhow::anyhow!("--camera: {e}"))?;
    }
    light_the_environment(&mut scene, &args.environment)?;
    let mut settings = scene.settings.clone();
    args.settings.apply(&mut settings);
    // Film: count + exact sums + sums of squares ≈ 80 B; a checkpoint's
    // copy, output copies and AOVs ≈ 100 B more.
    check_image_memory(
        settings.width,
        settings.height,
        if args.aovs { 420 } else { 180 },
    )?;
    args.parts.check(&settings, &args.output, args.aovs)?;

    if args.engine == Engine::Raster {
        let p = &args.parts;
        if p.writes_partial()
            || p.checkpoint.is_some()
            || p.resume.is_some()
            || p.target_relmse.is_some()
        {
            bail!(
                "--samples, --crop, --checkpoint, --resume and --target-relmse apply to --engine trace only (a raster frame is one pass)"
            );
        }
        return render_raster(&args, &scene, &settings);
    }
    if args.msaa != 1 {
        bail!("--msaa applies to --engine raster only");
    }
    for (set, flag) in [
        (!args.bake.is_empty(), "--bake"),
        (args.shadows.is_some(), "--shadows"),
        (args.shadow_map_size.is_some(), "--shadow-map-size"),
        (args.pcf.is_some(), "--pcf"),
        (args.ao.ssao.is_some(), "--ssao"),
        (
            args.ao.ao_radius.is_some(),
            "--ao-radius (the ray tracer's is --ao-distance)",
        ),
        (args.ao.ao_quality.is_some(), "--ao-quality"),
        (args.ao.ao_thin.is_some(), "--ao-thin"),
        (args.env_taps.is_some(), "--env-taps"),
    ] {
        if set {
            bail!(
                "{flag} applies to --engine raster only (the ray tracer's shadows come from --integrator direct, whitted or path)"
            );
        }
    }

    let identity = RenderIdentity::new(&scene, &settings, &args.parts);
    let resume = args.parts.resume(&identity)?;
    let resumed_at = resume.as_ref().map(|r| r.next);
    let checkpoints = args
        .parts
        .checkpoint_file()
        .map(|path| Checkpointer::new(path, args.parts.checkpoint_every, &identity));
    let checkpoint = |film: &penumbra_image::Film, samples: std::ops::Range<u32>| {
        if let Some(c) = &checkpoints {
            c.pass_done(film, samples);
        }
    };
    let bar = std::io::stderr().is_terminal().then(|| {
        let total = u64::from(identity.window.x.len() as u32)
            * u64::from(identity.window.y.len() as u32)
            * identity.samples.len() as u64;
        let pb = ProgressBar::new(total);
        pb.set_style(
            ProgressStyle::with_template("{spinner} [{elapsed_precise}] {wide_bar} {percent:>3}% {per_sec} samples, ETA {eta}")
                .unwrap_or_else(|_| ProgressStyle::default_bar()),
        );
        pb
    });
    let report = |p: Progress| {
        if let Some(b) = &bar {
            b.set_position(p.samples_done);
        }
    };
    let options = RenderOptions {
        time_limit: args.time_limit.map(Duration::from_secs_f64),
        progress: Some(&report),
        aovs: args.aovs,
        samples: Some(identity.samples.clone()),
        crop: Some(identity.window.clone()),
        resume,
        checkpoint: Some(&checkpoint),
        target_rel_mse: args.parts.target_relmse,
        scalar_paths: crate::options::scalar_paths_requested(),
        ..Default::default()
    };
    let out = pool.install(|| render(&scene, &settings, &options))?;
    if let Some(b) = &bar {
        b.finish_and_clear();
    }
    if let Some(c) = checkpoints {
        c.finish()?;
    }
    if args.parts.writes_partial() {
        let part = identity.part(out.film, out.samples.clone());
        penumbra_image::write_partial_film(&args.output, &part)?;
    } else {
        let aovs: Vec<(&str, &penumbra_image::Image)> =
            out.aovs.iter().map(|(n, i)| (n.as_str(), i)).collect();
        let tm = tone_mapping(&args, &out.image, Some(&out.surface));
        write_image(&args.output, &out.image, &aovs, &tm)
            .with_context(|| format!("writing {}", args.output.display()))?;
    }
    let ended = match out.stop {
        Stop::Complete => "complete".to_string(),
        Stop::TimeLimit => "stopped by --time-limit".to_string(),
        Stop::TargetReached => format!(
            "stopped at --target-relmse, estimated relMSE {:.3e}",
            penumbra_image::noise_rel_mse(&out.image, &out.variance)
        ),
    };
    let part = if args.parts.writes_partial() {
        format!(
            ", partial film of samples {}..{}",
            out.samples.start, out.samples.end
        )
    } else {
        String::new()
    };
    let resumed = resumed_at.map_or(String::new(), |n| format!(", resumed at sample {n}"));
    let lanes = if out.wavefront {
        ", 16 paths at a time"
    } else {
        ""
    };
    eprintln!(
        "penumbra: {} {}x{} at {} spp ({ended}{resumed}{part}{lanes}) in {:.2} s (+{:.2} s BVH) -> {}",
        settings.integrator,
        identity.window.x.len(),
        identity.window.y.len(),
        out.spp,
        out.render_seconds,
        out.build_seconds,
        args.output.display()
    );
    Ok(())
}

/// `--tonemap` with `--exposure` resolved for `image` (metering the
/// `metered` pixels); says which exposure `auto` chose when the output is a
/// PNG.
fn tone_mapping(
    args: &RenderArgs,
    image: &penumbra_image::Image,
    metered: Option<&[bool]>,
) -> ToneMapping {
    let ev = args.exposure.resolve(image, metered);
    let png = penumbra_image::ImageFormat::from_path(&args.output)
        .is_some_and(|f| f == penumbra_image::ImageFormat::Png);
    if png && args.exposure == Exposure::Auto {
        eprintln!("penumbra: exposure auto: {ev:+.2} EV (--exposure EV fixes it)");
    }
    ToneMapping {
        exposure_ev: ev,
        operator: args.tonemap.operator(),
    }
}

/// Applies `--environment` and says what it did.
pub fn light_the_environment(scene: &mut Scene, choice: &EnvironmentChoice) -> Result<()> {
    if let Some(note) =
        apply_environment(scene, choice).map_err(|e| anyhow::anyhow!("--environment: {e}"))?
    {
        eprintln!("penumbra: note: {note}");
    }
    Ok(())
}

/// Parses `--environment`: `default`, `none` or a file.
pub fn parse_environment(s: &str) -> Result<EnvironmentChoice, String> {
    match s.trim() {
        "default" => Ok(EnvironmentChoice::Default),
        "none" => Ok(EnvironmentChoice::None),
        "studio" => Ok(EnvironmentChoice::Studio),
        "" => Err("an empty --environment (default, none or FILE.hdr|.exr)".into()),
        file => Ok(EnvironmentChoice::File(PathBuf::from(file))),
    }
}

/// `--engine raster`: the scene's camera and film size, the same output
/// files and tone mapping as the CPU path.
fn render_raster(args: &RenderArgs, scene: &Scene, settings: &RenderSettings) -> Result<()> {
    let ao = args.ao.settings()?;
    if args.aovs && args.bake.is_empty() && !ao.enabled() {
        bail!(
            "--aovs with --engine raster writes the ambient-occlusion term (give --ssao hemisphere|gtao) and the looked-up bake values (ao, irradiance: give --bake DIR)"
        );
    }
    let bakes: Vec<penumbra_bake::LoadedBake> = args
        .bake
        .iter()
        .map(|dir| penumbra_bake::read_bake(dir, scene))
        .collect::<Result<_, _>>()?;
    let maps = penumbra_raster::BakedMaps::from_bakes(&bakes)?;
    if args
        .settings
        .integrator
        .is_some_and(|i| i != IntegratorKind::Local)
    {
        eprintln!(
            "penumbra: warning: --engine raster shades like --integrator local (direct light from the abstract lights; shadows only with --shadows map|planar|volume); --integrator is ignored"
        );
    }
    let shadows = shadow_mode(args.shadows.unwrap_or(ShadowArg::None));
    if shadows != ShadowMode::Map && (args.shadow_map_size.is_some() || args.pcf.is_some()) {
        bail!("--shadow-map-size and --pcf need --shadows map");
    }
    let camera = scene_camera_for(scene, settings.width, settings.height);
    let (out, adapter) = penumbra_raster::render_scene(
        scene,
        &camera,
        settings.width,
        settings.height,
        RasterOptions {
            msaa: args.msaa,
            shadows,
            shadow_map_size: args.shadow_map_size.unwrap_or(DEFAULT_SHADOW_MAP_SIZE),
            pcf: args.pcf.unwrap_or(1),
            ao,
            environment_taps: args.env_taps.unwrap_or(0),
            ..Default::default()
        },
        &maps,
        args.aovs,
    )?;
    for w in &out.warnings {
        eprintln!("penumbra: warning: {w}");
    }
    let aovs: Vec<(&str, &penumbra_image::Image)> =
        out.aovs.iter().map(|(n, i)| (n.as_str(), i)).collect();
    write_image(
        &args.output,
        &out.image,
        &aovs,
        &tone_mapping(args, &out.image, Some(&out.surface)),
    )
    .with_context(|| format!("writing {}", args.output.display()))?;
    let gpu: String = penumbra_raster::timing::by_kind(&out.passes)
        .iter()
        .map(|(kind, n, ms)| match n {
            1 => format!(", {kind} {ms:.2} ms GPU"),
            _ => format!(", {n} {kind} passes {ms:.2} ms GPU"),
        })
        .collect();
    eprintln!(
        "penumbra: raster {}x{} MSAA {} on {} in {:.1} ms (frame {:.1} ms{gpu}) -> {}",
        settings.width,
        settings.height,
        args.msaa,
        adapter,
        out.total_ms,
        out.frame_ms,
        args.output.display()
    );
    Ok(())
}
