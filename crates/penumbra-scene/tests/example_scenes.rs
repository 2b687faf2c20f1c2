//! Every example scene under `scenes/` loads without errors or warnings, and
//! its materials are the models its comments promise.

use penumbra_scene::{LoadOptions, load_scene};
use penumbra_shading::bsdf::Bsdf;
use std::path::PathBuf;

fn scenes_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../scenes")
}

#[test]
fn every_example_scene_loads_cleanly() {
    let mut count = 0;
    for entry in std::fs::read_dir(scenes_dir()).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "toml") {
            let scene = load_scene(&path, &LoadOptions::default())
                .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
            assert!(
                scene.warnings.is_empty(),
                "{}: {:?}",
                path.display(),
                scene.warnings
            );
            assert!(scene.triangle_count() > 0);
            count += 1;
        }
    }
    assert!(count >= 3, "cornell-box, materials, whitted");
}

#[test]
fn materials_showcase_has_every_model_family() {
    let scene = load_scene(
        &scenes_dir().join("materials.toml"),
        &LoadOptions::default(),
    )
    .unwrap();
    let has = |f: fn(&Bsdf) -> bool| scene.materials.iter().any(|m| f(&m.bsdf));
    assert!(has(|b| matches!(b, Bsdf::Lambert(_))));
    assert!(has(|b| matches!(b, Bsdf::PhongBlinn(_))));
    assert!(has(|b| matches!(b, Bsdf::Conductor(_))));
    assert!(has(|b| matches!(b, Bsdf::RoughConductor(_))));
    assert!(has(|b| matches!(b, Bsdf::Dielectric(_))));
    assert!(has(|b| matches!(b, Bsdf::RoughDielectric(_))));
    assert!(has(|b| matches!(b, Bsdf::MetallicRoughness(_))));
    assert!(!scene.area_lights.is_empty());
}
