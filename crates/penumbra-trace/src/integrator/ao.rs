//! Ambient occlusion: `kA(p) = (1/π) ∫Ω v(p, l) (n·l) dl` (notes 004),
//! estimated with cosine-weighted directions, for which the estimator is the
//! visibility itself. Rays longer than `ao_distance` count as unoccluded.
//! The output is kA in all three channels (1 = fully open).

use super::{PathSample, Shading, TraceContext};
use crate::ray::Ray;
use penumbra_shading::Rgb;
use penumbra_shading::sampling::{Sampler, square_to_cosine_hemisphere};

pub fn li(ctx: &TraceContext, ray: &Ray, sampler: &mut Sampler) -> PathSample {
    let Some(hit) = ctx.geometry.intersect_camera(ctx.scene, ray) else {
        return PathSample::default();
    };
    if hit.light.is_some() {
        // An emitter has no surface to occlude: black, like a back face.
        return ctx.first_hit_aovs(None, &hit);
    }
    let wo = -ray.direction;
    let shading = ctx.shading(&hit, wo, ctx.camera_cone.width_at(hit.t));
    let mut out = ctx.first_hit_aovs(shading.as_ref(), &hit);
    let Some(s) = shading else { return out };
    out.radiance = Rgb::splat(visibility(ctx, &s, sampler.next_2d()));
    out
}

/// One sample of kA at `s`: a cosine-weighted direction `u` about the
/// shading normal, 1 if it leaves above the geometric surface and nothing
/// lies within `ao_distance` along it, else 0. The `ao` integrator and the
/// ambient-occlusion bake share it, so they estimate the same quantity.
pub(crate) fn visibility(ctx: &TraceContext, s: &Shading, u: [f32; 2]) -> f32 {
    let wi = s.frame.to_world(square_to_cosine_hemisphere(u));
    if wi.dot(s.ng) <= 0.0 {
        return 0.0;
    }
    let r = ctx.spawn(s, wi, ctx.settings.ao_distance);
    if ctx.geometry.occluded(&r) { 0.0 } else { 1.0 }
}
