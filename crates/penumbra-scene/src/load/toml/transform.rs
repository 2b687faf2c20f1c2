//! Object transforms: `translate`, `rotate_deg` / `rotate_axis_angle`,
//! `scale`, or a full `matrix`.
//!
//! `M = T · R · S`: scale first, then rotate about the object's origin, then
//! translate. `rotate_deg = [x, y, z]` rotates about the fixed X axis, then
//! Y, then Z (`R = Rz · Ry · Rx`, right-handed, degrees). `matrix` is 4×4
//! **row-major** as written (`matrix[r][c]`, translation in the last column,
//! last row `[0, 0, 0, 1]`) and excludes the other keys.

use super::diag::Doc;
use super::raw::{Floats, RawObject};
use crate::error::SceneError;
use glam::{Mat3, Mat4, Vec3};

pub(super) fn transform(doc: &Doc<'_>, path: &str, o: &RawObject) -> Result<Mat4, SceneError> {
    let at = |k: &str| format!("{path}.{k}");
    if let Some(rows) = &o.matrix {
        for (k, present) in [
            ("translate", o.translate.is_some()),
            ("rotate_deg", o.rotate_deg.is_some()),
            ("rotate_axis_angle", o.rotate_axis_angle.is_some()),
            ("scale", o.scale.is_some()),
        ] {
            if present {
                return Err(doc.err(
                    &at(k),
                    format!("`{k}` cannot be combined with `matrix`; put the whole transform in the matrix"),
                ));
            }
        }
        return matrix(doc, &at("matrix"), rows);
    }
    let t = match &o.translate {
        Some(v) => doc.vec3(&at("translate"), v)?,
        None => Vec3::ZERO,
    };
    let r = match (&o.rotate_deg, &o.rotate_axis_angle) {
        (Some(_), Some(_)) => {
            return Err(doc.err(
                &at("rotate_axis_angle"),
                "give either rotate_deg or rotate_axis_angle, not both",
            ));
        }
        (Some(e), None) => {
            let e = doc.vec3(&at("rotate_deg"), e)?;
            Mat3::from_rotation_z(e.z.to_radians())
                * Mat3::from_rotation_y(e.y.to_radians())
                * Mat3::from_rotation_x(e.x.to_radians())
        }
        (None, Some(aa)) => {
            let axis = doc.direction(&at("rotate_axis_angle.axis"), &aa.axis)?;
            let angle =
                doc.in_range(&at("rotate_axis_angle.angle_deg"), aa.angle_deg, -1e6, 1e6)?;
            Mat3::from_axis_angle(axis, angle.to_radians())
        }
        (None, None) => Mat3::IDENTITY,
    };
    let s = match &o.scale {
        Some(v) => scale(doc, &at("scale"), v)?,
        None => Vec3::ONE,
    };
    Ok(Mat4::from_translation(t) * Mat4::from_mat3(r) * Mat4::from_scale(s))
}

/// `scale = s` or `[sx, sy, sz]`: finite and non-zero (negative mirrors).
fn scale(doc: &Doc<'_>, path: &str, v: &Floats) -> Result<Vec3, SceneError> {
    let s = match v.values.as_slice() {
        [s] => [*s; 3],
        [x, y, z] => [*x, *y, *z],
        _ => {
            return Err(doc.err(
                path,
                format!("scale must be one number or [x, y, z], got {v}"),
            ));
        }
    };
    if s.iter().any(|x| *x == 0.0 || !(*x as f32).is_finite()) {
        return Err(doc.err(
            path,
            format!("scale must be finite and non-zero in every axis, got {v}"),
        ));
    }
    Ok(Vec3::new(s[0] as f32, s[1] as f32, s[2] as f32))
}

fn matrix(doc: &Doc<'_>, path: &str, rows: &[Vec<f64>]) -> Result<Mat4, SceneError> {
    if rows.len() != 4 || rows.iter().any(|r| r.len() != 4) {
        return Err(doc.err(
            path,
            "matrix must be 4 rows of 4 numbers (row-major: [[m00, m01, m02, tx], …, [0, 0, 0, 1]])",
        ));
    }
    if rows.iter().flatten().any(|x| !(*x as f32).is_finite()) {
        return Err(doc.err(path, "matrix entries must be finite numbers"));
    }
    if rows[3] != [0.0, 0.0, 0.0, 1.0] {
        return Err(doc.err(
            &format!("{path}[3]"),
            format!(
                "the last row of matrix must be [0, 0, 0, 1] (affine transforms only), got {}",
                Floats {
                    values: rows[3].clone(),
                    scalar: false
                }
            ),
        ));
    }
    let mut a = [[0f32; 4]; 4];
    for (r, row) in rows.iter().enumerate() {
        for (c, x) in row.iter().enumerate() {
            a[r][c] = *x as f32;
        }
    }
    // glam stores columns; the file gives rows.
    let m = Mat4::from_cols_array_2d(&a).transpose();
    let det = Mat3::from_mat4(m).determinant();
    if det == 0.0 || !det.is_finite() {
        return Err(doc.err(
            path,
            "matrix is singular (its 3×3 part has determinant 0), it would flatten the object",
        ));
    }
    Ok(m)
}
