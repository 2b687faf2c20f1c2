//! The reference scenes of ../shared/reference, loaded from their glTF files,
//! against the converged Mitsuba 3 renders: mean radiance within 1 % per
//! channel, and relMSE no worse than 1.5× Mitsuba's own at the same spp;
//! and the glass-sphere Cornell box of tests/data/cornell-glass and the
//! metal spheres of tests/data/metal-spheres (their Mitsuba references
//! rendered once, see the READMEs there) within 1.2×.
//! On failure the render is written next to the test's temp dir path printed.

use penumbra_image::{ToneMapping, read_image, rel_mse, write_image};
use penumbra_scene::{IntegratorKind, LoadOptions, load_scene};
use penumbra_trace::{RenderOptions, render};
use std::path::PathBuf;

fn reference_dir(scene: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../../shared/reference")
        .join(scene)
}

fn check(
    scene_name: &str,
    gltf: &str,
    reference: &str,
    integrator: IntegratorKind,
    spp: u32,
    max_depth: u32,
    mitsuba_rel_mse: f64,
) {
    let dir = reference_dir(scene_name);
    check_in(
        &dir,
        scene_name,
        gltf,
        reference,
        integrator,
        spp,
        max_depth,
        mitsuba_rel_mse,
        1.5,
    );
}

/// Renders `dir/scene_file` and compares it with `dir/reference`: mean
/// within 1 % per channel, relMSE ≤ `ratio` × Mitsuba's at the same spp.
#[allow(clippy::too_many_arguments)]
fn check_in(
    dir: &std::path::Path,
    scene_name: &str,
    scene_file: &str,
    reference: &str,
    integrator: IntegratorKind,
    spp: u32,
    max_depth: u32,
    mitsuba_rel_mse: f64,
    ratio: f64,
) {
    let scene = load_scene(&dir.join(scene_file), &LoadOptions::default()).unwrap();
    let reference = read_image(&dir.join(reference)).unwrap();
    let mut settings = scene.settings.clone();
    settings.width = reference.width;
    settings.height = reference.height;
    settings.integrator = integrator;
    settings.spp = spp;
    settings.max_depth = max_depth;
    settings.seed = 1;
    let out = render(&scene, &settings, &RenderOptions::default()).unwrap();
    let (m_ref, m_out) = (reference.mean(), out.image.mean());
    let e = rel_mse(&reference, &out.image);
    let mean_ok = (0..3).all(|c| (m_out[c] / m_ref[c] - 1.0).abs() < 0.01);
    let err_ok = e <= ratio * mitsuba_rel_mse;
    if !(mean_ok && err_ok) {
        let path = std::env::temp_dir().join(format!("penumbra-{scene_name}-actual.exr"));
        let _ = write_image(&path, &out.image, &[], &ToneMapping::default());
        eprintln!("wrote the failing render to {}", path.display());
    }
    assert!(mean_ok, "{scene_name}: mean {m_out} vs reference {m_ref}");
    assert!(
        err_ok,
        "{scene_name}: relMSE {e:.5} > {ratio} × Mitsuba's {mitsuba_rel_mse}"
    );
    eprintln!(
        "{scene_name}: mean {m_out} (ref {m_ref}), relMSE {e:.5} (Mitsuba {mitsuba_rel_mse}), {:.2} s",
        out.render_seconds
    );
}

#[test]
fn cornell_path_depth8_256spp_matches_mitsuba() {
    check(
        "cornell",
        "cornell.gltf",
        "reference-path-depth8-4096spp.exr",
        IntegratorKind::Path,
        256,
        8,
        0.00109,
    );
}

#[test]
fn spheres_direct_16spp_matches_mitsuba() {
    check(
        "spheres-direct",
        "spheres-direct.gltf",
        "reference-direct-1024spp.exr",
        IntegratorKind::Direct,
        16,
        2,
        0.0071,
    );
}

/// Glass: paths inside the sphere carry radiance scaled by 1/η², which
/// Russian roulette must not take for a low throughput. With roulette on
/// the scaled throughput this scene gave relMSE 0.0195 (1.9× Mitsuba's);
/// with the scaling undone, 0.0102.
#[test]
fn cornell_glass_path_depth16_256spp_matches_mitsuba() {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data/cornell-glass");
    check_in(
        &dir,
        "cornell-glass",
        "scene.toml",
        "reference-path-depth16-4096spp.exr",
        IntegratorKind::Path,
        256,
        16,
        MITSUBA_GLASS_REL_MSE,
        1.2,
    );
}

/// Mitsuba 3.9.1 (llvm_ad_rgb) at 256 spp against its own 4096-spp
/// reference (another seed), measured once with ../shared/anchors (README
/// of tests/data/cornell-glass): relMSE 0.01016, FLIP 0.096.
const MITSUBA_GLASS_REL_MSE: f64 = 0.01016;

/// Issue 13's metal scene: glass, gold, mirror and rough copper (GGX)
/// spheres over a floor, lit by an emissive square, at depth 16. Paths
/// the light reaches only by mirrors (the floor's caustics, the wall seen
/// in the spheres) carry most of the error in both renderers.
#[test]
fn metal_spheres_path_depth16_256spp_matches_mitsuba() {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data/metal-spheres");
    check_in(
        &dir,
        "metal-spheres",
        "scene.toml",
        "reference-path-depth16-4096spp.exr",
        IntegratorKind::Path,
        256,
        16,
        MITSUBA_METALS_REL_MSE,
        1.2,
    );
}

/// Mitsuba 3.9.1 (llvm_ad_rgb) at 256 spp against its own 4096-spp
/// reference, measured once with ../shared/anchors (README of
/// tests/data/metal-spheres): relMSE 0.00758, FLIP 0.049.
const MITSUBA_METALS_REL_MSE: f64 = 0.00758;
