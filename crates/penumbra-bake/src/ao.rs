//! The ambient-occlusion bake: kA per texel, the notes'
//! `kA(p) = (1/π) ∫Ω v(p, l) (n·l) dl`, estimated exactly as the `ao`
//! integrator estimates it (cosine-weighted directions about the shading
//! normal, rays longer than the AO distance unoccluded), so a baked texel
//! and a rendered pixel at the same point have the same expectation.

use crate::atlas::AtlasSettings;
use crate::baked::{Bake, BakeKind, BakedMap};
use crate::baker::{BakeProgress, Prepared};
use crate::error::BakeError;
use penumbra_image::Rgb;
use penumbra_scene::{RenderSettings, Scene};
use std::time::Instant;

/// Settings of an AO bake.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AoSettings {
    /// Rays per texel.
    pub samples: u32,
    /// AO ray length [scene units]; infinite: every hit occludes.
    pub distance: f32,
    pub seed: u32,
}

impl Default for AoSettings {
    fn default() -> Self {
        Self {
            samples: 256,
            distance: f32::INFINITY,
            seed: 0,
        }
    }
}

/// Bakes kA for every texel of the scene's atlas.
pub fn bake_ao(
    scene: &Scene,
    settings: &AoSettings,
    atlas: &AtlasSettings,
    progress: Option<BakeProgress<'_>>,
) -> Result<Bake, BakeError> {
    if settings.samples == 0 {
        return Err(BakeError::Settings("--samples must be at least 1".into()));
    }
    if settings.distance.is_nan() || settings.distance <= 0.0 {
        return Err(BakeError::Settings(format!(
            "--ao-distance {} must be positive",
            settings.distance
        )));
    }
    let prep = Prepared::new(scene, atlas, progress)?;
    prep.check_memory(1)?;
    let render = RenderSettings {
        ao_distance: settings.distance,
        ..RenderSettings::default()
    };
    let ctx = prep.context(&render);
    let rays0 = penumbra_trace::stats::rays_traced();
    let t0 = Instant::now();
    let mut maps = prep.estimate(
        1,
        settings.samples,
        settings.seed,
        progress,
        "ambient occlusion",
        |hit, sampler, out| out[0] = Rgb::splat(ctx.ambient_occlusion_at(hit, sampler)),
    );
    let bake_seconds = t0.elapsed().as_secs_f64();
    let (pages, variance) = maps.remove(0);
    let map = BakedMap {
        name: "total".into(),
        light: None,
        pages,
        variance,
    };
    let rays = penumbra_trace::stats::rays_traced() - rays0;
    Ok(prep.finish(
        BakeKind::Ao {
            distance: settings.distance,
        },
        settings.samples,
        settings.seed,
        vec![map],
        bake_seconds,
        rays,
        Vec::new(),
    ))
}
