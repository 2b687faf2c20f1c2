//! The built-in Cornell box against the reference scene
//! (`shared/reference/cornell/scene.json` and its OBJ files).

use glam::Vec3;
use penumbra_scene::builtin::{CORNELL_BOX_PATH, CORNELL_BOX_TOML, cornell_box};
use penumbra_scene::{IntegratorKind, Projection, Scene};
use std::path::PathBuf;

fn reference_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../../shared/reference/cornell")
}

/// The reference scene.json; a missing reference is a failure, not a
/// skipped check.
fn scene_json() -> String {
    let path = reference_dir().join("scene.json");
    std::fs::read_to_string(&path).unwrap_or_else(|e| {
        panic!(
            "{}: {e} (the shared reference scenes are needed)",
            path.display()
        )
    })
}

/// The numbers of the first `"key": [ … ]` or `"key": n` in `text`.
fn json_numbers(text: &str, key: &str) -> Vec<f64> {
    let pat = format!("\"{key}\":");
    let start = text.find(&pat).unwrap_or_else(|| panic!("no {key}")) + pat.len();
    let rest = text[start..].trim_start();
    let body = if let Some(r) = rest.strip_prefix('[') {
        &r[..r.find(']').unwrap()]
    } else {
        &rest[..rest.find([',', '}', '\n']).unwrap()]
    };
    body.split(',').map(|s| s.trim().parse().unwrap()).collect()
}

fn v3(v: &[f64]) -> Vec3 {
    Vec3::new(v[0] as f32, v[1] as f32, v[2] as f32)
}

/// Per reference object: (name, albedo, emission).
fn reference_objects(json: &str) -> Vec<(String, Vec3, Vec3)> {
    let objects = &json[json.find("\"objects\"").unwrap()..];
    objects
        .split("\"name\":")
        .skip(1)
        .map(|chunk| {
            let name = chunk.split('"').nth(1).unwrap().to_string();
            (
                name,
                v3(&json_numbers(chunk, "albedo")),
                v3(&json_numbers(chunk, "emission")),
            )
        })
        .collect()
}

/// World-space triangles of the instance whose mesh is named `name`.
fn triangles(scene: &Scene, name: &str) -> Vec<[Vec3; 3]> {
    let inst = scene
        .instances
        .iter()
        .find(|i| scene.meshes[i.mesh].name == name)
        .unwrap_or_else(|| panic!("no object {name}"));
    let m = &scene.meshes[inst.mesh];
    m.indices
        .iter()
        .map(|t| t.map(|i| inst.transform.transform_point3(m.positions[i as usize])))
        .collect()
}

fn obj_triangles(name: &str) -> Vec<[Vec3; 3]> {
    let path = reference_dir().join(format!("{name}.obj"));
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| {
        panic!(
            "{}: {e} (the shared reference scenes are needed)",
            path.display()
        )
    });
    let mut v = Vec::new();
    let mut tris = Vec::new();
    for (n, line) in text.lines().enumerate() {
        let bad = || format!("{}:{}: cannot read '{line}'", path.display(), n + 1);
        let mut it = line.split_whitespace();
        match it.next() {
            Some("v") => {
                let mut c = [0f32; 3];
                for x in &mut c {
                    *x = it
                        .next()
                        .and_then(|t| t.parse().ok())
                        .unwrap_or_else(|| panic!("{}", bad()));
                }
                v.push(Vec3::from(c));
            }
            Some("f") => {
                let idx: Vec<usize> = it
                    .map(|s| {
                        s.parse::<usize>()
                            .ok()
                            .and_then(|i| i.checked_sub(1))
                            .unwrap_or_else(|| panic!("{}", bad()))
                    })
                    .collect();
                assert!(
                    idx.len() == 3 && idx.iter().all(|&i| i < v.len()),
                    "{}",
                    bad()
                );
                tris.push([v[idx[0]], v[idx[1]], v[idx[2]]]);
            }
            _ => {}
        }
    }
    assert!(!tris.is_empty(), "{}: no triangles", path.display());
    tris
}

#[test]
fn loads_with_the_reference_settings() {
    let s = cornell_box();
    assert!(s.warnings.is_empty(), "{:?}", s.warnings);
    assert_eq!((s.settings.width, s.settings.height), (512, 512));
    assert_eq!(s.settings.integrator, IntegratorKind::Path);
    assert_eq!(s.settings.max_depth, 8);
    assert_eq!(s.settings.spp, 64);
    assert_eq!(s.background, Vec3::ZERO);
    assert!(s.lights.is_empty());
    assert_eq!(s.instances.len(), 8);
    // Walls and light: 2 triangles each; blocks: 12 each.
    assert_eq!(s.triangle_count(), 6 * 2 + 2 * 12);
    assert!(CORNELL_BOX_TOML.contains("[camera]"));
    assert!(
        !CORNELL_BOX_TOML.contains("mesh ="),
        "must be self-contained"
    );
    assert_eq!(CORNELL_BOX_PATH, "<builtin>/cornell-box.toml");
    for m in &s.meshes {
        m.validate().unwrap();
    }
}

#[test]
fn camera_matches_scene_json() {
    let json = scene_json();
    let cam_json = &json[json.find("\"camera\"").unwrap()..];
    let pos = v3(&json_numbers(cam_json, "position"));
    let look = v3(&json_numbers(cam_json, "look_at"));
    let up = v3(&json_numbers(cam_json, "up"));
    let fov = json_numbers(cam_json, "fov_y_deg")[0];
    let res = json_numbers(cam_json, "resolution");
    let s = cornell_box();
    let cam = s.camera.expect("the built-in scene has a camera");
    let Projection::Perspective { fov_y } = cam.projection else {
        panic!("perspective expected");
    };
    assert!((fov_y as f64 - fov.to_radians()).abs() < 1e-6);
    assert_eq!(cam.position(), pos);
    let expected = penumbra_scene::Camera::look_at(pos, look, up, cam.projection);
    assert!(
        cam.camera_to_world
            .abs_diff_eq(expected.camera_to_world, 1e-6)
    );
    // The centre ray looks along +z (towards look_at), row 0 is the top.
    let (o, d) = cam.generate_ray(256.0, 256.0, 512, 512);
    assert_eq!(o, pos);
    assert!((d - (look - pos).normalize()).length() < 1e-6);
    assert!(cam.generate_ray(256.0, 0.0, 512, 512).1.y > 0.0);
    assert_eq!(
        (s.settings.width, s.settings.height),
        (res[0] as u32, res[1] as u32)
    );
}

#[test]
fn one_front_side_emitter_facing_down() {
    let s = cornell_box();
    let emissive: Vec<_> = s.materials.iter().filter(|m| m.is_emissive()).collect();
    assert_eq!(emissive.len(), 1);
    let light = emissive[0];
    assert_eq!(light.emission, Vec3::new(18.387, 13.9873, 6.75357));
    assert!(!light.double_sided, "emission is front side only");
    assert_eq!(light.bsdf.albedo(), Vec3::ZERO);
    let emitters: Vec<_> = s
        .instances
        .iter()
        .filter(|i| s.instance_material(i).is_emissive())
        .collect();
    assert_eq!(emitters.len(), 1);
    let tris = triangles(&s, "light");
    let mut area = 0.0;
    for [a, b, c] in tris {
        let n = (b - a).cross(c - a);
        area += 0.5 * n.length();
        assert!(
            n.normalize().abs_diff_eq(-Vec3::Y, 1e-6),
            "emitter normal {n} must point down"
        );
    }
    assert!((area - 130.0 * 105.0).abs() < 0.1, "{area}");
    for m in &s.materials {
        if !m.is_emissive() {
            assert!(m.double_sided);
        }
    }
}

#[test]
fn albedos_and_emission_match_scene_json() {
    let s = cornell_box();
    for (name, albedo, emission) in reference_objects(&scene_json()) {
        let inst = s
            .instances
            .iter()
            .find(|i| s.meshes[i.mesh].name == name)
            .unwrap_or_else(|| panic!("no object {name}"));
        let m = s.instance_material(inst);
        assert_eq!(m.bsdf.albedo(), albedo, "{name}");
        assert_eq!(m.emission, emission, "{name}");
    }
}

#[test]
fn walls_and_light_are_the_reference_quads() {
    let s = cornell_box();
    for name in [
        "floor",
        "ceiling",
        "backwall",
        "redwall",
        "greenwall",
        "light",
    ] {
        let reference = obj_triangles(name);
        let ours = triangles(&s, name);
        assert_eq!(ours.len(), reference.len(), "{name}");
        for (t, r) in ours.iter().zip(&reference) {
            for k in 0..3 {
                assert!(t[k].abs_diff_eq(r[k], 1e-3), "{name}: {:?} vs {:?}", t, r);
            }
        }
    }
}

#[test]
fn blocks_match_the_reference_within_a_millimetre_or_so() {
    let s = cornell_box();
    for (name, height) in [("shortbox", 165.0), ("tallbox", 330.0)] {
        let ours: Vec<Vec3> = triangles(&s, name).into_iter().flatten().collect();
        let (lo, hi) = ours.iter().fold(
            (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)),
            |(lo, hi), p| (lo.min(*p), hi.max(*p)),
        );
        assert!(lo.y.abs() < 1e-3 && (hi.y - height).abs() < 1e-3, "{name}");
        let reference = obj_triangles(name);
        // Every reference vertex has one of ours within 1.5 mm, and back.
        let near = |p: &Vec3, set: &[Vec3]| {
            set.iter()
                .map(|q| q.distance(*p))
                .fold(f32::INFINITY, f32::min)
        };
        let refs: Vec<Vec3> = reference.into_iter().flatten().collect();
        let worst = refs.iter().map(|p| near(p, &ours)).fold(0.0, f32::max);
        assert!(worst < 1.5, "{name}: reference corner {worst} mm away");
        let worst = ours.iter().map(|p| near(p, &refs)).fold(0.0, f32::max);
        assert!(worst < 1.5, "{name}: our corner {worst} mm away");
        // Closed and outward.
        let m = &s.meshes[s
            .instances
            .iter()
            .find(|i| s.meshes[i.mesh].name == name)
            .unwrap()
            .mesh];
        assert!(penumbra_scene::primitives::signed_volume(m) > 0.0);
    }
}
