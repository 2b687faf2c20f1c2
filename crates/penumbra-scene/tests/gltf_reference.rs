//! The two reference scenes load from glTF and agree with their neutral
//! description (`scene.json`, radiometric units) and the world-space OBJ
//! meshes beside them.

use glam::Vec3;
use gltf::json::Value;
use penumbra_scene::load::{LoadOptions, load_gltf, load_obj};
use penumbra_scene::{Projection, Scene};
use penumbra_shading::bsdf::Bsdf;
use penumbra_shading::light::Light;
use std::path::{Path, PathBuf};

fn reference(rel: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../../shared/reference")
        .join(rel)
}

fn scene_json(folder: &str) -> Value {
    let bytes = std::fs::read(reference(&format!("{folder}/scene.json"))).unwrap();
    gltf::json::deserialize::from_slice(&bytes).unwrap()
}

fn vec3(v: &Value) -> Vec3 {
    let a = v.as_array().expect("array of 3 numbers");
    Vec3::new(
        a[0].as_f64().unwrap() as f32,
        a[1].as_f64().unwrap() as f32,
        a[2].as_f64().unwrap() as f32,
    )
}

fn close(a: Vec3, b: Vec3, rel: f32) -> bool {
    (a - b).abs().max_element() <= rel * b.abs().max_element().max(1.0)
}

/// World-space triangles of the instances whose mesh is named `name`, each
/// rotated to start at its smallest vertex (winding kept), sorted.
fn world_triangles(scene: &Scene, name: &str) -> Vec<[Vec3; 3]> {
    let mut out = Vec::new();
    for inst in &scene.instances {
        let mesh = &scene.meshes[inst.mesh];
        if mesh.name != name {
            continue;
        }
        for t in &mesh.indices {
            let p = t.map(|i| inst.transform.transform_point3(mesh.positions[i as usize]));
            out.push(canonical(p));
        }
    }
    out.sort_by(|a, b| key(a).partial_cmp(&key(b)).unwrap());
    out
}

fn canonical(p: [Vec3; 3]) -> [Vec3; 3] {
    let k = |v: Vec3| (v.x, v.y, v.z);
    let first = (0..3)
        .min_by(|&a, &b| k(p[a]).partial_cmp(&k(p[b])).unwrap())
        .unwrap();
    [p[first], p[(first + 1) % 3], p[(first + 2) % 3]]
}

fn key(t: &[Vec3; 3]) -> [f32; 9] {
    [
        t[0].x, t[0].y, t[0].z, t[1].x, t[1].y, t[1].z, t[2].x, t[2].y, t[2].z,
    ]
}

/// Checks camera, objects (geometry against the OBJ files, materials) and
/// returns the loaded scene for scene-specific checks.
fn check_scene(folder: &str) -> (Scene, Value) {
    let path = reference(&format!("{folder}/{folder}.gltf"));
    let scene = load_gltf(&path, &LoadOptions::default()).unwrap();
    let json = scene_json(folder);
    assert!(
        scene.warnings.is_empty(),
        "the references are exactly representable: {:?}",
        scene.warnings
    );

    // Camera.
    let cam = scene.camera.expect("camera");
    let jc = &json["camera"];
    let eye = vec3(&jc["position"]);
    let forward = (vec3(&jc["look_at"]) - eye).normalize();
    assert!(
        close(cam.position(), eye, 1e-5),
        "{} vs {eye}",
        cam.position()
    );
    let cam_forward = -cam.camera_to_world.z_axis.truncate();
    assert!(
        (cam_forward - forward).length() < 1e-5,
        "{cam_forward} vs {forward}"
    );
    assert!(cam.camera_to_world.y_axis.truncate().dot(vec3(&jc["up"])) > 0.9);
    let fov = (jc["fov_y_deg"].as_f64().unwrap() as f32).to_radians();
    match cam.projection {
        Projection::Perspective { fov_y } => assert!((fov_y - fov).abs() < 1e-5),
        p => panic!("expected a perspective camera, got {p:?}"),
    }
    let res = jc["resolution"].as_array().unwrap();
    assert_eq!(scene.settings.width, res[0].as_u64().unwrap() as u32);
    assert_eq!(scene.settings.height, res[1].as_u64().unwrap() as u32);

    // Objects: one instance each, geometry identical to the OBJ mesh.
    let objects = json["objects"].as_array().unwrap();
    let mut total = 0;
    for o in objects {
        let name = o["name"].as_str().unwrap();
        let insts: Vec<_> = scene
            .instances
            .iter()
            .filter(|i| scene.meshes[i.mesh].name == name)
            .collect();
        assert_eq!(insts.len(), 1, "{name}");
        let inst = insts[0];
        let mesh = &scene.meshes[inst.mesh];

        let obj_path = reference(&format!("{folder}/{}", o["mesh"].as_str().unwrap()));
        let obj = load_obj(&obj_path, &LoadOptions::default()).unwrap();
        assert_eq!(mesh.indices.len(), obj.triangle_count(), "{name}");
        total += obj.triangle_count();
        let from_gltf = world_triangles(&scene, name);
        let mut from_obj: Vec<[Vec3; 3]> = Vec::new();
        for m in &obj.meshes {
            for t in &m.indices {
                from_obj.push(canonical(t.map(|i| m.positions[i as usize])));
            }
        }
        from_obj.sort_by(|a, b| key(a).partial_cmp(&key(b)).unwrap());
        for (a, b) in from_gltf.iter().zip(&from_obj) {
            for k in 0..3 {
                assert!(close(a[k], b[k], 1e-5), "{name}: {a:?} vs {b:?}");
            }
        }

        // Material.
        let mat = scene.instance_material(inst);
        let Bsdf::Lambert(l) = mat.bsdf else {
            panic!("{}: expected Lambert, got {:?}", mat.name, mat.bsdf)
        };
        assert!(close(l.albedo, vec3(&o["albedo"]), 1e-6), "{name}");
        let emission = vec3(&o["emission"]);
        assert!(
            close(mat.emission, emission, 1e-5),
            "{name}: {}",
            mat.emission
        );
        // Emitters are front-side only; the rest two-sided.
        assert_eq!(mat.double_sided, emission.max_element() == 0.0, "{name}");

        // Smooth objects carry vertex normals; the others are flat.
        let smooth = o["smooth"].as_bool().unwrap();
        assert_eq!(mesh.normals.is_some(), smooth, "{name}");
        if let Some(n) = &mesh.normals {
            assert_eq!(n.len(), mesh.positions.len());
            assert!(n.iter().all(|v| (v.length() - 1.0).abs() < 1e-3));
        }
    }
    assert_eq!(scene.triangle_count(), total);
    assert_eq!(scene.instances.len(), objects.len());
    (scene, json)
}

#[test]
fn cornell_box_loads_like_its_scene_json() {
    let (scene, json) = check_scene("cornell");
    assert_eq!(scene.triangle_count(), 32);
    assert!(scene.lights.is_empty());
    assert!(json["lights"].as_array().unwrap().is_empty());

    let light = scene
        .instances
        .iter()
        .find(|i| scene.meshes[i.mesh].name == "light")
        .unwrap();
    let mat = scene.instance_material(light);
    assert!(close(
        mat.emission,
        Vec3::new(18.387, 13.9873, 6.75357),
        1e-5
    ));
    assert!(!mat.double_sided);
    // The area light's front side (counter-clockwise) faces down, into the box.
    let mesh = &scene.meshes[light.mesh];
    for t in &mesh.indices {
        let p = t.map(|i| light.transform.transform_point3(mesh.positions[i as usize]));
        let n = (p[1] - p[0]).cross(p[2] - p[0]).normalize();
        assert!(n.dot(-Vec3::Y) > 0.999, "{n}");
    }
}

#[test]
fn spheres_direct_loads_like_its_scene_json() {
    let (scene, json) = check_scene("spheres-direct");
    assert_eq!(scene.triangle_count(), 2 + 3 * 5120);
    // One mesh per primitive, each sphere with smooth normals pointing out.
    for name in ["sphere_red", "sphere_green", "sphere_blue"] {
        let mesh = scene.meshes.iter().find(|m| m.name == name).unwrap();
        let normals = mesh.normals.as_ref().expect("smooth normals");
        let (lo, hi) = mesh.bounds();
        let centre = 0.5 * (lo + hi);
        for (p, n) in mesh.positions.iter().zip(normals) {
            assert!((*p - centre).normalize().dot(*n) > 0.99);
        }
    }

    let jlights = json["lights"].as_array().unwrap();
    assert_eq!(scene.lights.len(), jlights.len());
    for jl in jlights {
        match jl["type"].as_str().unwrap() {
            "point" => {
                let l = scene
                    .lights
                    .iter()
                    .find_map(|l| match l.light {
                        Light::Point(p) => Some(p),
                        _ => None,
                    })
                    .unwrap();
                assert!(close(l.position, vec3(&jl["position"]), 1e-6));
                // W/sr = cd / 683, with the colour.
                assert!(
                    close(l.intensity, vec3(&jl["intensity"]), 1e-5),
                    "{}",
                    l.intensity
                );
            }
            "directional" => {
                let l = scene
                    .lights
                    .iter()
                    .find_map(|l| match l.light {
                        Light::Directional(d) => Some(d),
                        _ => None,
                    })
                    .unwrap();
                // W/m² = lux / 683; direction of travel = the node's −Z.
                assert!(
                    close(l.irradiance, vec3(&jl["irradiance"]), 1e-5),
                    "{}",
                    l.irradiance
                );
                assert!(
                    (l.direction - vec3(&jl["direction"])).length() < 1e-5,
                    "{}",
                    l.direction
                );
            }
            other => panic!("unexpected light type {other}"),
        }
    }
}
