//! Textures of the raster engine: the mip chain of every texture a material
//! uses, packed into one storage buffer of texels and sampled in WGSL
//! (`shaders/textures.wgsl`) as the CPU samples
//! [`penumbra_scene::Texture`]: the same wrap modes, the same bilinear
//! filter at level 0, the same `KHR_texture_transform`. Minified textures
//! are filtered trilinearly between box-filtered levels (a pixel of the
//! CPU averages many samples over its footprint; one raster sample must
//! read a prefiltered level to give that average instead of aliasing).
//!
//! Texel storage ([`TexelFormat`]), chosen per texture from its level 0:
//! - 8-bit sources (PNG, JPEG) as one word per texel, `unpack4x8unorm`
//!   decoded, through the sRGB curve for colour textures: level 0 reads
//!   back what the CPU reads (within 10⁻⁶), the box-filtered levels below
//!   are rounded to 8 bits as GPUs store sRGB8 mip chains;
//! - anything else as two words of IEEE halves, `r | g << 16` and `b`
//!   (relative error ≤ 2⁻¹¹, values clamped to ±65504).
use crate::gpu::{
    ALPHA_BLEND, ALPHA_MASK, ALPHA_OPAQUE, GpuMaterialTextures, GpuTexture, NO_TEXTURE, WRAP_CLAMP,
    WRAP_MIRROR, WRAP_REPEAT,
};
use half::f16;
pub use penumbra_scene::mipmap::{MipLevel, mip_chain};
use penumbra_scene::texture::Wrap;
use penumbra_scene::{AlphaMode, Scene, Texels, TextureId};
use penumbra_shading::Rgb;
use penumbra_shading::color::{linear_to_srgb, srgb_to_linear};
use std::collections::BTreeMap;

/// How a texture's texels are stored (WGSL `TEXEL_*`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TexelFormat {
    /// Two words: IEEE halves (r, g), (b).
    Half = 0,
    /// One word of 8-bit sRGB-encoded r, g, b.
    Srgb8 = 1,
    /// One word of 8-bit linear r, g, b.
    Unorm8 = 2,
}

impl TexelFormat {
    /// Words per texel.
    pub fn words(self) -> u64 {
        match self {
            TexelFormat::Half => 2,
            _ => 1,
        }
    }

    /// The format that stores `texels` (a level 0) without loss: an 8-bit
    /// one when every channel is an 8-bit sRGB or linear level (within
    /// 10⁻⁶), else halves.
    pub fn of(texels: &[Rgb]) -> Self {
        let srgb_levels: [f32; 256] = std::array::from_fn(|i| srgb_to_linear(i as f32 / 255.0));
        let channels = || texels.iter().flat_map(|t| t.to_array());
        let srgb = |v: f32| {
            let q = (linear_to_srgb(v.clamp(0.0, 1.0)) * 255.0).round() as usize;
            (srgb_levels[q.min(255)] - v).abs() <= 1e-6
        };
        let unorm = |v: f32| ((v.clamp(0.0, 1.0) * 255.0).round() / 255.0 - v).abs() <= 1e-6;
        if channels().all(srgb) {
            TexelFormat::Srgb8
        } else if channels().all(unorm) {
            TexelFormat::Unorm8
        } else {
            TexelFormat::Half
        }
    }

    /// Appends `c` in this format.
    pub fn pack(self, c: Rgb, out: &mut Vec<u32>) {
        let byte = |v: f32| (v.clamp(0.0, 1.0) * 255.0).round() as u32;
        match self {
            TexelFormat::Half => out.extend(pack_texel(c)),
            TexelFormat::Srgb8 => {
                let e = c
                    .to_array()
                    .map(|v| byte(linear_to_srgb(v.clamp(0.0, 1.0))));
                out.push(e[0] | e[1] << 8 | e[2] << 16);
            }
            TexelFormat::Unorm8 => {
                let e = c.to_array().map(byte);
                out.push(e[0] | e[1] << 8 | e[2] << 16);
            }
        }
    }
}

/// A texel as two words of half floats: (r, g), (b, 0).
pub fn pack_texel(c: Rgb) -> [u32; 2] {
    let h = |v: f32| {
        let v = if v.is_finite() {
            v.clamp(-65504.0, 65504.0)
        } else {
            0.0
        };
        f16::from_f32(v).to_bits() as u32
    };
    [h(c.x) | (h(c.y) << 16), h(c.z)]
}

fn wrap_index(w: Wrap) -> u32 {
    match w {
        Wrap::Repeat => WRAP_REPEAT,
        Wrap::ClampToEdge => WRAP_CLAMP,
        Wrap::MirroredRepeat => WRAP_MIRROR,
    }
}

/// The textures the scene's materials use, ready for upload.
#[derive(Clone, Debug)]
pub struct TextureTable {
    /// At least one entry (storage bindings cannot be empty).
    pub textures: Vec<GpuTexture>,
    /// Every level of every texture, in each texture's [`TexelFormat`]
    /// (at least one word).
    pub texels: Vec<u32>,
    /// Per scene material.
    pub materials: Vec<GpuMaterialTextures>,
    pub warnings: Vec<String>,
}

/// What a scene's textures use, as the masks of the forward shaders'
/// pipeline constants: a pipeline keeps only the lookup code its scene
/// needs (a software rasteriser runs every branch some fragment of a SIMD
/// batch could take, so unused code still costs every fragment).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct TextureFeatures {
    /// `TEXTURE_SLOTS`: the `SLOT_*` bits of the slots some material fills.
    pub slots: u32,
    /// `TEXEL_FORMATS`: bit `1 << format` of each [`TexelFormat`] stored.
    pub formats: u32,
    /// `WRAP_MODES`: bit `1 << mode` of each `WRAP_*` mode read.
    pub wraps: u32,
}

impl TextureFeatures {
    /// The pipeline constants that specialise the shaders to these features.
    pub fn constants(&self) -> [(&'static str, f64); 3] {
        [
            ("TEXTURE_SLOTS", self.slots as f64),
            ("TEXEL_FORMATS", self.formats as f64),
            ("WRAP_MODES", self.wraps as f64),
        ]
    }
}

impl TextureTable {
    /// The features of the table's textures (none without textures).
    pub fn features(&self) -> TextureFeatures {
        let real = self.textures.iter().filter(|t| t.width > 0 && t.height > 0);
        TextureFeatures {
            slots: self.materials.iter().fold(0, |m, t| m | t.slot_mask()),
            formats: real.clone().fold(0, |m, t| m | 1 << t.format),
            wraps: real.fold(0, |m, t| m | 1 << t.wrap_u | 1 << t.wrap_v),
        }
    }

    /// Packs the textures of `scene`'s materials into at most
    /// `budget_bytes` of texels: when the chains do not fit, the largest
    /// texture loses its finest level until they do (with a warning).
    pub fn new(scene: &Scene, budget_bytes: u64) -> Self {
        let mut used: BTreeMap<TextureId, u32> = BTreeMap::new();
        let mut slot = |t: Option<TextureId>| match t {
            Some(t) if t < scene.textures.len() => {
                let next = used.len() as u32;
                *used.entry(t).or_insert(next)
            }
            _ => NO_TEXTURE,
        };
        let materials = scene
            .materials
            .iter()
            .map(|m| GpuMaterialTextures {
                albedo: slot(m.albedo_texture),
                metallic_roughness: slot(m.metallic_roughness_texture),
                emission: slot(m.emission_texture),
                normal: slot(m.normal_map.map(|n| n.texture)),
                normal_scale: m.normal_map.map_or(1.0, |n| n.scale),
                occlusion: slot(m.occlusion_map.map(|o| o.texture)),
                occlusion_strength: m.occlusion_map.map_or(1.0, |o| o.strength),
                alpha_mode: match m.alpha.map(|a| a.mode) {
                    None => ALPHA_OPAQUE,
                    Some(AlphaMode::Mask { .. }) => ALPHA_MASK,
                    Some(AlphaMode::Blend) => ALPHA_BLEND,
                },
                alpha_texture: slot(m.alpha.and_then(|a| a.texture)),
                alpha_factor: m.alpha.map_or(1.0, |a| a.factor),
                alpha_cutoff: match m.alpha.map(|a| a.mode) {
                    Some(AlphaMode::Mask { cutoff }) => cutoff,
                    _ => 0.0,
                },
                ..Default::default()
            })
            .collect();
        let mut order: Vec<(TextureId, u32)> = used.into_iter().collect();
        order.sort_by_key(|&(_, s)| s);
        let mut chains: Vec<Vec<MipLevel>> = order
            .iter()
            .map(|&(t, _)| mip_chain(&scene.textures[t]))
            .collect();
        // 8-bit sources say their format; f32 ones are scanned.
        let formats: Vec<TexelFormat> = order
            .iter()
            .zip(&chains)
            .map(|(&(t, _), c)| match scene.textures[t].texels {
                Texels::Srgb8(_) => TexelFormat::Srgb8,
                Texels::Unorm8(_) => TexelFormat::Unorm8,
                Texels::Linear(_) => TexelFormat::of(&c[0].texels),
            })
            .collect();
        let word_count = |c: &[Vec<MipLevel>]| -> u64 {
            c.iter()
                .zip(&formats)
                .flat_map(|(chain, f)| {
                    chain
                        .iter()
                        .map(move |l| l.width as u64 * l.height as u64 * f.words())
                })
                .sum()
        };
        let mut warnings = Vec::new();
        let budget = (budget_bytes / 4).min(u32::MAX as u64);
        let mut reduced = BTreeMap::new();
        while word_count(&chains) > budget {
            let largest = (0..chains.len())
                .filter(|&i| chains[i].len() > 1)
                .max_by_key(|&i| {
                    chains[i][0].width as u64 * chains[i][0].height as u64 * formats[i].words()
                });
            let Some(i) = largest else { break };
            chains[i].remove(0);
            reduced.insert(i, (chains[i][0].width, chains[i][0].height));
        }
        for (i, (w, h)) in &reduced {
            let t = &scene.textures[order[*i].0];
            warnings.push(format!(
                "raster: texture '{}' ({}×{}) uploaded at {w}×{h}: the scene's textures exceed the GPU's storage-buffer limit ({} MiB)",
                t.name,
                t.width,
                t.height,
                budget_bytes >> 20
            ));
        }
        let mut textures = Vec::with_capacity(chains.len().max(1));
        let mut texels = Vec::with_capacity(word_count(&chains) as usize);
        for ((&(t, _), chain), &format) in order.iter().zip(&chains).zip(&formats) {
            let tex = &scene.textures[t];
            let m = tex.uv_transform.matrix2;
            let o = tex.uv_transform.translation;
            textures.push(GpuTexture {
                u_row: [m.x_axis.x, m.y_axis.x, o.x, 0.0],
                v_row: [m.x_axis.y, m.y_axis.y, o.y, 0.0],
                width: chain[0].width,
                height: chain[0].height,
                levels: chain.len() as u32,
                first: texels.len() as u32,
                wrap_u: wrap_index(tex.wrap[0]),
                wrap_v: wrap_index(tex.wrap[1]),
                format: format as u32,
                uv_set: tex.uv_set as u32,
            });
            for level in chain {
                for &c in &level.texels {
                    format.pack(c, &mut texels);
                }
            }
        }
        if textures.is_empty() {
            textures.push(GpuTexture::default());
        }
        if texels.is_empty() {
            texels.push(0);
        }
        Self {
            textures,
            texels,
            materials,
            warnings,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::{Affine2, Vec2};
    use penumbra_scene::{Material, Texture};

    fn texture(width: u32, height: u32, texels: Vec<Rgb>) -> Texture {
        Texture {
            name: "t".into(),
            width,
            height,
            texels: texels.into(),
            wrap: [Wrap::Repeat; 2],
            uv_transform: Affine2::IDENTITY,
            uv_set: 0,
        }
    }

    #[test]
    fn eight_bit_sources_are_stored_in_one_word() {
        let srgb: Vec<Rgb> = (0..64u32)
            .map(|i| {
                Rgb::new(i as f32, (3 * i) as f32, (255 - i) as f32)
                    .map(|v| srgb_to_linear(v / 255.0))
            })
            .collect();
        assert_eq!(TexelFormat::of(&srgb), TexelFormat::Srgb8);
        let unorm: Vec<Rgb> = (0..64u32)
            .map(|i| Rgb::new(i as f32, 7.0, 200.0) / 255.0)
            .collect();
        assert_eq!(TexelFormat::of(&unorm), TexelFormat::Unorm8);
        let float = vec![Rgb::new(0.1234, 0.5, 2.0)];
        assert_eq!(TexelFormat::of(&float), TexelFormat::Half);
        // sRGB texel (10, 128, 255) packs to its bytes.
        let mut out = Vec::new();
        TexelFormat::Srgb8.pack(srgb[10], &mut out);
        assert_eq!(out, [10 | 30 << 8 | 245 << 16]);
        TexelFormat::Unorm8.pack(unorm[3], &mut out);
        assert_eq!(out[1], 3 | 7 << 8 | 200 << 16);
    }

    #[test]
    fn half_packing_round_trips() {
        let c = Rgb::new(0.25, 1.5, 1000.0);
        let [a, b] = pack_texel(c);
        let back = |bits: u32| f16::from_bits(bits as u16).to_f32();
        assert_eq!(back(a & 0xffff), 0.25);
        assert_eq!(back(a >> 16), 1.5);
        assert_eq!(back(b & 0xffff), 1000.0);
        assert_eq!(b >> 16, 0);
        assert_eq!(pack_texel(Rgb::splat(1e9))[1], f16::MAX.to_bits() as u32);
    }

    #[test]
    fn table_shares_textures_and_reduces_to_the_budget() {
        let mut scene = Scene::default();
        scene
            .textures
            .push(texture(64, 64, vec![Rgb::ONE; 64 * 64]));
        scene.textures.push(Texture {
            uv_transform: Affine2::from_scale_angle_translation(
                Vec2::new(2.0, 3.0),
                0.0,
                Vec2::new(0.5, 0.25),
            ),
            wrap: [Wrap::ClampToEdge, Wrap::MirroredRepeat],
            ..texture(4, 4, vec![Rgb::ONE; 16])
        });
        let mut a = Material::lambert("a", Rgb::ONE);
        a.albedo_texture = Some(1);
        let mut b = Material::lambert("b", Rgb::ONE);
        b.albedo_texture = Some(1);
        b.emission_texture = Some(0);
        scene.add_material(a);
        scene.add_material(b);
        scene.add_material(Material::lambert("c", Rgb::ONE));
        let table = TextureTable::new(&scene, u64::MAX);
        let slots: Vec<_> = table
            .materials
            .iter()
            .map(|m| (m.albedo, m.emission))
            .collect();
        assert_eq!(slots, [(0, NO_TEXTURE), (0, 1), (NO_TEXTURE, NO_TEXTURE)]);
        let small = table.textures[0];
        assert_eq!(
            (small.levels, small.wrap_u, small.wrap_v),
            (3, WRAP_CLAMP, WRAP_MIRROR)
        );
        assert_eq!(small.u_row, [2.0, 0.0, 0.5, 0.0]);
        assert_eq!(small.v_row, [0.0, 3.0, 0.25, 0.0]);
        let big = table.textures[1];
        assert_eq!((big.width, big.levels, big.first), (64, 7, 16 + 4 + 1));
        // White is an 8-bit level: one word per texel. 64² + 32² + ... + 1 =
        // 5461 words, the 4×4 chain 21: a budget of 1000 words drops the big
        // texture's levels 64 (1386 left) and 32.
        assert_eq!(table.texels.len(), 5461 + 21);
        let reduced = TextureTable::new(&scene, 1000 * 4);
        assert_eq!(reduced.textures[1].width, 16);
        assert_eq!(reduced.texels.len(), 341 + 21);
        assert_eq!(reduced.warnings.len(), 1, "{:?}", reduced.warnings);
    }
}
