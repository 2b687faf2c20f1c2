//! Khronos glTF sample models (../shared/gltf-samples) as the loader reads
//! them: every triangle topology (MeshPrimitiveModes) and
//! `KHR_materials_unlit` (UnlitTest).

use glam::Vec3;
use penumbra_scene::{LoadOptions, Scene, load_scene};
use penumbra_shading::bsdf::Bsdf;
use std::path::Path;

fn load(rel: &str) -> Scene {
    let file = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../../shared/gltf-samples")
        .join(rel);
    load_scene(&file, &LoadOptions::default()).unwrap_or_else(|e| panic!("{rel}: {e}"))
}

/// MeshPrimitiveModes: seven meshes over the same regular hexagon (centre
/// vertex 0, corners 1..6), one per glTF mode. TRIANGLES, TRIANGLE_STRIP
/// and TRIANGLE_FAN each cover it exactly: their triangles' areas, signed
/// along the common facing, add up to the hexagon's, and none is turned
/// over (a strip read without alternating the winding flips every second
/// triangle). The points and lines are skipped with one warning.
#[test]
fn strips_and_fans_cover_the_same_hexagon_as_triangles() {
    let scene = load("MeshPrimitiveModes/glTF/MeshPrimitiveModes.gltf");
    assert_eq!(scene.meshes.len(), 3, "{:?}", scene.warnings);
    let warned = scene.warnings.join("\n");
    assert!(
        warned.contains("skipped 4 primitive(s) of points or lines"),
        "{warned}"
    );
    // The hexagon's circumradius from its corners (the same positions in
    // every mesh), and its area 3√3/2 r².
    let corners = &scene.meshes[0].positions[1..7];
    let centre = scene.meshes[0].positions[0];
    let r = (corners[0] - centre).length();
    let hexagon = 1.5 * 3f32.sqrt() * r * r;
    let mut facing = None;
    for mesh in &scene.meshes {
        let p = &mesh.positions;
        let normals: Vec<Vec3> = mesh
            .indices
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|i| p[i as usize]);
                0.5 * (b - a).cross(c - a)
            })
            .collect();
        let up = *facing.get_or_insert(normals[0].normalize());
        let signed: f32 = normals.iter().map(|n| n.dot(up)).sum();
        let turned = normals.iter().filter(|n| n.dot(up) <= 0.0).count();
        assert_eq!(turned, 0, "{}: {turned} triangle(s) turned over", mesh.name);
        assert!(
            (signed - hexagon).abs() < 1e-4 * hexagon,
            "{}: area {signed} vs the hexagon's {hexagon}",
            mesh.name
        );
    }
    let counts: Vec<usize> = scene.meshes.iter().map(|m| m.indices.len()).collect();
    // TRIANGLES 18 indices, strip of 6 vertices, fan of 8: 6, 4 and 6.
    assert_eq!(counts, [6, 4, 6]);
}

/// UnlitTest: two unlit materials (orange and blue base colours) become
/// emitters of exactly their base colour that reflect nothing.
#[test]
fn unlit_materials_emit_their_base_colour() {
    let scene = load("UnlitTest/glTF/UnlitTest.gltf");
    let srgb_orange = Vec3::new(1.0, 0.217_637_64, 0.0);
    let srgb_blue = Vec3::new(0.0, 0.217_637_64, 1.0);
    let emissions: Vec<Vec3> = scene.materials.iter().map(|m| m.emission).collect();
    assert_eq!(emissions, [srgb_orange, srgb_blue]);
    for m in &scene.materials {
        assert!(
            matches!(m.bsdf, Bsdf::Lambert(l) if l.albedo == Vec3::ZERO),
            "{}: {:?}",
            m.name,
            m.bsdf
        );
    }
    assert!(
        !scene.warnings.iter().any(|w| w.contains("unlit")),
        "{:?}",
        scene.warnings
    );
}
