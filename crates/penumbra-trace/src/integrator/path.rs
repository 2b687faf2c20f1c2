//! Path tracing (global illumination): next-event estimation and BSDF
//! sampling combined by multiple importance sampling (power heuristic,
//! Veach 1997), Russian roulette after a few bounces.
//!
//! Estimates `L = Le + ∫ f Li cos dω` recursively. `max_depth` counts path
//! segments from the camera as Mitsuba does: 1 = emitters seen directly,
//! 2 = direct lighting, and so on.
//!
//! The walk is shared by camera paths ([`li`]) and by paths that start on
//! a surface ([`super::TraceContext::irradiance_at`], the light-map bake):
//! every emitted contribution goes to a [`RadianceSink`] with the light it
//! came from and the segment that reached it, so a sink can sum it, leave
//! out direct light, or split it per light.

use super::{PathSample, Shading, TraceContext};
use crate::lights::Emitter;
use crate::ray::Ray;
use crate::stages::{Stage, timed};
use crate::texture_lod::RayCone;
use glam::Vec3;
use penumbra_shading::Rgb;
use penumbra_shading::sampling::{Sampler, power_heuristic};

/// Segments after which Russian roulette may end a path.
pub(crate) const RR_START_DEPTH: u32 = 4;

/// Russian roulette's survival probability for a path of throughput
/// `beta` that has crossed refractions with η² product `eta_scale`: the
/// throughput with the 1/η² radiance scaling undone (pbrt-v4 and Mitsuba
/// do the same), capped at 0.95. A path inside glass (β = 1/η² ≈ 0.44)
/// is not ended more often than the same path outside it.
#[inline]
pub(crate) fn rr_survival(beta: Rgb, eta_scale: f32) -> f32 {
    (beta.max_element() * eta_scale).min(0.95)
}

/// Receives the emitted radiance a path collects.
pub trait RadianceSink {
    /// `value` (throughput and MIS weight applied) was emitted by `emitter`
    /// and reached the path along its segment number `segment` (counted
    /// from the path's start: 1 = the first ray, 2 = a light seen from the
    /// first vertex, ...).
    fn add(&mut self, emitter: Emitter, segment: u32, value: Rgb);
}

/// The plain sum (camera paths).
impl RadianceSink for Rgb {
    #[inline]
    fn add(&mut self, _emitter: Emitter, _segment: u32, value: Rgb) {
        *self += value;
    }
}

/// A path between bounces: the ray about to be traced and what it carries.
#[derive(Clone, Copy, Debug)]
pub(crate) struct PathState {
    pub ray: Ray,
    /// Throughput of the path up to the ray's origin.
    pub beta: Rgb,
    /// Product of η² over the refractions so far: `beta · eta_scale` is
    /// the throughput without the 1/η² radiance scaling, which Russian
    /// roulette looks at.
    pub eta_scale: f32,
    /// Solid-angle pdf of the BSDF sample that made `ray` (None = camera
    /// ray, or after a delta lobe: emitter hits get MIS weight 1).
    pub prev_bsdf_pdf: Option<f32>,
    pub prev_point: Vec3,
    /// Segments so far, counting `ray`.
    pub depth: u32,
    /// The ray's footprint, for texture filtering.
    pub cone: RayCone,
}

pub fn li(
    ctx: &TraceContext,
    camera_ray: &Ray,
    sampler: &mut Sampler,
    max_depth: u32,
) -> PathSample {
    let mut out = PathSample::default();
    if max_depth == 0 {
        return out;
    }
    let mut radiance = Rgb::ZERO;
    let start = PathState {
        ray: *camera_ray,
        beta: Rgb::ONE,
        eta_scale: 1.0,
        prev_bsdf_pdf: None,
        prev_point: camera_ray.origin,
        depth: 1,
        cone: ctx.camera_cone,
    };
    walk(ctx, start, sampler, max_depth, &mut radiance, &mut out);
    out.radiance = radiance;
    out
}

/// Traces `st` onwards until the path ends, handing emitted radiance to
/// `sink`; `aov` receives the first hit's AOVs when `st.depth` is 1.
pub(crate) fn walk<S: RadianceSink>(
    ctx: &TraceContext,
    mut st: PathState,
    sampler: &mut Sampler,
    max_depth: u32,
    sink: &mut S,
    aov: &mut PathSample,
) {
    loop {
        // Segment 1 is the camera ray, which culls glTF's single-sided back faces.
        let hit = timed(Stage::Closest, || {
            if st.depth == 1 {
                ctx.geometry.intersect_camera(ctx.scene, &st.ray)
            } else {
                ctx.geometry.intersect(ctx.scene, &st.ray)
            }
        });
        let Some(hit) = hit else {
            // Environment, MIS-weighted against its NEE sampling.
            let le = ctx.lights.environment().eval(st.ray.direction);
            if le != Rgb::ZERO {
                let weight = st.prev_bsdf_pdf.map_or(1.0, |bsdf_pdf| {
                    power_heuristic(bsdf_pdf, ctx.lights.pdf_environment(st.ray.direction))
                });
                sink.add(Emitter::Environment, st.depth, st.beta * le * weight);
            }
            return;
        };
        let wo = -st.ray.direction;
        if let Some(l) = hit.light {
            // Analytic area light: a pure emitter, MIS-weighted against NEE.
            let le = ctx.geometry.area_lights[l as usize].emitted(hit.ng, wo);
            if le != Rgb::ZERO {
                let weight = st.prev_bsdf_pdf.map_or(1.0, |bsdf_pdf| {
                    let light_pdf =
                        ctx.lights
                            .pdf_area_light(ctx.geometry, l, st.prev_point, st.ray.direction);
                    power_heuristic(bsdf_pdf, light_pdf)
                });
                sink.add(Emitter::Shape(l), st.depth, st.beta * le * weight);
            }
            if st.depth == 1 {
                *aov = ctx.first_hit_aovs(None, &hit);
            }
            return;
        }
        // Emission reached by this segment, MIS-weighted against NEE.
        let le = ctx.emitted(&hit, wo);
        if le != Rgb::ZERO {
            let weight = st.prev_bsdf_pdf.map_or(1.0, |bsdf_pdf| {
                let light_pdf = ctx
                    .lights
                    .pdf_triangle(hit.triangle, st.prev_point, hit.p, hit.ng);
                power_heuristic(bsdf_pdf, light_pdf)
            });
            sink.add(
                Emitter::Triangle(hit.triangle),
                st.depth,
                st.beta * le * weight,
            );
        }
        let cone = st.cone.at(hit.t);
        let shading = timed(Stage::Shading, || ctx.shading(&hit, wo, cone.width));
        if st.depth == 1 {
            *aov = ctx.first_hit_aovs(shading.as_ref(), &hit);
        }
        let Some(s) = shading else { return };
        if st.depth >= max_depth {
            return;
        }
        // The light's and the lobe's choice share a dimension pair.
        let [u_select, u_lobe] = sampler.next_2d();
        timed(Stage::NextEvent, || {
            next_event(ctx, &s, sampler, u_select, st.beta, st.depth, sink);
        });
        let next = timed(Stage::Scatter, || {
            scatter(
                ctx,
                &s,
                sampler,
                u_lobe,
                st.beta,
                st.eta_scale,
                st.depth,
                cone,
            )
        });
        match next {
            Some(next) => st = next,
            None => return,
        }
    }
}

/// Next-event estimation at `s` (the end of segment `depth`): one light
/// sample, weighted against BSDF sampling; skipped for purely specular
/// surfaces, whose eval is 0 everywhere. Adds to segment `depth + 1`.
/// `u_select` chooses the light; the point on it is drawn here.
#[allow(clippy::too_many_arguments)]
pub(crate) fn next_event<S: RadianceSink>(
    ctx: &TraceContext,
    s: &Shading,
    sampler: &mut Sampler,
    u_select: f32,
    beta: Rgb,
    depth: u32,
    sink: &mut S,
) {
    let u_light = sampler.next_2d();
    if !s.bsdf.flags().non_delta {
        return;
    }
    let Some(chosen) = ctx
        .lights
        .sample(ctx.scene, ctx.geometry, s.hit.p, u_select, u_light)
    else {
        return;
    };
    let ls = chosen.sample;
    let wi_local = s.frame.to_local(ls.wi);
    if !TraceContext::consistent_side(s, ls.wi, wi_local) {
        return;
    }
    let f = s.bsdf.eval(s.wo_local, wi_local);
    if f == Rgb::ZERO || !timed(Stage::Shadow, || ctx.visible(s, ls.wi, ls.distance)) {
        return;
    }
    let weight = if ls.is_delta {
        1.0
    } else {
        power_heuristic(ls.pdf * chosen.select_pdf, s.bsdf.pdf(s.wo_local, wi_local))
    };
    let cos = wi_local.z.abs();
    sink.add(
        Emitter::Entry(chosen.entry),
        depth + 1,
        beta * f * ls.value * (cos * weight / chosen.select_pdf),
    );
}

/// BSDF sampling at `s`, the end of segment `depth` of a path of throughput
/// `beta` (and η² product `eta_scale`) whose cone at `s` is `cone`: the
/// next segment, or `None` when the path ends (no sample, a direction on
/// the wrong side, Russian roulette). `u_lobe` chooses the BSDF's lobe;
/// the direction's numbers are drawn here.
///
/// Inlined into the path loop, so that the next [`PathState`] is built
/// where the loop keeps it: returned through memory, it was copied back
/// with wider loads than the stores that wrote it, which the CPU cannot
/// forward (about 3 % of a Cornell render's samples waited there in
/// `perf`; with this and [`SceneGeometry::intersect`] inlined, path
/// samples ran 3–8 % faster on the Cornell and glass scenes, medians of
/// 5–6 alternating runs on a noisy machine).
///
/// [`SceneGeometry::intersect`]: crate::geometry::SceneGeometry::intersect
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub(crate) fn scatter(
    ctx: &TraceContext,
    s: &Shading,
    sampler: &mut Sampler,
    u_lobe: f32,
    beta: Rgb,
    eta_scale: f32,
    depth: u32,
    cone: RayCone,
) -> Option<PathState> {
    let bs = s.bsdf.sample(s.wo_local, u_lobe, sampler.next_2d())?;
    let wi = s.frame.to_world(bs.wi);
    if !TraceContext::consistent_side(s, wi, bs.wi) {
        return None;
    }
    let mut beta = beta * bs.weight;
    let eta_scale = eta_scale * bs.eta * bs.eta;
    let depth = depth + 1;
    if depth > RR_START_DEPTH {
        let q = rr_survival(beta, eta_scale);
        if sampler.next_1d() >= q {
            return None;
        }
        beta /= q;
    }
    Some(PathState {
        ray: ctx.spawn(s, wi, f32::INFINITY),
        beta,
        eta_scale,
        // After a delta lobe the emitter hit gets weight 1: NEE cannot
        // sample that direction.
        prev_bsdf_pdf: (!bs.delta).then_some(bs.pdf),
        prev_point: s.hit.p,
        depth,
        cone: cone.scattered(0.0, (!bs.delta).then_some(bs.pdf), ctx.settings.spp),
    })
}
