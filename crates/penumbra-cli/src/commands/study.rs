//! `penumbra study`: every technique of the notes against the path-traced
//! truth, in one report (see the penumbra-study crate and docs/study.md).

use crate::options::{
    parse_msaa, parse_positive, parse_resolution, parse_seconds, scene_or_builtin, thread_pool,
};
use anyhow::{Result, bail};
use clap::Args;
use indicatif::{ProgressBar, ProgressStyle};
use penumbra_study::{StudyOptions, Target, parse_list, run_study};
use std::io::IsTerminal;
use std::path::PathBuf;

#[derive(Args, Debug)]
pub struct StudyArgs {
    /// Scene file (.gltf, .glb, .obj, .toml). Default: the built-in Cornell box.
    pub scene: Option<PathBuf>,
    /// Report directory (created, or an earlier report replaced): index.html,
    /// study.json, study.csv, the images and bakes.
    #[arg(short, long)]
    pub output: PathBuf,
    /// A reference image (.exr) to judge against instead of rendering the
    /// path-traced truth; it must have the study's resolution.
    #[arg(long)]
    pub reference: Option<PathBuf>,
    /// Render each truth (path, direct, ao) with this many samples per pixel.
    #[arg(long, value_parser = parse_positive, allow_negative_numbers = true, conflicts_with = "target_relmse")]
    pub spp: Option<u32>,
    /// Render each truth until its own relMSE (estimated from the film's
    /// variance) is below E [default: 0.002].
    #[arg(long, value_parser = parse_relmse, allow_negative_numbers = true)]
    pub target_relmse: Option<f64>,
    /// Most seconds each truth may take (it stops at the end of a sample
    /// pass and the report says so).
    #[arg(long, value_parser = parse_seconds, allow_negative_numbers = true)]
    pub time_budget: Option<f64>,
    /// Comma-separated techniques or groups (all, trace, shadows, maps,
    /// environment, ao, bakes; ids such as trace-path, raster-volume,
    /// raster-map-1024-pcf3, ssao-gtao, lightmap) [default: all].
    #[arg(long, default_value = "all")]
    pub techniques: String,
    /// Image size WIDTHxHEIGHT [default: the scene's].
    #[arg(long, value_parser = parse_resolution)]
    pub resolution: Option<(u32, u32)>,
    /// Samples per pixel of the ray-traced rows [default: the scene's].
    #[arg(long, value_parser = parse_positive, allow_negative_numbers = true)]
    pub row_spp: Option<u32>,
    /// Maximum path segments of path, whitted and the light-map bakes
    /// [default: the scene's].
    #[arg(long, value_parser = parse_positive, allow_negative_numbers = true)]
    pub max_depth: Option<u32>,
    /// Samples per pixel of the raster rows (1 or 4).
    #[arg(long, default_value_t = 4, value_parser = parse_msaa)]
    pub msaa: u32,
    /// Random seed of every render and bake.
    #[arg(long)]
    pub seed: Option<u32>,
    /// Worker threads (default: all cores).
    #[arg(long, value_parser = parse_positive, allow_negative_numbers = true)]
    pub threads: Option<u32>,
}

/// The study's default truth target.
pub const DEFAULT_TARGET_RELMSE: f64 = 0.002;

fn parse_relmse(s: &str) -> Result<f64, String> {
    let v: f64 = s
        .trim()
        .parse()
        .map_err(|_| format!("'{s}' is not a number"))?;
    if !(v > 0.0 && v.is_finite()) {
        return Err(format!("{v} must be a positive relMSE (e.g. 0.001)"));
    }
    Ok(v)
}

pub fn run(args: StudyArgs) -> Result<()> {
    let techniques =
        parse_list(&args.techniques).map_err(|e| anyhow::anyhow!("--techniques: {e}"))?;
    penumbra_study::output_dir::check(&args.output)?;
    if let Some(r) = &args.reference
        && !r.is_file()
    {
        bail!("--reference {}: no such file", r.display());
    }
    let scene = scene_or_builtin(args.scene.as_deref())?;
    let mut settings = scene.settings.clone();
    if let Some((w, h)) = args.resolution {
        settings.width = w;
        settings.height = h;
    }
    if let Some(n) = args.row_spp {
        settings.spp = n;
    }
    if let Some(d) = args.max_depth {
        settings.max_depth = d;
    }
    if let Some(s) = args.seed {
        settings.seed = s;
    }
    let options = StudyOptions {
        techniques,
        settings,
        reference: args.reference.clone(),
        target: match args.spp {
            Some(n) => Target::Spp(n),
            None => Target::RelMse(args.target_relmse.unwrap_or(DEFAULT_TARGET_RELMSE)),
        },
        time_budget: args.time_budget,
        msaa: args.msaa,
        scene_file: args.scene.as_ref().map(|p| p.display().to_string()),
    };
    let bar = std::io::stderr().is_terminal().then(|| {
        let pb = ProgressBar::new(0);
        pb.set_style(
            ProgressStyle::with_template(
                "{spinner} [{elapsed_precise}] {pos}/{len} {wide_bar} {msg}",
            )
            .unwrap_or_else(|_| ProgressStyle::default_bar()),
        );
        pb.enable_steady_tick(std::time::Duration::from_millis(200));
        pb
    });
    let progress = |what: &str, done: usize, total: usize| match &bar {
        Some(b) => {
            b.set_length(total as u64);
            b.set_position(done as u64);
            b.set_message(what.to_string());
        }
        None => eprintln!("penumbra: study [{}/{total}] {what}", done + 1),
    };
    let pool = thread_pool(args.threads)?;
    let study = pool.install(|| run_study(&scene, &options, &args.output, &progress));
    if let Some(b) = &bar {
        b.finish_and_clear();
    }
    let study = study?;
    for t in &study.truths {
        eprintln!(
            "penumbra: truth {:<7} {}{}",
            t.id,
            t.source,
            t.noise_rel_mse.map_or(String::new(), |n| format!(
                ", own noise relMSE {n:.2e}, {:.1} s",
                t.seconds
            ))
        );
    }
    eprintln!(
        "penumbra: {:<28} {:>10} {:>10} {:>8} {:>10} {:>9}",
        "technique", "relMSE q", "relMSE GI", "FLIP", "bake s", "time s"
    );
    for r in &study.rows {
        eprintln!(
            "penumbra: {:<28} {:>10.5} {:>10.5} {:>8.4} {:>10} {:>9.3}",
            r.id,
            r.quantity.rel_mse,
            r.full.rel_mse,
            r.full.flip_mean,
            r.cost
                .bake_seconds
                .map_or("-".into(), |s| format!("{s:.2}")),
            r.cost.seconds
        );
    }
    for s in &study.skipped {
        eprintln!("penumbra: skipped {}: {}", s.id, s.reason);
    }
    eprintln!(
        "penumbra: study of {} rows in {:.1} s -> {}",
        study.rows.len(),
        study.total_seconds,
        args.output.join("index.html").display()
    );
    Ok(())
}
