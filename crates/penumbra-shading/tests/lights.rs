//! Lights: the unified homogeneous form against the closed forms, sampling
//! of the area lights and the environment map against their pdfs
//! (chi-square), and irradiance from sphere and disk lights against the
//! closed forms.

use glam::{Vec2, Vec3};
use penumbra_shading::Rgb;
use penumbra_shading::light::{
    AreaLight, DirectionalLight, Environment, EnvironmentMap, HomogeneousLight, PointLight, Shape,
};
use penumbra_shading::stats::{ChiSquare, SphereBins, TestRng, chi_square_sphere};
use std::f32::consts::PI;
use std::sync::Arc;

/// Number of chi-square tests in this file (Šidák correction).
const TESTS: usize = 6;
const ALPHA: f64 = 0.01;

fn bins() -> SphereBins {
    SphereBins {
        cos_theta: 30,
        phi: 60,
        resolution: 32,
    }
}

fn check(name: &str, r: ChiSquare) {
    eprintln!(
        "{name}: chi2 {:.1} dof {} p {:.4} pdf integral {:.4}",
        r.statistic, r.dof, r.p_value, r.pdf_integral
    );
    assert!(r.passes(ALPHA, TESTS), "{name}: {r:?}");
    assert!(
        (r.pdf_integral - 1.0).abs() < 0.01,
        "{name}: pdf integrates to {}",
        r.pdf_integral
    );
}

/// Samples `light` from `p`; the pdf of every sample must equal `pdf_li`.
fn chi_square_area(name: &str, light: AreaLight, p: Vec3, n: usize) {
    let mut rng = TestRng::new(17);
    let r = chi_square_sphere(
        n,
        bins(),
        || {
            let s = light.sample_li(p, rng.next_2d())?;
            let q = light.pdf_li(p, s.wi);
            assert!(
                (q / s.pdf - 1.0).abs() < 1e-2,
                "{name}: sampled pdf {} vs pdf_li {q} at {}",
                s.pdf,
                s.wi
            );
            Some(s.wi)
        },
        |w| light.pdf_li(p, w),
    );
    check(name, r);
}

fn lit(shape: Shape) -> AreaLight {
    AreaLight {
        shape,
        radiance: Rgb::ONE,
        two_sided: false,
    }
}

#[test]
fn sphere_sampling_from_outside_near_and_far() {
    let s = lit(Shape::Sphere {
        center: Vec3::new(0.3, -0.2, 0.1),
        radius: 1.0,
    });
    // Near: sin θmax = 1/1.25 (53°); far: 1/4 (14.5°). Off-axis in x so the
    // cone spans many bins of the test.
    chi_square_area("sphere near", s, Vec3::new(-0.95, -0.2, 0.1), 100_000);
    chi_square_area("sphere far", s, Vec3::new(-3.7, -0.2, 0.1), 100_000);
}

#[test]
fn disk_and_quad_sampling() {
    let disk = lit(Shape::Disk {
        center: Vec3::new(1.0, 0.0, 0.0),
        normal: Vec3::new(-1.0, 0.2, 0.1).normalize(),
        radius: 0.8,
    });
    chi_square_area("disk", disk, Vec3::new(-0.2, 0.1, 0.3), 100_000);
    let quad = lit(Shape::Quad {
        corner: Vec3::new(1.0, -0.7, -0.4),
        edge1: Vec3::new(0.1, 0.0, 1.0),
        edge2: Vec3::new(0.0, 1.5, 0.2),
    });
    // edge1 × edge2 points to −x: the front faces the origin.
    chi_square_area("quad", quad, Vec3::new(-0.1, 0.0, 0.1), 100_000);
}

#[test]
fn sphere_sampling_from_inside_two_sided() {
    let s = AreaLight {
        two_sided: true,
        ..lit(Shape::Sphere {
            center: Vec3::ZERO,
            radius: 2.0,
        })
    };
    chi_square_area("sphere inside", s, Vec3::new(0.5, 0.7, -0.3), 100_000);
    // One-sided: nothing reaches the inside.
    let one = lit(Shape::Sphere {
        center: Vec3::ZERO,
        radius: 2.0,
    });
    assert!(one.sample_li(Vec3::ZERO, [0.3, 0.6]).is_none());
}

/// A 64×32 map, dim everywhere, with a bright spot.
fn spot_map(rotation: f32) -> EnvironmentMap {
    let (w, h) = (64, 32);
    let mut t = vec![Rgb::new(0.05, 0.1, 0.2); w * h];
    for y in 8..12 {
        for x in 40..46 {
            t[y * w + x] = Rgb::new(50.0, 40.0, 30.0);
        }
    }
    EnvironmentMap::new(w, h, t, Rgb::splat(2.0), rotation)
}

#[test]
fn environment_map_sampling() {
    let map = spot_map(0.7);
    let mut rng = TestRng::new(3);
    let mut in_spot = 0usize;
    let n = 200_000;
    // The test bins around its z axis: turn the map's pole (+y) onto it, so
    // the pdf's integrable 1/sin θ peak at the pole lies on a bin edge.
    let to_test = |d: Vec3| Vec3::new(d.z, d.x, d.y);
    let from_test = |t: Vec3| Vec3::new(t.y, t.z, t.x);
    let r = chi_square_sphere(
        n,
        bins(),
        || {
            let s = map.sample_li(rng.next_2d())?;
            assert!((map.pdf(s.wi) / s.pdf - 1.0).abs() < 1e-2, "{}", s.wi);
            // value = L / pdf with L the texel seen in that direction.
            let l = s.value * s.pdf;
            assert!((l - map.eval(s.wi)).abs().max_element() < 1e-3 * l.max_element());
            if l.x > 50.0 {
                in_spot += 1;
            }
            Some(to_test(s.wi))
        },
        |t| map.pdf(from_test(t)),
    );
    check("environment map", r);
    // The spot holds most of the luminance × solid angle: most samples go there.
    assert!(in_spot as f32 / n as f32 > 0.8, "{in_spot}");
}

#[test]
fn environment_lat_long_convention_and_rotation() {
    let map = spot_map(0.0);
    for (uv, d) in [
        (Vec2::new(0.5, 0.5), -Vec3::Z),
        (Vec2::new(0.75, 0.5), Vec3::X),
        (Vec2::new(0.25, 0.5), -Vec3::X),
        (Vec2::new(0.3, 0.0), Vec3::Y),
    ] {
        assert!((map.uv_to_direction(uv) - d).length() < 1e-5, "{uv}");
    }
    let d = Vec3::new(0.3, 0.5, -0.8).normalize();
    assert!((map.uv_to_direction(map.direction_to_uv(d)) - d).length() < 1e-5);
    // Rotating by +90° about +y carries the map's −z column to −x.
    let rot = spot_map(PI / 2.0);
    assert!((rot.uv_to_direction(Vec2::new(0.5, 0.5)) - -Vec3::X).length() < 1e-5);
    assert_eq!(rot.eval(-Vec3::X), map.eval(-Vec3::Z));
    // Constant environment: pdf 1/4π and value L/pdf.
    let c = Environment::Constant(Rgb::splat(0.5));
    let s = c.sample_li([0.2, 0.9]).unwrap();
    assert!((s.pdf - 1.0 / (4.0 * PI)).abs() < 1e-7);
    assert!((s.value.x - 0.5 * 4.0 * PI).abs() < 1e-4);
    let m = Environment::Map(Arc::new(map));
    assert!(!m.is_black());
}

/// E at the origin of a plane with normal +z from a sphere light of radius r
/// whose centre is at height d: `E = π Le (r/d)²` (the sphere is entirely
/// above the horizon when d > r).
#[test]
fn sphere_irradiance_on_facing_plane() {
    let le = 3.0f32;
    for (r, d) in [(0.5f32, 2.0f32), (1.0, 1.3), (0.05, 10.0)] {
        let light = AreaLight {
            radiance: Rgb::splat(le),
            ..lit(Shape::Sphere {
                center: Vec3::new(0.0, 0.0, d),
                radius: r,
            })
        };
        let e = irradiance(&light, Vec3::ZERO, Vec3::Z, 200_000);
        let expected = PI * le * (r / d) * (r / d);
        eprintln!("sphere r {r} d {d}: E {e} vs {expected}");
        assert!((e / expected - 1.0).abs() < 0.01, "{e} vs {expected}");
    }
}

/// On the axis of a disk of radius r at distance d, facing it:
/// `E = π Le r² / (r² + d²)`.
#[test]
fn disk_irradiance_on_axis() {
    let le = 2.0f32;
    for (r, d) in [(1.0f32, 1.0f32), (0.3, 2.0), (2.0, 0.5)] {
        let light = AreaLight {
            radiance: Rgb::splat(le),
            ..lit(Shape::Disk {
                center: Vec3::new(0.0, 0.0, d),
                normal: -Vec3::Z,
                radius: r,
            })
        };
        let e = irradiance(&light, Vec3::ZERO, Vec3::Z, 200_000);
        let expected = PI * le * r * r / (r * r + d * d);
        eprintln!("disk r {r} d {d}: E {e} vs {expected}");
        assert!((e / expected - 1.0).abs() < 0.01, "{e} vs {expected}");
        // Seen from behind, a one-sided disk gives nothing.
        assert_eq!(
            irradiance(&light, Vec3::new(0.0, 0.0, 2.0 * d), -Vec3::Z, 100),
            0.0
        );
    }
}

/// Monte Carlo irradiance `E = ∫ L cos⁺ dω ≈ mean(value · cos⁺)`.
fn irradiance(light: &AreaLight, p: Vec3, n: Vec3, samples: usize) -> f32 {
    let mut rng = TestRng::new(11);
    let mut sum = 0.0f64;
    for _ in 0..samples {
        if let Some(s) = light.sample_li(p, rng.next_2d()) {
            sum += (s.value.x * s.wi.dot(n).max(0.0)) as f64;
        }
    }
    (sum / samples as f64) as f32
}

#[test]
fn power_and_radiance_round_trip() {
    let quad = Shape::Quad {
        corner: Vec3::ZERO,
        edge1: Vec3::new(2.0, 0.0, 0.0),
        edge2: Vec3::new(0.0, 0.0, 3.0),
    };
    // Φ = π Le A, doubled when two-sided.
    let l = AreaLight::from_power(quad, Rgb::splat(60.0), false);
    assert!((l.radiance.x - 60.0 / (PI * 6.0)).abs() < 1e-5);
    let l2 = AreaLight::from_power(quad, Rgb::splat(60.0), true);
    assert!((l2.radiance.x - 60.0 / (2.0 * PI * 6.0)).abs() < 1e-5);
    assert!((l2.power().x - 60.0).abs() < 1e-3);
    let s = AreaLight::from_power(
        Shape::Sphere {
            center: Vec3::ZERO,
            radius: 0.5,
        },
        Rgb::splat(10.0),
        false,
    );
    assert!((s.radiance.x - 10.0 / (PI * 4.0 * PI * 0.25)).abs() < 1e-5);
}

/// The unified homogeneous light gives the separate closed forms: a point
/// light of power Φ at distance r, `E = Φ cos θ / (4π r²)`; a directional
/// light of irradiance E0, `E = E0 cos θ`.
#[test]
fn unified_light_equals_closed_forms() {
    let phi = 100.0f32;
    let pos = Vec3::new(1.0, 2.0, 3.0);
    let point = PointLight::from_power(pos, Rgb::splat(phi));
    let h = HomogeneousLight {
        position: pos.extend(1.0),
        m: Rgb::splat(phi / (4.0 * PI)),
    };
    let e0 = 7.0f32;
    let travel = Vec3::new(0.2, -1.0, 0.3).normalize();
    let dir = DirectionalLight {
        direction: travel,
        irradiance: Rgb::splat(e0),
    };
    let hd = HomogeneousLight {
        position: (-travel).extend(0.0),
        m: Rgb::splat(e0),
    };
    let n = Vec3::new(0.1, 0.9, 0.2).normalize();
    let mut rng = TestRng::new(1);
    for _ in 0..100 {
        let x = Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * 4.0 - 2.0;
        let r = pos - x;
        let closed = phi * (r.normalize().dot(n)).max(0.0) / (4.0 * PI * r.length_squared());
        for s in [h.sample_li(x).unwrap(), point.sample_li(x).unwrap()] {
            let e = s.value.x * s.wi.dot(n).max(0.0);
            assert!(
                (e - closed).abs() <= 1e-5 * closed.max(1e-3),
                "{e} vs {closed}"
            );
            assert!((s.distance - r.length()).abs() < 1e-5);
        }
        let closed_d = e0 * (-travel).dot(n).max(0.0);
        for s in [hd.sample_li(x).unwrap(), dir.sample_li(x).unwrap()] {
            let e = s.value.x * s.wi.dot(n).max(0.0);
            assert!((e - closed_d).abs() < 1e-5, "{e} vs {closed_d}");
            assert!(s.distance.is_infinite());
        }
    }
    assert_eq!(point.homogeneous().position, pos.extend(1.0));
}
