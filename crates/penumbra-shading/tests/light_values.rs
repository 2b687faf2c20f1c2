//! The abstract lights against values worked by hand: the spot light's cone
//! (glTF `KHR_lights_punctual`: t = clamp((cos θ − cos θo)/(cos θi − cos θo),
//! 0, 1), attenuation t²), the [`Light`] enum's dispatch of sampling, power
//! and range, the homogeneous position (y, w), and the unit conversions and
//! colour helpers the loaders use.

use glam::{Vec3, Vec4};
use penumbra_shading::Rgb;
use penumbra_shading::color::max_component;
use penumbra_shading::light::{DirectionalLight, HomogeneousLight, Light, PointLight, SpotLight};
use penumbra_shading::radiometry::candela_to_watts_per_sr;
use std::f32::consts::PI;

fn close(a: f32, b: f32, what: &str) {
    assert!(
        (a - b).abs() <= 1e-5 * b.abs().max(1.0),
        "{what}: {a} vs {b}"
    );
}

/// A spot at (0, 0, 4) pointing down −z, I = (8, 4, 2) W/sr, cos θi = 0.9,
/// cos θo = 0.7, no range.
fn spot() -> SpotLight {
    SpotLight {
        position: Vec3::new(0.0, 0.0, 4.0),
        direction: -Vec3::Z,
        intensity: Rgb::new(8.0, 4.0, 2.0),
        cos_inner: 0.9,
        cos_outer: 0.7,
        range: f32::INFINITY,
    }
}

/// On the axis, 4 m below: E⊥ = I/r² = I/16, direction to the light +z.
/// At (3, 0, 0): the light is 5 m away and cos θ = 4/5 = 0.8, halfway
/// through the falloff: t = (0.8 − 0.7)/0.2 = 0.5, E⊥ = I · 0.25/25.
/// At (4, 0, 0): cos θ = 4/√32 = 0.7071, t = 0.0355339, E⊥ = I t²/32.
/// Outside the cone (cos θ < 0.7) and behind the light: nothing.
#[test]
fn spot_light_irradiance_by_hand() {
    let s = spot();
    let on_axis = s.sample_li(Vec3::ZERO).expect("on the axis");
    assert_eq!(on_axis.wi, Vec3::Z);
    close(on_axis.distance, 4.0, "distance");
    assert!(on_axis.is_delta);
    for b in 0..3 {
        close(on_axis.value[b], s.intensity[b] / 16.0, "on axis");
    }
    let mid = s
        .sample_li(Vec3::new(3.0, 0.0, 0.0))
        .expect("in the falloff");
    close(mid.distance, 5.0, "distance");
    for b in 0..3 {
        close(mid.value[b], s.intensity[b] * 0.25 / 25.0, "halfway");
    }
    let t = (4.0 / 32f32.sqrt() - 0.7) / 0.2;
    let edge = s
        .sample_li(Vec3::new(4.0, 0.0, 0.0))
        .expect("near the edge");
    for b in 0..3 {
        close(
            edge.value[b],
            s.intensity[b] * t * t / 32.0,
            "near the edge",
        );
    }
    assert!(s.sample_li(Vec3::new(5.0, 0.0, 0.0)).is_none(), "outside");
    assert!(s.sample_li(Vec3::new(0.0, 0.0, 9.0)).is_none(), "behind");
    // A range of 10 m multiplies by (1 − (5/10)⁴)² at 5 m.
    let ranged = SpotLight { range: 10.0, ..s };
    let w = (1.0f32 - 0.0625).powi(2);
    let r = ranged.sample_li(Vec3::new(3.0, 0.0, 0.0)).unwrap();
    close(r.value.x, 8.0 * 0.25 / 25.0 * w, "with range");
}

/// The enum passes each query to its light: sampling, power (point 4πI,
/// directional π r² E through a disk of the scene radius, spot
/// 2πI[(1 − cos θi) + (cos θi − cos θo)/3]), range and the homogeneous
/// position (w = 1 at the light, w = 0 towards it).
#[test]
fn light_enum_dispatches_by_hand() {
    let point = PointLight {
        range: 7.0,
        ..PointLight::new(Vec3::new(1.0, 2.0, 2.0), Rgb::new(3.0, 6.0, 9.0))
    };
    let sun = DirectionalLight {
        direction: Vec3::new(0.0, -0.6, -0.8),
        irradiance: Rgb::new(2.0, 1.0, 0.5),
    };
    let s = SpotLight {
        range: 12.0,
        ..spot()
    };
    let (lp, ld, ls) = (Light::Point(point), Light::Directional(sun), Light::Spot(s));

    // Sampling from the origin. Point: 3 m, window (1 − (3/7)⁴)².
    let a = lp.sample_li(Vec3::ZERO).unwrap();
    let w = (1.0 - (3.0f32 / 7.0).powi(4)).powi(2);
    close(a.value.y, 6.0 / 9.0 * w, "point E⊥");
    close(a.distance, 3.0, "point distance");
    let b = ld.sample_li(Vec3::ZERO).unwrap();
    assert!((b.wi - Vec3::new(0.0, 0.6, 0.8)).length() < 1e-6);
    assert_eq!(b.distance, f32::INFINITY);
    close(b.value.x, 2.0, "sun E⊥");
    let c = ls.sample_li(Vec3::ZERO).unwrap();
    close(
        c.value.x,
        8.0 / 16.0 * (1.0 - (4.0f32 / 12.0).powi(4)).powi(2),
        "spot E⊥",
    );
    assert!(ls.sample_li(Vec3::new(5.0, 0.0, 0.0)).is_none());

    // Power.
    let p = lp.power(100.0);
    close(p.z, 4.0 * PI * 9.0, "point power");
    let p = ld.power(3.0);
    close(p.x, PI * 9.0 * 2.0, "directional power, r = 3");
    close(p.z, PI * 9.0 * 0.5, "directional power, r = 3");
    let p = ls.power(100.0);
    let spot_phi = 2.0 * PI * ((1.0 - 0.9) + (0.9 - 0.7) / 3.0);
    close(p.x, 8.0 * spot_phi, "spot power");
    close(p.z, 2.0 * spot_phi, "spot power");

    // Range.
    assert_eq!(lp.range(), 7.0);
    assert_eq!(ld.range(), f32::INFINITY);
    assert_eq!(ls.range(), 12.0);

    // Homogeneous position.
    assert_eq!(lp.homogeneous_position(), Vec4::new(1.0, 2.0, 2.0, 1.0));
    assert_eq!(ls.homogeneous_position(), Vec4::new(0.0, 0.0, 4.0, 1.0));
    let y = ld.homogeneous_position();
    assert!((y - Vec4::new(0.0, 0.6, 0.8, 0.0)).length() < 1e-6, "{y}");
}

/// The unified light at its own position has no direction (None, not a NaN
/// direction with infinite irradiance), and neither has a point at
/// infinity. With w = 2, (y, w) = ((4, 0, 0), 2) is the affine point
/// y/w = (2, 0, 0): seen from the origin at distance 2, from direction +x,
/// with E⊥ = M/|y − x w|² = M/16.
#[test]
fn homogeneous_light_degenerate_and_scaled_positions() {
    let l = HomogeneousLight::point(Vec3::new(1.0, -2.0, 0.5), Rgb::ONE);
    assert!(l.sample_li(Vec3::new(1.0, -2.0, 0.5)).is_none());
    assert!(l.sample_li(Vec3::splat(f32::INFINITY)).is_none());
    assert!(l.sample_li(Vec3::new(f32::NAN, 0.0, 0.0)).is_none());
    let scaled = HomogeneousLight {
        position: Vec4::new(4.0, 0.0, 0.0, 2.0),
        m: Rgb::splat(32.0),
    };
    let s = scaled.sample_li(Vec3::ZERO).unwrap();
    assert_eq!(s.wi, Vec3::X);
    close(s.distance, 2.0, "distance to y/w");
    close(s.value.x, 2.0, "M/|y − x w|²");
}

/// 1366 cd is 2 W/sr at 683 lm/W; the largest component of a colour, also
/// of a colour with negative components.
#[test]
fn conversions_by_hand() {
    close(candela_to_watts_per_sr(1366.0), 2.0, "1366 cd");
    close(candela_to_watts_per_sr(68.3), 0.1, "68.3 cd");
    assert_eq!(max_component(Rgb::new(0.2, 0.7, 0.5)), 0.7);
    assert_eq!(max_component(Rgb::new(3.0, 0.7, 0.5)), 3.0);
    assert_eq!(max_component(Rgb::new(0.2, 0.7, 2.5)), 2.5);
    assert_eq!(max_component(Rgb::new(-3.0, -2.0, -5.0)), -2.0);
}
