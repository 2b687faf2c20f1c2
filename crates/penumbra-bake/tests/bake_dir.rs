//! Bake directories: written whole or not at all, read back exactly, and
//! every kind of bad input refused with an error that names the file and
//! what is wrong.

use glam::Vec3;
use penumbra_bake::{
    AoSettings, AtlasSettings, BakeError, Density, LightmapSettings, bake_ao, bake_lightmap,
    read_bake, write_bake,
};
use penumbra_scene::{Material, Scene, builtin};
use std::path::Path;

fn small() -> AtlasSettings {
    AtlasSettings {
        density: Density::MaxSize(32),
        ..Default::default()
    }
}

fn ao_settings() -> AoSettings {
    AoSettings {
        samples: 4,
        distance: 50.0,
        seed: 0,
    }
}

/// A written AO bake of the Cornell box in `dir/name`.
fn written(dir: &Path, name: &str) -> (Scene, std::path::PathBuf) {
    let scene = builtin::cornell_box();
    let bake = bake_ao(&scene, &ao_settings(), &small(), None).unwrap();
    let path = dir.join(name);
    write_bake(&bake, &scene, &path, Some("cornell")).unwrap();
    (scene, path)
}

fn names(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

fn error_of(r: Result<penumbra_bake::LoadedBake, BakeError>) -> String {
    r.map(|_| ()).unwrap_err().to_string()
}

#[test]
fn a_bake_reads_back_exactly() {
    let dir = tempfile::tempdir().unwrap();
    let scene = builtin::cornell_box();
    let bake = bake_lightmap(
        &scene,
        &LightmapSettings {
            samples: 2,
            per_light: true,
            ..Default::default()
        },
        &small(),
        None,
    )
    .unwrap();
    let path = dir.path().join("lm");
    write_bake(&bake, &scene, &path, None).unwrap();
    assert_eq!(names(dir.path()), ["lm"], "no staging folder left behind");
    let back = read_bake(&path, &scene).unwrap();
    assert_eq!(back.kind, bake.kind);
    assert_eq!(back.atlas, bake.atlas);
    assert_eq!(back.pages[0].pixels, bake.maps[0].pages[0].pixels);
    assert_eq!(back.coverage[0].pixels, bake.coverage[0].pixels);
    assert_eq!(back.manifest.maps.len(), bake.maps.len());
    assert_eq!(back.manifest.units, "W/m^2");
}

#[test]
fn a_bake_for_another_scene_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let (_, path) = written(dir.path(), "ao");
    let mut other = builtin::cornell_box();
    other.instances[0].transform = glam::Mat4::from_translation(Vec3::X);
    let e = error_of(read_bake(&path, &other));
    assert!(
        e.contains("manifest.json") && e.contains("another scene") && e.contains("cornell"),
        "{e}"
    );
}

#[test]
fn missing_or_truncated_pages_and_layouts_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let (scene, path) = written(dir.path(), "ao");
    let page = path.join("total-0.exr");
    let bytes = std::fs::read(&page).unwrap();
    std::fs::write(&page, &bytes[..bytes.len() / 2]).unwrap();
    let e = error_of(read_bake(&path, &scene));
    assert!(e.contains("total-0.exr"), "{e}");
    std::fs::remove_file(&page).unwrap();
    let e = error_of(read_bake(&path, &scene));
    assert!(e.contains("total-0.exr"), "{e}");

    let (scene, path) = written(dir.path(), "ao2");
    let uvs = path.join("uvs.bin");
    let bytes = std::fs::read(&uvs).unwrap();
    std::fs::write(&uvs, &bytes[..bytes.len() - 8]).unwrap();
    let e = error_of(read_bake(&path, &scene));
    assert!(e.contains("uvs.bin") && e.contains("truncated"), "{e}");
}

#[test]
fn manifests_of_other_versions_or_formats_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let (scene, path) = written(dir.path(), "ao");
    let manifest = path.join("manifest.json");
    let text = std::fs::read_to_string(&manifest).unwrap();
    std::fs::write(&manifest, text.replace("\"version\": 1", "\"version\": 99")).unwrap();
    let e = error_of(read_bake(&path, &scene));
    assert!(
        e.contains("manifest.json") && e.contains("version 99"),
        "{e}"
    );
    std::fs::write(&manifest, text.replace("penumbra-bake", "something-else")).unwrap();
    let e = error_of(read_bake(&path, &scene));
    assert!(e.contains("not a penumbra bake manifest"), "{e}");
    std::fs::write(&manifest, &text[..text.len() / 2]).unwrap();
    let e = error_of(read_bake(&path, &scene));
    assert!(e.contains("not valid JSON"), "{e}");
    let e = error_of(read_bake(dir.path(), &scene));
    assert!(e.contains("manifest"), "{e}");
}

#[test]
fn bad_settings_are_refused_before_any_work() {
    let scene = builtin::cornell_box();
    let atlas = |density| AtlasSettings {
        density,
        ..Default::default()
    };
    let cases: Vec<(Result<penumbra_bake::Bake, BakeError>, &str)> = vec![
        (
            bake_ao(
                &scene,
                &AoSettings {
                    samples: 0,
                    ..ao_settings()
                },
                &small(),
                None,
            ),
            "--samples",
        ),
        (
            bake_ao(
                &scene,
                &AoSettings {
                    distance: -1.0,
                    ..ao_settings()
                },
                &small(),
                None,
            ),
            "--ao-distance",
        ),
        (
            bake_ao(
                &scene,
                &AoSettings {
                    distance: f32::NAN,
                    ..ao_settings()
                },
                &small(),
                None,
            ),
            "--ao-distance",
        ),
        (
            bake_ao(
                &scene,
                &ao_settings(),
                &atlas(Density::TexelsPerUnit(0.0)),
                None,
            ),
            "texels per unit",
        ),
        (
            bake_ao(
                &scene,
                &ao_settings(),
                &atlas(Density::TexelsPerUnit(-2.0)),
                None,
            ),
            "texels per unit",
        ),
        (
            bake_ao(&scene, &ao_settings(), &atlas(Density::MaxSize(4)), None),
            "atlas size",
        ),
        (
            bake_ao(
                &scene,
                &ao_settings(),
                &AtlasSettings {
                    padding: 0,
                    ..small()
                },
                None,
            ),
            "padding",
        ),
        (
            bake_lightmap(
                &scene,
                &LightmapSettings {
                    samples: 0,
                    ..Default::default()
                },
                &small(),
                None,
            ),
            "--samples",
        ),
        // 10⁶ texels per mm over the Cornell box: refused from the area
        // alone, before the packer would allocate anything.
        (
            bake_ao(
                &scene,
                &ao_settings(),
                &atlas(Density::TexelsPerUnit(1e6)),
                None,
            ),
            "more than one 8192x8192 page",
        ),
        (
            bake_ao(
                &scene,
                &ao_settings(),
                &atlas(Density::TexelsPerUnitPaged {
                    texels_per_unit: 1e6,
                    page: 4096,
                }),
                None,
            ),
            "texels a bake may have",
        ),
    ];
    for (result, expected) in cases {
        let e = result.map(|_| ()).unwrap_err().to_string();
        assert!(e.contains(expected), "'{e}' should mention '{expected}'");
    }
    let mut empty = Scene::default();
    empty.add_material(Material::default_grey());
    let e = bake_ao(&empty, &ao_settings(), &small(), None)
        .map(|_| ())
        .unwrap_err()
        .to_string();
    assert!(e.contains("no surfaces"), "{e}");
}

#[test]
fn outputs_that_are_files_or_foreign_folders_are_refused_and_bakes_replaced() {
    let dir = tempfile::tempdir().unwrap();
    let scene = builtin::cornell_box();
    let bake = bake_ao(&scene, &ao_settings(), &small(), None).unwrap();
    let file = dir.path().join("a-file");
    std::fs::write(&file, "x").unwrap();
    let e = write_bake(&bake, &scene, &file, None)
        .unwrap_err()
        .to_string();
    assert!(e.contains("a-file") && e.contains("not a directory"), "{e}");
    let foreign = dir.path().join("photos");
    std::fs::create_dir(&foreign).unwrap();
    std::fs::write(foreign.join("cat.jpg"), "x").unwrap();
    let e = write_bake(&bake, &scene, &foreign, None)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("photos") && e.contains("neither empty nor a bake"),
        "{e}"
    );
    assert_eq!(names(&foreign), ["cat.jpg"]);
    let e = write_bake(&bake, &scene, &dir.path().join("no/such/bake"), None)
        .unwrap_err()
        .to_string();
    assert!(e.contains("does not exist"), "{e}");
    // An earlier bake is replaced whole.
    let path = dir.path().join("ao");
    write_bake(&bake, &scene, &path, None).unwrap();
    std::fs::write(path.join("stale.txt"), "old").unwrap();
    write_bake(&bake, &scene, &path, None).unwrap();
    assert!(!path.join("stale.txt").exists());
    assert_eq!(names(dir.path()), ["a-file", "ao", "photos"]);
}
