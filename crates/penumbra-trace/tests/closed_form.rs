//! Integrators against closed-form answers.

mod common;

use common::*;
use glam::{Mat4, Vec3};
use penumbra_scene::{Camera, IntegratorKind, Material, Projection, Scene, SceneLight};
use penumbra_shading::Rgb;
use penumbra_shading::light::{Light, PointLight};
use penumbra_trace::{RenderOptions, render};

/// Adds a closed sphere of radius 3 (no UVs) made of `material` and a
/// camera at its centre.
fn furnace(scene: &mut Scene, material: Material) {
    let m = scene.add_material(material);
    let mut sphere = penumbra_trace::bench::bench_mesh(20_000);
    sphere.material = m;
    scene.add_mesh(sphere, Mat4::from_scale(Vec3::splat(3.0)));
    scene.camera = Some(Camera::look_at(
        Vec3::ZERO,
        Vec3::X,
        Vec3::Y,
        Projection::Perspective { fov_y: 1.5 },
    ));
}

/// Furnace: inside a closed surface of albedo ρ that also emits Le
/// everywhere, radiance is Le (1 + ρ + ρ² + …) = Le / (1 − ρ).
#[test]
fn furnace_gives_le_over_one_minus_rho() {
    for rho in [0.5f32, 0.8] {
        let mut scene = Scene::default();
        let le = 0.7;
        let m = Material {
            emission: Rgb::splat(le),
            double_sided: true,
            ..Material::lambert("furnace", Rgb::splat(rho))
        };
        furnace(&mut scene, m);
        let out = render(
            &scene,
            &settings(IntegratorKind::Path, 32, 32, 64, 1000),
            &RenderOptions::default(),
        )
        .unwrap();
        let mean = out.image.mean();
        let expected = le / (1.0 - rho);
        for c in [mean.x, mean.y, mean.z] {
            assert!(
                (c / expected - 1.0).abs() < 0.01,
                "rho {rho}: {c} vs {expected}"
            );
        }
    }
}

/// Furnace with a textured emitter: inside a sphere every surface element
/// sees every other with the same form-factor density, so the mean outgoing
/// radiance M obeys M = mean(Le) + ρM whatever the pattern of Le. The
/// sphere mesh has no UVs, so each triangle's UV is its barycentrics (u = b₁,
/// density 2(1 − u) under uniform area sampling). A 2×1 texture [0, 2] with
/// CLAMP_TO_EDGE, sampled bilinearly, is f(u) = 0 below ¼, 4u − 1 up to ¾,
/// and 2 above: its mean over a triangle is ∫ f(u) 2(1 − u) du = 13/24.
/// Light sampling picks triangles by their mean texture and evaluates the
/// texture at the sampled point; hits evaluate it at the hit.
#[test]
fn furnace_with_an_emission_texture() {
    let (rho, le) = (0.5f32, 0.7f32);
    let mut scene = Scene::default();
    scene.textures.push(penumbra_scene::Texture {
        name: "ramp".into(),
        width: 2,
        height: 1,
        texels: vec![Rgb::ZERO, Rgb::splat(2.0)].into(),
        wrap: [penumbra_scene::texture::Wrap::ClampToEdge; 2],
        uv_transform: glam::Affine2::IDENTITY,
        uv_set: 0,
    });
    let m = Material {
        emission: Rgb::splat(le),
        emission_texture: Some(0),
        double_sided: true,
        ..Material::lambert("furnace", Rgb::splat(rho))
    };
    furnace(&mut scene, m);
    let expected = le * 13.0 / 24.0 / (1.0 - rho);
    for integrator in [IntegratorKind::Path, IntegratorKind::Direct] {
        let out = render(
            &scene,
            &settings(integrator, 32, 32, 64, 1000),
            &RenderOptions::default(),
        )
        .unwrap();
        let mean = out.image.mean().x;
        // Direct light: the emission seen plus one bounce, Le(1 + ρ).
        let want = match integrator {
            IntegratorKind::Direct => le * 13.0 / 24.0 * (1.0 + rho),
            _ => expected,
        };
        assert!(
            (mean / want - 1.0).abs() < 0.01,
            "{integrator}: {mean} vs {want}"
        );
    }
}

/// Point light of intensity I at height d over a Lambertian plane of albedo
/// ρ: L = ρ/π · I cos θ / r², with cos θ = d / r. Checked pixel by pixel
/// against the analytic value averaged over each pixel's footprint.
#[test]
fn point_light_over_plane() {
    let (rho, intensity, d) = (0.6f32, 5.0f32, 1.0f32);
    let expected_at = |x: f32, z: f32| {
        let r2 = x * x + z * z + d * d;
        rho / std::f32::consts::PI * intensity * (d / r2.sqrt()) / r2
    };
    for integrator in [
        IntegratorKind::Local,
        IntegratorKind::Direct,
        IntegratorKind::Path,
    ] {
        let mut scene = Scene::default();
        let m = lambert(&mut scene, rho);
        add(
            &mut scene,
            quad(
                Vec3::new(-4.0, 0.0, -4.0),
                Vec3::new(0.0, 0.0, 8.0),
                Vec3::new(8.0, 0.0, 0.0),
                m,
            ),
        );
        scene.lights.push(SceneLight {
            name: "p".into(),
            light: Light::Point(PointLight {
                position: Vec3::new(0.0, d, 0.0),
                intensity: Rgb::splat(intensity),
                range: f32::INFINITY,
            }),
        });
        let view = 3.0;
        scene.camera = Some(top_down_camera(Vec3::ZERO, view));
        let n = 24u32;
        let out = render(
            &scene,
            &settings(integrator, n, n, 64, 2),
            &RenderOptions::default(),
        )
        .unwrap();
        let cam = scene.camera.unwrap();
        let mut worst = 0.0f32;
        for py in 0..n {
            for px in 0..n {
                // Average the analytic radiance over the pixel (8×8 points).
                let mut e = 0.0;
                for k in 0..64 {
                    let (o, _) = cam.generate_ray(
                        px as f32 + ((k % 8) as f32 + 0.5) / 8.0,
                        py as f32 + ((k / 8) as f32 + 0.5) / 8.0,
                        n,
                        n,
                    );
                    e += expected_at(o.x, o.z) / 64.0;
                }
                let got = out.image.get(px, py).x;
                worst = worst.max((got / e - 1.0).abs());
            }
        }
        assert!(worst < 0.01, "{integrator}: worst relative error {worst}");
    }
}

fn ao_at(scene: &Scene, p: Vec3, spp: u32) -> f32 {
    let mut scene = scene.clone();
    // A tiny orthographic view looking down at p.
    scene.camera = Some(top_down_camera(p, 1e-4));
    let s = settings(IntegratorKind::Ao, 1, 1, spp, 2);
    render(&scene, &s, &RenderOptions::default())
        .unwrap()
        .image
        .get(0, 0)
        .x
}

/// kA of an unoccluded plane is 1; in the edge between a floor and a wall
/// half of the cosine-weighted hemisphere is blocked (kA = 1/2), and in a
/// corner of three perpendicular planes three quarters are (kA = 1/4).
#[test]
fn ambient_occlusion_closed_forms() {
    let mut scene = Scene::default();
    let m = lambert(&mut scene, 0.5);
    // Floor y = 0 over x, z ∈ [0, 10].
    add(
        &mut scene,
        quad(
            Vec3::ZERO,
            Vec3::new(0.0, 0.0, 10.0),
            Vec3::new(10.0, 0.0, 0.0),
            m,
        ),
    );
    let plane = ao_at(&scene, Vec3::new(5.0, 0.0, 5.0), 256);
    assert_eq!(plane, 1.0);
    // Wall x = 0.
    add(
        &mut scene,
        quad(
            Vec3::ZERO,
            Vec3::new(0.0, 10.0, 0.0),
            Vec3::new(0.0, 0.0, 10.0),
            m,
        ),
    );
    let edge = ao_at(&scene, Vec3::new(1e-3, 0.0, 5.0), 4096);
    assert!((edge - 0.5).abs() < 0.03, "edge {edge}");
    // Wall z = 0.
    add(
        &mut scene,
        quad(
            Vec3::ZERO,
            Vec3::new(10.0, 0.0, 0.0),
            Vec3::new(0.0, 10.0, 0.0),
            m,
        ),
    );
    let corner = ao_at(&scene, Vec3::new(1e-3, 0.0, 1e-3), 4096);
    assert!((corner - 0.25).abs() < 0.03, "corner {corner}");
    // A short AO distance sees no occluder far away.
    let mut s2 = scene.clone();
    s2.camera = Some(top_down_camera(Vec3::new(5.0, 0.0, 5.0), 1e-4));
    let mut st = settings(IntegratorKind::Ao, 1, 1, 64, 2);
    st.ao_distance = 1.0;
    assert_eq!(
        render(&s2, &st, &RenderOptions::default())
            .unwrap()
            .image
            .get(0, 0)
            .x,
        1.0
    );
}

/// Emitters are seen directly with their radiance, front side only.
#[test]
fn emitter_front_side_only() {
    let mut scene = Scene::default();
    let m = scene.add_material(Material::emitter("light", Rgb::new(1.0, 2.0, 3.0)));
    // Facing up (+y): e1 × e2 = z × x = +y.
    add(
        &mut scene,
        quad(
            Vec3::new(-1.0, 0.0, -1.0),
            Vec3::new(0.0, 0.0, 2.0),
            Vec3::new(2.0, 0.0, 0.0),
            m,
        ),
    );
    scene.camera = Some(top_down_camera(Vec3::ZERO, 1.0));
    let s = settings(IntegratorKind::Path, 4, 4, 4, 8);
    assert_eq!(
        render(&scene, &s, &RenderOptions::default())
            .unwrap()
            .image
            .get(1, 1),
        Rgb::new(1.0, 2.0, 3.0)
    );
    scene.camera = Some(Camera::look_at(
        Vec3::new(0.0, -10.0, 0.0),
        Vec3::ZERO,
        Vec3::Z,
        Projection::Orthographic { height: 1.0 },
    ));
    assert_eq!(
        render(&scene, &s, &RenderOptions::default())
            .unwrap()
            .image
            .get(1, 1),
        Rgb::ZERO
    );
}
