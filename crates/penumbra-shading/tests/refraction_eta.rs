//! Every sampled transmission reports the relative index it crossed, and
//! reflections report 1: the path tracer multiplies η² back into the
//! throughput before Russian roulette (radiance crossing into glass is
//! scaled by 1/η², Veach 1997 §5.2), so a wrong η here makes paths
//! inside glass end too often or too rarely.

use glam::Vec3;
use penumbra_shading::Rgb;
use penumbra_shading::bsdf::{
    Bsdf, Dielectric, FresnelModel, Lambert, MetallicRoughness, RoughConductor, RoughDielectric,
};
use penumbra_shading::stats::TestRng;

/// Samples `bsdf` at 40° from the normal and checks each sample's η:
/// `eta_t` when `wi` is below the surface, 1 above. Returns the number
/// of (reflected, transmitted) samples seen.
fn check(name: &str, bsdf: &Bsdf, eta_t: f32) -> (u32, u32) {
    let t = 40f32.to_radians();
    let wo = Vec3::new(t.sin(), 0.0, t.cos());
    let mut rng = TestRng::new(7);
    let (mut refl, mut trans) = (0, 0);
    for _ in 0..4000 {
        let Some(s) = bsdf.sample(wo, rng.next_f32(), rng.next_2d()) else {
            continue;
        };
        if s.wi.z < 0.0 {
            trans += 1;
            assert_eq!(s.eta, eta_t, "{name}: transmitted sample's η");
        } else {
            refl += 1;
            assert_eq!(s.eta, 1.0, "{name}: reflected sample's η");
        }
    }
    (refl, trans)
}

#[test]
fn samples_report_the_index_they_cross() {
    let glass = Dielectric::new(1.5, Rgb::ONE, FresnelModel::Exact);
    let mut gltf_glass = MetallicRoughness::new(Rgb::ONE, 0.0, 0.3);
    gltf_glass.transmission = 1.0;
    gltf_glass.ior = 1.33;
    let mut smooth_gltf_glass = gltf_glass;
    smooth_gltf_glass.roughness = 0.0;
    let cases = [
        ("glass entering", Bsdf::Dielectric(glass), 1.5),
        (
            "glass leaving",
            Bsdf::Dielectric(glass.inverted()),
            1.0 / 1.5,
        ),
        (
            "rough glass entering",
            Bsdf::RoughDielectric(RoughDielectric::new(1.5, 0.3)),
            1.5,
        ),
        (
            "rough glass leaving",
            Bsdf::RoughDielectric(RoughDielectric::new(1.5, 0.3).inverted()),
            1.0 / 1.5,
        ),
        (
            "glTF transmission, rough",
            Bsdf::MetallicRoughness(gltf_glass),
            1.33,
        ),
        (
            "glTF transmission, smooth",
            Bsdf::MetallicRoughness(smooth_gltf_glass),
            1.33,
        ),
        (
            "glTF transmission, leaving",
            Bsdf::MetallicRoughness(gltf_glass.inverted()),
            1.0 / 1.33,
        ),
    ];
    for (name, bsdf, eta_t) in &cases {
        let (refl, trans) = check(name, bsdf, *eta_t);
        // Both lobes must be exercised (at 40° from inside, 1/1.5 is
        // below the critical angle of 41.8°, so light still leaves).
        assert!(
            refl > 20 && trans > 1000,
            "{name}: {refl} reflected, {trans} transmitted"
        );
    }
    for (name, bsdf) in [
        ("Lambert", Bsdf::Lambert(Lambert::new(Rgb::splat(0.5)))),
        (
            "rough conductor",
            Bsdf::RoughConductor(RoughConductor::new(Rgb::splat(0.2), Rgb::splat(3.0), 0.3)),
        ),
    ] {
        let (_, trans) = check(name, &bsdf, f32::NAN);
        assert_eq!(trans, 0, "{name} transmitted");
    }
}

/// Smooth glass: the transmitted weight is (1 − F)·T/η² over a selection
/// probability 1 − F, so weight · η² is the tint exactly.
#[test]
fn smooth_glass_weight_times_eta_squared_is_the_tint() {
    let tint = Rgb::new(0.9, 0.7, 0.4);
    let wo = Vec3::new(0.3, 0.0, 0.3f32.mul_add(-0.3, 1.0).sqrt());
    for eta in [1.5f32, 1.0 / 1.5, 2.4] {
        let glass = Dielectric::new(eta, tint, FresnelModel::Exact);
        let s = glass.sample(wo, 0.999, [0.5, 0.5]).expect("a sample");
        assert!(s.wi.z < 0.0, "η {eta}: u = 0.999 must transmit");
        let undone = s.weight * (s.eta * s.eta);
        for c in 0..3 {
            assert!((undone[c] - tint[c]).abs() < 1e-6, "η {eta}: {undone:?}");
        }
    }
}
