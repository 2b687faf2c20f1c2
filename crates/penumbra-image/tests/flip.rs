//! HDR-FLIP behaviour.

mod common;

use common::{add_relative_noise, reference_path, synthetic_scene};
use penumbra_image::{Image, compare, flip_exposure_range, hdr_flip, read_image};

#[test]
fn identical_images_have_zero_flip() {
    let r = synthetic_scene(64, 48);
    let (mean, map) = hdr_flip(&r, &r).expect("flip");
    assert_eq!(mean, 0.0);
    assert!(map.pixels.iter().all(|p| p.x == 0.0));
    assert_eq!((map.width, map.height), (64, 48));
}

#[test]
fn flip_grows_with_noise() {
    let r = synthetic_scene(64, 64);
    let mut last = 0.0;
    for (i, sigma) in [0.01f32, 0.05, 0.2, 0.5].into_iter().enumerate() {
        let t = add_relative_noise(&r, sigma, 7 + i as u64);
        let (mean, map) = hdr_flip(&r, &t).expect("flip");
        assert!(mean > last, "sigma {sigma}: FLIP {mean} not above {last}");
        assert!(
            map.pixels
                .iter()
                .all(|p| (0.0..=1.0).contains(&p.x) && p.x == p.y && p.y == p.z)
        );
        last = mean;
    }
    assert!(last < 1.0);
}

#[test]
fn flip_size_mismatch_is_an_error() {
    let e = hdr_flip(&Image::new(4, 4), &Image::new(4, 5)).expect_err("sizes differ");
    assert!(e.to_string().contains("4x5"), "{e}");
    assert!(hdr_flip(&Image::new(0, 0), &Image::new(0, 0)).is_err());
}

/// Sanity check against the README's numbers: Mitsuba at 256 spp reaches
/// relMSE 0.00109 and FLIP 0.050 on the Cornell box. Gaussian relative noise
/// with σ = 0.06 gives about the same relMSE; its FLIP must be of the same
/// order (path-tracing noise is not Gaussian, so only the order is checked;
/// this implementation gives ≈ 0.047).
#[test]
fn cornell_noise_flip_ballpark() {
    let r = read_image(&reference_path("cornell/reference-path-depth8-4096spp.exr")).expect("read");
    let range = flip_exposure_range(&r);
    assert!(range.count >= 2 && range.start < range.stop, "{range:?}");
    let t = add_relative_noise(&r, 0.06, 3);
    let m = compare(&r, &t).expect("compare");
    eprintln!("exposures {range:?}; {m}");
    assert!((0.0008..0.0013).contains(&m.rel_mse), "{m}");
    assert!((0.03..0.07).contains(&m.flip), "{m}");
}
