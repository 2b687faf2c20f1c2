//! What the path and Whitted integrators do on a path's first segment
//! and how they count segments: camera rays pass through single-sided
//! back faces, the AOVs are the first hit's, a mirror chain ends at the
//! last segment allowed, and light sampled at a surface arrives on the
//! segment after it (what the bakes split direct from indirect light by);
//! and the bakes' ambient-occlusion query.

mod common;

use common::*;
use glam::Vec3;
use penumbra_scene::{Camera, IntegratorKind, Material, Projection, Scene, SceneLight};
use penumbra_shading::Rgb;
use penumbra_shading::light::{Light, PointLight, Shape};
use penumbra_shading::sampling::Sampler;
use penumbra_trace::accel::BuildQuality;
use penumbra_trace::geometry::SceneGeometry;
use penumbra_trace::integrator::{RadianceSink, TraceContext};
use penumbra_trace::lights::{Emitter, LightSampler};
use penumbra_trace::ray::Ray;
use penumbra_trace::texture_lod::RayCone;
use penumbra_trace::{RenderOptions, render};

/// A 4 × 4 quad at height `y` whose front faces `up` (+y) or down.
fn horizontal_quad(y: f32, up: bool, material: usize) -> penumbra_scene::Mesh {
    let corner = Vec3::new(-2.0, y, -2.0);
    if up {
        quad(corner, Vec3::Z * 4.0, Vec3::X * 4.0, material)
    } else {
        quad(corner, Vec3::X * 4.0, Vec3::Z * 4.0, material)
    }
}

/// One pixel seen straight down from y = 10 at (x, z), path traced with
/// AOVs: (radiance, depth AOV).
fn look_down(scene: &Scene, x: f32, z: f32, spp: u32) -> (f32, f32) {
    look_down_with(scene, x, z, spp, IntegratorKind::Path, 4)
}

/// [`look_down`] with integrator `kind` and at most `max_depth` segments.
fn look_down_with(
    scene: &Scene,
    x: f32,
    z: f32,
    spp: u32,
    kind: IntegratorKind,
    max_depth: u32,
) -> (f32, f32) {
    let mut scene = scene.clone();
    scene.camera = Some(Camera::look_at(
        Vec3::new(x, 10.0, z),
        Vec3::new(x, 0.0, z),
        Vec3::Z,
        Projection::Orthographic { height: 1e-3 },
    ));
    let out = render(
        &scene,
        &settings(kind, 1, 1, spp, max_depth),
        &RenderOptions {
            aovs: true,
            ..RenderOptions::default()
        },
    )
    .unwrap();
    let depth = out
        .aovs
        .iter()
        .find(|(name, _)| name == "depth")
        .expect("a depth AOV")
        .1
        .get(0, 0)
        .x;
    (out.image.get(0, 0).x, depth)
}

/// An emitter (radiance 1, facing up) under a single-sided quad whose
/// front faces down: the camera above sees the quad's back, which it
/// passes through (glTF `doubleSided: false`), and so sees the emitter.
/// Turned to face the camera, the same quad hides the emitter.
#[test]
fn camera_rays_pass_through_single_sided_back_faces() {
    for facing_camera in [false, true] {
        let mut scene = Scene::default();
        let glow = scene.add_material(Material {
            double_sided: true,
            ..Material::emitter("glow", Rgb::ONE)
        });
        let one_sided = scene.add_material(Material {
            double_sided: false,
            cull_back_faces: true,
            ..Material::lambert("one-sided", Rgb::splat(0.5))
        });
        add(&mut scene, horizontal_quad(-1.0, true, glow));
        add(&mut scene, horizontal_quad(0.0, facing_camera, one_sided));
        for kind in [IntegratorKind::Path, IntegratorKind::Whitted] {
            let (radiance, depth) = look_down_with(&scene, 0.3, 0.2, 4, kind, 4);
            if facing_camera {
                // Lit from below through nothing: the emitter faces the
                // quad's back, which absorbs. Black, 10 away.
                assert_eq!(radiance, 0.0, "{kind}");
                assert!((depth - 10.0).abs() < 1e-4, "{kind}: {depth}");
            } else {
                assert!((radiance - 1.0).abs() < 1e-3, "{kind}: {radiance}");
                assert!((depth - 11.0).abs() < 1e-4, "{kind}: {depth}");
            }
        }
    }
}

/// A mirror floor (reflectance 0.5) under a constant sky of radiance 2:
/// with two segments allowed the camera sees the sky in it, 0.5 · 2 = 1;
/// with one, only what the first ray meets (the mirror emits nothing).
/// An emitter seen directly needs one segment; with none, all is black.
/// Between two facing mirrors no ray ever escapes: the chain ends at the
/// last segment allowed, black.
#[test]
fn mirror_chains_end_at_the_last_segment() {
    use penumbra_shading::bsdf::{Bsdf, Mirror};
    let mut scene = Scene::default();
    let mirror = scene.add_material(Material {
        bsdf: Bsdf::Mirror(Mirror {
            reflectance: Rgb::splat(0.5),
        }),
        ..Material::lambert("mirror", Rgb::ONE)
    });
    add(&mut scene, horizontal_quad(0.0, true, mirror));
    scene.background = Rgb::splat(2.0);
    for kind in [IntegratorKind::Path, IntegratorKind::Whitted] {
        let (seen, _) = look_down_with(&scene, 0.1, 0.1, 1, kind, 2);
        assert!((seen - 1.0).abs() < 1e-4, "{kind}: {seen}");
        let (first, _) = look_down_with(&scene, 0.1, 0.1, 1, kind, 1);
        assert_eq!(first, 0.0, "{kind}");
    }
    // An emitter seen directly: with one segment its radiance, with none
    // (max_depth 0, as Mitsuba counts) nothing.
    let mut glowing = Scene::default();
    let glow = glowing.add_material(Material::emitter("glow", Rgb::splat(3.0)));
    add(&mut glowing, horizontal_quad(0.0, true, glow));
    for kind in [IntegratorKind::Path, IntegratorKind::Whitted] {
        let (one, _) = look_down_with(&glowing, 0.1, 0.1, 1, kind, 1);
        assert!((one - 3.0).abs() < 1e-3, "{kind}: {one}");
        let (none, _) = look_down_with(&glowing, 0.1, 0.1, 1, kind, 0);
        assert_eq!(none, 0.0, "{kind}");
    }
    // A second mirror above the camera, facing down, 20 wide: the ray
    // bounces between the two until its segments run out.
    let mut closed = scene.clone();
    add(
        &mut closed,
        quad(
            Vec3::new(-10.0, 12.0, -10.0),
            Vec3::X * 20.0,
            Vec3::Z * 20.0,
            mirror,
        ),
    );
    for kind in [IntegratorKind::Path, IntegratorKind::Whitted] {
        let (trapped, _) = look_down_with(&closed, 0.1, 0.1, 1, kind, 16);
        assert_eq!(trapped, 0.0, "{kind}");
    }
}

/// The bakes' ambient-occlusion query at a floor point against a large
/// wall rising at x = 0.01: the wall hides almost exactly the half of the
/// cosine-weighted hemisphere towards +x, so kA ≈ ½ (the wall, 20 high and
/// 40 wide, leaves the grazing rest open: a little over ½).
#[test]
fn ambient_occlusion_at_the_foot_of_a_wall() {
    let mut scene = Scene::default();
    let grey = lambert(&mut scene, 0.5);
    add(&mut scene, horizontal_quad(0.0, true, grey));
    add(
        &mut scene,
        quad(
            Vec3::new(0.01, 0.0, -20.0),
            Vec3::Y * 20.0,
            Vec3::Z * 40.0,
            grey,
        ),
    );
    let geometry = SceneGeometry::build(&scene, BuildQuality::Fast).unwrap();
    let lights = LightSampler::new(&scene, &geometry);
    let settings = settings(IntegratorKind::Ao, 1, 1, 1, 1);
    let ctx = TraceContext {
        scene: &scene,
        geometry: &geometry,
        lights: &lights,
        settings: &settings,
        camera_cone: RayCone::POINT,
    };
    let ray = Ray::segment(Vec3::new(0.0, 1.0, 0.0), -Vec3::Y, f32::INFINITY);
    let hit = geometry.intersect(&scene, &ray).expect("the floor");
    let n = 4000;
    let ka = (0..n)
        .map(|i| ctx.ambient_occlusion_at(&hit, &mut Sampler::new(0, 0, i, 3)))
        .sum::<f32>()
        / n as f32;
    assert!((0.5..0.53).contains(&ka), "kA = {ka}");
}

/// The AOVs are the first hit's, whatever later segments meet: a floor
/// 10 below the camera under a large sphere light (every bounce from the
/// floor that hits the light would give another depth), and the sphere
/// itself seen directly (its top 10 − 3.5 below).
#[test]
fn aovs_are_the_first_hit() {
    let mut scene = Scene::default();
    let floor = lambert(&mut scene, 0.5);
    add(&mut scene, horizontal_quad(0.0, true, floor));
    let sphere = Shape::Sphere {
        center: Vec3::new(1.0, 2.0, 0.0),
        radius: 1.5,
    };
    scene.area_lights.push(area_light("sphere", sphere, 1.0));
    let (radiance, depth) = look_down(&scene, -1.0, 0.0, 64);
    assert!(radiance > 0.0);
    assert!((depth - 10.0).abs() < 1e-4, "floor: {depth}");
    let (radiance, depth) = look_down(&scene, 1.0, 0.0, 4);
    assert!((radiance - 1.0).abs() < 1e-3, "{radiance}");
    assert!((depth - 6.5).abs() < 1e-3, "sphere: {depth}");
}

/// Segments each contribution reached the query point by.
#[derive(Default)]
struct Segments(Vec<(u32, Rgb)>);

impl RadianceSink for Segments {
    fn add(&mut self, _emitter: Emitter, segment: u32, value: Rgb) {
        self.0.push((segment, value));
    }
}

/// A point light of intensity I, 2 above a floor: light sampled at the
/// floor arrives on segment 2 (segment 1 ends at the query point), and
/// the irradiance is the inverse-square law's I / d². With a wall beside
/// it and one bounce allowed, light also arrives on segment 3.
#[test]
fn sampled_light_arrives_on_the_next_segment() {
    let (intensity, d) = (8.0f32, 2.0f32);
    let mut scene = Scene::default();
    let floor = lambert(&mut scene, 0.5);
    add(&mut scene, horizontal_quad(0.0, true, floor));
    scene.lights.push(SceneLight {
        name: "point".into(),
        light: Light::Point(PointLight::new(
            Vec3::new(0.0, d, 0.0),
            Rgb::splat(intensity),
        )),
    });
    let irradiance = |scene: &Scene, bounces: u32| {
        let geometry = SceneGeometry::build(scene, BuildQuality::Fast).unwrap();
        let lights = LightSampler::new(scene, &geometry);
        let settings = settings(IntegratorKind::Path, 1, 1, 1, 8);
        let ctx = TraceContext {
            scene,
            geometry: &geometry,
            lights: &lights,
            settings: &settings,
            camera_cone: RayCone::POINT,
        };
        let ray = Ray::segment(Vec3::new(0.0, 1.0, 0.0), -Vec3::Y, f32::INFINITY);
        let hit = geometry.intersect(scene, &ray).expect("the floor");
        let mut sink = Segments::default();
        let n = 256;
        for i in 0..n {
            let mut sampler = Sampler::new(0, 0, i, 5);
            ctx.irradiance_at(&hit, &mut sampler, bounces, &mut sink);
        }
        (sink.0, n)
    };
    let (direct, n) = irradiance(&scene, 0);
    assert!(!direct.is_empty());
    assert!(
        direct.iter().all(|&(segment, _)| segment == 2),
        "{direct:?}"
    );
    let e: f32 = direct.iter().map(|(_, v)| v.x).sum::<f32>() * std::f32::consts::PI / n as f32;
    let expected = intensity / (d * d);
    assert!((e / expected - 1.0).abs() < 1e-4, "E = {e} vs {expected}");

    // A wall at x = 1 facing the point: some light now bounces off it.
    let wall = lambert(&mut scene, 0.8);
    add(
        &mut scene,
        quad(
            Vec3::new(1.0, 0.0, -2.0),
            Vec3::Z * 4.0,
            Vec3::Y * 4.0,
            wall,
        ),
    );
    let (both, _) = irradiance(&scene, 1);
    assert!(
        both.iter()
            .all(|&(segment, _)| segment == 2 || segment == 3)
    );
    assert!(both.iter().any(|&(segment, _)| segment == 3), "no bounce");
}
