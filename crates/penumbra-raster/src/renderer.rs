//! Forward renderer: meshes and instances uploaded once per render, a depth
//! buffer (reversed z), one draw per instance into an `Rgba32Float` target at
//! the settings' resolution, read back into a [`penumbra_image::Image`].

use crate::camera::gpu_camera;
use crate::context::{GpuContext, GpuError};
use crate::gpu::{GpuInstance, GpuLight, GpuShadow, GpuShadowView};
use crate::scene_data::SceneData;
use crate::shaders::forward_source;
use crate::shadow_map::{
    DEFAULT_NORMAL_OFFSET, DEFAULT_SHADOW_MAP_SIZE, DEFAULT_SLOPE_BIAS, SHADOW_CONSTANT_BIAS,
    shadow_views,
};
use crate::timing::{GpuTimer, PassTiming};
use glam::Vec3;
use penumbra_image::Image;
use penumbra_scene::Scene;
use penumbra_scene::camera::Camera;
use std::time::Instant;
use wgpu::util::DeviceExt;

const COLOR_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;
const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

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
}

impl Default for RasterOptions {
    fn default() -> Self {
        Self {
            msaa: 1,
            shadows: ShadowMode::None,
            shadow_map_size: DEFAULT_SHADOW_MAP_SIZE,
            pcf: 1,
            slope_bias: DEFAULT_SLOPE_BIAS,
            normal_offset: DEFAULT_NORMAL_OFFSET,
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
    /// Wall time from submitting the pass to the end of its execution [ms]
    /// (the queue is polled until idle).
    pub frame_ms: f64,
    /// GPU time of every pass in submission order (names: `"shadow map
    /// L"` per shadow-map layer, `"forward"`), where the adapter supports
    /// timestamp queries; empty otherwise.
    pub passes: Vec<PassTiming>,
    /// What the raster path approximated for this scene (see [`SceneData`]).
    pub warnings: Vec<String>,
}

struct GpuMesh {
    positions: wgpu::Buffer,
    normals: Option<wgpu::Buffer>,
    indices: wgpu::Buffer,
    index_count: u32,
}

/// The forward pipeline for one MSAA setting.
#[derive(Debug)]
pub struct ForwardRenderer {
    pipeline: wgpu::RenderPipeline,
    layout: wgpu::BindGroupLayout,
    shadow_pipeline: wgpu::RenderPipeline,
    shadow_layout: wgpu::BindGroupLayout,
    shadow_sampler: wgpu::Sampler,
    options: RasterOptions,
    msaa: u32,
}

fn storage_entry(binding: u32, visibility: wgpu::ShaderStages) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Storage { read_only: true },
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    }
}

impl ForwardRenderer {
    pub fn new(ctx: &GpuContext, options: RasterOptions) -> Result<Self, GpuError> {
        let msaa = options.msaa;
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
        let size = options.shadow_map_size;
        let max_dim = ctx.device.limits().max_texture_dimension_2d;
        if options.shadows == ShadowMode::Map && (size < 16 || size > max_dim) {
            return Err(GpuError::Unsupported(format!(
                "shadow map size {size} (the adapter allows 16 to {max_dim})"
            )));
        }
        if options.pcf == 0 || options.pcf > MAX_PCF {
            return Err(GpuError::Unsupported(format!(
                "PCF kernel {}: use 1 to {MAX_PCF}",
                options.pcf
            )));
        }
        let device = &ctx.device;
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("penumbra forward"),
            source: wgpu::ShaderSource::Wgsl(forward_source().into()),
        });
        let vf = wgpu::ShaderStages::VERTEX | wgpu::ShaderStages::FRAGMENT;
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("penumbra forward"),
            entries: &[
                wgpu::BindGroupLayoutEntry {
                    binding: 0,
                    visibility: vf,
                    ty: wgpu::BindingType::Buffer {
                        ty: wgpu::BufferBindingType::Uniform,
                        has_dynamic_offset: false,
                        min_binding_size: None,
                    },
                    count: None,
                },
                storage_entry(1, vf),
                storage_entry(2, wgpu::ShaderStages::FRAGMENT),
                storage_entry(3, wgpu::ShaderStages::FRAGMENT),
                storage_entry(4, wgpu::ShaderStages::FRAGMENT),
                storage_entry(5, wgpu::ShaderStages::FRAGMENT),
                wgpu::BindGroupLayoutEntry {
                    binding: 6,
                    visibility: wgpu::ShaderStages::FRAGMENT,
                    ty: wgpu::BindingType::Texture {
                        sample_type: wgpu::TextureSampleType::Depth,
                        view_dimension: wgpu::TextureViewDimension::D2Array,
                        multisampled: false,
                    },
                    count: None,
                },
                wgpu::BindGroupLayoutEntry {
                    binding: 7,
                    visibility: wgpu::ShaderStages::FRAGMENT,
                    ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Comparison),
                    count: None,
                },
            ],
        });
        let shadow_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("penumbra shadow"),
            entries: &[
                storage_entry(1, wgpu::ShaderStages::VERTEX),
                storage_entry(5, wgpu::ShaderStages::VERTEX),
            ],
        });
        let shadow_pipeline_layout =
            device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some("penumbra shadow"),
                bind_group_layouts: &[Some(&shadow_layout)],
                immediate_size: 0,
            });
        // Depth only, no culling (open meshes and single quads cast too);
        // reversed depth, so the bias is negative: it moves the stored
        // depth away from the light by `slope_bias` times the triangle's
        // depth slope, plus a few units of the depth format's precision.
        let shadow_pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("penumbra shadow"),
            layout: Some(&shadow_pipeline_layout),
            vertex: wgpu::VertexState {
                module: &module,
                entry_point: Some("vs_shadow"),
                compilation_options: Default::default(),
                buffers: &[Some(wgpu::VertexBufferLayout {
                    array_stride: 12,
                    step_mode: wgpu::VertexStepMode::Vertex,
                    attributes: &wgpu::vertex_attr_array![0 => Float32x3],
                })],
            },
            primitive: wgpu::PrimitiveState {
                topology: wgpu::PrimitiveTopology::TriangleList,
                cull_mode: None,
                ..Default::default()
            },
            depth_stencil: Some(wgpu::DepthStencilState {
                format: DEPTH_FORMAT,
                depth_write_enabled: Some(true),
                depth_compare: Some(wgpu::CompareFunction::Greater),
                stencil: Default::default(),
                bias: wgpu::DepthBiasState {
                    constant: -SHADOW_CONSTANT_BIAS,
                    slope_scale: -options.slope_bias,
                    clamp: 0.0,
                },
            }),
            multisample: Default::default(),
            fragment: None,
            multiview_mask: None,
            cache: None,
        });
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
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("penumbra forward"),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        let vec3_buffer = |location| wgpu::VertexBufferLayout {
            array_stride: 12,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: if location == 0 {
                &wgpu::vertex_attr_array![0 => Float32x3]
            } else {
                &wgpu::vertex_attr_array![1 => Float32x3]
            },
        };
        let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("penumbra forward"),
            layout: Some(&pipeline_layout),
            vertex: wgpu::VertexState {
                module: &module,
                entry_point: Some("vs_main"),
                compilation_options: Default::default(),
                buffers: &[Some(vec3_buffer(0)), Some(vec3_buffer(1))],
            },
            primitive: wgpu::PrimitiveState {
                topology: wgpu::PrimitiveTopology::TriangleList,
                front_face: wgpu::FrontFace::Ccw,
                cull_mode: None,
                ..Default::default()
            },
            depth_stencil: Some(wgpu::DepthStencilState {
                format: DEPTH_FORMAT,
                depth_write_enabled: Some(true),
                depth_compare: Some(wgpu::CompareFunction::Greater),
                stencil: Default::default(),
                bias: Default::default(),
            }),
            multisample: wgpu::MultisampleState {
                count: msaa,
                ..Default::default()
            },
            fragment: Some(wgpu::FragmentState {
                module: &module,
                entry_point: Some("fs_main"),
                compilation_options: Default::default(),
                targets: &[Some(wgpu::ColorTargetState {
                    format: COLOR_FORMAT,
                    blend: None,
                    write_mask: wgpu::ColorWrites::ALL,
                })],
            }),
            multiview_mask: None,
            cache: None,
        });
        Ok(Self {
            pipeline,
            layout,
            shadow_pipeline,
            shadow_layout,
            shadow_sampler,
            options,
            msaa,
        })
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
        let start = Instant::now();
        let device = &ctx.device;
        let max_dim = device.limits().max_texture_dimension_2d;
        if width == 0 || height == 0 || width > max_dim || height > max_dim {
            return Err(GpuError::Unsupported(format!(
                "resolution {width}x{height} (the adapter allows 1 to {max_dim} per edge)"
            )));
        }
        let data = SceneData::from_scene(scene);
        let bounds = scene
            .bounds()
            .unwrap_or((Vec3::splat(-1.0), Vec3::splat(1.0)));
        let cam = gpu_camera(camera, width, height, bounds, data.lights.len() as u32);

        let init = |label: &str, contents: &[u8], usage| {
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents,
                usage,
            })
        };
        let storage = wgpu::BufferUsages::STORAGE;
        let camera_buf = init(
            "camera",
            bytemuck::bytes_of(&cam),
            wgpu::BufferUsages::UNIFORM,
        );
        let mut instances = data.instances.clone();
        if instances.is_empty() {
            instances.push(GpuInstance::default());
        }
        let mut lights = data.lights.clone();
        if lights.is_empty() {
            lights.push(GpuLight::default());
        }
        let instance_buf = init("instances", bytemuck::cast_slice(&instances), storage);
        let material_buf = init("materials", bytemuck::cast_slice(&data.materials), storage);
        let light_buf = init("lights", bytemuck::cast_slice(&lights), storage);
        let o = self.options;
        let (mut shadows, mut views) = match o.shadows {
            ShadowMode::Map => shadow_views(
                &scene.lights,
                bounds,
                o.shadow_map_size,
                o.pcf,
                o.normal_offset,
            ),
            ShadowMode::None => (Vec::new(), Vec::new()),
        };
        let layers = views.len() as u32;
        let max_layers = device.limits().max_texture_array_layers;
        if layers > max_layers {
            return Err(GpuError::Unsupported(format!(
                "{layers} shadow-map layers (the adapter allows {max_layers}; a point light takes 6)"
            )));
        }
        shadows.resize(lights.len(), GpuShadow::default());
        if views.is_empty() {
            views.push(GpuShadowView::default());
        }
        let map_size = if layers > 0 { o.shadow_map_size } else { 1 };
        let shadow_map = device.create_texture(&wgpu::TextureDescriptor {
            label: Some("shadow maps"),
            size: wgpu::Extent3d {
                width: map_size,
                height: map_size,
                depth_or_array_layers: layers.max(1),
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: DEPTH_FORMAT,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
            view_formats: &[],
        });
        let shadow_array_view = shadow_map.create_view(&wgpu::TextureViewDescriptor {
            dimension: Some(wgpu::TextureViewDimension::D2Array),
            ..Default::default()
        });
        let shadow_buf = init("shadows", bytemuck::cast_slice(&shadows), storage);
        let view_buf = init("shadow views", bytemuck::cast_slice(&views), storage);
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("penumbra forward"),
            layout: &self.layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: camera_buf.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: instance_buf.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 2,
                    resource: material_buf.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 3,
                    resource: light_buf.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 4,
                    resource: shadow_buf.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 5,
                    resource: view_buf.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 6,
                    resource: wgpu::BindingResource::TextureView(&shadow_array_view),
                },
                wgpu::BindGroupEntry {
                    binding: 7,
                    resource: wgpu::BindingResource::Sampler(&self.shadow_sampler),
                },
            ],
        });
        let shadow_bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("penumbra shadow"),
            layout: &self.shadow_layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: instance_buf.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 5,
                    resource: view_buf.as_entire_binding(),
                },
            ],
        });
        let meshes: Vec<Option<GpuMesh>> = scene
            .meshes
            .iter()
            .map(|m| {
                if m.indices.is_empty() || m.positions.is_empty() {
                    return None;
                }
                let vertex = wgpu::BufferUsages::VERTEX;
                let flat = |v: &[Vec3]| v.iter().map(|p| p.to_array()).collect::<Vec<[f32; 3]>>();
                Some(GpuMesh {
                    positions: init(
                        "positions",
                        bytemuck::cast_slice(&flat(&m.positions)),
                        vertex,
                    ),
                    normals: m
                        .normals
                        .as_ref()
                        .map(|n| init("normals", bytemuck::cast_slice(&flat(n)), vertex)),
                    indices: init(
                        "indices",
                        bytemuck::cast_slice(&m.indices),
                        wgpu::BufferUsages::INDEX,
                    ),
                    index_count: (m.indices.len() * 3) as u32,
                })
            })
            .collect();

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
        let resolved = target(
            "colour",
            COLOR_FORMAT,
            1,
            attach | wgpu::TextureUsages::COPY_SRC,
        );
        let multisampled =
            (self.msaa > 1).then(|| target("colour msaa", COLOR_FORMAT, self.msaa, attach));
        let depth = target("depth", DEPTH_FORMAT, self.msaa, attach);
        let resolved_view = resolved.create_view(&Default::default());
        let ms_view = multisampled
            .as_ref()
            .map(|t| t.create_view(&Default::default()));
        let depth_view = depth.create_view(&Default::default());

        // One timed pass per shadow-map layer, plus the forward pass.
        let timer = GpuTimer::new(ctx, layers + 1);

        let bytes_per_row = (width * 16).div_ceil(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT)
            * wgpu::COPY_BYTES_PER_ROW_ALIGNMENT;
        let readback = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("readback"),
            size: bytes_per_row as u64 * height as u64,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });

        let bg = scene.background;
        let mut encoder = device.create_command_encoder(&Default::default());
        let instance_count = instances.len() as u32;
        for layer in 0..layers {
            let view = shadow_map.create_view(&wgpu::TextureViewDescriptor {
                dimension: Some(wgpu::TextureViewDimension::D2),
                base_array_layer: layer,
                array_layer_count: Some(1),
                ..Default::default()
            });
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("shadow"),
                color_attachments: &[],
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: &view,
                    depth_ops: Some(wgpu::Operations {
                        load: wgpu::LoadOp::Clear(0.0),
                        store: wgpu::StoreOp::Store,
                    }),
                    stencil_ops: None,
                }),
                timestamp_writes: timer.render_pass(&format!("shadow map {layer}")),
                occlusion_query_set: None,
                multiview_mask: None,
            });
            pass.set_pipeline(&self.shadow_pipeline);
            pass.set_bind_group(0, &shadow_bind_group, &[]);
            for (i, inst) in scene.instances.iter().enumerate() {
                let Some(mesh) = &meshes[inst.mesh] else {
                    continue;
                };
                pass.set_vertex_buffer(0, mesh.positions.slice(..));
                pass.set_index_buffer(mesh.indices.slice(..), wgpu::IndexFormat::Uint32);
                let i = layer * instance_count + i as u32;
                pass.draw_indexed(0..mesh.index_count, 0, i..i + 1);
            }
        }
        {
            let (view, resolve_target) = match &ms_view {
                Some(ms) => (ms, Some(&resolved_view)),
                None => (&resolved_view, None),
            };
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("forward"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view,
                    depth_slice: None,
                    resolve_target,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(wgpu::Color {
                            r: bg.x as f64,
                            g: bg.y as f64,
                            b: bg.z as f64,
                            a: 0.0,
                        }),
                        store: wgpu::StoreOp::Store,
                    },
                })],
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: &depth_view,
                    depth_ops: Some(wgpu::Operations {
                        load: wgpu::LoadOp::Clear(0.0),
                        store: wgpu::StoreOp::Discard,
                    }),
                    stencil_ops: None,
                }),
                timestamp_writes: timer.render_pass("forward"),
                occlusion_query_set: None,
                multiview_mask: None,
            });
            pass.set_pipeline(&self.pipeline);
            pass.set_bind_group(0, &bind_group, &[]);
            for (i, inst) in scene.instances.iter().enumerate() {
                let Some(mesh) = &meshes[inst.mesh] else {
                    continue;
                };
                pass.set_vertex_buffer(0, mesh.positions.slice(..));
                pass.set_vertex_buffer(
                    1,
                    mesh.normals.as_ref().unwrap_or(&mesh.positions).slice(..),
                );
                pass.set_index_buffer(mesh.indices.slice(..), wgpu::IndexFormat::Uint32);
                let i = i as u32;
                pass.draw_indexed(0..mesh.index_count, 0, i..i + 1);
            }
        }
        timer.resolve(&mut encoder);
        encoder.copy_texture_to_buffer(
            wgpu::TexelCopyTextureInfo {
                texture: &resolved,
                mip_level: 0,
                origin: wgpu::Origin3d::ZERO,
                aspect: wgpu::TextureAspect::All,
            },
            wgpu::TexelCopyBufferInfo {
                buffer: &readback,
                layout: wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(bytes_per_row),
                    rows_per_image: Some(height),
                },
            },
            size,
        );
        let frame_start = Instant::now();
        ctx.queue.submit([encoder.finish()]);
        ctx.wait_idle()?;
        let frame_ms = frame_start.elapsed().as_secs_f64() * 1e3;

        let bytes = map_read(ctx, &readback)?;
        let mut pixels = Vec::with_capacity(width as usize * height as usize);
        for y in 0..height as usize {
            let row: &[f32] =
                bytemuck::cast_slice(&bytes[y * bytes_per_row as usize..][..width as usize * 16]);
            pixels.extend(row.chunks_exact(4).map(|p| Vec3::new(p[0], p[1], p[2])));
        }
        let passes = timer.read(ctx)?;
        let image =
            Image::from_pixels(width, height, pixels).map_err(|e| GpuError::Wgpu(e.to_string()))?;
        Ok(RasterOutput {
            image,
            total_ms: start.elapsed().as_secs_f64() * 1e3,
            frame_ms,
            passes,
            warnings: data.warnings,
        })
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
) -> Result<(RasterOutput, crate::AdapterSummary), GpuError> {
    let ctx = GpuContext::new()?;
    let renderer = ForwardRenderer::new(&ctx, options)?;
    let out = renderer.render(&ctx, scene, camera, width, height)?;
    Ok((out, ctx.summary.clone()))
}
