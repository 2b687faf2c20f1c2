//! The environment light against values worked by hand: the lat-long
//! lookup at the map's edges (u = 1 along +z, v = 1 at the nadir), the
//! constant and map forms of `eval`, `pdf`, `is_black` and `power`
//! (Φ = π² r² L̄), no sample at the pole where sin θ = 0, and map equality.

use glam::Vec3;
use penumbra_shading::Rgb;
use penumbra_shading::light::{Environment, EnvironmentMap};
use std::f32::consts::PI;
use std::sync::Arc;

/// A 4 × 2 map whose texel i has radiance (i + 1, 0, 0).
fn numbered() -> EnvironmentMap {
    let texels = (0..8).map(|i| Rgb::new(i as f32 + 1.0, 0.0, 0.0)).collect();
    EnvironmentMap::new(4, 2, texels, Rgb::ONE, 0.0)
}

/// With φ = atan2(x, −z) and u = φ/2π + ½, +z is u = 1 (the right edge),
/// −z the centre u = ½, +x u = ¾; v = θ/π puts the horizon at v = ½ (the
/// lower row of two) and the nadir at v = 1. Both u = 1 and v = 1 are
/// clamped to the last column and row.
#[test]
fn lookups_at_the_edges_by_hand() {
    let m = numbered();
    let x = |d: Vec3| m.eval(d).x;
    assert_eq!(x(Vec3::Z), 8.0, "+z: row 1, column 3");
    assert_eq!(x(-Vec3::Z), 7.0, "−z: row 1, column 2");
    assert_eq!(x(Vec3::X), 8.0, "+x: u = 3/4, column 3");
    assert_eq!(x(-Vec3::X), 6.0, "−x: u = 1/4, column 1");
    assert_eq!(
        x(Vec3::new(0.3, 0.9, -0.3).normalize()),
        3.0,
        "upper row, u = 5/8"
    );
    assert_eq!(x(-Vec3::Y), 8.0, "nadir: v = 1, u = 1");
}

/// A map lit only in its top row, sampled with u₂ = 0: the marginal gives
/// v = 0 exactly, the zenith, where sin θ = 0 and the solid-angle density
/// p/(2π² sin θ) is infinite: no sample (never an infinite pdf). Other
/// samples have finite positive densities equal to `pdf`.
#[test]
fn no_sample_at_the_pole() {
    let mut texels = vec![Rgb::ZERO; 8];
    texels[..4].fill(Rgb::ONE);
    let m = EnvironmentMap::new(4, 2, texels, Rgb::ONE, 0.0);
    assert!(m.sample_li([0.3, 0.0]).is_none());
    let s = m.sample_li([0.3, 0.5]).expect("a sample inside the row");
    assert!(s.pdf.is_finite() && s.pdf > 0.0);
    assert!((s.pdf - m.pdf(s.wi)).abs() < 1e-4 * s.pdf);
}

/// Constant L = (2, 1, 0.5): eval L everywhere, pdf 1/4π, power through a
/// disk of radius 3: π L · π 3² = 9π² L. The map form passes on the map's
/// values; black means zero radiance everywhere.
#[test]
fn constant_and_map_forms_by_hand() {
    let l = Rgb::new(2.0, 1.0, 0.5);
    let c = Environment::Constant(l);
    assert_eq!(c.eval(Vec3::new(0.6, 0.0, -0.8)), l);
    assert_eq!(c.pdf(Vec3::Y), 1.0 / (4.0 * PI));
    let phi = c.power(3.0);
    assert!(
        (phi - l * 9.0 * PI * PI).abs().max_element() < 1e-4,
        "{phi}"
    );
    assert!(!c.is_black());
    assert!(Environment::Constant(Rgb::ZERO).is_black());
    assert!(Environment::default().is_black());

    let map = Arc::new(numbered());
    let e = Environment::Map(map.clone());
    assert_eq!(e.eval(-Vec3::X), Rgb::new(6.0, 0.0, 0.0));
    let d = Vec3::new(0.3, 0.9, -0.3).normalize();
    assert_eq!(e.pdf(d), map.pdf(d));
    assert!(e.pdf(d) > 0.0);
    assert!(!e.is_black());
    // A constant 3 map: mean radiance 3, power 9π² · 3 at r = 3.
    let flat = Environment::Map(Arc::new(EnvironmentMap::new(
        4,
        2,
        vec![Rgb::splat(3.0); 8],
        Rgb::ONE,
        0.0,
    )));
    let phi = flat.power(3.0);
    assert!((phi.x - 27.0 * PI * PI).abs() < 1e-3, "{phi}");
    let black = EnvironmentMap::new(2, 1, vec![Rgb::ZERO; 2], Rgb::ONE, 0.0);
    assert!(Environment::Map(Arc::new(black)).is_black());
}

/// Maps are equal when size, rotation and texels are: each one differing
/// makes them unequal.
#[test]
fn map_equality() {
    let t: Vec<Rgb> = (0..8).map(|i| Rgb::splat(i as f32)).collect();
    let m = |w, h, t: &[Rgb], rot| EnvironmentMap::new(w, h, t.to_vec(), Rgb::ONE, rot);
    assert!(m(4, 2, &t, 0.5) == m(4, 2, &t, 0.5));
    assert!(m(4, 2, &t, 0.5) != m(2, 4, &t, 0.5), "size");
    assert!(m(4, 2, &t, 0.5) != m(8, 1, &t, 0.5), "width and height");
    assert!(m(4, 2, &t, 0.5) != m(4, 2, &t, 0.25), "rotation");
    let mut u = t.clone();
    u[5] = Rgb::splat(9.0);
    assert!(m(4, 2, &t, 0.5) != m(4, 2, &u, 0.5), "texels");
}
