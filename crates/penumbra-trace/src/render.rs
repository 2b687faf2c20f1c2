//! The render loop: image tiles rendered in parallel (rayon), in passes of
//! samples so that long renders report progress and can stop at a time limit.
//!
//! Reproducibility: the random numbers of sample `s` of pixel (x, y) depend
//! only on (x, y, s, seed), and the film adds samples exactly (fixed-point
//! sums, [`penumbra_image::film`]), so the image is bit-identical for any
//! thread count, and a render split by sample range ([`RenderOptions::samples`])
//! or window ([`RenderOptions::crop`]), or stopped and resumed
//! ([`RenderOptions::resume`]), adds up to the same bits as one whole render.

use crate::accel::BuildQuality;
use crate::geometry::{SceneGeometry, SceneTooLarge};
use crate::integrator::TraceContext;
use crate::integrator::wavefront::WavefrontScene;
use crate::lights::LightSampler;
use crate::stages::{Stage, timed};
use crate::texture_lod::RayCone;
use glam::Vec3;
use penumbra_image::{Film, FilmTile, Image, noise_rel_mse};
use penumbra_scene::{Camera, RenderSettings, Scene};
use penumbra_shading::sampling::Sampler;
use rayon::prelude::*;
use std::ops::Range;
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

/// Samples per pixel a film must hold before `target_rel_mse` is tested:
/// a variance estimate from fewer samples is too noisy to stop on (and from
/// one sample it is zero).
pub const MIN_SPP_FOR_TARGET: u32 = 16;

/// A window of the image: columns `x`, rows `y`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Crop {
    pub x: Range<u32>,
    pub y: Range<u32>,
}

/// A film to continue: it holds samples `samples.start..next` of every
/// pixel of the render's window.
#[derive(Clone, Debug)]
pub struct Resume {
    pub film: Film,
    /// The first sample index the film does not hold.
    pub next: u32,
}

/// Why a render ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stop {
    /// Every sample of the range was taken.
    Complete,
    /// `time_limit` passed.
    TimeLimit,
    /// The film's own noise estimate reached `target_rel_mse`.
    TargetReached,
}

/// A callback given the film and the sample range it holds.
pub type CheckpointFn<'a> = dyn Fn(&Film, Range<u32>) + Sync + 'a;

/// Which samples of which pixels to take, and when to stop.
#[derive(Default)]
pub struct RenderOptions<'a> {
    /// Stop after the pass during which this much time has passed.
    pub time_limit: Option<Duration>,
    /// Called from worker threads as tiles finish.
    pub progress: Option<&'a (dyn Fn(Progress) + Sync)>,
    /// Also accumulate albedo, normal and depth.
    pub aovs: bool,
    pub build_quality: BuildQuality,
    /// Sample indices to take in every pixel (default `0..settings.spp`):
    /// the same numbers a whole render draws for them.
    pub samples: Option<Range<u32>>,
    /// Only these pixels (default: the whole image); the output images
    /// cover the window.
    pub crop: Option<Crop>,
    /// Continue this film instead of starting an empty one; its window
    /// must be the crop's.
    pub resume: Option<Resume>,
    /// Called after every pass with the film and the sample range it holds.
    pub checkpoint: Option<&'a CheckpointFn<'a>>,
    /// Stop after the first pass at which the film's estimate of its own
    /// relMSE ([`penumbra_image::noise_rel_mse`]) is at most this, once
    /// every pixel holds [`MIN_SPP_FOR_TARGET`] samples.
    pub target_rel_mse: Option<f64>,
    /// Trace paths one at a time even where the wavefront integrator
    /// (sixteen paths at a time, `integrator/wavefront.rs`) applies, for
    /// comparisons (the command line sets it from the environment
    /// variable `PENUMBRA_SCALAR_PATHS`).
    pub scalar_paths: bool,
    /// Run the wavefront integrator's sixteen lanes in two AVX2
    /// registers even where the CPU has AVX-512, for comparisons and
    /// tests.
    pub avx2_paths: bool,
}

impl std::fmt::Debug for RenderOptions<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("RenderOptions")
            .field("time_limit", &self.time_limit)
            .field("aovs", &self.aovs)
            .field("samples", &self.samples)
            .field("crop", &self.crop)
            .field("resume", &self.resume.as_ref().map(|r| r.next))
            .field("target_rel_mse", &self.target_rel_mse)
            .field("scalar_paths", &self.scalar_paths)
            .field("avx2_paths", &self.avx2_paths)
            .finish()
    }
}

/// A finished render.
#[derive(Clone, Debug)]
pub struct RenderOutput {
    /// Mean radiance per pixel (of the crop window, if any).
    pub image: Image,
    /// Variance of the per-pixel mean (s²/n).
    pub variance: Image,
    /// (name, image) pairs: `albedo`, `normal`, `depth` when requested.
    pub aovs: Vec<(String, Image)>,
    /// Samples per pixel the film holds (fewer than asked after a time
    /// limit or a reached target).
    pub spp: u32,
    /// The sample indices the film holds.
    pub samples: Range<u32>,
    /// The radiance sums, to write as a partial film or merge.
    pub film: Film,
    /// Per pixel of the window (row-major), whether most of the samples
    /// this process took there hit a surface (not the background): what
    /// automatic exposure meters.
    pub surface: Vec<bool>,
    pub stop: Stop,
    pub build_seconds: f64,
    pub render_seconds: f64,
    /// Whether the wavefront integrator traced the paths (sixteen at a
    /// time, `integrator/wavefront.rs`), not the scalar one.
    pub wavefront: bool,
}

/// The camera of the scene, or one framing its bounds
/// ([`Camera::framing`]) for the scene's own image size.
pub fn scene_camera(scene: &Scene) -> Camera {
    scene_camera_for(scene, scene.settings.width, scene.settings.height)
}

/// The camera of the scene, or one framing its bounds ([`Camera::framing`])
/// for a `width` × `height` image.
pub fn scene_camera_for(scene: &Scene, width: u32, height: u32) -> Camera {
    if let Some(c) = scene.camera {
        return c;
    }
    let (lo, hi) = scene
        .bounds()
        .unwrap_or((Vec3::splat(-1.0), Vec3::splat(1.0)));
    Camera::framing(lo, hi, width.max(1) as f32 / height.max(1) as f32)
}

struct TileRect {
    x0: u32,
    y0: u32,
    w: u32,
    h: u32,
}

fn tiles(crop: &Crop) -> Vec<TileRect> {
    let mut out = Vec::new();
    for y0 in crop.y.clone().step_by(TILE as usize) {
        for x0 in crop.x.clone().step_by(TILE as usize) {
            out.push(TileRect {
                x0,
                y0,
                w: TILE.min(crop.x.end - x0),
                h: TILE.min(crop.y.end - y0),
            });
        }
    }
    out
}

/// Renders `scene` with `settings` (which override the scene's own); an
/// error, before any work, for a scene larger than the BVH holds.
///
/// Panics if `options` are inconsistent (a crop outside the image, a sample
/// range beyond `settings.spp`, a resume film of another window or past the
/// range): callers check user input first.
pub fn render(
    scene: &Scene,
    settings: &RenderSettings,
    options: &RenderOptions,
) -> Result<RenderOutput, SceneTooLarge> {
    let t0 = Instant::now();
    let geometry = SceneGeometry::build(scene, options.build_quality)?;
    let lights = LightSampler::new(scene, &geometry);
    let build_seconds = t0.elapsed().as_secs_f64();
    let (w, h) = (settings.width, settings.height);
    let camera = scene_camera_for(scene, w, h);
    let ctx = TraceContext {
        scene,
        geometry: &geometry,
        lights: &lights,
        settings,
        camera_cone: RayCone::camera(&camera, h, settings.spp),
    };
    // Sixteen paths at a time where the scene allows (`wavefront.rs`).
    let wavefront = (!options.aovs && !options.scalar_paths)
        .then(|| WavefrontScene::new(scene, &geometry, &lights, settings, options.avx2_paths))
        .flatten();
    let crop = options.crop.clone().unwrap_or(Crop { x: 0..w, y: 0..h });
    assert!(crop.x.end <= w && crop.y.end <= h, "crop outside the image");
    let samples = options.samples.clone().unwrap_or(0..settings.spp);
    assert!(samples.start <= samples.end, "empty sample range");
    let (cw, ch) = (crop.x.len() as u32, crop.y.len() as u32);
    let rects = tiles(&crop);
    let (mut film, first) = match &options.resume {
        Some(r) => {
            assert!(
                (r.film.x0(), r.film.y0(), r.film.width(), r.film.height())
                    == (crop.x.start, crop.y.start, cw, ch),
                "the resumed film covers another window"
            );
            assert!(
                (samples.start..=samples.end).contains(&r.next),
                "the resumed film is past the range"
            );
            (r.film.clone(), r.next)
        }
        None => (
            Film::window(crop.x.start, crop.y.start, cw, ch),
            samples.start,
        ),
    };
    let aov_names = ["albedo", "normal", "depth"];
    let mut aov_films: Vec<Film> = if options.aovs {
        aov_names
            .iter()
            .map(|_| Film::window(crop.x.start, crop.y.start, cw, ch))
            .collect()
    } else {
        Vec::new()
    };
    let pixels = u64::from(cw) * u64::from(ch);
    let mut hits = vec![0u32; pixels as usize];
    let done = AtomicU64::new(pixels * u64::from(first - samples.start));
    let total = pixels * samples.len() as u64;
    let t1 = Instant::now();
    // Passes grow so early ones give quick feedback and later ones amortise.
    let mut next = first;
    let mut pass_spp = 1u32;
    let mut stop = Stop::Complete;
    while next < samples.end {
        let s0 = next;
        let s1 = (s0 + pass_spp).min(samples.end);
        let results: Vec<TileOutput> = rects
            .par_iter()
            .map(|r| {
                let out = match &wavefront {
                    Some(paths) => wavefront_tile(paths, &camera, settings, r, s0, s1),
                    None => render_tile(&ctx, &camera, r, s0, s1, options.aovs),
                };
                let n = r.w as u64 * r.h as u64 * (s1 - s0) as u64;
                let before = done.fetch_add(n, Ordering::Relaxed);
                if let Some(p) = options.progress {
                    p(Progress {
                        samples_done: before + n,
                        samples_total: total,
                    });
                }
                out
            })
            .collect();
        for (r, out) in rects.iter().zip(&results) {
            film.merge_tile(&out.film);
            for (f, t) in aov_films.iter_mut().zip(&out.aovs) {
                f.merge_tile(t);
            }
            for (i, &n) in out.hits.iter().enumerate() {
                let (x, y) = (r.x0 + i as u32 % r.w, r.y0 + i as u32 / r.w);
                hits[((y - crop.y.start) * cw + (x - crop.x.start)) as usize] += n;
            }
        }
        next = s1;
        pass_spp = (pass_spp * 2).min(64);
        if let Some(c) = options.checkpoint {
            c(&film, samples.start..next);
        }
        if next < samples.end {
            if options
                .target_rel_mse
                .is_some_and(|t| target_reached(&film, next - samples.start, t))
            {
                stop = Stop::TargetReached;
                break;
            }
            if options
                .time_limit
                .is_some_and(|limit| t1.elapsed() >= limit)
            {
                stop = Stop::TimeLimit;
                break;
            }
        }
    }
    Ok(RenderOutput {
        image: film.mean(),
        variance: film.variance(),
        aovs: aov_names
            .iter()
            .zip(&aov_films)
            .map(|(n, f)| (n.to_string(), f.mean()))
            .collect(),
        spp: next - samples.start,
        surface: hits.iter().map(|&n| 2 * n > next - first).collect(),
        samples: samples.start..next,
        film,
        stop,
        build_seconds,
        render_seconds: t1.elapsed().as_secs_f64(),
        wavefront: wavefront.is_some(),
    })
}

/// Whether `film`, holding `spp` samples per pixel, estimates its own
/// relMSE at or below `target`.
fn target_reached(film: &Film, spp: u32, target: f64) -> bool {
    spp >= MIN_SPP_FOR_TARGET && noise_rel_mse(&film.mean(), &film.variance()) <= target
}

/// What one tile's pass returns.
struct TileOutput {
    film: FilmTile,
    aovs: Vec<FilmTile>,
    /// Per pixel of the tile, the samples whose camera ray hit a surface.
    hits: Vec<u32>,
}

/// Samples `s0..s1` of tile `r` by the wavefront integrator.
fn wavefront_tile(
    paths: &WavefrontScene,
    camera: &Camera,
    settings: &RenderSettings,
    r: &TileRect,
    s0: u32,
    s1: u32,
) -> TileOutput {
    let mut tile = FilmTile::new(r.x0, r.y0, r.w, r.h);
    let mut hits = vec![0u32; (r.w * r.h) as usize];
    crate::integrator::wavefront::render_tile(
        paths,
        &camera.film(settings.width, settings.height),
        settings.seed,
        &mut tile,
        (r.x0, r.y0, r.w, r.h),
        s0,
        s1,
        &mut hits,
    );
    TileOutput {
        film: tile,
        aovs: Vec::new(),
        hits,
    }
}

fn render_tile(
    ctx: &TraceContext,
    camera: &Camera,
    r: &TileRect,
    s0: u32,
    s1: u32,
    aovs: bool,
) -> TileOutput {
    let settings = ctx.settings;
    let mut tile = FilmTile::new(r.x0, r.y0, r.w, r.h);
    let mut aov_tiles: Vec<FilmTile> = if aovs {
        (0..3)
            .map(|_| FilmTile::new(r.x0, r.y0, r.w, r.h))
            .collect()
    } else {
        Vec::new()
    };
    let mut hits = vec![0u32; (r.w * r.h) as usize];
    let film = camera.film(settings.width, settings.height);
    for y in r.y0..r.y0 + r.h {
        for x in r.x0..r.x0 + r.w {
            // One sampler per pixel: its samples share the scramble seeds.
            let mut sampler = Sampler::for_pixel(x, y, settings.seed);
            for s in s0..s1 {
                let result = timed(Stage::Sample, || {
                    sampler.start_sample(s);
                    let [jx, jy] = sampler.next_2d();
                    let (o, d) = film.ray(x as f32 + jx, y as f32 + jy);
                    ctx.li(&crate::ray::Ray::new(o, d), &mut sampler)
                });
                // A NaN or infinite sample would poison the pixel's mean; it
                // is a bug elsewhere, but one bad sample must not ruin an image.
                let value = if result.radiance.is_finite() {
                    result.radiance
                } else {
                    Vec3::ZERO
                };
                tile.add_sample(x, y, value);
                if result.depth > 0.0 {
                    hits[((y - r.y0) * r.w + (x - r.x0)) as usize] += 1;
                }
                if aovs {
                    aov_tiles[0].add_sample(x, y, result.albedo);
                    aov_tiles[1].add_sample(x, y, result.normal);
                    aov_tiles[2].add_sample(x, y, Vec3::splat(result.depth));
                }
            }
        }
    }
    crate::stages::flush();
    TileOutput {
        film: tile,
        aovs: aov_tiles,
        hits,
    }
}
