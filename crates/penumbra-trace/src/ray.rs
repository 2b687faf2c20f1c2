//! Rays and robust spawning of secondary rays.

use glam::Vec3;

/// A ray `o + t d`, `t ∈ (0, tmax)`. `d` is unit length for all rays penumbra
/// spawns, so `t` is a distance.
#[derive(Clone, Copy, Debug)]
pub struct Ray {
    pub origin: Vec3,
    pub direction: Vec3,
    pub tmax: f32,
}

impl Ray {
    pub fn new(origin: Vec3, direction: Vec3) -> Self {
        Self {
            origin,
            direction,
            tmax: f32::INFINITY,
        }
    }

    pub fn segment(origin: Vec3, direction: Vec3, tmax: f32) -> Self {
        Self {
            origin,
            direction,
            tmax,
        }
    }

    pub fn at(&self, t: f32) -> Vec3 {
        self.origin + self.direction * t
    }
}

/// Moves a surface point off the surface along the geometric normal `n`
/// (pointing to the side the new ray leaves from) so the new ray cannot hit
/// the surface it starts on.
///
/// Wächter & Binder 2019, "A Fast and Robust Method for Avoiding
/// Self-Intersection" (Ray Tracing Gems, ch. 6): offset by a fixed number of
/// ulps of each coordinate (256·n in integer ulps), and by a small absolute
/// amount (n/65536) near the origin where ulps are tiny.
pub fn offset_ray_origin(p: Vec3, n: Vec3) -> Vec3 {
    Vec3::new(
        offset_coordinate(p.x, n.x),
        offset_coordinate(p.y, n.y),
        offset_coordinate(p.z, n.z),
    )
}

/// [`offset_ray_origin`] of one coordinate `p` along normal component `n`:
/// 256·n integer ulps away from zero's side, or n/65536 where |p| < 1/32.
/// Without branches (both cases computed, one chosen), so that a loop over
/// many points (the wavefront path tracer's lanes) vectorises.
///
/// The integer step is `(256 n) as i32` for |256 n| ≤ 2²² (n a normal's
/// component), 0 for a NaN, converted without `as`'s saturating checks,
/// which kept such loops scalar.
#[inline(always)]
#[allow(unsafe_code)]
pub(crate) fn offset_coordinate(p: f32, n: f32) -> f32 {
    const ORIGIN: f32 = 1.0 / 32.0;
    const FLOAT_SCALE: f32 = 1.0 / 65536.0;
    const INT_SCALE: f32 = 256.0;
    const LIMIT: f32 = (1 << 22) as f32;
    let x = (INT_SCALE * n).clamp(-LIMIT, LIMIT);
    let x = if x.is_nan() { 0.0 } else { x };
    // SAFETY: x is finite and within i32's range.
    let of_i: i32 = unsafe { x.to_int_unchecked() };
    let bits = p.to_bits() as i32;
    let moved = if p < 0.0 {
        bits.wrapping_sub(of_i)
    } else {
        bits.wrapping_add(of_i)
    };
    if p.abs() < ORIGIN {
        p + FLOAT_SCALE * n
    } else {
        f32::from_bits(moved as u32)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rays_and_points_along_them() {
        let (o, d) = (Vec3::new(1.0, -2.0, 3.0), Vec3::new(0.0, 0.6, 0.8));
        let r = Ray::new(o, d);
        assert_eq!((r.origin, r.direction, r.tmax), (o, d, f32::INFINITY));
        assert_eq!(r.at(2.5), Vec3::new(1.0, -0.5, 5.0));
        let s = Ray::segment(o, d, 4.0);
        assert_eq!((s.origin, s.direction, s.tmax), (o, d, 4.0));
    }

    /// Hand-computed offsets. Away from 0 a coordinate moves by 256·n ulps:
    /// 1 + 256·2⁻²³ = 1 + 2⁻¹⁵; −2 moves up by 128 ulps of the binade
    /// below it (2⁻²³): −2 + 2⁻¹⁶; 1/32 (the first value that moves by
    /// ulps) moves down by 64 ulps of 2⁻²⁹: 1/32 − 2⁻²³; −8 by 0 ulps
    /// (256 · 0.001 truncates to 0). Near 0 it moves by n/65536:
    /// 0.01 − 4·2⁻¹⁶, −0.03 + 2⁻¹⁶.
    #[test]
    fn offsets_by_hand() {
        let q = offset_ray_origin(Vec3::new(1.0, -2.0, 0.01), Vec3::new(1.0, 0.5, -4.0));
        let exp2 = |e: i32| 2f32.powi(e);
        assert_eq!(
            q,
            Vec3::new(1.0 + exp2(-15), -2.0 + exp2(-16), 0.01 - exp2(-14))
        );
        let q = offset_ray_origin(
            Vec3::new(1.0 / 32.0, -8.0, -0.03),
            Vec3::new(-0.25, 1e-3, 1.0),
        );
        let expected = Vec3::new(1.0 / 32.0 - exp2(-23), -8.0, -0.03 + exp2(-16));
        assert_eq!(q, expected);
        // Just below 1/32 the absolute offset applies: 2⁻¹⁶ · (−0.25).
        let below = (1.0f32 / 32.0).next_down();
        let q = offset_ray_origin(Vec3::splat(below), Vec3::splat(-0.25));
        assert_eq!(q, Vec3::splat(below - exp2(-18)));
    }

    #[test]
    fn offset_moves_to_the_normal_side() {
        for p in [
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(1000.0, -200.0, 3.0),
            Vec3::new(-5e5, 1e-3, 7.0),
        ] {
            for n in [Vec3::X, -Vec3::Y, Vec3::new(0.3, -0.4, 0.866).normalize()] {
                let q = offset_ray_origin(p, n);
                assert!((q - p).dot(n) > 0.0, "{p} {n} {q}");
                // 256 ulps ≈ 256 · 2⁻²³ · |p| per coordinate, or 1/65536 near 0.
                assert!((q - p).length() < 1e-4 + p.abs().max_element() * 6e-5);
            }
        }
    }
}
