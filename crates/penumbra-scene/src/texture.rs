//! Textures in linear RGB, sampled bilinearly with the glTF sampler's wrap
//! modes per axis (REPEAT, CLAMP_TO_EDGE, MIRRORED_REPEAT).

use glam::{Affine2, Vec2};
use penumbra_shading::Rgb;

/// Index of a texture in [`crate::Scene::textures`].
pub type TextureId = usize;

/// What a lookup outside [0, 1] reads, per axis (OpenGL's and glTF's
/// wrap modes, applied to texel indices).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Wrap {
    /// Texel `i mod n`.
    #[default]
    Repeat,
    /// Texel `clamp(i, 0, n − 1)`.
    ClampToEdge,
    /// Period 2n, the second half mirrored: `m = i mod 2n`, texel `m` if
    /// `m < n`, else `2n − 1 − m`.
    MirroredRepeat,
}

impl Wrap {
    /// The texel index for index `i` of an axis of `n` texels.
    pub fn index(self, i: i64, n: i64) -> usize {
        // Inside the axis every mode is the identity (and no division).
        if (0..n).contains(&i) {
            return i as usize;
        }
        (match self {
            Wrap::Repeat => i.rem_euclid(n),
            Wrap::ClampToEdge => i.clamp(0, n - 1),
            Wrap::MirroredRepeat => {
                let m = i.rem_euclid(2 * n);
                if m < n { m } else { 2 * n - 1 - m }
            }
        }) as usize
    }
}

/// A linear-RGB image (sRGB-encoded inputs are decoded on load).
#[derive(Clone, Debug)]
pub struct Texture {
    pub name: String,
    pub width: u32,
    pub height: u32,
    /// Row-major, row 0 at the top (v = 0 in glTF's convention).
    pub texels: Vec<Rgb>,
    /// Wrap modes along u (glTF wrapS) and v (wrapT).
    pub wrap: [Wrap; 2],
    /// Applied to texture coordinates before the lookup (glTF
    /// `KHR_texture_transform`: `uv' = T(offset) · R(rotation) · S(scale) · uv`).
    pub uv_transform: Affine2,
    /// The UV set the texture reads: 0 (glTF `TEXCOORD_0`) or 1
    /// (`TEXCOORD_1`), as the textureInfo's `texCoord` says.
    pub uv_set: usize,
}

impl Texture {
    /// The texture at a point whose coordinates in UV sets 0 and 1 are
    /// `uvs`: [`Texture::sample`] on its own set.
    pub fn lookup(&self, uvs: [Vec2; 2]) -> Rgb {
        self.sample(uvs[self.uv_set.min(1)])
    }

    /// Bilinear lookup at `uv` (after [`Texture::uv_transform`]), wrapped
    /// per axis by [`Texture::wrap`].
    pub fn sample(&self, uv: Vec2) -> Rgb {
        let uv = self.uv_transform.transform_point2(uv);
        let (w, h) = (self.width as i64, self.height as i64);
        if w == 0 || h == 0 {
            return Rgb::ONE;
        }
        let x = uv.x * self.width as f32 - 0.5;
        let y = uv.y * self.height as f32 - 0.5;
        let (x0, y0) = (x.floor(), y.floor());
        let (fx, fy) = (x - x0, y - y0);
        // The two columns and the two rows of the 2×2 texels, wrapped once.
        let (x0, y0) = (x0 as i64, y0 as i64);
        let [left, right] = [x0, x0.saturating_add(1)].map(|i| self.wrap[0].index(i, w));
        let [top, bottom] =
            [y0, y0.saturating_add(1)].map(|i| self.wrap[1].index(i, h) * self.width as usize);
        let t = &self.texels;
        let upper = t[top + left].lerp(t[top + right], fx);
        let lower = t[bottom + left].lerp(t[bottom + right], fx);
        upper.lerp(lower, fy)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two texels, black then white, along u.
    fn black_white(wrap: [Wrap; 2], uv_set: usize) -> Texture {
        Texture {
            name: "t".into(),
            width: 2,
            height: 1,
            texels: vec![Rgb::ZERO, Rgb::ONE],
            wrap,
            uv_transform: Affine2::IDENTITY,
            uv_set,
        }
    }

    #[test]
    fn bilinear_and_wrap() {
        let t = black_white([Wrap::Repeat; 2], 0);
        assert!((t.sample(Vec2::new(0.25, 0.5)) - Rgb::ZERO).length() < 1e-6);
        assert!((t.sample(Vec2::new(0.5, 0.5)) - Rgb::splat(0.5)).length() < 1e-6);
        assert!((t.sample(Vec2::new(1.25, 0.5)) - Rgb::ZERO).length() < 1e-6);
    }

    #[test]
    fn wrap_modes_follow_opengl() {
        // Texel indices of an axis of 3 texels from −4 to 6.
        let along = |w: Wrap| (-4..=6).map(|i| w.index(i, 3)).collect::<Vec<_>>();
        assert_eq!(along(Wrap::Repeat), [2, 0, 1, 2, 0, 1, 2, 0, 1, 2, 0]);
        assert_eq!(along(Wrap::ClampToEdge), [0, 0, 0, 0, 0, 1, 2, 2, 2, 2, 2]);
        assert_eq!(
            along(Wrap::MirroredRepeat),
            [2, 2, 1, 0, 0, 1, 2, 2, 1, 0, 0]
        );
        let t = black_white([Wrap::ClampToEdge, Wrap::Repeat], 0);
        // Past the right edge, clamped: the last texel, not the first.
        assert!((t.sample(Vec2::new(1.25, 0.5)) - Rgb::ONE).length() < 1e-6);
        let m = Texture {
            wrap: [Wrap::MirroredRepeat, Wrap::Repeat],
            ..t
        };
        assert!((m.sample(Vec2::new(1.25, 0.5)) - Rgb::ONE).length() < 1e-6);
        assert!((m.sample(Vec2::new(1.75, 0.5)) - Rgb::ZERO).length() < 1e-6);
    }

    #[test]
    fn lookup_reads_the_texture_uv_set() {
        let t = black_white([Wrap::ClampToEdge; 2], 1);
        let uvs = [Vec2::new(0.0, 0.5), Vec2::new(1.0, 0.5)];
        assert_eq!(t.lookup(uvs), Rgb::ONE);
        assert_eq!(Texture { uv_set: 0, ..t }.lookup(uvs), Rgb::ZERO);
    }
}
