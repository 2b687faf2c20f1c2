//! Analytic area lights and the environment in the integrators, against
//! closed forms. Every case is a Lambertian plane (albedo ρ, normal +y) lit
//! by one emitter and seen at one point through a tiny orthographic view, so
//! the expected radiance is `Lo = ρ/π · E` with E the irradiance at that
//! point. A lone upward-facing plane sees nothing but the emitter and the
//! environment, so direct lighting is the whole answer and `path` must give
//! the same value as `direct`: this checks the MIS weights of light sampling
//! against BSDF rays that hit the lights (biased weights would not sum to 1).

mod common;

use common::*;
use glam::{Vec2, Vec3};
use penumbra_scene::{Camera, IntegratorKind, Projection, RenderSettings, Scene};
use penumbra_shading::Rgb;
use penumbra_shading::light::{EnvironmentMap, Shape};
use penumbra_trace::accel::BuildQuality;
use penumbra_trace::geometry::SceneGeometry;
use penumbra_trace::ray::Ray;
use penumbra_trace::{RenderOptions, render};
use std::f32::consts::PI;
use std::sync::Arc;

const RHO: f32 = 0.6;

fn plane_scene() -> Scene {
    let mut scene = Scene::default();
    let m = lambert(&mut scene, RHO);
    add(
        &mut scene,
        quad(
            Vec3::new(-50.0, 0.0, -50.0),
            Vec3::new(0.0, 0.0, 100.0),
            Vec3::new(100.0, 0.0, 0.0),
            m,
        ),
    );
    scene
}

fn add_light(scene: &mut Scene, shape: Shape, le: f32) {
    scene.area_lights.push(area_light("l", shape, le));
}

/// Radiance at `p` on the plane seen from direction `view` (towards the
/// camera), one pixel.
fn radiance_at(scene: &Scene, p: Vec3, view: Vec3, kind: IntegratorKind, spp: u32) -> f32 {
    let mut scene = scene.clone();
    scene.camera = Some(Camera::look_at(
        p + view.normalize() * 5.0,
        p,
        if view.cross(Vec3::Z).length() > 0.1 {
            Vec3::Z
        } else {
            Vec3::X
        },
        Projection::Orthographic { height: 1e-4 },
    ));
    let settings = RenderSettings {
        width: 1,
        height: 1,
        spp,
        max_depth: if kind == IntegratorKind::Path { 6 } else { 2 },
        integrator: kind,
        seed: 9,
        ao_distance: f32::INFINITY,
    };
    render(&scene, &settings, &RenderOptions::default())
        .unwrap()
        .image
        .get(0, 0)
        .x
}

const KINDS: [IntegratorKind; 3] = [
    IntegratorKind::Local,
    IntegratorKind::Direct,
    IntegratorKind::Path,
];

fn check(what: &str, got: f32, expected: f32, tol: f32) {
    eprintln!(
        "{what}: {got} vs {expected} ({:+.3}%)",
        100.0 * (got / expected - 1.0)
    );
    assert!(
        (got / expected - 1.0).abs() < tol,
        "{what}: {got} vs {expected}"
    );
}

/// Sphere of radius r, centre at height d over the plane, fully above the
/// horizon of a point at horizontal offset x (D² = x² + d²):
/// `E = π Le (r/D)² cos θ`, cos θ = d/D.
#[test]
fn sphere_light_over_plane() {
    let (r, d, le) = (0.5f32, 1.5f32, 4.0f32);
    let mut scene = plane_scene();
    add_light(
        &mut scene,
        Shape::Sphere {
            center: Vec3::new(0.0, d, 0.0),
            radius: r,
        },
        le,
    );
    for x in [0.8f32, 2.0] {
        let dd = (x * x + d * d).sqrt();
        let e = PI * le * (r / dd).powi(2) * (d / dd);
        for kind in KINDS {
            let got = radiance_at(&scene, Vec3::new(x, 0.0, 0.0), Vec3::Y, kind, 8192);
            check(&format!("sphere x={x} {kind}"), got, RHO / PI * e, 0.01);
        }
    }
}

/// Two spheres of different radiance (so they are chosen with different
/// probabilities, by power) light the point between them: their
/// irradiances add, each `π Le (r/D)² cos θ`. Every estimator divides a
/// light's sample by the probability of having chosen it.
#[test]
fn two_sphere_lights_add_up() {
    let (r, d, x) = (0.4f32, 1.2f32, 1.5f32);
    let mut scene = plane_scene();
    for (side, le) in [(-1.0f32, 5.0f32), (1.0, 1.5)] {
        add_light(
            &mut scene,
            Shape::Sphere {
                center: Vec3::new(side * x, d, 0.0),
                radius: r,
            },
            le,
        );
    }
    let dd = (x * x + d * d).sqrt();
    let e = PI * (5.0 + 1.5) * (r / dd).powi(2) * (d / dd);
    for kind in KINDS {
        let got = radiance_at(&scene, Vec3::ZERO, Vec3::Y, kind, 8192);
        check(&format!("two spheres {kind}"), got, RHO / PI * e, 0.015);
    }
}

/// Disk of radius r facing down at height d, on its axis:
/// `E = π Le r² / (r² + d²)`; viewed obliquely past the disk.
#[test]
fn disk_light_over_plane() {
    let (r, d, le) = (1.0f32, 1.0f32, 3.0f32);
    let mut scene = plane_scene();
    add_light(
        &mut scene,
        Shape::Disk {
            center: Vec3::new(0.0, d, 0.0),
            normal: -Vec3::Y,
            radius: r,
        },
        le,
    );
    let e = PI * le * r * r / (r * r + d * d);
    for kind in KINDS {
        let got = radiance_at(&scene, Vec3::ZERO, Vec3::new(10.0, 3.0, 0.0), kind, 8192);
        check(&format!("disk {kind}"), got, RHO / PI * e, 0.01);
    }
    // From above the one-sided disk shows its dark back and hides the plane.
    let got = radiance_at(&scene, Vec3::ZERO, Vec3::Y, IntegratorKind::Path, 16);
    assert_eq!(got, 0.0);
}

/// Square quad light of side 2a facing down at height d, centred above the
/// point: `E = 4 Le · [a/√(a²+d²)] · atan(a/√(a²+d²))` (the classic
/// form factor of a rectangle to a point below its corner, four times).
#[test]
fn quad_light_over_plane() {
    let (a, d, le) = (0.5f32, 1.0f32, 5.0f32);
    let mut scene = plane_scene();
    // edge1 × edge2 = x × z = −y: facing down.
    add_light(
        &mut scene,
        Shape::Quad {
            corner: Vec3::new(-a, d, -a),
            edge1: Vec3::new(2.0 * a, 0.0, 0.0),
            edge2: Vec3::new(0.0, 0.0, 2.0 * a),
        },
        le,
    );
    // Corner form factor for a×a at distance d (Howell, case B-3):
    // F = 1/(2π)[A/√(1+A²) atan(B/√(1+A²)) + B/√(1+B²) atan(A/√(1+B²))],
    // A = B = a/d; E = π Le F per quarter.
    let t = a / d;
    let s = (1.0 + t * t).sqrt();
    let f = (2.0 * t / s * (t / s).atan()) / (2.0 * PI);
    let e = 4.0 * PI * le * f;
    for kind in KINDS {
        let got = radiance_at(&scene, Vec3::ZERO, Vec3::new(10.0, 3.0, 1.0), kind, 8192);
        check(&format!("quad {kind}"), got, RHO / PI * e, 0.01);
    }
}

/// Constant environment L over a lone plane: the upper hemisphere sees only
/// the environment, `E = π L`, so `Lo = ρ L` (a white furnace in the
/// half-space: with ρ = 1 the plane would vanish into the sky).
#[test]
fn constant_environment_furnace() {
    let l = 0.8f32;
    let mut scene = plane_scene();
    scene.background = Rgb::splat(l);
    for kind in KINDS {
        let got = radiance_at(&scene, Vec3::new(1.0, 0.0, 2.0), Vec3::Y, kind, 4096);
        check(&format!("constant env {kind}"), got, RHO * l, 0.01);
    }
    // A miss (looking horizontally above the plane) sees the environment.
    for kind in KINDS {
        let got = radiance_at(&scene, Vec3::new(0.0, 1.0, 0.0), Vec3::X, kind, 4);
        assert_eq!(got, l, "{kind}");
    }
}

/// Environment map with a bright spot in the upper hemisphere: E is the
/// map integrated against cos⁺ numerically texel by texel.
#[test]
fn environment_map_over_plane() {
    let (w, h) = (32usize, 16usize);
    let mut texels = vec![Rgb::splat(0.1); w * h];
    for y in 3..5 {
        for x in 20..23 {
            texels[y * w + x] = Rgb::splat(200.0);
        }
    }
    let map = EnvironmentMap::new(w, h, texels.clone(), Rgb::splat(0.5), 0.4);
    // E = Σ L_t ∫_texel cos⁺θ dω, dω = 2π² sin θ du dv; cos θ = y of the
    // direction (the plane's normal is +y).
    let sub = 16;
    let mut e = 0.0f64;
    for ty in 0..h {
        for tx in 0..w {
            let lt = 0.5 * texels[ty * w + tx].x as f64;
            for j in 0..sub {
                for i in 0..sub {
                    let uv = Vec2::new(
                        (tx as f32 + (i as f32 + 0.5) / sub as f32) / w as f32,
                        (ty as f32 + (j as f32 + 0.5) / sub as f32) / h as f32,
                    );
                    let dir = map.uv_to_direction(uv);
                    let dw = 2.0 * PI * PI * (PI * uv.y).sin() / (w * h * sub * sub) as f32;
                    e += lt * (dir.y.max(0.0) * dw) as f64;
                }
            }
        }
    }
    let mut scene = plane_scene();
    scene.environment_map = Some(Arc::new(map));
    for kind in KINDS {
        let got = radiance_at(&scene, Vec3::new(-1.0, 0.0, 0.5), Vec3::Y, kind, 8192);
        check(&format!("env map {kind}"), got, RHO / PI * e as f32, 0.01);
    }
}

/// Area lights occlude shadow rays and are found by camera rays.
#[test]
fn area_lights_occlude_and_are_hit() {
    let mut scene = plane_scene();
    add_light(
        &mut scene,
        Shape::Sphere {
            center: Vec3::new(0.0, 2.0, 0.0),
            radius: 0.5,
        },
        1.0,
    );
    let g = SceneGeometry::build(&scene, BuildQuality::Fast).unwrap();
    let up = Ray::new(Vec3::new(0.0, 0.1, 0.0), Vec3::Y);
    assert!(g.occluded(&up));
    assert!(!g.occluded(&Ray::segment(Vec3::new(0.0, 0.1, 0.0), Vec3::Y, 1.0)));
    assert!(!g.occluded(&Ray::new(Vec3::new(2.0, 0.1, 0.0), Vec3::Y)));
    let hit = g.intersect(&scene, &up).unwrap();
    assert_eq!(hit.light, Some(0));
    assert!((hit.t - 1.4).abs() < 1e-5 && (hit.ng + Vec3::Y).length() < 1e-5);
    // The plane is still found below.
    // −Vec3::Y has −0.0 components (once missed by the BVH slab test).
    let down = g
        .intersect(&scene, &Ray::new(Vec3::new(3.0, 1.0, 0.0), -Vec3::Y))
        .unwrap();
    assert_eq!(down.light, None);
}
