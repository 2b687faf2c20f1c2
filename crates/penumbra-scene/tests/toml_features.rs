//! Round trips of every TOML feature into the scene model: values, defaults
//! and unit conversions.

use glam::{Mat4, Vec3};
use penumbra_scene::load::{LoadOptions, load_scene, load_toml_str};
use penumbra_scene::primitives::{signed_volume, surface_area};
use penumbra_scene::{Camera, IntegratorKind, Projection, RenderSettings, Scene};
use penumbra_shading::light::Light;
use std::f32::consts::PI;
use std::path::{Path, PathBuf};

const SPHERE: &str = "\n[[objects]]\nshape = \"sphere\"\nradius = 1\n";

fn load(text: &str) -> Scene {
    load_toml_str(text, Path::new("test/scene.toml"), &LoadOptions::default())
        .unwrap_or_else(|e| panic!("{e}\n---\n{text}"))
}

fn close(a: Vec3, b: Vec3, tol: f32) -> bool {
    (a - b).abs().max_element() <= tol * b.abs().max_element().max(1.0)
}

fn corpus(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/corpus/toml")
        .join(name)
}

#[test]
fn defaults_of_a_minimal_scene() {
    let s = load(SPHERE);
    assert_eq!(s.settings, RenderSettings::default());
    assert!(s.camera.is_none());
    assert_eq!(s.background, Vec3::ZERO);
    assert!(s.lights.is_empty());
    // The object without a material gets the default grey.
    assert_eq!(s.materials.len(), 1);
    assert_eq!(s.materials[0].name, "default");
    assert_eq!(s.materials[0].bsdf.albedo(), Vec3::splat(0.8));
    assert_eq!(s.instances.len(), 1);
    assert_eq!(s.instances[0].transform, Mat4::IDENTITY);
    assert!(s.warnings.is_empty());
}

#[test]
fn perspective_camera() {
    let s = load(&format!(
        "[camera]\nposition = [1, 2, 3]\nlook_at = [1, 2, -4]\nup = [0, 2, 0]\nfov_y_deg = 50\n{SPHERE}"
    ));
    let c = s.camera.unwrap();
    let expected = Camera::look_at(
        Vec3::new(1.0, 2.0, 3.0),
        Vec3::new(1.0, 2.0, -4.0),
        Vec3::Y,
        Projection::Perspective {
            fov_y: 50f32.to_radians(),
        },
    );
    assert_eq!(c, expected);
}

#[test]
fn orthographic_camera() {
    let s = load(&format!(
        "[camera]\ntype = \"orthographic\"\nposition = [0, 10, 0]\nlook_at = [0, 0, 0]\nup = [0, 0, -1]\nheight = 4\n{SPHERE}"
    ));
    let c = s.camera.unwrap();
    assert_eq!(c.projection, Projection::Orthographic { height: 4.0 });
    let (o, d) = c.generate_ray(0.5, 0.5, 1, 1);
    assert!(close(o, Vec3::new(0.0, 10.0, 0.0), 1e-6));
    assert!(close(d, -Vec3::Y, 1e-6));
}

#[test]
fn render_settings_and_background() {
    let s = load(&format!(
        "background = [0.1, 0.2, 0.3]\n[render]\nresolution = [320, 200]\nspp = 16\nmax_depth = 3\nintegrator = \"ao\"\nseed = 7\nao_distance = 2.5\n{SPHERE}"
    ));
    assert_eq!(
        s.settings,
        RenderSettings {
            width: 320,
            height: 200,
            spp: 16,
            max_depth: 3,
            integrator: IntegratorKind::Ao,
            seed: 7,
            ao_distance: 2.5,
        }
    );
    assert_eq!(s.background, Vec3::new(0.1, 0.2, 0.3));
    for k in IntegratorKind::ALL {
        let s = load(&format!("[render]\nintegrator = \"{k}\"\n{SPHERE}"));
        assert_eq!(s.settings.integrator, k);
    }
    let s = load(&format!(
        "background = 1\n[render]\nao_distance = inf\n{SPHERE}"
    ));
    assert_eq!(s.settings.ao_distance, f32::INFINITY);
    assert_eq!(s.background, Vec3::ONE);
}

#[test]
fn materials_albedo_kd_emission_and_sides() {
    let s = load(
        r#"
[[materials]]
name = "a"
type = "lambert"
albedo = [0.25, 0.5, 1]

[[materials]]
name = "notes"
type = "lambert"
kd = [0.1, 0.2, 0.3]

[[materials]]
name = "grey"
type = "lambert"
albedo = 0.5

[[materials]]
name = "lamp"
type = "lambert"
albedo = 0
emission = [10, 5, 1]

[[materials]]
name = "two-sided lamp"
type = "lambert"
albedo = 0.2
emission = 3
double_sided = true

[[materials]]
name = "one-sided"
type = "lambert"
albedo = 0.5
double_sided = false

[[objects]]
shape = "sphere"
radius = 1
material = "a"
"#,
    );
    let m = &s.materials;
    assert_eq!(m.len(), 6);
    assert_eq!(m[0].name, "a");
    assert_eq!(m[0].bsdf.albedo(), Vec3::new(0.25, 0.5, 1.0));
    assert!(m[0].double_sided && !m[0].is_emissive());
    // kd = albedo / π.
    assert!(close(
        m[1].bsdf.albedo(),
        Vec3::new(0.1, 0.2, 0.3) * PI,
        1e-6
    ));
    assert_eq!(m[2].bsdf.albedo(), Vec3::splat(0.5));
    assert_eq!(m[3].emission, Vec3::new(10.0, 5.0, 1.0));
    assert!(!m[3].double_sided, "emitters default to front side only");
    assert_eq!(m[4].emission, Vec3::splat(3.0));
    assert!(m[4].double_sided);
    assert!(!m[5].double_sided);
    // Materials no object uses are reported.
    assert_eq!(s.warnings.len(), 5, "{:?}", s.warnings);
    assert!(s.warnings[0].contains("materials[1] 'notes' is not used"));
    // The object uses material 0; no default grey was added.
    assert_eq!(s.meshes[0].material, 0);
}

#[test]
fn kd_of_one_over_pi_is_white() {
    let s = load(&format!(
        "[[materials]]\nname = \"w\"\ntype = \"lambert\"\nkd = 0.3183098861837907\n{SPHERE}material = \"w\"\n"
    ));
    assert!(s.materials[0].bsdf.albedo().max_element() <= 1.0);
    assert!(close(s.materials[0].bsdf.albedo(), Vec3::ONE, 1e-6));
}

fn light(text: &str) -> Light {
    let s = load(&format!("[[lights]]\n{text}\n{SPHERE}"));
    assert_eq!(s.lights.len(), 1);
    s.lights[0].light
}

#[test]
fn point_light_units() {
    let p = Vec3::new(1.0, 2.0, 3.0);
    let intensity = |l: Light| match l {
        Light::Point(pl) => {
            assert_eq!(pl.position, p);
            pl.intensity
        }
        other => panic!("{other:?}"),
    };
    let base = "type = \"point\"\nposition = [1, 2, 3]\n";
    assert_eq!(
        intensity(light(&format!("{base}intensity = [1, 2, 3]"))),
        Vec3::new(1.0, 2.0, 3.0)
    );
    // I = Φ / 4π.
    assert!(close(
        intensity(light(&format!("{base}power = 100"))),
        Vec3::splat(100.0 / (4.0 * PI)),
        1e-6
    ));
    // cd / 683.
    assert!(close(
        intensity(light(&format!("{base}intensity_cd = 683"))),
        Vec3::ONE,
        1e-6
    ));
    // lm / 683 / 4π, times the colour.
    assert!(close(
        intensity(light(&format!(
            "{base}power_lm = 6830\ncolor = [1, 0.5, 0]"
        ))),
        Vec3::new(1.0, 0.5, 0.0) * 10.0 / (4.0 * PI),
        1e-5
    ));
    let s = load(&format!(
        "[[lights]]\nname = \"bulb\"\n{base}intensity = 1\n{SPHERE}"
    ));
    assert_eq!(s.lights[0].name, "bulb");
}

#[test]
fn directional_light_units() {
    let get = |l: Light| match l {
        Light::Directional(d) => d,
        other => panic!("{other:?}"),
    };
    let d = get(light(
        "type = \"directional\"\ndirection = [0, -3, -4]\nirradiance = [2, 2, 1]",
    ));
    assert!(close(d.direction, Vec3::new(0.0, -0.6, -0.8), 1e-6));
    assert_eq!(d.irradiance, Vec3::new(2.0, 2.0, 1.0));
    // lux / 683.
    let d = get(light(
        "type = \"directional\"\ndirection = [0, -1, 0]\nilluminance_lux = 1366",
    ));
    assert!(close(d.irradiance, Vec3::splat(2.0), 1e-6));
}

#[test]
fn spot_light_cones_and_units() {
    let get = |l: Light| match l {
        Light::Spot(s) => s,
        other => panic!("{other:?}"),
    };
    let s = get(light(
        "type = \"spot\"\nposition = [0, 4, 0]\ndirection = [0, -2, 0]\nintensity = 5\ninner_cone_deg = 20\nouter_cone_deg = 30",
    ));
    assert_eq!(s.position, Vec3::new(0.0, 4.0, 0.0));
    assert_eq!(s.direction, -Vec3::Y);
    assert_eq!(s.intensity, Vec3::splat(5.0));
    assert!((s.cos_inner - 20f32.to_radians().cos()).abs() < 1e-6);
    assert!((s.cos_outer - 30f32.to_radians().cos()).abs() < 1e-6);
    assert!(s.cos_inner > s.cos_outer);
    // glTF defaults: inner 0, outer π/4; candela / 683.
    let s = get(light(
        "type = \"spot\"\nposition = [0, 4, 0]\ndirection = [0, -1, 0]\nintensity_cd = [683, 1366, 0]",
    ));
    assert_eq!(s.cos_inner, 1.0);
    assert!((s.cos_outer - (PI / 4.0).cos()).abs() < 1e-6);
    assert!(close(s.intensity, Vec3::new(1.0, 2.0, 0.0), 1e-6));
}

fn one_object(text: &str) -> (Scene, Vec<Vec3>) {
    let s = load(&format!("[[objects]]\n{text}\n"));
    assert_eq!(s.instances.len(), 1);
    let inst = &s.instances[0];
    let m = &s.meshes[inst.mesh];
    m.validate().unwrap();
    let world = m
        .positions
        .iter()
        .map(|p| inst.transform.transform_point3(*p))
        .collect();
    (s, world)
}

fn bounds(ps: &[Vec3]) -> (Vec3, Vec3) {
    ps.iter().fold(
        (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)),
        |(lo, hi), p| (lo.min(*p), hi.max(*p)),
    )
}

#[test]
fn sphere_primitive() {
    let (s, w) = one_object(
        "name = \"ball\"\nshape = \"sphere\"\ncenter = [1, 2, 3]\nradius = 0.5\nsubdivisions = 16",
    );
    let m = &s.meshes[0];
    assert_eq!(m.name, "ball");
    assert_eq!(m.indices.len(), 2 * 16 * 30);
    assert!(m.normals.is_some() && m.uv0.is_some());
    let c = Vec3::new(1.0, 2.0, 3.0);
    for p in &w {
        assert!(((*p - c).length() - 0.5).abs() < 1e-5);
    }
    let area = surface_area(m);
    assert!((PI - area) / PI < 0.01, "{area}");
    assert!(signed_volume(m) > 0.0);
    // Default tessellation.
    let (s, _) = one_object("shape = \"sphere\"\nradius = 2");
    assert_eq!(
        s.meshes[0].indices.len(),
        2 * 32 * 62,
        "32 rings × 64 segments"
    );
}

#[test]
fn quad_primitive_forms() {
    let (s, w) =
        one_object("shape = \"quad\"\ncorner = [0, 0, 0]\nedge1 = [2, 0, 0]\nedge2 = [0, 3, 0]");
    assert_eq!(surface_area(&s.meshes[0]), 6.0);
    assert_eq!(w[2], Vec3::new(2.0, 3.0, 0.0));
    let n = (w[1] - w[0]).cross(w[2] - w[0]).normalize();
    assert_eq!(n, Vec3::Z, "normal = edge1 × edge2");

    let (s, w) =
        one_object("shape = \"quad\"\nvertices = [[0, 0, 0], [0, 0, 1], [1, 0, 1], [1, 0, 0]]");
    assert_eq!(surface_area(&s.meshes[0]), 1.0);
    assert_eq!(w[1], Vec3::new(0.0, 0.0, 1.0));
    assert_eq!((w[1] - w[0]).cross(w[2] - w[0]).normalize(), Vec3::Y);

    let (s, w) = one_object("shape = \"quad\"\ncenter = [0, 1, 0]\nsize = [4, 2]");
    assert_eq!(surface_area(&s.meshes[0]), 8.0);
    assert_eq!(
        bounds(&w),
        (Vec3::new(-2.0, 1.0, -1.0), Vec3::new(2.0, 1.0, 1.0))
    );
    assert_eq!((w[1] - w[0]).cross(w[2] - w[0]).normalize(), Vec3::Y);
    let (s, _) = one_object("shape = \"quad\"\nsize = 3");
    assert_eq!(surface_area(&s.meshes[0]), 9.0);
}

#[test]
fn box_primitive_forms() {
    let (s, w) = one_object("shape = \"box\"\nmin = [-1, 0, 2]\nmax = [1, 3, 4]");
    assert_eq!(
        bounds(&w),
        (Vec3::new(-1.0, 0.0, 2.0), Vec3::new(1.0, 3.0, 4.0))
    );
    assert_eq!(s.meshes[0].indices.len(), 12);
    assert!((signed_volume(&s.meshes[0]) - 12.0).abs() < 1e-4);
    let (_, w) = one_object("shape = \"box\"\ncenter = [0, 1, 0]\nsize = [2, 2, 4]");
    assert_eq!(
        bounds(&w),
        (Vec3::new(-1.0, 0.0, -2.0), Vec3::new(1.0, 2.0, 2.0))
    );
    let (_, w) = one_object("shape = \"box\"\nsize = 2");
    assert_eq!(bounds(&w), (Vec3::splat(-1.0), Vec3::ONE));
}

#[test]
fn disk_primitive() {
    let (s, w) = one_object(
        "shape = \"disk\"\ncenter = [0, 2, 0]\nnormal = [0, -1, 0]\nradius = 3\nsegments = 128",
    );
    let m = &s.meshes[0];
    assert_eq!(m.indices.len(), 128);
    assert!((surface_area(m) - 9.0 * PI).abs() / (9.0 * PI) < 1e-3);
    for t in &m.indices {
        let [a, b, c] = t.map(|i| w[i as usize]);
        assert!(close((b - a).cross(c - a).normalize(), -Vec3::Y, 1e-5));
    }
    let (s, _) = one_object("shape = \"disk\"\nradius = 1");
    assert_eq!(s.meshes[0].indices.len(), 64);
}

#[test]
fn transforms_scale_then_rotate_then_translate() {
    let xf = |t: &str| {
        let s = load(&format!(
            "[[objects]]\nshape = \"sphere\"\nradius = 1\n{t}\n"
        ));
        s.instances[0].transform
    };
    // T · R · S applied to (1, 0, 0).
    let m = xf("scale = 2\nrotate_deg = [0, 0, 90]\ntranslate = [10, 0, 0]");
    assert!(close(
        m.transform_point3(Vec3::X),
        Vec3::new(10.0, 2.0, 0.0),
        1e-6
    ));
    // Euler order: about X first, then Y, then Z (R = Rz · Ry · Rx):
    // X by 90° takes +y to +z, then Y by 90° takes +z to +x.
    let m = xf("rotate_deg = [90, 90, 0]");
    assert!(close(m.transform_vector3(Vec3::Y), Vec3::X, 1e-6));
    // Non-uniform scale.
    let m = xf("scale = [1, 2, 3]");
    assert_eq!(m.transform_point3(Vec3::ONE), Vec3::new(1.0, 2.0, 3.0));
    // Axis-angle, right-handed: +x about +z by 90° → +y.
    let m = xf("rotate_axis_angle = { axis = [0, 0, 2], angle_deg = 90 }");
    assert!(close(m.transform_vector3(Vec3::X), Vec3::Y, 1e-6));
    // Row-major matrix: translation in the last column as written.
    let m = xf("matrix = [[0, -1, 0, 5], [1, 0, 0, 6], [0, 0, 1, 7], [0, 0, 0, 1]]");
    assert!(close(
        m.transform_point3(Vec3::X),
        Vec3::new(5.0, 7.0, 7.0),
        1e-6
    ));
    // Mirroring is allowed and reported by the instance.
    let s = load("[[objects]]\nshape = \"box\"\nsize = 1\nscale = [-1, 1, 1]\n");
    assert!(s.instances[0].flips_winding());
}

#[test]
fn objects_share_materials_by_name() {
    let s = load(
        r#"
[[materials]]
name = "red"
type = "lambert"
albedo = [0.6, 0.1, 0.1]

[[materials]]
name = "lamp"
type = "lambert"
albedo = 0
emission = 5

[[objects]]
shape = "box"
size = 1
material = "red"

[[objects]]
shape = "sphere"
radius = 1
material = "red"

[[objects]]
shape = "disk"
radius = 1
material = "lamp"

[[objects]]
shape = "quad"
size = 1
"#,
    );
    let mats: Vec<&str> = s
        .instances
        .iter()
        .map(|i| s.instance_material(i).name.as_str())
        .collect();
    assert_eq!(mats, ["red", "red", "lamp", "default"]);
    assert_eq!(s.materials.len(), 3);
    assert!(s.warnings.is_empty(), "{:?}", s.warnings);
}

#[test]
fn scene_files_in_the_repository_load() {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../scenes");
    let mut n = 0;
    for entry in std::fs::read_dir(&dir).unwrap() {
        let p = entry.unwrap().path();
        if p.extension().is_some_and(|e| e == "toml") {
            let s = load_scene(&p, &LoadOptions::default()).unwrap_or_else(|e| panic!("{e}"));
            assert!(!s.instances.is_empty());
            n += 1;
        }
    }
    assert!(n >= 1);
}

/// Mesh objects go through the OBJ / glTF loaders (written separately).
#[test]
fn mesh_objects_keep_or_override_materials() {
    let s = load_scene(&corpus("mesh-ok.toml"), &LoadOptions::default())
        .unwrap_or_else(|e| panic!("{e}"));
    // Two copies of the tetrahedron: the first with the file's own
    // material(s) and moved by +10 x, the second red and scaled by 2.
    let plain: Vec<_> = s
        .instances
        .iter()
        .filter(|i| i.transform.w_axis.x == 10.0)
        .collect();
    let painted: Vec<_> = s
        .instances
        .iter()
        .filter(|i| i.transform.x_axis.x == 2.0)
        .collect();
    assert!(!plain.is_empty() && !painted.is_empty());
    assert_eq!(plain.len() + painted.len(), s.instances.len());
    for i in &painted {
        assert_eq!(s.instance_material(i).name, "red");
    }
    for i in &plain {
        assert_ne!(s.instance_material(i).name, "red");
    }
    let tris: usize = painted.iter().map(|i| s.meshes[i.mesh].indices.len()).sum();
    assert_eq!(tris, 4);
}

#[test]
fn absolute_mesh_paths_only_when_allowed() {
    let mesh = corpus("meshes/tetra.obj");
    let text = format!("[[objects]]\nmesh = {:?}\n", mesh.to_str().unwrap());
    let f = Path::new("elsewhere/scene.toml");
    let err = load_toml_str(&text, f, &LoadOptions::default()).unwrap_err();
    assert!(err.to_string().contains("absolute path"), "{err}");
    let opts = LoadOptions {
        allowed_absolute_paths: vec![mesh.clone()],
    };
    // Allowed: the path resolves and the mesh loads.
    let s = load_toml_str(&text, f, &opts).unwrap_or_else(|e| panic!("{e}"));
    assert!(!s.instances.is_empty());
}

#[test]
fn objects_without_material_use_the_files_default() {
    let s = load(
        "[[materials]]\nname = \"default\"\ntype = \"lambert\"\nalbedo = 0.3\n[[objects]]\nshape = \"box\"\nsize = 1\n",
    );
    assert_eq!(s.materials.len(), 1);
    assert_eq!(
        s.instance_material(&s.instances[0]).bsdf.albedo(),
        Vec3::splat(0.3)
    );
}

#[test]
fn objects_can_be_marked_as_planar_receivers() {
    let s = load(
        "[[objects]]\nshape = \"quad\"\nsize = 4\nplanar_receiver = true\n\
         [[objects]]\nshape = \"sphere\"\nradius = 1\n\
         [[objects]]\nshape = \"quad\"\nsize = 2\nplanar_receiver = false\n",
    );
    let marks: Vec<bool> = s.instances.iter().map(|i| i.planar_receiver).collect();
    assert_eq!(marks, [true, false, false]);
}
