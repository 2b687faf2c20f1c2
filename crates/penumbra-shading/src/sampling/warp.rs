//! Warps from the unit square. Directions are in the local frame (z = normal).

use glam::{Vec2, Vec3};
use std::f32::consts::{FRAC_1_PI, PI};

/// Concentric map of [0,1)² onto the unit disk (Shirley & Chiu 1997);
/// uniform in area, pdf = 1/π.
pub fn square_to_disk_concentric(u: [f32; 2]) -> Vec2 {
    let a = 2.0 * u[0] - 1.0;
    let b = 2.0 * u[1] - 1.0;
    if a == 0.0 && b == 0.0 {
        return Vec2::ZERO;
    }
    let (r, phi) = if a.abs() > b.abs() {
        (a, (PI / 4.0) * (b / a))
    } else {
        (b, PI / 2.0 - (PI / 4.0) * (a / b))
    };
    Vec2::new(r * phi.cos(), r * phi.sin())
}

/// Cosine-weighted hemisphere (Malley's method). pdf(ω) = cos θ / π
/// with respect to solid angle.
pub fn square_to_cosine_hemisphere(u: [f32; 2]) -> Vec3 {
    let d = square_to_disk_concentric(u);
    let z = (1.0 - d.length_squared()).max(0.0).sqrt();
    Vec3::new(d.x, d.y, z)
}

/// Density of [`square_to_cosine_hemisphere`] in solid angle: cos⁺θ / π.
pub fn cosine_hemisphere_pdf(cos_theta: f32) -> f32 {
    cos_theta.max(0.0) * FRAC_1_PI
}

/// Uniform direction on the unit sphere; pdf = 1/(4π) per steradian.
pub fn square_to_uniform_sphere(u: [f32; 2]) -> Vec3 {
    let z = 1.0 - 2.0 * u[0];
    let r = (1.0 - z * z).max(0.0).sqrt();
    let phi = 2.0 * PI * u[1];
    Vec3::new(r * phi.cos(), r * phi.sin(), z)
}

/// Density of [`square_to_uniform_sphere`]: 1/(4π).
pub const UNIFORM_SPHERE_PDF: f32 = 1.0 / (4.0 * PI);

/// Uniform point on a triangle as barycentrics (b1, b2) (Heitz 2019,
/// "A Low-Distortion Map Between Triangle and Square"); pdf = 1/area.
pub fn square_to_triangle(u: [f32; 2]) -> Vec2 {
    let (mut b0, mut b1);
    if u[1] > u[0] {
        b0 = u[0] / 2.0;
        b1 = u[1] - b0;
    } else {
        b1 = u[1] / 2.0;
        b0 = u[0] - b1;
    }
    // keep inside the triangle under rounding
    b0 = b0.clamp(0.0, 1.0);
    b1 = b1.clamp(0.0, 1.0 - b0);
    Vec2::new(b0, b1)
}

/// Power heuristic with β = 2 (Veach 1997): w = a² / (a² + b²).
pub fn power_heuristic(pdf_a: f32, pdf_b: f32) -> f32 {
    let a2 = pdf_a * pdf_a;
    let b2 = pdf_b * pdf_b;
    if a2 + b2 == 0.0 { 0.0 } else { a2 / (a2 + b2) }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn grid(n: usize) -> impl Iterator<Item = [f32; 2]> {
        (0..n * n).map(move |i| {
            [
                ((i % n) as f32 + 0.5) / n as f32,
                ((i / n) as f32 + 0.5) / n as f32,
            ]
        })
    }

    #[test]
    fn cosine_hemisphere_moments() {
        // E[cos θ] under cos/π density = 2/3; all samples on the upper hemisphere.
        let n = 512;
        let mut sum = 0.0f64;
        for u in grid(n) {
            let w = square_to_cosine_hemisphere(u);
            assert!((w.length() - 1.0).abs() < 1e-4 && w.z >= 0.0);
            sum += w.z as f64;
        }
        assert!((sum / (n * n) as f64 - 2.0 / 3.0).abs() < 1e-3);
    }

    #[test]
    fn uniform_sphere_moments() {
        let n = 512;
        let mut s = Vec3::ZERO;
        let mut z2 = 0.0f64;
        for u in grid(n) {
            let w = square_to_uniform_sphere(u);
            s += w;
            z2 += (w.z * w.z) as f64;
        }
        assert!(s.length() / ((n * n) as f32) < 1e-3);
        assert!((z2 / (n * n) as f64 - 1.0 / 3.0).abs() < 1e-3);
    }

    #[test]
    fn triangle_is_uniform() {
        // Mean of barycentrics = (1/3, 1/3) and all inside.
        let n = 400;
        let mut m = Vec2::ZERO;
        for u in grid(n) {
            let b = square_to_triangle(u);
            assert!(b.x >= 0.0 && b.y >= 0.0 && b.x + b.y <= 1.0 + 1e-6);
            m += b;
        }
        m /= (n * n) as f32;
        assert!((m - Vec2::splat(1.0 / 3.0)).length() < 1e-3);
    }

    #[test]
    fn power_heuristic_sums_to_one() {
        assert!((power_heuristic(2.0, 3.0) + power_heuristic(3.0, 2.0) - 1.0).abs() < 1e-6);
        assert_eq!(power_heuristic(0.0, 0.0), 0.0);
    }
}
