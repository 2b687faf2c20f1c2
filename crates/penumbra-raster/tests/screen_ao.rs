//! Screen-space ambient occlusion (`--ssao hemisphere|gtao`) against the
//! CPU `ao` integrator at the same radius, on the Cornell box and on a row
//! of thin posts; the passes' invariants (an open plane gives 1, no NaN, no
//! halo across depth edges, MSAA, the coarse MIP levels are read); and the
//! WGSL slice integral against its Rust twin.

mod common;

use glam::{Mat4, Vec2, Vec3};
use penumbra_image::{Image, hdr_flip};
use penumbra_raster::passes::ao::{
    AoMethod, AoQuality, AoSettings, AoTextures, ScreenSpaceAo, gtao_slice_visibility,
};
use penumbra_raster::readback::TextureReadback;
use penumbra_raster::shaders::{GTAO_SLICE_WGSL, compute_pipeline};
use penumbra_raster::{BakedMaps, ForwardRenderer, GpuContext, GpuTimer, RasterOptions, map_read};
use penumbra_scene::camera::{Camera, Projection};
use penumbra_scene::{Material, Scene, builtin, primitives};
use penumbra_shading::stats::TestRng;
use penumbra_trace::accel::BuildQuality;
use penumbra_trace::geometry::SceneGeometry;
use penumbra_trace::ray::Ray;
use penumbra_trace::scene_camera;
use wgpu::util::DeviceExt;

const METHODS: [AoMethod; 2] = [AoMethod::Hemisphere, AoMethod::Gtao];
const QUALITIES: [AoQuality; 3] = [AoQuality::Low, AoQuality::Medium, AoQuality::High];

/// The `ao` AOV of a raster frame.
fn raster_ao(
    ctx: &GpuContext,
    scene: &Scene,
    size: u32,
    msaa: u32,
    ao: AoSettings,
) -> (Image, penumbra_raster::RasterOutput) {
    let r = ForwardRenderer::new(
        ctx,
        RasterOptions {
            msaa,
            ao,
            ..Default::default()
        },
    )
    .expect("renderer");
    let out = r
        .render_baked(
            ctx,
            scene,
            &scene_camera(scene),
            size,
            size,
            &BakedMaps::default(),
            true,
        )
        .expect("render");
    let img = out
        .aovs
        .iter()
        .find(|(n, _)| n == "ao")
        .expect("ao aov")
        .1
        .clone();
    for p in &img.pixels {
        assert!(p.x.is_finite() && (0.0..=1.0).contains(&p.x), "kA {}", p.x);
    }
    (img, out)
}

fn settings(method: AoMethod, quality: AoQuality, radius: f32) -> AoSettings {
    AoSettings {
        method,
        radius: Some(radius),
        quality,
        thin_occluders: 0.0,
    }
}

/// Which pixels see a non-emissive surface at their centre (the CPU
/// camera's first hit).
fn surface_mask(scene: &Scene, size: u32) -> Vec<bool> {
    let geometry = SceneGeometry::build(scene, BuildQuality::default()).unwrap();
    let camera = scene_camera(scene);
    (0..size * size)
        .map(|i| {
            let (o, d) =
                camera.generate_ray((i % size) as f32 + 0.5, (i / size) as f32 + 0.5, size, size);
            geometry
                .intersect(scene, &Ray::new(o, d))
                .is_some_and(|h| h.light.is_none() && !scene.materials[h.material].is_emissive())
        })
        .collect()
}

/// Mean absolute error over `mask` and HDR-FLIP of the masked images.
fn errors(gpu: &Image, cpu: &Image, mask: &[bool]) -> (f64, f64) {
    let (mut sum, mut n) = (0.0, 0usize);
    let masked = |img: &Image| {
        let px = img
            .pixels
            .iter()
            .zip(mask)
            .map(|(p, &m)| if m { *p } else { Vec3::ZERO })
            .collect();
        Image::from_pixels(img.width, img.height, px).unwrap()
    };
    for ((g, c), &m) in gpu.pixels.iter().zip(&cpu.pixels).zip(mask) {
        if m {
            sum += (g.x - c.x).abs() as f64;
            n += 1;
        }
    }
    let (flip, _) = hdr_flip(&masked(cpu), &masked(gpu)).unwrap();
    (sum / n.max(1) as f64, flip)
}

/// The methods compared with the tracer: (method, GTAO thin-occluder
/// compensation).
const VARIANTS: [(AoMethod, f32); 3] = [
    (AoMethod::Hemisphere, 0.0),
    (AoMethod::Gtao, 0.0),
    (AoMethod::Gtao, THIN),
];

/// The thin-occluder compensation measured against the default 0.
const THIN: f32 = 1.0;

/// Every variant and quality against the CPU integrator; returns the MAE
/// per (variant, quality), index 3 × variant + quality.
fn compare_with_tracer(
    ctx: &GpuContext,
    name: &str,
    reference: &str,
    scene: &Scene,
    radius: f32,
) -> Vec<f64> {
    let size = 256;
    let cpu = common::ao_reference::ao_reference(reference, scene, size, radius);
    let mask = surface_mask(scene, size);
    let mut out = Vec::new();
    for (method, thin) in VARIANTS {
        for quality in QUALITIES {
            let ao = AoSettings {
                thin_occluders: thin,
                ..settings(method, quality, radius)
            };
            let (gpu, _) = raster_ao(ctx, scene, size, 1, ao);
            let (mae, flip) = errors(&gpu, &cpu, &mask);
            eprintln!(
                "{name}, R = {radius}: {} {} (thin-occluder compensation {thin}): MAE {mae:.4}, FLIP {flip:.4} (vs ao integrator 1024 spp, {size}²)",
                method.name(),
                quality.name()
            );
            out.push(mae);
        }
    }
    out
}

#[test]
fn cornell_box_ao_approaches_the_ao_integrator() {
    let Some(ctx) = common::gpu("screen-space AO, Cornell box") else {
        return;
    };
    let mae = compare_with_tracer(
        &ctx,
        "Cornell box",
        "cornell-r100-256",
        &builtin::cornell_box(),
        100.0,
    );
    // Measured: hemisphere 0.045 / 0.045 / 0.042, GTAO 0.051 / 0.038 /
    // 0.033 (low / medium / high). Most of what remains is occlusion the
    // depth buffer cannot see (the back wall behind the tall box). A 3-D
    // range check |q − p| < R in the hemisphere method (it loses grazing
    // walls) read 0.096 and fails here; GTAO with XeGTAO's s² step
    // offsets and MIP offset 3.3 read 0.076 / 0.050 / 0.042. The
    // thin-occluder compensation (c = 1) fades the walls that rise towards
    // the camera: 0.081 / 0.066 / 0.058 measured, so it is off by default.
    assert!(mae[2] <= 0.05, "hemisphere high MAE {}", mae[2]);
    assert!(mae[5] <= 0.05, "GTAO high MAE {}", mae[5]);
    for (i, m) in mae[..6].iter().enumerate() {
        assert!(*m <= 0.08, "case {i}: MAE {m}");
    }
    for q in 0..3 {
        assert!(
            mae[6 + q] > mae[3 + q],
            "quality {q}: the compensation should cost here"
        );
    }
    // GTAO below the kernel at medium and high (not at low: 0.051 vs 0.045).
    for q in 1..3 {
        assert!(
            mae[3 + q] < mae[q],
            "quality {q}: GTAO {} vs hemisphere {}",
            mae[3 + q],
            mae[q]
        );
    }
}

/// A row of thin posts (5 % of R wide) standing on a floor, seen from above
/// at an angle.
fn posts_scene() -> Scene {
    let mut scene = Scene::default();
    let white = scene.add_material(Material::lambert("white", Vec3::splat(0.8)));
    let mut floor = primitives::rectangle(Vec3::ZERO, Vec2::new(6.0, 6.0));
    floor.material = white;
    scene.add_mesh(floor, Mat4::IDENTITY);
    for i in 0..7 {
        let x = -1.5 + 0.5 * i as f32;
        let mut post = primitives::cuboid(
            Vec3::new(x - 0.025, 0.0, -0.025),
            Vec3::new(x + 0.025, 1.2, 0.025),
        );
        post.material = white;
        scene.add_mesh(post, Mat4::IDENTITY);
    }
    scene.camera = Some(Camera::look_at(
        Vec3::new(0.0, 2.2, 3.2),
        Vec3::new(0.0, 0.3, 0.0),
        Vec3::Y,
        Projection::Perspective {
            fov_y: 45f32.to_radians(),
        },
    ));
    scene
}

#[test]
fn thin_posts_ao_approaches_the_ao_integrator() {
    let Some(ctx) = common::gpu("screen-space AO, thin posts") else {
        return;
    };
    let mae = compare_with_tracer(&ctx, "thin posts", "posts-r0.5-256", &posts_scene(), 0.5);
    // Here the depth buffer's height-field assumption costs GTAO: the floor
    // seen past a post is taken as hidden behind a solid wall, so GTAO
    // darkens a band beside each post that rays pass freely, the more so
    // the more steps find it (measured MAE 0.014 / 0.018 / 0.021 against
    // the kernel's 0.0099 / 0.0096 / 0.0093). The thin-occluder
    // compensation (c = 1) fades the posts' points towards the camera and
    // takes GTAO below the kernel at every quality (0.0076 / 0.0081 /
    // 0.0090).
    for (i, m) in mae.iter().enumerate() {
        assert!(*m <= 0.05, "case {i}: MAE {m}");
    }
    for q in 0..3 {
        assert!(
            mae[6 + q] < mae[q] && mae[6 + q] < mae[3 + q],
            "quality {q}: GTAO with compensation {} vs hemisphere {}, GTAO {}",
            mae[6 + q],
            mae[q],
            mae[3 + q]
        );
    }
}

/// A square facing the camera that fills the view.
fn facing_plane(projection: Projection, tilt: f32) -> Scene {
    let mut scene = Scene::default();
    let white = scene.add_material(Material::lambert("white", Vec3::splat(0.8)));
    let mut plane = primitives::quad(
        Vec3::new(-50.0, -50.0, 0.0),
        Vec3::new(100.0, 0.0, 0.0),
        Vec3::new(0.0, 100.0, 0.0),
    );
    plane.material = white;
    scene.add_mesh(plane, Mat4::from_rotation_x(tilt));
    scene.camera = Some(Camera::look_at(
        Vec3::new(0.0, 0.0, 10.0),
        Vec3::ZERO,
        Vec3::Y,
        projection,
    ));
    scene
}

#[test]
fn an_open_plane_is_unoccluded_to_the_screen_edges() {
    let Some(ctx) = common::gpu("screen-space AO, open plane") else {
        return;
    };
    let persp = Projection::Perspective {
        fov_y: 60f32.to_radians(),
    };
    let ortho = Projection::Orthographic { height: 12.0 };
    for (label, scene) in [
        ("facing, perspective", facing_plane(persp, 0.0)),
        (
            "tilted 60°, perspective",
            facing_plane(persp, -60f32.to_radians()),
        ),
        ("facing, orthographic", facing_plane(ortho, 0.0)),
    ] {
        let mask = surface_mask(&scene, 128);
        for method in METHODS {
            let (ao, _) = raster_ao(&ctx, &scene, 128, 1, settings(method, AoQuality::High, 2.0));
            let on: Vec<f32> = ao
                .pixels
                .iter()
                .zip(&mask)
                .filter(|(_, m)| **m)
                .map(|(p, _)| p.x)
                .collect();
            assert!(on.len() > 5000);
            let min = on.iter().copied().fold(1.0f32, f32::min);
            let mean = on.iter().map(|&k| k as f64).sum::<f64>() / on.len() as f64;
            eprintln!(
                "open plane, {label}, {}: min kA {min:.4}, mean {mean:.5}",
                method.name()
            );
            if label.starts_with("facing") {
                assert!(min >= 0.99, "{label}, {}: min kA {min}", method.name());
            } else {
                // The tilted plane runs past the camera: its nearest pixels
                // see R as hundreds of pixels, and GTAO's coarse levels
                // there darken a few of them (measured min 0.94).
                assert!(
                    mean >= 0.99 && min >= 0.9,
                    "{label}, {}: {min} {mean}",
                    method.name()
                );
            }
        }
    }
}

#[test]
fn the_denoise_does_not_spread_occlusion_across_a_depth_edge() {
    let Some(ctx) = common::gpu("screen-space AO, halo") else {
        return;
    };
    // A square in front of a far wall (5 R apart): nothing within R of the
    // wall occludes it, so the wall's kA is 1 right up to the silhouette.
    let mut scene = facing_plane(
        Projection::Perspective {
            fov_y: 40f32.to_radians(),
        },
        0.0,
    );
    let mut front = primitives::quad(
        Vec3::new(-1.0, -1.0, 5.0),
        Vec3::new(2.0, 0.0, 0.0),
        Vec3::new(0.0, 2.0, 0.0),
    );
    front.material = 0;
    scene.add_mesh(front, Mat4::IDENTITY);
    let size = 128;
    let mask = surface_mask(&scene, size);
    // Wall pixels: those whose camera ray hits z ≈ 0 (not the square).
    let camera = scene_camera(&scene);
    let geometry = SceneGeometry::build(&scene, BuildQuality::default()).unwrap();
    let wall: Vec<bool> = (0..size * size)
        .map(|i| {
            let (o, d) =
                camera.generate_ray((i % size) as f32 + 0.5, (i / size) as f32 + 0.5, size, size);
            geometry
                .intersect(&scene, &Ray::new(o, d))
                .is_some_and(|h| h.p.z.abs() < 1e-3)
        })
        .collect();
    for method in METHODS {
        let (ao, _) = raster_ao(
            &ctx,
            &scene,
            size,
            1,
            settings(method, AoQuality::High, 1.0),
        );
        // The widest band of darkened wall pixels next to the square.
        let mut widest = 0;
        for y in 0..size as usize {
            let row = &ao.pixels[y * size as usize..][..size as usize];
            let mut run = 0;
            for (x, p) in row.iter().enumerate() {
                let i = y * size as usize + x;
                if wall[i] && mask[i] && p.x < 0.98 {
                    run += 1;
                    widest = widest.max(run);
                } else {
                    run = 0;
                }
            }
        }
        eprintln!(
            "depth edge, {}: widest darkened wall band {widest} px",
            method.name()
        );
        assert!(widest <= 2, "{}: halo of {widest} px", method.name());
    }
}

#[test]
fn msaa_4_uses_the_pixel_centre_surface() {
    let Some(ctx) = common::gpu("screen-space AO, MSAA") else {
        return;
    };
    let scene = builtin::cornell_box();
    let size = 128;
    let ao = settings(AoMethod::Gtao, AoQuality::Medium, 100.0);
    let (one, _) = raster_ao(&ctx, &scene, size, 1, ao);
    let (four, _) = raster_ao(&ctx, &scene, size, 4, ao);
    let diffs: Vec<f32> = one
        .pixels
        .iter()
        .zip(&four.pixels)
        .map(|(a, b)| (a.x - b.x).abs())
        .collect();
    let share = diffs.iter().filter(|&&d| d <= 0.02).count() as f64 / diffs.len() as f64;
    let mean = diffs.iter().map(|&d| d as f64).sum::<f64>() / diffs.len() as f64;
    eprintln!(
        "GTAO MSAA 4 vs 1: mean |difference| {mean:.5}, {:.2} % of pixels within 0.02",
        100.0 * share
    );
    // Only pixels whose sample 0 lies on another surface than their centre
    // (edges), and what reads them (the denoise window, horizon samples),
    // may differ: measured 94.5 % of pixels within 0.02, mean 0.018.
    assert!(share >= 0.9 && mean <= 0.025, "{share} {mean}");
}

/// Runs the AO passes on hand-made inputs: a plane facing the camera at
/// view distance 10 in every level, except that `coarse_level` (if any)
/// holds z = 6 (something in front, within R).
fn ao_on_hand_made_inputs(ctx: &GpuContext, method: AoMethod, coarse_level: Option<u32>) -> f64 {
    let device = &ctx.device;
    let size = 256;
    let ao = ScreenSpaceAo::new(device, settings(method, AoQuality::High, 20.0), 1);
    let textures = AoTextures::new(device, size, size);
    let params = ao.params(Mat4::IDENTITY, Mat4::IDENTITY, false, (size, size), 20.0);
    for level in 0..textures.levels {
        let n = (size >> level) as usize;
        let z = if Some(level) == coarse_level {
            6.0f32
        } else {
            10.0
        };
        let data = vec![z; n * n];
        ctx.queue.write_texture(
            wgpu::TexelCopyTextureInfo {
                texture: &textures.view_depth,
                mip_level: level,
                origin: wgpu::Origin3d::ZERO,
                aspect: wgpu::TextureAspect::All,
            },
            bytemuck::cast_slice(&data),
            wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(4 * n as u32),
                rows_per_image: Some(n as u32),
            },
            wgpu::Extent3d {
                width: n as u32,
                height: n as u32,
                depth_or_array_layers: 1,
            },
        );
    }
    // View-space normals +z as Rgba16Float: (0, 0, 1, 0).
    let one = 0x3c00u16;
    let normals: Vec<u16> = (0..size * size).flat_map(|_| [0, 0, one, 0]).collect();
    ctx.queue.write_texture(
        wgpu::TexelCopyTextureInfo {
            texture: &textures.normals,
            mip_level: 0,
            origin: wgpu::Origin3d::ZERO,
            aspect: wgpu::TextureAspect::All,
        },
        bytemuck::cast_slice(&normals),
        wgpu::TexelCopyBufferLayout {
            offset: 0,
            bytes_per_row: Some(8 * size),
            rows_per_image: Some(size),
        },
        wgpu::Extent3d {
            width: size,
            height: size,
            depth_or_array_layers: 1,
        },
    );
    let timer = GpuTimer::new(ctx, 4);
    let uniform = ao.uniform(device, &params, textures.levels);
    let mut encoder = device.create_command_encoder(&Default::default());
    ao.record_main(device, &mut encoder, &textures, &uniform, &timer);
    let readback = TextureReadback::new(device, size, size, 4);
    readback.record(&mut encoder, &textures.raw, 0);
    ctx.queue.submit([encoder.finish()]);
    let values = readback.read_f32(ctx).expect("readback");
    values.iter().map(|&v| v as f64).sum::<f64>() / values.len() as f64
}

#[test]
fn gtao_reads_the_coarse_levels_of_the_depth_chain() {
    let Some(ctx) = common::gpu("GTAO depth MIP levels") else {
        return;
    };
    // R = 20 at distance 10 is 4× the image's half-height on screen, so
    // the far steps read levels 1 to 3 (Bevy #11222 read only level 0);
    // level 3 needs offsets of 2^(3 + 4.3) ≈ 158 px, hence 256².
    let flat = ao_on_hand_made_inputs(&ctx, AoMethod::Gtao, None);
    assert!(flat > 0.99, "open plane: {flat}");
    for level in 1..4 {
        let k = ao_on_hand_made_inputs(&ctx, AoMethod::Gtao, Some(level));
        eprintln!("GTAO on a plane: kA {flat:.4}; with level {level} raised: {k:.4}");
        assert!(k < flat - 0.01, "level {level}: {k} vs {flat}");
    }
    // The hemisphere kernel reads level 0 only: the same change does nothing.
    let h_flat = ao_on_hand_made_inputs(&ctx, AoMethod::Hemisphere, None);
    let h_raised = ao_on_hand_made_inputs(&ctx, AoMethod::Hemisphere, Some(2));
    assert_eq!(h_flat, h_raised);
}

#[test]
fn wgsl_slice_integral_equals_its_rust_twin() {
    let Some(ctx) = common::gpu("GTAO slice integral twin") else {
        return;
    };
    let device = &ctx.device;
    let mut rng = TestRng::new(11);
    let half_pi = std::f32::consts::FRAC_PI_2;
    let cases: Vec<[f32; 4]> = (0..10_000)
        .map(|_| {
            let n = (2.0 * rng.next_f32() - 1.0) * half_pi;
            let h0 = n - half_pi * rng.next_f32() * 2.0;
            let h1 = n + half_pi * rng.next_f32() * 2.0;
            [n, h0.max(n - half_pi), h1.min(n + half_pi), 0.0]
        })
        .collect();
    let source = format!(
        "{GTAO_SLICE_WGSL}
@group(0) @binding(0) var<storage, read> cases: array<vec4<f32>>;
@group(0) @binding(1) var<storage, read_write> out: array<f32>;
@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {{
    if id.x < arrayLength(&cases) {{
        let c = cases[id.x];
        out[id.x] = gtao_slice_visibility(c.x, c.y, c.z);
    }}
}}"
    );
    let pipeline = compute_pipeline(device, &source, "main");
    let input = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: None,
        contents: bytemuck::cast_slice(&cases),
        usage: wgpu::BufferUsages::STORAGE,
    });
    let bytes = 4 * cases.len() as u64;
    let output = device.create_buffer(&wgpu::BufferDescriptor {
        label: None,
        size: bytes,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    });
    let read = device.create_buffer(&wgpu::BufferDescriptor {
        label: None,
        size: bytes,
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: None,
        layout: &pipeline.get_bind_group_layout(0),
        entries: &[
            wgpu::BindGroupEntry {
                binding: 0,
                resource: input.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 1,
                resource: output.as_entire_binding(),
            },
        ],
    });
    let mut encoder = device.create_command_encoder(&Default::default());
    {
        let mut pass = encoder.begin_compute_pass(&Default::default());
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, &group, &[]);
        pass.dispatch_workgroups((cases.len() as u32).div_ceil(64), 1, 1);
    }
    encoder.copy_buffer_to_buffer(&output, 0, &read, 0, bytes);
    ctx.queue.submit([encoder.finish()]);
    let gpu: Vec<f32> = bytemuck::cast_slice(&map_read(&ctx, &read).unwrap()).to_vec();
    for (c, g) in cases.iter().zip(&gpu) {
        let r = gtao_slice_visibility(c[0], c[1], c[2]);
        assert!(
            (g - r).abs() <= 1e-5 + 1e-4 * r.abs(),
            "{c:?}: gpu {g} rust {r}"
        );
    }
}

/// An analytic area light is a light, not a surface: where a camera ray
/// meets one the `ao` integrator gives kA = 0, and so must the screen-space
/// methods (they once gave ≈ 1 there). An emissive mesh is a surface and
/// keeps its kA in both.
#[test]
fn analytic_lights_have_no_ambient_occlusion_term() {
    let Some(ctx) = common::gpu("screen-space AO, analytic lights") else {
        return;
    };
    let study_box = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../scenes/study/cornell-box.toml");
    let analytic =
        penumbra_scene::load_scene(&study_box, &penumbra_scene::LoadOptions::default()).unwrap();
    assert_eq!(analytic.area_lights.len(), 1);
    for (scene, want) in [(analytic, 0.0), (builtin::cornell_box(), 1.0)] {
        let size = 128;
        let geometry = SceneGeometry::build(&scene, BuildQuality::default()).unwrap();
        let camera = scene_camera(&scene);
        let on_light: Vec<bool> = (0..size * size)
            .map(|i| {
                let (o, d) = camera.generate_ray(
                    (i % size) as f32 + 0.5,
                    (i / size) as f32 + 0.5,
                    size,
                    size,
                );
                geometry
                    .intersect(&scene, &Ray::new(o, d))
                    .is_some_and(|h| h.light.is_some() || scene.materials[h.material].is_emissive())
            })
            .collect();
        // Pixels whose centre and 4 neighbours see the light.
        let interior: Vec<usize> = (0..on_light.len())
            .filter(|&i| {
                let (x, y) = ((i as u32 % size) as i32, (i as u32 / size) as i32);
                [(0, 0), (-1i32, 0i32), (1, 0), (0, -1), (0, 1)]
                    .iter()
                    .all(|(dx, dy)| on_light[((y + dy) as u32 * size + (x + dx) as u32) as usize])
            })
            .collect();
        assert!(
            interior.len() > 20,
            "{} interior light pixels",
            interior.len()
        );
        let cpu = common::ao_reference::ao_render(&scene, size, 100.0, 16);
        for &i in &interior {
            assert_eq!(cpu.pixels[i].x, want, "the ao integrator on the light");
        }
        for method in METHODS {
            let (gpu, _) = raster_ao(
                &ctx,
                &scene,
                size,
                1,
                settings(method, AoQuality::Low, 100.0),
            );
            let off = interior
                .iter()
                .filter(|&&i| (gpu.pixels[i].x - want).abs() > 0.05)
                .count();
            assert_eq!(
                off,
                0,
                "{}: kA differs from {want} on {off} of {} light pixels",
                method.name(),
                interior.len()
            );
        }
    }
}
