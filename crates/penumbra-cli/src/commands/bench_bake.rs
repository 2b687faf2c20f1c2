//! `penumbra bench --bake [SCENE]`: the bakes' ray throughput beside the
//! path tracer's on the same scene, in one run (rays counted by
//! `penumbra_trace::stats`: closest-hit and shadow rays alike), and the
//! radiosity solve's time against its patch count.

use crate::commands::bench::BenchArgs;
use crate::options::{load_scene, thread_pool};
use anyhow::Result;
use penumbra_bake::radiosity::{RadiositySettings, bake_radiosity};
use penumbra_bake::{AoSettings, AtlasSettings, LightmapSettings, bake_ao, bake_lightmap};
use penumbra_scene::IntegratorKind;
use penumbra_trace::stats::rays_traced;
use penumbra_trace::{RenderOptions, render};

pub fn run(args: BenchArgs) -> Result<()> {
    let scene = match &args.scene {
        Some(p) => load_scene(p)?,
        None => penumbra_scene::builtin::cornell_box(),
    };
    let pool = thread_pool(args.threads)?;
    pool.install(|| -> Result<()> {
        let spp = args.spp.max(1);
        let line = |name: &str, seconds: f64, rays: u64, extra: String| {
            let mrays = rays as f64 / seconds.max(1e-9) / 1e6;
            if args.json {
                println!(
                    "{{\"measure\":\"{name}\",\"seconds\":{seconds:.4},\"rays\":{rays},\"mrays_per_s\":{mrays:.4}{extra}}}"
                );
            } else {
                println!("{name:<24} {seconds:>9.3} s  {mrays:>8.3} Mrays/s  ({rays} rays{extra})");
            }
        };
        if !args.json {
            println!(
                "penumbra bench --bake: {} triangles, {} threads, {spp} samples per pixel and per texel",
                scene.triangle_count(),
                rayon::current_num_threads()
            );
        }
        let mut settings = scene.settings.clone();
        settings.integrator = IntegratorKind::Path;
        settings.spp = spp;
        let r0 = rays_traced();
        let out = render(&scene, &settings, &RenderOptions::default())?;
        line("path", out.render_seconds, rays_traced() - r0, String::new());
        let atlas = AtlasSettings::default();
        let lm = bake_lightmap(
            &scene,
            &LightmapSettings {
                samples: spp,
                ..Default::default()
            },
            &atlas,
            None,
        )?;
        let texels = |valid: u64| format!(", {valid} texels");
        line("bake lightmap", lm.stats.bake_seconds, lm.stats.rays, texels(lm.stats.valid));
        let radius = scene
            .bounds()
            .map_or(1.0, |(lo, hi)| 0.5 * (hi - lo).length());
        let ao = bake_ao(
            &scene,
            &AoSettings {
                samples: spp,
                distance: 0.1 * radius,
                seed: 0,
            },
            &atlas,
            None,
        )?;
        line("bake ao (D = R/10)", ao.stats.bake_seconds, ao.stats.rays, texels(ao.stats.valid));
        for &patches in &args.patches {
            let r = bake_radiosity(
                &scene,
                &RadiositySettings {
                    patches,
                    tolerance: 1e-3,
                    rays_per_patch: 2000,
                    seed: 0,
                },
                None,
            )?;
            let iterations = r.convergence.last().map_or(0, |s| s.iteration);
            line(
                &format!("radiosity {patches}"),
                r.stats.bake_seconds,
                r.stats.rays,
                format!(", {} patches, {iterations} iterations", r.stats.valid),
            );
        }
        Ok(())
    })
}
