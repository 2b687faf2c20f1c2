//! Textures in linear RGB, sampled bilinearly with the glTF sampler's wrap
//! modes per axis (REPEAT, CLAMP_TO_EDGE, MIRRORED_REPEAT). 8-bit sources
//! keep their bytes ([`Texels`]), decoded exactly on every read.

use glam::{Affine2, Vec2};
use penumbra_shading::Rgb;
use penumbra_shading::color::srgb_to_linear;
use std::sync::LazyLock;

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
    #[inline]
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

/// The texels of a texture, row-major, row 0 at the top. 8-bit sources
/// are kept as their bytes (4 per texel, a third of linear f32 RGB: the
/// lookups of a path tracer miss the caches less) and decoded on read to
/// exactly the values a decode on load gives.
#[derive(Clone, Debug, PartialEq)]
pub enum Texels {
    /// Linear RGB values.
    Linear(Vec<Rgb>),
    /// sRGB-encoded bytes r, g, b (the fourth unused): `srgb_to_linear(b / 255)`.
    Srgb8(Vec<[u8; 4]>),
    /// Linear bytes r, g, b (the fourth unused): `b / 255`.
    Unorm8(Vec<[u8; 4]>),
}

/// `srgb_to_linear(i / 255)` for every byte i.
static SRGB8_LEVELS: LazyLock<[f32; 256]> =
    LazyLock::new(|| std::array::from_fn(|i| srgb_to_linear(i as f32 / 255.0)));

/// The linear value of an sRGB-encoded byte.
pub fn srgb8_to_linear(b: u8) -> f32 {
    SRGB8_LEVELS[b as usize]
}

fn decode_srgb8(levels: &[f32; 256], b: [u8; 4]) -> Rgb {
    Rgb::new(
        levels[b[0] as usize],
        levels[b[1] as usize],
        levels[b[2] as usize],
    )
}

fn decode_unorm8(b: [u8; 4]) -> Rgb {
    Rgb::new(b[0] as f32, b[1] as f32, b[2] as f32) / 255.0
}

impl Texels {
    pub fn len(&self) -> usize {
        match self {
            Texels::Linear(t) => t.len(),
            Texels::Srgb8(t) | Texels::Unorm8(t) => t.len(),
        }
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Texel `i` in linear RGB.
    pub fn get(&self, i: usize) -> Rgb {
        match self {
            Texels::Linear(t) => t[i],
            Texels::Srgb8(t) => decode_srgb8(&SRGB8_LEVELS, t[i]),
            Texels::Unorm8(t) => decode_unorm8(t[i]),
        }
    }

    /// Every texel in linear RGB, in order.
    pub fn iter(&self) -> impl ExactSizeIterator<Item = Rgb> + '_ {
        (0..self.len()).map(|i| self.get(i))
    }

    /// Every texel in linear RGB.
    pub fn to_linear(&self) -> Vec<Rgb> {
        self.iter().collect()
    }
}

impl FromIterator<Rgb> for Texels {
    fn from_iter<I: IntoIterator<Item = Rgb>>(texels: I) -> Self {
        Texels::Linear(texels.into_iter().collect())
    }
}

impl From<Vec<Rgb>> for Texels {
    fn from(texels: Vec<Rgb>) -> Self {
        Texels::Linear(texels)
    }
}

/// A linear-RGB image (sRGB-encoded inputs are decoded on read).
#[derive(Clone, Debug)]
pub struct Texture {
    pub name: String,
    pub width: u32,
    pub height: u32,
    /// Row-major, row 0 at the top (v = 0 in glTF's convention).
    pub texels: Texels,
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
        match self.taps(uv) {
            Some(taps) => self.fetch(&taps),
            None => Rgb::ONE,
        }
    }

    /// Where a bilinear lookup at `uv` reads (after
    /// [`Texture::uv_transform`], wrapped per axis by [`Texture::wrap`]);
    /// `None` for a texture with no texels.
    #[inline]
    pub fn taps(&self, uv: Vec2) -> Option<BilinearTaps> {
        let uv = self.uv_transform.transform_point2(uv);
        let (w, h) = (self.width as i64, self.height as i64);
        if w == 0 || h == 0 {
            return None;
        }
        let x = uv.x * self.width as f32 - 0.5;
        let y = uv.y * self.height as f32 - 0.5;
        let (x0, y0) = (floor_to_int(x), floor_to_int(y));
        // In [0, 1) (clamped only where |x| ≥ 2⁶³ saturates the index).
        let (fx, fy) = (
            (x - x0 as f32).clamp(0.0, 1.0),
            (y - y0 as f32).clamp(0.0, 1.0),
        );
        // The two columns and the two rows of the 2×2 texels, wrapped once.
        let [left, right] = [x0, x0.saturating_add(1)].map(|i| self.wrap[0].index(i, w));
        let [top, bottom] =
            [y0, y0.saturating_add(1)].map(|i| self.wrap[1].index(i, h) * self.width as usize);
        Some(BilinearTaps {
            corners: [top + left, top + right, bottom + left, bottom + right],
            fx,
            fy,
        })
    }

    /// The bilinear blend of the texels `taps` names: `taps` from this
    /// texture's [`Texture::taps`], or from one of the same
    /// [`Texture::layout`].
    #[inline]
    pub fn fetch(&self, taps: &BilinearTaps) -> Rgb {
        let BilinearTaps { corners, fx, fy } = *taps;
        // One match per lookup, not per texel.
        match &self.texels {
            Texels::Linear(t) => bilinear(|i| t[i], corners, fx, fy),
            Texels::Srgb8(t) => {
                let levels = &*SRGB8_LEVELS;
                bilinear(|i| decode_srgb8(levels, t[i]), corners, fx, fy)
            }
            Texels::Unorm8(t) => bilinear(|i| decode_unorm8(t[i]), corners, fx, fy),
        }
    }

    /// What decides where a lookup reads: two textures of one layout read
    /// the same [`BilinearTaps`] at the same UVs (glTF materials often
    /// share one size and sampler across their maps).
    pub fn layout(&self) -> TextureLayout {
        TextureLayout {
            size: [self.width, self.height],
            wrap: self.wrap,
            uv_transform: self.uv_transform,
            uv_set: self.uv_set,
        }
    }
}

/// The texels a bilinear lookup blends (row-major indices of the top
/// left, top right, bottom left and bottom right texels) and its weights
/// along a row (`fx`) and down a column (`fy`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BilinearTaps {
    pub corners: [usize; 4],
    pub fx: f32,
    pub fy: f32,
}

/// A texture's size, wrap modes, UV transform and UV set: see
/// [`Texture::layout`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TextureLayout {
    pub size: [u32; 2],
    pub wrap: [Wrap; 2],
    pub uv_transform: Affine2,
    pub uv_set: usize,
}

/// ⌊x⌋ as an integer, without a call to libm's `floorf` (x86-64's
/// baseline has no rounding instruction): exact wherever |x| < 2⁶³, as
/// every f32 of magnitude ≥ 2²³ is an integer already; NaN gives 0.
#[inline(always)]
fn floor_to_int(x: f32) -> i64 {
    let i = x as i64;
    if (i as f32) > x { i - 1 } else { i }
}

/// The bilinear blend of texels [top left, top right, bottom left, bottom
/// right] with weights fx along a row and fy down a column.
#[inline(always)]
fn bilinear(texel: impl Fn(usize) -> Rgb, corners: [usize; 4], fx: f32, fy: f32) -> Rgb {
    let upper = texel(corners[0]).lerp(texel(corners[1]), fx);
    let lower = texel(corners[2]).lerp(texel(corners[3]), fx);
    upper.lerp(lower, fy)
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
            texels: vec![Rgb::ZERO, Rgb::ONE].into(),
            wrap,
            uv_transform: Affine2::IDENTITY,
            uv_set,
        }
    }

    #[test]
    fn floor_to_int_is_floor() {
        for x in [
            -2.5f32,
            -2.0,
            -1e-30,
            -0.0,
            0.0,
            0.3,
            0.999_999_94,
            1.0,
            7.5,
            -8_388_609.0,
            3e9,
            -1e15,
        ] {
            assert_eq!(floor_to_int(x), x.floor() as i64, "{x}");
        }
        assert_eq!(floor_to_int(f32::NAN), 0);
        assert_eq!(floor_to_int(1e30), i64::MAX);
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

    /// Every byte decodes to the value a decode on load gave: the sRGB
    /// curve of b / 255 (IEC 61966-2-1, evaluated here, not through the
    /// table), or b / 255 for linear bytes; and a bilinear lookup of byte
    /// texels equals the lookup of the same texture stored as f32.
    #[test]
    fn eight_bit_texels_decode_exactly() {
        let srgb = |b: u8| {
            let v = b as f32 / 255.0;
            if v <= 0.04045 {
                v / 12.92
            } else {
                ((v + 0.055) / 1.055).powf(2.4)
            }
        };
        let bytes: Vec<[u8; 4]> = (0..=255u8).map(|b| [b, 255 - b, b / 3, 0]).collect();
        let srgb8 = Texels::Srgb8(bytes.clone());
        let unorm8 = Texels::Unorm8(bytes.clone());
        for (i, b) in bytes.iter().enumerate() {
            let expected = Rgb::new(srgb(b[0]), srgb(b[1]), srgb(b[2]));
            assert!(
                (srgb8.get(i) - expected).abs().max_element() <= 1e-7,
                "byte {b:?}"
            );
            assert_eq!(
                srgb8.get(i),
                Rgb::new(
                    srgb8_to_linear(b[0]),
                    srgb8_to_linear(b[1]),
                    srgb8_to_linear(b[2])
                )
            );
            let linear = Rgb::new(b[0] as f32, b[1] as f32, b[2] as f32) / 255.0;
            assert_eq!(unorm8.get(i), linear);
        }
        assert_eq!(srgb8.get(128).x, srgb8_to_linear(128));
        assert!((srgb8_to_linear(128) - 0.2158605).abs() < 1e-6);
        for texels in [srgb8, unorm8] {
            let bytes = Texture {
                name: "bytes".into(),
                width: 16,
                height: 16,
                texels: texels.clone(),
                wrap: [Wrap::MirroredRepeat, Wrap::ClampToEdge],
                uv_transform: Affine2::IDENTITY,
                uv_set: 0,
            };
            let floats = Texture {
                texels: Texels::Linear(texels.to_linear()),
                ..bytes.clone()
            };
            for k in 0..500 {
                let uv = Vec2::new(
                    (k as f32 * 0.737).fract() * 3.0 - 1.0,
                    (k as f32 * 0.291).fract() * 3.0 - 1.0,
                );
                assert_eq!(bytes.sample(uv), floats.sample(uv), "uv {uv}");
            }
        }
    }

    #[test]
    fn lookup_reads_the_texture_uv_set() {
        let t = black_white([Wrap::ClampToEdge; 2], 1);
        let uvs = [Vec2::new(0.0, 0.5), Vec2::new(1.0, 0.5)];
        assert_eq!(t.lookup(uvs), Rgb::ONE);
        assert_eq!(Texture { uv_set: 0, ..t }.lookup(uvs), Rgb::ZERO);
    }
}
