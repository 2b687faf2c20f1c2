//! One test per file of `tests/corpus/obj/`: bad files give an error naming
//! the file and the 1-based line; files with recoverable problems load with
//! a warning. Plus a mutation test: no edit of a valid MTL file panics.

use glam::{Vec2, Vec3};
use penumbra_scene::Scene;
use penumbra_scene::load::{LoadOptions, load_obj};
use penumbra_shading::Rgb;
use penumbra_shading::bsdf::optics::f0_from_ior;
use penumbra_shading::bsdf::{Bsdf, FresnelModel, PhongVariant};
use std::path::{Path, PathBuf};

fn corpus(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/corpus/obj")
        .join(name)
}

fn load(name: &str) -> Scene {
    load_obj(&corpus(name), &LoadOptions::default())
        .unwrap_or_else(|e| panic!("{name} should load: {e}"))
}

/// Loads a file that must fail; the message must start with `place` (the
/// file's path with `:line` appended by the caller) and say every `problem`.
fn error(name: &str, place: &str, problem: &[&str]) -> String {
    let msg = match load_obj(&corpus(name), &LoadOptions::default()) {
        Ok(_) => panic!("{name} should not load"),
        Err(e) => e.to_string(),
    };
    assert!(
        msg.starts_with(place),
        "message must start with {place}: {msg}"
    );
    for p in problem {
        assert!(msg.contains(p), "message must say {p}: {msg}");
    }
    msg
}

fn at(name: &str, line: usize) -> String {
    format!("{}:{line}: ", corpus(name).display())
}

#[test]
fn empty_file() {
    error(
        "empty.obj",
        &format!("{}: ", corpus("empty.obj").display()),
        &["file is empty"],
    );
}

#[test]
fn no_faces() {
    error(
        "no_faces.obj",
        &format!("{}: ", corpus("no_faces.obj").display()),
        &["no faces"],
    );
}

#[test]
fn nan_vertex() {
    error(
        "nan_vertex.obj",
        &at("nan_vertex.obj", 3),
        &["vertex 2", "non-finite position", "NaN"],
    );
}

#[test]
fn face_index_out_of_range() {
    error(
        "face_out_of_range.obj",
        &at("face_out_of_range.obj", 5),
        &["face vertex index 9 is out of range", "3 vertices"],
    );
}

#[test]
fn mtllib_leaving_the_folder_is_refused() {
    error(
        "mtl_escape.obj",
        &at("mtl_escape.obj", 4),
        &["'../escape.mtl'", "leaves the scene's folder"],
    );
}

#[test]
fn malformed_mtl_names_the_mtl_line_and_the_obj() {
    let mtl = corpus("bad_mtl.mtl");
    error(
        "bad_mtl.obj",
        &format!("{}:2: ", mtl.display()),
        &[
            "Kd has 2 numbers",
            &format!("{}:1", corpus("bad_mtl.obj").display()),
        ],
    );
}

#[test]
fn missing_mtllib_loads_with_a_warning() {
    let scene = load("missing_mtl.obj");
    assert_eq!(scene.triangle_count(), 1);
    let mat = &scene.materials[scene.meshes[0].material];
    assert_eq!(mat.name, "default");
    let w = scene.warnings.join("\n");
    assert!(
        w.contains(&format!(
            "{}:1: material library 'not_here.mtl' cannot be read",
            corpus("missing_mtl.obj").display()
        )),
        "{w}"
    );
    assert!(w.contains("'red' (line 6)"), "{w}");
    assert!(scene.camera.is_none());
}

#[test]
fn degenerate_triangles_are_skipped_with_one_warning() {
    let scene = load("degenerate.obj");
    assert_eq!(scene.triangle_count(), 1);
    assert_eq!(scene.warnings.len(), 1, "{:?}", scene.warnings);
    assert!(
        scene.warnings[0].ends_with("degenerate.obj: skipped 2 degenerate triangle(s) (zero area)"),
        "{}",
        scene.warnings[0]
    );
}

#[test]
fn materials_textures_normals_and_uvs() {
    let scene = load("ok_materials.obj");
    assert!(scene.camera.is_none());
    assert_eq!(scene.meshes.len(), 3);
    assert_eq!(scene.triangle_count(), 4);
    let by_name = |n: &str| scene.meshes.iter().find(|m| m.name == n).unwrap();

    let quad = by_name("quad");
    assert_eq!(quad.indices.len(), 2);
    assert!(quad.normals.as_ref().unwrap().iter().all(|n| *n == Vec3::Z));
    // OBJ's v runs up; penumbra's (as glTF's) runs down the image.
    let uv = quad.uv0.as_ref().unwrap();
    let i0 = quad
        .positions
        .iter()
        .position(|p| *p == Vec3::ZERO)
        .unwrap();
    assert_eq!(uv[i0], Vec2::new(0.0, 1.0));
    let shiny = &scene.materials[quad.material];
    // illum 2: normalised Phong–Blinn with kd = Kd/π, ks = Ks, γ = Ns.
    let Bsdf::PhongBlinn(p) = shiny.bsdf else {
        panic!("shiny: expected PhongBlinn, got {:?}", shiny.bsdf)
    };
    assert!((p.kd * std::f32::consts::PI - Vec3::new(0.8, 0.2, 0.1)).length() < 1e-6);
    assert_eq!((p.ks, p.shininess), (Vec3::splat(0.5), 64.0));
    assert_eq!(p.variant, PhongVariant::Normalized);
    assert!(shiny.double_sided);

    let lamp = &scene.materials[by_name("lamp").material];
    assert_eq!(lamp.emission, Vec3::new(10.0, 8.0, 6.0));
    assert!(!lamp.double_sided, "emitters emit from the front only");
    assert_eq!(by_name("lamp").positions[0], Vec3::new(0.0, 0.0, 2.0));

    let textured = &scene.materials[by_name("plain").material];
    let tex = &scene.textures[textured.albedo_texture.unwrap()];
    assert_eq!((tex.width, tex.height), (2, 1));
    assert_eq!(tex.texels.get(1), Vec3::new(0.0, 0.0, 1.0));

    // One warning, for 'shiny' only (lamp: illum 1; textured: exact).
    assert_eq!(scene.warnings.len(), 1, "{:#?}", scene.warnings);
    let w = &scene.warnings[0];
    for part in [
        "material 'shiny'",
        "ok_materials.mtl",
        "transparency (d 0.5) ignored (opaque)",
    ] {
        assert!(w.contains(part), "{part}: {w}");
    }
    assert!(!w.contains("Ks"), "Ks is used now: {w}");
}

#[test]
fn illum_modes_map_to_the_nearest_model() {
    let scene = load("illum.obj");
    let bsdf = |name: &str| {
        let mesh = scene.meshes.iter().find(|m| m.name == name).unwrap();
        let m = &scene.materials[mesh.material];
        assert_eq!(m.name, name);
        (m.bsdf, m.double_sided)
    };
    let lambert = |name: &str| match bsdf(name).0 {
        Bsdf::Lambert(l) => l.albedo,
        other => panic!("{name}: expected Lambert, got {other:?}"),
    };
    // 0, 1: Lambert with Kd (illum 1 switches Ks off exactly).
    assert_eq!(lambert("flat0"), Vec3::splat(0.5));
    assert_eq!(lambert("flat1"), Vec3::new(0.2, 0.3, 0.4));
    // 2: Phong–Blinn (normalised), kd = Kd/π; without Ks exactly Lambert;
    // a material with Ks and no illum is read as illum 2.
    for (name, kd, ks, ns) in [
        ("phong", Vec3::new(0.4, 0.2, 0.1), 0.3, 50.0),
        ("no_illum", Vec3::splat(0.5), 0.2, 10.0),
    ] {
        let Bsdf::PhongBlinn(p) = bsdf(name).0 else {
            panic!("{name}: expected PhongBlinn, got {:?}", bsdf(name).0)
        };
        assert!((p.kd * std::f32::consts::PI - kd).length() < 1e-6, "{name}");
        assert_eq!((p.ks, p.shininess), (Vec3::splat(ks), ns), "{name}");
        assert_eq!(p.variant, PhongVariant::Normalized);
    }
    assert_eq!(lambert("phong_no_ks"), Vec3::splat(0.4));
    // 3: mirror of reflectance Ks.
    let Bsdf::Mirror(m) = bsdf("mirror").0 else {
        panic!("mirror: {:?}", bsdf("mirror").0)
    };
    assert_eq!(m.reflectance, Vec3::new(0.9, 0.8, 0.7));
    // 5: Fresnel mirror whose normal-incidence reflectance is Ks.
    let Bsdf::Conductor(c) = bsdf("fresnel").0 else {
        panic!("fresnel: {:?}", bsdf("fresnel").0)
    };
    assert_eq!(c.fresnel, FresnelModel::Schlick);
    let f0 = f0_from_ior(c.eta, c.k);
    assert!(
        (f0 - Rgb::new(0.04, 0.25, 1.0)).abs().max_element() < 1e-3,
        "{f0}"
    );
    // 4/6/7/9: smooth dielectric with Ni and Tf, two-sided.
    let (Bsdf::Dielectric(g), two_sided) = bsdf("glass") else {
        panic!("glass: {:?}", bsdf("glass").0)
    };
    assert_eq!((g.eta, g.tint), (1.45, Vec3::new(0.9, 0.95, 1.0)));
    assert_eq!(g.fresnel, FresnelModel::Exact);
    assert!(two_sided);
    let Bsdf::Dielectric(g) = bsdf("glass_no_ni").0 else {
        panic!("glass_no_ni: {:?}", bsdf("glass_no_ni").0)
    };
    assert_eq!((g.eta, g.tint), (1.5, Vec3::ONE));
    // Others: nearest (Lambert) with a warning.
    assert_eq!(lambert("odd"), Vec3::splat(0.3));
    // Pr/Pm: metallic–roughness.
    let Bsdf::MetallicRoughness(p) = bsdf("pbr").0 else {
        panic!("pbr: {:?}", bsdf("pbr").0)
    };
    assert_eq!(p.base_color, Vec3::new(0.6, 0.5, 0.4));
    assert_eq!((p.metallic, p.roughness, p.ior), (1.0, 0.3, 1.5));

    let w = &scene.warnings;
    assert_eq!(w.len(), 2, "{w:#?}");
    assert!(
        w.iter()
            .any(|s| s.contains("'glass_no_ni'")
                && s.contains("illum 4 without Ni: ior 1.5 assumed")),
        "{w:#?}"
    );
    assert!(
        w.iter().any(|s| s.contains("'odd'")
            && s.contains("illum 10 has no nearer model than Lambertian (Kd); Ks dropped")),
        "{w:#?}"
    );
}

/// Replaces each line of a valid MTL file with hostile statements and loads
/// the OBJ that uses it: any outcome but a panic is fine. (The same for OBJ
/// lines is a unit test in `src/load/obj.rs`: it runs in memory.)
#[test]
fn edited_mtl_files_never_panic() {
    let dir = std::env::temp_dir().join(format!("penumbra-obj-mutants-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::copy(corpus("tex.png"), dir.join("tex.png")).unwrap();
    std::fs::copy(corpus("ok_materials.obj"), dir.join("ok_materials.obj")).unwrap();
    let options = LoadOptions::default();
    let mtl = std::fs::read_to_string(corpus("ok_materials.mtl")).unwrap();
    let lines: Vec<&str> = mtl.lines().collect();
    let hostile = [
        "Kd",
        "Kd 1 2",
        "Kd spectral x.rfl",
        "Ke -1 0 0",
        "Ns",
        "d -halo",
        "illum 300",
        "newmtl",
        "map_Kd",
        "map_Kd -s 1 1 1",
        "map_Kd ../../etc/passwd",
        "Tf 1",
        "Tr x",
    ];
    let mut outcomes = (0, 0);
    for i in 0..lines.len() {
        for h in hostile {
            let mut m = lines.clone();
            m[i] = h;
            std::fs::write(dir.join("ok_materials.mtl"), m.join("\n")).unwrap();
            match load_obj(&dir.join("ok_materials.obj"), &options) {
                Ok(_) => outcomes.0 += 1,
                Err(_) => outcomes.1 += 1,
            }
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
    assert!(outcomes.0 > 0 && outcomes.1 > 0, "{outcomes:?}");
}
