//! Recursive (Whitted) ray tracing, the notes' "recursive ray tracing":
//! at every hit, direct light from the lights with shadow rays, shaded with
//! the non-delta lobes only (rough lobes are shaded locally, no indirect
//! diffuse light), plus the ideal reflection and refraction of the delta
//! lobes followed recursively, each weighted by its Fresnel throughput:
//!
//! `L(x, ωo) = Le + Σ_lights f(ωo, ωl) E_l cos θl V + Σ_delta T_k L(x_k, ω_k)`.
//!
//! Abstract lights are summed exactly; area lights and the environment get
//! one light sample per hit (so Whitted images of area-lit scenes are noisy
//! at 1 spp, as any stochastic direct-light estimate). A miss returns the
//! environment's radiance. Depth counts path segments as in
//! `path` (`max_depth` 1 = emitters only, 2 = direct light, each delta bounce
//! one more), so both integrators agree on purely specular scenes.

use super::{PathSample, TraceContext};
use crate::ray::Ray;
use crate::texture_lod::RayCone;
use penumbra_shading::Rgb;
use penumbra_shading::sampling::Sampler;

pub fn li(ctx: &TraceContext, camera_ray: &Ray, sampler: &mut Sampler) -> PathSample {
    let mut out = PathSample::default();
    out.radiance = trace(
        ctx,
        camera_ray,
        ctx.camera_cone,
        sampler,
        1,
        &mut Some(&mut out_aovs(&mut out)),
    );
    out
}

/// Where the first hit writes its AOVs.
struct FirstHit<'a> {
    out: &'a mut PathSample,
}

fn out_aovs(out: &mut PathSample) -> FirstHit<'_> {
    FirstHit { out }
}

/// Radiance along `ray` (footprint `cone`), which is path segment number
/// `depth`.
fn trace(
    ctx: &TraceContext,
    ray: &Ray,
    cone: RayCone,
    sampler: &mut Sampler,
    depth: u32,
    first: &mut Option<&mut FirstHit<'_>>,
) -> Rgb {
    let max_depth = ctx.settings.max_depth;
    if depth > max_depth {
        return Rgb::ZERO;
    }
    // Segment 1 is the camera ray, which culls glTF's single-sided back faces.
    let hit = if depth == 1 {
        ctx.geometry.intersect_camera(ctx.scene, ray)
    } else {
        ctx.geometry.intersect(ctx.scene, ray)
    };
    let Some(hit) = hit else {
        return ctx.lights.environment().eval(ray.direction);
    };
    let wo = -ray.direction;
    if let Some(l) = hit.light {
        // Analytic area light: a pure emitter.
        if let Some(f) = first.take() {
            *f.out = ctx.first_hit_aovs(None, &hit);
        }
        return ctx.geometry.area_lights[l as usize].emitted(hit.ng, wo);
    }
    let mut radiance = ctx.emitted(&hit, wo);
    // Delta bounces keep the cone's spread (curvature ignored).
    let cone = cone.at(hit.t);
    let shading = ctx.shading(&hit, wo, cone.width);
    if let Some(f) = first.take() {
        *f.out = ctx.first_hit_aovs(shading.as_ref(), &hit);
    }
    let Some(s) = shading else {
        return radiance;
    };
    if depth >= max_depth {
        return radiance;
    }
    if s.bsdf.flags().non_delta {
        radiance += ctx.direct_light(&s, sampler, true);
    }
    for (wi_local, throughput) in s.bsdf.specular(s.wo_local).iter() {
        let wi = s.frame.to_world(wi_local);
        if !TraceContext::consistent_side(&s, wi, wi_local) {
            continue;
        }
        let next = ctx.spawn(&s, wi, f32::INFINITY);
        radiance += throughput * trace(ctx, &next, cone, sampler, depth + 1, &mut None);
    }
    radiance
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::accel::BuildQuality;
    use crate::geometry::SceneGeometry;
    use crate::lights::LightSampler;
    use glam::{Mat4, Vec3};
    use penumbra_scene::{Material, RenderSettings, Scene, primitives};
    use penumbra_shading::bsdf::{Bsdf, Dielectric};

    /// A ray through a glass slab of thickness t leaves parallel to itself,
    /// shifted sideways by `t sin(θ − θt) / cos θt` (Snell: sin θ = η sin θt).
    #[test]
    fn glass_slab_shifts_a_ray_by_the_closed_form_offset() {
        let (t, eta) = (0.5f32, 1.5f32);
        let mut scene = Scene::default();
        let glass = scene.add_material(Material {
            bsdf: Bsdf::Dielectric(Dielectric::glass()),
            ..Material::lambert("glass", Rgb::ONE)
        });
        let mut slab = primitives::cuboid(Vec3::new(-50.0, -t, -50.0), Vec3::new(50.0, 0.0, 50.0));
        slab.material = glass;
        scene.add_mesh(slab, Mat4::IDENTITY);
        let geometry = SceneGeometry::build(&scene, BuildQuality::Medium).unwrap();
        let lights = LightSampler::new(&scene, &geometry);
        let settings = RenderSettings::default();
        let ctx = TraceContext {
            scene: &scene,
            geometry: &geometry,
            lights: &lights,
            settings: &settings,
            camera_cone: crate::texture_lod::RayCone::POINT,
        };
        for deg in [0.0f32, 15.0, 30.0, 45.0, 60.0, 75.0] {
            let th = deg.to_radians();
            let d = Vec3::new(th.sin(), -th.cos(), 0.0);
            let p0 = Vec3::new(0.3, 2.0, 0.1);
            let mut ray = Ray::segment(p0, d, f32::INFINITY);
            let mut exit = Vec3::ZERO;
            for _ in 0..2 {
                let hit = ctx.geometry.intersect(ctx.scene, &ray).expect("slab hit");
                let s = ctx
                    .shading(&hit, -ray.direction, 0.0)
                    .expect("glass is two-sided");
                let (wi_local, _) = s
                    .bsdf
                    .specular(s.wo_local)
                    .iter()
                    .find(|(w, _)| w.z < 0.0)
                    .expect("transmitted lobe");
                ray = ctx.spawn(&s, s.frame.to_world(wi_local), f32::INFINITY);
                exit = hit.p;
            }
            assert!(
                (ray.direction - d).length() < 1e-5,
                "{deg}°: leaves parallel"
            );
            let tht = (th.sin() / eta).asin();
            let expected = t * (th - tht).sin() / tht.cos();
            let shift = (exit - p0).cross(d).length();
            assert!(
                (shift - expected).abs() < 1e-4,
                "{deg}°: shift {shift} vs {expected}"
            );
        }
    }
}
