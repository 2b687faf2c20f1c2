//! The reference scenes' OBJ meshes load through `load_obj`.

use glam::Vec3;
use penumbra_scene::load::{LoadOptions, load_obj, load_scene};
use std::path::{Path, PathBuf};

fn reference(rel: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../../shared/reference")
        .join(rel)
}

/// Counts `v`, `vn` and `f` statements.
fn count(path: &Path) -> (usize, usize, usize) {
    let text = std::fs::read_to_string(path).unwrap();
    let n = |k: &str| {
        text.lines()
            .filter(|l| l.split_whitespace().next() == Some(k))
            .count()
    };
    (n("v"), n("vn"), n("f"))
}

#[test]
fn cornell_floor_obj() {
    let path = reference("cornell/floor.obj");
    let scene = load_obj(&path, &LoadOptions::default()).unwrap();
    assert!(scene.camera.is_none(), "an OBJ has no camera");
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    assert_eq!(scene.triangle_count(), 2);
    assert_eq!(scene.instances.len(), 1);
    let mesh = &scene.meshes[0];
    assert!(mesh.normals.is_none());
    let expected = [
        Vec3::new(552.8, 0.0, 0.0),
        Vec3::new(0.0, 0.0, 0.0),
        Vec3::new(0.0, 0.0, 559.2),
        Vec3::new(549.6, 0.0, 559.2),
    ];
    for p in &expected {
        assert!(
            mesh.positions.iter().any(|q| (*q - *p).length() < 1e-4),
            "{p}"
        );
    }
    // Faces are counter-clockwise seen from above: the floor faces up.
    for t in &mesh.indices {
        let p = t.map(|i| mesh.positions[i as usize]);
        assert!((p[1] - p[0]).cross(p[2] - p[0]).normalize().dot(Vec3::Y) > 0.999);
    }
    // Without a material library: the default grey material.
    assert_eq!(scene.materials[mesh.material].name, "default");
    // load_scene dispatches on the extension.
    let again = load_scene(&path, &LoadOptions::default()).unwrap();
    assert_eq!(again.triangle_count(), 2);
}

#[test]
fn every_reference_obj_loads_with_its_faces_and_normals() {
    for folder in ["cornell", "spheres-direct"] {
        let mut files: Vec<PathBuf> = std::fs::read_dir(reference(folder))
            .unwrap()
            .map(|e| e.unwrap().path())
            .filter(|p| p.extension().is_some_and(|e| e == "obj"))
            .collect();
        files.sort();
        assert!(!files.is_empty());
        for path in files {
            let (_, vn, f) = count(&path);
            let scene = load_obj(&path, &LoadOptions::default()).unwrap();
            assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
            assert_eq!(scene.triangle_count(), f, "{}", path.display());
            for m in &scene.meshes {
                assert_eq!(m.normals.is_some(), vn > 0, "{}", path.display());
                m.validate().unwrap();
            }
        }
    }
}
