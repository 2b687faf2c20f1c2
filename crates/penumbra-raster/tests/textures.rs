//! Textures in the raster engine.
//! - The WGSL lookup against the CPU's `Texture::sample` (wrap modes,
//!   `KHR_texture_transform`, bilinear; half-float and 8-bit sRGB storage)
//!   at level 0, and against
//!   independently computed levels when minified: level 1 exactly, halfway
//!   between levels 1 and 2, and the 1×1 level (the mean of every texel).
//! - Khronos' test sheets (../shared/gltf-samples: wrap modes, texture
//!   transforms, vertex colours, texture coordinates) rendered by both
//!   engines under a head-on light: mean HDR-FLIP ≤ 0.02, the sheets'
//!   fail marks absent from the raster image as from the CPU's, and the
//!   single-sided quad's back face culled (glTF `doubleSided: false`).
//! - A quad with base-colour and metallic–roughness textures under a point
//!   light, both engines: mean HDR-FLIP ≤ 0.02.
//! - NormalTangentTest's normal maps under an oblique light, both engines.
//! - AlphaBlendModeTest's MASK and BLEND quads, both engines, no red marks.
//! - occlusionTexture scales the environment term by its closed-form
//!   factor, and only that term.
//! - DamagedHelmet's emission texture: the raster image matches the CPU's.
//! - A minified checkerboard: the raster engine's mip levels give the
//!   average the CPU's many samples per pixel give, not aliasing.

mod common;

use glam::{Affine2, Mat4, Vec2, Vec3};
use penumbra_image::{Image, ToneMapping, hdr_flip, write_image};
use penumbra_raster::shaders::{SCENE_WGSL, TEXTURES_WGSL, with_library};
use penumbra_raster::textures::{TexelFormat, TextureTable, mip_chain};
use penumbra_raster::{ForwardRenderer, GpuContext, RasterOptions};
use penumbra_scene::texture::Wrap;
use penumbra_scene::{
    Camera, IntegratorKind, LoadOptions, Material, NormalMap, OcclusionMap, Projection, Scene,
    SceneLight, Texture, load_scene, primitives,
};
use penumbra_shading::bsdf::{Bsdf, MetallicRoughness};
use penumbra_shading::color::srgb_to_linear;
use penumbra_shading::light::{DirectionalLight, Light, PointLight};
use penumbra_shading::stats::TestRng;
use penumbra_trace::{RenderOptions, render};
use std::path::Path;

/// A texture lookup: `sample_texture(texture, uv, duv)`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, bytemuck::Pod, bytemuck::Zeroable)]
struct Lookup {
    uv: [f32; 2],
    texture: u32,
    _pad0: u32,
    duv: [f32; 4],
}

const LOOKUP_KERNEL: &str = r#"
@group(0) @binding(2) var<storage, read> materials: array<GpuMaterial>;
@group(0) @binding(23) var<storage, read> environment_materials: array<GpuEnvMaterial>;

struct Lookup {
    uv: vec2<f32>,
    texture: u32,
    _pad0: u32,
    duv: vec4<f32>,
}

@group(0) @binding(40) var<storage, read> lookups: array<Lookup>;
@group(0) @binding(41) var<storage, read_write> lookup_out: array<vec4<f32>>;

@compute @workgroup_size(64)
fn eval_lookup(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= arrayLength(&lookups) {
        return;
    }
    let c = lookups[i];
    lookup_out[i] = vec4<f32>(sample_texture(c.texture, c.uv, c.duv), 0.0);
}

struct PerturbCase {
    texel: vec3<f32>,
    scale: f32,
    n: vec4<f32>,
    t: vec4<f32>,
}

@group(0) @binding(42) var<storage, read> perturb_cases: array<PerturbCase>;
@group(0) @binding(43) var<storage, read_write> perturb_out: array<vec4<f32>>;

@compute @workgroup_size(64)
fn eval_perturb(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= arrayLength(&perturb_cases) {
        return;
    }
    let c = perturb_cases[i];
    perturb_out[i] = vec4<f32>(perturb_normal(c.texel, c.scale, c.n.xyz, c.t), 0.0);
}
"#;

/// One normal-map evaluation (WGSL `PerturbCase`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, bytemuck::Pod, bytemuck::Zeroable)]
struct PerturbCase {
    texel: [f32; 3],
    scale: f32,
    n: [f32; 4],
    t: [f32; 4],
}

/// WGSL `perturb_normal` against `NormalMap::perturb` on random texels,
/// scales, normals and tangents of both handednesses.
#[test]
fn wgsl_normal_perturbation_matches_rust() {
    let Some(ctx) = common::gpu("wgsl_normal_perturbation_matches_rust") else {
        return;
    };
    let mut rng = TestRng::new(72);
    let mut unit = || {
        let v = Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * 2.0 - 1.0;
        v.normalize_or(Vec3::Z)
    };
    let mut cases = Vec::new();
    for i in 0..2000 {
        let n = unit();
        let t = unit() * 1.7;
        let texel = (unit() + 1.0) * 0.5;
        let w = if i % 2 == 0 { 1.0 } else { -1.0 };
        cases.push(PerturbCase {
            texel: texel.to_array(),
            scale: 0.25 + (i % 7) as f32 * 0.3,
            n: n.extend(0.0).to_array(),
            t: [t.x, t.y, t.z, w],
        });
    }
    let source = with_library(&format!("{SCENE_WGSL}\n{TEXTURES_WGSL}\n{LOOKUP_KERNEL}"));
    let out: Vec<[f32; 4]> = common::dispatch(
        &ctx,
        &source,
        "eval_perturb",
        (42, bytemuck::cast_slice(&cases)),
        cases.len(),
        &[],
    );
    for (c, o) in cases.iter().zip(&out) {
        let map = NormalMap {
            texture: 0,
            scale: c.scale,
        };
        let cpu = map.perturb(
            Vec3::from_array(c.texel),
            Vec3::from_slice(&c.n),
            glam::Vec4::from_array(c.t),
        );
        let gpu = Vec3::new(o[0], o[1], o[2]);
        assert!((gpu - cpu).length() < 1e-4, "{c:?}: GPU {gpu} vs CPU {cpu}");
    }
}

fn random_texture(rng: &mut TestRng, width: u32, height: u32, wrap: [Wrap; 2]) -> Texture {
    Texture {
        name: format!("{width}x{height}"),
        width,
        height,
        texels: (0..width * height)
            .map(|_| Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()))
            .collect(),
        wrap,
        uv_transform: Affine2::IDENTITY,
        uv_set: 0,
    }
}

/// Half-float texels: relative error ≤ 2⁻¹¹ per texel.
fn near(gpu: Vec3, cpu: Vec3) -> bool {
    (gpu - cpu).abs().max_element() <= 2e-3 * cpu.abs().max_element().max(1.0)
}

/// A level-0 lookup (no footprint) of the albedo texture of material `t`
/// (texture `t` of `scene`) at random coordinates in [−2.5, 2.5)², and
/// what Texture::sample gives there.
fn level0_lookup(
    rng: &mut TestRng,
    scene: &Scene,
    table: &TextureTable,
    t: usize,
) -> (Lookup, Vec3) {
    let uv = Vec2::new(rng.next_f32() * 5.0 - 2.5, rng.next_f32() * 5.0 - 2.5);
    let case = Lookup {
        uv: uv.to_array(),
        texture: table.materials[t].albedo,
        ..Default::default()
    };
    (case, scene.textures[t].sample(uv))
}

/// The lookups `cases` in `table` made by WGSL `sample_texture` (in a
/// pipeline with the given constants) that are not `near` the `expected`
/// values: (index, case, GPU value, expected value).
fn mismatches(
    ctx: &GpuContext,
    constants: &[(&str, f64)],
    table: &TextureTable,
    cases: &[Lookup],
    expected: &[Vec3],
) -> Vec<(usize, Lookup, Vec3, Vec3)> {
    let source = with_library(&format!("{SCENE_WGSL}\n{TEXTURES_WGSL}\n{LOOKUP_KERNEL}"));
    let out: Vec<[f32; 4]> = common::dispatch_specialised(
        ctx,
        constants,
        &source,
        "eval_lookup",
        (40, bytemuck::cast_slice(cases)),
        cases.len(),
        &[
            (27, bytemuck::cast_slice(&table.textures)),
            (28, bytemuck::cast_slice(&table.texels)),
        ],
    );
    out.iter()
        .map(|o| Vec3::new(o[0], o[1], o[2]))
        .zip(expected)
        .enumerate()
        .filter(|&(_, (g, e))| !near(g, *e))
        .map(|(i, (g, e))| (i, cases[i], g, *e))
        .collect()
}

#[test]
fn wgsl_lookups_match_the_cpu_and_the_mip_levels() {
    let Some(ctx) = common::gpu("wgsl_lookups_match_the_cpu_and_the_mip_levels") else {
        return;
    };
    let mut rng = TestRng::new(71);
    let mut scene = Scene::default();
    scene
        .textures
        .push(random_texture(&mut rng, 5, 3, [Wrap::Repeat, Wrap::Repeat]));
    scene.textures.push(Texture {
        uv_transform: Affine2::from_scale_angle_translation(
            Vec2::new(1.5, -0.7),
            0.4,
            Vec2::new(0.3, 0.1),
        ),
        ..random_texture(&mut rng, 4, 6, [Wrap::ClampToEdge, Wrap::MirroredRepeat])
    });
    scene.textures.push(random_texture(
        &mut rng,
        16,
        16,
        [Wrap::MirroredRepeat, Wrap::ClampToEdge],
    ));
    // An 8-bit sRGB source, stored in one word per texel.
    scene.textures.push(Texture {
        texels: (0..64)
            .map(|_| {
                Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32())
                    .map(|v| srgb_to_linear((v * 255.0).floor() / 255.0))
            })
            .collect(),
        ..random_texture(&mut rng, 8, 8, [Wrap::Repeat, Wrap::MirroredRepeat])
    });
    for t in 0..4 {
        let mut m = Material::lambert(format!("m{t}"), Vec3::ONE);
        m.albedo_texture = Some(t);
        scene.add_material(m);
    }
    let table = TextureTable::new(&scene, u64::MAX);
    // Level 0 (no footprint): Texture::sample, for every texture.
    let mut cases = Vec::new();
    let mut expected = Vec::new();
    assert_eq!(
        table.textures[table.materials[3].albedo as usize].format,
        TexelFormat::Srgb8 as u32
    );
    for _ in 0..4000 {
        let t = (rng.next_f32() * 4.0) as usize % 4;
        let (case, value) = level0_lookup(&mut rng, &scene, &table, t);
        cases.push(case);
        expected.push(value);
    }
    let level0 = cases.len();
    // The 16×16 texture minified: a footprint of 2 texels reads level 1,
    // 2^1.5 texels halfway between levels 1 and 2, 64 texels the 1×1 level.
    let big = &scene.textures[2];
    let chain = mip_chain(big);
    let level = |l: usize| Texture {
        width: chain[l].width,
        height: chain[l].height,
        texels: chain[l].texels.clone().into(),
        ..big.clone()
    };
    let mean = big.texels.iter().sum::<Vec3>() / big.texels.len() as f32;
    for k in 0..600 {
        let uv = Vec2::new(rng.next_f32() * 3.0 - 1.0, rng.next_f32() * 3.0 - 1.0);
        let (texels, value) = match k % 3 {
            0 => (2.0, level(1).sample(uv)),
            1 => (
                2f32.powf(1.5),
                0.5 * (level(1).sample(uv) + level(2).sample(uv)),
            ),
            _ => (64.0, mean),
        };
        let d = texels / 16.0;
        cases.push(Lookup {
            uv: uv.to_array(),
            texture: table.materials[2].albedo,
            // Footprint along x on one axis, smaller along y.
            duv: [d, 0.0, 0.0, 0.3 * d],
            ..Default::default()
        });
        expected.push(value);
    }
    let bad = mismatches(&ctx, &[], &table, &cases, &expected);
    assert!(
        bad.is_empty(),
        "{} of {} lookups differ ({level0} at level 0), first: {:?}",
        bad.len(),
        cases.len(),
        &bad[..bad.len().min(4)]
    );
}

/// A texture of 8-bit texels: sRGB-encoded (`srgb`) or linear levels.
fn eight_bit_texture(rng: &mut TestRng, srgb: bool, wrap: [Wrap; 2]) -> Texture {
    let level = |v: f32| {
        let q = (v * 255.0).floor() / 255.0;
        if srgb { srgb_to_linear(q) } else { q }
    };
    Texture {
        texels: (0..6 * 5)
            .map(|_| Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()).map(level))
            .collect(),
        ..random_texture(rng, 6, 5, wrap)
    }
}

/// The lookups of pipelines specialised to a scene's texel formats and
/// wrap modes (`TextureFeatures`: a single format or mode is read without
/// a test, absent ones are dropped) give Texture::sample at level 0, for
/// tables of one format and one mode, of two, and of all three.
#[test]
fn specialised_lookups_match_the_cpu() {
    let Some(ctx) = common::gpu("specialised_lookups_match_the_cpu") else {
        return;
    };
    use Wrap::{ClampToEdge as C, MirroredRepeat as M, Repeat as R};
    let mut rng = TestRng::new(72);
    let srgb8 = 1 << TexelFormat::Srgb8 as u32;
    let unorm8 = 1 << TexelFormat::Unorm8 as u32;
    let half = 1 << TexelFormat::Half as u32;
    let (repeat, clamp, mirror) = (1 << 0, 1 << 1, 1 << 2);
    let tables: Vec<(Vec<Texture>, u32, u32)> = vec![
        (
            vec![eight_bit_texture(&mut rng, true, [C, C])],
            srgb8,
            clamp,
        ),
        (
            vec![eight_bit_texture(&mut rng, false, [M, M])],
            unorm8,
            mirror,
        ),
        (
            vec![random_texture(&mut rng, 5, 4, [R, C])],
            half,
            repeat | clamp,
        ),
        (
            vec![
                eight_bit_texture(&mut rng, true, [M, R]),
                eight_bit_texture(&mut rng, false, [C, C]),
            ],
            srgb8 | unorm8,
            repeat | clamp | mirror,
        ),
        (
            vec![
                eight_bit_texture(&mut rng, false, [C, M]),
                random_texture(&mut rng, 3, 7, [M, C]),
            ],
            unorm8 | half,
            clamp | mirror,
        ),
    ];
    for (k, (textures, formats, wraps)) in tables.into_iter().enumerate() {
        let mut scene = Scene::default();
        for (t, texture) in textures.into_iter().enumerate() {
            scene.textures.push(texture);
            let mut m = Material::lambert(format!("m{t}"), Vec3::ONE);
            m.albedo_texture = Some(t);
            scene.add_material(m);
        }
        let table = TextureTable::new(&scene, u64::MAX);
        let features = table.features();
        assert_eq!(
            (features.formats, features.wraps),
            (formats, wraps),
            "table {k}"
        );
        let mut cases = Vec::new();
        let mut expected = Vec::new();
        for i in 0..1200 {
            let t = i % scene.textures.len();
            let (case, value) = level0_lookup(&mut rng, &scene, &table, t);
            cases.push(case);
            expected.push(value);
        }
        let bad = mismatches(&ctx, &features.constants(), &table, &cases, &expected);
        assert!(
            bad.is_empty(),
            "table {k}: {} of {} lookups differ, first: {:?}",
            bad.len(),
            cases.len(),
            &bad[..bad.len().min(4)]
        );
    }
}

/// A glTF sample, its camera head-on (orthographic along −z, the model
/// filling the image), lit by a directional light from the camera of
/// irradiance π (a white Lambertian surface facing it has radiance 1).
fn head_on(model: &str, height: u32) -> (Scene, Camera, u32, u32) {
    let file = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../../shared/gltf-samples")
        .join(model);
    head_on_file(&file, height)
}

/// [`head_on`] for any glTF file.
fn head_on_file(file: &Path, height: u32) -> (Scene, Camera, u32, u32) {
    let mut scene = load_scene(file, &LoadOptions::default()).unwrap();
    let (lo, hi) = scene.bounds().unwrap();
    let (centre, size) = (0.5 * (lo + hi), hi - lo);
    let camera = Camera::look_at(
        centre + Vec3::Z * (10.0 + size.z),
        centre,
        Vec3::Y,
        Projection::Orthographic { height: size.y },
    );
    scene.lights.push(SceneLight {
        name: "head-on".into(),
        light: Light::Directional(DirectionalLight {
            direction: -Vec3::Z,
            irradiance: Vec3::splat(std::f32::consts::PI),
        }),
    });
    let width = (height as f32 * size.x / size.y).round() as u32;
    (scene, camera, width, height)
}

/// CPU `local` (every light, no shadows: the raster model).
fn cpu_local(scene: &Scene, camera: Camera, width: u32, height: u32, spp: u32) -> Image {
    let mut scene = scene.clone();
    scene.camera = Some(camera);
    let mut settings = scene.settings.clone();
    (settings.width, settings.height, settings.spp) = (width, height, spp);
    settings.integrator = IntegratorKind::Local;
    render(&scene, &settings, &RenderOptions::default())
        .unwrap()
        .image
}

fn raster(ctx: &GpuContext, scene: &Scene, camera: Camera, width: u32, height: u32) -> Image {
    let renderer = ForwardRenderer::new(
        ctx,
        RasterOptions {
            msaa: 4,
            ..Default::default()
        },
    )
    .expect("renderer");
    let out = renderer
        .render(ctx, scene, &camera, width, height)
        .expect("render");
    // Textures are all used; only a storage-buffer limit may make some
    // upload a level down (lavapipe's 128 MiB: DamagedHelmet's five
    // 2048² maps), which the renderer says.
    assert!(
        !out.warnings
            .iter()
            .any(|w| w.contains("texture") && !w.contains("storage-buffer limit")),
        "{:?}",
        out.warnings
    );
    out.image
}

/// Renders `model` both ways; checks mean HDR-FLIP ≤ 0.02 and that the
/// pixels `mark` picks in the `rows` (fractions of the height) are as few
/// in the raster image as in the CPU's (within `slack`); returns the
/// raster image.
fn sheet_parity(
    ctx: &GpuContext,
    model: &str,
    height: u32,
    (mark, rows): (&dyn Fn(Vec3) -> bool, std::ops::Range<f32>),
    slack: usize,
) -> Image {
    let (scene, camera, w, h) = head_on(model, height);
    let cpu = cpu_local(&scene, camera, w, h, 16);
    let gpu = raster(ctx, &scene, camera, w, h);
    let (flip, _) = hdr_flip(&cpu, &gpu).expect("flip");
    let (y0, y1) = ((rows.start * h as f32) as u32, (rows.end * h as f32) as u32);
    let count = |img: &Image| {
        (y0..y1)
            .flat_map(|y| (0..w).map(move |x| (x, y)))
            .filter(|&(x, y)| mark(img.get(x, y)))
            .count()
    };
    let (marks_cpu, marks_gpu) = (count(&cpu), count(&gpu));
    eprintln!("{model}: mean HDR-FLIP {flip:.4}; marks CPU {marks_cpu}, raster {marks_gpu}");
    let stem = Path::new(model).file_stem().unwrap().to_string_lossy();
    save_on_failure(&stem, flip > 0.02, &cpu, &gpu);
    assert!(flip <= 0.02, "{model}: mean HDR-FLIP {flip:.4}");
    assert!(
        marks_gpu <= marks_cpu + slack,
        "{model}: {marks_gpu} marked pixels in the raster image, {marks_cpu} in the CPU's"
    );
    gpu
}

/// A pixel whose colour is mostly one channel: a red "fail" mark.
fn reddish(p: Vec3) -> bool {
    p.x > 0.25 && p.y < 0.35 * p.x && p.z < 0.35 * p.x
}

#[test]
fn test_sheets_match_the_cpu() {
    let Some(ctx) = common::gpu("test_sheets_match_the_cpu") else {
        return;
    };
    // Wrap modes: red marks where a mode is wrong.
    let settings = sheet_parity(
        &ctx,
        "TextureSettingsTest/glTF-Binary/TextureSettingsTest.glb",
        1000,
        (&reddish, 0.0..1.0),
        20,
    );
    // The single-sided row (the second of nine) shows its quad's back face,
    // which glTF culls: the green check behind it shows in the "Test"
    // column (0.48–0.62 of the width).
    let (w, h) = (settings.width, settings.height);
    let green = |p: Vec3| p.y > 0.1 && p.x < 0.5 * p.y && p.z < 0.5 * p.y;
    let checks = (h / 9..2 * h / 9)
        .flat_map(|y| (w * 48 / 100..w * 62 / 100).map(move |x| (x, y)))
        .filter(|&(x, y)| green(settings.get(x, y)))
        .count();
    assert!(
        checks > 500,
        "single-sided row: {checks} green pixels in the test column"
    );
    // Texture transforms: the top row shows a yellow image where an offset
    // is missing (the bottom row has yellow markers by design).
    let yellow = |p: Vec3| p.x > 0.5 && p.y > 0.5 && p.z < 0.25 * p.x;
    sheet_parity(
        &ctx,
        "TextureTransformTest/glTF/TextureTransformTest.gltf",
        600,
        (&yellow, 0.0..0.5),
        10,
    );
    // Vertex colours: cyan, magenta or yellow X marks where COLOR_0 is
    // not applied.
    let two_channels = |p: Vec3| {
        let m = p.max_element();
        let on = [p.x, p.y, p.z].iter().filter(|c| **c > 0.5 * m).count();
        m > 0.3 && on == 2
    };
    sheet_parity(
        &ctx,
        "VertexColorTest/glTF-Binary/VertexColorTest.glb",
        600,
        (&two_channels, 0.0..1.0),
        20,
    );
}

/// AlphaBlendModeTest: alpha MASK discards (three cutoffs) and BLEND
/// blends (sorted, source-over) as the CPU's coverage tests and stochastic
/// transparency give on average. Its red marks show where a mode is
/// applied wrongly: none may show. The MASK quads' fills are as high as
/// the CPU's (within 3 of about 100 rows), and the BLEND quad's mean radiance is the CPU's
/// within 3 % (the CPU's coin flips average out over its 10⁴ pixels).
/// (Whole-image FLIP is not the measure here: the sheet's thin stripes and
/// outlines are minified, where MSAA and mip levels differ from the CPU's
/// 64 samples per pixel at every edge.)
#[test]
fn alpha_modes_match_the_cpu() {
    let Some(ctx) = common::gpu("alpha_modes_match_the_cpu") else {
        return;
    };
    let model = "AlphaBlendModeTest/glTF-Binary/AlphaBlendModeTest.glb";
    let (scene, camera, w, h) = head_on(model, 300);
    let cpu = cpu_local(&scene, camera, w, h, 64);
    let gpu = raster(&ctx, &scene, camera, w, h);
    let reds = gpu.pixels.iter().filter(|p| reddish(**p)).count();
    // The height in rows of the cyan and yellow fill, mid-quad.
    let coloured = |p: Vec3| {
        let cyan = p.y > 2.0 * p.x && p.z > 2.0 * p.x;
        let yellow = p.x > 2.0 * p.z && p.y > 2.0 * p.z && p.y > 0.7 * p.x;
        cyan || yellow
    };
    let tops = |img: &Image| -> Vec<usize> {
        [0.514, 0.68, 0.855]
            .iter()
            .map(|f| {
                let x = (f * w as f32) as u32;
                (0..h).filter(|&y| coloured(img.get(x, y))).count()
            })
            .collect()
    };
    let blend_mean = |img: &Image| {
        let (x0, x1) = ((0.31 * w as f32) as u32, (0.37 * w as f32) as u32);
        let (y0, y1) = ((0.25 * h as f32) as u32, (0.8 * h as f32) as u32);
        let sum: Vec3 = (y0..y1)
            .flat_map(|y| (x0..x1).map(move |x| (x, y)))
            .map(|(x, y)| img.get(x, y))
            .sum();
        sum / ((x1 - x0) * (y1 - y0)) as f32
    };
    let (tops_cpu, tops_gpu) = (tops(&cpu), tops(&gpu));
    let (mean_cpu, mean_gpu) = (blend_mean(&cpu), blend_mean(&gpu));
    let (flip, _) = hdr_flip(&cpu, &gpu).expect("flip");
    eprintln!(
        "alpha modes: fills {tops_gpu:?} rows high (CPU {tops_cpu:?}); BLEND quad mean {mean_gpu} (CPU {mean_cpu}); mean HDR-FLIP {flip:.4}"
    );
    let blend_off = ((mean_gpu - mean_cpu).abs() / mean_cpu).max_element();
    save_on_failure("alpha-modes", reds > 0 || blend_off > 0.03, &cpu, &gpu);
    assert_eq!(reds, 0, "{reds} red pixels in the raster image");
    for (g, c) in tops_gpu.iter().zip(&tops_cpu) {
        assert!(
            g.abs_diff(*c) <= 3,
            "MASK fills {tops_gpu:?} rows high, CPU {tops_cpu:?}"
        );
    }
    assert!(
        blend_off <= 0.03,
        "BLEND quad mean {mean_gpu}, CPU {mean_cpu}"
    );
}

/// NormalTangentTest (normal maps with MikkTSpace tangents, UVs turned a
/// different way in each row) under a light from the upper left, so that
/// a wrongly turned normal shades differently: raster and CPU agree (mean
/// HDR-FLIP ≤ 0.02; the CPU's normal maps are checked against the geometry
/// they replace in penumbra-trace's sheet tests).
#[test]
fn normal_maps_match_the_cpu() {
    let Some(ctx) = common::gpu("normal_maps_match_the_cpu") else {
        return;
    };
    let (mut scene, camera, w, h) =
        head_on("NormalTangentTest/glTF-Binary/NormalTangentTest.glb", 800);
    scene.lights[0].light = Light::Directional(DirectionalLight {
        direction: Vec3::new(0.6, -0.6, -1.0).normalize(),
        irradiance: Vec3::splat(std::f32::consts::PI),
    });
    let cpu = cpu_local(&scene, camera, w, h, 16);
    let gpu = raster(&ctx, &scene, camera, w, h);
    let (flip, _) = hdr_flip(&cpu, &gpu).expect("flip");
    eprintln!("NormalTangentTest: mean HDR-FLIP {flip:.4}");
    save_on_failure("NormalTangentTest", flip > 0.02, &cpu, &gpu);
    assert!(flip <= 0.02, "mean HDR-FLIP {flip:.4}");
}

/// glTF occlusionTexture darkens the environment term only: a white
/// Lambertian quad under a constant environment of radiance 1 (E = π, so
/// L = 1 where open) and a point light, its occlusion map 0.25 on the left
/// half and 1 on the right, strength 0.8. Left: 1 + 0.8 · (0.25 − 1) = 0.4
/// of the environment's light; right: all of it; the point light's part
/// alike on both sides.
#[test]
fn occlusion_maps_scale_the_environment_term_only() {
    let Some(ctx) = common::gpu("occlusion_maps_scale_the_environment_term_only") else {
        return;
    };
    // uv_set 1: the map on TEXCOORD_1, TEXCOORD_0 mirrored in u (reading
    // set 0 would swap the sides).
    let quad_scene_on = |uv_set: usize, with_map: bool, background: f32, lamp: f32| {
        let mut scene = Scene::default();
        scene.textures.push(Texture {
            name: "ao".into(),
            width: 4,
            height: 1,
            texels: vec![Vec3::splat(0.25), Vec3::splat(0.25), Vec3::ONE, Vec3::ONE].into(),
            wrap: [Wrap::ClampToEdge; 2],
            uv_transform: Affine2::IDENTITY,
            uv_set,
        });
        let mut m = Material::lambert("white", Vec3::ONE);
        if with_map {
            m.occlusion_map = Some(OcclusionMap {
                texture: 0,
                strength: 0.8,
            });
        }
        let id = scene.add_material(m);
        let mut quad = primitives::quad(Vec3::new(-1.0, -1.0, 0.0), Vec3::X * 2.0, Vec3::Y * 2.0);
        quad.material = id;
        if uv_set == 1 {
            let uv = quad.uv0.take().expect("the quad has UVs");
            quad.uv0 = Some(uv.iter().map(|t| Vec2::new(1.0 - t.x, t.y)).collect());
            quad.uv1 = Some(uv);
        }
        scene.add_mesh(quad, Mat4::IDENTITY);
        scene.background = Vec3::splat(background);
        scene.lights.push(SceneLight {
            name: "lamp".into(),
            light: Light::Point(PointLight {
                position: Vec3::new(0.0, 0.0, 2.0),
                intensity: Vec3::splat(lamp),
                range: f32::INFINITY,
            }),
        });
        scene
    };
    let quad_scene = |with_map, background, lamp| quad_scene_on(0, with_map, background, lamp);
    let camera = Camera::look_at(
        Vec3::Z * 5.0,
        Vec3::ZERO,
        Vec3::Y,
        Projection::Orthographic { height: 2.0 },
    );
    let render = |scene: &Scene| raster(&ctx, scene, camera, 64, 64);
    // Pixels 15 and 48 (centres at u = 0.242 and 0.758, symmetric about
    // the quad's centre) each read two texels of one value.
    let sides = |img: &Image| (img.get(15, 32), img.get(48, 32));
    let (env_left, env_right) = sides(&render(&quad_scene(true, 1.0, 0.0)));
    let (lamp_left, lamp_right) = sides(&render(&quad_scene(true, 0.0, 4.0)));
    let (plain_left, _) = sides(&render(&quad_scene(false, 1.0, 0.0)));
    let (set1_left, set1_right) = sides(&render(&quad_scene_on(1, true, 1.0, 0.0)));
    eprintln!(
        "occlusion: environment {env_left} | {env_right}, lamp {lamp_left} | {lamp_right}, without the map {plain_left}, on UV set 1 {set1_left} | {set1_right}"
    );
    assert!(
        (env_right - Vec3::ONE).abs().max_element() < 0.01,
        "{env_right}"
    );
    assert!(
        (env_left - Vec3::splat(0.4)).abs().max_element() < 0.01,
        "{env_left}"
    );
    assert!(
        (plain_left - Vec3::ONE).abs().max_element() < 0.01,
        "{plain_left}"
    );
    // On TEXCOORD_1, the same sides.
    assert!(
        (set1_left - env_left).abs().max_element() < 0.01
            && (set1_right - env_right).abs().max_element() < 0.01,
        "map on UV set 1: {set1_left} | {set1_right}"
    );
    // The lamp lights both sides alike (symmetric about the quad's centre).
    assert!(
        lamp_left.x > 0.05
            && (lamp_left - lamp_right).abs().max_element() < 1e-3 * lamp_left.x.max(1.0)
    );
}

/// TEXCOORD_1 (penumbra-scene's corpus file `ok_texcoord1.gltf`, as the
/// CPU test `textures_read_their_uv_set` reads it): every texture reads UV
/// set 1, set 0 is mirrored in u, the texture is black and transparent on
/// the left, white and opaque on the right. Lit head-on (white Lambert:
/// radiance = albedo), each row is dark on the left and bright on the
/// right — base colour, emission, alpha mask, and the set overridden by
/// KHR_texture_transform — and so is the CPU's image.
#[test]
fn textures_read_their_uv_set() {
    let Some(ctx) = common::gpu("textures_read_their_uv_set") else {
        return;
    };
    let file = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../penumbra-scene/tests/corpus/gltf/ok_texcoord1.gltf");
    // 20 pixels per unit: rows m = 0..4 centred on pixel row 10 + 25 m;
    // x = ∓0.75 (u = 0.125 and 0.875, one texel each) at columns 5 and 34.
    let (scene, camera, w, h) = head_on_file(&file, 95);
    assert_eq!((w, h), (40, 95));
    let gpu = raster(&ctx, &scene, camera, w, h);
    let cpu = cpu_local(&scene, camera, w, h, 4);
    for (row, what) in ["base colour", "emission", "alpha mask", "texCoord override"]
        .iter()
        .enumerate()
    {
        let y = 10 + 25 * row as u32;
        for (engine, image) in [("raster", &gpu), ("CPU", &cpu)] {
            let (left, right) = (image.get(5, y), image.get(34, y));
            eprintln!("{what}, {engine}: left {left}, right {right}");
            assert!(left.max_element() < 0.02, "{what}, {engine}: left {left}");
            assert!(
                (right - Vec3::ONE).abs().max_element() < 0.02,
                "{what}, {engine}: right {right}"
            );
        }
    }
}

/// DamagedHelmet's emission texture (no light: emission alone): the
/// raster image has the CPU's mean, far below the factor's white
/// silhouette.
#[test]
fn damaged_helmet_emission_matches_the_cpu() {
    let Some(ctx) = common::gpu("damaged_helmet_emission_matches_the_cpu") else {
        return;
    };
    let (mut scene, camera, w, h) = head_on("DamagedHelmet/glTF-Binary/DamagedHelmet.glb", 160);
    scene.lights.clear();
    let cpu = cpu_local(&scene, camera, w, h, 4);
    let gpu = raster(&ctx, &scene, camera, w, h);
    let mean = |img: &Image| img.pixels.iter().sum::<Vec3>() / img.pixels.len() as f32;
    let (mc, mg) = (mean(&cpu), mean(&gpu));
    eprintln!("DamagedHelmet emission: mean CPU {mc}, raster {mg}");
    // Untextured, the helmet glows with its emissive factor (1, 1, 1) over
    // its whole silhouette; the texture lights a small part of it.
    assert!(mc.max_element() > 0.005 && mc.max_element() < 0.15, "{mc}");
    assert!(
        (mg - mc).abs().max_element() <= 0.05 * mc.max_element(),
        "raster {mg} vs CPU {mc}"
    );
}

/// A metallic–roughness quad whose base colour, roughness (G) and
/// metallic (B) come from 4×4 textures, magnified (each texel about 40
/// pixels wide), under a point light placed for a broad highlight: raster
/// and CPU agree (mean HDR-FLIP ≤ 0.02).
#[test]
fn metallic_roughness_textures_match_the_cpu() {
    let Some(ctx) = common::gpu("metallic_roughness_textures_match_the_cpu") else {
        return;
    };
    let mut rng = TestRng::new(5);
    let mut scene = Scene::default();
    let mut base = random_texture(&mut rng, 4, 4, [Wrap::ClampToEdge; 2]);
    base.texels = base.texels.iter().map(|t| 0.2 + 0.8 * t).collect();
    scene.textures.push(base);
    let mut mr = random_texture(&mut rng, 4, 4, [Wrap::ClampToEdge; 2]);
    // Roughness 0.25..1, metallic 0 or 1 in a checker, 0.5 on the diagonal.
    mr.texels = (mr.texels.iter().enumerate())
        .map(|(i, mut t)| {
            let (x, y) = (i % 4, i / 4);
            t.y = 0.25 + 0.75 * t.y;
            t.z = if x == y { 0.5 } else { ((x + y) % 2) as f32 };
            t
        })
        .collect();
    scene.textures.push(mr);
    let mut m = Material {
        bsdf: Bsdf::MetallicRoughness(MetallicRoughness::new(Vec3::ONE, 1.0, 1.0)),
        ..Material::lambert("textured", Vec3::ONE)
    };
    m.albedo_texture = Some(0);
    m.metallic_roughness_texture = Some(1);
    let id = scene.add_material(m);
    let mut quad = primitives::quad(Vec3::new(-1.0, -1.0, 0.0), Vec3::X * 2.0, Vec3::Y * 2.0);
    quad.material = id;
    scene.add_mesh(quad, Mat4::IDENTITY);
    scene.lights.push(SceneLight {
        name: "lamp".into(),
        light: Light::Point(PointLight {
            position: Vec3::new(0.6, 0.4, 1.5),
            intensity: Vec3::splat(8.0),
            range: f32::INFINITY,
        }),
    });
    let camera = Camera::look_at(
        Vec3::new(0.0, -1.0, 3.0),
        Vec3::ZERO,
        Vec3::Y,
        Projection::Perspective {
            fov_y: 50f32.to_radians(),
        },
    );
    let size = 200;
    let cpu = cpu_local(&scene, camera, size, size, 16);
    let gpu = raster(&ctx, &scene, camera, size, size);
    let (flip, _) = hdr_flip(&cpu, &gpu).expect("flip");
    eprintln!("metallic-roughness textures: mean HDR-FLIP {flip:.4}");
    save_on_failure("metallic-roughness", flip > 0.02, &cpu, &gpu);
    assert!(flip <= 0.02, "mean HDR-FLIP {flip:.4}");
}

/// Writes both images to the temporary directory when `failed` or
/// PENUMBRA_TEST_IMAGES is set.
fn save_on_failure(stem: &str, failed: bool, cpu: &Image, gpu: &Image) {
    if failed || std::env::var_os("PENUMBRA_TEST_IMAGES").is_some() {
        for (what, img) in [("cpu", cpu), ("raster", gpu)] {
            let path = std::env::temp_dir().join(format!("{stem}-{what}.png"));
            write_image(&path, img, &[], &ToneMapping::default()).expect("write");
            eprintln!("wrote {}", path.display());
        }
    }
}

/// A 256×256 checkerboard of single texels on a quad 67.5 pixels wide:
/// each pixel covers 3.8 × 3.8 texels, so the CPU's 256 samples per pixel
/// average to about ½, and a raster lookup without mip levels would alias
/// (the pixel centres fall at ever other places in the checks).
#[test]
fn minified_textures_are_filtered_like_the_cpu_average() {
    let Some(ctx) = common::gpu("minified_textures_are_filtered_like_the_cpu_average") else {
        return;
    };
    let n = 256u32;
    let mut scene = Scene::default();
    scene.textures.push(Texture {
        name: "checks".into(),
        width: n,
        height: n,
        texels: (0..n * n)
            .map(|i| Vec3::splat(((i % n + i / n) % 2) as f32))
            .collect(),
        wrap: [Wrap::Repeat; 2],
        uv_transform: Affine2::IDENTITY,
        uv_set: 0,
    });
    let mut m = Material::lambert("checks", Vec3::ONE);
    m.albedo_texture = Some(0);
    let id = scene.add_material(m);
    let mut quad = primitives::quad(Vec3::new(-1.0, -1.0, 0.0), Vec3::X * 2.0, Vec3::Y * 2.0);
    quad.material = id;
    scene.add_mesh(quad, Mat4::IDENTITY);
    scene.lights.push(SceneLight {
        name: "head-on".into(),
        light: Light::Directional(DirectionalLight {
            direction: -Vec3::Z,
            irradiance: Vec3::splat(std::f32::consts::PI),
        }),
    });
    let camera = Camera::look_at(
        Vec3::Z * 5.0,
        Vec3::ZERO,
        Vec3::Y,
        Projection::Orthographic { height: 2.37 },
    );
    let size = 80;
    let cpu = cpu_local(&scene, camera, size, size, 256);
    let gpu = raster(&ctx, &scene, camera, size, size);
    // The quad's interior (it spans pixels 6.25..73.75).
    let mut err = 0.0;
    let mut count = 0;
    for y in 12..68 {
        for x in 12..68 {
            err += (gpu.get(x, y) - cpu.get(x, y)).abs().max_element();
            count += 1;
        }
    }
    let err = err / count as f32;
    let mean = |img: &Image| {
        (12..68)
            .flat_map(|y| (12..68).map(move |x| (x, y)))
            .map(|(x, y)| img.get(x, y).x)
            .sum::<f32>()
            / count as f32
    };
    eprintln!(
        "checkerboard: mean |raster − CPU| {err:.4}; means raster {:.4}, CPU {:.4}",
        mean(&gpu),
        mean(&cpu)
    );
    assert!((mean(&cpu) - 0.5).abs() < 0.02, "CPU mean {}", mean(&cpu));
    assert!(err < 0.05, "mean |raster − CPU| {err}");
}
