//! Runs one technique through the engines a user calls from the command
//! line (`render`, `render --engine raster`, `bake`), and says why where a
//! technique cannot run on this scene or machine.

use crate::error::StudyError;
use crate::measure::errors;
use crate::row::EqualTime;
use crate::study::StudyOptions;
use crate::technique::{RasterShadows, Technique};
use penumbra_bake::{AtlasSettings, LoadedBake};
use penumbra_image::Image;
use penumbra_raster::passes::ao::{AoMethod, AoQuality, AoSettings, default_radius};
use penumbra_raster::receivers::planar_receivers;
use penumbra_raster::{BakedMaps, ForwardRenderer, GpuContext, RasterOptions, ShadowMode};
use penumbra_scene::{IntegratorKind, RenderSettings, Scene};
use penumbra_shading::light::Environment;
use penumbra_trace::{RenderOptions, SceneTooLarge, render, scene_camera_for};
use std::collections::HashMap;
use std::path::Path;

/// Shadows of the real-time direct light in the rows that study something
/// else (environment, AO, indirect light map), so those rows differ only
/// by their technique: 2048² shadow maps with a 3×3 PCF.
pub const REALTIME_SHADOWS: RasterShadows = crate::technique::LIGHTMAP_SHADOWS;
/// Rays per texel of the AO bake.
pub const AO_BAKE_SAMPLES: u32 = 256;
/// Paths per texel of the light-map bakes.
pub const LIGHTMAP_SAMPLES: u32 = 64;
/// Radiosity patches.
pub const RADIOSITY_PATCHES: u32 = 10_000;
/// Why the environment rows skip a scene without ambient light.
const BLACK_ENVIRONMENT: &str =
    "the scene's environment is black: there is no ambient light to approximate";
/// Frames a raster row renders; the last one is timed (the first pays
/// for pipeline and upload warm-up).
const RASTER_FRAMES: usize = 2;

/// What a technique produced.
#[derive(Clone, Debug)]
pub struct Produced {
    pub image: Image,
    /// The approximated quantity when it is not the image (kA of AO rows).
    pub quantity: Option<Image>,
    /// Frame or render time [s].
    pub seconds: f64,
    pub bake_seconds: Option<f64>,
    /// The command lines that make the same image.
    pub command: String,
    pub notes: Vec<String>,
}

/// Runs techniques and keeps what rows share: the GPU device, the AO
/// radius, the path tracer's speed and its equal-time images.
pub struct Runner<'a> {
    scene: &'a Scene,
    options: &'a StudyOptions,
    out: &'a Path,
    gpu: Option<Result<GpuContext, String>>,
    /// R of every AO technique and of the `ao` truth [scene units].
    pub ao_radius: f32,
    /// Render time of one sample per pixel of `path` [s].
    pub path_seconds_per_spp: Option<f64>,
    equal_time: HashMap<u32, EqualTime>,
}

impl std::fmt::Debug for Runner<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Runner")
            .field("ao_radius", &self.ao_radius)
            .field("path_seconds_per_spp", &self.path_seconds_per_spp)
            .finish()
    }
}

impl<'a> Runner<'a> {
    pub fn new(scene: &'a Scene, options: &'a StudyOptions, out: &'a Path) -> Self {
        let bounds = scene
            .bounds()
            .unwrap_or((glam::Vec3::splat(-1.0), glam::Vec3::splat(1.0)));
        Self {
            scene,
            options,
            out,
            gpu: None,
            ao_radius: default_radius(bounds),
            path_seconds_per_spp: None,
            equal_time: HashMap::new(),
        }
    }

    /// The adapter the raster rows ran on.
    pub fn adapter(&self) -> Option<String> {
        match &self.gpu {
            Some(Ok(ctx)) => Some(ctx.summary.to_string()),
            _ => None,
        }
    }

    /// Runs `technique`; `Err` says why it cannot run here.
    pub fn run(&mut self, technique: &Technique) -> Result<Produced, String> {
        match *technique {
            Technique::Trace(i) => self.trace(i).map_err(|e| e.to_string()),
            Technique::Shadows(s) => {
                if s.mode == ShadowMode::Planar {
                    let bounds = self.scene.bounds().ok_or("the scene is empty")?;
                    if planar_receivers(self.scene, bounds).0.is_empty() {
                        return Err("the scene has no planar receiver (a flat object, e.g. a floor quad) for projected shadows".into());
                    }
                }
                self.raster(self.scene, s, AoMethod::None, &[], "")
            }
            Technique::Ambient => {
                let scene = self.ambient_scene()?;
                self.raster(&scene, REALTIME_SHADOWS, AoMethod::None, &[], "")
                    .map(|mut p| {
                        p.notes.insert(0, "the environment replaced by its mean radiance (a constant background); the command line has no flag for this: it is the scene file with `[environment] type = \"constant\"`".into());
                        p
                    })
            }
            Technique::Environment => {
                if self.scene.environment().is_black() {
                    return Err(BLACK_ENVIRONMENT.into());
                }
                self.raster(self.scene, REALTIME_SHADOWS, AoMethod::None, &[], "")
            }
            Technique::Ssao(m) => self.raster(self.scene, REALTIME_SHADOWS, m, &[], ""),
            Technique::BakedAo | Technique::Lightmap { .. } | Technique::Radiosity => {
                self.baked(technique)
            }
        }
    }

    fn settings(&self, integrator: IntegratorKind, spp: u32) -> RenderSettings {
        RenderSettings {
            integrator,
            spp,
            ao_distance: self.ao_radius,
            ..self.options.settings.clone()
        }
    }

    fn common_flags(&self) -> String {
        let s = &self.options.settings;
        format!(
            "penumbra render{} --resolution {}x{}",
            self.options.scene_arg(),
            s.width,
            s.height
        )
    }

    fn trace(&self, integrator: IntegratorKind) -> Result<Produced, SceneTooLarge> {
        let s = self.settings(integrator, self.options.settings.spp);
        let out = render(self.scene, &s, &RenderOptions::default())?;
        let mut command = format!(
            "{} --integrator {integrator} --spp {} --seed {}",
            self.common_flags(),
            s.spp,
            s.seed
        );
        match integrator {
            IntegratorKind::Ao => command += &format!(" --ao-distance {}", self.ao_radius),
            IntegratorKind::Path | IntegratorKind::Whitted => {
                command += &format!(" --max-depth {}", s.max_depth)
            }
            _ => {}
        }
        Ok(Produced {
            image: out.image,
            quantity: None,
            seconds: out.render_seconds,
            bake_seconds: None,
            command,
            notes: vec![format!(
                "BVH build {:.3} s (not counted)",
                out.build_seconds
            )],
        })
    }

    /// The scene with its environment map replaced by the map's mean
    /// radiance.
    fn ambient_scene(&self) -> Result<Scene, String> {
        let environment = self.scene.environment();
        if environment.is_black() {
            return Err(BLACK_ENVIRONMENT.into());
        }
        match environment {
            Environment::Map(m) => {
                let mut scene = self.scene.clone();
                scene.environment_map = None;
                scene.background = m.mean_radiance();
                Ok(scene)
            }
            Environment::Constant(_) => Err(
                "the scene's environment is already a constant: the constant ambient is E_env itself (see raster-environment)"
                    .into(),
            ),
        }
    }

    fn gpu(&mut self) -> Result<&GpuContext, String> {
        self.gpu
            .get_or_insert_with(|| GpuContext::new().map_err(|e| format!("no GPU adapter: {e}")))
            .as_ref()
            .map_err(Clone::clone)
    }

    /// Renders with the raster engine ([`RASTER_FRAMES`] frames, the last
    /// timed). AO rows also return the kA layer.
    fn raster(
        &mut self,
        scene: &Scene,
        shadows: RasterShadows,
        ao: AoMethod,
        bakes: &[LoadedBake],
        bake_flags: &str,
    ) -> Result<Produced, String> {
        let options = RasterOptions {
            msaa: self.options.msaa,
            shadows: shadows.mode,
            shadow_map_size: if shadows.mode == ShadowMode::Map {
                shadows.map_size
            } else {
                penumbra_raster::DEFAULT_SHADOW_MAP_SIZE
            },
            pcf: shadows.pcf,
            ao: AoSettings {
                method: ao,
                radius: Some(self.ao_radius),
                quality: AoQuality::Medium,
                thin_occluders: 0.0,
            },
            ..Default::default()
        };
        let (w, h) = (self.options.settings.width, self.options.settings.height);
        let wants_ao = ao != AoMethod::None || bakes.iter().any(|b| !b.kind.is_irradiance());
        let camera = scene_camera_for(scene, w, h);
        let maps = BakedMaps::from_bakes(bakes).map_err(|e| e.to_string())?;
        let ctx = self.gpu()?;
        let renderer = ForwardRenderer::new(ctx, options).map_err(|e| e.to_string())?;
        let mut last = None;
        for _ in 0..RASTER_FRAMES {
            last = Some(
                renderer
                    .render_baked(ctx, scene, &camera, w, h, &maps, wants_ao)
                    .map_err(|e| e.to_string())?,
            );
        }
        let out = last.ok_or("no frame")?;
        let quantity = out
            .aovs
            .into_iter()
            .find(|(n, _)| wants_ao && n == "ao")
            .map(|(_, i)| i);
        let mut command = format!(
            "{} --engine raster --msaa {}",
            self.common_flags(),
            self.options.msaa
        );
        match shadows.mode {
            ShadowMode::None => {}
            ShadowMode::Planar => command += " --shadows planar",
            ShadowMode::Volume => command += " --shadows volume",
            ShadowMode::Map => {
                command += &format!(
                    " --shadows map --shadow-map-size {} --pcf {}",
                    shadows.map_size, shadows.pcf
                )
            }
        }
        match ao {
            AoMethod::None => {}
            AoMethod::Hemisphere => command += " --ssao hemisphere",
            AoMethod::Gtao => command += " --ssao gtao",
        }
        if ao != AoMethod::None {
            command += &format!(" --ao-radius {}", self.ao_radius);
        }
        command += bake_flags;
        let mut notes = Vec::new();
        for w in out.warnings {
            if !notes.contains(&w) {
                notes.push(w);
            }
        }
        if wants_ao && scene.environment().is_black() {
            notes.push("the environment is black: kA multiplies nothing here, so the image equals the same row without AO; the kA error (against the ray-traced ao) is what this row measures".into());
        }
        Ok(Produced {
            image: out.image,
            quantity,
            seconds: out.frame_ms / 1000.0,
            bake_seconds: None,
            command,
            notes,
        })
    }

    /// Bakes into `bakes/<id>` (as `penumbra bake` does), then renders the
    /// bake with the raster engine.
    fn baked(&mut self, technique: &Technique) -> Result<Produced, String> {
        let scene = self.scene;
        let seed = self.options.settings.seed;
        let atlas = AtlasSettings::default();
        let (bake, bake_command, shadows) = match *technique {
            Technique::BakedAo => (
                penumbra_bake::bake_ao(
                    scene,
                    &penumbra_bake::AoSettings {
                        samples: AO_BAKE_SAMPLES,
                        distance: self.ao_radius,
                        seed,
                    },
                    &atlas,
                    None,
                ),
                format!(
                    "ao --samples {AO_BAKE_SAMPLES} --ao-distance {}",
                    self.ao_radius
                ),
                REALTIME_SHADOWS,
            ),
            Technique::Lightmap { indirect_only } => {
                let bounces = self.options.settings.max_depth.saturating_sub(2);
                (
                    penumbra_bake::bake_lightmap(
                        scene,
                        &penumbra_bake::LightmapSettings {
                            samples: LIGHTMAP_SAMPLES,
                            bounces,
                            indirect_only,
                            per_light: false,
                            seed,
                        },
                        &atlas,
                        None,
                    ),
                    format!(
                        "lightmap --samples {LIGHTMAP_SAMPLES} --bounces {bounces}{}",
                        if indirect_only {
                            " --indirect-only"
                        } else {
                            ""
                        }
                    ),
                    if indirect_only {
                        REALTIME_SHADOWS
                    } else {
                        RasterShadows {
                            mode: ShadowMode::None,
                            map_size: 0,
                            pcf: 1,
                        }
                    },
                )
            }
            Technique::Radiosity => (
                penumbra_bake::radiosity::bake_radiosity(
                    scene,
                    &penumbra_bake::radiosity::RadiositySettings {
                        patches: RADIOSITY_PATCHES,
                        tolerance: 1e-3,
                        rays_per_patch: 2000,
                        seed,
                    },
                    None,
                ),
                format!("radiosity --patches {RADIOSITY_PATCHES}"),
                RasterShadows {
                    mode: ShadowMode::None,
                    map_size: 0,
                    pcf: 1,
                },
            ),
            _ => unreachable!("not a bake: {technique:?}"),
        };
        let bake = bake.map_err(|e| format!("the bake failed: {e}"))?;
        let bake_seconds = bake.stats.prepare_seconds + bake.stats.bake_seconds;
        let id = technique.id();
        let dir = self.out.join("bakes").join(&id);
        penumbra_bake::write_bake(&bake, scene, &dir, Some(&self.options.scene_name()))
            .map_err(|e| format!("writing the bake: {e}"))?;
        let loaded = penumbra_bake::read_bake(&dir, scene).map_err(|e| e.to_string())?;
        let flags = format!(" --bake bakes/{id}");
        let mut p = self.raster(scene, shadows, AoMethod::None, &[loaded], &flags)?;
        p.bake_seconds = Some(bake_seconds);
        p.command = format!(
            "penumbra bake {bake_command}{} -o bakes/{id} && {}",
            self.options.scene_arg(),
            p.command
        );
        p.notes.extend(bake.warnings.iter().cloned());
        Ok(p)
    }

    /// `path` with as many samples per pixel as fit in `seconds` (at least
    /// one), from the speed of the `path` truth, and its errors against
    /// `full`; measured once per sample count (rows of similar cost share
    /// it).
    pub fn path_at_equal_time(
        &mut self,
        seconds: f64,
        full: &Image,
    ) -> Result<Option<EqualTime>, StudyError> {
        let per_spp = match self.path_seconds_per_spp {
            Some(t) => t,
            None => {
                // A given reference: time two samples per pixel once.
                let out = render(
                    self.scene,
                    &self.settings(IntegratorKind::Path, 2),
                    &RenderOptions::default(),
                )?;
                let t = out.render_seconds / 2.0;
                self.path_seconds_per_spp = Some(t);
                t
            }
        };
        if !(per_spp > 0.0 && seconds.is_finite()) {
            return Ok(None);
        }
        let spp = ((seconds / per_spp).round() as u32).max(1);
        if let Some(e) = self.equal_time.get(&spp) {
            return Ok(Some(*e));
        }
        let out = render(
            self.scene,
            &self.settings(IntegratorKind::Path, spp),
            &RenderOptions::default(),
        )?;
        let e = EqualTime {
            spp,
            seconds: out.render_seconds,
            full: errors(full, &out.image)?.0,
        };
        self.equal_time.insert(spp, e);
        Ok(Some(e))
    }
}
