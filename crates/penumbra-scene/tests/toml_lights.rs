//! TOML area lights and environments: values in every unit, and errors that
//! name the file and the key path.

use glam::Vec3;
use penumbra_scene::load::{LoadOptions, load_toml_str};
use penumbra_scene::{Location, Scene, SceneError};
use penumbra_shading::light::{Environment, Shape};
use std::f32::consts::PI;
use std::path::PathBuf;

const FLOOR: &str = "\n[[objects]]\nshape = \"quad\"\nsize = [4, 4]\n";

/// A virtual scene file in the corpus folder, so `env/sky.hdr` resolves.
fn file() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/corpus/toml/lights-test.toml")
}

fn load(text: &str) -> Scene {
    let t = format!("{text}{FLOOR}");
    load_toml_str(&t, &file(), &LoadOptions::default()).unwrap_or_else(|e| panic!("{e}\n{t}"))
}

/// The error of a scene that must fail: its location must be `at` and its
/// message must contain every needle.
fn fails(text: &str, at: &str, needles: &[&str]) {
    let t = format!("{text}{FLOOR}");
    let err = load_toml_str(&t, &file(), &LoadOptions::default())
        .err()
        .unwrap_or_else(|| panic!("loaded but must fail:\n{t}"));
    let msg = err.to_string();
    let SceneError::Invalid { location, .. } = &err else {
        panic!("{err:?}");
    };
    assert_eq!(location, &Location::Path(at.into()), "{msg}");
    assert!(msg.contains("lights-test.toml"), "{msg}");
    for n in needles {
        assert!(msg.contains(n), "lacks {n:?}: {msg}");
    }
}

#[test]
fn area_lights_in_every_unit() {
    let s = load(
        r#"
[[lights]]
name = "ball"
type = "sphere"
center = [0, 2, 0]
radius = 0.5
radiance = [2, 3, 4]

[[lights]]
type = "disk"
center = [1, 2, 0]
normal = [0, -2, 0]
radius = 0.5
power = 10

[[lights]]
type = "quad"
corner = [0, 3, 0]
edge1 = [2, 0, 0]
edge2 = [0, 0, 1]
power_lm = 683
two_sided = true
color = [1, 0.5, 0.25]

[[lights]]
type = "sphere"
center = [0, 0, 0]
radius = 2
luminance_nits = 1366
"#,
    );
    assert!(s.lights.is_empty());
    assert_eq!(s.area_lights.len(), 4);
    let a = &s.area_lights;
    assert_eq!(a[0].name, "ball");
    assert_eq!(a[1].name, "lights[1]");
    assert_eq!(a[0].light.radiance, Vec3::new(2.0, 3.0, 4.0));
    assert_eq!(
        a[0].light.shape,
        Shape::Sphere {
            center: Vec3::new(0.0, 2.0, 0.0),
            radius: 0.5
        }
    );
    // Disk: Le = Φ / (π · π r²), normal normalised.
    let le = 10.0 / (PI * PI * 0.25);
    assert!((a[1].light.radiance.x - le).abs() < 1e-5 * le);
    let Shape::Disk { normal, .. } = a[1].light.shape else {
        panic!()
    };
    assert_eq!(normal, -Vec3::Y);
    // Quad: 683 lm = 1 W, two-sided area 2 → Le = 1 / (π · 2 · 2) × colour.
    let le = 1.0 / (PI * 4.0);
    assert!(a[2].light.two_sided);
    assert!(
        (a[2].light.radiance - Vec3::new(1.0, 0.5, 0.25) * le)
            .abs()
            .max_element()
            < 1e-6
    );
    assert!((a[2].light.power().x - 1.0).abs() < 1e-5);
    // 1366 nits = 2 W/(sr·m²).
    assert!((a[3].light.radiance.x - 2.0).abs() < 1e-5);
}

#[test]
fn environments() {
    let s = load("[environment]\ntype = \"constant\"\nradiance = [0.1, 0.2, 0.3]\n");
    assert_eq!(s.background, Vec3::new(0.1, 0.2, 0.3));
    assert_eq!(s.environment(), Environment::Constant(s.background));
    let s = load("[environment]\ntype = \"constant\"\nluminance_nits = 683\ncolor = 0.5\n");
    assert!((s.background - Vec3::splat(0.5)).abs().max_element() < 1e-6);
    let s =
        load("[environment]\ntype = \"map\"\nfile = \"env/sky.hdr\"\nscale = 2\nrotate_deg = 90\n");
    let map = s.environment_map.as_ref().expect("map");
    assert_eq!((map.width(), map.height()), (16, 8));
    // The sun texels (11..13, 2) of the file are (40, 36, 30), scaled by 2;
    // with the map turned 90° the texel centre u = 11.5/16 lies 90° further
    // counter-clockwise about +y.
    let unrotated = |u: f32, v: f32| {
        let (phi, theta) = (2.0 * PI * (u - 0.5), PI * v);
        Vec3::new(
            theta.sin() * phi.sin(),
            theta.cos(),
            -theta.sin() * phi.cos(),
        )
    };
    let d = glam::Quat::from_rotation_y(PI / 2.0) * unrotated(11.5 / 16.0, 2.5 / 8.0);
    let l = map.eval(d);
    assert!(
        (l - Vec3::new(80.0, 72.0, 60.0)).abs().max_element() < 0.5,
        "{l}"
    );
    // Most of the map's power is in the sun: sampling goes there.
    let sample = map.sample_li([0.5, 0.5]).unwrap();
    assert!((map.eval(sample.wi).x - 80.0).abs() < 0.5);
}

#[test]
fn area_light_errors_name_the_key() {
    let sphere = "[[lights]]\ntype = \"sphere\"\ncenter = [0, 1, 0]\n";
    fails(
        &format!("{sphere}radius = -1\nradiance = 1\n"),
        "lights[0].radius",
        &["radius must be finite and > 0", "-1"],
    );
    fails(
        &format!("{sphere}radiance = 1\n"),
        "lights[0]",
        &["needs radius"],
    );
    fails(
        &format!("{sphere}radius = 1\n"),
        "lights[0]",
        &["exactly one of: radiance, luminance_nits, power, power_lm"],
    );
    fails(
        &format!("{sphere}radius = 1\nradiance = 1\npower = 3\n"),
        "lights[0].power",
        &["give only one of"],
    );
    fails(
        &format!("{sphere}radius = 1\nradiance = [1, -2, 0]\n"),
        "lights[0].radiance",
        &[">= 0"],
    );
    fails(
        &format!("{sphere}radius = 1\nradiance = 1\nnormal = [0, 1, 0]\n"),
        "lights[0].normal",
        &["does not apply to a sphere light", "center, radius"],
    );
    fails(
        "[[lights]]\ntype = \"quad\"\ncorner = [0, 1, 0]\nedge1 = [1, 0, 0]\nedge2 = [2, 0, 0]\nradiance = 1\n",
        "lights[0].edge2",
        &["parallel or zero", "no area"],
    );
    fails(
        "[[lights]]\ntype = \"disk\"\ncenter = [0, 1, 0]\nnormal = [0, 0, 0]\nradius = 1\npower = 1\n",
        "lights[0].normal",
        &[],
    );
    fails(
        "[[lights]]\ntype = \"cylinder\"\n",
        "lights[0].type",
        &["sphere, disk, quad"],
    );
}

#[test]
fn environment_errors_name_the_key_and_file() {
    fails(
        "[environment]\ntype = \"map\"\nfile = \"env/missing.hdr\"\n",
        "environment.file",
        &["env/missing.hdr"],
    );
    fails(
        "[environment]\ntype = \"map\"\nfile = \"env/not-an-image.hdr\"\n",
        "environment.file",
        &["cannot read environment map 'env/not-an-image.hdr'"],
    );
    fails(
        "[environment]\ntype = \"map\"\nfile = \"env/sky.hdr\"\nradiance = 1\n",
        "environment.radiance",
        &["does not apply to an environment map"],
    );
    fails(
        "[environment]\ntype = \"map\"\nfile = \"env/sky.hdr\"\nscale = -1\n",
        "environment.scale",
        &[">= 0"],
    );
    fails(
        "background = 1\n[environment]\ntype = \"constant\"\nradiance = 1\n",
        "environment",
        &["not both"],
    );
    fails(
        "[environment]\ntype = \"sky\"\n",
        "environment.type",
        &["constant, map"],
    );
    fails(
        "[environment]\nradiance = 1\n",
        "environment",
        &["needs a type"],
    );
}

#[test]
fn unknown_environment_key_is_a_syntax_error_naming_it() {
    let t = format!("[environment]\ntype = \"constant\"\nradiance = 1\nbrightness = 2\n{FLOOR}");
    let e = load_toml_str(&t, &file(), &LoadOptions::default()).unwrap_err();
    assert!(e.to_string().contains("brightness"), "{e}");
}

#[test]
fn point_and_spot_lights_take_a_range() {
    use penumbra_shading::light::Light;
    let s = load(
        "[[lights]]\ntype = \"point\"\nposition = [0, 1, 0]\nintensity = 2\nrange = 3.5\n\
         [[lights]]\ntype = \"spot\"\nposition = [0, 2, 0]\ndirection = [0, -1, 0]\nintensity = 1\nrange = 7\n\
         [[lights]]\ntype = \"point\"\nposition = [0, 1, 0]\nintensity = 2\n",
    );
    let ranges: Vec<f32> = s.lights.iter().map(|l| l.light.range()).collect();
    assert_eq!(ranges, [3.5, 7.0, f32::INFINITY]);
    assert!(matches!(s.lights[0].light, Light::Point(p) if p.range == 3.5));
    fails(
        "[[lights]]\ntype = \"point\"\nposition = [0, 1, 0]\nintensity = 2\nrange = 0\n",
        "lights[0].range",
        &["range must be finite and > 0", "0"],
    );
    fails(
        "[[lights]]\ntype = \"directional\"\ndirection = [0, -1, 0]\nirradiance = 2\nrange = 4\n",
        "lights[0].range",
        &["does not apply to a directional light"],
    );
}
