//! Iteration 0 of the solve: the lights that are not patches shoot first.
//!
//! Abstract lights (point, spot, directional), analytic area lights and the
//! environment have no texels, so they cannot take part in progressive
//! refinement as shooters. Their direct irradiance at each patch,
//! `E0_j = (1/A_j) ∫_{A_j} ∫Ω Li_direct(p, ω) cos θ dω dp`, is estimated by
//! next-event estimation with MIS (`TraceContext::irradiance_at` with no
//! bounce) at [`FIRST_SHOT_SAMPLES`] points spread over the footprint,
//! keeping only the contributions of those lights (emissive surfaces are
//! patches and shoot themselves). A point light seen whole is exact at
//! each point; the footprint average smooths its falloff and shadow edges
//! over the patch as every other term of the solve is.

use super::patches::{Patches, sample_footprint};
use crate::baker::{BakeProgress, Prepared};
use penumbra_image::Rgb;
use penumbra_scene::RenderSettings;
use penumbra_shading::sampling::Sampler;
use penumbra_trace::geometry::SceneGeometry;
use penumbra_trace::integrator::RadianceSink;
use penumbra_trace::lights::{Emitter, LightSampler, LightSource};
use rayon::prelude::*;
use std::f32::consts::PI;
use std::sync::atomic::{AtomicU64, Ordering};

/// Points (one light sample and one BSDF sample each) per patch.
pub const FIRST_SHOT_SAMPLES: u32 = 64;

/// Sums the contributions of the lights that are not patches.
struct NonPatchSink<'a> {
    lights: &'a LightSampler,
    geometry: &'a SceneGeometry,
    sum: Rgb,
}

impl RadianceSink for NonPatchSink<'_> {
    fn add(&mut self, emitter: Emitter, _segment: u32, value: Rgb) {
        if let Some(src) = self.lights.source(self.geometry, emitter)
            && !matches!(src, LightSource::EmissiveInstance(_))
        {
            self.sum += value;
        }
    }
}

/// Does the scene have a light that is not a patch?
pub(crate) fn has_non_patch_lights(prep: &Prepared<'_>) -> bool {
    prep.lights
        .sources(&prep.geometry)
        .iter()
        .any(|s| !matches!(s, LightSource::EmissiveInstance(_)))
}

/// Per patch, E0 [W/m²] from the lights that are not patches.
pub(crate) fn direct_from_non_patch_lights(
    prep: &Prepared<'_>,
    patches: &Patches,
    seed: u32,
    progress: Option<BakeProgress<'_>>,
) -> Vec<Rgb> {
    let render = RenderSettings::default();
    let ctx = prep.context(&render);
    let page_h = prep.atlas.height;
    let done = AtomicU64::new(0);
    let total = patches.patches.len() as u64;
    patches
        .patches
        .par_iter()
        .enumerate()
        .map(|(i, patch)| {
            let pieces = patches.pieces_of(i);
            let t = &patch.texel;
            let mut sink = NonPatchSink {
                lights: &prep.lights,
                geometry: &prep.geometry,
                sum: Rgb::ZERO,
            };
            let mut sampler = Sampler::for_pixel(t.x, t.y + t.page * page_h, seed);
            for s in 0..FIRST_SHOT_SAMPLES {
                sampler.start_sample(s);
                let u_pick = sampler.next_1d();
                let (triangle, b) = sample_footprint(pieces, patch.area, u_pick, sampler.next_2d());
                let hit = prep.geometry.surface_point(prep.scene, triangle, b.x, b.y);
                ctx.irradiance_at(&hit, &mut sampler, 0, &mut sink);
            }
            let d = done.fetch_add(1, Ordering::Relaxed) + 1;
            if let Some(p) = progress
                && d.is_multiple_of(256)
            {
                p("radiosity: lights shoot first", d, total);
            }
            // The sink's values are radiance off a white Lambertian: E = π Σ.
            sink.sum * (PI / FIRST_SHOT_SAMPLES as f32)
        })
        .collect()
}
