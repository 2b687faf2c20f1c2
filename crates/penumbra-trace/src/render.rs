//! The render loop: image tiles rendered in parallel (rayon), in passes of
//! samples so that long renders report progress and can stop at a time limit.
//!
//! Reproducibility: the random numbers of sample `s` of pixel (x, y) depend
//! only on (x, y, s, seed), and each pixel's samples are accumulated in
//! sample order by the one task that owns its tile, so the image is
//! bit-identical for any thread count.

use crate::accel::BuildQuality;
use crate::geometry::SceneGeometry;
use crate::integrator::TraceContext;
use crate::lights::LightSampler;
use glam::Vec3;
use penumbra_image::{Film, FilmTile, Image};
use penumbra_scene::{Camera, Projection, RenderSettings, Scene};
use penumbra_shading::sampling::Sampler;
use rayon::prelude::*;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::{Duration, Instant};

/// Tile edge in pixels.
const TILE: u32 = 16;

/// Progress of a running render.
#[derive(Clone, Copy, Debug)]
pub struct Progress {
    /// Pixel samples finished so far.
    pub samples_done: u64,
    /// Pixel samples the render will take if it is not stopped early.
    pub samples_total: u64,
}

/// Options that do not change the image.
#[derive(Default)]
pub struct RenderOptions<'a> {
    /// Stop after the pass during which this much time has passed.
    pub time_limit: Option<Duration>,
    /// Called from worker threads as tiles finish.
    pub progress: Option<&'a (dyn Fn(Progress) + Sync)>,
    /// Also accumulate albedo, normal and depth.
    pub aovs: bool,
    pub build_quality: BuildQuality,
}

impl std::fmt::Debug for RenderOptions<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("RenderOptions")
            .field("time_limit", &self.time_limit)
            .field("aovs", &self.aovs)
            .finish()
    }
}

/// A finished render.
#[derive(Clone, Debug)]
pub struct RenderOutput {
    /// Mean radiance per pixel.
    pub image: Image,
    /// Variance of the per-pixel mean (s²/n).
    pub variance: Image,
    /// (name, image) pairs: `albedo`, `normal`, `depth` when requested.
    pub aovs: Vec<(String, Image)>,
    /// Samples per pixel actually taken (fewer than asked after a time limit).
    pub spp: u32,
    pub build_seconds: f64,
    pub render_seconds: f64,
}

/// The camera of the scene, or one framing its bounds from +z.
pub fn scene_camera(scene: &Scene) -> Camera {
    if let Some(c) = scene.camera {
        return c;
    }
    let (lo, hi) = scene
        .bounds()
        .unwrap_or((Vec3::splat(-1.0), Vec3::splat(1.0)));
    let centre = 0.5 * (lo + hi);
    let radius = (0.5 * (hi - lo).length()).max(1e-3);
    let fov_y = 40f32.to_radians();
    let distance = radius / (0.5 * fov_y).sin();
    Camera::look_at(
        centre + Vec3::Z * distance,
        centre,
        Vec3::Y,
        Projection::Perspective { fov_y },
    )
}

struct TileRect {
    x0: u32,
    y0: u32,
    w: u32,
    h: u32,
}

fn tiles(width: u32, height: u32) -> Vec<TileRect> {
    let mut out = Vec::new();
    for y0 in (0..height).step_by(TILE as usize) {
        for x0 in (0..width).step_by(TILE as usize) {
            out.push(TileRect {
                x0,
                y0,
                w: TILE.min(width - x0),
                h: TILE.min(height - y0),
            });
        }
    }
    out
}

/// Renders `scene` with `settings` (which override the scene's own).
pub fn render(scene: &Scene, settings: &RenderSettings, options: &RenderOptions) -> RenderOutput {
    let t0 = Instant::now();
    let geometry = SceneGeometry::build(scene, options.build_quality);
    let lights = LightSampler::new(scene, &geometry);
    let build_seconds = t0.elapsed().as_secs_f64();
    let ctx = TraceContext {
        scene,
        geometry: &geometry,
        lights: &lights,
        settings,
    };
    let camera = scene_camera(scene);
    let (w, h) = (settings.width, settings.height);
    let rects = tiles(w, h);
    let mut film = Film::new(w, h);
    let aov_names = ["albedo", "normal", "depth"];
    let mut aov_films: Vec<Film> = if options.aovs {
        aov_names.iter().map(|_| Film::new(w, h)).collect()
    } else {
        Vec::new()
    };
    let done = AtomicU64::new(0);
    let total = w as u64 * h as u64 * settings.spp as u64;
    let t1 = Instant::now();
    // Passes grow so early ones give quick feedback and later ones amortise.
    let mut spp_done = 0u32;
    let mut pass_spp = 1u32;
    while spp_done < settings.spp {
        let s0 = spp_done;
        let s1 = (s0 + pass_spp).min(settings.spp);
        let results: Vec<(FilmTile, Vec<FilmTile>)> = rects
            .par_iter()
            .map(|r| {
                let out = render_tile(&ctx, &camera, r, s0, s1, options.aovs);
                let n = done.fetch_add(
                    r.w as u64 * r.h as u64 * (s1 - s0) as u64,
                    Ordering::Relaxed,
                );
                if let Some(p) = options.progress {
                    p(Progress {
                        samples_done: n + r.w as u64 * r.h as u64 * (s1 - s0) as u64,
                        samples_total: total,
                    });
                }
                out
            })
            .collect();
        for (tile, aovs) in &results {
            film.merge_tile(tile);
            for (f, t) in aov_films.iter_mut().zip(aovs) {
                f.merge_tile(t);
            }
        }
        spp_done = s1;
        pass_spp = (pass_spp * 2).min(64);
        if options
            .time_limit
            .is_some_and(|limit| t1.elapsed() >= limit)
        {
            break;
        }
    }
    RenderOutput {
        image: film.mean(),
        variance: film.variance(),
        aovs: aov_names
            .iter()
            .zip(&aov_films)
            .map(|(n, f)| (n.to_string(), f.mean()))
            .collect(),
        spp: spp_done,
        build_seconds,
        render_seconds: t1.elapsed().as_secs_f64(),
    }
}

fn render_tile(
    ctx: &TraceContext,
    camera: &Camera,
    r: &TileRect,
    s0: u32,
    s1: u32,
    aovs: bool,
) -> (FilmTile, Vec<FilmTile>) {
    let settings = ctx.settings;
    let mut tile = FilmTile::new(r.x0, r.y0, r.w, r.h);
    let mut aov_tiles: Vec<FilmTile> = if aovs {
        (0..3)
            .map(|_| FilmTile::new(r.x0, r.y0, r.w, r.h))
            .collect()
    } else {
        Vec::new()
    };
    for y in r.y0..r.y0 + r.h {
        for x in r.x0..r.x0 + r.w {
            for s in s0..s1 {
                let mut sampler = Sampler::new(x, y, s, settings.seed);
                let [jx, jy] = sampler.next_2d();
                let (o, d) = camera.generate_ray(
                    x as f32 + jx,
                    y as f32 + jy,
                    settings.width,
                    settings.height,
                );
                let result = ctx.li(&crate::ray::Ray::new(o, d), &mut sampler);
                // A NaN or infinite sample would poison the pixel's mean; it
                // is a bug elsewhere, but one bad sample must not ruin an image.
                let value = if result.radiance.is_finite() {
                    result.radiance
                } else {
                    Vec3::ZERO
                };
                tile.add_sample(x, y, value);
                if aovs {
                    aov_tiles[0].add_sample(x, y, result.albedo);
                    aov_tiles[1].add_sample(x, y, result.normal);
                    aov_tiles[2].add_sample(x, y, Vec3::splat(result.depth));
                }
            }
        }
    }
    (tile, aov_tiles)
}
