//! The irradiance light-map bake: `E(p) = ∫Ω Li(p, ω) cos θ dω` [W/m²] per
//! texel from every light of the scene (abstract lights, analytic area
//! lights, emissive surfaces, the environment), direct and indirect, by
//! path tracing from the texel's point (next-event estimation and BSDF
//! sampling with MIS, Russian roulette), as the `path` integrator does
//! from a camera hit. The notes store E apart from colour: a Lambertian
//! surface of albedo c then has radiosity `B = c · E` and radiance
//! `L = Le + c E / π`, and the maps of several lights add up.

use crate::atlas::AtlasSettings;
use crate::baked::{Bake, BakeKind, BakedMap};
use crate::baker::{BakeProgress, Prepared};
use crate::error::BakeError;
use penumbra_image::Rgb;
use penumbra_scene::{RenderSettings, Scene};
use penumbra_trace::geometry::SceneGeometry;
use penumbra_trace::integrator::RadianceSink;
use penumbra_trace::lights::{Emitter, LightSampler, LightSource};
use std::f32::consts::PI;
use std::time::Instant;

/// Settings of a light-map bake.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightmapSettings {
    /// Paths per texel.
    pub samples: u32,
    /// Surfaces light may scatter from between a light and the texel
    /// (0: direct light only).
    pub bounces: u32,
    /// Leave out the light arriving directly from the lights (for
    /// real-time direct light with shadows on top of the map).
    pub indirect_only: bool,
    /// Also write one map per light; they add up to the total.
    pub per_light: bool,
    pub seed: u32,
}

impl Default for LightmapSettings {
    fn default() -> Self {
        Self {
            samples: 128,
            bounces: 6,
            indirect_only: false,
            per_light: false,
            seed: 0,
        }
    }
}

/// Collects one path's contributions: the total and, per light, its share.
struct TexelSink<'a> {
    lights: &'a LightSampler,
    geometry: &'a SceneGeometry,
    /// The per-light maps' lights, in map order (empty: total only).
    sources: &'a [LightSource],
    indirect_only: bool,
    out: &'a mut [Rgb],
}

impl RadianceSink for TexelSink<'_> {
    fn add(&mut self, emitter: Emitter, segment: u32, value: Rgb) {
        // Segment 2 is the light reaching the texel's point directly.
        if self.indirect_only && segment <= 2 {
            return;
        }
        let e = value * PI;
        self.out[0] += e;
        if self.sources.is_empty() {
            return;
        }
        if let Some(src) = self.lights.source(self.geometry, emitter)
            && let Some(k) = self.sources.iter().position(|&s| s == src)
        {
            self.out[1 + k] += e;
        }
    }
}

/// A light named for people (`info --bake`, the manifest).
pub fn describe_source(scene: &Scene, source: LightSource) -> String {
    match source {
        LightSource::Light(i) => format!("light '{}'", scene.lights[i].name),
        LightSource::AreaLight(i) => format!("area light '{}'", scene.area_lights[i].name),
        LightSource::EmissiveInstance(i) => {
            let inst = &scene.instances[i];
            format!(
                "emissive surface '{}' (instance {i}, material '{}')",
                scene.meshes[inst.mesh].name,
                scene.instance_material(inst).name
            )
        }
        LightSource::Environment => "the environment".to_string(),
    }
}

/// Bakes E for every texel of the scene's atlas.
pub fn bake_lightmap(
    scene: &Scene,
    settings: &LightmapSettings,
    atlas: &AtlasSettings,
    progress: Option<BakeProgress<'_>>,
) -> Result<Bake, BakeError> {
    if settings.samples == 0 {
        return Err(BakeError::Settings("--samples must be at least 1".into()));
    }
    let prep = Prepared::new(scene, atlas, progress)?;
    let mut warnings = Vec::new();
    let sources = if settings.per_light {
        prep.lights.sources(&prep.geometry)
    } else {
        Vec::new()
    };
    if prep.lights.is_empty() {
        warnings.push("the scene has no lights: the light map is black".to_string());
    }
    prep.check_memory(1 + sources.len())?;
    let render = RenderSettings::default();
    let ctx = prep.context(&render);
    let rays0 = penumbra_trace::stats::rays_traced();
    let t0 = Instant::now();
    let maps = prep.estimate(
        1 + sources.len(),
        settings.samples,
        settings.seed,
        progress,
        "irradiance",
        |hit, sampler, out| {
            let mut sink = TexelSink {
                lights: &prep.lights,
                geometry: &prep.geometry,
                sources: &sources,
                indirect_only: settings.indirect_only,
                out,
            };
            ctx.irradiance_at(hit, sampler, settings.bounces, &mut sink);
        },
    );
    let bake_seconds = t0.elapsed().as_secs_f64();
    let maps = maps
        .into_iter()
        .enumerate()
        .map(|(k, (pages, variance))| BakedMap {
            name: if k == 0 {
                "total".into()
            } else {
                format!("light-{}", k - 1)
            },
            light: (k > 0).then(|| describe_source(scene, sources[k - 1])),
            pages,
            variance,
        })
        .collect();
    let rays = penumbra_trace::stats::rays_traced() - rays0;
    Ok(prep.finish(
        BakeKind::Lightmap {
            bounces: settings.bounces,
            indirect_only: settings.indirect_only,
        },
        settings.samples,
        settings.seed,
        maps,
        bake_seconds,
        rays,
        warnings,
    ))
}
