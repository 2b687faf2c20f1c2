//! Texture level of detail from ray cones (Amanatides 1984; Akenine-Möller
//! et al. 2019, "Texture Level of Detail Strategies for Real-Time Ray
//! Tracing", Ray Tracing Gems ch. 20).
//!
//! A ray carries a cone: its width `w` at the ray's origin and its spread
//! angle `γ`, so at distance t it is `w + γ t` wide. One lookup stands for
//! the whole footprint of its cone, so it reads the mip level whose texels
//! are that footprint's size:
//!
//! `λ = ½ log2((W / |cos θ|)² · A_uv / A_world · w_tex h_tex |det T|)`
//!
//! (½ log2 of the texels the footprint covers) with W the cone's width at
//! the hit, θ the angle between the ray and the geometric normal, A_uv and
//! A_world the triangle's areas in UV space and in the world, and T the
//! texture's `KHR_texture_transform`: one logarithm per lookup. Levels are
//! blended trilinearly; λ ≤ 0 reads level 0 exactly as a plain lookup.
//!
//! Camera rays start with the pixel's cone (`γ = 2 tan(½ fov_y) / height`
//! for a pinhole, `w` = the pixel's width for an orthographic camera)
//! scaled by `max(1/8, 1/√N)` for N samples per pixel, as pbrt-v4 scales
//! its camera ray differentials ([`RayCone::camera`]).
//! Delta (mirror, Snell) bounces keep the spread: curvature is ignored.
//! A bounce sampled with density p [1/sr] widens the spread to at least
//! the cone whose solid angle is one sample's share of the `N` samples a
//! pixel takes, `π γ²/4 = 1/(N p)`, i.e. `γ = 2/√(π N p)` (the path
//! footprint of Suykens & Willems 2001, as pbrt-v4 also shrinks its
//! footprints by √N): a diffuse bounce reads coarse levels, a glossy one
//! fine levels, and the blur vanishes as the sample count grows. That
//! filtering is the lever on cost: a secondary hit reads a small level
//! the caches hold instead of a random texel of a large one.
//!
//! Only the textures that shape the BSDF are filtered (base colour,
//! metallic–roughness, normal maps). Emission is read at level 0, as light
//! sampling reads it, so that the two strategies of multiple importance
//! sampling see one emitter; alpha coverage too, so that visibility stays
//! exact.

use glam::Vec2;
use penumbra_scene::mipmap::coarser_levels;
use penumbra_scene::texture::{BilinearTaps, TextureLayout};
use penumbra_scene::{Camera, Material, Projection, Scene, Texture, TextureId};
use penumbra_shading::Rgb;

/// The spread no cone exceeds [rad]: wider than a hemisphere means every
/// lookup reads the coarsest level anyway.
const MAX_SPREAD: f32 = std::f32::consts::PI;

/// |cos θ| below which a hit counts as grazing (λ stops growing there).
const MIN_COS: f32 = 1e-3;

/// A ray's footprint: width at its origin and spread angle.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct RayCone {
    /// Width at the ray's origin [world units].
    pub width: f32,
    /// Full apex angle [rad]: the width grows by `spread` per unit distance.
    pub spread: f32,
}

impl RayCone {
    /// No footprint: every lookup reads level 0.
    pub const POINT: RayCone = RayCone {
        width: 0.0,
        spread: 0.0,
    };

    /// The cone of one camera sample of `spp` in a pixel of an image
    /// `height` pixels high (square pixels) seen by `camera`: the pixel's
    /// cone scaled by `max(1/8, 1/√spp)`, as pbrt-v4 scales its camera ray
    /// differentials. The pixel's samples already spread over the pixel:
    /// filtering each over the whole pixel too would blur twice, and a
    /// filtered lookup of a nonlinear map (normals, roughness) is not the
    /// mean of the point lookups it replaces; the narrower cone keeps that
    /// bias small and lets it shrink as samples are added.
    pub fn camera(camera: &Camera, height: u32, spp: u32) -> RayCone {
        let h = height.max(1) as f32;
        let scale = (1.0 / (spp.max(1) as f32).sqrt()).max(0.125);
        match camera.projection {
            Projection::Perspective { fov_y } => RayCone {
                width: 0.0,
                spread: scale * 2.0 * (0.5 * fov_y).tan() / h,
            },
            Projection::Orthographic { height } => RayCone {
                width: scale * height / h,
                spread: 0.0,
            },
        }
    }

    /// Width at distance `t` along the ray.
    #[inline]
    pub fn width_at(&self, t: f32) -> f32 {
        self.width + self.spread * t
    }

    /// The same cone, its apex moved on by `t`: as it arrives at a hit at
    /// distance `t`.
    #[inline]
    pub fn at(&self, t: f32) -> RayCone {
        RayCone {
            width: self.width_at(t),
            spread: self.spread,
        }
    }

    /// The cone leaving a hit at distance `t` after a bounce: the same
    /// spread after a delta lobe (`pdf` None), else at least the spread of
    /// one of `spp` samples of density `pdf`, `2/√(π spp pdf)`.
    pub fn scattered(&self, t: f32, pdf: Option<f32>, spp: u32) -> RayCone {
        let spread = match pdf {
            None => self.spread,
            Some(p) => {
                let share = 2.0 / (std::f32::consts::PI * spp.max(1) as f32 * p).sqrt();
                // NaN (p = 0) and ∞ both become MAX_SPREAD.
                self.spread.max(share.min(MAX_SPREAD)).min(MAX_SPREAD)
            }
        };
        RayCone {
            width: self.width_at(t),
            spread,
        }
    }
}

/// A cone's footprint at one hit: its area in square UV units, per UV
/// set (from which each texture's level follows); `None` reads level 0.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Footprint(pub Option<[f32; 2]>);

impl Footprint {
    /// The footprint of a cone `width` wide meeting a surface at `cos` =
    /// |ray · geometric normal|, on a triangle whose UV sets span
    /// `uv_area_ratio` = A_uv / A_world: `(W / |cos θ|)² A_uv / A_world`.
    pub fn new(width: f32, cos: f32, uv_area_ratio: [f32; 2]) -> Footprint {
        // Also NaN: no footprint.
        if width.is_nan() || width <= 0.0 {
            return Footprint(None);
        }
        let across = width / cos.abs().max(MIN_COS);
        Footprint(Some(uv_area_ratio.map(|r| across * across * r)))
    }
}

/// `m`'s base colour, metallic–roughness and normal map textures: the
/// textures that shape its BSDF, which are the ones filtered.
pub fn filtered_maps(m: &Material) -> [Option<TextureId>; 3] {
    [
        m.albedo_texture,
        m.metallic_roughness_texture,
        m.normal_map.map(|n| n.texture),
    ]
}

/// The coarser levels of the scene's BSDF textures, and their lookups.
#[derive(Debug, Default)]
pub struct TextureLevels {
    /// Per scene texture.
    levels: Vec<Levels>,
}

/// One scene texture's coarser levels and what its lookups need.
#[derive(Debug)]
struct Levels {
    /// Levels 1.. (empty: never filtered).
    coarser: Vec<Texture>,
    /// w h |det T|, the texels of level 0 per square UV unit.
    texels_per_uv: f32,
    /// The first texture of the same [`Texture::layout`] and the same
    /// levels: textures of one class read the same taps at one hit.
    class: usize,
}

impl TextureLevels {
    /// Mip chains of the textures some material reads as base colour,
    /// metallic–roughness or normal map.
    pub fn new(scene: &Scene) -> Self {
        let mut used = vec![false; scene.textures.len()];
        for m in &scene.materials {
            for t in filtered_maps(m).into_iter().flatten() {
                if let Some(u) = used.get_mut(t) {
                    *u = true;
                }
            }
        }
        let keys: Vec<(TextureLayout, bool)> = scene
            .textures
            .iter()
            .zip(&used)
            .map(|(t, &used)| (t.layout(), used))
            .collect();
        let levels = scene
            .textures
            .iter()
            .zip(used)
            .enumerate()
            .map(|(i, (t, used))| {
                let det = t.uv_transform.matrix2.determinant().abs();
                Levels {
                    coarser: if used { coarser_levels(t) } else { Vec::new() },
                    texels_per_uv: t.width as f32 * t.height as f32 * det,
                    class: keys.iter().position(|k| *k == keys[i]).unwrap_or(i),
                }
            })
            .collect();
        Self { levels }
    }

    /// Texture `id` of `scene` at UV sets `uvs`, filtered over
    /// `footprint`: trilinear between the two levels around λ, level 0
    /// alone (a plain [`Texture::lookup`]) where λ ≤ 0.
    pub fn lookup(
        &self,
        scene: &Scene,
        id: TextureId,
        uvs: [Vec2; 2],
        footprint: Footprint,
    ) -> Rgb {
        self.read(scene, id, self.reads(scene, id, uvs, footprint))
    }

    /// [`TextureLevels::lookup`] of several textures at one hit (`None`
    /// for an absent map): each map whose layout (size, wrap, transform,
    /// UV set) is its predecessor's reuses that one's level and texel
    /// positions, so a material whose maps share a layout pays for one
    /// level choice and one set of taps, not one per map (the layouts
    /// are compared once, when the levels are built).
    pub fn lookup_maps<const N: usize>(
        &self,
        scene: &Scene,
        ids: [Option<TextureId>; N],
        uvs: [Vec2; 2],
        footprint: Footprint,
    ) -> [Option<Rgb>; N] {
        let mut previous: Option<(usize, Reads)> = None;
        ids.map(|id| {
            let id = id?;
            let class = self.levels.get(id).map(|l| l.class);
            let reads = match (previous, class) {
                (Some((p, reads)), Some(c)) if p == c => reads,
                _ => self.reads(scene, id, uvs, footprint),
            };
            previous = class.map(|c| (c, reads));
            Some(self.read(scene, id, reads))
        })
    }

    /// Where a lookup of texture `id` reads: the level λ selects and its
    /// taps, and the next level's with its weight where λ falls between.
    fn reads(&self, scene: &Scene, id: TextureId, uvs: [Vec2; 2], footprint: Footprint) -> Reads {
        let texture = &scene.textures[id];
        let uv = uvs[texture.uv_set.min(1)];
        let level_zero = || Reads {
            level: 0,
            taps: texture.taps(uv),
            next: None,
        };
        let (
            Some(area),
            Some(Levels {
                coarser: levels,
                texels_per_uv,
                ..
            }),
        ) = (footprint.0, self.levels.get(id))
        else {
            return level_zero();
        };
        // λ = ½ log2 of the texels the footprint covers.
        let lambda = 0.5 * (area[texture.uv_set.min(1)] * texels_per_uv).log2();
        if lambda.is_nan() || lambda <= 0.0 || levels.is_empty() {
            return level_zero();
        }
        let lambda = lambda.min(levels.len() as f32);
        let i = lambda.floor() as usize;
        let f = lambda - i as f32;
        let taps = |l: usize| match l {
            0 => texture.taps(uv),
            _ => levels[l - 1].taps(uv),
        };
        Reads {
            level: i,
            taps: taps(i),
            next: if f == 0.0 {
                None
            } else {
                taps(i + 1).map(|t| (t, f))
            },
        }
    }

    /// The texels `reads` names, of texture `id` (white for a texture
    /// with no texels, as [`Texture::sample`]).
    fn read(&self, scene: &Scene, id: TextureId, reads: Reads) -> Rgb {
        let level = |l: usize| match l {
            0 => &scene.textures[id],
            _ => &self.levels[id].coarser[l - 1],
        };
        let Some(taps) = reads.taps else {
            return Rgb::ONE;
        };
        let value = level(reads.level).fetch(&taps);
        match reads.next {
            None => value,
            Some((next, f)) => value.lerp(level(reads.level + 1).fetch(&next), f),
        }
    }
}

/// Where one filtered lookup reads ([`TextureLevels::reads`]).
#[derive(Clone, Copy, Debug)]
struct Reads {
    /// The level of `taps` (0: the texture itself).
    level: usize,
    /// `None`: the texture has no texels.
    taps: Option<BilinearTaps>,
    /// The next level's taps and their weight.
    next: Option<(BilinearTaps, f32)>,
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::{Affine2, Vec3};
    use penumbra_scene::NormalMap;
    use penumbra_scene::texture::Wrap;

    #[test]
    fn camera_cones_are_one_pixel_wide() {
        let look = |projection| Camera::look_at(Vec3::Z, Vec3::ZERO, Vec3::Y, projection);
        // 90°: the image plane at distance 1 is 2 high, 100 pixels.
        let cone = RayCone::camera(
            &look(Projection::Perspective {
                fov_y: 90f32.to_radians(),
            }),
            100,
            1,
        );
        assert_eq!(cone.width, 0.0);
        assert!((cone.spread - 0.02).abs() < 1e-7);
        assert!((cone.width_at(50.0) - 1.0).abs() < 1e-5);
        // 60°: 2 tan 30° / 100 = 0.0115470.
        let narrow = look(Projection::Perspective {
            fov_y: 60f32.to_radians(),
        });
        assert!((RayCone::camera(&narrow, 100, 1).spread - 0.011547).abs() < 1e-7);
        let ortho = look(Projection::Orthographic { height: 3.0 });
        let cone = RayCone::camera(&ortho, 60, 1);
        assert_eq!(
            cone,
            RayCone {
                width: 0.05,
                spread: 0.0
            }
        );
        assert_eq!(cone.width_at(1e3), 0.05);
        // 16 samples: a quarter of the pixel; 100 or more: an eighth.
        assert_eq!(RayCone::camera(&ortho, 60, 16).width, 0.0125);
        assert_eq!(RayCone::camera(&ortho, 60, 100).width, 0.05 / 8.0);
        assert_eq!(RayCone::camera(&ortho, 60, 4096).width, 0.05 / 8.0);
        assert_eq!(RayCone::camera(&ortho, 60, 0).width, 0.05);
    }

    /// A delta bounce keeps the spread; a sampled one widens it to
    /// 2/√(π N p): p = 1/π (a cosine lobe at the normal), N = 4 gives 1.
    #[test]
    fn bounces_widen_cones_by_the_sample_share() {
        let cone = RayCone {
            width: 0.5,
            spread: 0.01,
        };
        assert_eq!(
            cone.scattered(2.0, None, 4),
            RayCone {
                width: 0.52,
                spread: 0.01
            }
        );
        let diffuse = cone.scattered(2.0, Some(std::f32::consts::FRAC_1_PI), 4);
        assert!((diffuse.width - 0.52).abs() < 1e-7);
        assert!((diffuse.spread - 1.0).abs() < 1e-6, "{diffuse:?}");
        // One sample: twice as wide; 100 samples of a lobe of density 100:
        // 2/√(π 10⁴) = 0.01128.
        let one = cone.scattered(0.0, Some(std::f32::consts::FRAC_1_PI), 1);
        assert!((one.spread - 2.0).abs() < 1e-6);
        let glossy = cone.scattered(0.0, Some(100.0), 100);
        assert!((glossy.spread - 0.011284).abs() < 1e-6, "{glossy:?}");
        // A wider cone stays wider; no density means the widest cone.
        let wide = RayCone {
            width: 0.0,
            spread: 1.5,
        };
        assert_eq!(wide.scattered(0.0, Some(1e6), 1).spread, 1.5);
        assert_eq!(cone.scattered(0.0, Some(0.0), 1).spread, MAX_SPREAD);
        assert_eq!(wide.scattered(0.0, Some(1e-9), 1).spread, MAX_SPREAD);
    }

    #[test]
    fn footprints_grow_at_grazing_angles() {
        assert_eq!(Footprint::new(0.0, 1.0, [1.0; 2]), Footprint(None));
        assert_eq!(Footprint::new(-1.0, 1.0, [1.0; 2]), Footprint(None));
        assert_eq!(Footprint::new(f32::NAN, 1.0, [1.0; 2]), Footprint(None));
        // (0.5 / 0.5)² = 1 square world unit, times each set's ratio.
        assert_eq!(
            Footprint::new(0.5, -0.5, [2.0, 0.25]),
            Footprint(Some([2.0, 0.25]))
        );
        // Head-on, 0.25² = 1/16; grazing clamps at cos = 10⁻³.
        assert_eq!(
            Footprint::new(0.25, 1.0, [1.0, 3.0]),
            Footprint(Some([0.0625, 0.1875]))
        );
        let Footprint(Some([g, _])) = Footprint::new(1.0, 0.0, [1.0; 2]) else {
            panic!()
        };
        assert!((g / 1e6 - 1.0).abs() < 1e-5, "{g}");
    }

    /// One bright texel (16) at (3, 0) of a black 4×4 texture, clamped at
    /// the edges: at its centre level 0 reads 16, level 1 (its 2×2 block's
    /// mean) 4, level 2 (the mean) 1; levels between are blended linearly
    /// in λ = ½ log2(footprint · w h |det T|): a footprint of 2^(2λ − 4)
    /// square UV units on the 4×4 texture.
    #[test]
    fn lookups_blend_the_levels_around_lambda() {
        let mut texels = vec![Rgb::ZERO; 16];
        texels[3] = Rgb::splat(16.0);
        let bright = Texture {
            name: "bright".into(),
            width: 4,
            height: 4,
            texels: texels.into(),
            wrap: [Wrap::ClampToEdge; 2],
            uv_transform: Affine2::IDENTITY,
            uv_set: 0,
        };
        let mut scene = Scene::default();
        scene.textures.push(bright.clone());
        // The same texels read through set 1 and scaled 2× (det 4: one
        // more level at the same footprint).
        scene.textures.push(Texture {
            uv_set: 1,
            uv_transform: Affine2::from_scale(glam::Vec2::splat(2.0)),
            ..bright.clone()
        });
        // An emission texture: never filtered.
        scene.textures.push(bright);
        scene.add_material(Material {
            albedo_texture: Some(0),
            normal_map: Some(NormalMap {
                texture: 1,
                scale: 1.0,
            }),
            emission_texture: Some(2),
            ..Material::lambert("m", Rgb::ONE)
        });
        let levels = TextureLevels::new(&scene);
        let at = Vec2::new(0.875, 0.125);
        let read = |id, uvs, lambda: [f32; 2]| {
            levels
                .lookup(
                    &scene,
                    id,
                    uvs,
                    Footprint(Some(lambda.map(|l| (2.0 * l - 4.0).exp2()))),
                )
                .x
        };
        for (lambda, expected) in [
            (-0.5, 16.0),
            (0.0, 16.0),
            (0.25, 13.0),
            (1.0, 4.0),
            (1.5, 2.5),
            (2.0, 1.0),
            (7.0, 1.0),
        ] {
            let got = read(0, [at, Vec2::ZERO], [lambda, 9.0]);
            assert!((got - expected).abs() < 1e-5, "λ {lambda}: {got}");
            // Set 1 at half the coordinates, one level coarser.
            let got = read(1, [Vec2::ZERO, at * 0.5], [9.0, lambda - 1.0]);
            assert!((got - expected).abs() < 1e-5, "set 1, λ {lambda}: {got}");
            assert_eq!(read(2, [at, at], [lambda; 2]), 16.0);
        }
        assert_eq!(levels.lookup(&scene, 0, [at; 2], Footprint(None)).x, 16.0);
        // NaN (0/0 densities) reads level 0.
        assert_eq!(read(0, [at; 2], [f32::NAN; 2]), 16.0);
    }

    /// Maps of one layout share their reads; maps of another size or
    /// wrap mode read their own texels: every map of `lookup_maps` is its
    /// own `lookup`, near an edge (where clamping and repeating differ) and
    /// between levels.
    #[test]
    fn maps_of_one_layout_share_their_reads() {
        let ramp = |size: u32, offset: f32, wrap| Texture {
            name: "ramp".into(),
            width: size,
            height: size,
            texels: (0..size * size)
                .map(|i| Rgb::splat(offset + i as f32))
                .collect(),
            wrap: [wrap; 2],
            uv_transform: Affine2::IDENTITY,
            uv_set: 0,
        };
        let mut scene = Scene {
            textures: vec![
                ramp(4, 0.0, Wrap::ClampToEdge),
                ramp(4, 100.0, Wrap::ClampToEdge),
                ramp(4, 0.0, Wrap::Repeat),
                ramp(8, 0.0, Wrap::ClampToEdge),
            ],
            ..Scene::default()
        };
        scene.add_material(Material {
            albedo_texture: Some(0),
            metallic_roughness_texture: Some(1),
            normal_map: Some(NormalMap {
                texture: 2,
                scale: 1.0,
            }),
            ..Material::lambert("a", Rgb::ONE)
        });
        scene.add_material(Material {
            albedo_texture: Some(3),
            ..Material::lambert("b", Rgb::ONE)
        });
        let levels = TextureLevels::new(&scene);
        for uv in [Vec2::new(0.95, 0.4), Vec2::new(0.3, 0.99)] {
            for area in [None, Some(0.01f32), Some(0.2)] {
                let footprint = Footprint(area.map(|a| [a; 2]));
                let one = |id| Some(levels.lookup(&scene, id, [uv; 2], footprint));
                for ids in [[0, 1, 2], [0, 2, 1], [1, 0, 3], [3, 0, 0]] {
                    let got = levels.lookup_maps(&scene, ids.map(Some), [uv; 2], footprint);
                    assert_eq!(got, ids.map(one), "{ids:?} at {uv}, {area:?}");
                }
                assert_eq!(
                    levels.lookup_maps(&scene, [None, Some(1), None], [uv; 2], footprint),
                    [None, one(1), None]
                );
            }
        }
        // The sharing reads other texels where it should: repeating wraps
        // to the first column, clamping keeps the last.
        let edge = Vec2::new(0.99, 0.125);
        let [clamped, repeated] =
            levels.lookup_maps(&scene, [Some(0), Some(2)], [edge; 2], Footprint(None));
        assert!((clamped.unwrap().x - 3.0).abs() < 1e-5);
        assert!((repeated.unwrap().x - (3.0 - 3.0 * 0.46)).abs() < 1e-4);
    }
}
