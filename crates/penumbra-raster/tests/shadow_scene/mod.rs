//! The scene every shadow test shares: a 12 × 12 ground plane, a box
//! standing on it and a sphere floating above it, lit in turn by a
//! directional, a spot or a point light; the CPU renders and the shadow
//! classification the tests compare.
#![allow(dead_code)]

use glam::{Mat4, Vec3};
use penumbra_image::{Image, ToneMapping, write_image};
use penumbra_raster::{ForwardRenderer, GpuContext, RasterOptions};
use penumbra_scene::camera::{Camera, Projection};
use penumbra_scene::{IntegratorKind, Material, Scene, SceneLight, primitives};
use penumbra_shading::light::{DirectionalLight, Light, PointLight, SpotLight};
use penumbra_trace::{RenderOptions, render};

pub const RES: u32 = 256;

pub fn lum(p: Vec3) -> f32 {
    0.2126 * p.x + 0.7152 * p.y + 0.0722 * p.z
}

pub fn light(which: &str) -> Light {
    match which {
        "directional" => Light::Directional(DirectionalLight {
            direction: Vec3::new(1.0, -0.8, -0.6).normalize(),
            irradiance: Vec3::splat(2.0),
        }),
        "spot" => {
            let position = Vec3::new(-2.5, 5.0, 1.5);
            Light::Spot(SpotLight {
                position,
                direction: (Vec3::new(0.3, 0.0, -0.3) - position).normalize(),
                intensity: Vec3::splat(40.0),
                cos_inner: 30f32.to_radians().cos(),
                cos_outer: 42f32.to_radians().cos(),
                range: f32::INFINITY,
            })
        }
        "point" => Light::Point(PointLight::new(Vec3::new(1.5, 3.2, 1.0), Vec3::splat(20.0))),
        _ => unreachable!(),
    }
}

/// The ground plane, optionally the box and the sphere, and the named
/// lights.
pub fn scene_with(lights: &[&str], occluders: bool) -> Scene {
    let mut scene = Scene::default();
    let white = scene.add_material(Material::lambert("white", Vec3::splat(0.7)));
    let red = scene.add_material(Material::lambert("red", Vec3::new(0.7, 0.2, 0.1)));
    let mut ground = primitives::quad(
        Vec3::new(-6.0, 0.0, 6.0),
        Vec3::new(12.0, 0.0, 0.0),
        Vec3::new(0.0, 0.0, -12.0),
    );
    ground.material = white;
    scene.add_mesh(ground, Mat4::IDENTITY);
    if occluders {
        let mut b = primitives::cuboid(Vec3::new(-1.6, 0.0, -0.6), Vec3::new(-0.4, 1.2, 0.6));
        b.material = red;
        scene.add_mesh(b, Mat4::IDENTITY);
        let mut s = primitives::sphere(Vec3::new(1.0, 1.4, -0.8), 0.6, 32);
        s.material = red;
        scene.add_mesh(s, Mat4::IDENTITY);
    }
    scene.lights = lights
        .iter()
        .map(|which| SceneLight {
            name: which.to_string(),
            light: light(which),
        })
        .collect();
    scene
}

/// The scene lit by one light.
pub fn scene(which: &str, occluders: bool) -> Scene {
    scene_with(&[which], occluders)
}

pub fn camera() -> Camera {
    Camera::look_at(
        Vec3::new(0.0, 6.5, 7.5),
        Vec3::new(0.0, 0.3, -0.3),
        Vec3::Y,
        Projection::Perspective {
            fov_y: 50f32.to_radians(),
        },
    )
}

pub fn cpu_with(scene: &Scene, camera: Camera, integrator: IntegratorKind) -> Image {
    let mut scene = scene.clone();
    scene.camera = Some(camera);
    let mut settings = scene.settings.clone();
    settings.width = RES;
    settings.height = RES;
    settings.spp = 4;
    settings.integrator = integrator;
    render(&scene, &settings, &RenderOptions::default())
        .unwrap()
        .image
}

pub fn cpu(scene: &Scene, integrator: IntegratorKind) -> Image {
    cpu_with(scene, camera(), integrator)
}

/// The raster image and the GPU times of the passes whose name starts
/// with `timed`.
pub fn raster_with(
    ctx: &GpuContext,
    scene: &Scene,
    camera: &Camera,
    options: RasterOptions,
    timed: &str,
) -> (Image, Vec<f64>) {
    let r = ForwardRenderer::new(ctx, options).expect("renderer");
    let out = r.render(ctx, scene, camera, RES, RES).expect("render");
    assert!(out.image.all_finite());
    let ms = out
        .passes
        .iter()
        .filter(|p| p.name.starts_with(timed))
        .map(|p| p.ms)
        .collect();
    (out.image, ms)
}

pub fn raster(
    ctx: &GpuContext,
    scene: &Scene,
    options: RasterOptions,
    timed: &str,
) -> (Image, Vec<f64>) {
    raster_with(ctx, scene, &camera(), options, timed)
}

/// Shadowed where `shadowed` < ½ · `unshadowed`.
pub fn classify(shadowed: &Image, unshadowed: &Image) -> Vec<bool> {
    shadowed
        .pixels
        .iter()
        .zip(&unshadowed.pixels)
        .map(|(s, u)| lum(*s) < 0.5 * lum(*u))
        .collect()
}

/// Writes `img` to the temp folder when PENUMBRA_TEST_IMAGES is set.
pub fn save(name: &str, img: &Image) {
    if std::env::var_os("PENUMBRA_TEST_IMAGES").is_some() {
        let path = std::env::temp_dir().join(format!("shadow-{name}.png"));
        write_image(&path, img, &[], &ToneMapping::default()).expect("write");
        eprintln!("wrote {}", path.display());
    }
}

/// (pixels whose state differs, of which GPU-lit but CPU-shadowed), as
/// fractions of the pixels in `mask` (all pixels if `None`).
pub fn differences(gpu: &[bool], cpu: &[bool], mask: Option<&[bool]>) -> (f64, f64, usize) {
    let mut n = 0usize;
    let (mut diff, mut leak) = (0usize, 0usize);
    for (i, (g, c)) in gpu.iter().zip(cpu).enumerate() {
        if mask.is_some_and(|m| !m[i]) {
            continue;
        }
        n += 1;
        if g != c {
            diff += 1;
            if !*g {
                leak += 1;
            }
        }
    }
    let n = n.max(1) as f64;
    (diff as f64 / n, leak as f64 / n, n as usize)
}
