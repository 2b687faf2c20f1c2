//! Path tracing with sixteen paths advanced together ("SIMD across
//! paths", as Mitsuba 3's vectorised variants and wavefront GPU tracers
//! do; Laine, Karras & Aila 2013, "Megakernels considered harmful"): each
//! stage of a path segment (closest hit, emission, light sample, shadow
//! ray, BSDF sample, Russian roulette) runs for all sixteen lanes before
//! the next, its arithmetic written over 16-lane arrays so that the
//! compiler turns it into AVX-512 instructions, and a lane whose path
//! ends starts its pixel's next sample at once (its lanes stay busy).
//!
//! The estimator is [`super::path`]'s, operation for operation: next-event
//! estimation and BSDF sampling weighted by the power heuristic, Russian
//! roulette after [`RR_START_DEPTH`] segments, and every lane draws its
//! numbers from its pixel's sampler in `path::li`'s order. So the image is
//! the scalar integrator's up to rounding (relMSE between the two about
//! 1e-5 at 64 spp on the Cornell box: a few paths part where a hit's
//! rounding differs).
//!
//! Scope, checked by [`WavefrontScene::new`] (other scenes take the scalar
//! integrator): the `path` integrator without AOVs; at most
//! [`scan::MAX_TRIANGLES`] triangles, traced by testing every triangle
//! ([`TriangleScan`]); Lambert surfaces with flat normals and without
//! textures or vertex colours; light from emissive triangles only (no
//! environment, abstract or analytic area lights); a CPU with AVX-512.
//! `PENUMBRA_SCALAR_PATHS=1` (or [`crate::RenderOptions::scalar_paths`])
//! keeps the scalar integrator for comparisons.
//!
//! One of the crate's modules with `unsafe` code: the AVX-512 entry point
//! and table reads without bounds checks (a checked read's branch would
//! keep a lane loop from vectorising).
#![allow(unsafe_code)]
// Lane loops index several structure-of-arrays fields by lane: the form
// that vectorises plainly.
#![allow(clippy::needless_range_loop)]

use crate::accel::WatertightRay;
use crate::accel::scan::{self, TriangleScan};
use crate::geometry::SceneGeometry;
use crate::lights::LightSampler;
use crate::ray::offset_coordinate;
use glam::{Vec2, Vec3};
use penumbra_image::film::FilmTile;
use penumbra_scene::{FilmRays, IntegratorKind, RenderSettings, Scene};
use penumbra_shading::Frame;
use penumbra_shading::bsdf::Bsdf;
use penumbra_shading::sampling::{
    Sampler, power_heuristic, square_to_cosine_hemisphere, square_to_triangle,
};
use std::f32::consts::FRAC_1_PI;

/// Paths in flight per group: one AVX-512 register of f32.
pub(crate) const LANES: usize = 16;

// Segments after which Russian roulette may end a path, and its survival
// probability: `path.rs`'s.
use super::path::{RR_START_DEPTH, rr_survival};

type F = [f32; LANES];
type B = [bool; LANES];

/// One attribute component of every triangle, a table that sixteen lanes
/// read with two-register permutes instead of a gather.
#[derive(Clone, Copy, Debug)]
#[repr(C, align(64))]
struct Table([f32; scan::MAX_TRIANGLES]);

// The permutes read 32 entries of two registers; two of them, 64.
const _: () = assert!(scan::MAX_TRIANGLES == 64, "a table is four registers");

/// The tables, in [`WavefrontScene::tables`]: corner c's axis a at
/// `CORNERS + 3c + a`, then the unit front normal, albedo and emission
/// (three components each), the probability of being chosen as a light
/// over the triangle's area (0 for a non-emitter: a light sample's pdf is
/// this × d² / |cos θ_light|), and 1 for a two-sided surface, else 0.
const CORNERS: usize = 0;
const NORMAL: usize = 9;
const ALBEDO: usize = 12;
const EMISSION: usize = 15;
const PMF_PER_AREA: usize = 18;
const TWO_SIDED: usize = 19;
const ATTRIBUTES: usize = 20;

/// What the lanes read of the scene: the triangles' attributes as tables;
/// the light sampler's emissive triangles with the running sums of their
/// weights; the scan.
#[derive(Debug)]
pub(crate) struct WavefrontScene {
    tables: Box<[Table; ATTRIBUTES]>,
    /// The light sampler's choices (triangles), the running sums of their
    /// weights and the total, as `Distribution1D::sample` reads them.
    lights: Vec<u32>,
    running_sums: Vec<f64>,
    total_weight: f64,
    scan: TriangleScan,
    max_depth: u32,
}

impl WavefrontScene {
    /// The scene as the lanes read it, or `None` where the scene, the
    /// settings or the CPU are outside this integrator's scope (see the
    /// module's documentation).
    pub(crate) fn new(
        scene: &Scene,
        geometry: &SceneGeometry,
        light_sampler: &LightSampler,
        settings: &RenderSettings,
    ) -> Option<Self> {
        // Every feature `trace_group` is compiled for.
        #[cfg(target_arch = "x86_64")]
        let cpu = {
            use std::arch::is_x86_feature_detected as has;
            has!("avx512f")
                && has!("avx512vl")
                && has!("avx512dq")
                && has!("avx512bw")
                && has!("avx2")
                && has!("fma")
                && has!("bmi1")
                && has!("bmi2")
                && has!("lzcnt")
                && has!("popcnt")
        };
        #[cfg(not(target_arch = "x86_64"))]
        let cpu = false;
        let n = geometry.triangles.len();
        if !cpu
            || settings.integrator != IntegratorKind::Path
            || n == 0
            || n > scan::MAX_TRIANGLES
            || !scene.lights.is_empty()
            || !scene.area_lights.is_empty()
            || scene.environment_map.is_some()
            || scene.background != Vec3::ZERO
        {
            return None;
        }
        let mut tables = Box::new([Table([0.0; scan::MAX_TRIANGLES]); ATTRIBUTES]);
        let mut normal = Vec::with_capacity(n);
        let mut culls = Vec::with_capacity(n);
        for t in 0..n as u32 {
            let m = &scene.materials[geometry.material_of(t)];
            let Bsdf::Lambert(lambert) = m.bsdf else {
                return None;
            };
            if m.albedo_texture.is_some()
                || m.emission_texture.is_some()
                || m.normal_map.is_some()
                || m.alpha.is_some()
            {
                return None;
            }
            let ng = geometry.front_normal_scaled(t).normalize_or_zero();
            // Flat and plain: the shading normal is the face's, and no
            // vertex colour tints it, at every corner (so everywhere).
            for (b1, b2) in [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0)] {
                let h = geometry.surface_point(scene, t, b1, b2);
                if h.color != Vec3::ONE || h.ns != ng {
                    return None;
                }
            }
            let k = t as usize;
            for a in 0..3 {
                for (c, corner) in geometry.triangles[k].iter().enumerate() {
                    tables[CORNERS + 3 * c + a].0[k] = corner[a];
                }
                tables[NORMAL + a].0[k] = ng[a];
                tables[ALBEDO + a].0[k] = lambert.albedo[a];
                tables[EMISSION + a].0[k] = m.emission[a];
            }
            tables[TWO_SIDED].0[k] = if m.double_sided { 1.0 } else { 0.0 };
            normal.push(ng);
            culls.push(m.cull_back_faces);
        }
        // The lights as the scalar integrator chooses them.
        let (lights, distribution) = light_sampler.triangle_lights()?;
        let (running_sums, total_weight) = distribution.running_sums();
        if lights.is_empty() || !(total_weight > 0.0 && total_weight.is_finite()) {
            return None;
        }
        for (entry, &t) in lights.iter().enumerate() {
            tables[PMF_PER_AREA].0[t as usize] = distribution.pmf(entry) / geometry.area(t);
        }
        Some(WavefrontScene {
            scan: TriangleScan::new(&geometry.triangles, &normal, &culls)?,
            tables,
            lights,
            running_sums: running_sums.to_vec(),
            total_weight,
            max_depth: settings.max_depth,
        })
    }
}

/// Reads `v[k]` without a bounds check.
///
/// # Safety
/// `k < v.len()`.
#[inline(always)]
unsafe fn at<T: Copy>(v: &[T], k: usize) -> T {
    debug_assert!(k < v.len());
    // SAFETY: the caller's contract.
    unsafe { *v.get_unchecked(k) }
}

/// Every attribute of the triangles `index` (one a lane, each below
/// [`scan::MAX_TRIANGLES`]): per table, entries 0–31 and 32–63 permuted
/// from two registers each, then chosen by bit 5 of the index.
///
/// # Safety
/// The CPU must support AVX-512F.
#[inline(always)]
unsafe fn gather(tables: &[Table; ATTRIBUTES], index: &[u32; LANES]) -> [F; ATTRIBUTES] {
    use std::arch::x86_64::*;
    let mut out = [[0.0f32; LANES]; ATTRIBUTES];
    // SAFETY: AVX-512F (the caller's contract); each table is 64 aligned
    // f32, read as four aligned registers; 16 values read and written.
    unsafe {
        let index = _mm512_loadu_si512(index.as_ptr().cast());
        let upper = _mm512_test_epi32_mask(index, _mm512_set1_epi32(32));
        for (table, out) in tables.iter().zip(&mut out) {
            let t = table.0.as_ptr();
            let low = _mm512_permutex2var_ps(_mm512_load_ps(t), index, _mm512_load_ps(t.add(16)));
            let high =
                _mm512_permutex2var_ps(_mm512_load_ps(t.add(32)), index, _mm512_load_ps(t.add(48)));
            _mm512_storeu_ps(out.as_mut_ptr(), _mm512_mask_blend_ps(upper, low, high));
        }
    }
    out
}

/// The paths of a group of pixels in flight, one per lane, in
/// structure-of-arrays form (component, then lane).
struct Paths {
    /// The lane's path is alive (its ray is to be traced).
    live: B,
    /// The lane holds a path whose sample is not yet on the film.
    in_flight: B,
    next_sample: [u32; LANES],
    origin: [F; 3],
    dir: [F; 3],
    radiance: [F; 3],
    beta: [F; 3],
    /// Solid-angle pdf of the BSDF sample that made the ray; 0 for a
    /// camera ray (emitters it hits get weight 1).
    prev_pdf: F,
    prev_point: [F; 3],
    depth: [u32; LANES],
    camera_hit: B,
}

/// Sample indices `s0..s1` of every pixel of `pixels` (at most
/// [`LANES`]), each with its sampler, onto `tile`; `hits` counts per
/// pixel of the tile (row length `tile_w`, origin `tile_origin`) the
/// samples whose camera ray met a surface.
///
/// # Safety
/// The CPU must support the features it is compiled for (checked by
/// [`WavefrontScene::new`]).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f,avx512vl,avx512dq,avx512bw,avx2,fma,bmi1,bmi2,lzcnt,popcnt")]
#[allow(clippy::too_many_arguments)]
unsafe fn trace_group(
    s: &WavefrontScene,
    film: &FilmRays,
    pixels: &[(u32, u32)],
    samplers: &mut [Sampler],
    (s0, s1): (u32, u32),
    tile: &mut FilmTile,
    hits: &mut [u32],
    (tile_origin, tile_w): ((u32, u32), u32),
) {
    let mut p = Paths {
        live: [false; LANES],
        in_flight: [false; LANES],
        next_sample: [s0; LANES],
        origin: [[0.0; LANES]; 3],
        dir: [[0.0; LANES]; 3],
        radiance: [[0.0; LANES]; 3],
        beta: [[1.0; LANES]; 3],
        prev_pdf: [0.0; LANES],
        prev_point: [[0.0; LANES]; 3],
        depth: [1; LANES],
        camera_hit: [false; LANES],
    };
    loop {
        // Lanes whose path ended hand in their sample and start their
        // pixel's next one.
        let mut any_live = false;
        for i in 0..pixels.len() {
            let (x, y) = pixels[i];
            if p.in_flight[i] && !p.live[i] {
                let v = Vec3::new(p.radiance[0][i], p.radiance[1][i], p.radiance[2][i]);
                // As `render_tile`: one bad sample must not ruin a pixel.
                tile.add_sample(x, y, if v.is_finite() { v } else { Vec3::ZERO });
                if p.camera_hit[i] {
                    let (x0, y0) = tile_origin;
                    hits[((y - y0) * tile_w + (x - x0)) as usize] += 1;
                }
                p.in_flight[i] = false;
            }
            if !p.in_flight[i] && p.next_sample[i] < s1 {
                let sampler = &mut samplers[i];
                sampler.start_sample(p.next_sample[i]);
                p.next_sample[i] += 1;
                let [jx, jy] = sampler.next_2d();
                let (o, d) = film.ray(x as f32 + jx, y as f32 + jy);
                for a in 0..3 {
                    p.origin[a][i] = o[a];
                    p.dir[a][i] = d[a];
                    p.prev_point[a][i] = o[a];
                    p.radiance[a][i] = 0.0;
                    p.beta[a][i] = 1.0;
                }
                p.prev_pdf[i] = 0.0;
                p.depth[i] = 1;
                p.camera_hit[i] = false;
                p.live[i] = true;
                p.in_flight[i] = true;
            }
            any_live |= p.live[i];
        }
        if !any_live {
            return;
        }
        segment(s, &mut p, samplers);
    }
}

/// One segment of every live path: its closest hit, the emission found
/// there, a light sample with its shadow ray, and the BSDF sample that
/// makes the next ray (or the path's end).
#[inline(always)]
fn segment(s: &WavefrontScene, p: &mut Paths, samplers: &mut [Sampler]) {
    // Closest hits, lane by lane (each scan tests 16 triangles at once).
    let mut tri = [0u32; LANES];
    let mut bary = [[0.0f32; LANES]; 2];
    let mut rays = 0;
    for i in 0..LANES {
        if !p.live[i] {
            continue;
        }
        rays += 1;
        let o = Vec3::new(p.origin[0][i], p.origin[1][i], p.origin[2][i]);
        let d = Vec3::new(p.dir[0][i], p.dir[1][i], p.dir[2][i]);
        let ray = WatertightRay::new(o, d);
        // SAFETY: AVX-512F (`trace_group`'s contract).
        match unsafe {
            s.scan
                .closest_avx512(&ray, d, f32::INFINITY, p.depth[i] == 1)
        } {
            Some((t, h)) => {
                tri[i] = t;
                bary[0][i] = h.b1;
                bary[1][i] = h.b2;
                p.camera_hit[i] |= p.depth[i] == 1;
            }
            None => p.live[i] = false,
        }
    }
    crate::stats::count_rays(rays);
    // The hits' surfaces, gathered lane by lane (dead lanes read
    // triangle 0, whose values no live result uses).
    let mut point = [[0.0f32; LANES]; 3];
    let mut ng = [[0.0f32; LANES]; 3];
    let mut albedo = [[0.0f32; LANES]; 3];
    let mut emitted = [[0.0f32; LANES]; 3];
    let mut pmf_per_area = [0.0f32; LANES];
    let mut two_sided = [false; LANES];
    for i in 0..LANES {
        tri[i] = if p.live[i] { tri[i] } else { 0 };
    }
    // SAFETY: AVX-512F (`trace_group`'s contract); triangle indices.
    let g = unsafe { gather(&s.tables, &tri) };
    for i in 0..LANES {
        pmf_per_area[i] = g[PMF_PER_AREA][i];
        two_sided[i] = g[TWO_SIDED][i] != 0.0;
        let (b1, b2) = (bary[0][i], bary[1][i]);
        let b0 = 1.0 - b1 - b2;
        for a in 0..3 {
            // Interpolating the corners is more accurate than o + t d.
            let c = |v: usize| g[CORNERS + 3 * v + a][i];
            point[a][i] = c(0) * b0 + c(1) * b1 + c(2) * b2;
            ng[a][i] = g[NORMAL + a][i];
            albedo[a][i] = g[ALBEDO + a][i];
            emitted[a][i] = g[EMISSION + a][i];
        }
    }
    // Emission reached by this segment, weighted against next-event
    // estimation; the normal turned towards the ray's origin.
    for i in 0..LANES {
        let dn = p.dir[0][i] * ng[0][i] + p.dir[1][i] * ng[1][i] + p.dir[2][i] * ng[2][i];
        let front = dn < 0.0;
        let emits = p.live[i] & (two_sided[i] | front);
        let mut dist2 = 0.0;
        for a in 0..3 {
            let d = point[a][i] - p.prev_point[a][i];
            dist2 += d * d;
        }
        let cos = dn.abs();
        let light_pdf = if cos > 1e-7 {
            pmf_per_area[i] * dist2 / cos
        } else {
            0.0
        };
        let weight = if p.prev_pdf[i] > 0.0 {
            power_heuristic(p.prev_pdf[i], light_pdf)
        } else {
            1.0
        };
        for a in 0..3 {
            let add = p.beta[a][i] * emitted[a][i] * weight;
            // A select, not a product with 0: a dead lane's values may be
            // NaN.
            p.radiance[a][i] += if emits { add } else { 0.0 };
            ng[a][i] = if front { ng[a][i] } else { -ng[a][i] };
        }
        // One-sided surfaces are black from behind; black ones reflect
        // nothing (a path ends there as `path::li`'s would add nothing).
        let black = (albedo[0][i] == 0.0) & (albedo[1][i] == 0.0) & (albedo[2][i] == 0.0);
        p.live[i] &= (front | two_sided[i]) & !black & (p.depth[i] < s.max_depth);
    }
    // Next-event estimation, its numbers drawn as `path::next_event` draws
    // them.
    let mut u_select = [0.0f32; LANES];
    let mut u_light = [[0.0f32; LANES]; 2];
    for i in 0..LANES {
        if p.live[i] {
            // The lobe's number (unused: Lambert has one) shares the
            // light choice's pair, as in `path::walk`.
            [u_select[i], _] = samplers[i].next_2d();
            [u_light[0][i], u_light[1][i]] = samplers[i].next_2d();
        }
    }
    let mut lc = [[[0.0f32; LANES]; 3]; 3];
    let mut ln = [[0.0f32; LANES]; 3];
    let mut le = [[0.0f32; LANES]; 3];
    let mut l_pmf_per_area = [0.0f32; LANES];
    let mut l_two_sided = [false; LANES];
    let mut light = [0u32; LANES];
    let last = s.lights.len() - 1;
    for i in 0..LANES {
        // The light: the first whose running sum exceeds u × total, as
        // `Distribution1D::sample` (every weight is positive, so it is
        // the number of sums at or below it).
        let target = f64::from(u_select[i]) * s.total_weight;
        let mut j = 0;
        for &c in &s.running_sums[..last] {
            j += (c <= target) as usize;
        }
        // SAFETY: j ≤ last < lights.len().
        light[i] = unsafe { at(&s.lights, j) };
    }
    // SAFETY: AVX-512F (`trace_group`'s contract); triangle indices.
    let g = unsafe { gather(&s.tables, &light) };
    for i in 0..LANES {
        for a in 0..3 {
            for v in 0..3 {
                lc[v][a][i] = g[CORNERS + 3 * v + a][i];
            }
            ln[a][i] = g[NORMAL + a][i];
            le[a][i] = g[EMISSION + a][i];
        }
        l_pmf_per_area[i] = g[PMF_PER_AREA][i];
        l_two_sided[i] = g[TWO_SIDED][i] != 0.0;
    }
    let mut shadow_origin = [[0.0f32; LANES]; 3];
    let mut wi = [[0.0f32; LANES]; 3];
    let mut shadow_tmax = [0.0f32; LANES];
    let mut shadow = [false; LANES];
    let mut contribution = [[0.0f32; LANES]; 3];
    for i in 0..LANES {
        // A uniform point of the triangle.
        let Vec2 { x: b0, y: b1 } = square_to_triangle([u_light[0][i], u_light[1][i]]);
        let mut d = [0.0f32; 3];
        for a in 0..3 {
            let q = lc[0][a][i] * (1.0 - b0 - b1) + lc[1][a][i] * b0 + lc[2][a][i] * b1;
            d[a] = q - point[a][i];
        }
        let dist2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
        let dist = dist2.sqrt();
        let w = d.map(|c| c / dist);
        let cos_light = -(w[0] * ln[0][i] + w[1] * ln[1][i] + w[2] * ln[2][i]);
        let lit_side = (cos_light > 0.0) | l_two_sided[i];
        let cos_light = cos_light.abs();
        let cos = w[0] * ng[0][i] + w[1] * ng[1][i] + w[2] * ng[2][i];
        let ok = p.live[i] & (dist2 > 0.0) & lit_side & (cos_light > 1e-7) & (cos > 0.0);
        // Area density → solid angle, with the selection: pdf = P(light)
        // d² / (A |cos θ_light|).
        let pdf = l_pmf_per_area[i] * dist2 / cos_light;
        let weight = power_heuristic(pdf, cos * FRAC_1_PI);
        // f cos / pdf with f = albedo / π.
        let scale = if ok {
            cos * FRAC_1_PI * weight / pdf
        } else {
            0.0
        };
        for a in 0..3 {
            contribution[a][i] = p.beta[a][i] * albedo[a][i] * le[a][i] * scale;
            shadow_origin[a][i] = offset_coordinate(point[a][i], ng[a][i]);
            wi[a][i] = w[a];
        }
        // Stop just short of the light, as `TraceContext::visible`.
        shadow_tmax[i] = dist * (1.0 - 1e-4);
        shadow[i] = ok;
    }
    let mut rays = 0;
    for i in 0..LANES {
        if !shadow[i] {
            continue;
        }
        rays += 1;
        let o = Vec3::new(
            shadow_origin[0][i],
            shadow_origin[1][i],
            shadow_origin[2][i],
        );
        let ray = WatertightRay::new(o, Vec3::new(wi[0][i], wi[1][i], wi[2][i]));
        // SAFETY: `trace_group` runs only where AVX-512 is (its contract).
        if unsafe { s.scan.occluded_avx512(&ray, shadow_tmax[i]) } {
            shadow[i] = false;
        }
    }
    crate::stats::count_rays(rays);
    for i in 0..LANES {
        for a in 0..3 {
            p.radiance[a][i] += if shadow[i] { contribution[a][i] } else { 0.0 };
        }
    }
    // BSDF sampling (cosine-weighted), then Russian roulette.
    let mut u_bsdf = [[0.0f32; LANES]; 2];
    let mut u_rr = [0.0f32; LANES];
    for i in 0..LANES {
        p.depth[i] += 1;
        if p.live[i] {
            [u_bsdf[0][i], u_bsdf[1][i]] = samplers[i].next_2d();
            if p.depth[i] > RR_START_DEPTH {
                u_rr[i] = samplers[i].next_1d();
            }
        }
    }
    for i in 0..LANES {
        let local = square_to_cosine_hemisphere([u_bsdf[0][i], u_bsdf[1][i]]);
        let n = Vec3::new(ng[0][i], ng[1][i], ng[2][i]);
        let w = Frame::from_normal(n).to_world(local);
        // On the normal's side, as `TraceContext::consistent_side`.
        let mut alive = p.live[i] & (local.z > 0.0) & (w.dot(n) > 0.0);
        for a in 0..3 {
            p.beta[a][i] *= albedo[a][i];
        }
        let q = if p.depth[i] > RR_START_DEPTH {
            // No refraction on Lambert surfaces: η² product 1.
            let beta = Vec3::new(p.beta[0][i], p.beta[1][i], p.beta[2][i]);
            rr_survival(beta, 1.0)
        } else {
            1.0
        };
        alive &= u_rr[i] < q;
        for a in 0..3 {
            p.beta[a][i] /= q;
            p.origin[a][i] = offset_coordinate(point[a][i], n[a]);
            p.dir[a][i] = w[a];
            p.prev_point[a][i] = point[a][i];
        }
        p.prev_pdf[i] = local.z * FRAC_1_PI;
        p.live[i] = alive;
    }
}

/// Sample indices `s0..s1` of the tile `(x0, y0, w, h)`'s pixels onto
/// `tile`, [`LANES`] pixels a group; `hits` counts per pixel the samples
/// whose camera ray met a surface.
#[allow(clippy::too_many_arguments)]
pub(crate) fn render_tile(
    s: &WavefrontScene,
    film: &FilmRays,
    seed: u32,
    tile: &mut FilmTile,
    (x0, y0, w, h): (u32, u32, u32, u32),
    s0: u32,
    s1: u32,
    hits: &mut [u32],
) {
    let pixels: Vec<(u32, u32)> = (y0..y0 + h)
        .flat_map(|y| (x0..x0 + w).map(move |x| (x, y)))
        .collect();
    for group in pixels.chunks(LANES) {
        // One sampler per pixel, as `render_tile`'s scalar loop.
        let mut samplers: Vec<Sampler> = group
            .iter()
            .map(|&(x, y)| Sampler::for_pixel_avx512(x, y, seed))
            .collect();
        #[cfg(target_arch = "x86_64")]
        // SAFETY: `WavefrontScene::new` checked the CPU's features.
        unsafe {
            trace_group(
                s,
                film,
                group,
                &mut samplers,
                (s0, s1),
                tile,
                hits,
                ((x0, y0), w),
            );
        }
    }
}
