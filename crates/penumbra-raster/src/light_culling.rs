//! Tiled light culling (Forward+): after the depth prepass, a compute pass
//! gives each 16×16-pixel tile the list of lights whose range sphere meets
//! the tile's slice of the view frustum (side planes from the tile's
//! corners, depth bounds from the prepass); the forward pass then shades
//! each pixel with its tile's lights only. Lights without a range are in
//! every list. The lists keep increasing light order, so a culled pixel sums
//! exactly the non-zero terms of the unculled loop: culling changes no
//! pixel (the test for tile seams compares both images).

use crate::gpu::{GpuCulling, GpuLight, LIGHT_DIRECTIONAL, TILE_OVERFLOW};
use crate::scene_gpu::{buffer_init, storage_entry, uniform_entry, whole};
use crate::shaders::light_culling_source;
use glam::Mat4;
use std::sync::OnceLock;

/// Tile edge in pixels (WGSL `TILE`).
pub const TILE: u32 = 16;
/// Most lights one tile list holds; tiles with more shade every light.
pub const MAX_LIGHTS_PER_TILE: u32 = 512;
/// Most lights the culling pass handles (its workgroup bit mask); with more,
/// culling is off and every pixel shades every light.
pub const MAX_CULLED_LIGHTS: u32 = 256 * 32;

/// The culling pipeline for one depth sample count, made when a frame first
/// culls (frames with stencil shadows never do).
#[derive(Debug)]
pub(crate) struct LightCulling {
    samples: u32,
    /// The bind group layout and the pipeline.
    pipeline: OnceLock<(wgpu::BindGroupLayout, wgpu::ComputePipeline)>,
}

/// One frame's culling resources.
pub(crate) struct CullingFrame {
    pub uniform: GpuCulling,
    pub uniform_buffer: wgpu::Buffer,
    /// `tiles × (max_per_tile + 1)` words, written by the compute pass.
    pub tile_lights: wgpu::Buffer,
    spheres: wgpu::Buffer,
    /// Where the tile lists are copied for [`CullingStats`], if asked for.
    readback: Option<wgpu::Buffer>,
}

/// What the culling pass left in the tile lists (read back on request,
/// [`crate::RasterOptions::culling_stats`]).
#[derive(Clone, Debug, PartialEq)]
pub struct CullingStats {
    pub tiles: usize,
    /// Lights in the scene.
    pub lights: u32,
    /// Mean list length over all tiles (overflowed tiles count every light).
    pub mean_lights: f64,
    /// Longest list.
    pub max_lights: u32,
    /// Tiles with at least one light (background-only tiles have none).
    pub tiles_with_lights: usize,
    /// Tiles whose list overflowed (their pixels shade every light).
    pub overflowed: usize,
}

/// View-space bounding spheres of the lights' ranges: (centre, range), or
/// w = −1 for lights that reach everywhere (directional, no range).
pub fn light_spheres(view: Mat4, lights: &[GpuLight]) -> Vec<[f32; 4]> {
    lights
        .iter()
        .map(|l| {
            if l.kind == LIGHT_DIRECTIONAL || l.range <= 0.0 {
                [0.0, 0.0, 0.0, -1.0]
            } else {
                let c = view.transform_point3(l.xyz());
                [c.x, c.y, c.z, l.range]
            }
        })
        .collect()
}

impl LightCulling {
    pub fn new(samples: u32) -> Self {
        Self {
            samples,
            pipeline: OnceLock::new(),
        }
    }

    fn pipeline(&self, device: &wgpu::Device) -> &(wgpu::BindGroupLayout, wgpu::ComputePipeline) {
        self.pipeline.get_or_init(|| self.build(device))
    }

    fn build(&self, device: &wgpu::Device) -> (wgpu::BindGroupLayout, wgpu::ComputePipeline) {
        let samples = self.samples;
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("light culling"),
            source: wgpu::ShaderSource::Wgsl(light_culling_source(samples > 1).into()),
        });
        let c = wgpu::ShaderStages::COMPUTE;
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("light culling"),
            entries: &[
                uniform_entry(0, c),
                storage_entry(1, c, true),
                wgpu::BindGroupLayoutEntry {
                    binding: 2,
                    visibility: c,
                    ty: wgpu::BindingType::Texture {
                        sample_type: wgpu::TextureSampleType::Depth,
                        view_dimension: wgpu::TextureViewDimension::D2,
                        multisampled: samples > 1,
                    },
                    count: None,
                },
                storage_entry(3, c, false),
            ],
        });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("light culling"),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some("light culling"),
            layout: Some(&pipeline_layout),
            module: &module,
            entry_point: Some("cull"),
            // The pass initialises its workgroup memory itself.
            compilation_options: wgpu::PipelineCompilationOptions {
                zero_initialize_workgroup_memory: false,
                ..Default::default()
            },
            cache: None,
        });
        (layout, pipeline)
    }

    /// The frame's uniform, sphere and tile buffers. `enabled` = false (or
    /// too many lights) leaves the lists unused: every pixel loops over all
    /// lights.
    #[allow(clippy::too_many_arguments)]
    pub fn frame(
        device: &wgpu::Device,
        enabled: bool,
        stats: bool,
        view: Mat4,
        proj: Mat4,
        lights: &[GpuLight],
        width: u32,
        height: u32,
        samples: u32,
    ) -> CullingFrame {
        let light_count = lights.len() as u32;
        let enabled = enabled && light_count > 0 && light_count <= MAX_CULLED_LIGHTS;
        let tiles_x = width.div_ceil(TILE);
        let tiles_y = height.div_ceil(TILE);
        let max_per_tile = light_count.clamp(1, MAX_LIGHTS_PER_TILE);
        let uniform = GpuCulling {
            inv_proj: proj.inverse().to_cols_array_2d(),
            tiles_x,
            tiles_y,
            light_count,
            max_per_tile,
            width,
            height,
            enabled: enabled as u32,
            samples,
        };
        let words = if enabled {
            tiles_x as u64 * tiles_y as u64 * (max_per_tile as u64 + 1)
        } else {
            1
        };
        let tile_lights = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("tile lights"),
            size: 4 * words,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let readback = (stats && enabled).then(|| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("tile lights readback"),
                size: 4 * words,
                usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            })
        });
        let mut spheres = light_spheres(view, lights);
        if spheres.is_empty() {
            spheres.push([0.0; 4]);
        }
        CullingFrame {
            uniform_buffer: buffer_init(
                device,
                "culling",
                bytemuck::bytes_of(&uniform),
                wgpu::BufferUsages::UNIFORM,
            ),
            spheres: buffer_init(
                device,
                "light spheres",
                bytemuck::cast_slice(&spheres),
                wgpu::BufferUsages::STORAGE,
            ),
            tile_lights,
            uniform,
            readback,
        }
    }

    /// Records the copy of the tile lists for [`Self::stats`] (if asked for).
    pub fn record_stats_copy(encoder: &mut wgpu::CommandEncoder, frame: &CullingFrame) {
        if let Some(r) = &frame.readback {
            encoder.copy_buffer_to_buffer(&frame.tile_lights, 0, r, 0, r.size());
        }
    }

    /// The tile-list statistics of a submitted frame, if asked for.
    pub fn stats(
        ctx: &crate::GpuContext,
        frame: &CullingFrame,
    ) -> Result<Option<CullingStats>, crate::GpuError> {
        let Some(r) = &frame.readback else {
            return Ok(None);
        };
        let bytes = crate::renderer::map_read(ctx, r)?;
        let words: &[u32] = bytemuck::cast_slice(&bytes);
        let u = &frame.uniform;
        let stride = u.max_per_tile as usize + 1;
        let tiles = (u.tiles_x * u.tiles_y) as usize;
        let (mut sum, mut max, mut overflowed, mut with_lights) = (0u64, 0u32, 0usize, 0usize);
        for t in 0..tiles {
            let count = words[t * stride];
            let n = if count == TILE_OVERFLOW {
                overflowed += 1;
                u.light_count
            } else {
                count
            };
            sum += n as u64;
            max = max.max(n);
            with_lights += usize::from(n > 0);
        }
        Ok(Some(CullingStats {
            tiles,
            lights: u.light_count,
            mean_lights: sum as f64 / tiles.max(1) as f64,
            max_lights: max,
            tiles_with_lights: with_lights,
            overflowed,
        }))
    }

    /// Records the culling pass, timed as `light culling` (nothing when
    /// culling is off).
    pub fn record(
        &self,
        device: &wgpu::Device,
        encoder: &mut wgpu::CommandEncoder,
        frame: &CullingFrame,
        depth: &wgpu::TextureView,
        timer: &crate::timing::GpuTimer,
    ) {
        if frame.uniform.enabled == 0 {
            return;
        }
        let (layout, pipeline) = self.pipeline(device);
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("light culling"),
            layout,
            entries: &[
                whole(0, &frame.uniform_buffer),
                whole(1, &frame.spheres),
                wgpu::BindGroupEntry {
                    binding: 2,
                    resource: wgpu::BindingResource::TextureView(depth),
                },
                whole(3, &frame.tile_lights),
            ],
        });
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("light culling"),
            timestamp_writes: timer.compute_pass("light culling"),
        });
        pass.set_pipeline(pipeline);
        pass.set_bind_group(0, &bind_group, &[]);
        pass.dispatch_workgroups(frame.uniform.tiles_x, frame.uniform.tiles_y, 1);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gpu::{LIGHT_POINT, LIGHT_SPOT};
    use glam::Vec3;

    #[test]
    fn spheres_are_in_view_space_and_unbounded_lights_are_marked() {
        let view = Mat4::from_translation(Vec3::new(0.0, 0.0, -5.0));
        let light = |kind, range| GpuLight {
            position: [1.0, 2.0, 3.0, 1.0],
            kind,
            range,
            ..Default::default()
        };
        let s = light_spheres(
            view,
            &[
                light(LIGHT_POINT, 2.0),
                light(LIGHT_SPOT, 4.0),
                light(LIGHT_POINT, 0.0),
                light(LIGHT_DIRECTIONAL, 3.0),
            ],
        );
        assert_eq!(s[0], [1.0, 2.0, -2.0, 2.0]);
        assert_eq!(s[1], [1.0, 2.0, -2.0, 4.0]);
        assert_eq!(s[2][3], -1.0);
        assert_eq!(s[3][3], -1.0);
    }
}
