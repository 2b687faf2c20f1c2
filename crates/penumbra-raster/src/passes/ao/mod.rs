//! Screen-space ambient occlusion: kA(p) = (1/π) ∫Ω v(p, l)(n·l) dl (notes
//! 004) from the depth prepass, for the environment (ambient) term only.
//!
//! The frame's passes, each a compute pass timed by name:
//! 1. `ao inputs` (`inputs.wgsl`): the prepass's normal target (world
//!    normal and view distance per pixel; sample 0 under MSAA) becomes
//!    view-space normals and level 0 of a view-distance MIP chain;
//! 2. `ao depth mip` (×levels − 1): the chain's coarser levels (GTAO reads
//!    them for far horizon samples);
//! 3. `ssao hemisphere` (`hemisphere.wgsl`) or `gtao` (`gtao.wgsl`): raw kA
//!    per pixel, jittered by a 4×4 tile;
//! 4. `ao denoise` (`denoise.wgsl`): a depth-aware 4×4 mean.
//!
//! The result ([`AoTextures::ao`], `R32Float`, one value per pixel) is read
//! by the shading passes at their pixel: under MSAA every sample of a pixel
//! gets the kA computed from its sample 0.

mod settings;

pub use settings::{
    AoMethod, AoQuality, AoSettings, DEFAULT_RADIUS_FRACTION, GTAO_FALLOFF, default_radius,
    gtao_slice_visibility, hemisphere_kernel, jitter_tile,
};

use crate::gpu::GpuAoParams;
use crate::readback::TextureReadback;
use crate::scene_gpu::{buffer_init, whole};
use crate::shaders::{
    ao_denoise_source, ao_inputs_source, compute_pipeline, gtao_source, hemisphere_source,
};
use crate::timing::GpuTimer;
use glam::Mat4;

/// Levels of the view-distance MIP chain (XeGTAO uses 5).
pub const AO_MIP_LEVELS: u32 = 5;

/// Format of the prepass's normal target: world normal (xyz) and view
/// distance at the pixel centre (w; 0 where no surface).
pub const NORMAL_TARGET_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;

/// The AO passes' textures for one frame size.
#[derive(Debug)]
pub struct AoTextures {
    /// View distance (`R32Float`), [`AoTextures::levels`] MIP levels;
    /// 1e30 where no surface.
    pub view_depth: wgpu::Texture,
    /// View-space unit normals (`Rgba16Float`; 0 where no surface).
    pub normals: wgpu::Texture,
    /// kA before the denoise (`R32Float`).
    pub raw: wgpu::Texture,
    /// kA after the denoise (`R32Float`; 0 where no surface).
    pub ao: wgpu::Texture,
    pub width: u32,
    pub height: u32,
    pub levels: u32,
}

impl AoTextures {
    pub fn new(device: &wgpu::Device, width: u32, height: u32) -> Self {
        let levels = AO_MIP_LEVELS.min(32 - width.min(height).max(1).leading_zeros());
        let texture = |label, format, mips| {
            device.create_texture(&wgpu::TextureDescriptor {
                label: Some(label),
                size: wgpu::Extent3d {
                    width,
                    height,
                    depth_or_array_layers: 1,
                },
                mip_level_count: mips,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format,
                usage: wgpu::TextureUsages::STORAGE_BINDING
                    | wgpu::TextureUsages::TEXTURE_BINDING
                    | wgpu::TextureUsages::COPY_SRC
                    | wgpu::TextureUsages::COPY_DST,
                view_formats: &[],
            })
        };
        let r32 = wgpu::TextureFormat::R32Float;
        Self {
            view_depth: texture("ao view depth", r32, levels),
            normals: texture("ao normals", wgpu::TextureFormat::Rgba16Float, 1),
            raw: texture("ao raw", r32, 1),
            ao: texture("ao", r32, 1),
            width,
            height,
            levels,
        }
    }

    fn level(&self, level: u32) -> wgpu::TextureView {
        self.view_depth.create_view(&wgpu::TextureViewDescriptor {
            base_mip_level: level,
            mip_level_count: Some(1),
            ..Default::default()
        })
    }

    /// Copies kA (after the denoise) into a buffer to read after submit.
    pub fn record_readback(
        &self,
        device: &wgpu::Device,
        encoder: &mut wgpu::CommandEncoder,
    ) -> TextureReadback {
        let r = TextureReadback::new(device, self.width, self.height, 4);
        r.record(encoder, &self.ao, 0);
        r
    }
}

/// The AO pipelines for one method, quality and prepass sample count.
#[derive(Debug)]
pub struct ScreenSpaceAo {
    settings: AoSettings,
    inputs: wgpu::ComputePipeline,
    depth_mip: wgpu::ComputePipeline,
    main: wgpu::ComputePipeline,
    denoise: wgpu::ComputePipeline,
    /// The hemisphere kernel (one dummy point for GTAO).
    kernel: wgpu::Buffer,
}

fn texture_entry(binding: u32, view: &wgpu::TextureView) -> wgpu::BindGroupEntry<'_> {
    wgpu::BindGroupEntry {
        binding,
        resource: wgpu::BindingResource::TextureView(view),
    }
}

impl ScreenSpaceAo {
    /// `settings.method` must not be [`AoMethod::None`]; `prepass_samples`
    /// is the sample count of the prepass's normal target.
    pub fn new(device: &wgpu::Device, settings: AoSettings, prepass_samples: u32) -> Self {
        let (main, kernel) = match settings.method {
            AoMethod::Gtao | AoMethod::None => (
                compute_pipeline(device, &gtao_source(), "gtao"),
                vec![[0.0; 4]],
            ),
            AoMethod::Hemisphere => (
                compute_pipeline(device, &hemisphere_source(), "ssao_hemisphere"),
                hemisphere_kernel(settings.quality.hemisphere_samples()),
            ),
        };
        let inputs_source = ao_inputs_source(prepass_samples > 1);
        Self {
            settings,
            inputs: compute_pipeline(device, &inputs_source, "ao_inputs"),
            depth_mip: compute_pipeline(device, &inputs_source, "ao_depth_mip"),
            main,
            denoise: compute_pipeline(device, &ao_denoise_source(), "ao_denoise"),
            kernel: buffer_init(
                device,
                "ao kernel",
                bytemuck::cast_slice(&kernel),
                wgpu::BufferUsages::STORAGE,
            ),
        }
    }

    pub fn settings(&self) -> AoSettings {
        self.settings
    }

    /// The passes' constants for a frame: `view` and `proj` as the camera's
    /// ([`crate::camera::view_and_projection`]), `size` = (width, height),
    /// R in world units (`mip_levels` is set by [`Self::uniform`]).
    pub fn params(
        &self,
        view: Mat4,
        proj: Mat4,
        orthographic: bool,
        size: (u32, u32),
        radius: f32,
    ) -> GpuAoParams {
        let (width, height) = size;
        let (slices, steps) = self.settings.quality.gtao_slices_steps();
        GpuAoParams {
            view: view.to_cols_array_2d(),
            tile: jitter_tile(),
            proj_scale: [proj.x_axis.x, proj.y_axis.y],
            size: [width as f32, height as f32],
            radius,
            falloff: GTAO_FALLOFF,
            ortho: orthographic as u32,
            samples: self.settings.quality.hemisphere_samples(),
            slices,
            steps,
            mip_levels: 1,
            thin_occluders: self.settings.thin_occluders,
        }
    }

    /// Records every AO pass of a frame from the prepass's normal target
    /// (`prepass`, [`NORMAL_TARGET_FORMAT`], single- or multisampled as
    /// given to [`Self::new`]) into `textures` (kA in [`AoTextures::ao`]).
    pub fn record(
        &self,
        device: &wgpu::Device,
        encoder: &mut wgpu::CommandEncoder,
        prepass: &wgpu::TextureView,
        params: &GpuAoParams,
        textures: &AoTextures,
        timer: &GpuTimer,
    ) {
        let (w, h) = (textures.width, textures.height);
        let uniform = self.uniform(device, params, textures.levels);
        {
            let depth0 = textures.level(0);
            let normals = textures.normals.create_view(&Default::default());
            let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("ao inputs"),
                layout: &self.inputs.get_bind_group_layout(0),
                entries: &[
                    whole(0, &uniform),
                    texture_entry(1, prepass),
                    texture_entry(2, &depth0),
                    texture_entry(3, &normals),
                ],
            });
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("ao inputs"),
                timestamp_writes: timer.compute_pass("ao inputs"),
            });
            pass.set_pipeline(&self.inputs);
            pass.set_bind_group(0, &group, &[]);
            pass.dispatch_workgroups(w.div_ceil(8), h.div_ceil(8), 1);
        }
        self.record_depth_mips(device, encoder, textures, &uniform, 1, timer);
        self.record_main(device, encoder, textures, &uniform, timer);
    }

    /// The uniform buffer of `params` (its `mip_levels` set to `levels`).
    pub fn uniform(
        &self,
        device: &wgpu::Device,
        params: &GpuAoParams,
        levels: u32,
    ) -> wgpu::Buffer {
        let p = GpuAoParams {
            mip_levels: levels,
            ..*params
        };
        buffer_init(
            device,
            "ao params",
            bytemuck::bytes_of(&p),
            wgpu::BufferUsages::UNIFORM,
        )
    }

    /// Builds levels `first..` of the view-distance chain from the level
    /// below each.
    pub fn record_depth_mips(
        &self,
        device: &wgpu::Device,
        encoder: &mut wgpu::CommandEncoder,
        textures: &AoTextures,
        uniform: &wgpu::Buffer,
        first: u32,
        timer: &GpuTimer,
    ) {
        for level in first.max(1)..textures.levels {
            let (finer, coarser) = (textures.level(level - 1), textures.level(level));
            let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("ao depth mip"),
                layout: &self.depth_mip.get_bind_group_layout(0),
                entries: &[
                    whole(0, uniform),
                    texture_entry(4, &finer),
                    texture_entry(5, &coarser),
                ],
            });
            let (w, h) = (
                (textures.width >> level).max(1),
                (textures.height >> level).max(1),
            );
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("ao depth mip"),
                timestamp_writes: timer.compute_pass("ao depth mip"),
            });
            pass.set_pipeline(&self.depth_mip);
            pass.set_bind_group(0, &group, &[]);
            pass.dispatch_workgroups(w.div_ceil(8), h.div_ceil(8), 1);
        }
    }

    /// The method's pass and the denoise, on inputs already in `textures`
    /// (the view-distance chain and normals): writes `raw` and `ao`.
    pub fn record_main(
        &self,
        device: &wgpu::Device,
        encoder: &mut wgpu::CommandEncoder,
        textures: &AoTextures,
        uniform: &wgpu::Buffer,
        timer: &GpuTimer,
    ) {
        let (w, h) = (textures.width, textures.height);
        let depth = textures.view_depth.create_view(&Default::default());
        let normals = textures.normals.create_view(&Default::default());
        let raw = textures.raw.create_view(&Default::default());
        let ao = textures.ao.create_view(&Default::default());
        let mut entries = vec![
            whole(0, uniform),
            texture_entry(1, &depth),
            texture_entry(2, &normals),
            texture_entry(4, &raw),
        ];
        let name = match self.settings.method {
            AoMethod::Hemisphere => {
                entries.push(whole(3, &self.kernel));
                "ssao hemisphere"
            }
            _ => "gtao",
        };
        let main_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some(name),
            layout: &self.main.get_bind_group_layout(0),
            entries: &entries,
        });
        let depth0 = textures.level(0);
        let denoise_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("ao denoise"),
            layout: &self.denoise.get_bind_group_layout(0),
            entries: &[
                whole(0, uniform),
                texture_entry(1, &depth0),
                texture_entry(2, &normals),
                texture_entry(3, &raw),
                texture_entry(4, &ao),
            ],
        });
        for (label, pipeline, group) in [
            (name, &self.main, &main_group),
            ("ao denoise", &self.denoise, &denoise_group),
        ] {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some(label),
                timestamp_writes: timer.compute_pass(label),
            });
            pass.set_pipeline(pipeline);
            pass.set_bind_group(0, group, &[]);
            pass.dispatch_workgroups(w.div_ceil(8), h.div_ceil(8), 1);
        }
    }
}
