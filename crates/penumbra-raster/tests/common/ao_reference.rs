//! The CPU `ao` integrator's 1024-spp images that the screen-space and
//! baked AO tests compare with, stored in `tests/data/ao-reference/` so
//! that CI does not spend ~22 s rendering each one on every run.
//!
//! Each image has a key file beside it: the scene's fingerprint
//! (`penumbra_scene::fingerprint`: geometry, materials, camera), the size,
//! the radius and the sample count. A key that differs from the test's
//! fails the test with the command that renders the image again
//! (`PENUMBRA_REGENERATE_AO=1`). A stale image (the `ao` integrator
//! changed, not the scene) is caught by a fresh 32-spp render, which must
//! agree with the stored one within its noise, block by block.

use penumbra_image::{Image, read_image, write_image};
use penumbra_scene::{IntegratorKind, RenderSettings, Scene, fingerprint};
use penumbra_trace::{RenderOptions, render};
use std::path::PathBuf;

/// Samples per pixel of a stored reference.
pub const REFERENCE_SPP: u32 = 1024;
/// Samples per pixel of the freshness check.
const CHECK_SPP: u32 = 32;
/// Side of the blocks whose means the freshness check compares.
const BLOCK: u32 = 8;

/// The `ao` integrator's `size`² image of `scene` at `radius`.
pub fn ao_render(scene: &Scene, size: u32, radius: f32, spp: u32) -> Image {
    let s = RenderSettings {
        width: size,
        height: size,
        spp,
        integrator: IntegratorKind::Ao,
        ao_distance: radius,
        ..Default::default()
    };
    render(scene, &s, &RenderOptions::default()).unwrap().image
}

fn key(scene: &Scene, size: u32, radius: f32) -> String {
    format!(
        "scene {}\nsize {size}\nradius {radius:?}\nspp {REFERENCE_SPP}\n",
        fingerprint(scene)
    )
}

/// The stored 1024-spp `ao` image `name` of `scene`, checked against the
/// scene (its key) and against the integrator as it is now (a 32-spp
/// render). Panics, saying how to regenerate it, when either differs.
pub fn ao_reference(name: &str, scene: &Scene, size: u32, radius: f32) -> Image {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data/ao-reference");
    let image_path = dir.join(format!("{name}.exr"));
    let key_path = dir.join(format!("{name}.key"));
    let want = key(scene, size, radius);
    if std::env::var("PENUMBRA_REGENERATE_AO").is_ok_and(|v| v == "1") {
        std::fs::create_dir_all(&dir).unwrap();
        let img = ao_render(scene, size, radius, REFERENCE_SPP);
        write_image(&image_path, &img, &[], &Default::default()).unwrap();
        std::fs::write(&key_path, &want).unwrap();
        eprintln!("wrote {}", image_path.display());
    }
    let regenerate = "render it again with `PENUMBRA_REGENERATE_AO=1 cargo test -p penumbra-raster --test screen_ao --test baked_maps` and commit tests/data/ao-reference";
    let have = std::fs::read_to_string(&key_path)
        .unwrap_or_else(|e| panic!("{}: {e}; {regenerate}", key_path.display()));
    assert_eq!(
        have,
        want,
        "{}: the stored AO reference was rendered from another scene or settings; {regenerate}",
        key_path.display()
    );
    let stored = read_image(&image_path)
        .unwrap_or_else(|e| panic!("{}: {e}; {regenerate}", image_path.display()));
    assert_eq!((stored.width, stored.height), (size, size));
    let fresh = ao_render(scene, size, radius, CHECK_SPP);
    let worst = worst_block_difference(&stored, &fresh);
    let mean =
        |img: &Image| img.pixels.iter().map(|p| p.x as f64).sum::<f64>() / img.pixels.len() as f64;
    let shift = mean(&fresh) - mean(&stored);
    eprintln!(
        "{name}: stored {REFERENCE_SPP}-spp AO vs a fresh {CHECK_SPP}-spp render: largest {BLOCK}² block difference {worst:.4}, mean difference {shift:.5}"
    );
    // A block's mean of 8² pixels × 32 binary visibility samples has a
    // standard deviation of at most 0.5 / √2048 ≈ 0.011 (p = ½); 0.06 is
    // over 5 of them, for 1024 blocks. A 32-spp render shares its samples
    // with the first 32 of the stored 1024, which only narrows the
    // difference while the integrator is unchanged.
    assert!(
        worst <= 0.06,
        "{}: a {CHECK_SPP}-spp render of the ao integrator differs from the stored reference by {worst:.3} in an {BLOCK}² block (noise allows 0.06): the integrator changed; {regenerate}",
        image_path.display()
    );
    // The image's mean: a standard deviation of at most 0.5 / √(256² · 32)
    // ≈ 0.00034; 0.002 is about 6 of them.
    assert!(
        shift.abs() <= 0.002,
        "{}: the mean of a {CHECK_SPP}-spp render of the ao integrator is {shift:+.4} from the stored reference's (noise allows 0.002): the integrator changed; {regenerate}",
        image_path.display()
    );
    stored
}

/// The largest difference between the means of `a` and `b` over any
/// `BLOCK`² block (red channel: AO is grey).
fn worst_block_difference(a: &Image, b: &Image) -> f64 {
    let mut worst = 0.0f64;
    for by in 0..a.height / BLOCK {
        for bx in 0..a.width / BLOCK {
            let mut d = 0.0f64;
            for y in by * BLOCK..(by + 1) * BLOCK {
                for x in bx * BLOCK..(bx + 1) * BLOCK {
                    d += (a.get(x, y).x - b.get(x, y).x) as f64;
                }
            }
            worst = worst.max((d / (BLOCK * BLOCK) as f64).abs());
        }
    }
    worst
}
