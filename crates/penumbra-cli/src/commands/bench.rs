//! `penumbra bench`: BVH build rate, closest-hit throughput for coherent and
//! incoherent rays (traced one at a time, a few interleaved per thread,
//! and in packets), and path-tracing speed; with `--engine raster`, GPU time
//! per pass of the raster path (commands/bench_raster.rs).

use crate::commands::bench_raster::{self, RasterBench};
use crate::commands::render::{AoArgs, Engine, ShadowArg, shadow_mode};
use crate::options::{load_scene, parse_positive, parse_resolution, thread_pool};
use anyhow::{Context, Result, bail};
use clap::Args;
use glam::{Mat4, Vec3};
use penumbra_scene::{Camera, IntegratorKind, Material, Projection, Scene, SceneLight};
use penumbra_shading::Rgb;
use penumbra_shading::light::{DirectionalLight, Light};
use penumbra_trace::accel::{Accel, BuildQuality, Kernel};
use penumbra_trace::bench::{
    Measure, Tracing, bench_mesh, camera_rays, incoherent_rays, measure_closest_hit,
    parse_ray_file, write_obj, write_ray_file,
};
use penumbra_trace::geometry::SceneGeometry;
use penumbra_trace::ray::Ray;
use penumbra_trace::{RenderOptions, render, scene_camera};
use std::path::PathBuf;

#[derive(Args, Debug)]
pub struct BenchArgs {
    /// Scene to benchmark. Without SCENE or --mesh: the generated bench mesh.
    pub scene: Option<PathBuf>,
    /// An OBJ mesh to benchmark (lit by a directional light, default camera).
    #[arg(long, conflicts_with = "scene")]
    pub mesh: Option<PathBuf>,
    /// Triangles in the generated bench mesh [default: 1000000 for trace,
    /// 200000 for raster].
    #[arg(long, value_parser = parse_positive)]
    pub triangles: Option<u32>,
    /// Write the generated bench mesh as OBJ (for other renderers) and exit.
    #[arg(long)]
    pub write_mesh: Option<PathBuf>,
    /// Trace exactly these rays (little-endian f32 ox oy oz dx dy dz per ray, no header).
    #[arg(long)]
    pub rays: Option<PathBuf>,
    /// Write the coherent and incoherent ray sets to FILE.coherent / FILE.incoherent.
    #[arg(long)]
    pub write_rays: Option<PathBuf>,
    /// Camera-ray image size for the coherent set (square).
    #[arg(long, default_value_t = 1024, value_parser = parse_positive)]
    pub ray_resolution: u32,
    /// Samples per pixel of the path-tracing measurement (0 skips it).
    #[arg(long, default_value_t = 16)]
    pub spp: u32,
    /// Worker threads (default: all cores).
    #[arg(long, value_parser = parse_positive)]
    pub threads: Option<u32>,
    /// One JSON object per line.
    #[arg(long)]
    pub json: bool,
    /// trace: BVH and ray-tracing throughput on the CPU; raster: GPU time
    /// per pass of the raster path.
    #[arg(long, value_enum, default_value_t = Engine::Trace)]
    pub engine: Engine,
    /// Trace: whether the closest-hit measures (ray sets and `--rays`)
    /// prefetch the BVH children each node enters; `auto` (the renderer's
    /// choice) prefetches when the tree is larger than about an L2 cache.
    /// The path measure always uses `auto`.
    #[arg(long, value_enum, default_value_t = PrefetchArg::Auto)]
    pub prefetch: PrefetchArg,
    /// Trace: the traversal kernel of the closest-hit measures (default:
    /// the fastest this CPU runs); an error if the CPU cannot run it.
    #[arg(long, value_enum)]
    pub kernel: Option<KernelArg>,
    /// Raster: image size.
    #[arg(long, default_value = "1920x1080", value_parser = parse_resolution)]
    pub resolution: (u32, u32),
    /// Raster: comma-separated light counts, each a set of generated point
    /// lights of finite range just above the scene's surfaces (range
    /// 2.5 R/√count, R the bounds radius); 0 = the scene's own lights.
    #[arg(long, value_delimiter = ',', default_value = "1,8,1024")]
    pub lights: Vec<u32>,
    /// Raster: timed frames per light count (the median is reported).
    #[arg(long, default_value_t = 5, value_parser = parse_positive)]
    pub frames: u32,
    /// Raster: shadows (as `penumbra render --shadows`).
    #[arg(long, value_enum, default_value_t = ShadowArg::None)]
    pub shadows: ShadowArg,
    /// Raster: samples per pixel (1 or 4).
    #[arg(long, default_value_t = 1)]
    pub msaa: u32,
    /// Raster: shade every pixel with every light (no tiled light culling),
    /// the baseline culling is measured against.
    #[arg(long)]
    pub no_light_culling: bool,
    /// Raster: screen-space AO (as `penumbra render`); its passes (ao
    /// inputs, depth MIPs, the method, denoise) are timed each.
    #[command(flatten)]
    pub ao: AoArgs,
    /// Raster: also measure every light count showing these bake
    /// directories (made for SCENE). Trace: `--bake` alone measures the
    /// bakes' ray throughput beside the path tracer's on SCENE (default:
    /// the built-in Cornell box), in one run.
    #[arg(long, num_args = 0..)]
    pub bake: Option<Vec<PathBuf>>,
    /// Trace, textured scenes: also the cost of each kind of map alone
    /// (base colour, metallic–roughness, normal map): the scene with
    /// only that kind replaced by its mean, against the textured scene,
    /// timed in the same order as the total.
    #[arg(long)]
    pub texture_breakdown: bool,
    /// With --bake (trace): patch counts of the radiosity timings.
    #[arg(long, value_delimiter = ',', default_value = "1000,4000,16000")]
    pub patches: Vec<u32>,
}

/// `bench --prefetch`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum PrefetchArg {
    Auto,
    On,
    Off,
}

/// `bench --kernel`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum KernelArg {
    Portable,
    Avx2,
    Avx512,
}

/// A scene of `meshes` in grey, lit by a sun, framed by the camera.
fn mesh_scene(meshes: Vec<(penumbra_scene::Mesh, Mat4)>) -> Scene {
    let mut scene = Scene::default();
    let mat = scene.add_material(Material::lambert("grey", Rgb::splat(0.7)));
    for (mut mesh, transform) in meshes {
        mesh.material = mat;
        scene.add_mesh(mesh, transform);
    }
    scene.lights.push(SceneLight {
        name: "sun".into(),
        light: Light::Directional(DirectionalLight {
            direction: Vec3::new(-0.3, -1.0, -0.5).normalize(),
            irradiance: Rgb::splat(3.0),
        }),
    });
    scene.background = Rgb::splat(0.2);
    // Frame the mesh so that it fills the view: most camera rays hit it.
    if let Some((lo, hi)) = scene.bounds() {
        let centre = 0.5 * (lo + hi);
        let half = 0.5 * (hi - lo);
        let fov_y = 40f32.to_radians();
        let eye = centre + Vec3::Z * (half.z + half.y.max(half.x) / (0.5 * fov_y).tan() * 0.9);
        scene.camera = Some(Camera::look_at(
            eye,
            centre,
            Vec3::Y,
            Projection::Perspective { fov_y },
        ));
    }
    scene
}

/// The time of each stage of the path measure's `samples` samples (a
/// `stage-timing` build): ticks and calls per sample, ticks per call and
/// the share of a sample's time (stages nest: see `penumbra_trace::stages`).
fn report_stages(stages: &[penumbra_trace::stages::StageTime], samples: u64, json: bool) {
    use penumbra_trace::stages::Stage;
    let per_sample = |x: u64| x as f64 / samples.max(1) as f64;
    let sample_ticks = stages
        .iter()
        .find(|s| s.stage == Stage::Sample)
        .map_or(0, |s| s.ticks);
    for s in stages {
        let share = 100.0 * s.ticks as f64 / sample_ticks.max(1) as f64;
        let per_call = s.ticks as f64 / s.calls.max(1) as f64;
        if json {
            println!(
                "{{\"stage\":\"{}\",\"ticks_per_sample\":{:.1},\"calls_per_sample\":{:.3},\"ticks_per_call\":{per_call:.1},\"percent_of_sample\":{share:.2}}}",
                s.stage.name(),
                per_sample(s.ticks),
                per_sample(s.calls)
            );
        } else {
            // A nested stage indented under the one it runs inside.
            let indent = if s.stage.within().is_some() { "  " } else { "" };
            println!(
                "stage {:<14} {:>8.1} ticks/sample {:>5.1} %  {:>5.2} calls/sample {:>8.1} ticks/call",
                format!("{indent}{}", s.stage.name()),
                per_sample(s.ticks),
                share,
                per_sample(s.calls),
                per_call
            );
        }
    }
}

/// What the single-ray walk visited since the last call (a `stage-timing`
/// build), per query of the measure just reported: `queries` rays, or the
/// path measure's closest-hit queries. Packets are left out: only their
/// rays' single-ray parts would be counted.
fn report_visits(name: &str, queries: u64, json: bool) {
    let Some(v) = penumbra_trace::stages::take_visits() else {
        return;
    };
    let per = |x: u64| x as f64 / queries.max(1) as f64;
    let (nodes, leaves, triangles) = (per(v.nodes), per(v.leaves), per(v.triangles));
    if json {
        println!(
            "{{\"visits\":\"{name}\",\"nodes_per_query\":{nodes:.2},\"leaves_per_query\":{leaves:.2},\"triangles_per_query\":{triangles:.2}}}"
        );
    } else {
        println!(
            "visits {name:<24} {nodes:>6.2} nodes {leaves:>5.2} leaves {triangles:>6.2} triangles per query"
        );
    }
}

/// Measures and reports one closest-hit measure, with the walk's visits
/// per ray in a `stage-timing` build (not for packets).
fn closest_hit_measure(
    accel: &Accel,
    rays: &[Ray],
    name: &'static str,
    tracing: Tracing,
    json: bool,
) {
    penumbra_trace::stages::take_visits();
    report(
        &measure_closest_hit(accel, rays, name, tracing),
        json,
        "Mrays/s",
    );
    if !matches!(tracing, Tracing::Packets) {
        report_visits(name, rays.len() as u64, json);
    }
}

fn report(m: &Measure, json: bool, unit: &str) {
    if json {
        let key = if matches!(m.name, "build" | "load" | "bvh+mips") {
            "mtris_per_s"
        } else if m.name.starts_with("path") {
            "msamples_per_s"
        } else {
            "mrays_per_s"
        };
        println!(
            "{{\"measure\":\"{}\",\"seconds\":{:.6},\"count\":{},\"hits\":{},\"{key}\":{:.4}}}",
            m.name,
            m.seconds,
            m.count,
            m.hits,
            m.millions_per_second()
        );
    } else {
        let hits = if matches!(m.name, "build" | "load" | "bvh+mips") {
            String::new()
        } else if m.name.starts_with("path") {
            // A path measure's `hits` holds the rays it traced.
            format!(
                ", {:.2} rays per sample",
                m.hits as f64 / m.count.max(1) as f64
            )
        } else {
            format!(
                ", {:.1} % hit",
                100.0 * m.hits as f64 / m.count.max(1) as f64
            )
        };
        println!(
            "{:<22} {:>10.4} s  {:>9.3} {unit}  ({} items{hits})",
            m.name,
            m.seconds,
            m.millions_per_second(),
            m.count
        );
    }
}

pub fn run(args: BenchArgs) -> Result<()> {
    if args.engine == Engine::Raster {
        return run_raster(&args);
    }
    if args.ao.any() {
        bail!("--ssao, --ao-radius, --ao-quality and --ao-thin apply to --engine raster only");
    }
    if let Some(dirs) = &args.bake {
        if !dirs.is_empty() {
            bail!(
                "--bake DIR applies to --engine raster; for the bake throughput give --bake alone"
            );
        }
        return crate::commands::bench_bake::run(args);
    }
    let triangles = args.triangles.unwrap_or(1_000_000) as usize;
    if let Some(out) = &args.write_mesh {
        let mesh = bench_mesh(triangles);
        write_obj(out, &mesh).with_context(|| format!("writing {}", out.display()))?;
        eprintln!(
            "penumbra: wrote {} triangles to {}",
            mesh.indices.len(),
            out.display()
        );
        return Ok(());
    }
    let pool = thread_pool(args.threads)?;
    let start = std::time::Instant::now();
    // Loaded on the measuring workers (`--threads` also bounds the load).
    let scene = pool.install(|| -> Result<Scene> {
        Ok(match (&args.scene, &args.mesh) {
            (Some(p), _) => load_scene(p)?,
            (None, Some(m)) => {
                let loaded = load_scene(m)?;
                mesh_scene(
                    loaded
                        .instances
                        .iter()
                        .map(|i| (loaded.meshes[i.mesh].clone(), i.transform))
                        .collect(),
                )
            }
            (None, None) => mesh_scene(vec![(bench_mesh(triangles), Mat4::IDENTITY)]),
        })
    })?;
    // Parsing, decoding textures and preparing meshes (tangents included).
    let load = (args.scene.is_some() || args.mesh.is_some()).then(|| Measure {
        name: "load",
        seconds: start.elapsed().as_secs_f64(),
        count: scene.triangle_count() as u64,
        hits: 0,
    });
    if scene.triangle_count() == 0 {
        bail!("the scene has no triangles to benchmark");
    }
    pool.install(|| run_measures(&args, &scene, load))
}

fn run_raster(args: &BenchArgs) -> Result<()> {
    if args.write_mesh.is_some()
        || args.rays.is_some()
        || args.write_rays.is_some()
        || args.kernel.is_some()
    {
        bail!("--write-mesh, --rays, --write-rays and --kernel apply to --engine trace only");
    }
    if args.msaa != 1 && args.msaa != 4 {
        bail!("--msaa {}: use 1 or 4", args.msaa);
    }
    let scene = match (&args.scene, &args.mesh) {
        (Some(p), _) => load_scene(p)?,
        (None, Some(m)) => {
            let loaded = load_scene(m)?;
            mesh_scene(
                loaded
                    .instances
                    .iter()
                    .map(|i| (loaded.meshes[i.mesh].clone(), i.transform))
                    .collect(),
            )
        }
        (None, None) => {
            bench_raster::raster_bench_scene(args.triangles.unwrap_or(200_000) as usize)
        }
    };
    let (width, height) = args.resolution;
    let bench = RasterBench {
        width,
        height,
        light_counts: args.lights.clone(),
        frames: args.frames,
        options: penumbra_raster::RasterOptions {
            msaa: args.msaa,
            shadows: shadow_mode(args.shadows),
            light_culling: !args.no_light_culling,
            ao: args.ao.settings()?,
            ..Default::default()
        },
        json: args.json,
        bakes: args
            .bake
            .iter()
            .flatten()
            .map(|dir| penumbra_bake::read_bake(dir, &scene))
            .collect::<Result<_, _>>()?,
    };
    bench_raster::run(&bench, &scene)
}

fn run_measures(args: &BenchArgs, scene: &Scene, load: Option<Measure>) -> Result<()> {
    let start = std::time::Instant::now();
    let mut geometry = SceneGeometry::build(scene, BuildQuality::Medium)?;
    // With textures, their mip chains build beside the BVH: the wall time
    // of both is what a render waits for after loading.
    let prepare = (!scene.textures.is_empty()).then(|| Measure {
        name: "bvh+mips",
        seconds: start.elapsed().as_secs_f64(),
        count: geometry.triangles.len() as u64,
        hits: 0,
    });
    match args.prefetch {
        PrefetchArg::Auto => {}
        PrefetchArg::On => geometry.accel.set_prefetch(true),
        PrefetchArg::Off => geometry.accel.set_prefetch(false),
    }
    if let Some(kernel) = args.kernel {
        let kernel = match kernel {
            KernelArg::Portable => Kernel::Portable,
            KernelArg::Avx2 => Kernel::Avx2,
            KernelArg::Avx512 => Kernel::Avx512,
        };
        geometry
            .accel
            .set_kernel(kernel)
            .map_err(anyhow::Error::msg)?;
    }
    let accel = &geometry.accel;
    let build = Measure {
        name: "build",
        seconds: geometry.accel_seconds,
        count: geometry.triangles.len() as u64,
        hits: 0,
    };
    if !args.json {
        println!(
            "penumbra bench: {} triangles, {} threads, {:?} kernel, BVH prefetch {}",
            geometry.triangles.len(),
            rayon::current_num_threads(),
            accel.kernel(),
            if accel.prefetch() { "on" } else { "off" }
        );
    }
    if let Some(load) = &load {
        report(load, args.json, "Mtris/s");
    }
    report(&build, args.json, "Mtris/s");
    if let Some(prepare) = &prepare {
        report(prepare, args.json, "Mtris/s");
    }
    if let Some(path) = &args.rays {
        let bytes = std::fs::read(path)
            .with_context(|| format!("cannot read ray file {}", path.display()))?;
        let rays =
            parse_ray_file(&bytes).map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))?;
        for (name, tracing) in [
            ("file", Tracing::OneAtATime),
            ("file-interleaved", Tracing::Interleaved),
            ("file-packets", Tracing::Packets),
        ] {
            closest_hit_measure(accel, &rays, name, tracing, args.json);
        }
        return Ok(());
    }
    let camera = scene_camera(scene);
    let coherent = camera_rays(&camera, args.ray_resolution, args.ray_resolution);
    let incoherent = incoherent_rays(accel, &geometry.triangles, &coherent, 4, 7);
    if let Some(base) = &args.write_rays {
        for (suffix, set) in [("coherent", &coherent), ("incoherent", &incoherent)] {
            let p = PathBuf::from(format!("{}.{suffix}", base.display()));
            std::fs::write(&p, write_ray_file(set))
                .with_context(|| format!("writing {}", p.display()))?;
        }
    }
    // Warm up caches once, then measure.
    measure_closest_hit(
        accel,
        &coherent[..coherent.len().min(65_536)],
        "warmup",
        Tracing::OneAtATime,
    );
    for (rays, name, tracing) in [
        (&coherent, "coherent", Tracing::OneAtATime),
        (&coherent, "coherent-interleaved", Tracing::Interleaved),
        (&coherent, "coherent-packets", Tracing::Packets),
        (&incoherent, "incoherent", Tracing::OneAtATime),
        (&incoherent, "incoherent-interleaved", Tracing::Interleaved),
        (&incoherent, "incoherent-packets", Tracing::Packets),
    ] {
        closest_hit_measure(accel, rays, name, tracing, args.json);
    }
    // The path measurement builds its own BVH: release the ray sets and
    // this one first so peak memory is that of one render.
    drop((coherent, incoherent, geometry));
    if args.spp > 0 {
        let mut settings = scene.settings.clone();
        settings.integrator = IntegratorKind::Path;
        settings.spp = args.spp;
        let path = |name, scene: &Scene| {
            let rays = penumbra_trace::stats::rays_traced();
            let options = RenderOptions {
                scalar_paths: crate::options::scalar_paths_requested(),
                ..Default::default()
            };
            let out = render(scene, &settings, &options)?;
            anyhow::Ok(Measure {
                name,
                seconds: out.render_seconds,
                count: settings.width as u64 * settings.height as u64 * out.spp as u64,
                // The rays traced (closest-hit and shadow), in `hits`.
                hits: penumbra_trace::stats::rays_traced() - rays,
            })
        };
        if scene.textures.is_empty() {
            penumbra_trace::stages::take();
            penumbra_trace::stages::take_visits();
            let m = path("path", scene)?;
            report(&m, args.json, "Msamples/s");
            if let Some(stages) = penumbra_trace::stages::take() {
                report_stages(&stages, m.count, args.json);
                let closest = stages
                    .iter()
                    .find(|s| s.stage == penumbra_trace::stages::Stage::Traversal)
                    .map_or(0, |s| s.calls);
                report_visits("path closest-hit", closest, args.json);
            }
        } else {
            // The cost of texture lookups: the same render with every
            // material's textures replaced by their means, in the same
            // run. A process's first render runs 4–7 % slower than its
            // second of the same scene (measured), so the two are timed
            // in the order plain, textured, textured, plain, each the sum
            // of its two renders.
            let abba = |name, variant: &Scene| {
                let first = path(name, variant)?;
                let textured = sum(path("path", scene)?, path("path", scene)?);
                anyhow::Ok((textured, sum(first, path(name, variant)?)))
            };
            let (textured, plain) = abba("path-untextured", &without_maps(scene, |_| true))?;
            report(&textured, args.json, "Msamples/s");
            report(&plain, args.json, "Msamples/s");
            // Per ray as well: the textures also change the paths (normal
            // maps, roughness), so their lengths differ.
            let per_ray = |m: &Measure| m.seconds / m.hits.max(1) as f64;
            let cost = |textured: &Measure, plain: &Measure| {
                (
                    100.0 * (1.0 - plain.seconds / textured.seconds),
                    100.0 * (1.0 - per_ray(plain) / per_ray(textured)),
                )
            };
            if !args.json {
                let (total, ray) = cost(&textured, &plain);
                println!(
                    "textures cost {total:.1} % of path throughput ({ray:.1} % of the time per ray)"
                );
            }
            if args.texture_breakdown {
                for (kind, name, label) in [
                    (MapKind::BaseColour, "path-mean-base-colour", "base colour"),
                    (
                        MapKind::MetallicRoughness,
                        "path-mean-metallic-roughness",
                        "metallic-roughness",
                    ),
                    (MapKind::Normal, "path-mean-normal", "normal map"),
                ] {
                    if !scene.materials.iter().any(|m| kind.textured(m)) {
                        continue;
                    }
                    let (textured, variant) = abba(name, &without_maps(scene, |k| k == kind))?;
                    report(&variant, args.json, "Msamples/s");
                    if !args.json {
                        let (total, ray) = cost(&textured, &variant);
                        println!(
                            "  {label} alone costs {total:.1} % ({ray:.1} % per ray; the other maps kept)"
                        );
                    }
                }
            }
        }
    }
    Ok(())
}

/// Two measures of the same work as one: times, counts and hits added.
fn sum(a: Measure, b: Measure) -> Measure {
    Measure {
        seconds: a.seconds + b.seconds,
        count: a.count + b.count,
        hits: a.hits + b.hits,
        ..a
    }
}

/// The kinds of texture a material reads.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum MapKind {
    BaseColour,
    MetallicRoughness,
    Normal,
    Emission,
    Occlusion,
    Alpha,
}

impl MapKind {
    /// Whether `m` reads a texture of this kind.
    fn textured(self, m: &penumbra_scene::Material) -> bool {
        match self {
            MapKind::BaseColour => m.albedo_texture.is_some(),
            MapKind::MetallicRoughness => m.metallic_roughness_texture.is_some(),
            MapKind::Normal => m.normal_map.is_some(),
            MapKind::Emission => m.emission_texture.is_some(),
            MapKind::Occlusion => m.occlusion_map.is_some(),
            MapKind::Alpha => m.alpha.is_some_and(|a| a.texture.is_some()),
        }
    }
}

/// `scene` with the textures of the kinds `strip` names removed from
/// every material: each texture's mean texel folded into the factors it
/// multiplies (base colour, roughness and metallic, emission, coverage),
/// so that the materials stay alike on average; normal and occlusion maps
/// dropped.
fn without_maps(scene: &Scene, strip: impl Fn(MapKind) -> bool) -> Scene {
    use penumbra_shading::bsdf::Bsdf;
    let mean = |t: usize| {
        let texels = &scene.textures[t].texels;
        texels.iter().sum::<Rgb>() / texels.len().max(1) as f32
    };
    let mut plain = scene.clone();
    for m in &mut plain.materials {
        if strip(MapKind::BaseColour)
            && let Some(t) = m.albedo_texture.take()
        {
            m.bsdf = m.bsdf.tinted(mean(t));
        }
        if strip(MapKind::MetallicRoughness)
            && let (Some(t), Bsdf::MetallicRoughness(mr)) =
                (m.metallic_roughness_texture.take(), &mut m.bsdf)
        {
            let texel = mean(t);
            mr.roughness *= texel.y;
            mr.metallic *= texel.z;
        }
        if strip(MapKind::Emission)
            && let Some(t) = m.emission_texture.take()
        {
            m.emission *= mean(t);
        }
        if strip(MapKind::Normal) {
            m.normal_map = None;
        }
        if strip(MapKind::Occlusion) {
            m.occlusion_map = None;
        }
        if strip(MapKind::Alpha)
            && let Some(a) = &mut m.alpha
            && let Some(t) = a.texture.take()
        {
            a.factor *= mean(t).x;
        }
    }
    plain
}
