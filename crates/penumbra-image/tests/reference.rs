//! The shared Mitsuba reference EXRs can be read.

mod common;

use common::reference_path;
use penumbra_image::{ImageFormat, read_exr_layers, read_image};

fn check(rel: &str) {
    let path = reference_path(rel);
    assert_eq!(ImageFormat::from_path(&path), Some(ImageFormat::Exr));
    let img = read_image(&path).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!((img.width, img.height), (512, 512));
    assert_eq!(img.pixels.len(), 512 * 512);
    assert!(img.all_finite(), "{rel}: non-finite pixels");
    let mean = img.mean();
    assert!(mean.min_element() > 0.0, "{rel}: mean radiance {mean}");
    assert!(img.pixels.iter().all(|p| p.min_element() >= 0.0));
    let layers = read_exr_layers(&path).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(layers.rgb, img);
    assert!(layers.aovs.is_empty());
    eprintln!("{rel}: mean {mean}, max {}", img.max_value());
}

#[test]
fn cornell_reference() {
    check("cornell/reference-path-depth8-4096spp.exr");
}

#[test]
fn spheres_direct_reference() {
    check("spheres-direct/reference-direct-1024spp.exr");
}
