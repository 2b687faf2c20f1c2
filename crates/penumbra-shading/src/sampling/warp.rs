//! Warps from the unit square. Directions are in the local frame (z = normal).

use glam::{Vec2, Vec3};
use std::f32::consts::{FRAC_1_PI, PI};

/// Concentric map of [0,1)² onto the unit disk (Shirley & Chiu 1997);
/// uniform in area, pdf = 1/π. Free of branches (both sectors' values are
/// computed and one is chosen), so that loops over many samples vectorise.
#[inline]
pub fn square_to_disk_concentric(u: [f32; 2]) -> Vec2 {
    let a = 2.0 * u[0] - 1.0;
    let b = 2.0 * u[1] - 1.0;
    // φ = ψ in the sectors around ±x (r = a), φ = π/2 − ψ around ±y
    // (r = b; cos φ = sin ψ, sin φ = cos ψ), with |ψ| ≤ π/4 either way.
    let around_x = a.abs() > b.abs();
    let (r, other) = if around_x { (a, b) } else { (b, a) };
    // The centre (r = 0) maps to 0 whatever ψ; ψ = 0 avoids 0/0.
    let psi = if r == 0.0 {
        0.0
    } else {
        (PI / 4.0) * (other / r)
    };
    let (cos, sin) = cos_sin_within_quarter(psi);
    if around_x {
        Vec2::new(r * cos, r * sin)
    } else {
        Vec2::new(r * sin, r * cos)
    }
}

/// (cos ψ, sin ψ) for |ψ| ≤ π/4: the Taylor polynomials to degree 8 and
/// 9, whose remainders (below ψ¹⁰/10! < 2.5e-8 and ψ¹¹/11! < 1.8e-9) are
/// below half an f32 ulp of the values (cos ψ ≥ 0.7); inline and free of
/// the range reduction a general `sin_cos` makes.
#[inline]
fn cos_sin_within_quarter(psi: f32) -> (f32, f32) {
    let x2 = psi * psi;
    let sin = psi
        * (1.0
            + x2 * (-1.0 / 6.0
                + x2 * (1.0 / 120.0 + x2 * (-1.0 / 5040.0 + x2 * (1.0 / 362_880.0)))));
    let cos = 1.0 + x2 * (-0.5 + x2 * (1.0 / 24.0 + x2 * (-1.0 / 720.0 + x2 * (1.0 / 40_320.0))));
    (cos, sin)
}

/// Cosine-weighted hemisphere (Malley's method). pdf(ω) = cos θ / π
/// with respect to solid angle.
#[inline]
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
///
/// Written with selects, and with `max` and `min` where `clamp` would
/// check its variable bounds, so that a loop over lanes vectorises.
#[inline]
pub fn square_to_triangle(u: [f32; 2]) -> Vec2 {
    let upper = u[1] > u[0];
    // The halved coordinate is the smaller one.
    let half = if upper { u[0] } else { u[1] } / 2.0;
    let b0 = if upper { half } else { u[0] - half };
    let b1 = if upper { u[1] - half } else { half };
    // Kept inside the triangle under rounding.
    let b0 = b0.clamp(0.0, 1.0);
    let b1 = b1.max(0.0).min(1.0 - b0);
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

    /// The polynomials against f64's sin and cos over the whole quarter
    /// (its ends included): within 2⁻²³ in absolute terms, one ulp of
    /// values in [½, 1), where cos always lies and sin at the quarter's
    /// ends; and the concentric map they serve against the same map made
    /// in f64, on a grid that reaches every sector and the diagonals
    /// between them.
    #[test]
    fn quarter_sin_cos_match_f64() {
        let quarter = std::f64::consts::FRAC_PI_4;
        let n = 100_000;
        for i in 0..=n {
            let psi = (-quarter + 2.0 * quarter * i as f64 / n as f64) as f32;
            let (cos, sin) = cos_sin_within_quarter(psi);
            let x = psi as f64;
            let (e_cos, e_sin) = ((cos as f64 - x.cos()).abs(), (sin as f64 - x.sin()).abs());
            assert!(
                e_cos <= 2f64.powi(-23) && e_sin <= 2f64.powi(-23),
                "ψ = {psi}: cos error {e_cos:e}, sin error {e_sin:e}"
            );
        }
        for u in grid(200).chain([[0.75, 0.75], [0.25, 0.75], [0.0, 0.0]]) {
            let (a, b) = (2.0 * u[0] as f64 - 1.0, 2.0 * u[1] as f64 - 1.0);
            let (r, phi) = if a.abs() > b.abs() {
                (a, quarter * (b / a))
            } else {
                (b, 2.0 * quarter - quarter * (a / b))
            };
            let d = square_to_disk_concentric(u);
            let e = ((d.x as f64 - r * phi.cos()).abs()).max((d.y as f64 - r * phi.sin()).abs());
            assert!(e < 4e-7, "{u:?}: {d} is {e:e} off");
        }
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
