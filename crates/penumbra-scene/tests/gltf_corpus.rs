//! One test per file of `tests/corpus/gltf/` (regenerate them with
//! `make_corpus.py` there): bad files give an error naming the file, the
//! place in it and the problem; good ones load with the expected warnings.
//! (The mutation test, "no corruption of a valid file panics", is a unit test
//! in `src/load/gltf.rs`: it runs in memory.)

use glam::{Vec2, Vec3};
use penumbra_scene::load::{LoadOptions, load_gltf};
use penumbra_scene::{Projection, Scene};
use penumbra_shading::bsdf::Bsdf;
use penumbra_shading::color::srgb_to_linear;
use penumbra_shading::light::Light;
use std::path::{Path, PathBuf};

fn corpus(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/corpus/gltf")
        .join(name)
}

fn load(name: &str) -> Scene {
    load_gltf(&corpus(name), &LoadOptions::default())
        .unwrap_or_else(|e| panic!("{name} should load: {e}"))
}

/// Loads a file that must fail; checks the message starts with the file's
/// path, names `place` and contains every one of `problem`.
fn error(name: &str, place: &str, problem: &[&str]) -> String {
    let path = corpus(name);
    let msg = match load_gltf(&path, &LoadOptions::default()) {
        Ok(_) => panic!("{name} should not load"),
        Err(e) => e.to_string(),
    };
    assert!(
        msg.starts_with(&path.display().to_string()),
        "message must start with the file: {msg}"
    );
    assert!(msg.contains(place), "message must name {place}: {msg}");
    for p in problem {
        assert!(msg.contains(p), "message must say {p}: {msg}");
    }
    msg
}

#[test]
fn empty_file() {
    let msg = error("empty.gltf", "empty.gltf", &["file is empty"]);
    assert!(msg.ends_with("empty.gltf: file is empty"), "{msg}");
}

#[test]
fn truncated_glb() {
    error(
        "truncated.glb",
        "at GLB header",
        &["truncated GLB", "declares 588 bytes", "only 568"],
    );
}

#[test]
fn truncated_json() {
    let msg = error(
        "truncated_json.gltf",
        "truncated_json.gltf:",
        &["truncated JSON"],
    );
    // file:line:column: message
    let rest = msg.split("truncated_json.gltf:").nth(1).unwrap();
    let mut parts = rest.splitn(3, ':');
    assert!(parts.next().unwrap().parse::<usize>().unwrap() > 1, "{msg}");
    assert!(parts.next().unwrap().parse::<usize>().is_ok(), "{msg}");
}

#[test]
fn missing_bin() {
    error(
        "missing_bin.gltf",
        "at buffers[0].uri",
        &["cannot read buffer file", "missing.bin"],
    );
}

#[test]
fn short_bin() {
    error(
        "short_bin.gltf",
        "at buffers[0].byteLength",
        &["byteLength is 44", "holds only 20 bytes"],
    );
}

#[test]
fn accessor_past_end_of_buffer() {
    error(
        "accessor_past_end.gltf",
        "at accessors[0]",
        &[
            "past the end of bufferViews[0]",
            "needs 48 bytes",
            "has 36 bytes",
            "meshes[0].primitives[0].attributes.POSITION",
        ],
    );
}

#[test]
fn buffer_view_past_end_of_buffer() {
    error(
        "view_past_buffer.gltf",
        "at bufferViews[0]",
        &["byteLength 400", "buffers[0]"],
    );
}

#[test]
fn nan_position() {
    error(
        "nan_position.gltf",
        "at meshes[0].primitives[0].attributes.POSITION",
        &["vertex 1", "non-finite position", "NaN", "accessors[0]"],
    );
}

#[test]
fn index_out_of_range() {
    error(
        "index_out_of_range.gltf",
        "at meshes[0].primitives[0].indices",
        &["vertex 7", "only 3 vertices", "accessors[1]"],
    );
}

#[test]
fn unknown_version() {
    error(
        "version3.gltf",
        "at asset.version",
        &["\"3.0\"", "not supported"],
    );
}

#[test]
fn uri_leaving_the_folder_is_refused() {
    error(
        "uri_parent.gltf",
        "at buffers[0].uri",
        &["'../outside.bin'", "leaves the scene's folder"],
    );
}

#[test]
fn absolute_uri_is_refused() {
    error(
        "uri_absolute.gltf",
        "at buffers[0].uri",
        &["'/etc/passwd'", "not allowed"],
    );
    // ... unless the user named it explicitly.
    let options = LoadOptions {
        allowed_absolute_paths: vec![PathBuf::from("/etc/passwd")],
    };
    if Path::new("/etc/passwd").exists() {
        let e = load_gltf(&corpus("uri_absolute.gltf"), &options).unwrap_err();
        assert!(!e.to_string().contains("not allowed"), "{e}");
    }
}

#[test]
fn position_accessor_index_out_of_range() {
    // The gltf crate's own validation would panic on this one.
    error(
        "position_accessor_missing.gltf",
        "at meshes[0].primitives[0].attributes.POSITION",
        &["accessor index 99", "out of range"],
    );
}

#[test]
fn node_cycle() {
    error("node_cycle.gltf", "at nodes[", &["reached twice"]);
}

#[test]
fn bad_base64() {
    error("bad_base64.gltf", "at buffers[0].uri", &["invalid base64"]);
}

#[test]
fn unsupported_required_extension() {
    error(
        "required_draco.gltf",
        "at extensionsRequired[0]",
        &["KHR_draco_mesh_compression", "not supported"],
    );
}

#[test]
fn degenerate_triangles_are_skipped_with_one_warning() {
    let scene = load("degenerate.gltf");
    assert_eq!(scene.triangle_count(), 1);
    assert_eq!(scene.warnings.len(), 1, "{:?}", scene.warnings);
    assert!(
        scene.warnings[0].contains("degenerate.gltf: skipped 2 degenerate triangle(s)"),
        "{}",
        scene.warnings[0]
    );
}

#[test]
fn glb_with_bin_chunk_loads() {
    let scene = load("ok_triangle.glb");
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    assert_eq!(scene.triangle_count(), 1);
    assert_eq!(scene.meshes[0].positions[1], Vec3::X);
    assert_eq!(
        scene.materials[scene.meshes[0].material].name, "default",
        "no material: default grey"
    );
    assert!(scene.camera.is_none());
}

#[test]
fn features_hierarchy_instancing_camera_light_materials() {
    let scene = load("ok_features.gltf");

    // Primitive 0 (indexed) and 1 (non-indexed) become meshes shared by the
    // two nodes; primitive 2 (LINES) is skipped with a warning.
    assert_eq!(scene.meshes.len(), 2);
    assert_eq!(scene.instances.len(), 4);
    assert_eq!(scene.triangle_count(), 4);
    let inst0: Vec<_> = scene.instances.iter().filter(|i| i.mesh == 0).collect();
    assert_eq!(inst0.len(), 2);
    // parent: T(10,0,0)·S(2); node b adds a 90° turn about z.
    let a = inst0[0].transform.transform_point3(Vec3::X);
    let b = inst0[1].transform.transform_point3(Vec3::X);
    assert!((a - Vec3::new(12.0, 0.0, 0.0)).length() < 1e-5, "{a}");
    assert!((b - Vec3::new(10.0, 2.0, 0.0)).length() < 1e-5, "{b}");

    let m0 = &scene.meshes[0];
    assert_eq!(m0.normals.as_ref().unwrap()[0], Vec3::Z);
    assert_eq!(m0.uv0.as_ref().unwrap()[1], Vec2::new(1.0, 0.0));
    assert!(m0.uv1.is_none());
    assert_eq!(scene.meshes[1].indices, vec![[0, 1, 2]]);

    // Camera: aspect ratio 2 → 512 × 256.
    let cam = scene.camera.unwrap();
    assert_eq!(cam.projection, Projection::Perspective { fov_y: 0.5 });
    assert!((cam.position() - Vec3::new(0.0, 0.0, 5.0)).length() < 1e-6);
    assert_eq!((scene.settings.width, scene.settings.height), (512, 256));

    // Spot light pointing down (node −Z rotated by −90° about x); 683 cd = 1 W/sr.
    assert_eq!(scene.lights.len(), 1);
    let Light::Spot(s) = scene.lights[0].light else {
        panic!("expected a spot light")
    };
    assert_eq!(scene.lights[0].name, "spot");
    assert!((s.position - Vec3::new(0.0, 3.0, 0.0)).length() < 1e-6);
    assert!((s.direction - -Vec3::Y).length() < 1e-6, "{}", s.direction);
    assert!((s.intensity - Vec3::new(1.0, 0.5, 0.25)).length() < 1e-6);
    assert!((s.cos_inner - 0.2f32.cos()).abs() < 1e-6);
    assert!((s.cos_outer - 0.4f32.cos()).abs() < 1e-6);
    assert_eq!(s.range, 10.0);

    // Materials: 'textured' is exact (no warning), texture decoded from sRGB.
    let textured = &scene.materials[m0.material];
    assert_eq!(textured.name, "textured");
    let Bsdf::Lambert(l) = textured.bsdf else {
        panic!(
            "{}: expected Lambert, got {:?}",
            textured.name, textured.bsdf
        )
    };
    assert_eq!(l.albedo, Vec3::splat(0.5));
    let tex = &scene.textures[textured.albedo_texture.unwrap()];
    assert_eq!((tex.width, tex.height), (2, 1));
    assert!(
        (tex.texels.get(0) - Vec3::new(1.0, srgb_to_linear(128.0 / 255.0), 0.0)).length() < 1e-6
    );
    assert!(!textured.double_sided);
    let shiny = &scene.materials[scene.meshes[1].material];
    assert_eq!(shiny.emission, Vec3::splat(4.0));
    assert!(shiny.double_sided);
    // metallic 0.5 with the default dielectric layer: the glTF model itself.
    let Bsdf::MetallicRoughness(mr) = shiny.bsdf else {
        panic!("shiny: expected MetallicRoughness, got {:?}", shiny.bsdf)
    };
    assert_eq!(mr.base_color, Vec3::new(0.2, 0.4, 0.6));
    assert_eq!((mr.metallic, mr.roughness, mr.ior), (0.5, 0.3, 1.5));
    assert_eq!((mr.transmission, mr.specular), (0.0, 1.0));
    assert_eq!(mr.specular_color, Vec3::ONE);

    // Warnings: one per material with ignored parts, one per kind of
    // skipped data, and one for the textured primitive without TEXCOORD_0.
    let w = &scene.warnings;
    assert_eq!(w.len(), 5, "{w:#?}");
    assert!(
        w.iter()
            .any(|w| w.contains("UV set") && w.contains("meshes[0].primitives[1] (TEXCOORD_0)")),
        "{w:#?}"
    );
    // shiny's normalTexture is read, but its primitive has no NORMAL to
    // build a tangent frame from.
    assert!(shiny.normal_map.is_some());
    assert!(
        w.iter()
            .any(|s| s.contains("normal map not applied") && s.contains("meshes[0].primitives[1]")),
        "{w:#?}"
    );
    let material: Vec<_> = w.iter().filter(|s| s.contains("material")).collect();
    assert_eq!(material.len(), 1, "{w:#?}");
    for part in [
        "material 'shiny' (materials[1]): ",
        "KHR_materials_clearcoat ignored",
    ] {
        assert!(material[0].contains(part), "{part}: {}", material[0]);
    }
    for gone in ["Lambertian", "metallicFactor", "specular layer"] {
        assert!(!material[0].contains(gone), "{gone}: {}", material[0]);
    }
    assert!(
        w.iter()
            .any(|s| s.contains("meshes[0].primitives[2] (LINES)"))
    );
    assert!(!w.iter().any(|s| s.contains("range")));
    assert!(
        w.iter()
            .any(|s| s.contains("not supported, ignored: KHR_animation_pointer"))
    );
}

#[test]
fn sparse_accessors() {
    let scene = load("ok_sparse.gltf");
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    let m = &scene.meshes[0];
    assert_eq!(
        m.positions,
        vec![Vec3::ZERO, Vec3::X, Vec3::new(0.0, 5.0, 0.0)]
    );
    // No bufferView: zeros, then the sparse values.
    assert_eq!(m.normals.as_ref().unwrap(), &vec![Vec3::Z; 3]);
}

#[test]
fn sparse_index_out_of_range() {
    error(
        "sparse_index_out_of_range.gltf",
        "at accessors[0].sparse.indices",
        &[
            "sparse index 9 is out of range",
            "meshes[0].primitives[0].attributes.POSITION",
        ],
    );
}

#[test]
fn missing_image() {
    error(
        "missing_image.gltf",
        "at images[0].uri",
        &["cannot read image file", "no_such_image.png"],
    );
}

#[test]
fn materials_map_to_the_metallic_roughness_model() {
    let scene = load("ok_materials.gltf");
    let mat = |name: &str| {
        scene
            .materials
            .iter()
            .find(|m| m.name == name)
            .unwrap_or_else(|| panic!("no material {name}"))
    };
    let mr = |name: &str| match mat(name).bsdf {
        Bsdf::MetallicRoughness(m) => m,
        other => panic!("{name}: expected MetallicRoughness, got {other:?}"),
    };

    // ior 1 switches the dielectric layer off: exactly Lambertian.
    let matte = mat("matte");
    let Bsdf::Lambert(l) = matte.bsdf else {
        panic!("matte: expected Lambert, got {:?}", matte.bsdf)
    };
    assert_eq!(l.albedo, Vec3::new(0.7, 0.6, 0.5));
    assert!(matte.metallic_roughness_texture.is_none());

    // KHR_materials_ior + _transmission; transmissive → two-sided.
    let glass = mr("glass");
    assert_eq!(glass.base_color, Vec3::ONE);
    assert_eq!((glass.metallic, glass.roughness), (0.0, 0.0));
    assert_eq!((glass.ior, glass.transmission), (1.33, 0.9));
    assert!(
        mat("glass").double_sided,
        "transmissive materials are two-sided"
    );

    // metallicRoughnessTexture: decoded as linear data (no sRGB curve).
    let metal = mr("metal");
    assert_eq!(metal.base_color, Vec3::new(1.0, 0.8, 0.3));
    assert_eq!((metal.metallic, metal.roughness), (1.0, 0.25));
    let tex = &scene.textures[mat("metal").metallic_roughness_texture.unwrap()];
    assert_eq!((tex.width, tex.height), (2, 1));
    assert!((tex.texels.get(0) - Vec3::new(1.0, 128.0 / 255.0, 0.0)).length() < 1e-6);
    assert!(!mat("metal").double_sided);

    // KHR_materials_specular and _emissive_strength.
    let coated = mr("coated");
    assert_eq!(coated.base_color, Vec3::new(0.1, 0.2, 0.3));
    assert_eq!((coated.metallic, coated.roughness), (0.0, 0.5));
    assert_eq!(coated.specular, 0.5);
    assert_eq!(coated.specular_color, Vec3::new(1.0, 0.5, 0.25));
    assert_eq!(mat("coated").emission, Vec3::new(3.0, 1.5, 0.0));

    // glTF's defaults: white, metallic 1, roughness 1, ior 1.5, specular 1.
    let d = mr("defaults");
    assert_eq!(d.base_color, Vec3::ONE);
    assert_eq!((d.metallic, d.roughness, d.ior), (1.0, 1.0, 1.5));
    assert_eq!((d.transmission, d.specular), (0.0, 1.0));

    // Only what is still ignored is warned about: the specular texture;
    // and the textured metal's primitive has no TEXCOORD_0.
    assert_eq!(scene.warnings.len(), 2, "{:#?}", scene.warnings);
    assert!(
        scene.warnings[1].contains("UV set")
            && scene.warnings[1].contains("meshes[0].primitives[2] (TEXCOORD_0)"),
        "{:#?}",
        scene.warnings
    );
    let w = &scene.warnings[0];
    assert!(
        w.contains("material 'coated' (materials[3]): specularTexture ignored"),
        "{w}"
    );
}

/// EXT_mesh_gpu_instancing: the triangle (0,0,0), (1,0,0), (0,1,0) drawn
/// three times under a node moved up by 10, each row's T·R·S inside the
/// node's transform (rotations stored as normalised shorts).
#[test]
fn ok_instancing() {
    let scene = load("ok_instancing.gltf");
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    assert_eq!((scene.meshes.len(), scene.instances.len()), (1, 3));
    let corners = |i: usize| -> Vec<Vec3> {
        scene.meshes[0]
            .positions
            .iter()
            .map(|p| scene.instances[i].transform.transform_point3(*p))
            .collect()
    };
    let expect = [
        // As is, 10 up.
        [(0.0, 10.0, 0.0), (1.0, 10.0, 0.0), (0.0, 11.0, 0.0)],
        // Scaled 2, turned 90° about z (x → y, y → −x), then x + 2.
        [(2.0, 10.0, 0.0), (2.0, 12.0, 0.0), (0.0, 10.0, 0.0)],
        // y squashed to 0.5, turned 180° about y (x → −x), then z − 3.
        [(0.0, 10.0, -3.0), (-1.0, 10.0, -3.0), (0.0, 10.5, -3.0)],
    ];
    for (i, e) in expect.iter().enumerate() {
        for (got, want) in corners(i).iter().zip(e) {
            let want = Vec3::new(want.0, want.1, want.2);
            // Shorts hold 1/√2 to 1.5e-5.
            assert!(
                (*got - want).length() < 1e-3,
                "instance {i}: {got} vs {want}"
            );
        }
    }
}

/// TEXCOORD_1: every texture of the file's four materials reads UV set 1
/// (`texCoord: 1`, or KHR_texture_transform's `texCoord` override), both
/// sets are loaded as written (set 0 mirrored in u), and nothing is warned.
#[test]
fn ok_texcoord1() {
    let scene = load("ok_texcoord1.gltf");
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    assert_eq!(scene.materials.len(), 4);
    let mut read = 0;
    for m in &scene.materials {
        for t in m.textures() {
            assert_eq!(scene.textures[t].uv_set, 1, "material '{}'", m.name);
            read += 1;
        }
    }
    // Base colour, emission, base colour + its alpha, base colour.
    assert_eq!(read, 5);
    let mesh = &scene.meshes[0];
    let (uv0, uv1) = (mesh.uv0.as_ref().unwrap(), mesh.uv1.as_ref().unwrap());
    assert_eq!(uv1[0], Vec2::new(0.0, 1.0));
    assert_eq!(uv0[0], Vec2::new(1.0, 1.0));
}
