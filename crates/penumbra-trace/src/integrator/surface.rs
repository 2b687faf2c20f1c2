//! Queries that start on a surface instead of at the camera: the estimators
//! behind the bakes (penumbra-bake), built from the same pieces as the
//! integrators so that a baked value and a rendered one estimate exactly the
//! same quantity.
//!
//! A query point is a [`SurfaceHit`] (see
//! [`crate::geometry::SceneGeometry::surface_point`]) seen from its front:
//! the side its geometric normal `ng` points to.

use super::path::{RadianceSink, next_event, scatter, walk};
use super::{PathSample, Shading, TraceContext, ao};
use crate::geometry::SurfaceHit;
use crate::texture_lod::RayCone;
use penumbra_shading::Rgb;
use penumbra_shading::bsdf::{Bsdf, Lambert};
use penumbra_shading::sampling::Sampler;

impl TraceContext<'_> {
    /// The shading state of `hit` seen from its front side, with its
    /// material's BSDF; `None` for the back of a one-sided surface (cannot
    /// happen from the front) or a point on an analytic light.
    fn front_shading<'h>(&self, hit: &'h SurfaceHit) -> Option<Shading<'h>> {
        if hit.light.is_some() {
            return None;
        }
        self.shading(hit, hit.ng, 0.0)
    }

    /// One sample of the ambient-occlusion term kA at `hit` (0 or 1), with
    /// the definition of the `ao` integrator: a cosine-weighted direction
    /// about the shading normal, unoccluded when nothing lies within
    /// `settings.ao_distance`. Its mean over samples is kA(p).
    pub fn ambient_occlusion_at(&self, hit: &SurfaceHit, sampler: &mut Sampler) -> f32 {
        match self.front_shading(hit) {
            Some(s) => ao::visibility(self, &s, sampler.next_2d()),
            None => 0.0,
        }
    }

    /// One path-traced sample of the irradiance at `hit` on its front side,
    /// `E(p) = ∫Ω Li(p, ω) cos θ dω` [W/m²], handed to `sink` contribution
    /// by contribution (each with its light and segment number: 2 = light
    /// arriving directly, 3 = after one bounce, ...). The values given to
    /// the sink are radiance reflected by a white Lambertian surface
    /// (f = 1/π) at `hit`, so their sum times π estimates E.
    ///
    /// `bounces` is the number of surfaces light may scatter from between
    /// the emitter and `hit` (0: direct light only); longer paths are
    /// still ended early by Russian roulette, without bias.
    pub fn irradiance_at<S: RadianceSink>(
        &self,
        hit: &SurfaceHit,
        sampler: &mut Sampler,
        bounces: u32,
        sink: &mut S,
    ) {
        let Some(mut s) = self.front_shading(hit) else {
            return;
        };
        s.bsdf = Bsdf::Lambert(Lambert::new(Rgb::ONE));
        // The query point is the end of segment 1 of a path, so segment 2
        // is direct light and the walk stops after `bounces` more.
        let max_depth = bounces.saturating_add(2);
        let beta = Rgb::ONE;
        let [u_select, u_lobe] = sampler.next_2d();
        next_event(self, &s, sampler, u_select, beta, 1, sink);
        if let Some(next) = scatter(self, &s, sampler, u_lobe, beta, 1.0, 1, RayCone::POINT) {
            walk(
                self,
                next,
                sampler,
                max_depth,
                sink,
                &mut PathSample::default(),
            );
        }
    }
}
