//! Recursive (Whitted) ray tracing against closed forms and against the path
//! tracer.

mod common;

use common::*;
use glam::{Mat4, Vec3};
use penumbra_scene::{Camera, IntegratorKind, Material, Projection, Scene, SceneLight, primitives};
use penumbra_shading::Rgb;
use penumbra_shading::bsdf::optics::fresnel_conductor;
use penumbra_shading::bsdf::{Bsdf, Conductor, Dielectric, FresnelModel, Mirror};
use penumbra_shading::light::{Light, PointLight};
use penumbra_trace::{RenderOptions, render};

fn with_bsdf(name: &str, bsdf: Bsdf) -> Material {
    Material {
        bsdf,
        ..Material::lambert(name, Rgb::ONE)
    }
}

/// A mirror at 45° under an orthographic camera looking down −z sends every
/// camera ray straight up (+y) into an emitter of radiance Le: each pixel is
/// exactly R(45°)·Le, for a constant-reflectance mirror and a Fresnel
/// conductor, with `whitted` and with `path` (delta lobe, no MIS).
#[test]
fn mirror_at_45_degrees_reflects_a_known_emitter_exactly() {
    let le = Rgb::new(2.0, 3.0, 4.0);
    let gold = (Rgb::new(0.18, 0.42, 1.37), Rgb::new(3.42, 2.35, 1.77));
    let cases = [
        (
            Bsdf::Mirror(Mirror::new(Rgb::new(0.9, 0.5, 0.2))),
            Rgb::new(0.9, 0.5, 0.2),
        ),
        (
            Bsdf::Conductor(Conductor::new(gold.0, gold.1, FresnelModel::Exact)),
            fresnel_conductor(std::f32::consts::FRAC_1_SQRT_2, gold.0, gold.1),
        ),
    ];
    for (bsdf, reflectance) in cases {
        let mut scene = Scene::default();
        let mirror = scene.add_material(with_bsdf("mirror", bsdf));
        let light = scene.add_material(Material::emitter("light", le));
        // Front normal e1 × e2 = (0, 1, 1): faces the camera and the emitter.
        add(
            &mut scene,
            quad(
                Vec3::new(-2.0, -2.0, 2.0),
                Vec3::new(4.0, 0.0, 0.0),
                Vec3::new(0.0, 4.0, -4.0),
                mirror,
            ),
        );
        // Emitter above, front normal −y.
        add(
            &mut scene,
            quad(
                Vec3::new(-20.0, 5.0, -20.0),
                Vec3::new(40.0, 0.0, 0.0),
                Vec3::new(0.0, 0.0, 40.0),
                light,
            ),
        );
        scene.camera = Some(Camera::look_at(
            Vec3::new(0.0, 0.0, 10.0),
            Vec3::ZERO,
            Vec3::Y,
            Projection::Orthographic { height: 1.0 },
        ));
        for kind in [IntegratorKind::Whitted, IntegratorKind::Path] {
            let out = render(
                &scene,
                &settings(kind, 8, 8, 4, 3),
                &RenderOptions::default(),
            )
            .unwrap();
            let expected = reflectance * le;
            for y in 0..8 {
                for x in 0..8 {
                    let v = out.image.get(x, y);
                    let err = ((v - expected) / expected).abs().max_element();
                    assert!(
                        err < 1e-4,
                        "{kind}: pixel ({x},{y}) = {v}, expected {expected}"
                    );
                }
            }
        }
    }
}

/// On a scene whose only non-specular surface is one Lambertian floor, lit
/// by point lights, with `max_depth = 3`, Whitted and path tracing estimate
/// the same integral: the floor's indirect light would need a 4th segment
/// (floor → sphere → floor → light). They must agree within noise; Whitted
/// follows both lobes of the glass, path tracing picks one by Fresnel.
#[test]
fn whitted_and_path_agree_on_a_specular_scene() {
    let mut scene = Scene::default();
    let floor = lambert(&mut scene, 0.7);
    let mirror = scene.add_material(with_bsdf(
        "mirror",
        Bsdf::Mirror(Mirror::new(Rgb::splat(0.9))),
    ));
    let glass = scene.add_material(with_bsdf("glass", Bsdf::Dielectric(Dielectric::glass())));
    let copper = scene.add_material(with_bsdf(
        "copper",
        Bsdf::Conductor(Conductor::new(
            Rgb::new(0.27, 0.68, 1.22),
            Rgb::new(3.61, 2.63, 2.29),
            FresnelModel::Schlick,
        )),
    ));
    add(
        &mut scene,
        quad(
            Vec3::new(-10.0, 0.0, 10.0),
            Vec3::new(20.0, 0.0, 0.0),
            Vec3::new(0.0, 0.0, -20.0),
            floor,
        ),
    );
    for (c, r, m) in [
        (Vec3::new(-1.3, 1.0, 0.0), 1.0, mirror),
        (Vec3::new(0.2, 0.6, -1.8), 0.6, copper),
    ] {
        let mut s = primitives::sphere(c, r, 48);
        s.material = m;
        scene.add_mesh(s, Mat4::IDENTITY);
    }
    // A single tilted glass interface (one refraction, no exit) so that
    // refracted light reaches the lit floor within three segments.
    add(
        &mut scene,
        quad(
            Vec3::new(0.5, 0.2, 2.0),
            Vec3::new(1.5, 0.0, 0.3),
            Vec3::new(0.0, 1.2, 0.0),
            glass,
        ),
    );
    for (p, i) in [
        (Vec3::new(2.0, 5.0, 3.0), 30.0),
        (Vec3::new(-4.0, 3.0, -1.0), 12.0),
    ] {
        scene.lights.push(SceneLight {
            name: "bulb".into(),
            light: Light::Point(PointLight {
                position: p,
                intensity: Rgb::splat(i),
                range: f32::INFINITY,
            }),
        });
    }
    scene.camera = Some(Camera::look_at(
        Vec3::new(0.0, 3.0, 8.0),
        Vec3::new(0.0, 0.8, 0.0),
        Vec3::Y,
        Projection::Perspective { fov_y: 0.7 },
    ));
    let (w, h) = (48, 32);
    let whitted = render(
        &scene,
        &settings(IntegratorKind::Whitted, w, h, 64, 3),
        &RenderOptions::default(),
    )
    .unwrap();
    let path = render(
        &scene,
        &settings(IntegratorKind::Path, w, h, 256, 3),
        &RenderOptions::default(),
    )
    .unwrap();
    // Compare 8×8-pixel block means (pixel-level noise of the path tracer's
    // lobe and light choices averages out) and the image mean.
    let block = |img: &penumbra_image::Image, bx: u32, by: u32| {
        let mut s = Rgb::ZERO;
        for y in by * 8..by * 8 + 8 {
            for x in bx * 8..bx * 8 + 8 {
                s += img.get(x, y);
            }
        }
        s / 64.0
    };
    let (mw, mp) = (whitted.image.mean(), path.image.mean());
    assert!(mw.max_element() > 0.05, "scene is lit: {mw}");
    assert!(
        ((mw - mp) / mw).abs().max_element() < 0.01,
        "means {mw} vs {mp}"
    );
    for by in 0..h / 8 {
        for bx in 0..w / 8 {
            let (a, b) = (block(&whitted.image, bx, by), block(&path.image, bx, by));
            let err = (a - b).abs().max_element() / (a.max_element() + 0.02);
            assert!(err < 0.04, "block ({bx},{by}): whitted {a} vs path {b}");
        }
    }
}
