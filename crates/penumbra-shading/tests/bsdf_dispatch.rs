//! The `Bsdf` enum and its delta-lobe set against closed forms: a Lambert
//! surface through the enum has f = ρ/π, pdf = cos θ/π and albedo ρ; a
//! mirror's one lobe is the reflection with throughput R; `diffuse_albedo`
//! is ρ, π kd, base × (1 − metallic)(1 − transmission) or 0 (notes 004);
//! lobes without throughput are not listed.

use glam::Vec3;
use penumbra_shading::Rgb;
use penumbra_shading::bsdf::{
    Bsdf, Conductor, FresnelModel, Lambert, MetallicRoughness, Mirror, PhongBlinn, PhongVariant,
    SpecularSet,
};
use std::f32::consts::PI;

#[test]
fn lambert_through_the_enum_by_hand() {
    let rho = Rgb::new(0.6, 0.3, 0.9);
    let b = Bsdf::Lambert(Lambert::new(rho));
    let (wo, wi) = (Vec3::new(0.0, 0.6, 0.8), Vec3::new(0.8, 0.0, 0.6));
    assert!((b.eval(wo, wi) - rho / PI).abs().max_element() < 1e-7);
    assert!((b.pdf(wo, wi) - 0.6 / PI).abs() < 1e-7);
    assert_eq!(b.albedo(), rho);
    assert!(b.specular(wo).is_empty());
    let s = b.sample(wo, 0.5, [0.3, 0.7]).expect("a diffuse sample");
    assert!(s.wi.z > 0.0 && (s.pdf - s.wi.z / PI).abs() < 1e-5);
}

#[test]
fn mirror_lobe_through_the_enum() {
    let r = Rgb::new(0.9, 0.8, 0.7);
    let b = Bsdf::Mirror(Mirror::new(r));
    let wo = Vec3::new(0.6, 0.0, 0.8);
    let set = b.specular(wo);
    assert!(!set.is_empty());
    assert_eq!(set.len(), 1);
    let (wi, t) = set.iter().next().unwrap();
    assert!((wi - Vec3::new(-0.6, 0.0, 0.8)).length() < 1e-6);
    assert_eq!(t, r);
    assert_eq!(b.eval(wo, wi), Rgb::ZERO);
    assert_eq!(b.pdf(wo, wi), 0.0);
    assert_eq!(b.albedo(), r);
}

#[test]
fn diffuse_albedo_by_hand() {
    let rho = Rgb::new(0.5, 0.25, 0.125);
    assert_eq!(Bsdf::Lambert(Lambert::new(rho)).diffuse_albedo(), rho);
    let kd = Rgb::new(0.1, 0.2, 0.05);
    let p = PhongBlinn::new(kd, Rgb::splat(0.3), 20.0, PhongVariant::Normalized);
    assert!(
        (Bsdf::PhongBlinn(p).diffuse_albedo() - kd * PI)
            .abs()
            .max_element()
            < 1e-7
    );
    let mut m = MetallicRoughness::new(Rgb::new(0.8, 0.4, 0.2), 0.25, 0.5);
    m.transmission = 0.5;
    // (1 − 0.25)(1 − 0.5) = 0.375.
    let want = Rgb::new(0.3, 0.15, 0.075);
    let got = Bsdf::MetallicRoughness(m).diffuse_albedo();
    assert!((got - want).abs().max_element() < 1e-6, "{got}");
    let c = Conductor::new(Rgb::splat(0.2), Rgb::splat(3.0), FresnelModel::Exact);
    assert_eq!(Bsdf::Conductor(c).diffuse_albedo(), Rgb::ZERO);
    assert_eq!(
        Bsdf::Mirror(Mirror::new(Rgb::ONE)).diffuse_albedo(),
        Rgb::ZERO
    );
}

#[test]
fn specular_set_lists_only_lobes_with_throughput() {
    let mut set = SpecularSet::default();
    assert!(set.is_empty());
    set.push(Vec3::Z, Rgb::ZERO);
    set.push(Vec3::Z, Rgb::new(-1.0, 0.0, 0.0));
    assert!(set.is_empty(), "no throughput, no lobe");
    set.push(Vec3::Z, Rgb::new(0.0, 0.5, 0.0));
    set.push(-Vec3::Z, Rgb::splat(0.25));
    assert_eq!(set.len(), 2);
    let items: Vec<_> = set.iter().collect();
    assert_eq!(
        items,
        vec![
            (Vec3::Z, Rgb::new(0.0, 0.5, 0.0)),
            (-Vec3::Z, Rgb::splat(0.25))
        ]
    );
}
