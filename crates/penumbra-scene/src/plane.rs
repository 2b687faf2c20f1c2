//! Planes `Ax + By + Cz + D = 0` and how they transform (SEEDS.md, "Planes
//! and normals under transformation").
//!
//! A point p lies on the plane iff its homogeneous row vector times the
//! column of coefficients is zero: `[x y z 1] · [A B C D]ᵀ = 0`. If points
//! move by an affine map T, written for row vectors as `p' = p T_row`, then
//! p' lies on the transformed plane iff `p' T_row⁻¹` lies on the original:
//! the coefficient column becomes `T_row⁻¹ [A B C D]ᵀ` — the inverse, from
//! the left. penumbra (glam) uses column vectors, `p' = M p` with
//! `M = T_rowᵀ`, so the same rule reads `(M⁻¹)ᵀ [A B C D]ᵀ`: the inverse
//! transpose. A normal is the plane's (A, B, C) part, which is why normals go
//! through the inverse transpose of the linear part (see
//! [`crate::Instance::normal_matrix`]) and stay perpendicular to surfaces
//! under non-uniform scale, where transforming them like points would not.

use glam::{Mat4, Vec3, Vec4};

/// The plane `a·x + b·y + c·z + d = 0`, coefficients `(a, b, c, d)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Plane {
    pub coefficients: Vec4,
}

impl Plane {
    /// The plane through `point` with normal `normal` (any length):
    /// `(n, −n·p)`.
    pub fn from_point_normal(point: Vec3, normal: Vec3) -> Self {
        Self {
            coefficients: normal.extend(-normal.dot(point)),
        }
    }

    /// The plane through three points (normal `(p1 − p0) × (p2 − p0)`);
    /// `None` if they are collinear.
    pub fn through_points(p0: Vec3, p1: Vec3, p2: Vec3) -> Option<Self> {
        let n = (p1 - p0).cross(p2 - p0);
        (n.length_squared() > 0.0).then(|| Self::from_point_normal(p0, n))
    }

    /// The (unnormalised) normal `(a, b, c)`.
    pub fn normal(&self) -> Vec3 {
        self.coefficients.truncate()
    }

    /// `[x y z 1] · [a b c d]ᵀ`, divided by |(a, b, c)|: the signed distance.
    pub fn signed_distance(&self, p: Vec3) -> f32 {
        self.coefficients.dot(p.extend(1.0)) / self.normal().length()
    }

    /// The plane containing the images of this plane's points under the
    /// column-vector transform `m` (p' = m p): coefficients `(m⁻¹)ᵀ c`. In
    /// the notes' row-vector convention this is `T⁻¹ c` with `T = mᵀ`.
    pub fn transformed(&self, m: &Mat4) -> Self {
        Self {
            coefficients: m.inverse().transpose() * self.coefficients,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::{Mat3, Quat};

    /// A deterministic stream of numbers in [−1, 1).
    fn stream(seed: u32) -> impl FnMut() -> f32 {
        let mut s = seed.wrapping_mul(2_654_435_761).wrapping_add(1);
        move || {
            s ^= s << 13;
            s ^= s >> 17;
            s ^= s << 5;
            (s as f32 / u32::MAX as f32) * 2.0 - 1.0
        }
    }

    /// Affine maps with rotation, non-uniform scale, shear and translation.
    fn transforms() -> Vec<Mat4> {
        let mut r = stream(7);
        (0..50)
            .map(|_| {
                let rot =
                    Quat::from_axis_angle(Vec3::new(r(), r(), r() + 2.0).normalize(), r() * 3.0);
                let scale = Vec3::new(
                    0.2 + r().abs() * 3.0,
                    0.5 + r().abs(),
                    0.1 + r().abs() * 5.0,
                );
                let shear = Mat4::from_cols_array(&[
                    1.0,
                    r() * 0.5,
                    0.0,
                    0.0, //
                    0.0,
                    1.0,
                    r() * 0.5,
                    0.0, //
                    r() * 0.5,
                    0.0,
                    1.0,
                    0.0, //
                    0.0,
                    0.0,
                    0.0,
                    1.0,
                ]);
                Mat4::from_translation(Vec3::new(r(), r(), r()) * 10.0)
                    * Mat4::from_quat(rot)
                    * shear
                    * Mat4::from_scale(scale)
            })
            .collect()
    }

    #[test]
    fn transformed_plane_contains_transformed_points() {
        let mut r = stream(11);
        for m in transforms() {
            let (p0, p1, p2) = (
                Vec3::new(r(), r(), r()) * 4.0,
                Vec3::new(r(), r(), r()) * 4.0,
                Vec3::new(r(), r(), r()) * 4.0,
            );
            let plane = Plane::through_points(p0, p1, p2).unwrap();
            let moved = plane.transformed(&m);
            let scale = m.to_scale_rotation_translation().0.max_element() * 10.0;
            for (a, b) in [(0.3f32, 0.5f32), (-2.0, 1.5), (4.0, -3.0), (0.0, 0.0)] {
                // Any point of the original plane…
                let p = p0 + a * (p1 - p0) + b * (p2 - p0);
                assert!(plane.signed_distance(p).abs() < 1e-3);
                // …lands on the transformed plane.
                let q = m.transform_point3(p);
                assert!(moved.signed_distance(q).abs() < 1e-4 * scale, "{m}");
            }
            // A point off the plane stays off it by the mapped distance's sign.
            let off = p0 + plane.normal().normalize();
            let side = moved.signed_distance(m.transform_point3(off));
            assert!(side.abs() > 1e-3);
        }
    }

    #[test]
    fn normals_need_the_inverse_transpose_under_non_uniform_scale() {
        let mut r = stream(5);
        let mut naive_failures = 0;
        for m in transforms() {
            let lin = Mat3::from_mat4(m);
            let normal_matrix = lin.inverse().transpose();
            let n = Vec3::new(r(), r(), r()).normalize();
            // Two tangents perpendicular to n.
            let t1 = n.any_orthonormal_vector();
            let t2 = n.cross(t1);
            let n_good = (normal_matrix * n).normalize();
            let n_naive = (lin * n).normalize();
            for t in [t1, t2, (t1 + 2.0 * t2)] {
                let tw = (lin * t).normalize();
                assert!(
                    n_good.dot(tw).abs() < 1e-4,
                    "inverse transpose keeps n ⟂ surface"
                );
                if n_naive.dot(tw).abs() > 1e-2 {
                    naive_failures += 1;
                }
            }
            // The plane rule and the normal rule agree.
            let plane = Plane::from_point_normal(Vec3::ZERO, n).transformed(&m);
            assert!(plane.normal().normalize().dot(n_good) > 1.0 - 1e-5);
        }
        assert!(
            naive_failures > 10,
            "transforming normals like points must fail here"
        );
    }
}
