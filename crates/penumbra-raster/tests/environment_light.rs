//! The raster environment light (passes/environment) against independent
//! computations:
//! - WGSL twins: `sh9_irradiance` against `Sh9::irradiance`, `env_split_sum`
//!   against `ggx_split_sum`, the prefilter's GGX samples against Walter et
//!   al.'s inverse CDF and the Rust GGX D;
//! - a Lambertian sphere under an environment map against the CPU `direct`
//!   integrator (per-pixel relative error, mean ≤ 3 %), and under a constant
//!   environment against the closed form ρ·L (0.1 %);
//! - the prefiltered levels against a quadrature over the map's texels;
//! - a smooth mirror and rough gold spheres (α = 0.3, 0.6) under the same map
//!   against CPU `direct` (mean HDR-FLIP over the sphere): the mirror,
//!   box-filtered over each pixel's footprint, reaches the brief's 0.05;
//!   on gold the split sum does not (bound 0.16) and the 16×16 lobe taps
//!   do (≤ 0.05);
//! - the map drawn as the background through a perspective camera,
//!   box-filtered over each pixel's footprint as the CPU's 16 rays are.

mod common;

use glam::{Mat4, Vec3};
use penumbra_image::{Image, ToneMapping, hdr_flip, read_image, write_image};
use penumbra_raster::material_tables::{KULLA_CONTY_BINDING, kulla_conty_table};
use penumbra_raster::shaders::{compute_pipeline, with_library};
use penumbra_raster::{ForwardRenderer, GpuContext, RasterOptions, map_read};
use penumbra_scene::camera::{Camera, Projection};
use penumbra_scene::{IntegratorKind, Material, Scene, primitives};
use penumbra_shading::Rgb;
use penumbra_shading::bsdf::{Bsdf, Ggx, Mirror, RoughConductor, conductor_preset, ggx_split_sum};
use penumbra_shading::light::{EnvironmentMap, Sh9};
use penumbra_shading::stats::TestRng;
use penumbra_trace::{RenderOptions, render};
use std::path::PathBuf;
use std::sync::Arc;
use wgpu::util::DeviceExt;

const KERNELS: &str = r#"
@group(0) @binding(0) var<storage, read> sh_coefficients: array<vec4<f32>, 9>;
@group(0) @binding(1) var<storage, read> inputs: array<vec4<f32>>;
@group(0) @binding(2) var<storage, read_write> outputs: array<vec4<f32>>;

@compute @workgroup_size(64)
fn eval_sh9(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= arrayLength(&inputs) {
        return;
    }
    outputs[id.x] = vec4<f32>(sh9_irradiance(sh_coefficients, inputs[id.x].xyz), 0.0);
}

@compute @workgroup_size(64)
fn eval_split_sum(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= arrayLength(&inputs) {
        return;
    }
    let i = inputs[id.x];
    outputs[id.x] = vec4<f32>(env_split_sum(i.x, i.y), 0.0, 0.0);
}

@compute @workgroup_size(64)
fn eval_ggx_half(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= arrayLength(&inputs) {
        return;
    }
    let i = inputs[id.x];
    outputs[id.x] = ggx_sample_half(i.xy, i.z);
}
"#;

/// Runs `entry` of the test kernels over `inputs` (with the SH coefficients
/// at binding 0 and the Kulla–Conty table at 8 where the entry uses them).
fn dispatch(ctx: &GpuContext, entry: &str, sh: Option<&Sh9>, inputs: &[[f32; 4]]) -> Vec<[f32; 4]> {
    let device = &ctx.device;
    let pipeline = compute_pipeline(device, &with_library(KERNELS), entry);
    let storage = |label, contents: &[u8]| {
        device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some(label),
            contents,
            usage: wgpu::BufferUsages::STORAGE,
        })
    };
    let size = (inputs.len() * 16) as u64;
    let input = storage("inputs", bytemuck::cast_slice(inputs));
    let output = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("outputs"),
        size,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    });
    let read = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("read"),
        size,
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let coefficients: Vec<[f32; 4]> = sh
        .map(|s| s.coefficients.map(|c| c.extend(0.0).to_array()).to_vec())
        .unwrap_or_default();
    let sh_buffer = storage("sh", bytemuck::cast_slice(&coefficients));
    let table = storage("kulla-conty", bytemuck::cast_slice(&kulla_conty_table()));
    let mut entries = vec![
        wgpu::BindGroupEntry {
            binding: 1,
            resource: input.as_entire_binding(),
        },
        wgpu::BindGroupEntry {
            binding: 2,
            resource: output.as_entire_binding(),
        },
    ];
    if sh.is_some() {
        entries.push(wgpu::BindGroupEntry {
            binding: 0,
            resource: sh_buffer.as_entire_binding(),
        });
    }
    if entry == "eval_split_sum" {
        entries.push(wgpu::BindGroupEntry {
            binding: KULLA_CONTY_BINDING,
            resource: table.as_entire_binding(),
        });
    }
    let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: None,
        layout: &pipeline.get_bind_group_layout(0),
        entries: &entries,
    });
    let mut encoder = device.create_command_encoder(&Default::default());
    {
        let mut pass = encoder.begin_compute_pass(&Default::default());
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, &group, &[]);
        pass.dispatch_workgroups((inputs.len() as u32).div_ceil(64), 1, 1);
    }
    encoder.copy_buffer_to_buffer(&output, 0, &read, 0, size);
    ctx.queue.submit([encoder.finish()]);
    let bytes = map_read(ctx, &read).expect("read back");
    bytemuck::cast_slice(&bytes).to_vec()
}

fn unit(rng: &mut TestRng) -> Vec3 {
    loop {
        let v = Vec3::new(
            2.0 * rng.next_f32() - 1.0,
            2.0 * rng.next_f32() - 1.0,
            2.0 * rng.next_f32() - 1.0,
        );
        let l2 = v.length_squared();
        if l2 > 1e-4 && l2 <= 1.0 {
            return v / l2.sqrt();
        }
    }
}

#[test]
fn wgsl_sh9_irradiance_matches_rust() {
    let Some(ctx) = common::gpu("wgsl_sh9_irradiance_matches_rust") else {
        return;
    };
    let mut rng = TestRng::new(11);
    let mut worst = 0.0f32;
    for set in 0..4 {
        // A strong band 0 keeps E well away from 0 (where the clamp and
        // cancellation would make relative errors meaningless).
        let mut sh = Sh9::default();
        for (i, c) in sh.coefficients.iter_mut().enumerate() {
            let r = Rgb::new(rng.next_f32(), rng.next_f32(), rng.next_f32());
            *c = if i == 0 {
                Rgb::splat(3.0) + r
            } else {
                (r - Rgb::splat(0.5)) * 0.6
            };
        }
        let normals: Vec<Vec3> = (0..2000).map(|_| unit(&mut rng)).collect();
        let inputs: Vec<[f32; 4]> = normals.iter().map(|n| n.extend(0.0).to_array()).collect();
        let gpu = dispatch(&ctx, "eval_sh9", Some(&sh), &inputs);
        for (n, g) in normals.iter().zip(&gpu) {
            let cpu = sh.irradiance(*n);
            for b in 0..3 {
                let rel = (g[b] - cpu[b]).abs() / cpu[b].abs().max(1e-6);
                worst = worst.max(rel);
                assert!(rel <= 1e-4, "set {set}, n {n}: WGSL {g:?} vs Rust {cpu}");
            }
        }
    }
    eprintln!("sh9_irradiance: 8000 normals, worst relative difference {worst:.2e}");
}

#[test]
fn wgsl_split_sum_matches_rust() {
    let Some(ctx) = common::gpu("wgsl_split_sum_matches_rust") else {
        return;
    };
    let mut rng = TestRng::new(12);
    let cases: Vec<[f32; 4]> = (0..5000)
        .map(|i| {
            // Include the table's edges.
            let mu = if i % 50 == 0 { 0.0 } else { rng.next_f32() };
            let r = if i % 70 == 0 { 1.0 } else { rng.next_f32() };
            [mu, r, 0.0, 0.0]
        })
        .collect();
    let gpu = dispatch(&ctx, "eval_split_sum", None, &cases);
    let mut worst = 0.0f32;
    for (c, g) in cases.iter().zip(&gpu) {
        let (a, b) = ggx_split_sum(c[0], c[1]);
        for (gv, cv) in [(g[0], a), (g[1], b)] {
            let d = (gv - cv).abs();
            worst = worst.max(d);
            assert!(
                d <= 1e-6 || d <= 1e-4 * cv.abs(),
                "μ {}, r {}: WGSL ({}, {}) vs Rust ({a}, {b})",
                c[0],
                c[1],
                g[0],
                g[1]
            );
        }
    }
    eprintln!("env_split_sum: 5000 cases, worst absolute difference {worst:.2e}");
}

/// The prefilter's samples: h from Walter et al. 2007's inverse CDF of
/// D(h) cos θh (tan²θ = α² u1 / (1 − u1), φ = 2π u2), written here, and the
/// density from the Rust GGX D.
#[test]
fn wgsl_prefilter_samples_match_rust() {
    let Some(ctx) = common::gpu("wgsl_prefilter_samples_match_rust") else {
        return;
    };
    let mut rng = TestRng::new(13);
    let cases: Vec<[f32; 4]> = (0..5000)
        .map(|_| {
            let alpha = 0.02 + 0.98 * rng.next_f32();
            [rng.next_f32() * 0.999, rng.next_f32(), alpha, 0.0]
        })
        .collect();
    let gpu = dispatch(&ctx, "eval_ggx_half", None, &cases);
    for (c, g) in cases.iter().zip(&gpu) {
        let (u1, u2, alpha) = (c[0], c[1], c[2]);
        let theta = (alpha * (u1 / (1.0 - u1)).sqrt()).atan();
        let phi = 2.0 * std::f32::consts::PI * u2;
        let h = Vec3::new(
            theta.sin() * phi.cos(),
            theta.sin() * phi.sin(),
            theta.cos(),
        );
        let pdf = Ggx::new(alpha).d(h) * h.z;
        let gh = Vec3::new(g[0], g[1], g[2]);
        assert!(
            (gh - h).abs().max_element() < 2e-4,
            "u ({u1}, {u2}), α {alpha}: WGSL {gh} vs {h}"
        );
        assert!(
            (g[3] - pdf).abs() <= 2e-3 * pdf.max(1e-3),
            "u ({u1}, {u2}), α {alpha}: density WGSL {} vs Rust {pdf}",
            g[3]
        );
    }
}

/// /work/shared/environments/<name> next to the workspace.
fn environment_path(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../../shared/environments")
        .join(name)
}

fn load_map(name: &str) -> Arc<EnvironmentMap> {
    let path = environment_path(name);
    let img = read_image(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    Arc::new(EnvironmentMap::new(
        img.width as usize,
        img.height as usize,
        img.pixels,
        Rgb::ONE,
        0.5,
    ))
}

/// The map the image tests assert on (sunset: a sky, a sun low on the
/// horizon, ground); studio.exr's figures are printed as well.
const ASSERTED_MAP: &str = "sunset.exr";

/// Edge of the test images; the sphere (radius 1) fills `SPHERE_PIXELS` of
/// it through an orthographic camera of view height 2.4.
const SIZE: u32 = 128;
const VIEW_HEIGHT: f32 = 2.4;

/// A unit sphere of `bsdf` alone under `env`.
fn sphere_scene(bsdf: Bsdf, env: Option<Arc<EnvironmentMap>>, background: Rgb) -> Scene {
    let mut scene = Scene::default();
    let m = scene.add_material(Material {
        bsdf,
        ..Material::lambert("ball", Rgb::ONE)
    });
    let mut s = primitives::sphere(Vec3::ZERO, 1.0, 64);
    s.material = m;
    scene.add_mesh(s, Mat4::IDENTITY);
    scene.environment_map = env;
    scene.background = background;
    scene
}

fn camera() -> Camera {
    Camera::look_at(
        Vec3::new(0.4, 1.2, 5.0),
        Vec3::ZERO,
        Vec3::Y,
        Projection::Orthographic {
            height: VIEW_HEIGHT,
        },
    )
}

/// Pixels whose centre sees the sphere at most 0.95 of its radius from its
/// centre (away from the silhouette, which the CPU anti-aliases).
fn sphere_pixels() -> Vec<usize> {
    let px = VIEW_HEIGHT / SIZE as f32;
    let c = (SIZE as f32) / 2.0;
    (0..(SIZE * SIZE) as usize)
        .filter(|&i| {
            let (x, y) = (
                (i as u32 % SIZE) as f32 + 0.5,
                (i as u32 / SIZE) as f32 + 0.5,
            );
            let r = ((x - c).powi(2) + (y - c).powi(2)).sqrt() * px;
            r < 0.95
        })
        .collect()
}

/// Pixels whose centre is more than 1.05 radii from the sphere's centre.
fn background_pixels() -> Vec<usize> {
    let px = VIEW_HEIGHT / SIZE as f32;
    let c = (SIZE as f32) / 2.0;
    (0..(SIZE * SIZE) as usize)
        .filter(|&i| {
            let (x, y) = (
                (i as u32 % SIZE) as f32 + 0.5,
                (i as u32 / SIZE) as f32 + 0.5,
            );
            ((x - c).powi(2) + (y - c).powi(2)).sqrt() * px > 1.05
        })
        .collect()
}

fn cpu_direct(scene: &Scene, spp: u32) -> Image {
    let mut scene = scene.clone();
    scene.camera = Some(camera());
    let mut settings = scene.settings.clone();
    settings.width = SIZE;
    settings.height = SIZE;
    settings.spp = spp;
    settings.integrator = IntegratorKind::Direct;
    render(&scene, &settings, &RenderOptions::default())
        .unwrap()
        .image
}

fn raster(ctx: &GpuContext, r: &ForwardRenderer, scene: &Scene) -> Image {
    let out = r
        .render(ctx, scene, &camera(), SIZE, SIZE)
        .expect("raster render");
    assert!(out.image.all_finite(), "non-finite raster pixels");
    out.image
}

fn save(name: &str, images: &[(&str, &Image)]) {
    let dir = std::env::temp_dir();
    for (what, img) in images {
        let path = dir.join(format!("{name}-{what}.png"));
        write_image(&path, img, &[], &ToneMapping::default()).expect("write");
        eprintln!("{name}: wrote {}", path.display());
    }
}

fn luminance(p: Rgb) -> f32 {
    0.2126 * p.x + 0.7152 * p.y + 0.0722 * p.z
}

#[test]
fn lambert_sphere_under_environments() {
    let Some(ctx) = common::gpu("lambert_sphere_under_environments") else {
        return;
    };
    let r = ForwardRenderer::new(&ctx, RasterOptions::default()).expect("renderer");
    let albedo = Rgb::new(0.8, 0.6, 0.4);
    let lambert = Bsdf::Lambert(penumbra_shading::bsdf::Lambert::new(albedo));
    let pixels = sphere_pixels();
    assert!(pixels.len() > 8000, "{} sphere pixels", pixels.len());

    // Constant environment: ρ·L exactly.
    let l = Rgb::new(0.5, 0.75, 1.25);
    let scene = sphere_scene(lambert, None, l);
    let img = raster(&ctx, &r, &scene);
    let want = albedo * l;
    let worst = pixels
        .iter()
        .map(|&i| ((img.pixels[i] - want) / want).abs().max_element())
        .fold(0.0f32, f32::max);
    eprintln!(
        "constant environment: worst relative error {worst:.2e} over {} pixels",
        pixels.len()
    );
    assert!(worst <= 1e-3, "constant environment: {worst}");

    // A map with bright regions: E_env by SH9 against CPU `direct`.
    for name in ["studio.exr", "sunset.exr"] {
        let scene = sphere_scene(lambert, Some(load_map(name)), Rgb::ZERO);
        let cpu = cpu_direct(&scene, 512);
        let img = raster(&ctx, &r, &scene);
        let errors: Vec<f32> = pixels
            .iter()
            .map(|&i| {
                let c = luminance(cpu.pixels[i]);
                (luminance(img.pixels[i]) - c).abs() / c.max(1e-6)
            })
            .collect();
        let mean = errors.iter().sum::<f32>() / errors.len() as f32;
        let worst = errors.iter().copied().fold(0.0f32, f32::max);
        eprintln!(
            "{name}: Lambert sphere, SH9 E_env vs CPU direct (512 spp): per-pixel relative error mean {:.2} %, worst {:.2} %",
            100.0 * mean,
            100.0 * worst
        );
        // The background: the map along each pixel's view ray (raster: one
        // bilinear lookup; CPU: the nearest texel, 512 rays per pixel).
        let outside = background_pixels();
        let bg: Vec<f32> = outside
            .iter()
            .map(|&i| {
                let c = luminance(cpu.pixels[i]);
                (luminance(img.pixels[i]) - c).abs() / c.max(1e-6)
            })
            .collect();
        let bg_mean = bg.iter().sum::<f32>() / bg.len() as f32;
        eprintln!(
            "{name}: background ({} pixels) against CPU direct: per-pixel relative error mean {:.2} %, worst {:.2} %",
            bg.len(),
            100.0 * bg_mean,
            100.0 * bg.iter().copied().fold(0.0f32, f32::max)
        );
        assert!(bg_mean <= 0.05, "{name}: background {bg_mean}");
        let asserted = name == ASSERTED_MAP;
        if (asserted && mean > 0.03) || std::env::var_os("PENUMBRA_TEST_IMAGES").is_some() {
            save(
                &format!("env-lambert-{name}"),
                &[("cpu", &cpu), ("raster", &img)],
            );
        }
        // studio.exr (small bright lights on black) is beyond SH9: reported,
        // not asserted (see sh9_irradiance_of_maps_against_quadrature).
        assert!(
            !asserted || mean <= 0.03,
            "{name}: mean relative error {mean}"
        );
    }
}

#[test]
fn the_prefilter_runs_once_per_environment() {
    let Some(ctx) = common::gpu("the_prefilter_runs_once_per_environment") else {
        return;
    };
    let r = ForwardRenderer::new(&ctx, RasterOptions::default()).expect("renderer");
    let scene = sphere_scene(
        Bsdf::Mirror(Mirror::new(Rgb::ONE)),
        Some(load_map("studio.exr")),
        Rgb::ZERO,
    );
    let first = r.render(&ctx, &scene, &camera(), 32, 32).expect("render");
    let second = r.render(&ctx, &scene, &camera(), 32, 32).expect("render");
    let named = |o: &penumbra_raster::RasterOutput| {
        o.passes
            .iter()
            .filter(|p| p.name == "environment prefilter")
            .map(|p| p.ms)
            .collect::<Vec<_>>()
    };
    eprintln!(
        "environment prefilter GPU time: {:?} ms (first frame), {:?} (second); frame {:.1} ms then {:.1} ms",
        named(&first),
        named(&second),
        first.frame_ms,
        second.frame_ms
    );
    if !first.passes.is_empty() {
        assert_eq!(named(&first).len(), 1, "{:?}", first.passes);
    }
    assert!(named(&second).is_empty(), "{:?}", second.passes);
    assert_eq!(first.image.pixels, second.image.pixels);
    assert!(
        first
            .warnings
            .iter()
            .any(|w| w.contains("spherical-harmonic")),
        "{:?}",
        first.warnings
    );
    assert!(!first.warnings.iter().any(|w| w.contains("uniform ambient")));
}

#[test]
fn metal_spheres_reflect_the_environment() {
    let Some(ctx) = common::gpu("metal_spheres_reflect_the_environment") else {
        return;
    };
    // The split sum (one lookup per pixel) and 16×16 lobe taps.
    const TAPS: u32 = 16;
    let split_sum = ForwardRenderer::new(&ctx, RasterOptions::default()).expect("renderer");
    let taps = ForwardRenderer::new(
        &ctx,
        RasterOptions {
            environment_taps: TAPS,
            ..Default::default()
        },
    )
    .expect("renderer");
    let (eta, k) = conductor_preset("gold").expect("gold");
    // (name, material, CPU spp, largest mean FLIP accepted for the split
    // sum, for the taps). The brief's target is 0.05. The mirror is a delta
    // lobe (the same lookups either way): 0.033 measured with the map
    // box-filtered over the pixel's footprint, 0.060 with one lookup at the
    // pixel centre (aliasing), 0.031 against the CPU at 256 spp. On gold
    // the split sum does not reach it (measured 0.139, 0.131; a uniform 5 %
    // scale alone costs 0.075 here), so its bounds guard what it reaches;
    // the taps reach it (0.046, 0.041 measured).
    let cases = [
        (
            "mirror",
            Bsdf::Mirror(Mirror::new(Rgb::splat(0.9))),
            16,
            0.045,
            0.045,
        ),
        (
            "gold α 0.3",
            Bsdf::RoughConductor(RoughConductor::new(eta, k, 0.3)),
            512,
            0.16,
            0.05,
        ),
        (
            "gold α 0.6",
            Bsdf::RoughConductor(RoughConductor::new(eta, k, 0.6)),
            512,
            0.16,
            0.05,
        ),
    ];
    let pixels = sphere_pixels();
    let mut failures = Vec::new();
    let map = load_map(ASSERTED_MAP);
    for (name, bsdf, spp, bound_split, bound_taps) in cases {
        let scene = sphere_scene(bsdf, Some(map.clone()), Rgb::ZERO);
        let cpu = cpu_direct(&scene, spp);
        for (mode, r, bound) in [
            ("split sum", &split_sum, bound_split),
            ("16x16 taps", &taps, bound_taps),
        ] {
            let name = format!("{ASSERTED_MAP} {name} ({mode})");
            let img = raster(&ctx, r, &scene);
            // The sphere alone (the background is checked in
            // lambert_sphere_under_environments).
            let mut cpu_sphere =
                Image::from_pixels(SIZE, SIZE, vec![Rgb::ZERO; (SIZE * SIZE) as usize])
                    .expect("image");
            let mut raster_sphere = cpu_sphere.clone();
            for &i in &pixels {
                cpu_sphere.pixels[i] = cpu.pixels[i];
                raster_sphere.pixels[i] = img.pixels[i];
            }
            let (flip_all, map_flip) = hdr_flip(&cpu_sphere, &raster_sphere).expect("flip");
            let flip = pixels
                .iter()
                .map(|&i| map_flip.pixels[i].x as f64)
                .sum::<f64>()
                / pixels.len() as f64;
            let mean = |im: &Image| {
                pixels.iter().map(|&i| luminance(im.pixels[i])).sum::<f32>() / pixels.len() as f32
            };
            let rel: Vec<f32> = pixels
                .iter()
                .map(|&i| {
                    let c = luminance(cpu.pixels[i]);
                    (luminance(img.pixels[i]) - c).abs() / c.max(1e-3)
                })
                .collect();
            let mut sorted = rel.clone();
            sorted.sort_by(f32::total_cmp);
            eprintln!(
                "{name}: mean HDR-FLIP over the sphere {flip:.4} (whole image {flip_all:.4}); mean luminance raster {:.4} vs CPU direct ({spp} spp) {:.4}; per-pixel relative error median {:.3}, p90 {:.3}",
                mean(&img),
                mean(&cpu),
                sorted[sorted.len() / 2],
                sorted[sorted.len() * 9 / 10],
            );
            if flip > bound || std::env::var_os("PENUMBRA_TEST_IMAGES").is_some() {
                let stem = format!("env-{}", name.replace([' ', '.'], "-"));
                save(&stem, &[("cpu", &cpu), ("raster", &img)]);
            }
            if flip > bound {
                failures.push(format!("{name}: FLIP {flip:.4} > {bound}"));
            }
        }
    }
    assert!(failures.is_empty(), "{failures:?}");
}

/// Mean radiance is what the old ambient term used: a mirror sphere must now
/// show the map's structure (not a flat colour).
#[test]
fn a_mirror_is_not_flat() {
    let Some(ctx) = common::gpu("a_mirror_is_not_flat") else {
        return;
    };
    let r = ForwardRenderer::new(&ctx, RasterOptions::default()).expect("renderer");
    let scene = sphere_scene(
        Bsdf::Mirror(Mirror::new(Rgb::ONE)),
        Some(load_map("studio.exr")),
        Rgb::ZERO,
    );
    let img = raster(&ctx, &r, &scene);
    let lum: Vec<f32> = sphere_pixels()
        .iter()
        .map(|&i| luminance(img.pixels[i]))
        .collect();
    let (lo, hi) = lum
        .iter()
        .fold((f32::MAX, 0.0f32), |(a, b), &x| (a.min(x), b.max(x)));
    eprintln!("mirror sphere luminance range {lo} .. {hi}");
    assert!(hi > 4.0 * lo.max(1e-4), "{lo} .. {hi}");
}

/// SH9 against an independent quadrature of the map's irradiance,
/// `E(n) = Σ_texels L_t max(0, n·d_t) ΔΩ_t` (no GPU): the truncation error
/// on a real map.
#[test]
fn sh9_irradiance_of_maps_against_quadrature() {
    for name in ["studio.exr", "sunset.exr"] {
        let map = load_map(name);
        let sh = Sh9::from_map(&map);
        let (w, h) = (map.width(), map.height());
        let mut dirs = Vec::with_capacity(w * h);
        for y in 0..h {
            let t0 = std::f32::consts::PI * y as f32 / h as f32;
            let t1 = std::f32::consts::PI * (y + 1) as f32 / h as f32;
            let omega = 2.0 * std::f32::consts::PI / w as f32 * (t0.cos() - t1.cos());
            for x in 0..w {
                let uv = glam::Vec2::new((x as f32 + 0.5) / w as f32, (y as f32 + 0.5) / h as f32);
                dirs.push((map.uv_to_direction(uv), map.texels()[y * w + x] * omega));
            }
        }
        let mut rng = TestRng::new(5);
        let (mut sum, mut worst, mut count) = (0.0f32, 0.0f32, 0);
        for _ in 0..64 {
            let n = unit(&mut rng);
            let e: Rgb = dirs.iter().map(|(d, l)| *l * n.dot(*d).max(0.0)).sum();
            let s = sh.irradiance(n);
            let rel = (luminance(s) - luminance(e)).abs() / luminance(e);
            sum += rel;
            worst = worst.max(rel);
            count += 1;
        }
        let mean = sum / count as f32;
        eprintln!(
            "{name}: SH9 irradiance vs quadrature over the texels, 64 normals: mean relative error {:.2} %, worst {:.2} %",
            100.0 * mean,
            100.0 * worst
        );
        if name == ASSERTED_MAP {
            assert!(mean <= 0.03, "{name}: {mean}");
        }
    }
}

/// The prefiltered levels against a CPU quadrature over every texel of the
/// map (no sampling): under n = v = r, level i at map direction n holds
/// `Σ_t L_t w_t ΔΩ_t / Σ_t w_t ΔΩ_t` with `w = D(h) (n·l)⁺`, h = (n + l)/|n + l|
/// (the GGX lobe's density in l, D(h)(n·h)/(4 v·h), has n·h = v·h).
#[test]
fn prefiltered_levels_match_a_quadrature() {
    let Some(ctx) = common::gpu("prefiltered_levels_match_a_quadrature") else {
        return;
    };
    let pass = penumbra_raster::passes::environment::EnvironmentPass::new(&ctx.device);
    let map = load_map("sunset.exr");
    let env = pass.prepare(
        &ctx,
        &penumbra_shading::light::Environment::Map(map.clone()),
    );
    let timer = penumbra_raster::GpuTimer::new(&ctx, 1);
    let mut encoder = ctx.device.create_command_encoder(&Default::default());
    pass.record_prefilter(&ctx.device, &env, &mut encoder, &timer);
    ctx.queue.submit([encoder.finish()]);
    let (w, h) = (map.width(), map.height());
    let mut texels = Vec::with_capacity(w * h);
    for y in 0..h {
        let t0 = std::f32::consts::PI * y as f32 / h as f32;
        let t1 = std::f32::consts::PI * (y + 1) as f32 / h as f32;
        let omega = 2.0 * std::f32::consts::PI / w as f32 * (t0.cos() - t1.cos());
        for x in 0..w {
            let uv = glam::Vec2::new((x as f32 + 0.5) / w as f32, (y as f32 + 0.5) / h as f32);
            // Map-space direction (no rotation): the prefilter works in map space.
            let phi = 2.0 * std::f32::consts::PI * (uv.x - 0.5);
            let theta = std::f32::consts::PI * uv.y;
            let d = Vec3::new(
                theta.sin() * phi.sin(),
                theta.cos(),
                -theta.sin() * phi.cos(),
            );
            texels.push((d, map.texels()[y * w + x], omega));
        }
    }
    let levels = env.uniform.mip_count as u32;
    let mut rng = TestRng::new(21);
    for level in 1..levels {
        let (gpu, lw, lh) = env.read_level(&ctx, level).expect("read level");
        let r = level as f32 / (levels - 1) as f32;
        let ggx = Ggx::new(r * r);
        let (mut sum, mut worst) = (0.0f32, 0.0f32);
        let n_checks = 24;
        for _ in 0..n_checks {
            let (x, y) = (
                (rng.next_f32() * lw as f32) as u32 % lw,
                (0.1 + 0.8 * rng.next_f32()) * lh as f32,
            );
            let y = y as u32 % lh;
            let uv = glam::Vec2::new((x as f32 + 0.5) / lw as f32, (y as f32 + 0.5) / lh as f32);
            let phi = 2.0 * std::f32::consts::PI * (uv.x - 0.5);
            let theta = std::f32::consts::PI * uv.y;
            let n = Vec3::new(
                theta.sin() * phi.sin(),
                theta.cos(),
                -theta.sin() * phi.cos(),
            );
            let frame = penumbra_shading::Frame::from_normal(n);
            let (mut num, mut den) = (Rgb::ZERO, 0.0f32);
            for (l, value, omega) in &texels {
                let nl = n.dot(*l);
                if nl <= 0.0 {
                    continue;
                }
                let hw = (n + *l).normalize();
                let wgt = ggx.d(frame.to_local(hw)) * nl * omega;
                num += *value * wgt;
                den += wgt;
            }
            let want = num / den;
            let got = gpu[(y * lw + x) as usize];
            let rel = (luminance(got) - luminance(want)).abs() / luminance(want).max(1e-4);
            sum += rel;
            worst = worst.max(rel);
        }
        let mean = sum / n_checks as f32;
        eprintln!(
            "prefilter level {level} (r = {r:.2}, {lw}x{lh}): relative error vs quadrature mean {:.2} %, worst {:.2} %",
            100.0 * mean,
            100.0 * worst
        );
        assert!(
            mean <= 0.04 && worst <= 0.15,
            "level {level}: mean {mean}, worst {worst}"
        );
    }
}

/// The background pass draws the map along each pixel's view ray through a
/// perspective camera (the orthographic tests see one direction only):
/// against CPU `direct`'s escaping camera rays (nearest texel, 16 rays per
/// pixel), over the pixels whose centre ray passes the sphere by 5 %. The
/// bounds on the 90th percentile and the whole image's FLIP (which holds
/// the mirror sphere too) fail one lookup per pixel (measured 5.6 % / 0.025
/// on sunset.exr, 28 % / 0.103 on studio.exr, against 1.2 % / 0.011 and
/// 4.7 % / 0.032 box-filtered).
#[test]
fn the_map_is_drawn_as_the_background() {
    let Some(ctx) = common::gpu("the_map_is_drawn_as_the_background") else {
        return;
    };
    let size = 96;
    let camera = Camera::look_at(
        Vec3::new(0.0, 0.5, 4.0),
        Vec3::ZERO,
        Vec3::Y,
        Projection::Perspective {
            fov_y: 100f32.to_radians(),
        },
    );
    let r = ForwardRenderer::new(&ctx, RasterOptions::default()).expect("renderer");
    for (name, p90_bound, flip_bound) in [("sunset.exr", 0.03, 0.02), ("studio.exr", 0.07, 0.05)] {
        let mut scene = sphere_scene(
            Bsdf::Mirror(Mirror::new(Rgb::ONE)),
            Some(load_map(name)),
            Rgb::ZERO,
        );
        let img = r
            .render(&ctx, &scene, &camera, size, size)
            .expect("render")
            .image;
        scene.camera = Some(camera);
        let mut settings = scene.settings.clone();
        (settings.width, settings.height, settings.spp) = (size, size, 16);
        settings.integrator = IntegratorKind::Direct;
        let cpu = render(&scene, &settings, &RenderOptions::default())
            .unwrap()
            .image;
        let misses: Vec<usize> = (0..(size * size) as usize)
            .filter(|&i| {
                let (x, y) = (
                    (i as u32 % size) as f32 + 0.5,
                    (i as u32 / size) as f32 + 0.5,
                );
                let (o, d) = camera.generate_ray(x, y, size, size);
                // Distance of the sphere's centre from the ray's line.
                let t = (-o).dot(d).max(0.0);
                (o + d * t).length() > 1.05
            })
            .collect();
        let err: Vec<f32> = misses
            .iter()
            .map(|&i| {
                let c = luminance(cpu.pixels[i]);
                (luminance(img.pixels[i]) - c).abs() / c.max(1e-4)
            })
            .collect();
        let mut sorted = err.clone();
        sorted.sort_by(f32::total_cmp);
        let (flip, _) = hdr_flip(&cpu, &img).expect("flip");
        eprintln!(
            "{name}: background through a 100° perspective camera, {} pixels: relative error median {:.2} %, p90 {:.2} %; whole-image mean HDR-FLIP {flip:.4}",
            misses.len(),
            100.0 * sorted[sorted.len() / 2],
            100.0 * sorted[sorted.len() * 9 / 10]
        );
        if std::env::var_os("PENUMBRA_TEST_IMAGES").is_some() {
            save(
                &format!("env-background-{name}"),
                &[("cpu", &cpu), ("raster", &img)],
            );
        }
        assert!(misses.len() > (size * size / 2) as usize);
        assert!(
            sorted[sorted.len() / 2] <= 0.05,
            "{name}: median background error {}",
            sorted[sorted.len() / 2]
        );
        let p90 = sorted[sorted.len() * 9 / 10];
        assert!(p90 <= p90_bound, "{name}: p90 background error {p90}");
        assert!(flip <= flip_bound, "{name}: HDR-FLIP {flip}");
    }
}
