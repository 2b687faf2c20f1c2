//! Every ```toml block of docs/scene-format.md is a complete scene that
//! loads without errors or warnings, so the documentation cannot rot.

use penumbra_scene::builtin::CORNELL_BOX_TOML;
use penumbra_scene::load::{LoadOptions, load_toml_str};
use penumbra_scene::primitives::{
    DEFAULT_DISK_SEGMENTS, DEFAULT_SPHERE_RINGS, disk, sphere, surface_area,
};
use std::f32::consts::PI;
use std::path::PathBuf;

fn manifest() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// (first line number, text) of every fenced block tagged `lang`.
fn code_blocks(markdown: &str, lang: &str) -> Vec<(usize, String)> {
    let mut blocks = Vec::new();
    let mut current: Option<(usize, String)> = None;
    for (i, line) in markdown.lines().enumerate() {
        let fence = line.trim_start().strip_prefix("```");
        match (&mut current, fence) {
            (None, Some(tag)) if tag.trim() == lang => current = Some((i + 2, String::new())),
            (Some(_), Some(_)) => blocks.extend(current.take()),
            (Some((_, text)), None) => {
                text.push_str(line);
                text.push('\n');
            }
            _ => {}
        }
    }
    assert!(current.is_none(), "unclosed code block");
    blocks
}

#[test]
fn every_toml_example_in_the_docs_loads() {
    let doc_path = manifest().join("../../docs/scene-format.md");
    let markdown = std::fs::read_to_string(&doc_path).unwrap();
    let blocks = code_blocks(&markdown, "toml");
    assert!(
        blocks.len() >= 11,
        "found only {} toml blocks",
        blocks.len()
    );
    // Mesh paths in the examples resolve against the test corpus folder.
    let virtual_file = manifest().join("tests/corpus/toml/docs-example.toml");
    for (line, text) in &blocks {
        let scene = load_toml_str(text, &virtual_file, &LoadOptions::default())
            .unwrap_or_else(|e| panic!("docs/scene-format.md block at line {line}: {e}\n{text}"));
        assert!(
            scene.warnings.is_empty(),
            "docs/scene-format.md block at line {line}: {:?}",
            scene.warnings
        );
        assert!(!scene.instances.is_empty());
    }
}

#[test]
fn the_docs_cover_every_feature() {
    let markdown = std::fs::read_to_string(manifest().join("../../docs/scene-format.md")).unwrap();
    let all: String = code_blocks(&markdown, "toml")
        .into_iter()
        .map(|(_, t)| t)
        .collect();
    for needle in [
        "[camera]",
        "type = \"orthographic\"",
        "[render]",
        "resolution =",
        "spp =",
        "max_depth =",
        "integrator =",
        "seed =",
        "ao_distance =",
        "background =",
        "albedo =",
        "kd =",
        "emission =",
        "double_sided =",
        "type = \"point\"",
        "type = \"directional\"",
        "type = \"spot\"",
        "intensity =",
        "power =",
        "intensity_cd =",
        "power_lm =",
        "irradiance =",
        "illuminance_lux =",
        "inner_cone_deg =",
        "outer_cone_deg =",
        "color =",
        "type = \"sphere\"",
        "type = \"disk\"",
        "type = \"quad\"",
        "radiance =",
        "luminance_nits =",
        "two_sided =",
        "[environment]",
        "type = \"constant\"",
        "type = \"map\"",
        "file =",
        "rotate_deg = 90",
        "shape = \"sphere\"",
        "subdivisions =",
        "shape = \"quad\"",
        "corner =",
        "edge1 =",
        "vertices =",
        "shape = \"box\"",
        "min =",
        "max =",
        "shape = \"disk\"",
        "normal =",
        "segments =",
        "mesh = \"meshes/tetra.obj\"",
        "mesh = \"meshes/triangle.gltf\"",
        "translate =",
        "rotate_deg =",
        "rotate_axis_angle =",
        "scale =",
        "matrix =",
    ] {
        assert!(all.contains(needle), "no docs example uses {needle}");
    }
    // The built-in scene the docs point to is the one compiled in.
    let file = std::fs::read_to_string(manifest().join("../../scenes/cornell-box.toml")).unwrap();
    assert_eq!(file, CORNELL_BOX_TOML);
}

#[test]
fn tessellation_errors_quoted_in_the_docs() {
    // "0.3 % and 0.16 % at the defaults".
    let s = surface_area(&sphere(glam::Vec3::ZERO, 1.0, DEFAULT_SPHERE_RINGS));
    let e = (4.0 * PI - s) / (4.0 * PI);
    assert!(e > 0.002 && e < 0.0035, "sphere {e}");
    let d = surface_area(&disk(
        glam::Vec3::ZERO,
        glam::Vec3::Y,
        1.0,
        DEFAULT_DISK_SEGMENTS,
    ));
    let e = (PI - d) / PI;
    assert!((e - 0.0016).abs() < 0.00005, "disk {e}");
}
