//! Baked maps in the frame: an ambient-occlusion bake and an irradiance
//! bake (light map or radiosity), read back from penumbra-bake directories
//! ([`penumbra_bake::read_bake`]) and bound as group 2 of the geometry
//! passes; `lightmap.wgsl` looks them up per fragment. A bake is data: this
//! pass reads the manifest's atlas and pages and never calls the baker.
//!
//! Each bake has its own atlas, so its coordinates are stored per mesh
//! corner (3 per triangle, in the bake's layout) plus a rectangle per
//! instance; with bakes the meshes are drawn unwelded so that
//! `vertex_index` is the corner (see `SceneGpu::upload`).

use crate::context::GpuError;
use crate::gpu::{GpuBakeInstance, GpuBakeParams};
use crate::scene_data::SceneData;
use crate::scene_gpu::{buffer_init, storage_entry, uniform_entry, whole};
use penumbra_bake::{BakeKind, LoadedBake};
use penumbra_image::Image;
use penumbra_scene::Scene;

/// Index of the bind group the bakes use.
pub const BAKE_GROUP: u32 = 2;

/// The bakes a frame shows: at most one of each kind.
#[derive(Clone, Copy, Debug, Default)]
pub struct BakedMaps<'a> {
    /// Ambient occlusion: multiplies the ambient (environment) light.
    pub ao: Option<&'a LoadedBake>,
    /// Irradiance (light map or radiosity): the diffuse light.
    pub irradiance: Option<&'a LoadedBake>,
}

impl<'a> BakedMaps<'a> {
    /// Sorts `bakes` by kind; two of one kind are refused (two AO terms
    /// would multiply, two irradiance maps would count light twice).
    pub fn from_bakes(bakes: &'a [LoadedBake]) -> Result<Self, GpuError> {
        let mut out = Self::default();
        for b in bakes {
            let slot = if b.kind.is_irradiance() {
                &mut out.irradiance
            } else {
                &mut out.ao
            };
            if let Some(first) = slot {
                return Err(GpuError::Unsupported(format!(
                    "two {} bakes ({} and {}): give at most one ambient-occlusion bake and one irradiance bake (light map or radiosity)",
                    if b.kind.is_irradiance() {
                        "irradiance"
                    } else {
                        "ambient-occlusion"
                    },
                    first.dir.display(),
                    b.dir.display()
                )));
            }
            *slot = Some(b);
        }
        Ok(out)
    }

    pub fn is_empty(&self) -> bool {
        self.ao.is_none() && self.irradiance.is_none()
    }

    /// An irradiance bake that holds all light, direct included.
    pub fn has_full_irradiance(&self) -> bool {
        self.irradiance.is_some_and(|b| !b.kind.indirect_only())
    }

    pub(crate) fn params(&self) -> GpuBakeParams {
        GpuBakeParams {
            ao: self.ao.is_some() as u32,
            irradiance: self.irradiance.is_some() as u32,
            indirect_only: self.irradiance.is_some_and(|b| b.kind.indirect_only()) as u32,
            _pad0: 0,
        }
    }
}

/// The bind-group layout of the bakes (group [`BAKE_GROUP`]).
pub(crate) fn bake_layout(device: &wgpu::Device) -> wgpu::BindGroupLayout {
    let vf = wgpu::ShaderStages::VERTEX_FRAGMENT;
    let fragment = wgpu::ShaderStages::FRAGMENT;
    let pages = |binding| wgpu::BindGroupLayoutEntry {
        binding,
        visibility: fragment,
        ty: wgpu::BindingType::Texture {
            sample_type: wgpu::TextureSampleType::Float { filterable: false },
            view_dimension: wgpu::TextureViewDimension::D2Array,
            multisampled: false,
        },
        count: None,
    };
    device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("penumbra bakes"),
        entries: &[
            pages(0),
            storage_entry(1, vf, true),
            storage_entry(2, vf, true),
            pages(3),
            storage_entry(4, vf, true),
            storage_entry(5, vf, true),
            uniform_entry(6, vf),
        ],
    })
}

/// One bake on the GPU (or the 1×1 stand-ins of an absent one).
struct BakeGpu {
    pages: wgpu::TextureView,
    corners: wgpu::Buffer,
    instances: wgpu::Buffer,
}

/// The bakes of one frame, bound.
pub(crate) struct LightmapFrame {
    pub bind_group: wgpu::BindGroup,
}

impl LightmapFrame {
    pub fn new(
        ctx: &crate::GpuContext,
        layout: &wgpu::BindGroupLayout,
        maps: &BakedMaps<'_>,
        scene: &Scene,
        data: &SceneData,
    ) -> Result<Self, GpuError> {
        let device = &ctx.device;
        let ao = upload_bake(ctx, maps.ao, scene, data.instances.len())?;
        let irradiance = upload_bake(ctx, maps.irradiance, scene, data.instances.len())?;
        let params = maps.params();
        let params_buffer = buffer_init(
            device,
            "bake params",
            bytemuck::bytes_of(&params),
            wgpu::BufferUsages::UNIFORM,
        );
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("penumbra bakes"),
            layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: wgpu::BindingResource::TextureView(&ao.pages),
                },
                whole(1, &ao.corners),
                whole(2, &ao.instances),
                wgpu::BindGroupEntry {
                    binding: 3,
                    resource: wgpu::BindingResource::TextureView(&irradiance.pages),
                },
                whole(4, &irradiance.corners),
                whole(5, &irradiance.instances),
                whole(6, &params_buffer),
            ],
        });
        Ok(Self { bind_group })
    }
}

/// Uploads one bake's pages, corner coordinates and instance rectangles
/// (`instances` entries: the scene's instances, then the area lights'
/// emitters, which have no texels).
fn upload_bake(
    ctx: &crate::GpuContext,
    bake: Option<&LoadedBake>,
    scene: &Scene,
    instances: usize,
) -> Result<BakeGpu, GpuError> {
    let device = &ctx.device;
    let storage = wgpu::BufferUsages::STORAGE;
    let Some(bake) = bake else {
        return Ok(BakeGpu {
            pages: page_array(ctx, &[Image::new(1, 1)], "no bake")?,
            corners: buffer_init(device, "no bake corners", &[0u8; 8], storage),
            instances: buffer_init(
                device,
                "no bake instances",
                bytemuck::bytes_of(&GpuBakeInstance::default()),
                storage,
            ),
        });
    };
    let atlas = &bake.atlas;
    let mut corners: Vec<[f32; 2]> = Vec::new();
    let mut first_corner = vec![0u32; scene.meshes.len()];
    for (m, layout) in atlas.meshes.iter().enumerate() {
        let Some(layout) = layout else { continue };
        first_corner[m] = corners.len() as u32;
        corners.extend(layout.corner_uvs.iter().flatten().map(|c| c.to_array()));
    }
    if corners.is_empty() {
        corners.push([0.0; 2]);
    }
    let mut table = vec![GpuBakeInstance::default(); instances.max(1)];
    for (i, rect) in atlas.instances.iter().enumerate() {
        let Some(rect) = rect else { continue };
        let mesh = scene.instances[i].mesh;
        if atlas.meshes[mesh].is_none() {
            continue;
        }
        table[i] = GpuBakeInstance {
            uv_min: rect.min.to_array(),
            uv_max: rect.max.to_array(),
            first_corner: first_corner[mesh],
            page: rect.page,
            valid: 1,
            _pad0: 0,
        };
    }
    let what = match bake.kind {
        BakeKind::Ao { .. } => "ao bake",
        _ => "irradiance bake",
    };
    Ok(BakeGpu {
        pages: page_array(ctx, &bake.pages, what)?,
        corners: buffer_init(
            device,
            "bake corners",
            bytemuck::cast_slice(&corners),
            storage,
        ),
        instances: buffer_init(
            device,
            "bake instances",
            bytemuck::cast_slice(&table),
            storage,
        ),
    })
}

/// The pages as one `Rgba32Float` 2-D array texture (a = 1).
fn page_array(
    ctx: &crate::GpuContext,
    pages: &[Image],
    label: &str,
) -> Result<wgpu::TextureView, GpuError> {
    let limits = ctx.device.limits();
    let (w, h) = (pages[0].width, pages[0].height);
    if w > limits.max_texture_dimension_2d
        || h > limits.max_texture_dimension_2d
        || pages.len() as u32 > limits.max_texture_array_layers
    {
        return Err(GpuError::Unsupported(format!(
            "{label}: {} pages of {w}x{h} texels exceed the adapter's limits ({} per edge, {} layers); bake with a smaller --max-size",
            pages.len(),
            limits.max_texture_dimension_2d,
            limits.max_texture_array_layers
        )));
    }
    let size = wgpu::Extent3d {
        width: w,
        height: h,
        depth_or_array_layers: pages.len() as u32,
    };
    let texture = ctx.device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size,
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: wgpu::TextureFormat::Rgba32Float,
        usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
        view_formats: &[],
    });
    for (layer, page) in pages.iter().enumerate() {
        let texels: Vec<[f32; 4]> = page
            .pixels
            .iter()
            .map(|p| p.extend(1.0).to_array())
            .collect();
        ctx.queue.write_texture(
            wgpu::TexelCopyTextureInfo {
                texture: &texture,
                mip_level: 0,
                origin: wgpu::Origin3d {
                    x: 0,
                    y: 0,
                    z: layer as u32,
                },
                aspect: wgpu::TextureAspect::All,
            },
            bytemuck::cast_slice(&texels),
            wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(w * 16),
                rows_per_image: Some(h),
            },
            wgpu::Extent3d {
                width: w,
                height: h,
                depth_or_array_layers: 1,
            },
        );
    }
    Ok(texture.create_view(&wgpu::TextureViewDescriptor {
        dimension: Some(wgpu::TextureViewDimension::D2Array),
        ..Default::default()
    }))
}
