//! What every texel bake shares: the atlas and its texels, the scene ready
//! for tracing, the validity test, per-texel estimation in parallel
//! (reproducible: sample `s` of texel (x, y) on page p uses the sampler of
//! "pixel" (x, y + p·H), whatever the thread count), and dilation.

use crate::atlas::{Atlas, AtlasSettings};
use crate::baked::{Bake, BakeKind, BakeStats, BakedMap};
use crate::dilate::{TexelState, dilate};
use crate::error::BakeError;
use crate::texels::{Texel, Texels};
use crate::validity::{BACKFACE_LIMIT, backface_fractions};
use penumbra_image::{Film, FilmTile, Image, Rgb, available_memory};
use penumbra_scene::{RenderSettings, Scene};
use penumbra_shading::sampling::Sampler;
use penumbra_trace::accel::BuildQuality;
use penumbra_trace::geometry::{SceneGeometry, SurfaceHit};
use penumbra_trace::integrator::TraceContext;
use penumbra_trace::lights::LightSampler;
use penumbra_trace::texture_lod::RayCone;
use rayon::prelude::*;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::Instant;

/// Progress of a bake: the stage, and work done of the stage's total.
pub type BakeProgress<'a> = &'a (dyn Fn(&str, u64, u64) + Sync);

/// Texels a parallel task bakes together (one row segment of a page).
const SEGMENT: u32 = 64;

/// Bytes of memory a texel needs per map while baking (a film pixel: count,
/// mean, M₂ in f64) and for its output images (mean, variance).
const BYTES_PER_TEXEL_AND_MAP: u64 = 56 + 24;

/// A scene made ready for baking.
pub(crate) struct Prepared<'a> {
    pub scene: &'a Scene,
    pub geometry: SceneGeometry,
    pub lights: LightSampler,
    pub atlas: Atlas,
    pub texels: Texels,
    /// Per texel of every page (page-major), how it gets its value.
    pub states: Vec<TexelState>,
    pub atlas_seconds: f64,
}

impl<'a> Prepared<'a> {
    /// Builds the BVH, the atlas and its texels, and runs the validity test.
    pub fn new(
        scene: &'a Scene,
        settings: &AtlasSettings,
        progress: Option<BakeProgress<'_>>,
    ) -> Result<Self, BakeError> {
        let t0 = Instant::now();
        let geometry = SceneGeometry::build(scene, BuildQuality::default())?;
        let lights = LightSampler::new(scene, &geometry);
        let report = |stage: &str, done: usize, total: Option<usize>| {
            if let Some(p) = progress {
                p(stage, done as u64, total.unwrap_or(0) as u64);
            }
        };
        let atlas = Atlas::build(scene, settings, Some(&report))?;
        if atlas.pages == 0 {
            return Err(BakeError::Settings(
                "the scene has no surfaces to bake (no instance with triangles)".into(),
            ));
        }
        report("covering texels", 0, None);
        let texels = Texels::cover(scene, &geometry, &atlas);
        report("testing texels for back faces", 0, None);
        let fractions = backface_fractions(scene, &geometry, &texels);
        let mut states = vec![TexelState::Empty; atlas.texel_count() as usize];
        for (t, &f) in texels.texels.iter().zip(&fractions) {
            states[texel_offset(&texels, t)] = if f > BACKFACE_LIMIT {
                TexelState::Invalid
            } else {
                TexelState::Baked
            };
        }
        Ok(Self {
            scene,
            geometry,
            lights,
            atlas,
            texels,
            states,
            atlas_seconds: t0.elapsed().as_secs_f64(),
        })
    }

    /// A trace context with `settings` (the AO distance is read from it).
    pub fn context<'s>(&'s self, settings: &'s RenderSettings) -> TraceContext<'s> {
        TraceContext {
            scene: self.scene,
            geometry: &self.geometry,
            lights: &self.lights,
            settings,
            // Bake paths start on surfaces: no camera footprint.
            camera_cone: RayCone::POINT,
        }
    }

    pub fn is_valid(&self, t: &Texel) -> bool {
        self.states[texel_offset(&self.texels, t)] == TexelState::Baked
    }

    /// Texels baked (valid) and found inside geometry.
    pub fn counts(&self) -> (u64, u64) {
        let valid = self
            .states
            .iter()
            .filter(|&&s| s == TexelState::Baked)
            .count();
        (valid as u64, self.texels.texels.len() as u64 - valid as u64)
    }

    /// Refuses a bake of `maps` maps that would not fit in memory.
    pub fn check_memory(&self, maps: usize) -> Result<(), BakeError> {
        let need = self.atlas.texel_count() * maps as u64 * BYTES_PER_TEXEL_AND_MAP;
        if let Some(avail) = available_memory()
            && need > avail
        {
            return Err(BakeError::Atlas(format!(
                "{} pages of {}x{} texels with {maps} map(s) need about {:.1} GiB, more than the {:.1} GiB of memory available; lower the density or the number of maps",
                self.atlas.pages,
                self.atlas.width,
                self.atlas.height,
                need as f64 / (1u64 << 30) as f64,
                avail as f64 / (1u64 << 30) as f64
            )));
        }
        Ok(())
    }

    /// Estimates `maps` quantities at every valid texel with `samples`
    /// samples each: `sample(hit, sampler, out)` writes one sample of each
    /// map into `out`. Returns per map, per page, the mean and the variance
    /// of the mean, dilated into every unbaked texel.
    pub fn estimate<F>(
        &self,
        maps: usize,
        samples: u32,
        seed: u32,
        progress: Option<BakeProgress<'_>>,
        stage: &str,
        sample: F,
    ) -> Vec<(Vec<Image>, Vec<Image>)>
    where
        F: Fn(&SurfaceHit, &mut Sampler, &mut [Rgb]) + Sync,
    {
        let (w, h) = (self.atlas.width, self.atlas.height);
        let segments: Vec<(u32, u32, u32)> = (0..self.atlas.pages)
            .flat_map(|p| {
                (0..h).flat_map(move |y| (0..w).step_by(SEGMENT as usize).map(move |x| (p, y, x)))
            })
            .collect();
        let valid_total = self.counts().0;
        let done = AtomicU64::new(0);
        let total = valid_total * samples as u64;
        let tiles: Vec<(u32, Vec<FilmTile>)> = segments
            .par_iter()
            .map(|&(page, y, x0)| {
                let x1 = (x0 + SEGMENT).min(w);
                let mut tiles: Vec<FilmTile> = (0..maps)
                    .map(|_| FilmTile::new(x0, y, x1 - x0, 1))
                    .collect();
                let mut values = vec![Rgb::ZERO; maps];
                let mut n = 0u64;
                for x in x0..x1 {
                    let Some(t) = self.texels.at(page, x, y) else {
                        continue;
                    };
                    if !self.is_valid(t) {
                        continue;
                    }
                    let hit = self
                        .geometry
                        .surface_point(self.scene, t.triangle, t.b1, t.b2);
                    // One sampler per texel: its samples share the scramble seeds.
                    let mut sampler = Sampler::for_pixel(x, y + page * h, seed);
                    for s in 0..samples {
                        sampler.start_sample(s);
                        values.fill(Rgb::ZERO);
                        sample(&hit, &mut sampler, &mut values);
                        for (tile, &v) in tiles.iter_mut().zip(&values) {
                            tile.add_sample(x, y, v);
                        }
                    }
                    n += samples as u64;
                }
                if n > 0 {
                    let d = done.fetch_add(n, Ordering::Relaxed) + n;
                    if let Some(p) = progress {
                        p(stage, d, total);
                    }
                }
                (page, tiles)
            })
            .collect();
        let page_len = w as usize * h as usize;
        (0..maps)
            .map(|m| {
                let mut films: Vec<Film> = (0..self.atlas.pages).map(|_| Film::new(w, h)).collect();
                for (page, t) in &tiles {
                    films[*page as usize].merge_tile(&t[m]);
                }
                let mut means = Vec::new();
                let mut variances = Vec::new();
                for (p, film) in films.iter().enumerate() {
                    let states = &self.states[p * page_len..][..page_len];
                    let mut mean = film.mean();
                    let mut var = film.variance();
                    dilate(&mut mean, states);
                    dilate(&mut var, states);
                    means.push(mean);
                    variances.push(var);
                }
                (means, variances)
            })
            .collect()
    }

    /// The finished texel bake: its maps with the atlas, texels, coverage
    /// and the figures of the estimation (`rays` traced in `bake_seconds`).
    #[allow(clippy::too_many_arguments)]
    pub fn finish(
        self,
        kind: BakeKind,
        samples: u32,
        seed: u32,
        maps: Vec<BakedMap>,
        bake_seconds: f64,
        rays: u64,
        warnings: Vec<String>,
    ) -> Bake {
        let (valid, invalid) = self.counts();
        Bake {
            kind,
            samples,
            seed,
            coverage: self.coverage(),
            maps,
            stats: BakeStats {
                prepare_seconds: self.atlas_seconds,
                bake_seconds,
                rays,
                covered: self.texels.texels.len() as u64,
                valid,
                invalid,
            },
            warnings,
            convergence: Vec::new(),
            atlas: self.atlas,
            texels: self.texels,
        }
    }

    /// The `coverage` layer of each page ([`TexelState::coverage`]).
    pub fn coverage(&self) -> Vec<Image> {
        let (w, h) = (self.atlas.width, self.atlas.height);
        let page_len = w as usize * h as usize;
        (0..self.atlas.pages as usize)
            .map(|p| Image {
                width: w,
                height: h,
                pixels: self.states[p * page_len..][..page_len]
                    .iter()
                    .map(|s| Rgb::splat(s.coverage()))
                    .collect(),
            })
            .collect()
    }
}

/// Offset of a texel in the page-major state array.
fn texel_offset(texels: &Texels, t: &Texel) -> usize {
    (t.page as usize * texels.height as usize + t.y as usize) * texels.width as usize + t.x as usize
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Mat4;
    use penumbra_scene::Mesh;

    /// A scene of 2²⁷ triangles (a 2²⁰-triangle mesh placed 128 times),
    /// one more than the BVH holds, is an error before anything is built.
    #[test]
    fn a_scene_past_the_bvh_limit_is_an_error() {
        let mut scene = Scene::default();
        let mesh = Mesh {
            positions: vec![glam::Vec3::ZERO, glam::Vec3::X, glam::Vec3::Y],
            indices: vec![[0, 1, 2]; 1 << 20],
            ..Mesh::default()
        };
        scene.add_mesh(mesh, Mat4::IDENTITY);
        scene.instances.resize(128, scene.instances[0].clone());
        let err = Prepared::new(&scene, &AtlasSettings::default(), None).err();
        assert!(
            matches!(err, Some(BakeError::SceneTooLarge(e)) if e.triangles == 1 << 27),
            "{err:?}"
        );
    }
}
