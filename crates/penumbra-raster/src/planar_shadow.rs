//! Planar projected shadows (see `shaders/planar_shadow.wgsl`): per light,
//! one render pass marks each receiver's visible pixels in the stencil
//! (value receiver + 1) and draws the other objects flattened onto the
//! receiver's plane, which inverts those stencil values once; the
//! renderer's one-light pass then adds the light where the stencil's top bit
//! is clear.

use crate::gpu::GpuReceiver;
use crate::receivers::Receiver;
use crate::scene_gpu::{
    PassParams, SceneGpu, begin_stencil_pass, buffer_init, storage_entry, uniform_entry, whole,
};
use crate::shaders::planar_shadow_source;
use crate::timing::GpuTimer;
use glam::Vec3;

/// Occluder points closer to the receiver's plane than this (in scene
/// radii) cast nothing on it: objects standing on the floor do not shadow
/// it through their own base.
const PLANE_EPS_RADII: f32 = 1e-4;

/// The planar-shadow pipelines.
#[derive(Debug)]
pub(crate) struct PlanarShadows {
    mark: wgpu::RenderPipeline,
    project: wgpu::RenderPipeline,
    layout: wgpu::BindGroupLayout,
}

/// One frame's receivers on the GPU.
pub(crate) struct PlanarFrame {
    pub receivers: Vec<Receiver>,
    bind_group: wgpu::BindGroup,
    _buffer: wgpu::Buffer,
}

impl PlanarShadows {
    pub fn new(
        device: &wgpu::Device,
        params_layout: &wgpu::BindGroupLayout,
        depth_format: wgpu::TextureFormat,
        samples: u32,
    ) -> Self {
        let vf = wgpu::ShaderStages::VERTEX_FRAGMENT;
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("planar shadow"),
            entries: &[
                uniform_entry(0, vf),
                storage_entry(1, vf, true),
                storage_entry(3, vf, true),
                storage_entry(18, vf, true),
            ],
        });
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("planar shadow"),
            source: wgpu::ShaderSource::Wgsl(planar_shadow_source().into()),
        });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("planar shadow"),
            bind_group_layouts: &[Some(&layout), Some(params_layout)],
            immediate_size: 0,
        });
        let face = |compare, pass_op| wgpu::StencilFaceState {
            compare,
            fail_op: wgpu::StencilOperation::Keep,
            depth_fail_op: wgpu::StencilOperation::Keep,
            pass_op,
        };
        let pipeline = |vs: &str, fs: Option<&str>, depth_compare, stencil_face| {
            device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some(vs),
                layout: Some(&pipeline_layout),
                vertex: wgpu::VertexState {
                    module: &module,
                    entry_point: Some(vs),
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
                    format: depth_format,
                    depth_write_enabled: Some(false),
                    depth_compare: Some(depth_compare),
                    stencil: wgpu::StencilState {
                        front: stencil_face,
                        back: stencil_face,
                        read_mask: 0xff,
                        write_mask: 0xff,
                    },
                    bias: Default::default(),
                }),
                multisample: wgpu::MultisampleState {
                    count: samples,
                    ..Default::default()
                },
                fragment: fs.map(|fs| wgpu::FragmentState {
                    module: &module,
                    entry_point: Some(fs),
                    compilation_options: Default::default(),
                    targets: &[],
                }),
                multiview_mask: None,
                cache: None,
            })
        };
        // Mark: where the receiver is the visible surface (the prepass's
        // depth, equal clip positions), stencil = receiver + 1.
        let mark = pipeline(
            "vs_mark",
            None,
            wgpu::CompareFunction::GreaterEqual,
            face(
                wgpu::CompareFunction::Always,
                wgpu::StencilOperation::Replace,
            ),
        );
        // Project: on that receiver's pixels only, invert once (k → 255 − k).
        let project = pipeline(
            "vs_project",
            Some("fs_project"),
            wgpu::CompareFunction::Always,
            face(wgpu::CompareFunction::Equal, wgpu::StencilOperation::Invert),
        );
        Self {
            mark,
            project,
            layout,
        }
    }

    pub fn frame(
        &self,
        device: &wgpu::Device,
        gpu: &SceneGpu,
        receivers: Vec<Receiver>,
    ) -> PlanarFrame {
        let (lo, hi) = gpu.bounds;
        let radius = (0.5 * (hi - lo).length()).max(1e-6);
        let mut raw: Vec<GpuReceiver> = receivers
            .iter()
            .map(|r| GpuReceiver {
                plane: r.plane.to_array(),
                plane_eps: PLANE_EPS_RADII * radius,
                ..Default::default()
            })
            .collect();
        if raw.is_empty() {
            raw.push(GpuReceiver {
                plane: Vec3::Y.extend(0.0).to_array(),
                ..Default::default()
            });
        }
        let buffer = buffer_init(
            device,
            "receivers",
            bytemuck::cast_slice(&raw),
            wgpu::BufferUsages::STORAGE,
        );
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("planar shadow"),
            layout: &self.layout,
            entries: &[
                whole(0, &gpu.camera),
                whole(1, &gpu.instances),
                whole(3, &gpu.lights),
                whole(18, &buffer),
            ],
        });
        PlanarFrame {
            receivers,
            bind_group,
            _buffer: buffer,
        }
    }

    /// Records light `light`'s stencil pass; parameter slot
    /// `first_slot + k` holds (light, receiver k).
    #[allow(clippy::too_many_arguments)]
    pub fn record(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        frame: &PlanarFrame,
        gpu: &SceneGpu,
        params: &wgpu::BindGroup,
        first_slot: usize,
        light: u32,
        depth_stencil: &wgpu::TextureView,
        timer: &GpuTimer,
    ) {
        let mut pass = begin_stencil_pass(
            encoder,
            "planar shadow",
            depth_stencil,
            timer.render_pass(&format!("planar shadow {light}")),
        );
        pass.set_bind_group(0, &frame.bind_group, &[]);
        let mut mesh_of = vec![None; gpu.instance_count as usize];
        for &(i, mesh) in &gpu.draws {
            mesh_of[i as usize] = Some(mesh);
        }
        for (k, r) in frame.receivers.iter().enumerate() {
            let Some(mesh) = mesh_of[r.instance] else {
                continue;
            };
            pass.set_bind_group(1, params, &[PassParams::offset(first_slot + k)]);
            pass.set_stencil_reference(k as u32 + 1);
            pass.set_pipeline(&self.mark);
            gpu.draw_instance(&mut pass, r.instance as u32, mesh, false, 0);
            pass.set_pipeline(&self.project);
            for &o in &r.occluders {
                if let Some(mesh) = mesh_of[o] {
                    gpu.draw_instance(&mut pass, o as u32, mesh, false, 0);
                }
            }
        }
    }
}
