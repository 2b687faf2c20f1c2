//! Mip chains: a texture prefiltered at every power-of-two minification,
//! each level the box-filtered mean of the one above (Williams 1983). Both
//! engines read them where one lookup stands for a footprint of many
//! texels: the raster engine per pixel, the tracer per ray cone.

use crate::texture::{Texels, Texture};
use penumbra_shading::Rgb;
use penumbra_shading::color::linear_to_srgb;
use rayon::prelude::*;

/// One level of a mip chain, in linear RGB.
#[derive(Clone, Debug, PartialEq)]
pub struct MipLevel {
    pub width: u32,
    pub height: u32,
    /// Row-major, top row first.
    pub texels: Vec<Rgb>,
}

/// Rows of output per parallel task when downsampling.
const ROWS_PER_TASK: usize = 16;

/// The next level of a `w`×`h` level whose texel (x, y) is `at(y·w + x)`:
/// half the size (at least 1), each texel the mean of the 2×2 texels above
/// it (a row or column past an odd edge repeats the edge).
fn downsample_with(w: usize, h: usize, at: impl Fn(usize) -> Rgb + Sync) -> MipLevel {
    let (nw, nh) = ((w / 2).max(1), (h / 2).max(1));
    let texel = |x: usize, y: usize| at(y.min(h - 1) * w + x.min(w - 1));
    let mut texels = vec![Rgb::ZERO; nw * nh];
    texels
        .par_chunks_mut(nw * ROWS_PER_TASK)
        .enumerate()
        .for_each(|(chunk, rows)| {
            for (i, out) in rows.iter_mut().enumerate() {
                let (x, y) = (i % nw, chunk * ROWS_PER_TASK + i / nw);
                let (x0, y0) = (2 * x, 2 * y);
                *out =
                    (texel(x0, y0) + texel(x0 + 1, y0) + texel(x0, y0 + 1) + texel(x0 + 1, y0 + 1))
                        * 0.25;
            }
        });
    MipLevel {
        width: nw as u32,
        height: nh as u32,
        texels,
    }
}

/// The next level: half the size (at least 1), each texel the mean of the
/// 2×2 texels above it (a row or column past an odd edge repeats the
/// edge).
pub fn downsample(level: &MipLevel) -> MipLevel {
    downsample_with(level.width as usize, level.height as usize, |i| {
        level.texels[i]
    })
}

/// Level 0 (the texture itself) down to 1×1.
pub fn mip_chain(t: &Texture) -> Vec<MipLevel> {
    halved_down_to_one(MipLevel {
        width: t.width,
        height: t.height,
        texels: t.texels.to_linear(),
    })
}

/// `first` and every level below it, down to 1×1.
fn halved_down_to_one(first: MipLevel) -> Vec<MipLevel> {
    let mut levels = vec![first];
    while let Some(last) = levels.last().filter(|l| l.width > 1 || l.height > 1) {
        let next = downsample(last);
        levels.push(next);
    }
    levels
}

/// Levels 1 (half size) down to 1×1 of `t`, each a [`Texture`] with `t`'s
/// sampler (wrap modes, UV transform, UV set) and stored as `t` stores its
/// texels: 8-bit sources keep 8-bit levels (the box means rounded to the
/// nearest byte of their encoding, as GPUs store sRGB8 mip chains), so a
/// level costs the caches a quarter of the one above. Empty for a texture
/// of one texel or none.
pub fn coarser_levels(t: &Texture) -> Vec<Texture> {
    let (w, h) = (t.width as usize, t.height as usize);
    if w * h <= 1 || t.texels.len() != w * h {
        return Vec::new();
    }
    halved_down_to_one(downsample_with(w, h, |i| t.texels.get(i)))
        .into_par_iter()
        .map(|l| Texture {
            name: t.name.clone(),
            width: l.width,
            height: l.height,
            texels: encode_like(&t.texels, &l.texels),
            wrap: t.wrap,
            uv_transform: t.uv_transform,
            uv_set: t.uv_set,
        })
        .collect()
}

/// `linear` stored in the encoding of `like`.
fn encode_like(like: &Texels, linear: &[Rgb]) -> Texels {
    let byte = |v: f32| (v.clamp(0.0, 1.0) * 255.0).round() as u8;
    let bytes = |f: &dyn Fn(f32) -> u8| {
        linear
            .iter()
            .map(|c| [f(c.x), f(c.y), f(c.z), 255])
            .collect::<Vec<_>>()
    };
    match like {
        Texels::Linear(_) => Texels::Linear(linear.to_vec()),
        Texels::Srgb8(_) => Texels::Srgb8(bytes(&|v| byte(linear_to_srgb(v.clamp(0.0, 1.0))))),
        Texels::Unorm8(_) => Texels::Unorm8(bytes(&|v| byte(v))),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::texture::Wrap;
    use glam::{Affine2, Vec2};

    fn texture(width: u32, height: u32, texels: Texels) -> Texture {
        Texture {
            name: "t".into(),
            width,
            height,
            texels,
            wrap: [Wrap::Repeat; 2],
            uv_transform: Affine2::IDENTITY,
            uv_set: 0,
        }
    }

    #[test]
    fn mip_levels_are_box_means_down_to_one_texel() {
        // 3×2: odd width repeats the last column.
        let v = |x: f32| Rgb::splat(x);
        let t = texture(
            3,
            2,
            vec![v(0.0), v(4.0), v(8.0), v(2.0), v(6.0), v(10.0)].into(),
        );
        let chain = mip_chain(&t);
        assert_eq!(chain.len(), 2);
        assert_eq!((chain[1].width, chain[1].height), (1, 1));
        // (0 + 4 + 2 + 6) / 4 = 3: texels (0,0), (1,0), (0,1), (1,1).
        assert_eq!(chain[1].texels, vec![v(3.0)]);
        let big = texture(8, 4, vec![v(1.0); 32].into());
        let sizes: Vec<_> = mip_chain(&big)
            .iter()
            .map(|l| (l.width, l.height))
            .collect();
        assert_eq!(sizes, [(8, 4), (4, 2), (2, 1), (1, 1)]);
        // A column goes on halving its height after the width reached 1.
        let column = texture(1, 4, vec![v(1.0); 4].into());
        let sizes: Vec<_> = mip_chain(&column)
            .iter()
            .map(|l| (l.width, l.height))
            .collect();
        assert_eq!(sizes, [(1, 4), (1, 2), (1, 1)]);
        // 4×4 texels x + 4y: each texel of level 1 the mean of its 2×2
        // block, (0 + 1 + 4 + 5)/4 = 2.5, then 4.5, 10.5, 12.5.
        let grid = texture(4, 4, (0..16).map(|i| v(i as f32)).collect());
        assert_eq!(
            mip_chain(&grid)[1].texels,
            vec![v(2.5), v(4.5), v(10.5), v(12.5)]
        );
        // More rows than one parallel task: row y of a 2×40 ramp's level 1
        // is the mean of rows 2y and 2y + 1, (4y + 1) / 2.
        let ramp = texture(2, 40, (0..80).map(|i| v((i / 2) as f32)).collect());
        let level = &mip_chain(&ramp)[1];
        for y in 0..20 {
            assert_eq!(level.texels[y], v((4 * y + 1) as f32 / 2.0), "row {y}");
        }
    }

    /// Coarser levels keep the sampler and the storage of level 0; 8-bit
    /// levels hold the nearest byte of the linear box mean: sRGB bytes
    /// (0, 255, 0, 255) average to linear 0.5, sRGB-encoded 187.516 → 188;
    /// (10, 200, 30, 90) to linear 0.173960 (IEC 61966-2-1 by hand), encoded
    /// 115.787 → 116; linear bytes (0, 255, 0, 255) to 127.5 → 128.
    #[test]
    fn coarser_levels_keep_sampler_and_storage() {
        let bytes = |a: [u8; 4], b: [u8; 4]| (0..4).map(|i| [a[i], b[i], 0, 255]).collect();
        let srgb = Texture {
            wrap: [Wrap::ClampToEdge, Wrap::MirroredRepeat],
            uv_transform: Affine2::from_scale(Vec2::splat(2.0)),
            uv_set: 1,
            ..texture(
                2,
                2,
                Texels::Srgb8(bytes([0, 255, 0, 255], [10, 200, 30, 90])),
            )
        };
        let levels = coarser_levels(&srgb);
        assert_eq!(levels.len(), 1);
        let l = &levels[0];
        assert_eq!((l.width, l.height), (1, 1));
        assert_eq!(l.texels, Texels::Srgb8(vec![[188, 116, 0, 255]]));
        assert_eq!(
            (l.wrap, l.uv_transform, l.uv_set),
            (srgb.wrap, srgb.uv_transform, 1)
        );
        let unorm = texture(2, 2, Texels::Unorm8(bytes([0, 255, 0, 255], [0, 0, 0, 4])));
        assert_eq!(
            coarser_levels(&unorm)[0].texels,
            Texels::Unorm8(vec![[128, 1, 0, 255]])
        );
        let linear = texture(4, 2, vec![Rgb::splat(0.3); 8].into());
        let levels = coarser_levels(&linear);
        let sizes: Vec<_> = levels.iter().map(|l| (l.width, l.height)).collect();
        assert_eq!(sizes, [(2, 1), (1, 1)]);
        assert!(
            matches!(&levels[1].texels, Texels::Linear(t) if (t[0] - Rgb::splat(0.3)).length() < 1e-7)
        );
        // One texel, or none: nothing coarser.
        assert!(coarser_levels(&texture(1, 1, vec![Rgb::ONE].into())).is_empty());
        assert!(coarser_levels(&texture(0, 0, Vec::<Rgb>::new().into())).is_empty());
    }
}
