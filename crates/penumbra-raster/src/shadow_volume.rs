//! Stencil shadow volumes (z-fail with caps, extruded to infinity; see
//! `shaders/shadow_volume.wgsl` for the construction and why open meshes
//! stay correct). Per light: a compute pass decides which triangles cast,
//! then one render pass clears the stencil and draws every instance's caps
//! and silhouette quads into it; the renderer's one-light pass then adds the
//! light where the stencil is 0.

use crate::camera::ORTHO_EXTRUSION_RADII;
use crate::context::GpuError;
use crate::gpu::{GpuVolumeGeometry, GpuVolumeInstance};
use crate::scene_gpu::{
    SceneGpu, begin_stencil_pass, buffer_init, storage_entry, uniform_entry, whole,
};
use crate::shaders::shadow_volume_source;
use crate::timing::GpuTimer;
use crate::topology::mesh_topology;
use penumbra_scene::Scene;

/// Start of each prism behind its triangle, in scene radii.
const PRISM_OFFSET_RADII: f32 = 2e-4;

/// The shadow-volume pipelines.
#[derive(Debug)]
pub(crate) struct ShadowVolumes {
    facing: wgpu::ComputePipeline,
    caps: wgpu::RenderPipeline,
    edges: wgpu::RenderPipeline,
    facing_layout: wgpu::BindGroupLayout,
    draw_layout: wgpu::BindGroupLayout,
}

/// Every instance's geometry merged for the volume passes, and the bind
/// groups over it.
pub(crate) struct VolumeFrame {
    volumes: Vec<GpuVolumeInstance>,
    max_triangles: u32,
    facing_group: wgpu::BindGroup,
    draw_group: wgpu::BindGroup,
    _buffers: Vec<wgpu::Buffer>,
}

fn stencil_face(depth_fail_op: wgpu::StencilOperation) -> wgpu::StencilFaceState {
    wgpu::StencilFaceState {
        compare: wgpu::CompareFunction::Always,
        fail_op: wgpu::StencilOperation::Keep,
        depth_fail_op,
        pass_op: wgpu::StencilOperation::Keep,
    }
}

impl ShadowVolumes {
    pub fn new(
        device: &wgpu::Device,
        params_layout: &wgpu::BindGroupLayout,
        depth_format: wgpu::TextureFormat,
        samples: u32,
    ) -> Self {
        let c = wgpu::ShaderStages::COMPUTE;
        let v = wgpu::ShaderStages::VERTEX;
        let entries = |stages, facing_read_only| {
            vec![
                uniform_entry(0, stages),
                storage_entry(1, stages, true),
                storage_entry(3, stages, true),
                storage_entry(12, stages, true),
                storage_entry(13, stages, true),
                storage_entry(14, stages, true),
                storage_entry(15, stages, true),
                storage_entry(16, stages, facing_read_only),
                uniform_entry(17, stages),
            ]
        };
        let facing_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("shadow volume facing"),
            entries: &entries(c, false),
        });
        let draw_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("shadow volume draw"),
            entries: &entries(v, true),
        });
        let facing_module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("shadow volume facing"),
            source: wgpu::ShaderSource::Wgsl(shadow_volume_source(true).into()),
        });
        let draw_module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("shadow volume draw"),
            source: wgpu::ShaderSource::Wgsl(shadow_volume_source(false).into()),
        });
        let layout = |group: &wgpu::BindGroupLayout| {
            device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some("shadow volume"),
                bind_group_layouts: &[Some(group), Some(params_layout)],
                immediate_size: 0,
            })
        };
        let facing = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some("shadow volume facing"),
            layout: Some(&layout(&facing_layout)),
            module: &facing_module,
            entry_point: Some("facing_main"),
            compilation_options: Default::default(),
            cache: None,
        });
        let draw_pipeline_layout = layout(&draw_layout);
        // z-fail: count the faces behind the visible surface, back faces +1,
        // front faces −1; no culling (both sides count), no depth writes.
        let stencil = wgpu::StencilState {
            front: stencil_face(wgpu::StencilOperation::DecrementWrap),
            back: stencil_face(wgpu::StencilOperation::IncrementWrap),
            read_mask: 0xff,
            write_mask: 0xff,
        };
        let pipeline = |entry: &str| {
            device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some(entry),
                layout: Some(&draw_pipeline_layout),
                vertex: wgpu::VertexState {
                    module: &draw_module,
                    entry_point: Some(entry),
                    compilation_options: Default::default(),
                    buffers: &[],
                },
                primitive: wgpu::PrimitiveState {
                    topology: wgpu::PrimitiveTopology::TriangleList,
                    front_face: wgpu::FrontFace::Ccw,
                    cull_mode: None,
                    ..Default::default()
                },
                depth_stencil: Some(wgpu::DepthStencilState {
                    format: depth_format,
                    depth_write_enabled: Some(false),
                    depth_compare: Some(wgpu::CompareFunction::Greater),
                    stencil: stencil.clone(),
                    bias: Default::default(),
                }),
                multisample: wgpu::MultisampleState {
                    count: samples,
                    ..Default::default()
                },
                fragment: None,
                multiview_mask: None,
                cache: None,
            })
        };
        Self {
            facing,
            caps: pipeline("vs_cap"),
            edges: pipeline("vs_edge"),
            facing_layout,
            draw_layout,
        }
    }

    /// Merges the scene's instanced meshes (with their adjacency) into the
    /// volume buffers; an error if a mesh has more triangles than one
    /// facing dispatch covers.
    pub fn frame(
        &self,
        device: &wgpu::Device,
        scene: &Scene,
        gpu: &SceneGpu,
    ) -> Result<VolumeFrame, GpuError> {
        let limit = 64 * device.limits().max_compute_workgroups_per_dimension as u64;
        if let Some(m) = gpu.draws[..gpu.casters]
            .iter()
            .map(|&(_, mesh)| &scene.meshes[mesh])
            .find(|m| m.indices.len() as u64 > limit)
        {
            return Err(GpuError::Unsupported(format!(
                "mesh '{}' has more than {limit} triangles, the most one shadow-volume dispatch covers",
                m.name
            )));
        }
        let mut positions: Vec<[f32; 4]> = Vec::new();
        let mut indices: Vec<u32> = Vec::new();
        let mut edges: Vec<[u32; 4]> = Vec::new();
        // Per mesh: (first index, first vertex, first edge, edge count,
        // triangles, closed), built once however many instances use it.
        let mut mesh_slot: Vec<Option<[u32; 6]>> = vec![None; scene.meshes.len()];
        let mut volumes = Vec::new();
        let mut facing_len = 0u32;
        for &(instance, mesh) in &gpu.draws[..gpu.casters] {
            let slot = *mesh_slot[mesh].get_or_insert_with(|| {
                let m = &scene.meshes[mesh];
                let topo = mesh_topology(&m.positions, &m.indices);
                let slot = [
                    indices.len() as u32,
                    positions.len() as u32,
                    edges.len() as u32,
                    topo.edges.len() as u32,
                    m.indices.len() as u32,
                    topo.closed as u32,
                ];
                positions.extend(m.positions.iter().map(|p| p.extend(1.0).to_array()));
                indices.extend(m.indices.iter().flatten());
                edges.extend(topo.edges);
                slot
            });
            volumes.push(GpuVolumeInstance {
                first_index: slot[0],
                first_vertex: slot[1],
                first_edge: slot[2],
                edge_count: slot[3],
                first_facing: facing_len,
                triangle_count: slot[4],
                closed: slot[5],
                instance,
            });
            facing_len += slot[4];
        }
        let max_triangles = volumes.iter().map(|v| v.triangle_count).max().unwrap_or(0);
        let (lo, hi) = gpu.bounds;
        let radius = (0.5 * (hi - lo).length()).max(1e-6);
        let constants = GpuVolumeGeometry {
            eps: PRISM_OFFSET_RADII * radius,
            extrude: ORTHO_EXTRUSION_RADII * radius,
            ..Default::default()
        };
        let storage = wgpu::BufferUsages::STORAGE;
        // Storage bindings cannot be empty.
        if positions.is_empty() {
            positions.push([0.0; 4]);
        }
        if edges.is_empty() {
            edges.push([0; 4]);
        }
        if indices.is_empty() {
            indices.push(0);
        }
        let volume_list = if volumes.is_empty() {
            vec![GpuVolumeInstance::default()]
        } else {
            volumes.clone()
        };
        let buffers = vec![
            buffer_init(
                device,
                "volume positions",
                bytemuck::cast_slice(&positions),
                storage,
            ),
            buffer_init(
                device,
                "volume indices",
                bytemuck::cast_slice(&indices),
                storage,
            ),
            buffer_init(
                device,
                "volume edges",
                bytemuck::cast_slice(&edges),
                storage,
            ),
            buffer_init(
                device,
                "volume instances",
                bytemuck::cast_slice(&volume_list),
                storage,
            ),
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("facing"),
                size: 4 * facing_len.max(1) as u64,
                usage: storage,
                mapped_at_creation: false,
            }),
            buffer_init(
                device,
                "volume constants",
                bytemuck::bytes_of(&constants),
                wgpu::BufferUsages::UNIFORM,
            ),
        ];
        let group = |layout| {
            device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("shadow volume"),
                layout,
                entries: &[
                    whole(0, &gpu.camera),
                    whole(1, &gpu.instances),
                    whole(3, &gpu.lights),
                    whole(12, &buffers[0]),
                    whole(13, &buffers[1]),
                    whole(14, &buffers[2]),
                    whole(15, &buffers[3]),
                    whole(16, &buffers[4]),
                    whole(17, &buffers[5]),
                ],
            })
        };
        Ok(VolumeFrame {
            facing_group: group(&self.facing_layout),
            draw_group: group(&self.draw_layout),
            volumes,
            max_triangles,
            _buffers: buffers,
        })
    }

    /// Records light `light`'s facing pass and stencil pass; afterwards the
    /// stencil is 0 exactly where the light is not shadowed.
    #[allow(clippy::too_many_arguments)]
    pub fn record(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        frame: &VolumeFrame,
        params: &wgpu::BindGroup,
        params_offset: u32,
        light: u32,
        depth_stencil: &wgpu::TextureView,
        timer: &GpuTimer,
    ) {
        {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("shadow volume facing"),
                timestamp_writes: timer.compute_pass(&format!("shadow volume facing {light}")),
            });
            pass.set_pipeline(&self.facing);
            pass.set_bind_group(0, &frame.facing_group, &[]);
            pass.set_bind_group(1, params, &[params_offset]);
            if frame.max_triangles > 0 {
                pass.dispatch_workgroups(
                    frame.max_triangles.div_ceil(64),
                    frame.volumes.len() as u32,
                    1,
                );
            }
        }
        let mut pass = begin_stencil_pass(
            encoder,
            "shadow volume stencil",
            depth_stencil,
            timer.render_pass(&format!("shadow volume stencil {light}")),
        );
        pass.set_bind_group(0, &frame.draw_group, &[]);
        pass.set_bind_group(1, params, &[params_offset]);
        pass.set_pipeline(&self.caps);
        for (i, v) in frame.volumes.iter().enumerate() {
            let i = i as u32;
            pass.draw(0..6 * v.triangle_count, i..i + 1);
        }
        pass.set_pipeline(&self.edges);
        for (i, v) in frame.volumes.iter().enumerate() {
            let copies = if v.closed != 0 { 1 } else { 2 };
            let i = i as u32;
            pass.draw(0..6 * copies * v.edge_count, i..i + 1);
        }
    }
}
