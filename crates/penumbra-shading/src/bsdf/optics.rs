//! Geometric optics of smooth surfaces (SEEDS.md, "Optically smooth
//! surfaces"): mirror reflection, Snell refraction with total internal
//! reflection, and the Fresnel reflectance — Schlick's approximation with a
//! complex index n + iκ per RGB band, and the exact dielectric and conductor
//! formulas.
//!
//! The notes write directions as `v` pointing **towards** the surface; the
//! rest of penumbra uses directions pointing away. [`reflect_incident`] and
//! [`refract_incident`] follow the notes literally; [`reflect`] and
//! [`refract`] are the same formulas in the away-pointing convention.

use crate::Rgb;
use glam::Vec3;

/// How a smooth or rough material evaluates Fresnel reflectance.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum FresnelModel {
    /// `F0 + (1 − F0)(1 − cos θ)^5` with F0 from the complex index.
    Schlick,
    /// The exact (unpolarised) Fresnel equations.
    #[default]
    Exact,
}

/// Reflectance at normal incidence of a medium with complex index n + iκ
/// seen from vacuum: `F0 = ((n − 1)² + κ²) / ((n + 1)² + κ²)`.
#[inline]
pub fn f0_from_ior(n: Rgb, k: Rgb) -> Rgb {
    let k2 = k * k;
    ((n - 1.0) * (n - 1.0) + k2) / ((n + 1.0) * (n + 1.0) + k2)
}

/// Schlick's approximation `F0 + (1 − F0)(1 − cos θ)^5`, per band.
#[inline]
pub fn schlick(f0: Rgb, cos_theta: f32) -> Rgb {
    let m = (1.0 - cos_theta.clamp(0.0, 1.0)).powi(5);
    f0 + (Rgb::ONE - f0) * m
}

/// Schlick's approximation for one band.
#[inline]
pub fn schlick_scalar(f0: f32, cos_theta: f32) -> f32 {
    f0 + (1.0 - f0) * (1.0 - cos_theta.clamp(0.0, 1.0)).powi(5)
}

/// Schlick's approximation for a dielectric interface of relative index
/// `eta` = n_inside / n_outside, with `cos_theta_i` measured on the side the
/// light arrives from (negative: from inside). Inside a denser medium the
/// approximation uses the transmitted angle, and is 1 beyond the critical
/// angle, so it too shows total internal reflection.
#[inline]
pub fn schlick_dielectric(cos_theta_i: f32, eta: f32) -> f32 {
    let f0 = ((eta - 1.0) / (eta + 1.0)).powi(2);
    let (cos_i, eta_rel) = if cos_theta_i >= 0.0 {
        (cos_theta_i, eta)
    } else {
        (-cos_theta_i, 1.0 / eta)
    };
    if eta_rel >= 1.0 {
        return schlick_scalar(f0, cos_i);
    }
    // Leaving the denser medium: use cos θt (Snell), TIR past the critical angle.
    let sin2_t = (1.0 - cos_i * cos_i) / (eta_rel * eta_rel);
    if sin2_t >= 1.0 {
        return 1.0;
    }
    schlick_scalar(f0, (1.0 - sin2_t).sqrt())
}

/// Exact unpolarised Fresnel reflectance of a dielectric interface.
///
/// `eta` = n_inside / n_outside (the side the normal points to is outside);
/// `cos_theta_i` < 0 means the light arrives from inside. Returns 1 under total
/// internal reflection. `F = (r_s² + r_p²) / 2` with
/// `r_s = (η_i cos θi − η_t cos θt)/(η_i cos θi + η_t cos θt)` and
/// `r_p = (η_t cos θi − η_i cos θt)/(η_t cos θi + η_i cos θt)`.
#[inline]
pub fn fresnel_dielectric(cos_theta_i: f32, eta: f32) -> f32 {
    let (cos_i, eta) = if cos_theta_i >= 0.0 {
        (cos_theta_i.min(1.0), eta)
    } else {
        ((-cos_theta_i).min(1.0), 1.0 / eta)
    };
    let sin2_t = (1.0 - cos_i * cos_i) / (eta * eta);
    if sin2_t >= 1.0 {
        return 1.0;
    }
    let cos_t = (1.0 - sin2_t).max(0.0).sqrt();
    let r_s = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    let r_p = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    0.5 * (r_s * r_s + r_p * r_p)
}

/// Exact unpolarised Fresnel reflectance of a conductor with complex index
/// n + iκ (relative to the outside medium), for one band; `cos_theta_i` ∈ [0,1].
///
/// Uses the complex Snell law: with `a² + b² = √((n² − κ² − sin²θ)² + 4n²κ²)`,
/// `R_s = (a² + b² − 2a cos θ + cos²θ) / (a² + b² + 2a cos θ + cos²θ)` and
/// `R_p = R_s (a² + b² − 2a sin θ tan θ + sin²θ tan²θ) / (a² + b² + 2a sin θ tan θ + sin²θ tan²θ)`.
#[inline]
pub fn fresnel_conductor_scalar(cos_theta_i: f32, n: f32, k: f32) -> f32 {
    let cos = cos_theta_i.clamp(0.0, 1.0);
    let cos2 = cos * cos;
    let sin2 = 1.0 - cos2;
    let t0 = n * n - k * k - sin2;
    let a2b2 = (t0 * t0 + 4.0 * n * n * k * k).sqrt();
    let a = (0.5 * (a2b2 + t0)).max(0.0).sqrt();
    let t1 = a2b2 + cos2;
    let t2 = 2.0 * a * cos;
    let rs = (t1 - t2) / (t1 + t2);
    let t3 = cos2 * a2b2 + sin2 * sin2;
    let t4 = t2 * sin2;
    let rp = rs * (t3 - t4) / (t3 + t4);
    let r = 0.5 * (rp + rs);
    if r.is_finite() { r } else { 1.0 }
}

/// [`fresnel_conductor_scalar`] per RGB band.
#[inline]
pub fn fresnel_conductor(cos_theta_i: f32, n: Rgb, k: Rgb) -> Rgb {
    Rgb::new(
        fresnel_conductor_scalar(cos_theta_i, n.x, k.x),
        fresnel_conductor_scalar(cos_theta_i, n.y, k.y),
        fresnel_conductor_scalar(cos_theta_i, n.z, k.z),
    )
}

/// The notes' reflection `R = v − 2 n (n·v)`, `v` pointing towards the surface.
#[inline]
pub fn reflect_incident(v: Vec3, n: Vec3) -> Vec3 {
    v - 2.0 * n * n.dot(v)
}

/// The notes' refraction of `v` (unit, pointing towards the surface) through
/// a surface with unit normal `n` on v's side, `eta` = sin θin / sin θ =
/// n_t / n_i: `cos α = −v·n`, `disc = 1 − (1 − cos²α)/η²`; `None` (total
/// internal reflection) if `disc < 0`, else `T = v/η + n (cos α/η − √disc)`.
#[inline]
pub fn refract_incident(v: Vec3, n: Vec3, eta: f32) -> Option<Vec3> {
    let cos_a = -v.dot(n);
    let disc = 1.0 - (1.0 - cos_a * cos_a) / (eta * eta);
    if disc < 0.0 {
        return None;
    }
    Some(v / eta + n * (cos_a / eta - disc.sqrt()))
}

/// Mirror direction of `wo` (pointing away) about `n`: `2 (n·wo) n − wo`.
#[inline]
pub fn reflect(wo: Vec3, n: Vec3) -> Vec3 {
    reflect_incident(-wo, n)
}

/// Refracted direction (pointing away, on the far side) of light leaving
/// along `wo` (pointing away from the surface, on the side of `n`), where
/// `eta` = n_far / n_near. `None` under total internal reflection.
#[inline]
pub fn refract(wo: Vec3, n: Vec3, eta: f32) -> Option<Vec3> {
    refract_incident(-wo, n, eta)
}

/// Critical angle [rad] for light leaving a medium of index `n_inside` into
/// one of index `n_outside` < n_inside: `asin(n_outside / n_inside)`.
pub fn critical_angle(n_inside: f32, n_outside: f32) -> Option<f32> {
    (n_outside < n_inside).then(|| (n_outside / n_inside).asin())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn notes_quiz_f0() {
        // Quiz 1: n = 1.4 → 2.78 %, glass n = 1.5 → 4 %.
        let f = f0_from_ior(Rgb::splat(1.4), Rgb::ZERO).x;
        assert!((f - 0.02778).abs() < 5e-5, "{f}");
        let g = f0_from_ior(Rgb::splat(1.5), Rgb::ZERO).x;
        assert!((g - 0.04).abs() < 1e-6);
        // Exact and Schlick agree at normal incidence.
        assert!((fresnel_dielectric(1.0, 1.4) - f).abs() < 1e-6);
        assert!((fresnel_conductor_scalar(1.0, 1.4, 0.0) - f).abs() < 1e-6);
        assert!((schlick_dielectric(1.0, 1.4) - f).abs() < 1e-6);
    }

    #[test]
    fn notes_quiz_total_internal_reflection() {
        // Quiz 3: leaving n = 10 into air: TIR from asin(0.1) = 5.74°.
        let crit = critical_angle(10.0, 1.0).unwrap().to_degrees();
        assert!((crit - 5.739).abs() < 1e-3, "{crit}");
        let n = Vec3::Z;
        for (deg, tir) in [(5.6f32, false), (5.8, true), (30.0, true)] {
            let t = deg.to_radians();
            // Inside the medium (below the surface), heading up towards it.
            let v = Vec3::new(t.sin(), 0.0, t.cos());
            // Normal on v's side is −z, relative index n_t/n_i = 1/10.
            assert_eq!(refract_incident(v, -n, 0.1).is_none(), tir, "{deg}");
            let f = fresnel_dielectric(-t.cos(), 10.0);
            assert_eq!(f == 1.0, tir, "{deg}: F = {f}");
            assert_eq!(schlick_dielectric(-t.cos(), 10.0) == 1.0, tir);
        }
    }

    #[test]
    fn snell_law_and_reflection() {
        let n = Vec3::Z;
        for deg in [0.0f32, 10.0, 45.0, 80.0] {
            let t = deg.to_radians();
            let v = Vec3::new(t.sin(), 0.0, -t.cos()); // towards the surface
            let r = reflect_incident(v, n);
            assert!((r - Vec3::new(t.sin(), 0.0, t.cos())).length() < 1e-6);
            let tr = refract_incident(v, n, 1.5).unwrap();
            assert!((tr.length() - 1.0).abs() < 1e-5);
            assert!((t.sin() - 1.5 * tr.x).abs() < 1e-5, "sin θi = η sin θt");
            assert!(tr.z < 0.0);
            // Away-pointing forms agree.
            assert!((reflect(-v, n) - r).length() < 1e-6);
            assert!((refract(-v, n, 1.5).unwrap() - tr).length() < 1e-6);
        }
    }

    #[test]
    fn fresnel_energy_and_limits() {
        for i in 0..=100 {
            let c = i as f32 / 100.0;
            let fd = fresnel_dielectric(c, 1.5);
            assert!((0.0..=1.0).contains(&fd));
            // Reciprocal interface: F(θi, η) = F(θt, 1/η) seen from inside.
            let sin_t = (1.0 - c * c).sqrt() / 1.5;
            let cos_t = (1.0 - sin_t * sin_t).sqrt();
            if i > 0 {
                assert!((fd - fresnel_dielectric(-cos_t, 1.5)).abs() < 1e-4, "{c}");
            }
            let fc = fresnel_conductor(c, Rgb::new(0.2, 0.9, 1.1), Rgb::new(3.0, 2.4, 1.8));
            assert!(fc.min_element() >= 0.0 && fc.max_element() <= 1.0);
            let s = schlick(Rgb::splat(0.04), c);
            assert!(s.x >= 0.04 - 1e-7 && s.x <= 1.0);
        }
        assert!((fresnel_dielectric(0.0, 1.5) - 1.0).abs() < 1e-6);
        assert!((fresnel_conductor_scalar(0.0, 0.2, 3.0) - 1.0).abs() < 1e-5);
        // A conductor with κ = 0 is a dielectric.
        for c in [0.1f32, 0.5, 0.9] {
            assert!(
                (fresnel_conductor_scalar(c, 1.5, 0.0) - fresnel_dielectric(c, 1.5)).abs() < 1e-5
            );
        }
    }
}
