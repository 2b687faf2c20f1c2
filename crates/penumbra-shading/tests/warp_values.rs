//! Warps, the MIS weight and the refraction edge cases at points whose
//! values are known in closed form (computed by hand from the published
//! definitions, not by the functions under test). The statistical tests
//! beside the code check the distributions; these pin the maps themselves,
//! including on the lines and corners a distribution never sees.

use glam::{Vec2, Vec3};
use penumbra_shading::bsdf::optics::{critical_angle, refract_incident};
use penumbra_shading::sampling::{
    UNIFORM_SPHERE_PDF, cosine_hemisphere_pdf, power_heuristic, square_to_disk_concentric,
    square_to_triangle,
};
use std::f32::consts::PI;

fn near(a: Vec2, b: Vec2, what: &str) {
    assert!((a - b).length() < 1e-6, "{what}: {a} vs {b}");
}

/// Shirley & Chiu's concentric map: (a, b) = 2u − 1; |a| > |b|: r = a,
/// φ = (π/4)(b/a); else r = b, φ = π/2 − (π/4)(a/b).
#[test]
fn concentric_disk_at_known_points() {
    near(square_to_disk_concentric([0.5, 0.5]), Vec2::ZERO, "centre");
    near(
        square_to_disk_concentric([1.0, 0.5]),
        Vec2::new(1.0, 0.0),
        "right edge",
    );
    near(
        square_to_disk_concentric([0.5, 1.0]),
        Vec2::new(0.0, 1.0),
        "top edge",
    );
    near(
        square_to_disk_concentric([0.0, 0.5]),
        Vec2::new(-1.0, 0.0),
        "left edge",
    );
    near(
        square_to_disk_concentric([0.5, 0.0]),
        Vec2::new(0.0, -1.0),
        "bottom edge",
    );
    // On the axes through the centre (a = 0 or b = 0 alone).
    near(
        square_to_disk_concentric([0.5, 0.9]),
        Vec2::new(0.0, 0.8),
        "a = 0",
    );
    near(
        square_to_disk_concentric([0.9, 0.5]),
        Vec2::new(0.8, 0.0),
        "b = 0",
    );
    // a = 0.5, b = 0.25: r = 0.5, φ = π/8.
    let (c, s) = ((PI / 8.0).cos(), (PI / 8.0).sin());
    near(
        square_to_disk_concentric([0.75, 0.625]),
        Vec2::new(0.5 * c, 0.5 * s),
        "|a| > |b|",
    );
    // a = 0.25, b = 0.5: r = 0.5, φ = 3π/8.
    near(
        square_to_disk_concentric([0.625, 0.75]),
        Vec2::new(0.5 * s, 0.5 * c),
        "|a| < |b|",
    );
    // a = −0.5, b = −0.25: r = −0.5, φ = π/8.
    near(
        square_to_disk_concentric([0.25, 0.375]),
        Vec2::new(-0.5 * c, -0.5 * s),
        "third quadrant",
    );
    // a = −0.25, b = 0.5: r = 0.5, φ = π/2 + π/8.
    near(
        square_to_disk_concentric([0.375, 0.75]),
        Vec2::new(-0.5 * s, 0.5 * c),
        "second quadrant",
    );
    // The corner (1, 1) lands on the circle at 45°.
    let h = std::f32::consts::FRAC_1_SQRT_2;
    near(
        square_to_disk_concentric([1.0, 1.0]),
        Vec2::new(h, h),
        "corner",
    );
}

/// Heitz 2019: u₁ > u₀: b₀ = u₀/2, b₁ = u₁ − b₀; else b₁ = u₁/2, b₀ = u₀ − b₁.
#[test]
fn triangle_map_at_known_points() {
    near(
        square_to_triangle([0.2, 0.6]),
        Vec2::new(0.1, 0.5),
        "u1 > u0",
    );
    near(
        square_to_triangle([0.6, 0.2]),
        Vec2::new(0.5, 0.1),
        "u1 < u0",
    );
    near(square_to_triangle([0.0, 0.0]), Vec2::ZERO, "vertex 0");
    near(
        square_to_triangle([1.0, 0.0]),
        Vec2::new(1.0, 0.0),
        "vertex 1",
    );
    near(
        square_to_triangle([0.0, 1.0]),
        Vec2::new(0.0, 1.0),
        "vertex 2",
    );
    near(
        square_to_triangle([1.0, 1.0]),
        Vec2::new(0.5, 0.5),
        "far corner",
    );
    // Rounding: at u = (1, 5.8e-8), b₁ = 2.9e-8 and b₀ = fl(1 − b₁) = 1, so
    // b₀ + b₁ > 1 unless b₁ is clamped to 1 − b₀ = 0: the point must stay
    // in the triangle (b₂ = 1 − b₀ − b₁ ≥ 0, as the tracer computes it).
    let b = square_to_triangle([1.0, 5.8e-8]);
    assert!(1.0 - b.x - b.y >= 0.0, "outside the triangle: {b}");
    assert_eq!(b, Vec2::new(1.0, 0.0));
}

/// Veach's power heuristic (β = 2): w = a² / (a² + b²).
#[test]
fn power_heuristic_values() {
    assert_eq!(power_heuristic(1.0, 1.0), 0.5);
    assert!((power_heuristic(3.0, 4.0) - 9.0 / 25.0).abs() < 1e-7);
    assert!((power_heuristic(4.0, 3.0) - 16.0 / 25.0).abs() < 1e-7);
    assert_eq!(power_heuristic(2.0, 0.0), 1.0);
    assert_eq!(power_heuristic(0.0, 2.0), 0.0);
    // No strategy could have made the sample: weight 0, not NaN.
    assert_eq!(power_heuristic(0.0, 0.0), 0.0);
}

#[test]
fn refraction_edge_cases() {
    // η = 1: every ray passes straight, even one grazing the surface
    // (cos α = 0, disc = 1 − 1/1 = 0 exactly: not total reflection).
    assert_eq!(refract_incident(Vec3::X, Vec3::Y, 1.0), Some(Vec3::X));
    // Leaving glass (η = 1/1.5) past the critical angle: none.
    let v = Vec3::new(0.8, -0.6, 0.0);
    assert_eq!(refract_incident(v, Vec3::Y, 1.0 / 1.5), None);
    // Equal indices have no critical angle; glass to air asin(1/1.5).
    assert_eq!(critical_angle(1.5, 1.5), None);
    assert_eq!(critical_angle(1.0, 1.5), None);
    let c = critical_angle(1.5, 1.0).unwrap();
    assert!((c - (1.0f32 / 1.5).asin()).abs() < 1e-7 && (c.to_degrees() - 41.81).abs() < 0.01);
}

/// The densities: uniform sphere 1/(4π) = 0.0795775 sr⁻¹; cosine
/// hemisphere cos θ / π (0.5/π = 0.1591549 at 60°, 0 below the horizon).
#[test]
fn warp_densities() {
    assert!((UNIFORM_SPHERE_PDF - 0.079_577_47).abs() < 1e-8);
    assert!((cosine_hemisphere_pdf(0.5) - 0.159_154_94).abs() < 1e-8);
    assert!((cosine_hemisphere_pdf(1.0) - 1.0 / PI).abs() < 1e-7);
    assert_eq!(cosine_hemisphere_pdf(-0.3), 0.0);
}
