//! Validation of single values: each check names the key path, the value as
//! written and the allowed range.

use super::diag::Doc;
use super::raw::{Floats, num};
use crate::error::SceneError;
use glam::{Vec2, Vec3};
use penumbra_shading::Rgb;

/// Allowed range of a colour.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum ColorRange {
    /// A reflectance: every channel in [0, 1].
    Reflectance,
    /// A radiometric quantity: every channel finite and ≥ 0.
    NonNegative,
}

/// Converts to f32, refusing NaN, ±∞ and values too large for f32.
fn finite32(x: f64) -> Option<f32> {
    let y = x as f32;
    y.is_finite().then_some(y)
}

impl Doc<'_> {
    /// A colour: one number (grey) or `[r, g, b]`.
    pub fn rgb(&self, path: &str, v: &Floats, range: ColorRange) -> Result<Rgb, SceneError> {
        let c = match v.values.as_slice() {
            [g] => [*g; 3],
            [r, g, b] => [*r, *g, *b],
            _ => {
                return Err(self.err(
                    path,
                    format!(
                        "expected a colour [r, g, b] or a single number, got {} numbers: {v}",
                        v.values.len()
                    ),
                ));
            }
        };
        let (ok, allowed) = match range {
            ColorRange::Reflectance => (
                c.iter().all(|x| (0.0..=1.0).contains(x)),
                "reflectance must be in [0, 1] in every channel",
            ),
            ColorRange::NonNegative => (
                c.iter().all(|x| *x >= 0.0 && finite32(*x).is_some()),
                "value must be finite and >= 0 in every channel",
            ),
        };
        if !ok {
            return Err(self.err(path, format!("{allowed}, got {v}")));
        }
        Ok(Rgb::new(c[0] as f32, c[1] as f32, c[2] as f32))
    }

    /// A point or vector `[x, y, z]` of finite numbers.
    pub fn vec3(&self, path: &str, v: &Floats) -> Result<Vec3, SceneError> {
        match v.values.as_slice() {
            [x, y, z] if !v.scalar => match (finite32(*x), finite32(*y), finite32(*z)) {
                (Some(x), Some(y), Some(z)) => Ok(Vec3::new(x, y, z)),
                _ => Err(self.err(path, format!("expected finite numbers, got {v}"))),
            },
            _ => Err(self.err(path, format!("expected an array [x, y, z], got {v}"))),
        }
    }

    /// A direction: a non-zero `[x, y, z]`, returned normalised.
    pub fn direction(&self, path: &str, v: &Floats) -> Result<Vec3, SceneError> {
        let d = self.vec3(path, v)?;
        let n = d.normalize_or_zero();
        if n == Vec3::ZERO {
            return Err(self.err(path, format!("direction must be non-zero, got {v}")));
        }
        Ok(n)
    }

    /// Either one number `s` (→ `[s, s, s]`) or `[x, y, z]`, every component
    /// finite and > 0 (sizes, extents).
    pub fn extent3(&self, path: &str, v: &Floats) -> Result<Vec3, SceneError> {
        let e = match v.values.as_slice() {
            [s] => [*s; 3],
            [x, y, z] => [*x, *y, *z],
            _ => {
                return Err(self.err(path, format!("expected one number or [x, y, z], got {v}")));
            }
        };
        self.all_positive(path, v, &e)?;
        Ok(Vec3::new(e[0] as f32, e[1] as f32, e[2] as f32))
    }

    /// Either one number `s` (→ `[s, s]`) or `[a, b]`, each finite and > 0.
    pub fn extent2(&self, path: &str, v: &Floats) -> Result<Vec2, SceneError> {
        let e = match v.values.as_slice() {
            [s] => [*s; 2],
            [a, b] => [*a, *b],
            _ => return Err(self.err(path, format!("expected one number or [a, b], got {v}"))),
        };
        self.all_positive(path, v, &e)?;
        Ok(Vec2::new(e[0] as f32, e[1] as f32))
    }

    fn all_positive(&self, path: &str, v: &Floats, e: &[f64]) -> Result<(), SceneError> {
        if e.iter().all(|x| *x > 0.0 && finite32(*x).is_some()) {
            Ok(())
        } else {
            let key = path.rsplit('.').next().unwrap_or(path);
            Err(self.err(path, format!("{key} must be finite and > 0, got {v}")))
        }
    }

    /// A finite number > 0.
    pub fn positive(&self, path: &str, x: f64) -> Result<f32, SceneError> {
        match finite32(x) {
            Some(y) if y > 0.0 => Ok(y),
            _ => {
                let key = path.rsplit('.').next().unwrap_or(path);
                Err(self.err(
                    path,
                    format!("{key} must be finite and > 0, got {}", num(x)),
                ))
            }
        }
    }

    /// A finite number in `[lo, hi]`.
    pub fn in_range(&self, path: &str, x: f64, lo: f64, hi: f64) -> Result<f32, SceneError> {
        if (lo..=hi).contains(&x) {
            Ok(x as f32)
        } else {
            let key = path.rsplit('.').next().unwrap_or(path);
            Err(self.err(
                path,
                format!(
                    "{key} must be in [{}, {}], got {}",
                    num(lo),
                    num(hi),
                    num(x)
                ),
            ))
        }
    }

    /// An integer in `[lo, hi]`.
    pub fn int_in(&self, path: &str, x: i64, lo: i64, hi: i64) -> Result<u32, SceneError> {
        match u32::try_from(x) {
            Ok(y) if (lo..=hi).contains(&x) => Ok(y),
            _ => {
                let key = path.rsplit('.').next().unwrap_or(path);
                Err(self.err(
                    path,
                    format!("{key} must be an integer in [{lo}, {hi}], got {x}"),
                ))
            }
        }
    }

    /// Errors if a key appears that the `kind` (a type or shape) does not take.
    pub fn only_keys(
        &self,
        path: &str,
        what: &str,
        present: &[&'static str],
        allowed: &[&str],
    ) -> Result<(), SceneError> {
        match present.iter().find(|k| !allowed.contains(k)) {
            Some(k) => Err(self.err(
                &format!("{path}.{k}"),
                format!(
                    "`{k}` does not apply to {what} (it takes: {})",
                    allowed.join(", ")
                ),
            )),
            None => Ok(()),
        }
    }
}
