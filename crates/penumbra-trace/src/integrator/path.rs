//! Path tracing (global illumination): next-event estimation and BSDF
//! sampling combined by multiple importance sampling (power heuristic,
//! Veach 1997), Russian roulette after a few bounces.
//!
//! Estimates `L = Le + ∫ f Li cos dω` recursively. `max_depth` counts path
//! segments from the camera as Mitsuba does: 1 = emitters seen directly,
//! 2 = direct lighting, and so on.

use super::{PathSample, TraceContext};
use crate::lights::emitted;
use crate::ray::Ray;
use penumbra_shading::Rgb;
use penumbra_shading::sampling::{Sampler, power_heuristic};

/// Segments after which Russian roulette may end a path.
const RR_START_DEPTH: u32 = 4;

pub fn li(
    ctx: &TraceContext,
    camera_ray: &Ray,
    sampler: &mut Sampler,
    max_depth: u32,
) -> PathSample {
    let mut out = PathSample::default();
    let mut radiance = Rgb::ZERO;
    let mut beta = Rgb::ONE;
    let mut ray = *camera_ray;
    // Solid-angle pdf of the BSDF sample that made `ray` (None = camera ray).
    let mut prev_bsdf_pdf: Option<f32> = None;
    let mut prev_point = ray.origin;
    let mut depth = 1u32; // segments so far, counting `ray`
    if max_depth == 0 {
        return out;
    }
    loop {
        let Some(hit) = ctx.geometry.intersect(ctx.scene, &ray) else {
            // Environment, MIS-weighted against its NEE sampling.
            let le = ctx.lights.environment().eval(ray.direction);
            if le != Rgb::ZERO {
                let weight = prev_bsdf_pdf.map_or(1.0, |bsdf_pdf| {
                    power_heuristic(bsdf_pdf, ctx.lights.pdf_environment(ray.direction))
                });
                radiance += beta * le * weight;
            }
            break;
        };
        let wo = -ray.direction;
        if let Some(l) = hit.light {
            // Analytic area light: a pure emitter, MIS-weighted against NEE.
            let le = ctx.geometry.area_lights[l as usize].emitted(hit.ng, wo);
            if le != Rgb::ZERO {
                let weight = prev_bsdf_pdf.map_or(1.0, |bsdf_pdf| {
                    let light_pdf =
                        ctx.lights
                            .pdf_area_light(ctx.geometry, l, prev_point, ray.direction);
                    power_heuristic(bsdf_pdf, light_pdf)
                });
                radiance += beta * le * weight;
            }
            if depth == 1 {
                out = ctx.first_hit_aovs(None, &hit);
            }
            break;
        }
        let material = &ctx.scene.materials[hit.material];
        // Emission reached by this segment, MIS-weighted against NEE.
        let le = emitted(material.emission, material.double_sided, hit.ng, wo);
        if le != Rgb::ZERO {
            let weight = match prev_bsdf_pdf {
                None => 1.0,
                Some(bsdf_pdf) => {
                    let light_pdf =
                        ctx.lights
                            .pdf_triangle(hit.triangle, prev_point, hit.p, hit.ng);
                    power_heuristic(bsdf_pdf, light_pdf)
                }
            };
            radiance += beta * le * weight;
        }
        let shading = ctx.shading(&hit, wo);
        if depth == 1 {
            out = ctx.first_hit_aovs(shading.as_ref(), &hit);
        }
        let Some(s) = shading else { break };
        if depth >= max_depth {
            break;
        }
        // Next-event estimation: one light sample (adds segment depth + 1),
        // skipped for purely specular surfaces, whose eval is 0 everywhere.
        let [u_sel, _] = sampler.next_2d();
        let u_light = sampler.next_2d();
        let chosen = if s.bsdf.flags().non_delta {
            ctx.lights
                .sample(ctx.scene, ctx.geometry, s.hit.p, u_sel, u_light)
        } else {
            None
        };
        if let Some(chosen) = chosen {
            let ls = chosen.sample;
            let wi_local = s.frame.to_local(ls.wi);
            let cos = wi_local.z.abs();
            if TraceContext::consistent_side(&s, ls.wi, wi_local) {
                let f = s.bsdf.eval(s.wo_local, wi_local);
                if f != Rgb::ZERO && ctx.visible(&s, ls.wi, ls.distance) {
                    let weight = if ls.is_delta {
                        1.0
                    } else {
                        power_heuristic(
                            ls.pdf * chosen.select_pdf,
                            s.bsdf.pdf(s.wo_local, wi_local),
                        )
                    };
                    radiance += beta * f * ls.value * (cos * weight / chosen.select_pdf);
                }
            }
        }
        // BSDF sampling continues the path.
        let Some(bs) = s
            .bsdf
            .sample(s.wo_local, sampler.next_1d(), sampler.next_2d())
        else {
            break;
        };
        let wi = s.frame.to_world(bs.wi);
        if !TraceContext::consistent_side(&s, wi, bs.wi) {
            break;
        }
        beta *= bs.weight;
        depth += 1;
        if depth > RR_START_DEPTH {
            let q = beta.max_element().min(0.95);
            if sampler.next_1d() >= q {
                break;
            }
            beta /= q;
        }
        // After a delta lobe the emitter hit gets weight 1: NEE cannot
        // sample that direction.
        prev_bsdf_pdf = (!bs.delta).then_some(bs.pdf);
        prev_point = s.hit.p;
        ray = ctx.spawn(&s, wi, f32::INFINITY);
    }
    out.radiance = radiance;
    out
}
