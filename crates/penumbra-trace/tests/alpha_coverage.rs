//! Coverage (glTF alphaMode) in the tracer: MASK cuts where α < cutoff,
//! BLEND is met with probability α, and a render through a BLEND surface
//! averages to `α · C_surface + (1 − α) · C_behind`.

mod common;

use common::{add, quad, settings};
use glam::{Vec2, Vec3};
use penumbra_scene::texture::Wrap;
use penumbra_scene::{
    AlphaCoverage, AlphaMode, Camera, IntegratorKind, Material, Projection, Scene, Texture,
};
use penumbra_shading::Rgb;
use penumbra_trace::accel::BuildQuality;
use penumbra_trace::geometry::SceneGeometry;
use penumbra_trace::ray::Ray;
use penumbra_trace::{RenderOptions, render};

/// A black quad over [−1, 1]² in the plane z = 0 (u along x, v along y)
/// with coverage `alpha`.
fn covered_quad(scene: &mut Scene, alpha: AlphaCoverage) {
    let m = scene.add_material(Material {
        alpha: Some(alpha),
        ..Material::lambert("covered", Rgb::ZERO)
    });
    add(
        scene,
        quad(Vec3::new(-1.0, -1.0, 0.0), 2.0 * Vec3::X, 2.0 * Vec3::Y, m),
    );
}

/// Rays straight down −z through (x, y), x and y in [−0.9, 0.9] on a
/// 100 × 100 grid jittered by a fixed hash.
fn rays_down() -> impl Iterator<Item = Ray> {
    (0..100 * 100).map(|i| {
        let j = penumbra_shading::sampling::hash_u32(i) as f32 / u32::MAX as f32;
        let (x, y) = ((i % 100) as f32 + j, (i / 100) as f32 + 0.5);
        let p = Vec2::new(x, y) / 100.0 * 1.8 - 0.9;
        Ray::new(p.extend(1.0), -Vec3::Z)
    })
}

#[test]
fn blend_is_met_with_probability_alpha() {
    for alpha in [0.0, 0.3, 0.75] {
        let mut scene = Scene::default();
        covered_quad(
            &mut scene,
            AlphaCoverage {
                mode: AlphaMode::Blend,
                factor: alpha,
                texture: None,
            },
        );
        let geometry = SceneGeometry::build(&scene, BuildQuality::Medium).unwrap();
        let (mut hits, mut n) = (0, 0);
        for ray in rays_down() {
            let hit = geometry.intersect(&scene, &ray).is_some();
            // A ray's shadow query and closest-hit query agree.
            assert_eq!(hit, geometry.occluded(&ray), "{ray:?}");
            hits += hit as u32;
            n += 1;
        }
        let p = hits as f64 / n as f64;
        let sigma = (alpha as f64 * (1.0 - alpha as f64) / n as f64).sqrt();
        assert!(
            (p - alpha as f64).abs() <= 4.0 * sigma + 1e-9,
            "α = {alpha}: met {p:.4} of the time (σ = {sigma:.4})"
        );
    }
}

/// A scene holding one texture: α = 0.2 on the left half, 0.8 on the
/// right (two texels, clamped: bilinear lookups blend them only near
/// u = ½).
fn scene_with_alpha_halves() -> Scene {
    let mut scene = Scene::default();
    scene.textures.push(Texture {
        name: "alpha".into(),
        width: 2,
        height: 1,
        texels: vec![Rgb::splat(0.2), Rgb::splat(0.8)].into(),
        wrap: [Wrap::ClampToEdge; 2],
        uv_transform: glam::Affine2::IDENTITY,
        uv_set: 0,
    });
    scene
}

#[test]
fn mask_cuts_where_alpha_is_below_the_cutoff() {
    let scene = scene_with_alpha_halves();
    for (cutoff, factor, left, right) in [
        (0.5, 1.0, false, true),
        (0.1, 1.0, true, true),
        (0.9, 1.0, false, false),
        // The factor multiplies the texture: 0.5 · 0.8 < 0.5.
        (0.5, 0.5, false, false),
    ] {
        let mut s = scene.clone();
        covered_quad(
            &mut s,
            AlphaCoverage {
                mode: AlphaMode::Mask { cutoff },
                factor,
                texture: Some(0),
            },
        );
        let geometry = SceneGeometry::build(&s, BuildQuality::Medium).unwrap();
        for ray in rays_down() {
            // u = (x + 1) / 2: left of x = −0.2 reads 0.2, right of 0.2 reads 0.8.
            let x = ray.origin.x;
            let expected = if x < -0.2 {
                left
            } else if x > 0.2 {
                right
            } else {
                continue;
            };
            let hit = geometry.intersect(&s, &ray);
            assert_eq!(hit.is_some(), expected, "cutoff {cutoff}, x = {x}");
            assert_eq!(
                geometry.occluded(&ray),
                expected,
                "cutoff {cutoff}, x = {x}"
            );
        }
    }
}

/// The coverage is read at the hit's UV, interpolated from all three
/// corners: the quad's UVs mirrored (u = (1 − x)/2), so no corner of
/// either triangle has UV (0, 0), and the opaque half is now x < 0.
#[test]
fn mask_reads_the_uv_interpolated_at_the_hit() {
    let mut scene = scene_with_alpha_halves();
    covered_quad(
        &mut scene,
        AlphaCoverage {
            mode: AlphaMode::Mask { cutoff: 0.5 },
            factor: 1.0,
            texture: Some(0),
        },
    );
    scene.meshes[0].uv0 = Some(vec![
        Vec2::new(1.0, 0.0),
        Vec2::new(0.0, 0.0),
        Vec2::new(0.0, 1.0),
        Vec2::new(1.0, 1.0),
    ]);
    let geometry = SceneGeometry::build(&scene, BuildQuality::Medium).unwrap();
    let mut checked = 0;
    for ray in rays_down() {
        let x = ray.origin.x;
        if x.abs() < 0.2 {
            continue;
        }
        let expected = x < 0.0;
        assert_eq!(
            geometry.intersect(&scene, &ray).is_some(),
            expected,
            "x = {x}"
        );
        assert_eq!(geometry.occluded(&ray), expected, "x = {x}");
        checked += 1;
    }
    assert!(checked > 7000);
}

/// An emitter of radiance 1 behind a black BLEND quad of α = 0.25, seen
/// head-on: every pixel averages (1 − α) · 1 = 0.75.
#[test]
fn a_render_through_blend_averages_alpha_of_the_surface() {
    let mut scene = Scene::default();
    let alpha = 0.25f64;
    covered_quad(
        &mut scene,
        AlphaCoverage {
            mode: AlphaMode::Blend,
            factor: alpha as f32,
            texture: None,
        },
    );
    let light = scene.add_material(Material::emitter("light", Rgb::ONE));
    add(
        &mut scene,
        quad(
            Vec3::new(-2.0, -2.0, -1.0),
            4.0 * Vec3::X,
            4.0 * Vec3::Y,
            light,
        ),
    );
    scene.camera = Some(Camera::look_at(
        Vec3::new(0.0, 0.0, 5.0),
        Vec3::ZERO,
        Vec3::Y,
        Projection::Orthographic { height: 1.5 },
    ));
    let s = settings(IntegratorKind::Path, 16, 16, 64, 8);
    let out = render(&scene, &s, &RenderOptions::default()).unwrap();
    let mean: f64 = out.image.pixels.iter().map(|p| p.x as f64).sum::<f64>()
        / (out.image.width * out.image.height) as f64;
    let n = (16 * 16 * 64) as f64;
    let sigma = (alpha * (1.0 - alpha) / n).sqrt();
    assert!(
        (mean - (1.0 - alpha)).abs() < 4.0 * sigma,
        "mean {mean:.4}, expected {} (σ = {sigma:.4})",
        1.0 - alpha
    );
}
