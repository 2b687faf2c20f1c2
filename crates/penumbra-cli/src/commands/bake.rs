//! `penumbra bake ao | lightmap | radiosity`: precompute a quantity per
//! texel of the scene's light-map atlas and write a bake directory.

use crate::options::{parse_positive, scene_or_builtin, thread_pool};
use anyhow::{Context, Result, bail};
use clap::{Args, Subcommand};
use indicatif::{ProgressBar, ProgressStyle};
use penumbra_bake::{AtlasSettings, Bake, Density};
use penumbra_scene::Scene;
use std::io::IsTerminal;
use std::path::PathBuf;
use std::sync::Mutex;

#[derive(Args, Debug)]
pub struct BakeArgs {
    #[command(subcommand)]
    pub what: BakeCommand,
}

#[derive(Subcommand, Debug)]
pub enum BakeCommand {
    /// Ambient occlusion kA per texel, as `render --integrator ao` defines it.
    Ao(AoArgs),
    /// Irradiance E [W/m²] per texel by path tracing, direct + indirect.
    Lightmap(LightmapArgs),
    /// Irradiance E [W/m²] by classic radiosity (progressive refinement).
    Radiosity(RadiosityArgs),
}

/// Options every bake shares.
#[derive(Args, Debug)]
pub struct CommonArgs {
    /// Scene file (.gltf, .glb, .obj, .toml). Default: the built-in Cornell box.
    pub scene: Option<PathBuf>,
    /// Output bake directory (created, or an earlier bake replaced).
    #[arg(short, long)]
    pub output: PathBuf,
    /// Texel density in texels per scene unit (one page that grows to fit;
    /// with --max-size, as many pages of that size as needed).
    #[arg(long, value_parser = parse_density, allow_negative_numbers = true)]
    pub texels_per_unit: Option<f32>,
    /// Largest atlas page edge in texels; alone, the highest density that
    /// fits one page [default: 512].
    #[arg(long, value_parser = parse_positive, allow_negative_numbers = true)]
    pub max_size: Option<u32>,
    /// Empty texels around each chart [default: 2].
    #[arg(long, value_parser = parse_positive, allow_negative_numbers = true)]
    pub padding: Option<u32>,
    /// Random seed; the same seed gives the same bake for any --threads.
    #[arg(long, default_value_t = 0)]
    pub seed: u32,
    /// Worker threads (default: all cores).
    #[arg(long, value_parser = parse_positive, allow_negative_numbers = true)]
    pub threads: Option<u32>,
}

#[derive(Args, Debug)]
pub struct AoArgs {
    #[command(flatten)]
    pub common: CommonArgs,
    /// Rays per texel.
    #[arg(long, default_value_t = 256, value_parser = parse_positive, allow_negative_numbers = true)]
    pub samples: u32,
    /// AO ray length in scene units (default: unlimited, as the ao integrator).
    #[arg(long, value_parser = parse_distance, allow_negative_numbers = true)]
    pub ao_distance: Option<f32>,
    /// Also write the scene as glTF 2.0 (.glb) with the AO as each
    /// material's occlusionTexture on TEXCOORD_1 (glTF scenes only).
    #[arg(long)]
    pub gltf: Option<PathBuf>,
}

#[derive(Args, Debug)]
pub struct LightmapArgs {
    #[command(flatten)]
    pub common: CommonArgs,
    /// Paths per texel.
    #[arg(long, default_value_t = 128, value_parser = parse_positive, allow_negative_numbers = true)]
    pub samples: u32,
    /// Surfaces light may scatter from on its way (0: direct light only;
    /// 6 matches `render --max-depth 8`).
    #[arg(long, default_value_t = 6)]
    pub bounces: u32,
    /// Leave out the light arriving directly from the lights (for real-time
    /// direct light and shadows on top).
    #[arg(long)]
    pub indirect_only: bool,
    /// Also write one map per light; they add up to the total.
    #[arg(long)]
    pub per_light: bool,
}

#[derive(Args, Debug)]
pub struct RadiosityArgs {
    #[command(flatten)]
    pub common: CommonArgs,
    /// About how many patches (texels of a coarse atlas) to solve for.
    #[arg(long, default_value_t = 10_000, value_parser = parse_positive, allow_negative_numbers = true)]
    pub patches: u32,
    /// Stop when the unshot power is below this fraction of the emitted power.
    #[arg(long, default_value_t = 1e-3, value_parser = parse_tolerance, allow_negative_numbers = true)]
    pub tolerance: f32,
    /// Form-factor rays cast per patch of the scene, spread over the shots
    /// in proportion to the power they shoot.
    #[arg(long, default_value_t = 2000, value_parser = parse_positive, allow_negative_numbers = true)]
    pub rays_per_patch: u32,
}

fn parse_density(s: &str) -> Result<f32, String> {
    let v: f32 = s
        .trim()
        .parse()
        .map_err(|_| format!("'{s}' is not a number of texels per unit"))?;
    if !(v > 0.0 && v.is_finite()) {
        return Err(format!("{v} must be a positive number of texels per unit"));
    }
    Ok(v)
}

fn parse_distance(s: &str) -> Result<f32, String> {
    let v: f32 = s
        .trim()
        .parse()
        .map_err(|_| format!("'{s}' is not a distance"))?;
    if v.is_nan() || v <= 0.0 {
        return Err(format!("{v} must be a positive distance"));
    }
    Ok(v)
}

fn parse_tolerance(s: &str) -> Result<f32, String> {
    let v: f32 = s
        .trim()
        .parse()
        .map_err(|_| format!("'{s}' is not a number"))?;
    if !(v > 0.0 && v < 1.0) {
        return Err(format!(
            "{v} must lie between 0 and 1 (a fraction of the emitted power)"
        ));
    }
    Ok(v)
}

impl CommonArgs {
    fn atlas(&self) -> AtlasSettings {
        let mut a = AtlasSettings::default();
        a.density = match (self.texels_per_unit, self.max_size) {
            (Some(d), Some(n)) => Density::TexelsPerUnitPaged {
                texels_per_unit: d,
                page: n,
            },
            (Some(d), None) => Density::TexelsPerUnit(d),
            (None, Some(n)) => Density::MaxSize(n),
            (None, None) => a.density,
        };
        if let Some(p) = self.padding {
            a.padding = p;
        }
        a
    }

    fn load(&self) -> Result<Scene> {
        scene_or_builtin(self.scene.as_deref())
    }

    fn scene_name(&self) -> String {
        self.scene
            .as_ref()
            .map_or("(built-in Cornell box)".to_string(), |p| {
                p.display().to_string()
            })
    }
}

/// A progress bar over the stages of a bake (none when stderr is not a
/// terminal).
struct Bar {
    bar: Option<ProgressBar>,
    stage: Mutex<String>,
}

impl Bar {
    fn new() -> Self {
        let bar = std::io::stderr().is_terminal().then(|| {
            let pb = ProgressBar::new(0);
            pb.set_style(
                ProgressStyle::with_template(
                    "{spinner} [{elapsed_precise}] {msg:<28} {wide_bar} {percent:>3}% ETA {eta}",
                )
                .unwrap_or_else(|_| ProgressStyle::default_bar()),
            );
            pb
        });
        Self {
            bar,
            stage: Mutex::new(String::new()),
        }
    }

    fn report(&self, stage: &str, done: u64, total: u64) {
        let Some(b) = &self.bar else { return };
        let mut s = self.stage.lock().unwrap_or_else(|e| e.into_inner());
        if *s != stage {
            *s = stage.to_string();
            b.set_message(stage.to_string());
            b.reset();
        }
        b.set_length(total.max(done));
        b.set_position(done);
    }

    fn finish(&self) {
        if let Some(b) = &self.bar {
            b.finish_and_clear();
        }
    }
}

pub fn run(args: BakeArgs) -> Result<()> {
    let common = match &args.what {
        BakeCommand::Ao(a) => &a.common,
        BakeCommand::Lightmap(a) => &a.common,
        BakeCommand::Radiosity(a) => &a.common,
    };
    penumbra_bake::bake_dir::check_output_dir(&common.output)?;
    let scene = common.load()?;
    let atlas = common.atlas();
    atlas.validate()?;
    let pool = thread_pool(common.threads)?;
    let bar = Bar::new();
    let progress = |stage: &str, done: u64, total: u64| bar.report(stage, done, total);
    let bake = pool.install(|| -> Result<Bake> {
        Ok(match &args.what {
            BakeCommand::Ao(a) => {
                if let Some(g) = &a.gltf
                    && !g.extension().is_some_and(|e| e.eq_ignore_ascii_case("glb"))
                {
                    bail!(
                        "--gltf {}: the file must end in .glb (binary glTF)",
                        g.display()
                    );
                }
                penumbra_bake::bake_ao(
                    &scene,
                    &penumbra_bake::AoSettings {
                        samples: a.samples,
                        distance: a.ao_distance.unwrap_or(f32::INFINITY),
                        seed: common.seed,
                    },
                    &atlas,
                    Some(&progress),
                )?
            }
            BakeCommand::Lightmap(a) => penumbra_bake::bake_lightmap(
                &scene,
                &penumbra_bake::LightmapSettings {
                    samples: a.samples,
                    bounces: a.bounces,
                    indirect_only: a.indirect_only,
                    per_light: a.per_light,
                    seed: common.seed,
                },
                &atlas,
                Some(&progress),
            )?,
            BakeCommand::Radiosity(a) => penumbra_bake::radiosity::bake_radiosity(
                &scene,
                &penumbra_bake::radiosity::RadiositySettings {
                    patches: a.patches,
                    tolerance: a.tolerance,
                    rays_per_patch: a.rays_per_patch,
                    seed: common.seed,
                },
                Some(&progress),
            )?,
        })
    });
    bar.finish();
    let bake = bake?;
    for w in &bake.warnings {
        eprintln!("penumbra: warning: {w}");
    }
    penumbra_bake::write_bake(&bake, &scene, &common.output, Some(&common.scene_name()))
        .with_context(|| format!("writing the bake {}", common.output.display()))?;
    if let BakeCommand::Ao(a) = &args.what
        && let Some(g) = &a.gltf
    {
        for w in penumbra_bake::gltf_export::write_glb_with_warnings(&bake, &scene, g)? {
            eprintln!("penumbra: warning: glTF export: {w}");
        }
        eprintln!(
            "penumbra: glTF with the AO as occlusionTexture -> {}",
            g.display()
        );
    }
    let s = &bake.stats;
    let a = &bake.atlas;
    eprintln!(
        "penumbra: {} bake of {}: {} page(s) of {}x{} texels ({:.2} texels/unit, {} charts, {:.0} % used), {} texels baked, {} inside geometry; {} samples each; {:.2} s (+{:.2} s atlas and BVH), {:.2} Mrays/s -> {}",
        bake.kind.name(),
        common.scene_name(),
        a.pages,
        a.width,
        a.height,
        a.texels_per_unit,
        a.charts,
        100.0 * a.utilization,
        s.valid,
        s.invalid,
        bake.samples,
        s.bake_seconds,
        s.prepare_seconds,
        if s.bake_seconds > 0.0 {
            s.rays as f64 / s.bake_seconds / 1e6
        } else {
            0.0
        },
        common.output.display()
    );
    Ok(())
}
