//! The analytic area lights against values worked by hand: bounds, ray
//! hits (near and far roots, tangent rays, rays starting on the surface),
//! the sampled point of a quad, the sampled distance to a sphere, power,
//! one-sided emission, and the consistency of `sample_li` with `pdf_li`
//! from inside, on and outside a sphere.

use glam::Vec3;
use penumbra_shading::Rgb;
use penumbra_shading::light::{AreaLight, Shape};
use penumbra_shading::stats::TestRng;
use std::f32::consts::PI;

fn near(a: Vec3, b: Vec3, what: &str) {
    assert!(
        (a - b).length() <= 1e-5 * b.length().max(1.0),
        "{what}: {a} vs {b}"
    );
}

/// Sphere and disk: centre ± r. The quad corner (1, 0, 0), edges (0, 2, 0)
/// and (−3, 0, 1) has the corners (1, 0, 0), (1, 2, 0), (−2, 0, 1),
/// (−2, 2, 1): the box (−2, 0, 0)–(1, 2, 1).
#[test]
fn bounds_by_hand() {
    let c = Vec3::new(1.0, 2.0, 3.0);
    let sphere = Shape::Sphere {
        center: c,
        radius: 0.5,
    };
    let disk = Shape::Disk {
        center: c,
        normal: Vec3::Y,
        radius: 0.5,
    };
    for s in [sphere, disk] {
        assert_eq!(
            s.bounds(),
            (Vec3::new(0.5, 1.5, 2.5), Vec3::new(1.5, 2.5, 3.5))
        );
    }
    let quad = Shape::Quad {
        corner: Vec3::new(1.0, 0.0, 0.0),
        edge1: Vec3::new(0.0, 2.0, 0.0),
        edge2: Vec3::new(-3.0, 0.0, 1.0),
    };
    assert_eq!(
        quad.bounds(),
        (Vec3::new(-2.0, 0.0, 0.0), Vec3::new(1.0, 2.0, 1.0))
    );
    // Corner (1, 0, 0), edges (1, 1, 0) and (1, −1, 1): the corners
    // (1, 0, 0), (2, 1, 0), (2, −1, 1) and (3, 0, 1), the last alone
    // reaching x = 3.
    let skew = Shape::Quad {
        corner: Vec3::new(1.0, 0.0, 0.0),
        edge1: Vec3::new(1.0, 1.0, 0.0),
        edge2: Vec3::new(1.0, -1.0, 1.0),
    };
    assert_eq!(
        skew.bounds(),
        (Vec3::new(1.0, -1.0, 0.0), Vec3::new(3.0, 1.0, 1.0))
    );
}

/// The unit sphere at (0, 0, 5): from the origin along +z the near root
/// t = 4 (normal −z); from its centre along +x the far root t = 1; from the
/// surface point (0, 0, 4) inwards the far side at t = 2 (not t = 0); a
/// tangent ray from (1, 0, 0) along +z touches (1, 0, 5); tmax and a ray
/// pointing away give nothing.
#[test]
fn sphere_hits_by_hand() {
    let s = Shape::Sphere {
        center: Vec3::new(0.0, 0.0, 5.0),
        radius: 1.0,
    };
    let h = s.intersect(Vec3::ZERO, Vec3::Z, f32::INFINITY).unwrap();
    assert_eq!(h.t, 4.0);
    near(h.p, Vec3::new(0.0, 0.0, 4.0), "near root");
    near(h.n, -Vec3::Z, "normal at the near root");
    let h = s
        .intersect(Vec3::new(0.0, 0.0, 5.0), Vec3::X, f32::INFINITY)
        .unwrap();
    assert_eq!(h.t, 1.0);
    near(h.n, Vec3::X, "normal from inside");
    let h = s
        .intersect(Vec3::new(0.0, 0.0, 4.0), Vec3::Z, f32::INFINITY)
        .unwrap();
    assert_eq!(h.t, 2.0, "from the surface inwards");
    near(h.n, Vec3::Z, "far side");
    let h = s
        .intersect(Vec3::new(1.0, 0.0, 0.0), Vec3::Z, f32::INFINITY)
        .unwrap();
    assert_eq!(h.t, 5.0, "tangent");
    near(h.n, Vec3::X, "tangent normal");
    assert!(
        s.intersect(Vec3::ZERO, Vec3::Z, 3.5).is_none(),
        "beyond tmax"
    );
    assert!(
        s.intersect(Vec3::ZERO, -Vec3::Z, f32::INFINITY).is_none(),
        "away"
    );
}

/// A disk of radius 1 in the plane z = 2: a ray behind it, or starting in
/// its plane, does not hit it (no hit at t ≤ 0); from below it hits at 2.
#[test]
fn disk_hits_only_ahead() {
    let d = Shape::Disk {
        center: Vec3::new(0.0, 0.0, 2.0),
        normal: -Vec3::Z,
        radius: 1.0,
    };
    assert_eq!(
        d.intersect(Vec3::ZERO, Vec3::Z, f32::INFINITY).unwrap().t,
        2.0
    );
    assert!(
        d.intersect(Vec3::ZERO, -Vec3::Z, f32::INFINITY).is_none(),
        "behind"
    );
    let on = Vec3::new(0.5, 0.0, 2.0);
    assert!(
        d.intersect(on, Vec3::Z, f32::INFINITY).is_none(),
        "from its plane"
    );
    assert!(
        d.intersect(on, -Vec3::Z, f32::INFINITY).is_none(),
        "from its plane"
    );
}

/// Quad corner (−1, −1, 2), edges (0, 2, 0) and (2, 0, 0): front normal
/// e1 × e2 = −z, towards the origin. u = (0.25, 0.75) samples
/// q = (−1, −1, 2) + 0.25 e1 + 0.75 e2 = (0.5, −0.5, 2): distance √4.5,
/// cos θl = 2/√4.5, pdf = d²/(A cos θl) = 4.5 √4.5 / 8, value = Le / pdf.
#[test]
fn quad_sample_by_hand() {
    let l = AreaLight {
        shape: Shape::Quad {
            corner: Vec3::new(-1.0, -1.0, 2.0),
            edge1: Vec3::new(0.0, 2.0, 0.0),
            edge2: Vec3::new(2.0, 0.0, 0.0),
        },
        radiance: Rgb::new(3.0, 2.0, 1.0),
        two_sided: false,
    };
    let s = l.sample_li(Vec3::ZERO, [0.25, 0.75]).unwrap();
    let d = 4.5f32.sqrt();
    near(
        s.wi * s.distance,
        Vec3::new(0.5, -0.5, 2.0),
        "sampled point",
    );
    assert!((s.distance - d).abs() < 1e-5);
    let pdf = 4.5 * d / 8.0;
    assert!((s.pdf - pdf).abs() < 1e-5 * pdf, "{} vs {pdf}", s.pdf);
    near(s.value, l.radiance / pdf, "Le / pdf");
    assert!((l.pdf_li(Vec3::ZERO, s.wi) - pdf).abs() < 1e-5 * pdf);
    // From above, the one-sided quad shows its back: nothing, density 0.
    let above = Vec3::new(0.0, 0.0, 4.0);
    assert!(l.sample_li(above, [0.25, 0.75]).is_none());
    assert_eq!(l.pdf_li(above, -Vec3::Z), 0.0);
}

/// Power Φ = π Le A per emitting side; a two-sided sphere still counts one
/// side (its inner light stays inside). One-sided emission is zero in the
/// surface's own plane.
#[test]
fn power_and_emission_by_hand() {
    let sphere = Shape::Sphere {
        center: Vec3::ZERO,
        radius: 2.0,
    };
    let quad = Shape::Quad {
        corner: Vec3::ZERO,
        edge1: Vec3::new(3.0, 0.0, 0.0),
        edge2: Vec3::new(0.0, 2.0, 0.0),
    };
    for two_sided in [false, true] {
        let s = AreaLight {
            shape: sphere,
            radiance: Rgb::splat(1.5),
            two_sided,
        };
        let phi = PI * 1.5 * 16.0 * PI;
        assert!(
            (s.power().x - phi).abs() < 1e-4 * phi,
            "sphere, two-sided {two_sided}"
        );
        let q = AreaLight {
            shape: quad,
            radiance: Rgb::splat(1.5),
            two_sided,
        };
        let phi = PI * 1.5 * 6.0 * if two_sided { 2.0 } else { 1.0 };
        assert!(
            (q.power().x - phi).abs() < 1e-4 * phi,
            "quad, two-sided {two_sided}"
        );
        let back = AreaLight::from_power(quad, Rgb::splat(phi), two_sided);
        assert!((back.radiance.x - 1.5).abs() < 1e-5);
    }
    let one = AreaLight {
        shape: quad,
        radiance: Rgb::ONE,
        two_sided: false,
    };
    assert_eq!(one.emitted(Vec3::Z, Vec3::new(0.3, 0.4, 0.1)), Rgb::ONE);
    assert_eq!(one.emitted(Vec3::Z, Vec3::X), Rgb::ZERO, "in the plane");
    assert_eq!(one.emitted(Vec3::Z, -Vec3::Z), Rgb::ZERO, "behind");
}

/// Sampling a sphere light from outside (the cone) and from inside (uniform
/// area): every sample's pdf is `pdf_li` of its direction, and its distance
/// is where that direction's ray meets the sphere. (A point exactly on the
/// sphere is left out: `pdf_li`'s ray from it meets the surface at t ≈ 0.)
#[test]
fn sphere_samples_agree_with_pdf_and_hit_distance() {
    let center = Vec3::new(0.5, -1.0, 2.0);
    let l = AreaLight {
        shape: Shape::Sphere {
            center,
            radius: 1.5,
        },
        radiance: Rgb::ONE,
        two_sided: true,
    };
    let mut rng = TestRng::new(3);
    // r = 1.5, not 2 (where r + r = r · r), and an inside point farther
    // than 1 from the centre (r/r = 1): wrong formulas do not happen to
    // agree here.
    for (p, what) in [
        (center + Vec3::new(0.0, 0.0, -7.0), "outside"),
        (center + Vec3::new(2.0, 0.0, 0.0), "just outside"),
        (center + Vec3::new(1.2, 0.0, 0.0), "inside"),
    ] {
        let mut n = 0;
        for _ in 0..200 {
            let Some(s) = l.sample_li(p, rng.next_2d()) else {
                continue;
            };
            n += 1;
            let pdf = l.pdf_li(p, s.wi);
            assert!(
                (s.pdf - pdf).abs() <= 1e-3 * pdf,
                "{what}: pdf {} vs {pdf}",
                s.pdf
            );
            let hit = l.shape.intersect(p, s.wi, f32::INFINITY).expect("a hit");
            assert!(
                (s.distance - hit.t).abs() <= 1e-3 * hit.t.max(1.0),
                "{what}: {} vs {}",
                s.distance,
                hit.t
            );
        }
        assert!(n > 150, "{what}: {n} samples");
    }
}
