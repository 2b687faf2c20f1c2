//! The raster frame: the scene uploaded once, then
//!
//! 1. shadow maps (`--shadows map`), one depth pass per layer;
//! 2. a depth prepass (reversed depth, @invariant clip positions);
//! 3. without stencil shadows: tiled light culling, then one forward pass
//!    that shades each pixel with its tile's lights (shadow-mapped or not);
//! 4. with stencil shadows (`planar`, `volume`): a base pass (emission),
//!    then per light a stencil pass (planar projection or shadow volumes)
//!    and an additive pass of that light where the stencil says lit;
//!
//! into an `Rgba32Float` target (MSAA 1 or 4), read back as an [`Image`].
//! Baked maps ([`BakedMaps`]: ambient occlusion, irradiance) are looked up
//! by the shading passes (group 2), and with `aovs` a last pass writes the
//! looked-up values into their own targets.

use crate::camera::view_and_projection;
use crate::context::{GpuContext, GpuError};
use crate::gpu::GpuPassParams;
use crate::light_culling::{CullingStats, LightCulling, MAX_CULLED_LIGHTS};
use crate::material_tables::{KULLA_CONTY_BINDING, kulla_conty_table};
use crate::passes::ao::{AoSettings, AoTextures, NORMAL_TARGET_FORMAT, ScreenSpaceAo};
use crate::passes::environment::{
    ENVIRONMENT_MATERIALS_BINDING, EnvironmentPass, layout_entries as environment_entries,
};
use crate::passes::lightmap::{BAKE_GROUP, BakedMaps, LightmapFrame, bake_layout};
use crate::planar_shadow::{PlanarFrame, PlanarShadows};
use crate::readback::TextureReadback;
use crate::receivers::planar_receivers;
use crate::scene_gpu::{
    PassParams, SceneGpu, buffer_init, params_layout, storage_entry, uniform_entry, whole,
};
use crate::shaders::forward_source;
use crate::shadow_map::{
    DEFAULT_NORMAL_OFFSET, DEFAULT_SHADOW_MAP_SIZE, DEFAULT_SLOPE_BIAS, SHADOW_CONSTANT_BIAS,
    SHADOW_MAP_FORMAT, ShadowMapFrame,
};
use crate::shadow_volume::{ShadowVolumes, VolumeFrame};
use crate::textures::TextureFeatures;
use crate::timing::{GpuTimer, PassTiming};
use glam::Vec3;
use penumbra_image::Image;
use penumbra_scene::Scene;
use penumbra_scene::camera::Camera;
use std::collections::HashMap;
use std::sync::{Arc, Mutex, OnceLock};
use std::time::Instant;

const COLOR_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;

/// How the raster path shadows the abstract lights.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum ShadowMode {
    /// No shadows (the CPU `local` integrator's model).
    #[default]
    None,
    /// Shadow maps: orthographic for directional lights (fitted to the scene
    /// bounds), perspective for spot lights (frustum = outer cone), six
    /// perspective cube faces for point lights.
    Map,
    /// Planar projected shadows on the planar receivers (stencil).
    Planar,
    /// Stencil shadow volumes (z-fail, caps, extruded to infinity).
    Volume,
}

impl ShadowMode {
    /// Modes that shade one light per pass through the stencil buffer.
    pub fn uses_stencil(self) -> bool {
        matches!(self, ShadowMode::Planar | ShadowMode::Volume)
    }
}

/// Options of the raster path.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RasterOptions {
    /// Samples per pixel of the colour and depth targets: 1 or 4.
    pub msaa: u32,
    pub shadows: ShadowMode,
    /// Edge of every shadow map (layer) in texels.
    pub shadow_map_size: u32,
    /// PCF kernel edge N: N×N comparison taps one texel apart (1 = one hard
    /// tap with nearest filtering; N > 1 taps are bilinearly filtered).
    pub pcf: u32,
    /// Slope-scaled depth bias of the shadow passes (see
    /// [`DEFAULT_SLOPE_BIAS`]).
    pub slope_bias: f32,
    /// Normal offset of the lookup in texels (see [`DEFAULT_NORMAL_OFFSET`]).
    pub normal_offset: f32,
    /// Tiled light culling of the forward pass (off: every pixel loops over
    /// every light; the image is the same, see `light_culling.rs`).
    pub light_culling: bool,
    /// Read the tile lists back after the frame and report
    /// [`RasterOutput::culling`] (costs a copy and a readback).
    pub culling_stats: bool,
    /// Screen-space ambient occlusion of the environment term.
    pub ao: AoSettings,
    /// Glossy environment reflections (see `passes/environment`): 0 = the
    /// split sum with one lookup of the prefiltered map along the lobe's
    /// dominant direction; N (1 to [`MAX_ENVIRONMENT_TAPS`]) = the
    /// prefiltered radiance averaged over N×N visible-normal taps of the
    /// lobe (N² lookups per pixel), times the same split-sum factor.
    pub environment_taps: u32,
}

/// Largest [`RasterOptions::environment_taps`].
pub const MAX_ENVIRONMENT_TAPS: u32 = 32;

impl Default for RasterOptions {
    fn default() -> Self {
        Self {
            msaa: 1,
            shadows: ShadowMode::None,
            shadow_map_size: DEFAULT_SHADOW_MAP_SIZE,
            pcf: 1,
            slope_bias: DEFAULT_SLOPE_BIAS,
            normal_offset: DEFAULT_NORMAL_OFFSET,
            light_culling: true,
            culling_stats: false,
            ao: AoSettings::default(),
            environment_taps: 0,
        }
    }
}

/// Largest PCF kernel edge.
pub const MAX_PCF: u32 = 15;

/// A finished raster render.
#[derive(Clone, Debug)]
pub struct RasterOutput {
    /// Linear radiance, row 0 = top (as the CPU film).
    pub image: Image,
    /// Wall time of upload, draw and readback [ms].
    pub total_ms: f64,
    /// Wall time from submitting the frame to the end of its execution
    /// [ms] (the queue is polled until idle).
    pub frame_ms: f64,
    /// GPU time of every pass in submission order (names: `"environment
    /// prefilter"` (in the first frame that shows an environment map),
    /// `"shadow map L"`, `"background"` (after the lighting passes, with an
    /// environment map), `"depth prepass"`, `"light culling"`, `"forward"`, `"base"`,
    /// `"shadow volume facing L"`, `"shadow volume stencil L"`, `"planar
    /// shadow L"`, `"light L"`, `"blend"` (with BLEND materials)), where
    /// the adapter supports timestamp
    /// queries; empty otherwise.
    pub passes: Vec<PassTiming>,
    /// Per pixel, row 0 = top: whether a surface covers most of it (the
    /// colour target's alpha: 1 where a surface was drawn, 0 for the
    /// background, averaged by the MSAA resolve; BLEND surfaces add α).
    pub surface: Vec<bool>,
    /// What the raster path approximated for this scene (see
    /// [`crate::SceneData`]).
    pub warnings: Vec<String>,
    /// The light lists of the tiles, with [`RasterOptions::culling_stats`].
    pub culling: Option<CullingStats>,
    /// With `aovs`: `ao` (kA: looked up in an AO bake, or the screen-space
    /// term after its denoise) and, with an irradiance bake, `irradiance`
    /// (E in W/m²), per pixel.
    pub aovs: Vec<(String, Image)>,
}

/// One vertex buffer of `vec3<f32>` at `location` (0 positions, 1 normals).
fn vec3_buffer(location: u32) -> wgpu::VertexBufferLayout<'static> {
    wgpu::VertexBufferLayout {
        array_stride: 12,
        step_mode: wgpu::VertexStepMode::Vertex,
        attributes: if location == 0 {
            &wgpu::vertex_attr_array![0 => Float32x3]
        } else {
            &wgpu::vertex_attr_array![1 => Float32x3]
        },
    }
}

fn depth_state(
    write: bool,
    compare: wgpu::CompareFunction,
    stencil: wgpu::StencilState,
    format: wgpu::TextureFormat,
) -> wgpu::DepthStencilState {
    wgpu::DepthStencilState {
        format,
        depth_write_enabled: Some(write),
        depth_compare: Some(compare),
        stencil,
        bias: Default::default(),
    }
}

/// One render pipeline of the forward module.
struct PipelineSpec<'a> {
    label: &'a str,
    vs: &'a str,
    fs: Option<&'a str>,
    buffers: &'a [Option<wgpu::VertexBufferLayout<'a>>],
    depth: wgpu::DepthStencilState,
    blend: Option<wgpu::BlendState>,
    samples: u32,
    /// Values of the module's `override` constants.
    constants: &'a [(&'a str, f64)],
    /// Whether the fragment stage writes a colour target (false: depth only).
    color: bool,
}

fn build_pipeline(
    device: &wgpu::Device,
    module: &wgpu::ShaderModule,
    layout: &wgpu::PipelineLayout,
    s: PipelineSpec<'_>,
) -> wgpu::RenderPipeline {
    let target = [Some(wgpu::ColorTargetState {
        format: COLOR_FORMAT,
        blend: s.blend,
        write_mask: wgpu::ColorWrites::ALL,
    })];
    let targets: &[Option<wgpu::ColorTargetState>] = if s.color { &target } else { &[] };
    let options = wgpu::PipelineCompilationOptions {
        constants: s.constants,
        ..Default::default()
    };
    device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some(s.label),
        layout: Some(layout),
        vertex: wgpu::VertexState {
            module,
            entry_point: Some(s.vs),
            compilation_options: options.clone(),
            buffers: s.buffers,
        },
        primitive: wgpu::PrimitiveState {
            topology: wgpu::PrimitiveTopology::TriangleList,
            front_face: wgpu::FrontFace::Ccw,
            cull_mode: None,
            ..Default::default()
        },
        depth_stencil: Some(s.depth),
        multisample: wgpu::MultisampleState {
            count: s.samples,
            ..Default::default()
        },
        fragment: s.fs.map(|fs| wgpu::FragmentState {
            module,
            entry_point: Some(fs),
            compilation_options: options,
            targets,
        }),
        multiview_mask: None,
        cache: None,
    })
}

/// What the shading pipelines are specialised to: the material models of
/// a scene (the `MATERIAL_MODELS` mask), what its textures use
/// (`TEXTURE_SLOTS`, `TEXEL_FORMATS`, `WRAP_MODES`) and the presence of
/// bakes (`BAKED_MAPS`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
struct ShadingKey {
    models: u32,
    textures: TextureFeatures,
    baked: bool,
}

/// The shading passes: opaque materials with every light (`fs_forward`),
/// BLEND materials source-over (`fs_blend`), one light added where the
/// stencil says lit (`fs_light`).
#[derive(Clone, Copy, Debug)]
enum ShadingPass {
    Forward,
    Blend,
    Light,
}

/// The shading pipelines of one [`ShadingKey`].
#[derive(Debug)]
struct ShadingPipelines {
    /// The key's values of the module's `override` constants.
    constants: Vec<(&'static str, f64)>,
    /// By [`ShadingPass`], each made on first use.
    pipelines: [OnceLock<wgpu::RenderPipeline>; 3],
}

/// The raster pipelines for one set of options. Those in `OnceLock`s (and
/// the shading pipelines) are made when a frame first uses them: each is a
/// shader compilation in the driver, and most frames use few of them.
#[derive(Debug)]
pub struct ForwardRenderer {
    layout: wgpu::BindGroupLayout,
    params_layout: wgpu::BindGroupLayout,
    depth_pipeline: wgpu::RenderPipeline,
    /// The prepass of scenes with culled back faces, without AO (the AO
    /// prepass discards them itself).
    depth_discarding_pipeline: OnceLock<wgpu::RenderPipeline>,
    /// Emission and ambient light (the first pass of stencil shadows).
    base_pipeline: OnceLock<wgpu::RenderPipeline>,
    /// Draws the environment map where no geometry is.
    background_pipeline: OnceLock<wgpu::RenderPipeline>,
    shadow_pipeline: OnceLock<wgpu::RenderPipeline>,
    /// Shadow maps of scenes with alpha masks.
    masked_shadow_pipeline: OnceLock<wgpu::RenderPipeline>,
    /// The forward module and layouts, for the pipelines made on first use.
    module: wgpu::ShaderModule,
    pipeline_layout: wgpu::PipelineLayout,
    shadow_pipeline_layout: wgpu::PipelineLayout,
    light_stencil: wgpu::StencilState,
    /// The shading pipelines by key.
    shading: Mutex<HashMap<ShadingKey, Arc<ShadingPipelines>>>,
    /// Group 2: the baked maps.
    bake_layout: wgpu::BindGroupLayout,
    /// Writes the looked-up bake values (`ao`, `irradiance`) as AOVs.
    bake_aov_pipeline: OnceLock<wgpu::RenderPipeline>,
    shadow_layout: wgpu::BindGroupLayout,
    shadow_sampler: wgpu::Sampler,
    culling: LightCulling,
    volumes: Option<ShadowVolumes>,
    planar: Option<PlanarShadows>,
    depth_format: wgpu::TextureFormat,
    /// The metallic–roughness model's Kulla–Conty table (a constant).
    kulla_conty: wgpu::Buffer,
    /// Screen-space AO (with [`RasterOptions::ao`]).
    ao: Option<ScreenSpaceAo>,
    /// Bound instead of the AO term in frames without screen-space AO.
    no_ao: wgpu::TextureView,
    /// The environment light: prefilter pipeline, sampler, last environment.
    environment: EnvironmentPass,
    options: RasterOptions,
}

/// What the passes of one frame share.
struct Frame<'a> {
    gpu: &'a SceneGpu,
    bind_group: &'a wgpu::BindGroup,
    bakes: &'a wgpu::BindGroup,
    params: &'a PassParams,
    targets: &'a Targets,
    timer: &'a GpuTimer,
}

impl Frame<'_> {
    /// A shading pass named `name` over the frame's targets: colour loaded
    /// as `load` (resolved when `resolve`), depth (and the stencil, when
    /// `stencil`) loaded; `pipeline` set with the frame's three bind groups,
    /// the pass parameters at `params_offset`.
    #[allow(clippy::too_many_arguments)]
    fn shading_pass<'e>(
        &self,
        encoder: &'e mut wgpu::CommandEncoder,
        name: &str,
        load: wgpu::LoadOp<wgpu::Color>,
        resolve: bool,
        stencil: bool,
        pipeline: &wgpu::RenderPipeline,
        params_offset: u32,
    ) -> wgpu::RenderPass<'e> {
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some(name),
            color_attachments: &[Some(self.targets.colour(load, resolve))],
            depth_stencil_attachment: Some(self.targets.depth_loaded(stencil)),
            timestamp_writes: self.timer.render_pass(name),
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_pipeline(pipeline);
        pass.set_bind_group(0, self.bind_group, &[]);
        pass.set_bind_group(1, &self.params.bind_group, &[params_offset]);
        pass.set_bind_group(BAKE_GROUP, self.bakes, &[]);
        pass
    }
}

/// The frame's render targets.
struct Targets {
    resolved: wgpu::Texture,
    resolved_view: wgpu::TextureView,
    multisampled_view: Option<wgpu::TextureView>,
    depth_view: wgpu::TextureView,
    /// With screen-space AO: the prepass's world normals and view distances.
    normal_view: Option<wgpu::TextureView>,
}

impl Targets {
    /// The colour attachment: the multisampled target (resolved into the
    /// single-sample one when `resolve`), or the single-sample target.
    fn colour(
        &self,
        load: wgpu::LoadOp<wgpu::Color>,
        resolve: bool,
    ) -> wgpu::RenderPassColorAttachment<'_> {
        let (view, resolve_target) = match &self.multisampled_view {
            Some(ms) => (ms, resolve.then_some(&self.resolved_view)),
            None => (&self.resolved_view, None),
        };
        wgpu::RenderPassColorAttachment {
            view,
            depth_slice: None,
            resolve_target,
            ops: wgpu::Operations {
                load,
                store: wgpu::StoreOp::Store,
            },
        }
    }

    /// The depth(-stencil) attachment, depth loaded (read by the shading
    /// passes), stencil loaded when the format has one.
    fn depth_loaded(&self, stencil: bool) -> wgpu::RenderPassDepthStencilAttachment<'_> {
        wgpu::RenderPassDepthStencilAttachment {
            view: &self.depth_view,
            depth_ops: Some(wgpu::Operations {
                load: wgpu::LoadOp::Load,
                store: wgpu::StoreOp::Store,
            }),
            stencil_ops: stencil.then_some(wgpu::Operations {
                load: wgpu::LoadOp::Load,
                store: wgpu::StoreOp::Store,
            }),
        }
    }
}

fn check_msaa(ctx: &GpuContext, msaa: u32) -> Result<(), GpuError> {
    if msaa != 1 && msaa != 4 {
        return Err(GpuError::Unsupported(format!("MSAA {msaa}: use 1 or 4")));
    }
    if msaa > 1 {
        let f = ctx.adapter.get_texture_format_features(COLOR_FORMAT);
        let ok = ctx
            .device
            .features()
            .contains(wgpu::Features::TEXTURE_ADAPTER_SPECIFIC_FORMAT_FEATURES)
            && f.flags.sample_count_supported(msaa)
            && f.flags
                .contains(wgpu::TextureFormatFeatureFlags::MULTISAMPLE_RESOLVE);
        if !ok {
            return Err(GpuError::Unsupported(format!(
                "adapter '{}' cannot resolve {msaa}x multisampled {COLOR_FORMAT:?} targets; use --msaa 1",
                ctx.summary.name
            )));
        }
    }
    Ok(())
}

impl ForwardRenderer {
    pub fn new(ctx: &GpuContext, options: RasterOptions) -> Result<Self, GpuError> {
        let msaa = options.msaa;
        check_msaa(ctx, msaa)?;
        let size = options.shadow_map_size;
        let max_dim = ctx.device.limits().max_texture_dimension_2d;
        if options.shadows == ShadowMode::Map && (size < 16 || size > max_dim) {
            return Err(GpuError::Unsupported(format!(
                "shadow map size {size} (the adapter allows 16 to {max_dim})"
            )));
        }
        if options.environment_taps > MAX_ENVIRONMENT_TAPS {
            return Err(GpuError::Unsupported(format!(
                "{} environment taps: use 0 to {MAX_ENVIRONMENT_TAPS}",
                options.environment_taps
            )));
        }
        if options.pcf == 0 || options.pcf > MAX_PCF {
            return Err(GpuError::Unsupported(format!(
                "PCF kernel {}: use 1 to {MAX_PCF}",
                options.pcf
            )));
        }
        let device = &ctx.device;
        let depth_format = if !options.shadows.uses_stencil() {
            wgpu::TextureFormat::Depth32Float
        } else if device
            .features()
            .contains(wgpu::Features::DEPTH32FLOAT_STENCIL8)
        {
            wgpu::TextureFormat::Depth32FloatStencil8
        } else {
            wgpu::TextureFormat::Depth24PlusStencil8
        };
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("penumbra forward"),
            source: wgpu::ShaderSource::Wgsl(forward_source().into()),
        });
        let vf = wgpu::ShaderStages::VERTEX_FRAGMENT;
        let fragment = wgpu::ShaderStages::FRAGMENT;
        let env = environment_entries();
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("penumbra forward"),
            entries: &[
                uniform_entry(0, vf),
                storage_entry(1, vf, true),
                storage_entry(2, fragment, true),
                storage_entry(3, fragment, true),
                storage_entry(4, fragment, true),
                storage_entry(5, fragment, true),
                wgpu::BindGroupLayoutEntry {
                    binding: 6,
                    visibility: fragment,
                    ty: wgpu::BindingType::Texture {
                        sample_type: wgpu::TextureSampleType::Depth,
                        view_dimension: wgpu::TextureViewDimension::D2Array,
                        multisampled: false,
                    },
                    count: None,
                },
                wgpu::BindGroupLayoutEntry {
                    binding: 7,
                    visibility: fragment,
                    ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Comparison),
                    count: None,
                },
                storage_entry(KULLA_CONTY_BINDING, fragment, true),
                storage_entry(10, fragment, true),
                uniform_entry(11, fragment),
                storage_entry(25, wgpu::ShaderStages::VERTEX, true),
                storage_entry(26, wgpu::ShaderStages::VERTEX, true),
                storage_entry(27, fragment, true),
                storage_entry(28, fragment, true),
                storage_entry(29, fragment, true),
                storage_entry(30, wgpu::ShaderStages::VERTEX, true),
                env[0],
                env[1],
                env[2],
                env[3],
                wgpu::BindGroupLayoutEntry {
                    binding: SCREEN_AO_BINDING,
                    visibility: fragment,
                    ty: wgpu::BindingType::Texture {
                        sample_type: wgpu::TextureSampleType::Float { filterable: false },
                        view_dimension: wgpu::TextureViewDimension::D2,
                        multisampled: false,
                    },
                    count: None,
                },
            ],
        });
        let params_layout = params_layout(device);
        let shadow_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("penumbra shadow"),
            entries: &[
                storage_entry(1, vf, true),
                storage_entry(5, wgpu::ShaderStages::VERTEX, true),
                // Alpha masks (vs_shadow_masked / fs_shadow_masked): the
                // materials, texture coordinates and textures.
                storage_entry(2, fragment, true),
                storage_entry(25, wgpu::ShaderStages::VERTEX, true),
                storage_entry(27, fragment, true),
                storage_entry(28, fragment, true),
                storage_entry(29, fragment, true),
            ],
        });
        let shadow_pipeline_layout =
            device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some("penumbra shadow"),
                bind_group_layouts: &[Some(&shadow_layout)],
                immediate_size: 0,
            });
        let bake_layout = bake_layout(device);
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("penumbra forward"),
            bind_group_layouts: &[Some(&layout), Some(&params_layout), Some(&bake_layout)],
            immediate_size: 0,
        });
        let ao_on = options.ao.enabled();
        // The prepass (every frame runs it): depth written, nearer
        // (reversed depth) wins; with screen-space AO it also writes the
        // normal target (the same @invariant clip positions as vs_depth).
        let with_normals = [Some(vec3_buffer(0)), Some(vec3_buffer(1))];
        let (vs, fs, buffers) = if ao_on {
            ("vs_main", Some("fs_ao_prepass"), &with_normals[..])
        } else {
            ("vs_depth", None, &with_normals[..1])
        };
        let spec = prepass_spec("depth prepass", vs, fs, buffers, true, depth_format, msaa);
        let depth_pipeline = build_pipeline(device, &module, &pipeline_layout, spec);
        // One light, added where the stencil is 0 (shadow volumes: count 0;
        // planar shadows: top bit clear).
        let read_mask = if options.shadows == ShadowMode::Planar {
            0x80
        } else {
            0xff
        };
        let lit_where_zero = wgpu::StencilFaceState {
            compare: wgpu::CompareFunction::Equal,
            fail_op: wgpu::StencilOperation::Keep,
            depth_fail_op: wgpu::StencilOperation::Keep,
            pass_op: wgpu::StencilOperation::Keep,
        };
        let light_stencil = if options.shadows.uses_stencil() {
            wgpu::StencilState {
                front: lit_where_zero,
                back: lit_where_zero,
                read_mask,
                write_mask: 0,
            }
        } else {
            Default::default()
        };
        let filter = if options.pcf == 1 {
            wgpu::FilterMode::Nearest
        } else {
            wgpu::FilterMode::Linear
        };
        let shadow_sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("shadow compare"),
            mag_filter: filter,
            min_filter: filter,
            compare: Some(wgpu::CompareFunction::GreaterEqual),
            ..Default::default()
        });
        let volumes = (options.shadows == ShadowMode::Volume)
            .then(|| ShadowVolumes::new(device, &params_layout, depth_format, msaa));
        let planar = (options.shadows == ShadowMode::Planar)
            .then(|| PlanarShadows::new(device, &params_layout, depth_format, msaa));
        Ok(Self {
            layout,
            params_layout,
            depth_pipeline,
            depth_discarding_pipeline: OnceLock::new(),
            base_pipeline: OnceLock::new(),
            background_pipeline: OnceLock::new(),
            shadow_pipeline: OnceLock::new(),
            masked_shadow_pipeline: OnceLock::new(),
            module,
            pipeline_layout,
            shadow_pipeline_layout,
            light_stencil,
            shading: Mutex::new(HashMap::new()),
            bake_layout,
            bake_aov_pipeline: OnceLock::new(),
            shadow_layout,
            shadow_sampler,
            culling: LightCulling::new(msaa),
            volumes,
            planar,
            depth_format,
            kulla_conty: buffer_init(
                device,
                "kulla-conty table",
                bytemuck::cast_slice(&kulla_conty_table()),
                wgpu::BufferUsages::STORAGE,
            ),
            ao: ao_on.then(|| ScreenSpaceAo::new(device, options.ao, msaa)),
            no_ao: unit_ao(device),
            environment: EnvironmentPass::new(device),
            options,
        })
    }

    /// The shadow-map pipeline (with a fragment stage that discards the
    /// masked-out fragments where `masked`, so alpha masks cast the shadows
    /// they cut out): depth only, no culling (open meshes and single quads
    /// cast too); reversed depth, so the bias is negative: it moves the
    /// stored depth away from the light by `slope_bias` times the
    /// triangle's depth slope, plus a few units of the format's precision.
    fn shadow_map_pipeline(&self, device: &wgpu::Device, masked: bool) -> &wgpu::RenderPipeline {
        let (cell, label, vs, fs) = if masked {
            let fs = Some("fs_shadow_masked");
            let label = "shadow map (alpha masks)";
            (&self.masked_shadow_pipeline, label, "vs_shadow_masked", fs)
        } else {
            (&self.shadow_pipeline, "shadow map", "vs_shadow", None)
        };
        cell.get_or_init(|| {
            let spec = PipelineSpec {
                label,
                vs,
                fs,
                buffers: &[Some(vec3_buffer(0))],
                depth: wgpu::DepthStencilState {
                    bias: wgpu::DepthBiasState {
                        constant: -SHADOW_CONSTANT_BIAS,
                        slope_scale: -self.options.slope_bias,
                        clamp: 0.0,
                    },
                    ..depth_state(
                        true,
                        wgpu::CompareFunction::Greater,
                        Default::default(),
                        SHADOW_MAP_FORMAT,
                    )
                },
                blend: None,
                samples: 1,
                constants: &[],
                color: false,
            };
            build_pipeline(device, &self.module, &self.shadow_pipeline_layout, spec)
        })
    }

    /// The prepass of the frame: the one that discards culled back faces
    /// and alpha masks where the scene has them (`culls`) and screen-space
    /// AO is off (its prepass always checks), else the plain one.
    fn prepass_pipeline(&self, device: &wgpu::Device, culls: bool) -> &wgpu::RenderPipeline {
        if !culls || self.ao.is_some() {
            return &self.depth_pipeline;
        }
        self.depth_discarding_pipeline.get_or_init(|| {
            let position_only = [Some(vec3_buffer(0))];
            let spec = prepass_spec(
                "depth prepass (culled back faces, alpha masks)",
                "vs_depth_discarding",
                Some("fs_depth_discarding"),
                &position_only,
                false,
                self.depth_format,
                self.options.msaa,
            );
            build_pipeline(device, &self.module, &self.pipeline_layout, spec)
        })
    }

    /// Emission and ambient light only: no material model needed.
    fn base_pipeline(&self, device: &wgpu::Device) -> &wgpu::RenderPipeline {
        self.base_pipeline.get_or_init(|| {
            let spec = PipelineSpec {
                label: "base",
                vs: "vs_main",
                fs: Some("fs_base"),
                buffers: &[Some(vec3_buffer(0)), Some(vec3_buffer(1))],
                depth: self.shading_depth(wgpu::CompareFunction::GreaterEqual, Default::default()),
                blend: None,
                samples: self.options.msaa,
                constants: &[
                    ("MATERIAL_MODELS", 0.0),
                    ("SHADOW_MAPS", 0.0),
                    ("SCREEN_AO", self.ao.is_some() as u32 as f64),
                    ("ENV_LOBE_TAPS", self.options.environment_taps as f64),
                ],
                color: true,
            };
            build_pipeline(device, &self.module, &self.pipeline_layout, spec)
        })
    }

    /// The environment map where the prepass left the far plane (0).
    fn background_pipeline(&self, device: &wgpu::Device) -> &wgpu::RenderPipeline {
        self.background_pipeline.get_or_init(|| {
            let spec = PipelineSpec {
                label: "background",
                vs: "vs_background",
                fs: Some("fs_background"),
                buffers: &[],
                depth: self.shading_depth(wgpu::CompareFunction::Equal, Default::default()),
                blend: None,
                samples: self.options.msaa,
                constants: &[("MATERIAL_MODELS", 0.0), ("SHADOW_MAPS", 0.0)],
                color: true,
            };
            build_pipeline(device, &self.module, &self.pipeline_layout, spec)
        })
    }

    fn bake_aov_pipeline(&self, device: &wgpu::Device) -> &wgpu::RenderPipeline {
        self.bake_aov_pipeline.get_or_init(|| {
            let depth = self.shading_depth(wgpu::CompareFunction::GreaterEqual, Default::default());
            bake_aov_pipeline(
                device,
                &self.module,
                &self.pipeline_layout,
                depth,
                self.options.msaa,
            )
        })
    }

    /// The depth state of the passes after the prepass: depth tested with
    /// `compare`, not written.
    fn shading_depth(
        &self,
        compare: wgpu::CompareFunction,
        stencil: wgpu::StencilState,
    ) -> wgpu::DepthStencilState {
        depth_state(false, compare, stencil, self.depth_format)
    }

    /// The shading pipelines of `key` (their constants; each pipeline is
    /// made on first use), one set per key.
    fn shading_pipelines(&self, key: ShadingKey) -> Arc<ShadingPipelines> {
        let mut cache = self.shading.lock().unwrap_or_else(|e| e.into_inner());
        cache
            .entry(key)
            .or_insert_with(|| {
                let shadow_maps = if self.options.shadows == ShadowMode::Map {
                    1.0
                } else {
                    0.0
                };
                let mut constants = vec![
                    ("MATERIAL_MODELS", key.models as f64),
                    ("SHADOW_MAPS", shadow_maps),
                    ("BAKED_MAPS", key.baked as u32 as f64),
                    ("SCREEN_AO", self.ao.is_some() as u32 as f64),
                    ("ENV_LOBE_TAPS", self.options.environment_taps as f64),
                ];
                constants.extend(key.textures.constants());
                Arc::new(ShadingPipelines {
                    constants,
                    pipelines: Default::default(),
                })
            })
            .clone()
    }

    /// The pipeline of `pass` in `shading`, made on first use.
    fn shading_pipeline<'s>(
        &self,
        device: &wgpu::Device,
        shading: &'s ShadingPipelines,
        pass: ShadingPass,
    ) -> &'s wgpu::RenderPipeline {
        shading.pipelines[pass as usize].get_or_init(|| {
            let add = wgpu::BlendComponent {
                src_factor: wgpu::BlendFactor::One,
                dst_factor: wgpu::BlendFactor::One,
                operation: wgpu::BlendOperation::Add,
            };
            let (label, fs, stencil, blend) = match pass {
                ShadingPass::Forward => ("forward", "fs_forward", Default::default(), None),
                ShadingPass::Blend => (
                    "blend",
                    "fs_blend",
                    Default::default(),
                    Some(wgpu::BlendState::ALPHA_BLENDING),
                ),
                ShadingPass::Light => (
                    "light",
                    "fs_light",
                    self.light_stencil.clone(),
                    Some(wgpu::BlendState {
                        color: add,
                        alpha: add,
                    }),
                ),
            };
            let spec = PipelineSpec {
                label,
                vs: "vs_main",
                fs: Some(fs),
                buffers: &[Some(vec3_buffer(0)), Some(vec3_buffer(1))],
                depth: self.shading_depth(wgpu::CompareFunction::GreaterEqual, stencil),
                blend,
                samples: self.options.msaa,
                constants: &shading.constants,
                color: true,
            };
            build_pipeline(device, &self.module, &self.pipeline_layout, spec)
        })
    }

    /// Stencil shadows: the base pass (emission, ambient), then per light
    /// its stencil pass and its additive pass where the stencil says lit;
    /// the last colour pass resolves the multisampled target.
    #[allow(clippy::too_many_arguments)]
    fn record_stencil_lighting(
        &self,
        device: &wgpu::Device,
        encoder: &mut wgpu::CommandEncoder,
        f: &Frame<'_>,
        shading: &ShadingPipelines,
        clear: wgpu::LoadOp<wgpu::Color>,
        per_light: usize,
        volume_frame: Option<&VolumeFrame>,
        planar_frame: Option<&PlanarFrame>,
    ) {
        let (gpu, params, targets, timer) = (f.gpu, f.params, f.targets, f.timer);
        let light_count = gpu.light_count();
        {
            let mut pass = f.shading_pass(
                encoder,
                "base",
                clear,
                light_count == 0,
                true,
                self.base_pipeline(device),
                0,
            );
            gpu.draw_all(&mut pass, true, 0);
        }
        for light in 0..light_count {
            let slot = light as usize * per_light;
            let offset = PassParams::offset(slot);
            if let (Some(v), Some(frame)) = (&self.volumes, volume_frame) {
                v.record(
                    encoder,
                    frame,
                    &params.bind_group,
                    offset,
                    light,
                    &targets.depth_view,
                    timer,
                );
            }
            if let (Some(p), Some(frame)) = (&self.planar, planar_frame) {
                p.record(
                    encoder,
                    frame,
                    gpu,
                    &params.bind_group,
                    slot,
                    light,
                    &targets.depth_view,
                    timer,
                );
            }
            let last = light + 1 == light_count;
            let mut pass = f.shading_pass(
                encoder,
                &format!("light {light}"),
                wgpu::LoadOp::Load,
                last,
                true,
                self.shading_pipeline(device, shading, ShadingPass::Light),
                offset,
            );
            pass.set_stencil_reference(0);
            gpu.draw_all(&mut pass, true, 0);
        }
    }

    fn targets(&self, device: &wgpu::Device, width: u32, height: u32) -> Targets {
        let size = wgpu::Extent3d {
            width,
            height,
            depth_or_array_layers: 1,
        };
        let target = |label: &str, format, samples, usage| {
            device.create_texture(&wgpu::TextureDescriptor {
                label: Some(label),
                size,
                mip_level_count: 1,
                sample_count: samples,
                dimension: wgpu::TextureDimension::D2,
                format,
                usage,
                view_formats: &[],
            })
        };
        let attach = wgpu::TextureUsages::RENDER_ATTACHMENT;
        let msaa = self.options.msaa;
        let resolved = target(
            "colour",
            COLOR_FORMAT,
            1,
            attach | wgpu::TextureUsages::COPY_SRC,
        );
        let multisampled = (msaa > 1).then(|| target("colour msaa", COLOR_FORMAT, msaa, attach));
        let depth = target(
            "depth",
            self.depth_format,
            msaa,
            attach | wgpu::TextureUsages::TEXTURE_BINDING,
        );
        let normals = self.ao.is_some().then(|| {
            target(
                "ao normals",
                NORMAL_TARGET_FORMAT,
                msaa,
                attach | wgpu::TextureUsages::TEXTURE_BINDING,
            )
        });
        Targets {
            normal_view: normals.map(|t| t.create_view(&Default::default())),
            resolved_view: resolved.create_view(&Default::default()),
            multisampled_view: multisampled
                .as_ref()
                .map(|t| t.create_view(&Default::default())),
            depth_view: depth.create_view(&Default::default()),
            resolved,
        }
    }

    /// Renders `scene` through `camera` at `width`×`height`.
    pub fn render(
        &self,
        ctx: &GpuContext,
        scene: &Scene,
        camera: &Camera,
        width: u32,
        height: u32,
    ) -> Result<RasterOutput, GpuError> {
        self.render_baked(
            ctx,
            scene,
            camera,
            width,
            height,
            &BakedMaps::default(),
            false,
        )
    }

    /// Renders `scene` with baked maps (made for this scene: see
    /// [`penumbra_bake::read_bake`]); with `aovs` also returns the looked-up
    /// values ([`RasterOutput::aovs`]).
    #[allow(clippy::too_many_arguments)]
    pub fn render_baked(
        &self,
        ctx: &GpuContext,
        scene: &Scene,
        camera: &Camera,
        width: u32,
        height: u32,
        bakes: &BakedMaps<'_>,
        aovs: bool,
    ) -> Result<RasterOutput, GpuError> {
        let start = Instant::now();
        let device = &ctx.device;
        let max_dim = device.limits().max_texture_dimension_2d;
        if width == 0 || height == 0 || width > max_dim || height > max_dim {
            return Err(GpuError::Unsupported(format!(
                "resolution {width}x{height} (the adapter allows 1 to {max_dim} per edge)"
            )));
        }
        let o = self.options;
        if bakes.has_full_irradiance() && o.shadows != ShadowMode::None {
            return Err(GpuError::Unsupported(
                "a full light map already holds the direct light and its shadows; bake it with --indirect-only to add real-time lights and shadows".into(),
            ));
        }
        if aovs && bakes.is_empty() && self.ao.is_none() {
            return Err(GpuError::Unsupported(
                "the raster engine's AOVs are the ambient-occlusion term (give --ssao hemisphere|gtao) and the looked-up bake values (ao, irradiance: give --bake)".into(),
            ));
        }
        if bakes.ao.is_some() && self.ao.is_some() {
            return Err(GpuError::Unsupported(
                "an ambient-occlusion bake and screen-space AO would both darken the ambient light (kA twice): use one".into(),
            ));
        }
        let baked = !bakes.is_empty();
        let gpu = SceneGpu::upload(device, scene, camera, width, height, baked);
        let shading = self.shading_pipelines(ShadingKey {
            models: gpu.data.model_mask(),
            textures: gpu.texture_features,
            baked,
        });
        let mut warnings = gpu.data.warnings.clone();
        warnings.extend(bake_warnings(scene, bakes));
        let lightmaps = LightmapFrame::new(ctx, &self.bake_layout, bakes, scene, &gpu.data)?;
        let light_count = gpu.light_count();
        let shadow_maps = ShadowMapFrame::new(
            device,
            o.shadows == ShadowMode::Map,
            &gpu.data.lights,
            gpu.bounds,
            o.shadow_map_size,
            o.pcf,
            o.normal_offset,
        )?;
        let (view, proj) = view_and_projection(camera, width, height, gpu.bounds);
        let culled = !o.shadows.uses_stencil() && o.light_culling;
        let culling = LightCulling::frame(
            device,
            culled,
            o.culling_stats,
            view,
            proj,
            &gpu.data.lights,
            width,
            height,
            o.msaa,
        );
        if culled && culling.uniform.enabled == 0 && light_count > 0 {
            warnings.push(format!(
                "raster: {light_count} lights: more than the {MAX_CULLED_LIGHTS} light culling handles; every pixel shades every light"
            ));
        }
        let screen_ao = self
            .ao
            .is_some()
            .then(|| AoTextures::new(device, width, height));
        let screen_ao_view = screen_ao
            .as_ref()
            .map(|t| t.ao.create_view(&Default::default()));
        let environment = self.environment.prepare(ctx, &scene.environment());
        let [env20, env21, env22] = environment.entries(&self.environment.sampler);
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("penumbra forward"),
            layout: &self.layout,
            entries: &[
                whole(0, &gpu.camera),
                whole(1, &gpu.instances),
                whole(2, &gpu.materials),
                whole(3, &gpu.lights),
                whole(4, &shadow_maps.shadows),
                whole(5, &shadow_maps.views),
                wgpu::BindGroupEntry {
                    binding: 6,
                    resource: wgpu::BindingResource::TextureView(&shadow_maps.array_view),
                },
                wgpu::BindGroupEntry {
                    binding: 7,
                    resource: wgpu::BindingResource::Sampler(&self.shadow_sampler),
                },
                whole(KULLA_CONTY_BINDING, &self.kulla_conty),
                whole(10, &culling.tile_lights),
                whole(11, &culling.uniform_buffer),
                env20,
                env21,
                env22,
                whole(ENVIRONMENT_MATERIALS_BINDING, &gpu.env_materials),
                whole(25, &gpu.vertex_uvs),
                whole(26, &gpu.vertex_colors),
                whole(27, &gpu.textures),
                whole(28, &gpu.texels),
                whole(29, &gpu.material_textures),
                whole(30, &gpu.vertex_tangents),
                wgpu::BindGroupEntry {
                    binding: SCREEN_AO_BINDING,
                    resource: wgpu::BindingResource::TextureView(
                        screen_ao_view.as_ref().unwrap_or(&self.no_ao),
                    ),
                },
            ],
        });
        let masks = scene.materials.iter().any(|m| m.is_masked());
        let shadow_bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("penumbra shadow"),
            layout: &self.shadow_layout,
            entries: &[
                whole(1, &gpu.instances),
                whole(5, &shadow_maps.views),
                whole(2, &gpu.materials),
                whole(25, &gpu.vertex_uvs),
                whole(27, &gpu.textures),
                whole(28, &gpu.texels),
                whole(29, &gpu.material_textures),
            ],
        });

        // Stencil shadows: the receivers or volumes, and a parameter slot
        // per (light, receiver) or per light.
        let planar_frame = self.planar.as_ref().map(|p| {
            let (receivers, w) = planar_receivers(scene, gpu.bounds);
            warnings.extend(w);
            p.frame(device, &gpu, receivers)
        });
        let volume_frame = match &self.volumes {
            Some(v) => Some(v.frame(device, scene, &gpu)?),
            None => None,
        };
        let per_light = planar_frame
            .as_ref()
            .map_or(1, |f| f.receivers.len().max(1));
        let slots: Vec<GpuPassParams> = (0..light_count as usize * per_light)
            .map(|i| GpuPassParams {
                light: (i / per_light) as u32,
                receiver: (i % per_light) as u32,
                ..Default::default()
            })
            .collect();
        let params = PassParams::new(device, &self.params_layout, &slots);

        let targets = self.targets(device, width, height);
        let stencil_passes = if o.shadows == ShadowMode::Volume {
            3
        } else {
            2
        };
        let ao_passes = if self.ao.is_some() { 8 } else { 0 };
        let timer = GpuTimer::new(
            ctx,
            shadow_maps.layers + 8 + ao_passes + stencil_passes * light_count,
        );
        let draw_background = environment.is_map();
        environment.write_view(ctx, (proj * view).inverse(), draw_background);

        let readback = TextureReadback::new(device, width, height, 16);

        let bg = scene.background;
        let clear = wgpu::LoadOp::Clear(wgpu::Color {
            r: bg.x as f64,
            g: bg.y as f64,
            b: bg.z as f64,
            a: 0.0,
        });
        let has_stencil = o.shadows.uses_stencil();
        let mut encoder = device.create_command_encoder(&Default::default());
        self.environment
            .record_prefilter(device, &environment, &mut encoder, &timer);
        shadow_maps.record(
            &mut encoder,
            || self.shadow_map_pipeline(device, masks),
            &shadow_bind_group,
            &gpu,
            &timer,
        );
        {
            let normal_attachment = targets.normal_view.as_ref().map(|view| {
                Some(wgpu::RenderPassColorAttachment {
                    view,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                        store: wgpu::StoreOp::Store,
                    },
                })
            });
            // No slot at all without screen-space AO (the plain prepass
            // pipeline has no colour target).
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("depth prepass"),
                color_attachments: normal_attachment.as_slice(),
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: &targets.depth_view,
                    depth_ops: Some(wgpu::Operations {
                        load: wgpu::LoadOp::Clear(0.0),
                        store: wgpu::StoreOp::Store,
                    }),
                    stencil_ops: has_stencil.then_some(wgpu::Operations {
                        load: wgpu::LoadOp::Clear(0),
                        store: wgpu::StoreOp::Store,
                    }),
                }),
                timestamp_writes: timer.render_pass("depth prepass"),
                occlusion_query_set: None,
                multiview_mask: None,
            });
            let culls = scene.materials.iter().any(|m| m.cull_back_faces) || masks;
            pass.set_pipeline(self.prepass_pipeline(device, culls));
            pass.set_bind_group(0, &bind_group, &[]);
            pass.set_bind_group(1, &params.bind_group, &[0]);
            pass.set_bind_group(BAKE_GROUP, &lightmaps.bind_group, &[]);
            gpu.draw_all(&mut pass, self.ao.is_some(), 0);
        }
        if let (Some(ao), Some(normals), Some(textures)) =
            (&self.ao, &targets.normal_view, &screen_ao)
        {
            let radius = ao.settings().radius_for(gpu.bounds);
            let ortho = matches!(
                camera.projection,
                penumbra_scene::camera::Projection::Orthographic { .. }
            );
            let params = ao.params(view, proj, ortho, (width, height), radius);
            ao.record(device, &mut encoder, normals, &params, textures, &timer);
        }
        let frame = Frame {
            gpu: &gpu,
            bind_group: &bind_group,
            bakes: &lightmaps.bind_group,
            params: &params,
            targets: &targets,
            timer: &timer,
        };
        if !has_stencil {
            self.culling
                .record(device, &mut encoder, &culling, &targets.depth_view, &timer);
            let mut pass = frame.shading_pass(
                &mut encoder,
                "forward",
                clear,
                true,
                false,
                self.shading_pipeline(device, &shading, ShadingPass::Forward),
                0,
            );
            gpu.draw_all(&mut pass, true, 0);
        } else {
            self.record_stencil_lighting(
                device,
                &mut encoder,
                &frame,
                &shading,
                clear,
                per_light,
                volume_frame.as_ref(),
                planar_frame.as_ref(),
            );
        }
        let over = wgpu::LoadOp::Load;
        if draw_background {
            let background = self.background_pipeline(device);
            let mut pass = frame.shading_pass(
                &mut encoder,
                "background",
                over,
                true,
                has_stencil,
                background,
                0,
            );
            pass.draw(0..3, 0..1);
        }
        if !gpu.blended.is_empty() {
            let mut pass = frame.shading_pass(
                &mut encoder,
                "blend",
                over,
                true,
                has_stencil,
                self.shading_pipeline(device, &shading, ShadingPass::Blend),
                0,
            );
            gpu.draw_blended(&mut pass);
        }
        let aov_targets = (aovs && !bakes.is_empty()).then(|| {
            let t = BakeAovTargets::new(device, width, height, o.msaa);
            t.record(
                &mut encoder,
                self.bake_aov_pipeline(device),
                &gpu,
                [&bind_group, &params.bind_group, &lightmaps.bind_group],
                &targets,
                &timer,
            );
            t
        });
        let ao_readback = screen_ao
            .as_ref()
            .filter(|_| aovs)
            .map(|t| t.record_readback(device, &mut encoder));
        timer.resolve(&mut encoder);
        LightCulling::record_stats_copy(&mut encoder, &culling);
        readback.record(&mut encoder, &targets.resolved, 0);
        let frame_start = Instant::now();
        ctx.queue.submit([encoder.finish()]);
        ctx.wait_idle()?;
        let frame_ms = frame_start.elapsed().as_secs_f64() * 1e3;

        let rgba = readback.read_f32(ctx)?;
        let surface = rgba.chunks_exact(4).map(|p| p[3] > 0.5).collect();
        let image = Image::from_pixels(
            width,
            height,
            rgba.chunks_exact(4)
                .map(|p| Vec3::new(p[0], p[1], p[2]))
                .collect(),
        )
        .map_err(|e| GpuError::Wgpu(e.to_string()))?;
        let mut aovs = match &aov_targets {
            Some(t) => t.read(ctx)?,
            None => Vec::new(),
        };
        if let Some(r) = &ao_readback {
            aovs.retain(|(name, _)| name != "ao");
            aovs.insert(0, ("ao".to_string(), image_of(r, ctx, (width, height), 1)?));
        }
        let passes = timer.read(ctx)?;
        let culling_stats = LightCulling::stats(ctx, &culling)?;
        Ok(RasterOutput {
            image,
            total_ms: start.elapsed().as_secs_f64() * 1e3,
            frame_ms,
            passes,
            surface,
            warnings,
            culling: culling_stats,
            aovs,
        })
    }
}

/// Group-0 binding of the screen-space AO texture in the geometry passes.
pub const SCREEN_AO_BINDING: u32 = 24;

/// A float readback of `channels` per texel (1: grey; 4: RGBA, alpha
/// dropped) as an image.
fn image_of(
    r: &TextureReadback,
    ctx: &GpuContext,
    (width, height): (u32, u32),
    channels: usize,
) -> Result<Image, GpuError> {
    let pixels = r
        .read_f32(ctx)?
        .chunks_exact(channels)
        .map(|p| match p {
            [v] => Vec3::splat(*v),
            _ => Vec3::new(p[0], p[1], p[2]),
        })
        .collect();
    Image::from_pixels(width, height, pixels).map_err(|e| GpuError::Wgpu(e.to_string()))
}

/// The 1×1 `R32Float` texture bound at [`SCREEN_AO_BINDING`] in frames
/// without screen-space AO; never read (their pipelines have `SCREEN_AO`
/// false, so kA = 1).
fn unit_ao(device: &wgpu::Device) -> wgpu::TextureView {
    device
        .create_texture(&wgpu::TextureDescriptor {
            label: Some("no screen-space ao"),
            size: wgpu::Extent3d::default(),
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: wgpu::TextureFormat::R32Float,
            usage: wgpu::TextureUsages::TEXTURE_BINDING,
            view_formats: &[],
        })
        .create_view(&Default::default())
}

/// What the raster path approximates when it shows `bakes`.
fn bake_warnings(scene: &Scene, bakes: &BakedMaps<'_>) -> Vec<String> {
    let mut out = Vec::new();
    if bakes.irradiance.is_some()
        && scene
            .materials
            .iter()
            .any(|m| !matches!(m.bsdf, penumbra_shading::bsdf::Bsdf::Lambert(_)))
    {
        out.push(
            "raster: a light map gives diffuse light (c_diff · E / π); the glossy and specular lobes of non-Lambert materials get none of its light".to_string(),
        );
    }
    if bakes.irradiance.is_some_and(|b| b.kind.indirect_only())
        && scene.materials.iter().any(|m| m.is_emissive())
    {
        out.push(
            "raster: with an indirect-only light map the direct light comes from the real-time lights, and emissive surfaces light nothing in real time: their direct light is missing".to_string(),
        );
    }
    out
}

/// A prepass pipeline: depth written, nearer (reversed depth) wins.
fn prepass_spec<'a>(
    label: &'a str,
    vs: &'a str,
    fs: Option<&'a str>,
    buffers: &'a [Option<wgpu::VertexBufferLayout<'a>>],
    color: bool,
    depth_format: wgpu::TextureFormat,
    samples: u32,
) -> PipelineSpec<'a> {
    PipelineSpec {
        label,
        vs,
        fs,
        buffers,
        depth: depth_state(
            true,
            wgpu::CompareFunction::Greater,
            Default::default(),
            depth_format,
        ),
        blend: None,
        samples,
        constants: &[],
        color,
    }
}

/// The pipeline of the bake AOV pass: the geometry again, depth-tested
/// against the prepass, into two `Rgba32Float` targets (kA, E).
fn bake_aov_pipeline(
    device: &wgpu::Device,
    module: &wgpu::ShaderModule,
    layout: &wgpu::PipelineLayout,
    depth: wgpu::DepthStencilState,
    samples: u32,
) -> wgpu::RenderPipeline {
    let target = Some(wgpu::ColorTargetState {
        format: COLOR_FORMAT,
        blend: None,
        write_mask: wgpu::ColorWrites::ALL,
    });
    let buffers = [Some(vec3_buffer(0)), Some(vec3_buffer(1))];
    device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some("bake aovs"),
        layout: Some(layout),
        vertex: wgpu::VertexState {
            module,
            entry_point: Some("vs_main"),
            compilation_options: Default::default(),
            buffers: &buffers,
        },
        primitive: wgpu::PrimitiveState {
            topology: wgpu::PrimitiveTopology::TriangleList,
            front_face: wgpu::FrontFace::Ccw,
            cull_mode: None,
            ..Default::default()
        },
        depth_stencil: Some(depth),
        multisample: wgpu::MultisampleState {
            count: samples,
            ..Default::default()
        },
        fragment: Some(wgpu::FragmentState {
            module,
            entry_point: Some("fs_bake_aovs"),
            compilation_options: Default::default(),
            targets: &[target.clone(), target],
        }),
        multiview_mask: None,
        cache: None,
    })
}

/// The targets of the bake AOV pass (multisampled and resolved when MSAA is
/// on) and their readbacks.
struct BakeAovTargets {
    resolved: [wgpu::Texture; 2],
    views: [wgpu::TextureView; 2],
    multisampled: Option<[wgpu::TextureView; 2]>,
    readbacks: [TextureReadback; 2],
    width: u32,
    height: u32,
}

impl BakeAovTargets {
    const NAMES: [&'static str; 2] = ["ao", "irradiance"];

    fn new(device: &wgpu::Device, width: u32, height: u32, msaa: u32) -> Self {
        let texture = |label: &str, samples: u32, usage| {
            device.create_texture(&wgpu::TextureDescriptor {
                label: Some(label),
                size: wgpu::Extent3d {
                    width,
                    height,
                    depth_or_array_layers: 1,
                },
                mip_level_count: 1,
                sample_count: samples,
                dimension: wgpu::TextureDimension::D2,
                format: COLOR_FORMAT,
                usage,
                view_formats: &[],
            })
        };
        let attach = wgpu::TextureUsages::RENDER_ATTACHMENT;
        let resolved = Self::NAMES.map(|n| texture(n, 1, attach | wgpu::TextureUsages::COPY_SRC));
        let views = [0, 1].map(|i| resolved[i].create_view(&Default::default()));
        let multisampled = (msaa > 1).then(|| {
            Self::NAMES.map(|n| texture(n, msaa, attach).create_view(&Default::default()))
        });
        Self {
            resolved,
            views,
            multisampled,
            readbacks: [0, 1].map(|_| TextureReadback::new(device, width, height, 16)),
            width,
            height,
        }
    }

    fn record(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        pipeline: &wgpu::RenderPipeline,
        gpu: &SceneGpu,
        groups: [&wgpu::BindGroup; 3],
        targets: &Targets,
        timer: &GpuTimer,
    ) {
        let attachment = |i: usize| {
            let (view, resolve_target) = match &self.multisampled {
                Some(ms) => (&ms[i], Some(&self.views[i])),
                None => (&self.views[i], None),
            };
            Some(wgpu::RenderPassColorAttachment {
                view,
                depth_slice: None,
                resolve_target,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                    store: wgpu::StoreOp::Store,
                },
            })
        };
        {
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("bake aovs"),
                color_attachments: &[attachment(0), attachment(1)],
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: &targets.depth_view,
                    depth_ops: Some(wgpu::Operations {
                        load: wgpu::LoadOp::Load,
                        store: wgpu::StoreOp::Store,
                    }),
                    stencil_ops: None,
                }),
                timestamp_writes: timer.render_pass("bake aovs"),
                occlusion_query_set: None,
                multiview_mask: None,
            });
            pass.set_pipeline(pipeline);
            for (g, group) in groups.iter().enumerate() {
                if g == 1 {
                    pass.set_bind_group(g as u32, *group, &[0]);
                } else {
                    pass.set_bind_group(g as u32, *group, &[]);
                }
            }
            gpu.draw_all(&mut pass, true, 0);
        }
        for (r, t) in self.readbacks.iter().zip(&self.resolved) {
            r.record(encoder, t, 0);
        }
    }

    fn read(&self, ctx: &GpuContext) -> Result<Vec<(String, Image)>, GpuError> {
        self.readbacks
            .iter()
            .zip(Self::NAMES)
            .map(|(r, n)| {
                Ok((
                    n.to_string(),
                    image_of(r, ctx, (self.width, self.height), 4)?,
                ))
            })
            .collect()
    }
}

/// Maps a `MAP_READ` buffer and copies its bytes out.
pub fn map_read(ctx: &GpuContext, buffer: &wgpu::Buffer) -> Result<Vec<u8>, GpuError> {
    let (tx, rx) = std::sync::mpsc::channel();
    buffer.map_async(wgpu::MapMode::Read, .., move |r| {
        let _ = tx.send(r);
    });
    ctx.wait_idle()?;
    rx.recv()
        .map_err(|e| GpuError::Wgpu(e.to_string()))?
        .map_err(|e| GpuError::Wgpu(e.to_string()))?;
    let out = buffer
        .get_mapped_range(..)
        .map_err(|e| GpuError::Wgpu(e.to_string()))?
        .to_vec();
    buffer.unmap();
    Ok(out)
}

/// Renders with a fresh context and pipeline: the CLI's entry point.
pub fn render_scene(
    scene: &Scene,
    camera: &Camera,
    width: u32,
    height: u32,
    options: RasterOptions,
    bakes: &BakedMaps<'_>,
    aovs: bool,
) -> Result<(RasterOutput, crate::AdapterSummary), GpuError> {
    let ctx = GpuContext::new()?;
    let renderer = ForwardRenderer::new(&ctx, options)?;
    let out = renderer.render_baked(&ctx, scene, camera, width, height, bakes, aovs)?;
    Ok((out, ctx.summary.clone()))
}
