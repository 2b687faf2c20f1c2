//! Local illumination (the notes' direct-light approximation, as in the
//! real-time pipeline): `Lo = Le + Σ_k f(l_k, v) E_k cos θ_k` over every
//! light, with **no shadow rays**. Abstract lights are summed exactly; area
//! lights (emissive triangles, spheres, disks, quads) and the environment
//! are estimated with one light sample per camera sample, also without
//! visibility.

use super::{PathSample, TraceContext};
use crate::ray::Ray;
use penumbra_shading::sampling::Sampler;

pub fn li(ctx: &TraceContext, ray: &Ray, sampler: &mut Sampler) -> PathSample {
    let Some(hit) = ctx.geometry.intersect_camera(ctx.scene, ray) else {
        return PathSample {
            radiance: ctx.lights.environment().eval(ray.direction),
            ..Default::default()
        };
    };
    let wo = -ray.direction;
    if let Some(l) = hit.light {
        let mut out = ctx.first_hit_aovs(None, &hit);
        out.radiance = ctx.geometry.area_lights[l as usize].emitted(hit.ng, wo);
        return out;
    }
    let mut radiance = ctx.emitted(&hit, wo);
    let shading = ctx.shading(&hit, wo, ctx.camera_cone.width_at(hit.t));
    let mut out = ctx.first_hit_aovs(shading.as_ref(), &hit);
    if let Some(s) = shading {
        radiance += ctx.direct_light(&s, sampler, false);
    }
    out.radiance = radiance;
    out
}
