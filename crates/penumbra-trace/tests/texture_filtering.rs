//! Texture filtering by ray cones in whole renders: a checkerboard of
//! one-texel checks, much finer than a pixel, renders as its mean in every
//! pixel at one sample (seen head-on and through a mirror, whose delta
//! bounce must carry the camera's cone on), while a texture magnified
//! on screen keeps its level-0 detail.

mod common;

use common::{add, quad, settings};
use glam::{Affine2, Vec3};
use penumbra_scene::texture::Wrap;
use penumbra_scene::{
    Camera, IntegratorKind, Material, Projection, Scene, SceneLight, Texels, Texture,
};
use penumbra_shading::Rgb;
use penumbra_shading::bsdf::{Bsdf, Mirror};
use penumbra_shading::light::{DirectionalLight, Light};
use penumbra_trace::{RenderOptions, render};

/// An `n`×`n` checkerboard of `check`×`check` squares of texels 1 and 0
/// (linear, so its mean is exactly 0.5, and so is every texel of the
/// levels whose texels span two checks or more: levels from
/// log2(2 · check) on).
fn checkerboard(n: u32, check: u32) -> Texture {
    Texture {
        name: "checks".into(),
        width: n,
        height: n,
        texels: Texels::Linear(
            (0..n * n)
                .map(
                    |i| Rgb::splat((i % n / check + i / n / check).is_multiple_of(2) as u32 as f32),
                )
                .collect(),
        ),
        wrap: [Wrap::ClampToEdge; 2],
        uv_transform: Affine2::IDENTITY,
        uv_set: 0,
    }
}

/// A white Lambertian quad over [−1, 1]² at z = 0 facing +z, textured with
/// `texture` (UVs 0..1 across it), lit by a directional light travelling
/// along `travel` whose irradiance on the quad is π: its radiance is the
/// texture's value.
fn textured_floor(texture: Texture, travel: Vec3) -> Scene {
    let mut scene = Scene::default();
    scene.textures.push(texture);
    let m = scene.add_material(Material {
        albedo_texture: Some(0),
        ..Material::lambert("floor", Rgb::ONE)
    });
    add(
        &mut scene,
        quad(Vec3::new(-1.0, -1.0, 0.0), 2.0 * Vec3::X, 2.0 * Vec3::Y, m),
    );
    let travel = travel.normalize();
    scene.lights.push(SceneLight {
        name: "sun".into(),
        light: Light::Directional(DirectionalLight {
            direction: travel,
            irradiance: Rgb::splat(std::f32::consts::PI / -travel.z),
        }),
    });
    scene
}

/// Every pixel's red channel.
fn pixels(scene: &Scene, integrator: IntegratorKind, n: u32, max_depth: u32) -> Vec<f32> {
    let out = render(
        scene,
        &settings(integrator, n, n, 1, max_depth),
        &RenderOptions::default(),
    )
    .unwrap();
    out.image.pixels.iter().map(|p| p.x).collect()
}

/// An orthographic camera 5 above the floor looking down, 1.5 wide.
fn from_above() -> Camera {
    Camera::look_at(
        Vec3::new(0.0, 0.0, 5.0),
        Vec3::ZERO,
        Vec3::Y,
        Projection::Orthographic { height: 1.5 },
    )
}

/// The largest |pixel − v|.
fn largest_deviation(pixels: &[f32], v: f32) -> f32 {
    pixels.iter().map(|p| (p - v).abs()).fold(0.0, f32::max)
}

/// Seen from above by an orthographic camera 1.5 wide over 16 pixels, a
/// pixel spans 12 texels of a 256² checkerboard: λ ≈ 3.6, every lookup
/// reads levels 3 and 4, all 0.5. Unfiltered, one sample per pixel would
/// read single checks (values 0 to 1).
#[test]
fn a_minified_checkerboard_reads_its_mean() {
    let mut scene = textured_floor(checkerboard(256, 1), -Vec3::Z);
    scene.camera = Some(from_above());
    for integrator in [IntegratorKind::Local, IntegratorKind::Path] {
        let px = pixels(&scene, integrator, 16, 2);
        let worst = largest_deviation(&px, 0.5);
        assert!(worst < 1e-4, "{integrator:?}: a pixel off 0.5 by {worst}");
    }
}

/// The same checkerboard seen only in a 45° mirror, 5 units from a narrow
/// perspective camera (6°, 16 pixels) and 1 above the floor: the camera's
/// cone is about 5 texels wide where it meets the floor (λ ≈ 2.3) only if
/// the mirror passes it on; restarted at the mirror it would be under one
/// texel wide (λ < 0).
#[test]
fn a_mirror_passes_the_cone_on() {
    // The light travels along the mirror's plane: it casts no shadow.
    let mut scene = textured_floor(checkerboard(256, 1), Vec3::new(1.0, 0.0, -1.0));
    let mirror = scene.add_material(Material {
        bsdf: Bsdf::Mirror(Mirror::new(Rgb::ONE)),
        ..Material::lambert("mirror", Rgb::ONE)
    });
    // Centred at (0, 0, 1), normal (−1, 0, −1)/√2: towards the camera and down.
    let s = std::f32::consts::FRAC_1_SQRT_2;
    add(
        &mut scene,
        quad(
            Vec3::new(-0.5 * s, -0.5, 1.0 + 0.5 * s),
            Vec3::Y,
            Vec3::new(s, 0.0, -s),
            mirror,
        ),
    );
    scene.camera = Some(Camera::look_at(
        Vec3::new(-5.0, 0.0, 1.0),
        Vec3::new(0.0, 0.0, 1.0),
        Vec3::Z,
        Projection::Perspective {
            fov_y: 6f32.to_radians(),
        },
    ));
    for integrator in [IntegratorKind::Whitted, IntegratorKind::Path] {
        let px = pixels(&scene, integrator, 16, 3);
        let worst = largest_deviation(&px, 0.5);
        assert!(worst < 1e-3, "{integrator:?}: a pixel off 0.5 by {worst}");
    }
}

/// A 2×2 checkerboard stretched over the quad is magnified (a pixel spans
/// a tenth of a texel, λ < 0): the lookups read level 0, bilinearly
/// blended from black to white across the image, never its mean alone.
#[test]
fn a_magnified_texture_keeps_its_detail() {
    let mut scene = textured_floor(checkerboard(2, 1), -Vec3::Z);
    scene.camera = Some(from_above());
    let px = pixels(&scene, IntegratorKind::Local, 16, 2);
    let (lo, hi) = px
        .iter()
        .fold((f32::MAX, f32::MIN), |(lo, hi), &v| (lo.min(v), hi.max(v)));
    // Texel centres at u, v = 0.25 and 0.75 lie at x, y = ±0.5 on the
    // quad, inside the view (±0.75): pixels near them read almost 0 and 1.
    assert!(lo < 0.1 && hi > 0.9, "values from {lo} to {hi}");
}

/// A diffuse bounce widens the cone to the sample's share of the
/// hemisphere (at one sample per pixel, `2/√(π p)` ≥ 2 rad): light reaching
/// a white ceiling from a checkerboard floor 1 below reads the floor's
/// coarsest levels, 0.5, so the render equals, path for path, the one with
/// a plain floor of albedo 0.5 (the lookups draw no random numbers). Kept
/// at the camera's narrow spread, the lookups would read the checks.
#[test]
fn a_diffuse_bounce_reads_the_coarse_levels() {
    use penumbra_shading::light::PointLight;
    let render_with = |floor_texture: Option<Texture>| {
        let mut scene = Scene::default();
        let floor = match floor_texture {
            Some(t) => {
                scene.textures.push(t);
                scene.add_material(Material {
                    albedo_texture: Some(0),
                    ..Material::lambert("floor", Rgb::ONE)
                })
            }
            None => scene.add_material(Material::lambert("floor", Rgb::splat(0.5))),
        };
        let ceiling = scene.add_material(Material::lambert("ceiling", Rgb::ONE));
        add(
            &mut scene,
            quad(
                Vec3::new(-1.0, -1.0, 0.0),
                2.0 * Vec3::X,
                2.0 * Vec3::Y,
                floor,
            ),
        );
        // Facing down (2y × 2x = −4z).
        add(
            &mut scene,
            quad(
                Vec3::new(-1.0, -1.0, 1.0),
                2.0 * Vec3::Y,
                2.0 * Vec3::X,
                ceiling,
            ),
        );
        scene.lights.push(SceneLight {
            name: "lamp".into(),
            light: Light::Point(PointLight {
                position: Vec3::new(0.3, 0.2, 0.6),
                intensity: Rgb::ONE,
                range: f32::INFINITY,
            }),
        });
        // Below the ceiling, looking up at it only.
        scene.camera = Some(Camera::look_at(
            Vec3::new(0.0, 0.0, 0.2),
            Vec3::new(0.0, 0.0, 1.0),
            Vec3::Y,
            Projection::Perspective {
                fov_y: 30f32.to_radians(),
            },
        ));
        pixels(&scene, IntegratorKind::Path, 16, 3)
    };
    // Checks of 32 texels: levels 0 to 5 show them, 6 on are all 0.5. At
    // the floor the widened cone is at least 2 wide (λ ≥ 8); the camera's
    // alone would be about 0.06 wide (λ ≈ 3 to 4 away from grazing).
    let textured = render_with(Some(checkerboard(256, 32)));
    let plain = render_with(None);
    let mean = plain.iter().sum::<f32>() / plain.len() as f32;
    assert!(mean > 0.0);
    for (i, (t, p)) in textured.iter().zip(&plain).enumerate() {
        assert!((t - p).abs() <= 1e-5 * p.max(mean), "pixel {i}: {t} vs {p}");
    }
}
