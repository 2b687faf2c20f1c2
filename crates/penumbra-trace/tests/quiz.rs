//! The lecture notes' quiz (SEEDS.md, "Numbers a correct implementation
//! reproduces") as pixel radiance of small TOML scenes, rendered end to end
//! (TOML loader → integrator → film). The library-level checks of the same
//! numbers live next to the models (optics.rs, lambert.rs, tests/phong.rs).
//!
//! The notes' frame has the normal along z; these scenes use y-up, with the
//! notes' (x, y, z) written as (x, z, y).

use penumbra_scene::{IntegratorKind, LoadOptions, load_scene};
use penumbra_shading::Rgb;
use penumbra_shading::bsdf::optics::fresnel_dielectric;
use penumbra_trace::{RenderOptions, render};

/// Renders a TOML scene (its own [render] settings, `integrator` overridden)
/// and returns every pixel.
fn render_toml(text: &str, integrator: IntegratorKind) -> Vec<Rgb> {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("quiz.toml");
    std::fs::write(&path, text).unwrap();
    let scene = load_scene(&path, &LoadOptions::default()).unwrap();
    let mut settings = scene.settings.clone();
    settings.integrator = integrator;
    let out = render(&scene, &settings, &RenderOptions::default()).unwrap();
    let (w, h) = (settings.width, settings.height);
    (0..h)
        .flat_map(|y| (0..w).map(move |x| (x, y)))
        .map(|(x, y)| out.image.get(x, y))
        .collect()
}

fn assert_all_near(pixels: &[Rgb], expected: f32, rel: f32, what: &str) {
    for p in pixels {
        for c in [p.x, p.y, p.z] {
            assert!(
                (c - expected).abs() <= rel * expected.abs().max(1e-6),
                "{what}: pixel {p}, expected {expected}"
            );
        }
    }
}

/// A plane y = 0 facing +y (the notes' n = (0,0,1)) under an orthographic
/// camera from `view` (the notes' v, y-up) and a directional light from the
/// notes' l = (0,3,4).
fn plane_scene(material: &str, irradiance: f32, view: [f32; 3]) -> String {
    format!(
        r#"
[camera]
type = "orthographic"
position = [{vx}, {vy}, {vz}]
look_at = [0, 0, 0]
up = [0, 1, 0]
height = 1

[render]
resolution = [4, 4]
spp = 4
max_depth = 4

[[materials]]
name = "m"
{material}

[[objects]]
shape = "quad"
corner = [-5, 0, 5]
edge1 = [10, 0, 0]
edge2 = [0, 0, -10]
material = "m"

[[lights]]
type = "directional"
direction = [0, -4, -3]
irradiance = {irradiance}
"#,
        vx = view[0] * 2.0,
        vy = view[1] * 2.0,
        vz = view[2] * 2.0,
    )
}

/// Quiz 2: L = Lin kd cos θ = 2.4 from any view. The notes' kd = 0.6 is
/// above 1/π (albedo 1.9), which the TOML format refuses as a reflectance,
/// so the scene keeps the product Lin·kd = 3: kd = 0.2, Lin = 15.
#[test]
fn quiz_2_lambert_is_2_4_from_any_view() {
    for view in [[0.0, 3.0, 4.0], [0.0, 4.0, 3.0], [2.0, 1.0, -1.0]] {
        let text = plane_scene("type = \"lambert\"\nkd = 0.2", 15.0, view);
        for kind in [
            IntegratorKind::Local,
            IntegratorKind::Whitted,
            IntegratorKind::Direct,
        ] {
            assert_all_near(
                &render_toml(&text, kind),
                2.4,
                1e-5,
                &format!("{kind} {view:?}"),
            );
        }
    }
}

/// Quiz 4: the notes' Phong–Blinn, ks = √2, γ = 3, Lin = 5, camera along the
/// notes' (0,4,3): L = 2.5 (cos δ = 0.7071, cos θ = 0.8).
#[test]
fn quiz_4_phong_blinn_is_2_5() {
    let text = plane_scene(
        "type = \"phong\"\nvariant = \"notes\"\nks = 1.41421356\nshininess = 3",
        5.0,
        [0.0, 3.0, 4.0],
    );
    for kind in [IntegratorKind::Local, IntegratorKind::Whitted] {
        assert_all_near(&render_toml(&text, kind), 2.5, 1e-4, &format!("{kind}"));
    }
}

/// A smooth dielectric interface y = 0 (front +y, the medium below) of index
/// `ior`, under an emitter of radiance 1 facing down at y = 5 (black
/// elsewhere), seen by an orthographic camera at `eye` looking at the origin.
fn interface_scene(ior: f32, eye: [f32; 3], view_height: f32, spp: u32) -> String {
    format!(
        r#"
[camera]
type = "orthographic"
position = [{x}, {y}, {z}]
look_at = [0, 0, 0]
up = [0, 0, -1]
height = {view_height}

[render]
resolution = [4, 4]
spp = {spp}
max_depth = 4

[[materials]]
name = "dielectric"
type = "dielectric"
ior = {ior}

[[objects]]
shape = "quad"
corner = [-5, 0, 5]
edge1 = [10, 0, 0]
edge2 = [0, 0, -10]
material = "dielectric"

[[lights]]
type = "quad"
corner = [-50, 5, -50]
edge1 = [100, 0, 0]
edge2 = [0, 0, 100]
radiance = 1
"#,
        x = eye[0],
        y = eye[1],
        z = eye[2],
    )
}

/// Quiz 1: a smooth dielectric of n = 1.4 seen at normal incidence reflects
/// F0 = 2.78 % of an emitter behind the camera (glass n = 1.5: 4 %).
#[test]
fn quiz_1_normal_incidence_reflectance() {
    for (ior, f0) in [(1.4f32, 0.027_78f32), (1.5, 0.04)] {
        let text = interface_scene(ior, [0.0, 2.0, 0.0], 1.0, 4);
        assert_all_near(
            &render_toml(&text, IntegratorKind::Whitted),
            f0,
            2e-3,
            &format!("n = {ior}"),
        );
    }
}

/// Quiz 3: seen from inside a medium of index 10, the surface to air
/// transmits below asin(1/10) = 5.74° and reflects totally above. The camera
/// looks up through the interface (y = 0, medium below) at an emitter of
/// radiance 1; the medium's reflection leads to the black background.
#[test]
fn quiz_3_total_internal_reflection_from_5_74_degrees() {
    for deg in [5.5f32, 5.7, 5.78, 6.0, 20.0] {
        let t = deg.to_radians();
        let text = interface_scene(10.0, [-t.sin(), -t.cos(), 0.0], 0.1, 1);
        let pixels = render_toml(&text, IntegratorKind::Whitted);
        if deg < 5.74 {
            // Light entering the dense medium: (1 − F) · (10/1)² · Le.
            let expected = (1.0 - fresnel_dielectric(-t.cos(), 10.0)) * 100.0;
            assert!(expected > 1.0);
            assert_all_near(&pixels, expected, 1e-3, &format!("{deg}°"));
        } else {
            assert_all_near(
                &pixels,
                0.0,
                0.0,
                &format!("{deg}°: total internal reflection"),
            );
        }
    }
}
