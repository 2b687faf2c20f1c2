//! The wavefront path tracer (sixteen paths at a time) against the scalar
//! one on the Cornell box of ../shared/reference and on the glass-sphere
//! box (a dielectric with vertex normals, its 5,120 triangles in a BVH
//! beside the scanned walls) and on spheres of the other models (shaded
//! lane by lane with the shared BSDF code): the same estimator with the same numbers,
//! so the images agree to rounding; the same image for any thread count;
//! scenes outside its scope take the scalar integrator.

use glam::Vec3;
use penumbra_image::rel_mse;
use penumbra_scene::{IntegratorKind, LoadOptions, RenderSettings, Scene, load_scene};
use penumbra_shading::Rgb;
use penumbra_shading::bsdf::{
    Bsdf, Conductor, FresnelModel, Lambert, MetallicRoughness, PhongBlinn, PhongVariant,
    RoughDielectric,
};
use penumbra_trace::{RenderOptions, RenderOutput, render};
use std::path::PathBuf;

fn cornell() -> (Scene, RenderSettings) {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../../shared/reference/cornell/cornell.gltf");
    let scene = load_scene(&path, &LoadOptions::default()).unwrap();
    let mut settings = scene.settings.clone();
    (settings.width, settings.height) = (96, 96);
    settings.integrator = IntegratorKind::Path;
    settings.spp = 24;
    settings.max_depth = 8;
    settings.seed = 5;
    (scene, settings)
}

fn glass() -> (Scene, RenderSettings) {
    let path =
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data/cornell-glass/scene.toml");
    let scene = load_scene(&path, &LoadOptions::default()).unwrap();
    let mut settings = scene.settings.clone();
    (settings.width, settings.height) = (64, 64);
    settings.spp = 16;
    settings.seed = 3;
    (scene, settings)
}

/// Issue 13's metal scene: glass, gold, mirror and rough copper spheres
/// over a floor.
fn metals() -> (Scene, RenderSettings) {
    let path =
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data/metal-spheres/scene.toml");
    let scene = load_scene(&path, &LoadOptions::default()).unwrap();
    let mut settings = scene.settings.clone();
    (settings.width, settings.height) = (72, 48);
    settings.spp = 16;
    settings.seed = 4;
    (scene, settings)
}

/// How the paths are traced.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Paths {
    /// One at a time (`RenderOptions::scalar_paths`).
    Scalar,
    /// Sixteen at a time where the scene allows, in the CPU's widest
    /// registers.
    Lanes,
    /// As `Lanes`, in AVX2 registers even where AVX-512 runs.
    Avx2Lanes,
}

fn render_with(
    scene: &Scene,
    settings: &RenderSettings,
    paths: Paths,
    threads: usize,
) -> RenderOutput {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    pool.install(|| {
        render(
            scene,
            settings,
            &RenderOptions {
                scalar_paths: paths == Paths::Scalar,
                avx2_paths: paths == Paths::Avx2Lanes,
                ..Default::default()
            },
        )
        .unwrap()
    })
}

/// Whether the sixteen-lane tracer runs here: on x86-64, whose CPUs it
/// serves, this test needs AVX2 (the tracer would go untested).
fn lanes() -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        assert!(
            std::arch::is_x86_feature_detected!("avx2"),
            "no AVX2 here: the wavefront's tests need it"
        );
        true
    }
    #[cfg(not(target_arch = "x86_64"))]
    false
}

/// The kinds of lanes to test here: the CPU's widest and, where that is
/// AVX-512, AVX2 too.
fn kinds() -> Vec<Paths> {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx512f") {
        return vec![Paths::Lanes, Paths::Avx2Lanes];
    }
    eprintln!("no AVX-512 here: only the AVX2 lanes are tested");
    vec![Paths::Lanes]
}

/// The two images differ only where a hit's rounding parts a path: the
/// relMSE between them is far below the noise's (about 0.02 at 24 spp on
/// the Cornell box), and the means agree to 0.1 %. A wrong weight, pdf,
/// Fresnel term or roulette moves either by orders of magnitude more.
/// For every kind of lanes the CPU runs.
fn assert_same_image(scene: &Scene, settings: &RenderSettings) {
    let scalar = render_with(scene, settings, Paths::Scalar, 2);
    for kind in kinds() {
        let wide = render_with(scene, settings, kind, 2);
        assert!(!scalar.wavefront && wide.wavefront, "{kind:?}");
        let e = rel_mse(&scalar.image, &wide.image);
        assert!(e < 1e-4, "{kind:?}: relMSE between the images {e}");
        let (ms, mw) = (scalar.image.mean(), wide.image.mean());
        for c in 0..3 {
            assert!(
                (mw[c] / ms[c] - 1.0).abs() < 1e-3,
                "{kind:?}: means {mw} and {ms}"
            );
        }
        // The surface mask (camera rays that met a surface) is the same.
        assert_eq!(scalar.surface, wide.surface, "{kind:?}");
    }
}

/// Each lane draws its pixel's numbers in the scalar integrator's order.
#[test]
fn wavefront_image_is_the_scalar_image() {
    if !lanes() {
        return;
    }
    let (scene, settings) = cornell();
    assert_same_image(&scene, &settings);
}

/// Refraction (Fresnel's choice, 1/η² weights, η² undone for the
/// roulette), shading normals and the BVH part of the tracer, at depth 16.
#[test]
fn wavefront_glass_image_is_the_scalar_image() {
    if !lanes() {
        return;
    }
    let (scene, settings) = glass();
    assert_same_image(&scene, &settings);
}

/// The same seed gives the same bits with one thread and with two.
#[test]
fn wavefront_is_deterministic_across_threads() {
    if !lanes() {
        return;
    }
    let (scene, mut settings) = cornell();
    settings.spp = 9;
    let one = render_with(&scene, &settings, Paths::Lanes, 1);
    let two = render_with(&scene, &settings, Paths::Lanes, 2);
    assert!(one.wavefront);
    assert_eq!(one.image, two.image);
}

/// Shading normals on a Lambert surface (the sphere made matte, its vertex
/// normals pulled towards +x, n + 1.2 x̂ normalised, so that they part far
/// from the faces'):
/// next-event estimation and cosine sampling in the interpolated normal's
/// frame, with the geometric side checks of
/// `TraceContext::consistent_side`.
#[test]
fn wavefront_smooth_lambert_image_is_the_scalar_image() {
    if !lanes() {
        return;
    }
    let (mut scene, settings) = glass();
    for m in &mut scene.materials {
        if matches!(m.bsdf, Bsdf::Dielectric(_)) {
            m.bsdf = Bsdf::Lambert(Lambert::new(Rgb::new(0.8, 0.6, 0.4)));
        }
    }
    let mut tilted = 0;
    for mesh in &mut scene.meshes {
        for n in mesh.normals.iter_mut().flatten() {
            *n = (*n + Vec3::new(1.2, 0.0, 0.0)).normalize();
            tilted += 1;
        }
    }
    assert!(tilted > 0, "the sphere has vertex normals");
    assert_same_image(&scene, &settings);
}

/// Mirror, smooth and rough conductors (the shared BSDF code, lane by
/// lane: delta lobes without next-event estimation, a glossy one with it
/// and its MIS weights), the glass sphere beside them, and the BVH part's
/// tests by object (four spheres apart).
#[test]
fn wavefront_metal_image_is_the_scalar_image() {
    if !lanes() {
        return;
    }
    let (scene, settings) = metals();
    assert_same_image(&scene, &settings);
}

/// More objects beyond the scan than are tested one by one (the four
/// spheres and two copies of each, above and behind them): the BVH part
/// is then one tree over them all, walked a ray at a time, instead of
/// a cluster scan per object.
#[test]
fn wavefront_image_with_many_objects_is_the_scalar_image() {
    if !lanes() {
        return;
    }
    let (mut scene, settings) = metals();
    let large: Vec<_> = scene
        .instances
        .iter()
        .filter(|i| scene.meshes[i.mesh].indices.len() > 64)
        .cloned()
        .collect();
    assert_eq!(large.len(), 4);
    for k in 1..=2 {
        for i in &large {
            let mut copy = i.clone();
            copy.transform =
                glam::Mat4::from_translation(Vec3::new(0.0, 1.2 * k as f32, -1.5)) * i.transform;
            scene.instances.push(copy);
        }
    }
    assert_same_image(&scene, &settings);
}

/// The other models, shared code too: a rough dielectric (transmission,
/// light samples through the surface, η inverted from inside), Phong,
/// metallic–roughness and a Schlick conductor; and one-sided opaque
/// surfaces seen from behind, which are black (the copper sphere turned
/// inside out: every hit on it is from behind).
#[test]
fn wavefront_shared_models_image_is_the_scalar_image() {
    if !lanes() {
        return;
    }
    let (mut scene, settings) = metals();
    let (eta, k) = (Rgb::new(0.2, 0.9, 1.1), Rgb::new(3.7, 2.6, 2.4));
    for m in &mut scene.materials {
        m.bsdf = match m.name.as_str() {
            "glass" => Bsdf::RoughDielectric(RoughDielectric::new(1.5, 0.1)),
            "gold" => Bsdf::PhongBlinn(PhongBlinn::new(
                Rgb::new(0.5, 0.3, 0.2),
                Rgb::splat(0.3),
                40.0,
                PhongVariant::Normalized,
            )),
            "mirror" => {
                Bsdf::MetallicRoughness(MetallicRoughness::new(Rgb::new(0.8, 0.2, 0.1), 0.3, 0.4))
            }
            "copper" => {
                m.double_sided = false;
                Bsdf::Conductor(Conductor::new(eta, k, FresnelModel::Schlick))
            }
            _ => continue,
        };
    }
    let copper = scene.materials.iter().position(|m| m.name == "copper");
    let mut turned = 0;
    for mesh in &mut scene.meshes {
        if Some(mesh.material) == copper {
            for t in &mut mesh.indices {
                t.swap(1, 2);
            }
            for n in mesh.normals.iter_mut().flatten() {
                *n = -*n;
            }
            turned += 1;
        }
    }
    assert_eq!(turned, 1);
    let image = render_with(&scene, &settings, Paths::Lanes, 2).image;
    // The copper sphere (on the right, its centre near pixel (64, 24) of
    // 72 x 48) is black.
    assert_eq!(image.get(64, 24), Rgb::ZERO);
    assert_same_image(&scene, &settings);
}

/// A scene whose BVH part is larger than the wavefront takes (a bumpy
/// ground of 72,200 triangles under a square light; beyond 65,536 the
/// tree walks dominate, and one path at a time does as well) takes the
/// scalar integrator.
#[test]
fn large_scenes_take_the_scalar_integrator() {
    let dir = tempfile::tempdir().unwrap();
    let n = 190;
    let mut obj = String::new();
    for j in 0..=n {
        for i in 0..=n {
            let (x, z) = (
                i as f32 / n as f32 * 4.0 - 2.0,
                j as f32 / n as f32 * 4.0 - 2.0,
            );
            let y = 0.2 * (3.0 * x).sin() * (2.0 * z).cos();
            obj += &format!("v {x} {y} {z}\n");
        }
    }
    for j in 0..n {
        for i in 0..n {
            let v = |a: usize, b: usize| (b * (n + 1) + a + 1).to_string();
            let (a, b, c, d) = (v(i, j), v(i + 1, j), v(i + 1, j + 1), v(i, j + 1));
            obj += &format!("f {a} {d} {c}\nf {a} {c} {b}\n");
        }
    }
    std::fs::write(dir.path().join("ground.obj"), obj).unwrap();
    std::fs::write(
        dir.path().join("light.obj"),
        "v -0.5 2 -0.5\nv 0.5 2 -0.5\nv 0.5 2 0.5\nv -0.5 2 0.5\nf 1 2 3\nf 1 3 4\n",
    )
    .unwrap();
    let toml = r#"
background = [0, 0, 0]
[camera]
position = [0, 3, 3]
look_at = [0, 0, 0]
up = [0, 1, 0]
fov_y_deg = 50
[render]
resolution = [48, 48]
integrator = "path"
max_depth = 6
spp = 16
[[materials]]
name = "ground"
type = "lambert"
albedo = [0.7, 0.6, 0.5]
[[materials]]
name = "light"
type = "lambert"
albedo = 0
emission = [8, 8, 8]
[[objects]]
name = "ground"
mesh = "ground.obj"
material = "ground"
[[objects]]
name = "light"
mesh = "light.obj"
material = "light"
"#;
    let path = dir.path().join("scene.toml");
    std::fs::write(&path, toml).unwrap();
    let scene = load_scene(&path, &LoadOptions::default()).unwrap();
    let settings = scene.settings.clone();
    let out = render_with(&scene, &settings, Paths::Lanes, 2);
    assert!(!out.wavefront);
    assert!(out.image.mean().max_element() > 0.01, "the ground is lit");
}

/// Scenes outside the wavefront's scope (light from the background) and the
/// other integrators take the scalar one.
#[test]
fn other_scenes_take_the_scalar_integrator() {
    let (mut scene, mut settings) = glass();
    (settings.width, settings.height, settings.spp) = (16, 16, 1);
    assert_eq!(
        render_with(&scene, &settings, Paths::Lanes, 1).wavefront,
        lanes()
    );
    scene.background = Vec3::splat(0.1);
    assert!(!render_with(&scene, &settings, Paths::Lanes, 1).wavefront);
    let (scene, mut settings) = cornell();
    (settings.width, settings.height, settings.spp) = (16, 16, 1);
    settings.integrator = IntegratorKind::Direct;
    assert!(!render_with(&scene, &settings, Paths::Lanes, 1).wavefront);
    settings.integrator = IntegratorKind::Path;
    assert_eq!(
        render_with(&scene, &settings, Paths::Lanes, 1).wavefront,
        lanes()
    );
}
