//! glTF export of an AO bake (`bake ao --gltf OUT.glb`): the file read back
//! by penumbra's loader and by the `gltf` crate, its occlusion textures
//! against the bake, and the Khronos glTF validator's verdict.
//!
//! The validator (npm package `gltf-validator`, pinned in
//! `tools/gltf-validator/package.json`) is installed by `scripts/test.sh`;
//! without it these tests fail, unless `PENUMBRA_SKIP_GLTF_VALIDATOR=1`.

use glam::{Mat4, Quat, Vec2, Vec3};
use penumbra_bake::gltf_export::{write_glb, write_glb_with_warnings};
use penumbra_bake::lookup::bilinear;
use penumbra_bake::{AoSettings, AtlasSettings, Bake, BakeError, BakeKind, Density, bake_ao};
use penumbra_image::Image;
use penumbra_scene::{
    Camera, Material, Projection, Scene, SceneAreaLight, SceneLight, Texture, builtin, primitives,
};
use penumbra_shading::Rgb;
use penumbra_shading::bsdf::{
    Bsdf, Conductor, Dielectric, FresnelModel, MetallicRoughness, Mirror, PhongBlinn, PhongVariant,
    RoughConductor, RoughDielectric,
};
use penumbra_shading::light::{AreaLight, DirectionalLight, Light, PointLight, Shape, SpotLight};
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::OnceLock;

fn small_bake(scene: &Scene, distance: f32) -> Bake {
    bake_ao(
        scene,
        &AoSettings {
            samples: 16,
            distance,
            seed: 0,
        },
        &AtlasSettings {
            density: Density::MaxSize(64),
            ..Default::default()
        },
        None,
    )
    .expect("AO bake")
}

/// The built-in Cornell box and a small AO bake of it (baked once).
fn cornell() -> &'static (Scene, Bake) {
    static CELL: OnceLock<(Scene, Bake)> = OnceLock::new();
    CELL.get_or_init(|| {
        let scene = builtin::cornell_box();
        let bake = small_bake(&scene, 100.0);
        (scene, bake)
    })
}

// --- the Khronos validator --------------------------------------------------

/// The validator's report on `path` (JSON), or `None` when
/// `PENUMBRA_SKIP_GLTF_VALIDATOR=1`. Panics, naming `scripts/test.sh`, when
/// node or the validator is missing.
fn validator_report(path: &Path) -> Option<serde_json::Value> {
    if std::env::var("PENUMBRA_SKIP_GLTF_VALIDATOR").as_deref() == Ok("1") {
        eprintln!(
            "note: PENUMBRA_SKIP_GLTF_VALIDATOR=1: {} is not checked with the Khronos glTF validator",
            path.display()
        );
        return None;
    }
    let tools = Path::new(env!("CARGO_MANIFEST_DIR"))
        .ancestors()
        .nth(2)
        .expect("the workspace root")
        .join("tools/gltf-validator");
    let how = "run scripts/test.sh (it installs the Khronos glTF validator with npm into \
               tools/gltf-validator/node_modules), or set PENUMBRA_SKIP_GLTF_VALIDATOR=1 to skip this check";
    match Command::new("node").arg("--version").output() {
        Ok(o) if o.status.success() => {}
        Ok(o) => panic!("`node --version` failed ({}): {how}", o.status),
        Err(e) => panic!("Node.js (`node`) is not available ({e}): {how}"),
    }
    let module = tools.join("node_modules/gltf-validator/package.json");
    assert!(
        module.is_file(),
        "the glTF validator is not installed ({} is missing): {how}",
        module.display()
    );
    let out = Command::new("node")
        .arg(tools.join("validate.mjs"))
        .arg(path)
        .output()
        .expect("running node");
    assert!(
        out.status.success(),
        "the glTF validator failed on {} ({}): {}",
        path.display(),
        out.status,
        String::from_utf8_lossy(&out.stderr)
    );
    Some(serde_json::from_slice(&out.stdout).expect("the validator's report is JSON"))
}

/// Validates `path`: no errors and no warnings (infos and hints are
/// listed). Prints the summary.
fn assert_valid(path: &Path) {
    let Some(report) = validator_report(path) else {
        return;
    };
    let issues = &report["issues"];
    let count = |k: &str| issues[k].as_u64().unwrap_or(u64::MAX);
    let messages: Vec<String> = issues["messages"]
        .as_array()
        .into_iter()
        .flatten()
        .map(|m| {
            format!(
                "  [{}] {} at {}: {}",
                m["severity"], m["code"], m["pointer"], m["message"]
            )
        })
        .collect();
    let summary = format!(
        "gltf-validator {} on {}: {} errors, {} warnings, {} infos, {} hints",
        report["validatorVersion"].as_str().unwrap_or("?"),
        path.file_name().unwrap().to_string_lossy(),
        count("numErrors"),
        count("numWarnings"),
        count("numInfos"),
        count("numHints"),
    );
    println!("{summary}\n{}", messages.join("\n"));
    assert_eq!(
        count("numErrors"),
        0,
        "{summary}\n{}\nfull report:\n{report:#}",
        messages.join("\n")
    );
    assert_eq!(
        count("numWarnings"),
        0,
        "{summary}\n{}",
        messages.join("\n")
    );
}

// --- reading the file back with the gltf crate ---------------------------------

/// One node's primitive: its TEXCOORD_1 per triangle corner and the
/// decoded occlusion image (R channel, 0–1) with its texCoord.
struct Exported {
    corner_uv1: Vec<[Vec2; 3]>,
    occlusion: Option<(u32, Image)>,
    occlusion_tex_coord: u32,
}

fn read_exported(bytes: &[u8]) -> Vec<Exported> {
    let gltf = gltf::Gltf::from_slice(bytes).expect("the gltf crate reads the GLB");
    let blob = gltf.blob.as_deref().expect("a BIN chunk");
    let mut out = Vec::new();
    for node in gltf.document.nodes() {
        let Some(mesh) = node.mesh() else { continue };
        let prims: Vec<_> = mesh.primitives().collect();
        assert_eq!(prims.len(), 1, "one primitive per mesh");
        let prim = &prims[0];
        let reader = prim.reader(|_| Some(blob));
        let indices: Vec<u32> = reader.read_indices().expect("indices").into_u32().collect();
        let uv1: Vec<Vec2> = reader
            .read_tex_coords(1)
            .map(|t| t.into_f32().map(Vec2::from).collect())
            .unwrap_or_default();
        let corner_uv1 = if uv1.is_empty() {
            Vec::new()
        } else {
            indices
                .chunks_exact(3)
                .map(|t| std::array::from_fn(|c| uv1[t[c] as usize]))
                .collect()
        };
        let occ = prim.material().occlusion_texture();
        let occlusion_tex_coord = occ.as_ref().map_or(u32::MAX, |o| o.tex_coord());
        let occlusion = occ.map(|o| {
            let img = o.texture().source();
            let gltf::image::Source::View { view, mime_type } = img.source() else {
                panic!("the occlusion image is not embedded");
            };
            assert_eq!(mime_type, "image/png");
            let png = &blob[view.offset()..view.offset() + view.length()];
            let decoded = image::load_from_memory(png).expect("PNG").to_rgb8();
            let (w, h) = decoded.dimensions();
            for p in decoded.pixels() {
                assert!(p[0] == p[1] && p[1] == p[2], "R = G = B = kA");
            }
            let page = Image::from_fn(w, h, |x, y| {
                Rgb::splat(decoded.get_pixel(x, y)[0] as f32 / 255.0)
            });
            (img.index() as u32, page)
        });
        out.push(Exported {
            corner_uv1,
            occlusion,
            occlusion_tex_coord,
        });
    }
    out
}

fn write(bake: &Bake, scene: &Scene, name: &str) -> (tempfile::TempDir, PathBuf, Vec<String>) {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join(name);
    let warnings = write_glb_with_warnings(bake, scene, &path).expect("write_glb");
    (dir, path, warnings)
}

fn assert_bounds_match(a: &Scene, b: &Scene) {
    let (alo, ahi) = a.bounds().unwrap();
    let (blo, bhi) = b.bounds().unwrap();
    let tol = 1e-5 * (ahi - alo).length();
    assert!(
        (alo - blo).abs().max_element() <= tol && (ahi - bhi).abs().max_element() <= tol,
        "bounds {alo}..{ahi} vs {blo}..{bhi}"
    );
}

// --- the Cornell box -------------------------------------------------------

#[test]
fn cornell_glb_reads_back_with_the_bake_as_occlusion() {
    let (scene, bake) = cornell();
    let (_dir, path, warnings) = write(bake, scene, "cornell.glb");
    // Lambertian materials and a camera: nothing to approximate.
    assert!(warnings.is_empty(), "{warnings:?}");
    let bytes = std::fs::read(&path).unwrap();
    assert_eq!(&bytes[..4], b"glTF");
    assert_eq!(
        u32::from_le_bytes(bytes[8..12].try_into().unwrap()) as usize,
        bytes.len()
    );

    // penumbra's own loader: same geometry, materials and camera.
    let loaded = penumbra_scene::load_scene(&path, &Default::default()).expect("loads");
    assert_eq!(loaded.instances.len(), scene.instances.len());
    assert_eq!(loaded.triangle_count(), scene.triangle_count());
    assert_bounds_match(scene, &loaded);
    for (i, (a, b)) in scene.instances.iter().zip(&loaded.instances).enumerate() {
        let (ma, mb) = (&scene.meshes[a.mesh], &loaded.meshes[b.mesh]);
        assert_eq!(ma.indices.len(), mb.indices.len(), "instance {i}");
        assert!(mb.uv1.is_some(), "instance {i} has TEXCOORD_1");
        // World-space corners, triangle by triangle, winding included.
        for (ta, tb) in ma.indices.iter().zip(&mb.indices) {
            for c in 0..3 {
                let pa = a.transform.transform_point3(ma.positions[ta[c] as usize]);
                let pb = b.transform.transform_point3(mb.positions[tb[c] as usize]);
                assert!((pa - pb).length() < 1e-3, "instance {i}: {pa} vs {pb}");
            }
        }
        // Lambert stays Lambert (specularFactor 0), emission survives
        // emissiveFactor × KHR_materials_emissive_strength.
        let (xa, xb) = (scene.instance_material(a), loaded.instance_material(b));
        assert_eq!(xa.bsdf, xb.bsdf, "material '{}'", xa.name);
        assert_eq!(xa.double_sided, xb.double_sided, "material '{}'", xa.name);
        assert!(
            (xa.emission - xb.emission).abs().max_element() <= 1e-5 * xa.emission.max_element(),
            "emission {} vs {}",
            xa.emission,
            xb.emission
        );
    }
    let (ca, cb) = (scene.camera.unwrap(), loaded.camera.unwrap());
    assert_eq!(ca.projection, cb.projection);
    assert!((ca.position() - cb.position()).length() < 1e-3);
    let (fa, fb) = (
        ca.camera_to_world.transform_vector3(-Vec3::Z),
        cb.camera_to_world.transform_vector3(-Vec3::Z),
    );
    assert!((fa - fb).length() < 1e-5, "view direction {fa} vs {fb}");

    // The gltf crate: TEXCOORD_1 is the atlas, occlusion reads it, and the
    // PNG holds the bake's kA (linear 8-bit).
    let exported = read_exported(&bytes);
    assert_eq!(exported.len(), scene.instances.len());
    let pages = &bake.maps[0].pages;
    let mut corners = 0;
    let mut worst = 0.0f32;
    for (i, e) in exported.iter().enumerate() {
        assert_eq!(e.occlusion_tex_coord, 1, "instance {i}: occlusion texCoord");
        let (_, png) = e.occlusion.as_ref().expect("occlusionTexture");
        let tris = scene.meshes[scene.instances[i].mesh].indices.len();
        assert_eq!(e.corner_uv1.len(), tris, "instance {i}");
        for (t, uv1) in e.corner_uv1.iter().enumerate() {
            let (page, expected) = bake.atlas.triangle_uvs(scene, i, t).unwrap();
            assert_eq!(*uv1, expected, "instance {i} triangle {t}: TEXCOORD_1");
            let page = &pages[page as usize];
            assert_eq!((png.width, png.height), (page.width, page.height));
            for &uv in uv1 {
                let want = bilinear(page, uv).x;
                let got = bilinear(png, uv).x;
                worst = worst.max((want - got).abs());
                assert!(
                    (want - got).abs() <= 2.0 / 255.0,
                    "instance {i} triangle {t} at {uv}: kA {want} baked, {got} in the PNG"
                );
                corners += 1;
            }
        }
    }
    println!("{corners} corners, largest |kA(bake) − kA(PNG)| = {worst:.5}");
    // Every texel of every page: linear 8-bit values (no sRGB transfer).
    let mut seen = std::collections::BTreeSet::new();
    for e in &exported {
        let (image, png) = e.occlusion.as_ref().unwrap();
        if !seen.insert(*image) {
            continue;
        }
        // The image whose texels are the page's: find the page by content.
        let page = pages
            .iter()
            .find(|p| {
                p.pixels
                    .iter()
                    .zip(&png.pixels)
                    .all(|(a, b)| (a.x.clamp(0.0, 1.0) - b.x).abs() <= 0.5 / 255.0 + 1e-6)
            })
            .expect("the PNG is a page of the bake, linear, to 8 bits");
        assert_eq!(page.width, png.width);
    }
    assert_eq!(seen.len(), bake.atlas.pages as usize);
}

#[test]
fn cornell_glb_passes_the_khronos_validator() {
    let (scene, bake) = cornell();
    let (_dir, path, _) = write(bake, scene, "cornell.glb");
    assert_valid(&path);
}

// --- every material model, lights, odd transforms -------------------------

/// A scene with every BSDF, a texture, sheared, mirrored and repeated
/// instances, a material override, punctual and area lights, and an
/// orthographic camera.
fn assorted_scene() -> Scene {
    let mut s = Scene::default();
    let textured = {
        let mut m = Material::lambert("checker", Rgb::new(0.8, 0.7, 0.6));
        s.textures.push(Texture {
            name: "checker".into(),
            width: 2,
            height: 2,
            texels: vec![Rgb::ONE, Rgb::splat(0.2), Rgb::splat(0.2), Rgb::ONE].into(),
            wrap: Default::default(),
            uv_transform: glam::Affine2::IDENTITY,
            uv_set: 0,
        });
        m.albedo_texture = Some(0);
        s.add_material(m)
    };
    let bsdfs = [
        (
            "phong",
            Bsdf::PhongBlinn(PhongBlinn::from_albedo(
                Rgb::new(0.5, 0.3, 0.2),
                Rgb::splat(0.3),
                40.0,
                PhongVariant::Notes,
            )),
        ),
        (
            "plastic",
            Bsdf::MetallicRoughness(MetallicRoughness {
                ior: 1.45,
                ..MetallicRoughness::new(Rgb::new(0.1, 0.2, 0.7), 0.0, 0.4)
            }),
        ),
        (
            "gold",
            Bsdf::Conductor(Conductor::new(
                Rgb::new(0.143, 0.374, 1.442),
                Rgb::new(3.983, 2.385, 1.603),
                FresnelModel::Exact,
            )),
        ),
        (
            "rough gold",
            Bsdf::RoughConductor(RoughConductor::new(
                Rgb::new(0.143, 0.374, 1.442),
                Rgb::new(3.983, 2.385, 1.603),
                0.09,
            )),
        ),
        (
            "glass",
            Bsdf::Dielectric(Dielectric::new(1.5, Rgb::ONE, FresnelModel::Exact)),
        ),
        (
            "frosted",
            Bsdf::RoughDielectric(RoughDielectric::new(1.33, 0.2)),
        ),
        ("mirror", Bsdf::Mirror(Mirror::new(Rgb::splat(0.9)))),
    ];
    let mut ids = Vec::new();
    for (name, bsdf) in bsdfs {
        ids.push(s.add_material(Material {
            bsdf,
            ..Material::lambert(name, Rgb::ONE)
        }));
    }
    let glowing = s.add_material(Material::emitter("glow", Rgb::new(0.5, 2.0, 0.25)));
    let floor = primitives::quad(Vec3::new(-5.0, 0.0, 5.0), Vec3::X * 10.0, -Vec3::Z * 10.0);
    let m = s.add_mesh(floor, Mat4::IDENTITY);
    s.meshes[m].material = textured;
    // One sphere mesh, many instances (TRS, sheared, mirrored, overridden).
    let mut sphere = primitives::sphere(Vec3::ZERO, 0.5, 6);
    sphere.name = "ball".into();
    sphere.material = ids[0];
    s.meshes.push(sphere);
    let ball = s.meshes.len() - 1;
    for (k, &id) in ids.iter().enumerate() {
        let t = Mat4::from_scale_rotation_translation(
            Vec3::splat(1.0 + 0.1 * k as f32),
            Quat::from_rotation_y(0.3 * k as f32),
            Vec3::new(-4.0 + 1.2 * k as f32, 0.6, 0.0),
        );
        let mut inst = penumbra_scene::Instance::new(ball, t);
        inst.material = (k > 0).then_some(id);
        s.instances.push(inst);
    }
    let mut shear = Mat4::from_translation(Vec3::new(0.0, 0.7, 2.0));
    shear.y_axis.x = 0.6;
    s.instances.push(penumbra_scene::Instance::new(ball, shear));
    let mut boxy = primitives::cuboid(Vec3::new(0.0, 0.0, -0.5), Vec3::new(1.0, 1.0, 0.5));
    boxy.material = glowing;
    boxy.normals = None;
    s.meshes.push(boxy);
    let boxy = s.meshes.len() - 1;
    // Mirrored (negative determinant) and mirrored-and-sheared.
    s.instances.push(penumbra_scene::Instance::new(
        boxy,
        Mat4::from_scale_rotation_translation(
            Vec3::new(-1.0, 1.0, 1.0),
            Quat::IDENTITY,
            Vec3::new(3.0, 0.0, 3.0),
        ),
    ));
    let mut ms = Mat4::from_scale(Vec3::new(-1.0, 1.0, 1.0));
    ms.z_axis.y = 0.4;
    ms.w_axis = glam::Vec4::new(-3.0, 0.0, 3.0, 1.0);
    s.instances.push(penumbra_scene::Instance::new(boxy, ms));
    s.lights.push(SceneLight {
        name: "bulb".into(),
        light: Light::Point(PointLight {
            position: Vec3::new(0.0, 4.0, 0.0),
            intensity: Rgb::new(10.0, 8.0, 6.0),
            range: f32::INFINITY,
        }),
    });
    s.lights.push(SceneLight {
        name: "spot".into(),
        light: Light::Spot(SpotLight {
            position: Vec3::new(2.0, 4.0, 2.0),
            direction: Vec3::new(-0.3, -1.0, -0.2).normalize(),
            intensity: Rgb::splat(30.0),
            cos_inner: 20f32.to_radians().cos(),
            cos_outer: 30f32.to_radians().cos(),
            range: 20.0,
        }),
    });
    s.lights.push(SceneLight {
        name: "sun".into(),
        light: Light::Directional(DirectionalLight {
            direction: Vec3::new(0.2, -1.0, 0.4).normalize(),
            irradiance: Rgb::splat(2.0),
        }),
    });
    s.area_lights.push(SceneAreaLight {
        name: "orb".into(),
        light: AreaLight {
            shape: Shape::Sphere {
                center: Vec3::new(0.0, 3.0, -3.0),
                radius: 0.3,
            },
            radiance: Rgb::splat(50.0),
            two_sided: false,
        },
    });
    s.camera = Some(Camera::look_at(
        Vec3::new(0.0, 5.0, 10.0),
        Vec3::ZERO,
        Vec3::Y,
        Projection::Orthographic { height: 8.0 },
    ));
    s.settings.width = 320;
    s.settings.height = 200;
    s
}

fn assorted() -> &'static (Scene, Bake) {
    static CELL: OnceLock<(Scene, Bake)> = OnceLock::new();
    CELL.get_or_init(|| {
        let scene = assorted_scene();
        let bake = small_bake(&scene, f32::INFINITY);
        (scene, bake)
    })
}

#[test]
fn every_material_model_lights_and_transforms_export() {
    let (scene, bake) = assorted();
    let (_dir, path, warnings) = write(bake, scene, "assorted.glb");
    for w in &warnings {
        println!("warning: {w}");
    }
    // Approximated: Phong–Blinn, the exact-Fresnel conductors, the mirror,
    // both dielectrics, the area light.
    for name in [
        "phong",
        "'gold'",
        "rough gold",
        "glass",
        "frosted",
        "mirror",
        "orb",
    ] {
        assert!(
            warnings.iter().any(|w| w.contains(name)),
            "no warning about {name}: {warnings:?}"
        );
    }
    assert!(
        !warnings
            .iter()
            .any(|w| w.contains("plastic") || w.contains("checker"))
    );
    assert_valid(&path);

    let loaded = penumbra_scene::load_scene(&path, &Default::default()).expect("loads");
    let orb = loaded.instances.len() - 1;
    assert_eq!(
        loaded.instances.len(),
        scene.instances.len() + 1,
        "+ the orb"
    );
    for (i, (a, b)) in scene.instances.iter().zip(&loaded.instances).enumerate() {
        let (ma, mb) = (&scene.meshes[a.mesh], &loaded.meshes[b.mesh]);
        assert_eq!(ma.indices.len(), mb.indices.len(), "instance {i}");
        // Same world-space triangles with the same front faces (sheared
        // transforms are applied to the vertices, mirrored ones keep their
        // winding).
        for (ta, tb) in ma.indices.iter().zip(&mb.indices) {
            let wa: Vec<Vec3> = ta
                .iter()
                .map(|&v| a.transform.transform_point3(ma.positions[v as usize]))
                .collect();
            let wb: Vec<Vec3> = tb
                .iter()
                .map(|&v| b.transform.transform_point3(mb.positions[v as usize]))
                .collect();
            let front = |w: &[Vec3], flip: bool| {
                let n = (w[1] - w[0]).cross(w[2] - w[0]).normalize();
                if flip { -n } else { n }
            };
            let (na, nb) = (front(&wa, a.flips_winding()), front(&wb, b.flips_winding()));
            assert!(na.dot(nb) > 0.999, "instance {i}: front {na} vs {nb}");
            let set = |w: &[Vec3]| {
                let mut v: Vec<[i64; 3]> = w
                    .iter()
                    .map(|p| (*p * 1e4).round().as_i64vec3().to_array())
                    .collect();
                v.sort();
                v
            };
            let (sa, sb) = (set(&wa), set(&wb));
            let close = sa
                .iter()
                .zip(&sb)
                .all(|(x, y)| x.iter().zip(y).all(|(p, q)| (p - q).abs() <= 2));
            assert!(close, "instance {i}: {wa:?} vs {wb:?}");
        }
        if let (Some(na), Some(nb)) = (&ma.normals, &mb.normals) {
            assert!(na.iter().all(|n| (n.length() - 1.0).abs() < 1e-3));
            assert!(nb.iter().all(|n| (n.length() - 1.0).abs() < 1e-5));
        } else {
            assert_eq!(ma.normals.is_some(), mb.normals.is_some(), "instance {i}");
        }
        let (xa, xb) = (scene.instance_material(a), loaded.instance_material(b));
        match (xa.bsdf, xb.bsdf) {
            (Bsdf::Lambert(p), Bsdf::Lambert(q)) => assert_eq!(p, q),
            (Bsdf::MetallicRoughness(p), Bsdf::MetallicRoughness(q)) => assert_eq!(p, q),
            (Bsdf::Lambert(_) | Bsdf::MetallicRoughness(_), other) => {
                panic!("material '{}' came back as {other:?}", xa.name)
            }
            _ => {}
        }
        assert_eq!(xa.albedo_texture.is_some(), xb.albedo_texture.is_some());
        assert!((xa.emission - xb.emission).abs().max_element() < 1e-5);
    }
    assert!(
        loaded
            .instance_material(&loaded.instances[orb])
            .is_emissive()
    );
    assert_eq!(loaded.lights.len(), 3);
    for (a, b) in scene.lights.iter().zip(&loaded.lights) {
        let rel = |x: Rgb, y: Rgb| (x - y).abs().max_element() / x.max_element();
        match (a.light, b.light) {
            (Light::Point(p), Light::Point(q)) => {
                assert!(rel(p.intensity, q.intensity) < 1e-5);
                assert!((p.position - q.position).length() < 1e-5);
            }
            (Light::Spot(p), Light::Spot(q)) => {
                assert!(rel(p.intensity, q.intensity) < 1e-5);
                assert!(p.direction.dot(q.direction) > 1.0 - 1e-6);
                assert!((p.cos_outer - q.cos_outer).abs() < 1e-5);
                assert!((p.cos_inner - q.cos_inner).abs() < 1e-5);
                assert!((p.range - q.range).abs() < 1e-4);
            }
            (Light::Directional(p), Light::Directional(q)) => {
                assert!(rel(p.irradiance, q.irradiance) < 1e-5);
                assert!(p.direction.dot(q.direction) > 1.0 - 1e-6);
            }
            (p, q) => panic!("light {p:?} came back as {q:?}"),
        }
    }
    let cam = loaded.camera.unwrap();
    assert_eq!(cam.projection, Projection::Orthographic { height: 8.0 });

    // TEXCOORD_1 of every instance is its own atlas rectangle.
    let exported = read_exported(&std::fs::read(&path).unwrap());
    for (i, e) in exported.iter().take(scene.instances.len()).enumerate() {
        // A mirroring transform applied to the vertices reverses the corners.
        let reversed = scene.instances[i].flips_winding() != loaded.instances[i].flips_winding();
        for (t, uv1) in e.corner_uv1.iter().enumerate() {
            let (_, [a, b, c]) = bake.atlas.triangle_uvs(scene, i, t).unwrap();
            let expected = if reversed { [a, c, b] } else { [a, b, c] };
            assert_eq!(*uv1, expected, "instance {i} triangle {t}");
        }
        assert_eq!(e.occlusion_tex_coord, 1);
    }
    // The orb (not in the atlas) has no occlusion.
    assert!(exported.last().unwrap().occlusion.is_none());
}

// --- errors ----------------------------------------------------------------

#[test]
fn a_non_ao_bake_is_refused_and_nothing_is_written() {
    let (scene, bake) = cornell();
    let mut not_ao = bake.clone();
    not_ao.kind = BakeKind::Lightmap {
        bounces: 1,
        indirect_only: false,
    };
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("out.glb");
    let err = write_glb(&not_ao, scene, &path).unwrap_err();
    assert!(matches!(err, BakeError::Settings(_)), "{err:?}");
    let msg = err.to_string();
    assert!(msg.contains("AO bake") && msg.contains("lightmap"), "{msg}");
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
}

#[test]
fn a_missing_folder_names_the_file_and_leaves_nothing() {
    let (scene, bake) = cornell();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("no-such-folder").join("out.glb");
    let err = write_glb(bake, scene, &path).unwrap_err();
    let msg = err.to_string();
    assert!(msg.contains(&path.display().to_string()), "{msg}");
    assert!(msg.contains("does not exist"), "{msg}");
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);

    // A folder in the way is refused too; an old file is replaced whole,
    // with no temporary file left beside it.
    let folder = dir.path().join("taken.glb");
    std::fs::create_dir(&folder).unwrap();
    let msg = write_glb(bake, scene, &folder).unwrap_err().to_string();
    assert!(msg.contains("taken.glb") && msg.contains("folder"), "{msg}");
    let file = dir.path().join("out.glb");
    std::fs::write(&file, b"old").unwrap();
    write_glb(bake, scene, &file).unwrap();
    assert_eq!(&std::fs::read(&file).unwrap()[..4], b"glTF");
    let mut names: Vec<String> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert_eq!(names, ["out.glb", "taken.glb"]);
}
