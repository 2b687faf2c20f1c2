//! Environment light in the raster frame: the scene's environment (a
//! constant radiance or a lat-long map) lighting every material, diffuse and
//! specular, as WGSL `environment_light(s, kA)` (environment.wgsl) returns
//! it to the forward and base passes.
//!
//! - **Diffuse**: `c_diff · kA · E_env(n) / π`, E_env from the environment's
//!   projection on nine spherical harmonics per channel
//!   ([`penumbra_shading::light::Sh9`], Ramamoorthi & Hanrahan 2001),
//!   c_diff = `Bsdf::diffuse_albedo` (metallic–roughness: times
//!   1 − E_d(μo), its energy-conserving base under uniform light).
//! - **Specular**: the split sum (Karis 2013). The map is prefiltered once
//!   per environment into a lat-long mip chain ([`PREFILTER_LEVELS`]
//!   levels; level i holds the map convolved with GGX of perceptual
//!   roughness r = i/(levels − 1), α = r², level 0 the map itself), by a
//!   compute pass (prefilter.wgsl, timed as `"environment prefilter"`);
//!   the Fresnel-weighted directional albedo `f0·A + (f90 − f0)·B` comes
//!   from the GGX tables already bound for metallic–roughness (the
//!   Kulla–Conty table, [`penumbra_shading::bsdf::ggx_split_sum`]).
//!   The prefiltered map is read along the lobe's dominant direction
//!   (Lagarde & de Rousiers 2014), or, with
//!   [`crate::RasterOptions::environment_taps`] = N, averaged over N×N
//!   visible-normal taps of the pixel's own lobe (more accurate, N²
//!   lookups). Delta lobes (mirror, smooth conductor, smooth glass) reflect
//!   the map itself (level 0) along the mirror direction with their exact
//!   F(n·v).
//! - **Specular occlusion** from kA: `so = saturate((n·v + kA)^(2^(−16α−1))
//!   − 1 + kA)` (Lagarde & de Rousiers 2014).
//!
//! Approximations, per model ([`env_material`]): rough conductors with the
//! exact Fresnel equations use the Schlick-shaped split sum with
//! F0 = F_exact(cos 0) (their F at normal incidence) and F90 = 1;
//! Phong–Blinn's specular lobe is a GGX lobe of α = √(2/(n+2)) (Walter et
//! al. 2007's Phong–Beckmann exponent map) reflecting `ks ×` its normal-
//! incidence albedo; refraction is the environment seen straight through
//! the surface (along −v, no bending), weighted by the tint × (1 − F) for
//! glass and by base colour × transmission × (1 − E) for
//! metallic–roughness, and prefiltered at the lobe's roughness (rough
//! dielectrics); nothing is shadowed by other geometry except through kA.
//!
//! Group-0 bindings: [`ENVIRONMENT_BINDING`] (the uniform
//! [`GpuEnvironment`]), [`ENVIRONMENT_MAP_BINDING`] (the prefiltered map),
//! [`ENVIRONMENT_SAMPLER_BINDING`], [`ENVIRONMENT_MATERIALS_BINDING`] (one
//! [`GpuEnvMaterial`] per material).

use crate::context::GpuContext;
use crate::gpu::{
    ENV_SPEC_DELTA_CONDUCTOR, ENV_SPEC_DELTA_CONSTANT, ENV_SPEC_DELTA_DIELECTRIC, ENV_SPEC_NONE,
    ENV_SPEC_SPLIT_SUM, FRESNEL_EXACT, FRESNEL_SCHLICK, GpuEnvMaterial, GpuEnvironment,
    GpuPrefilterParams,
};
use crate::scene_gpu::{buffer_init, uniform_entry, whole};
use crate::timing::GpuTimer;
use penumbra_shading::Rgb;
use penumbra_shading::bsdf::{Bsdf, FresnelModel, optics::f0_from_ior};
use penumbra_shading::light::{Environment, EnvironmentMap, Sh9};
use std::sync::{Arc, Mutex, OnceLock};

/// The uniform [`GpuEnvironment`].
pub const ENVIRONMENT_BINDING: u32 = 20;
/// The prefiltered lat-long map (`texture_2d<f32>`, [`PREFILTER_LEVELS`] mips).
pub const ENVIRONMENT_MAP_BINDING: u32 = 21;
/// Its trilinear sampler (u repeats, v clamps).
pub const ENVIRONMENT_SAMPLER_BINDING: u32 = 22;
/// One [`GpuEnvMaterial`] per material (storage).
pub const ENVIRONMENT_MATERIALS_BINDING: u32 = 23;

/// Levels of the prefiltered map (fewer if the map is smaller): roughness
/// 0, 0.2, 0.4, 0.6, 0.8, 1 on a map of half the resolution each.
pub const PREFILTER_LEVELS: u32 = 6;

/// GGX samples per texel of prefiltered level i (level 0 is the map).
/// Rougher levels have fewer texels and wider lobes: about 1.6·10⁷ samples
/// in all for a 1024×512 map.
pub const PREFILTER_SAMPLES: [u32; PREFILTER_LEVELS as usize] = [0, 64, 128, 256, 512, 1024];

/// Texture format of the source and prefiltered maps (filterable
/// everywhere, and a storage format).
const MAP_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;

/// The environment pass's WGSL structs and functions without bindings
/// (SH9, lat-long, split sum, GGX samples, specular occlusion), appended to
/// the shading library ([`crate::shaders::library`]).
pub const COMMON_WGSL: &str = include_str!("common.wgsl");
/// The forward passes' bindings and `environment_light`.
pub const ENVIRONMENT_WGSL: &str = include_str!("environment.wgsl");
/// The prefilter compute pass.
pub const PREFILTER_WGSL: &str = include_str!("prefilter.wgsl");

/// The prefilter module: the shading library (which holds
/// [`COMMON_WGSL`]) and the host-shared structs, then the pass.
pub fn prefilter_source() -> String {
    format!(
        "{}\n{}\n{PREFILTER_WGSL}",
        crate::shaders::library(),
        crate::shaders::SCENE_WGSL
    )
}

/// Layout entries of the environment's group-0 bindings (fragment stage).
pub fn layout_entries() -> [wgpu::BindGroupLayoutEntry; 4] {
    let fragment = wgpu::ShaderStages::FRAGMENT;
    [
        uniform_entry(ENVIRONMENT_BINDING, fragment),
        wgpu::BindGroupLayoutEntry {
            binding: ENVIRONMENT_MAP_BINDING,
            visibility: fragment,
            ty: wgpu::BindingType::Texture {
                sample_type: wgpu::TextureSampleType::Float { filterable: true },
                view_dimension: wgpu::TextureViewDimension::D2,
                multisampled: false,
            },
            count: None,
        },
        wgpu::BindGroupLayoutEntry {
            binding: ENVIRONMENT_SAMPLER_BINDING,
            visibility: fragment,
            ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
            count: None,
        },
        crate::scene_gpu::storage_entry(ENVIRONMENT_MATERIALS_BINDING, fragment, true),
    ]
}

/// What the environment light needs of `bsdf` (see the module doc for the
/// approximations).
pub fn env_material(bsdf: &Bsdf) -> GpuEnvMaterial {
    let mut m = GpuEnvMaterial {
        diffuse: bsdf.diffuse_albedo().to_array(),
        kind: ENV_SPEC_NONE,
        ..Default::default()
    };
    let split_sum = |m: &mut GpuEnvMaterial, f0: Rgb, f90: Rgb, alpha: f32| {
        m.kind = ENV_SPEC_SPLIT_SUM;
        m.f0 = f0.to_array();
        m.f90 = f90.to_array();
        m.roughness = alpha.clamp(0.0, 1.0).sqrt();
    };
    match bsdf {
        Bsdf::Lambert(_) => {}
        Bsdf::PhongBlinn(p) => {
            let n = p.shininess.max(0.0);
            let s = p.ks * p.variant.normal_incidence_albedo(n);
            split_sum(&mut m, s, s, (2.0 / (n + 2.0)).sqrt());
        }
        Bsdf::Mirror(mirror) => {
            m.kind = ENV_SPEC_DELTA_CONSTANT;
            m.f0 = mirror.reflectance.to_array();
        }
        Bsdf::Conductor(c) => {
            m.kind = ENV_SPEC_DELTA_CONDUCTOR;
            m.eta = c.eta.to_array();
            m.k = c.k.to_array();
            m.fresnel = fresnel_index(c.fresnel);
        }
        Bsdf::Dielectric(d) => {
            m.kind = ENV_SPEC_DELTA_DIELECTRIC;
            m.ior = d.eta;
            m.transmit = d.tint.to_array();
        }
        Bsdf::RoughConductor(c) => {
            split_sum(&mut m, f0_from_ior(c.eta, c.k), Rgb::ONE, c.ggx().alpha());
        }
        Bsdf::RoughDielectric(d) => {
            let f0 = ((d.eta - 1.0) / (d.eta + 1.0)).powi(2);
            split_sum(&mut m, Rgb::splat(f0), Rgb::ONE, d.ggx().alpha());
            m.transmit = d.tint.to_array();
        }
        Bsdf::MetallicRoughness(mr) => {
            let metallic = mr.metallic.clamp(0.0, 1.0);
            let s = mr.specular.clamp(0.0, 1.0);
            let r = ((mr.ior - 1.0) / (mr.ior + 1.0)).powi(2);
            let d_f0 = (r * mr.specular_color).clamp(Rgb::ZERO, Rgb::ONE) * s;
            let d_f90 = Rgb::splat(s);
            // F = mix(F_d, Schlick(base_color), metallic): linear in (f0, f90).
            let f0 = d_f0 * (1.0 - metallic) + mr.base_color * metallic;
            let f90 = d_f90 * (1.0 - metallic) + Rgb::ONE * metallic;
            split_sum(&mut m, f0, f90, mr.alpha());
            m.diffuse_kc = 1;
            m.d_f0 = d_f0.to_array();
            m.d_f90 = s;
            m.transmit =
                (mr.base_color * ((1.0 - metallic) * mr.transmission.clamp(0.0, 1.0))).to_array();
        }
    }
    m
}

fn fresnel_index(f: FresnelModel) -> u32 {
    match f {
        FresnelModel::Exact => FRESNEL_EXACT,
        FresnelModel::Schlick => FRESNEL_SCHLICK,
    }
}

/// The uniform of an environment whose prefiltered map has `mip_count`
/// levels.
pub fn gpu_environment(env: &Environment, sh: &Sh9, mip_count: u32) -> GpuEnvironment {
    let (rotation_cos, rotation_sin) = match env {
        Environment::Map(m) => {
            // R_y(α) maps +x to (cos α, 0, −sin α).
            let x = m.rotation() * glam::Vec3::X;
            (x.x, -x.z)
        }
        Environment::Constant(_) => (1.0, 0.0),
    };
    GpuEnvironment {
        sh: sh.coefficients.map(|c| c.extend(0.0).to_array()),
        rotation_cos,
        rotation_sin,
        mip_count: mip_count as f32,
        background: 0,
        inv_view_proj: glam::Mat4::IDENTITY.to_cols_array_2d(),
    }
}

/// IEEE half-precision bits of `x` (the `half` crate: round to nearest
/// even); beyond the half range clamped to ±65504, non-finite to 0.
pub fn f16_bits(x: f32) -> u16 {
    let x = if x.is_finite() {
        x.clamp(-65504.0, 65504.0)
    } else {
        0.0
    };
    half::f16::from_f32(x).to_bits()
}

/// The value of IEEE half-precision bits.
pub fn f16_value(bits: u16) -> f32 {
    half::f16::from_bits(bits).to_f32()
}

/// One level of a lat-long mip chain.
struct Level {
    width: usize,
    height: usize,
    texels: Vec<Rgb>,
}

impl Level {
    /// The next level: 2×2 box filter (1×2 or 2×1 where an edge is 1).
    fn half(&self) -> Level {
        let (w, h) = ((self.width / 2).max(1), (self.height / 2).max(1));
        let (sx, sy) = (self.width / w, self.height / h);
        let mut texels = Vec::with_capacity(w * h);
        for y in 0..h {
            for x in 0..w {
                let mut sum = Rgb::ZERO;
                for dy in 0..sy {
                    for dx in 0..sx {
                        sum += self.texels[(y * sy + dy) * self.width + x * sx + dx];
                    }
                }
                texels.push(sum / (sx * sy) as f32);
            }
        }
        Level {
            width: w,
            height: h,
            texels,
        }
    }

    fn rgba16(&self) -> Vec<u16> {
        self.texels
            .iter()
            .flat_map(|t| [f16_bits(t.x), f16_bits(t.y), f16_bits(t.z), f16_bits(1.0)])
            .collect()
    }
}

/// The map and its box-filtered mip chain down to 1×1.
fn mip_chain(map: &EnvironmentMap) -> Vec<Level> {
    let mut levels = vec![Level {
        width: map.width(),
        height: map.height(),
        texels: map.texels().to_vec(),
    }];
    while levels.last().is_some_and(|l| l.width > 1 || l.height > 1) {
        let next = levels.last().map(Level::half);
        levels.extend(next);
    }
    levels
}

fn write_level(ctx: &GpuContext, texture: &wgpu::Texture, mip: u32, level: &Level) {
    ctx.queue.write_texture(
        wgpu::TexelCopyTextureInfo {
            texture,
            mip_level: mip,
            origin: wgpu::Origin3d::ZERO,
            aspect: wgpu::TextureAspect::All,
        },
        bytemuck::cast_slice(&level.rgba16()),
        wgpu::TexelCopyBufferLayout {
            offset: 0,
            bytes_per_row: Some(level.width as u32 * 8),
            rows_per_image: Some(level.height as u32),
        },
        wgpu::Extent3d {
            width: level.width as u32,
            height: level.height as u32,
            depth_or_array_layers: 1,
        },
    );
}

/// The prefilter's work, recorded into the first frame that shows the
/// environment.
#[derive(Debug)]
struct PrefilterJob {
    /// The source map with its mip chain (kept alive until submitted).
    _source: wgpu::Texture,
    /// Per prefiltered level ≥ 1: its bind group and size.
    levels: Vec<(wgpu::BindGroup, u32, u32)>,
}

/// One environment on the GPU: its uniform and prefiltered map.
#[derive(Debug)]
pub struct EnvironmentGpu {
    key: Environment,
    pub uniform: GpuEnvironment,
    uniform_buffer: wgpu::Buffer,
    _map: wgpu::Texture,
    view: wgpu::TextureView,
    prefilter: Mutex<Option<PrefilterJob>>,
}

impl EnvironmentGpu {
    /// Bind-group entries 20–22 (the materials, 23, are per scene).
    pub fn entries<'a>(&'a self, sampler: &'a wgpu::Sampler) -> [wgpu::BindGroupEntry<'a>; 3] {
        [
            whole(ENVIRONMENT_BINDING, &self.uniform_buffer),
            wgpu::BindGroupEntry {
                binding: ENVIRONMENT_MAP_BINDING,
                resource: wgpu::BindingResource::TextureView(&self.view),
            },
            wgpu::BindGroupEntry {
                binding: ENVIRONMENT_SAMPLER_BINDING,
                resource: wgpu::BindingResource::Sampler(sampler),
            },
        ]
    }

    /// Whether the environment is a map (drawn as the background).
    pub fn is_map(&self) -> bool {
        matches!(self.key, Environment::Map(_))
    }

    /// Writes the frame's camera (clip → world) and whether the background
    /// pass draws the map into the uniform (frames are recorded and
    /// submitted one at a time).
    pub fn write_view(&self, ctx: &GpuContext, inv_view_proj: glam::Mat4, background: bool) {
        let mut u = self.uniform;
        u.inv_view_proj = inv_view_proj.to_cols_array_2d();
        u.background = background as u32;
        ctx.queue
            .write_buffer(&self.uniform_buffer, 0, bytemuck::bytes_of(&u));
    }

    /// Level `level` of the prefiltered map, read back (after the frame that
    /// prefiltered it): row-major rgb, its width and height.
    pub fn read_level(
        &self,
        ctx: &GpuContext,
        level: u32,
    ) -> Result<(Vec<Rgb>, u32, u32), crate::GpuError> {
        let w = (self._map.width() >> level).max(1);
        let h = (self._map.height() >> level).max(1);
        let readback = crate::readback::TextureReadback::new(&ctx.device, w, h, 8);
        let mut encoder = ctx.device.create_command_encoder(&Default::default());
        readback.record(&mut encoder, &self._map, level);
        ctx.queue.submit([encoder.finish()]);
        let half: Vec<u16> = bytemuck::pod_collect_to_vec(&readback.read(ctx)?);
        let out = half
            .chunks_exact(4)
            .map(|t| Rgb::new(f16_value(t[0]), f16_value(t[1]), f16_value(t[2])))
            .collect();
        Ok((out, w, h))
    }

    /// Whether the prefilter still has to run (it runs in the next frame).
    pub fn needs_prefilter(&self) -> bool {
        self.prefilter
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .is_some()
    }
}

/// The prefilter pipeline, the samplers, and the last environment
/// prepared (a cache: the same environment is projected and prefiltered
/// once).
#[derive(Debug)]
pub struct EnvironmentPass {
    layout: wgpu::BindGroupLayout,
    /// The prefilter pipeline, made when a map is first prefiltered.
    pipeline: OnceLock<wgpu::ComputePipeline>,
    /// Trilinear, u repeating, v clamped: the source's and the forward's.
    pub sampler: wgpu::Sampler,
    cache: Mutex<Option<Arc<EnvironmentGpu>>>,
}

impl EnvironmentPass {
    pub fn new(device: &wgpu::Device) -> Self {
        let compute = wgpu::ShaderStages::COMPUTE;
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("environment prefilter"),
            entries: &[
                wgpu::BindGroupLayoutEntry {
                    binding: 0,
                    visibility: compute,
                    ty: wgpu::BindingType::Texture {
                        sample_type: wgpu::TextureSampleType::Float { filterable: true },
                        view_dimension: wgpu::TextureViewDimension::D2,
                        multisampled: false,
                    },
                    count: None,
                },
                wgpu::BindGroupLayoutEntry {
                    binding: 1,
                    visibility: compute,
                    ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
                    count: None,
                },
                wgpu::BindGroupLayoutEntry {
                    binding: 2,
                    visibility: compute,
                    ty: wgpu::BindingType::StorageTexture {
                        access: wgpu::StorageTextureAccess::WriteOnly,
                        format: MAP_FORMAT,
                        view_dimension: wgpu::TextureViewDimension::D2,
                    },
                    count: None,
                },
                uniform_entry(3, compute),
            ],
        });
        let sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("environment"),
            address_mode_u: wgpu::AddressMode::Repeat,
            address_mode_v: wgpu::AddressMode::ClampToEdge,
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            mipmap_filter: wgpu::MipmapFilterMode::Linear,
            ..Default::default()
        });
        Self {
            layout,
            pipeline: OnceLock::new(),
            sampler,
            cache: Mutex::new(None),
        }
    }

    /// The GPU form of `env`: the cached one if `env` is the last
    /// environment prepared, else projected, uploaded and with its
    /// prefilter pending ([`EnvironmentPass::record_prefilter`]).
    pub fn prepare(&self, ctx: &GpuContext, env: &Environment) -> Arc<EnvironmentGpu> {
        let mut cache = self.cache.lock().unwrap_or_else(|e| e.into_inner());
        if let Some(c) = cache.as_ref()
            && same_environment(&c.key, env)
        {
            return c.clone();
        }
        let made = Arc::new(self.upload(ctx, env));
        *cache = Some(made.clone());
        made
    }

    fn upload(&self, ctx: &GpuContext, env: &Environment) -> EnvironmentGpu {
        let device = &ctx.device;
        let sh = Sh9::from_environment(env);
        let chain = match env {
            Environment::Map(m) => mip_chain(m),
            Environment::Constant(l) => vec![Level {
                width: 1,
                height: 1,
                texels: vec![*l],
            }],
        };
        let levels = (chain.len() as u32).min(PREFILTER_LEVELS);
        let texture = |label, mips, usage| {
            device.create_texture(&wgpu::TextureDescriptor {
                label: Some(label),
                size: wgpu::Extent3d {
                    width: chain[0].width as u32,
                    height: chain[0].height as u32,
                    depth_or_array_layers: 1,
                },
                mip_level_count: mips,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format: MAP_FORMAT,
                usage,
                view_formats: &[],
            })
        };
        let sampled = wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST;
        let map = texture(
            "environment prefiltered",
            levels,
            sampled | wgpu::TextureUsages::STORAGE_BINDING | wgpu::TextureUsages::COPY_SRC,
        );
        // Level 0 is the map itself.
        write_level(ctx, &map, 0, &chain[0]);
        let prefilter = (levels > 1).then(|| {
            let source = texture("environment source", chain.len() as u32, sampled);
            for (i, level) in chain.iter().enumerate() {
                write_level(ctx, &source, i as u32, level);
            }
            let source_view = source.create_view(&Default::default());
            let levels = (1..levels)
                .map(|i| {
                    let level = &chain[i as usize];
                    let r = i as f32 / (levels - 1) as f32;
                    let params = GpuPrefilterParams {
                        alpha: r * r,
                        samples: PREFILTER_SAMPLES[i as usize],
                        width: level.width as u32,
                        height: level.height as u32,
                        source_width: chain[0].width as f32,
                        source_height: chain[0].height as f32,
                        source_levels: chain.len() as f32,
                        _pad0: 0.0,
                    };
                    let buffer = buffer_init(
                        device,
                        "prefilter params",
                        bytemuck::bytes_of(&params),
                        wgpu::BufferUsages::UNIFORM,
                    );
                    let target = map.create_view(&wgpu::TextureViewDescriptor {
                        base_mip_level: i,
                        mip_level_count: Some(1),
                        ..Default::default()
                    });
                    let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
                        label: Some("environment prefilter"),
                        layout: &self.layout,
                        entries: &[
                            wgpu::BindGroupEntry {
                                binding: 0,
                                resource: wgpu::BindingResource::TextureView(&source_view),
                            },
                            wgpu::BindGroupEntry {
                                binding: 1,
                                resource: wgpu::BindingResource::Sampler(&self.sampler),
                            },
                            wgpu::BindGroupEntry {
                                binding: 2,
                                resource: wgpu::BindingResource::TextureView(&target),
                            },
                            whole(3, &buffer),
                        ],
                    });
                    (group, params.width, params.height)
                })
                .collect();
            PrefilterJob {
                _source: source,
                levels,
            }
        });
        let uniform = gpu_environment(env, &sh, levels);
        EnvironmentGpu {
            key: env.clone(),
            uniform,
            uniform_buffer: buffer_init(
                device,
                "environment",
                bytemuck::bytes_of(&uniform),
                wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            ),
            view: map.create_view(&Default::default()),
            _map: map,
            prefilter: Mutex::new(prefilter),
        }
    }

    fn pipeline(&self, device: &wgpu::Device) -> &wgpu::ComputePipeline {
        self.pipeline.get_or_init(|| self.build_pipeline(device))
    }

    fn build_pipeline(&self, device: &wgpu::Device) -> wgpu::ComputePipeline {
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("environment prefilter"),
            source: wgpu::ShaderSource::Wgsl(prefilter_source().into()),
        });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("environment prefilter"),
            bind_group_layouts: &[Some(&self.layout)],
            immediate_size: 0,
        });
        device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some("environment prefilter"),
            layout: Some(&pipeline_layout),
            module: &module,
            entry_point: Some("prefilter_level"),
            compilation_options: Default::default(),
            cache: None,
        })
    }

    /// Records the prefilter of `env` if it has not run yet (one compute
    /// pass, `"environment prefilter"`, one dispatch per level ≥ 1).
    pub fn record_prefilter(
        &self,
        device: &wgpu::Device,
        env: &EnvironmentGpu,
        encoder: &mut wgpu::CommandEncoder,
        timer: &GpuTimer,
    ) {
        let Some(job) = env
            .prefilter
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .take()
        else {
            return;
        };
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("environment prefilter"),
            timestamp_writes: timer.compute_pass("environment prefilter"),
        });
        pass.set_pipeline(self.pipeline(device));
        for (group, w, h) in &job.levels {
            pass.set_bind_group(0, group, &[]);
            pass.dispatch_workgroups(w.div_ceil(8), h.div_ceil(8), 1);
        }
    }
}

/// Whether `a` and `b` are the same environment (maps: the same shared map,
/// or equal texels and rotation).
fn same_environment(a: &Environment, b: &Environment) -> bool {
    match (a, b) {
        (Environment::Map(x), Environment::Map(y)) => Arc::ptr_eq(x, y) || x == y,
        _ => a == b,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn f16_conversion_rounds_and_clamps() {
        assert_eq!(f16_bits(0.0), 0);
        assert_eq!(f16_bits(1.0), 0x3c00);
        assert_eq!(f16_bits(-2.0), 0xc000);
        assert_eq!(f16_bits(65504.0), 0x7bff);
        assert_eq!(f16_bits(1e9), 0x7bff);
        assert_eq!(f16_bits(f32::NAN), 0);
        // Smallest subnormal 2^-24 and a value that rounds to it.
        assert_eq!(f16_bits(5.960_464_5e-8), 1);
        assert_eq!(f16_bits(0.1), 0x2e66);
        assert_eq!(f16_bits(1.0 + 1.0 / 2048.0), 0x3c00); // ties to even
        for x in [0.0, 1.0, 0.1, 3.5e-6, 1234.5, 65504.0] {
            let back = f16_value(f16_bits(x));
            assert!((back - x).abs() <= x * 1e-3 + 6e-8, "{x} -> {back}");
        }
    }

    #[test]
    fn materials_choose_their_environment_lobes() {
        use penumbra_shading::bsdf::{Dielectric, Lambert, Mirror, RoughConductor};
        let l = env_material(&Bsdf::Lambert(Lambert::new(Rgb::splat(0.5))));
        assert_eq!((l.kind, l.diffuse), (ENV_SPEC_NONE, [0.5; 3]));
        let m = env_material(&Bsdf::Mirror(Mirror::new(Rgb::splat(0.9))));
        assert_eq!((m.kind, m.f0), (ENV_SPEC_DELTA_CONSTANT, [0.9; 3]));
        let g = env_material(&Bsdf::Dielectric(Dielectric::glass()));
        assert_eq!((g.kind, g.ior), (ENV_SPEC_DELTA_DIELECTRIC, 1.5));
        let c = RoughConductor::new(Rgb::splat(0.2), Rgb::splat(3.0), 0.09);
        let r = env_material(&Bsdf::RoughConductor(c));
        assert_eq!(r.kind, ENV_SPEC_SPLIT_SUM);
        assert!((r.roughness - 0.3).abs() < 1e-6);
        assert_eq!(r.diffuse, [0.0; 3]);
    }
}
