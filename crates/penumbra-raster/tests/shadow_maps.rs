//! Shadow maps against the CPU ray tracer's hard shadows (`direct`
//! integrator: one shadow ray per abstract light).
//!
//! A box standing on a plane and a sphere floating above it, lit in turn by
//! a directional, a spot and a point light. A pixel is *shadowed* on the CPU
//! where `direct` < ½ · `local` (same scene, same samples, shadows only
//! differ), on the GPU where the shadow-mapped image < ½ · the unshadowed
//! raster image. With `--pcf 1` the fraction of pixels whose state differs
//! must be small at 2048² and must not increase from 512² to 4096² (and be
//! strictly lower at 4096² than at 512²). A plane without occluder must be
//! fully lit for every light (no acne) and the box's contact shadow must not
//! detach (no peter-panning: few CPU-shadowed pixels lit on the GPU).

mod common;
mod shadow_scene;

use penumbra_raster::{GpuContext, RasterOptions, ShadowMode};
use penumbra_scene::IntegratorKind;
use shadow_scene::{RES, classify, cpu, lum, save, scene};

const SIZES: [u32; 4] = [512, 1024, 2048, 4096];
const MAX_DIFF_AT_2048: f64 = 0.015;

fn raster(
    ctx: &GpuContext,
    scene: &penumbra_scene::Scene,
    options: RasterOptions,
) -> (penumbra_image::Image, Vec<f64>) {
    shadow_scene::raster(ctx, scene, options, "shadow map")
}

fn map_options(size: u32, pcf: u32) -> RasterOptions {
    RasterOptions {
        shadows: ShadowMode::Map,
        shadow_map_size: size,
        pcf,
        ..Default::default()
    }
}

/// (differing fraction, GPU-lit-but-CPU-shadowed fraction, mean ms per
/// shadow pass) for each shadow-map size.
fn errors_over_sizes(ctx: &GpuContext, which: &str) -> Vec<(f64, f64, f64)> {
    let s = scene(which, true);
    let cpu_shadowed = classify(
        &cpu(&s, IntegratorKind::Direct),
        &cpu(&s, IntegratorKind::Local),
    );
    let n = cpu_shadowed.len() as f64;
    let in_shadow = cpu_shadowed.iter().filter(|b| **b).count() as f64 / n;
    // The view must contain a real shadow, or the comparison proves nothing.
    assert!(
        in_shadow > 0.02,
        "{which}: only {in_shadow:.4} of the pixels in shadow on the CPU"
    );
    let (plain, _) = raster(ctx, &s, RasterOptions::default());
    let none = classify(&plain, &plain);
    assert!(none.iter().all(|b| !b));
    let mut out = Vec::new();
    for size in SIZES {
        let (img, ms) = raster(ctx, &s, map_options(size, 1));
        save(&format!("{which}-{size}"), &img);
        let gpu_shadowed = classify(&img, &plain);
        let diff = gpu_shadowed
            .iter()
            .zip(&cpu_shadowed)
            .filter(|(g, c)| g != c)
            .count();
        let leak = gpu_shadowed
            .iter()
            .zip(&cpu_shadowed)
            .filter(|(g, c)| !**g && **c)
            .count();
        let mean_ms = if ms.is_empty() {
            f64::NAN
        } else {
            ms.iter().sum::<f64>() / ms.len() as f64
        };
        eprintln!(
            "{which}: map {size}: {:.3} % of pixels differ from CPU direct ({:.3} % lit on the GPU but shadowed on the CPU; {:.2} % shadowed on the CPU), {} shadow pass(es), {mean_ms:.2} ms each (GPU timestamps)",
            100.0 * diff as f64 / n,
            100.0 * leak as f64 / n,
            100.0 * in_shadow,
            ms.len(),
        );
        out.push((diff as f64 / n, leak as f64 / n, mean_ms));
    }
    out
}

fn check_light(which: &str) {
    let Some(ctx) = common::gpu(which) else {
        return;
    };
    let e = errors_over_sizes(&ctx, which);
    let diff: Vec<f64> = e.iter().map(|x| x.0).collect();
    assert!(
        diff[2] <= MAX_DIFF_AT_2048,
        "{which}: {:.3} % of pixels differ at 2048 (> {:.1} %)",
        100.0 * diff[2],
        100.0 * MAX_DIFF_AT_2048
    );
    for w in diff.windows(2) {
        assert!(
            w[1] <= w[0],
            "{which}: error grows with the map size: {diff:?}"
        );
    }
    assert!(
        diff[3] < diff[0],
        "{which}: no gain from 512 to 4096: {diff:?}"
    );
    // Peter-panning would leave light under the box's contact edge.
    assert!(
        e[2].1 <= 0.5 * MAX_DIFF_AT_2048,
        "{which}: light leaks: {e:?}"
    );
}

#[test]
fn directional_shadow_map_matches_cpu_direct() {
    check_light("directional");
}

#[test]
fn spot_shadow_map_matches_cpu_direct() {
    check_light("spot");
}

#[test]
fn point_shadow_cube_matches_cpu_direct() {
    check_light("point");
}

/// A plane with nothing above it is fully lit with the default bias for
/// every light and map size (no acne), and with PCF.
#[test]
fn unoccluded_plane_has_no_acne() {
    let Some(ctx) = common::gpu("unoccluded_plane_has_no_acne") else {
        return;
    };
    for which in ["directional", "spot", "point"] {
        let s = scene(which, false);
        let (plain, _) = raster(&ctx, &s, RasterOptions::default());
        let lit = plain.pixels.iter().filter(|p| lum(**p) > 1e-4).count();
        assert!(
            lit > (RES * RES / 4) as usize,
            "{which}: plane hardly lit ({lit})"
        );
        for (size, pcf) in [(512, 1), (2048, 1), (4096, 1), (2048, 3)] {
            let (img, _) = raster(&ctx, &s, map_options(size, pcf));
            let shadowed = classify(&img, &plain).iter().filter(|b| **b).count();
            let darker = img
                .pixels
                .iter()
                .zip(&plain.pixels)
                .filter(|(m, p)| lum(**m) < 0.999 * lum(**p))
                .count();
            eprintln!(
                "{which}: plane alone, map {size}, pcf {pcf}: {shadowed} shadowed, {darker} darkened pixels of {lit} lit"
            );
            assert_eq!(
                darker, 0,
                "{which}: acne at {size}, pcf {pcf}: {darker} pixels darkened"
            );
        }
        // The check can fail: without any bias the same plane shows acne.
        let (img, _) = raster(
            &ctx,
            &s,
            RasterOptions {
                slope_bias: 0.0,
                normal_offset: 0.0,
                ..map_options(512, 1)
            },
        );
        let acne = classify(&img, &plain).iter().filter(|b| **b).count();
        eprintln!("{which}: plane alone without bias, map 512: {acne} shadowed pixels");
        assert!(acne > 0, "{which}: no acne even without bias");
    }
}

/// Without occluders and with `ShadowMode::None` nothing changes, and the
/// shadow mode actually darkens something when an occluder is there (the
/// comparison above cannot pass with a map that never shadows).
#[test]
fn shadows_none_is_unshadowed_and_map_darkens() {
    let Some(ctx) = common::gpu("shadows_none_is_unshadowed_and_map_darkens") else {
        return;
    };
    let s = scene("directional", true);
    let (plain, _) = raster(&ctx, &s, RasterOptions::default());
    let (img, ms) = raster(&ctx, &s, map_options(1024, 3));
    let shadowed = classify(&img, &plain).iter().filter(|b| **b).count();
    assert!(shadowed > (RES * RES / 50) as usize, "{shadowed}");
    if ctx
        .device
        .features()
        .contains(penumbra_raster::wgpu::Features::TIMESTAMP_QUERY)
    {
        assert_eq!(ms.len(), 1);
    }
    // PCF softens: some pixels are strictly between lit and shadowed.
    let partial = img
        .pixels
        .iter()
        .zip(&plain.pixels)
        .filter(|(m, p)| lum(**m) > 0.05 * lum(**p) && lum(**m) < 0.95 * lum(**p))
        .count();
    assert!(partial > 0, "PCF 3 left no partially lit pixel");
}

/// An alpha-masked quad (glTF MASK over a 4 × 4 checkerboard of α = 0 and
/// α = 1) high above the plane casts the checkerboard's shadow, as the CPU's
/// shadow rays see it: the shadow-map pass discards masked-out fragments.
/// The pixels whose shadowed state differs from the CPU's are fewer than a
/// quarter of those by which the unmasked quad's shadow differs.
#[test]
fn alpha_masks_cut_their_shadows() {
    use penumbra_scene::{AlphaCoverage, AlphaMode, Material, Texture, texture::Wrap};
    let Some(ctx) = common::gpu("alpha_masks_cut_their_shadows") else {
        return;
    };
    let mut s = scene("directional", false);
    s.textures.push(Texture {
        name: "checker".into(),
        width: 4,
        height: 4,
        texels: (0..16)
            .map(|i| glam::Vec3::splat(((i % 4 + i / 4) % 2) as f32))
            .collect(),
        wrap: [Wrap::ClampToEdge; 2],
        uv_transform: glam::Affine2::IDENTITY,
        uv_set: 0,
    });
    let masked = s.add_material(Material {
        alpha: Some(AlphaCoverage {
            mode: AlphaMode::Mask { cutoff: 0.5 },
            factor: 1.0,
            texture: Some(0),
        }),
        ..Material::lambert("masked", glam::Vec3::new(0.7, 0.2, 0.1))
    });
    // Its shadow falls beside it (the light's offset at height 3 is
    // (3.75, −2.25)), in view.
    let mut quad = penumbra_scene::primitives::quad(
        glam::Vec3::new(-2.5, 3.0, 2.0),
        glam::Vec3::new(3.0, 0.0, 0.0),
        glam::Vec3::new(0.0, 0.0, -3.0),
    );
    quad.material = masked;
    s.add_mesh(quad, glam::Mat4::IDENTITY);
    let shadowed = |scene: &penumbra_scene::Scene| {
        classify(
            &cpu(scene, IntegratorKind::Direct),
            &cpu(scene, IntegratorKind::Local),
        )
    };
    let cpu_shadowed = shadowed(&s);
    let (plain, _) = raster(&ctx, &s, RasterOptions::default());
    let (img, _) = raster(&ctx, &s, map_options(2048, 1));
    save("alpha-mask", &img);
    let gpu_shadowed = classify(&img, &plain);
    let mut opaque = s.clone();
    opaque.materials[masked].alpha = None;
    let whole = shadowed(&opaque);
    let n = cpu_shadowed.len() as f64;
    let count = |v: &[bool]| v.iter().filter(|b| **b).count() as f64 / n;
    let differ =
        |a: &[bool], b: &[bool]| a.iter().zip(b).filter(|(x, y)| x != y).count() as f64 / n;
    let (diff, unmasked_diff) = (
        differ(&gpu_shadowed, &cpu_shadowed),
        differ(&whole, &cpu_shadowed),
    );
    eprintln!(
        "alpha mask: shadowed {:.2} % (CPU {:.2} %, unmasked {:.2} %); {:.3} % of pixels differ from the CPU (the unmasked shadow: {:.3} %)",
        100.0 * count(&gpu_shadowed),
        100.0 * count(&cpu_shadowed),
        100.0 * count(&whole),
        100.0 * diff,
        100.0 * unmasked_diff
    );
    assert!(count(&cpu_shadowed) > 0.01, "no shadow in view");
    assert!(
        diff < 0.25 * unmasked_diff,
        "{:.3} % differ ({:.3} % for the unmasked shadow)",
        100.0 * diff,
        100.0 * unmasked_diff
    );
}
