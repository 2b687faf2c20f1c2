//! Forward renderer: meshes and instances uploaded once per render, a depth
//! buffer (reversed z), one draw per instance into an `Rgba32Float` target at
//! the settings' resolution, read back into a [`penumbra_image::Image`].

use crate::context::{GpuContext, GpuError};
use crate::gpu::{GpuCamera, GpuInstance, GpuLight, GpuMaterial, GpuShadow, GpuShadowView};
use crate::shaders::forward_source;
use glam::{Mat4, Vec3, Vec4};
use penumbra_image::Image;
use penumbra_scene::Scene;
use penumbra_scene::camera::{Camera, Projection};
use std::time::Instant;
use wgpu::util::DeviceExt;

const COLOR_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;
const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;
/// Constant part of the shadow passes' depth bias, in units of the depth
/// format's precision at the triangle's depth.
const SHADOW_CONSTANT_BIAS: i32 = 16;

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

/// Default edge of a shadow map in texels.
pub const DEFAULT_SHADOW_MAP_SIZE: u32 = 2048;
/// Default slope-scaled depth bias of the shadow passes, in units of the
/// depth slope of the occluder's triangle per texel (rasteriser state).
pub const DEFAULT_SLOPE_BIAS: f32 = 1.5;
/// Default normal offset of the shadow lookup, in shadow-map texels.
pub const DEFAULT_NORMAL_OFFSET: f32 = 1.0;

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

/// Right-handed world-to-view transform of an eye at `eye` looking along
/// `dir` (view −z) with `up` roughly view +y.
fn look_to(eye: Vec3, dir: Vec3, up: Vec3) -> Mat4 {
    let f = dir.normalize();
    let s = f.cross(up).normalize();
    let u = s.cross(f);
    Mat4::from_cols(
        Vec4::new(s.x, u.x, -f.x, 0.0),
        Vec4::new(s.y, u.y, -f.y, 0.0),
        Vec4::new(s.z, u.z, -f.z, 0.0),
        Vec4::new(-s.dot(eye), -u.dot(eye), f.dot(eye), 1.0),
    )
}

/// The shadow-map views of the scene's lights: one [`GpuShadow`] per light
/// and one [`GpuShadowView`] per layer of the shadow-map array.
///
/// Every view stores reversed depth (1 near the light). Directional lights:
/// an orthographic view along the light fitted to the eight corners of the
/// scene bounds. Spot lights: an infinite reversed perspective along the
/// spot axis whose square frustum contains the outer cone (a cone wider than
/// 170° is clamped to 170°). Point lights: six 90° faces looking along ±x,
/// ±y, ±z (a depth "cube" stored as six array layers with their own
/// view-projections; the shader picks the face of the major axis). The
/// perspective frusta are widened by the PCF kernel's half-width plus a
/// texel so that taps near a face edge stay inside the face.
pub fn shadow_views(
    lights: &[penumbra_scene::SceneLight],
    bounds: (Vec3, Vec3),
    size: u32,
    pcf: u32,
    normal_offset: f32,
) -> (Vec<GpuShadow>, Vec<GpuShadowView>) {
    use penumbra_shading::light::Light;
    let (lo, hi) = bounds;
    let centre = 0.5 * (lo + hi);
    let radius = (0.5 * (hi - lo).length()).max(1e-4);
    let size_f = size as f32;
    let margin = (pcf / 2 + 1) as f32;
    let widen = size_f / (size_f - 2.0 * margin).max(1.0);
    let mut shadows = Vec::with_capacity(lights.len());
    let mut views = Vec::new();
    let up_for = |axis: Vec3| {
        if axis.y.abs() > 0.99 {
            Vec3::Z
        } else {
            Vec3::Y
        }
    };
    // Reversed infinite perspective (depth = near / distance along the axis).
    let perspective = |pos: Vec3, axis: Vec3, tan_half: f32| {
        let near = radius * 1e-4;
        let f = 1.0 / tan_half;
        let proj = Mat4::from_cols(
            Vec4::new(f, 0.0, 0.0, 0.0),
            Vec4::new(0.0, f, 0.0, 0.0),
            Vec4::new(0.0, 0.0, 0.0, -1.0),
            Vec4::new(0.0, 0.0, near, 0.0),
        );
        GpuShadowView {
            view_proj: (proj * look_to(pos, axis, up_for(axis))).to_cols_array_2d(),
            axis: axis.extend(0.0).to_array(),
        }
    };
    for l in lights {
        let first_layer = views.len() as u32;
        let mut sh = GpuShadow {
            first_layer,
            pcf,
            normal_offset,
            map_size: size_f,
            ..GpuShadow::default()
        };
        match &l.light {
            Light::Directional(d) => {
                let axis = d.direction.normalize();
                let eye = centre - axis * (2.0 * radius);
                let view = look_to(eye, axis, up_for(axis));
                let mut vlo = Vec3::splat(f32::INFINITY);
                let mut vhi = Vec3::splat(f32::NEG_INFINITY);
                for i in 0..8 {
                    let c = Vec3::new(
                        if i & 1 == 0 { lo.x } else { hi.x },
                        if i & 2 == 0 { lo.y } else { hi.y },
                        if i & 4 == 0 { lo.z } else { hi.z },
                    );
                    let v = view.transform_point3(c);
                    vlo = vlo.min(v);
                    vhi = vhi.max(v);
                }
                // A square texel grid over the fitted rectangle, a margin of
                // the PCF half-width around it.
                let extent = (vhi.x - vlo.x).max(vhi.y - vlo.y).max(1e-4) * widen;
                let mid = 0.5 * (vlo + vhi);
                let pad = 1e-3 * radius;
                let (zn, zf) = (vhi.z + pad, vlo.z - pad);
                let s = 2.0 / extent;
                let proj = Mat4::from_cols(
                    Vec4::new(s, 0.0, 0.0, 0.0),
                    Vec4::new(0.0, s, 0.0, 0.0),
                    Vec4::new(0.0, 0.0, 1.0 / (zn - zf), 0.0),
                    Vec4::new(-s * mid.x, -s * mid.y, -zf / (zn - zf), 1.0),
                );
                views.push(GpuShadowView {
                    view_proj: (proj * view).to_cols_array_2d(),
                    axis: axis.extend(0.0).to_array(),
                });
                sh.layer_count = 1;
                sh.texel = extent / size_f;
            }
            Light::Spot(sp) => {
                let c = sp.cos_outer.clamp(85f32.to_radians().cos(), 1.0 - 1e-6);
                let tan_half = (1.0 - c * c).sqrt() / c * widen;
                views.push(perspective(sp.position, sp.direction.normalize(), tan_half));
                sh.layer_count = 1;
                sh.perspective = 1;
                sh.texel = 2.0 * tan_half / size_f;
            }
            Light::Point(pt) => {
                for axis in [
                    Vec3::X,
                    Vec3::NEG_X,
                    Vec3::Y,
                    Vec3::NEG_Y,
                    Vec3::Z,
                    Vec3::NEG_Z,
                ] {
                    views.push(perspective(pt.position, axis, widen));
                }
                sh.layer_count = 6;
                sh.perspective = 1;
                sh.texel = 2.0 * widen / size_f;
            }
        }
        shadows.push(sh);
    }
    (shadows, views)
}

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
    /// GPU time of the forward pass from timestamp queries [ms], where the
    /// adapter supports them.
    pub gpu_pass_ms: Option<f64>,
    /// GPU time of each shadow pass (one per shadow-map layer: one per
    /// directional or spot light, six per point light) [ms], where the
    /// adapter supports timestamp queries; empty otherwise.
    pub shadow_pass_ms: Vec<f64>,
    /// What the raster path approximated for this scene (see [`SceneData`]).
    pub warnings: Vec<String>,
}

/// The scene as the forward pass sees it, and what it approximates.
#[derive(Clone, Debug, Default)]
pub struct SceneData {
    pub lights: Vec<GpuLight>,
    pub materials: Vec<GpuMaterial>,
    pub instances: Vec<GpuInstance>,
    /// What the raster path renders differently from the CPU `local`
    /// integrator for this scene.
    pub warnings: Vec<String>,
}

impl SceneData {
    pub fn from_scene(scene: &Scene) -> Self {
        let mut warnings = Vec::new();
        let mut materials = Vec::with_capacity(scene.materials.len());
        for m in &scene.materials {
            let (g, exact) = GpuMaterial::from_bsdf(&m.bsdf, m.emission, m.double_sided);
            if !exact {
                warnings.push(format!(
                    "raster: material '{}' ({}) has no WGSL twin yet; shaded as Lambert with its albedo",
                    m.name,
                    bsdf_name(&m.bsdf)
                ));
            }
            if m.albedo_texture.is_some() || m.metallic_roughness_texture.is_some() {
                warnings.push(format!(
                    "raster: material '{}': textures are ignored (untextured factors used)",
                    m.name
                ));
            }
            materials.push(g);
        }
        if materials.is_empty() {
            // Storage bindings cannot be empty.
            materials.push(GpuMaterial::default());
        }
        let instances = scene
            .instances
            .iter()
            .map(|inst| {
                let material = inst.material.unwrap_or(scene.meshes[inst.mesh].material);
                GpuInstance::new(
                    inst.transform,
                    inst.normal_matrix(),
                    material as u32,
                    scene.meshes[inst.mesh].normals.is_some(),
                )
            })
            .collect();
        let lights: Vec<GpuLight> = scene
            .lights
            .iter()
            .map(|l| GpuLight::from_light(&l.light))
            .collect();
        if !scene.area_lights.is_empty() {
            warnings.push(format!(
                "raster: {} analytic area light(s) are neither drawn nor lit from (abstract lights only)",
                scene.area_lights.len()
            ));
        }
        if scene.materials.iter().any(|m| m.is_emissive()) {
            warnings.push(
                "raster: emissive surfaces are drawn with their emission but do not light other surfaces"
                    .to_string(),
            );
        }
        if scene.environment_map.is_some() {
            warnings.push(
                "raster: the environment map is not drawn or lit from; the background colour is used"
                    .to_string(),
            );
        }
        Self {
            lights,
            materials,
            instances,
            warnings,
        }
    }
}

fn bsdf_name(b: &penumbra_shading::bsdf::Bsdf) -> &'static str {
    use penumbra_shading::bsdf::Bsdf;
    match b {
        Bsdf::Lambert(_) => "Lambert",
        Bsdf::PhongBlinn(_) => "Phong-Blinn",
        Bsdf::Mirror(_) => "mirror",
        Bsdf::Conductor(_) => "conductor",
        Bsdf::Dielectric(_) => "dielectric",
        Bsdf::RoughConductor(_) => "rough conductor",
        Bsdf::RoughDielectric(_) => "rough dielectric",
        Bsdf::MetallicRoughness(_) => "metallic-roughness",
    }
}

/// View-projection of `camera` for a `width`×`height` image with reversed
/// depth (1 at the near plane, 0 at the far plane or infinity). Pixel
/// centres map to the same points as `Camera::generate_ray(x + ½, y + ½)`:
/// both use NDC x = 2 sx / width − 1, y = 1 − 2 sy / height.
pub fn view_projection(camera: &Camera, width: u32, height: u32, bounds: (Vec3, Vec3)) -> Mat4 {
    let aspect = width as f32 / height as f32;
    let view = camera.camera_to_world.inverse();
    let (lo, hi) = bounds;
    let centre = 0.5 * (lo + hi);
    let radius = (0.5 * (hi - lo).length()).max(1e-6);
    let proj = match camera.projection {
        Projection::Perspective { fov_y } => {
            let dist = (camera.position() - centre).length();
            // Reversed float depth keeps precision far away, so the near
            // plane can sit well in front of the scene.
            let near = ((dist - radius) * 0.5).max(radius * 1e-5).max(1e-6);
            // Right-handed, infinite far plane, depth = near / −z_view.
            let f = 1.0 / (0.5 * fov_y).tan();
            Mat4::from_cols(
                Vec4::new(f / aspect, 0.0, 0.0, 0.0),
                Vec4::new(0.0, f, 0.0, 0.0),
                Vec4::new(0.0, 0.0, 0.0, -1.0),
                Vec4::new(0.0, 0.0, near, 0.0),
            )
        }
        Projection::Orthographic { height } => {
            // Rays start on the camera plane (z = 0), as the CPU's.
            let z_centre = view.transform_point3(centre).z;
            let far = (-z_centre + radius) * 1.01 + 1e-4;
            let far = far.max(1e-4);
            Mat4::from_cols(
                Vec4::new(2.0 / (height * aspect), 0.0, 0.0, 0.0),
                Vec4::new(0.0, 2.0 / height, 0.0, 0.0),
                Vec4::new(0.0, 0.0, 1.0 / far, 0.0),
                Vec4::new(0.0, 0.0, 1.0, 1.0),
            )
        }
    };
    proj * view
}

/// The camera constants of a frame.
pub fn gpu_camera(
    camera: &Camera,
    width: u32,
    height: u32,
    bounds: (Vec3, Vec3),
    light_count: u32,
) -> GpuCamera {
    let back = camera
        .camera_to_world
        .transform_vector3(Vec3::Z)
        .normalize();
    let ortho = matches!(camera.projection, Projection::Orthographic { .. });
    GpuCamera {
        view_proj: view_projection(camera, width, height, bounds).to_cols_array_2d(),
        eye: camera.position().extend(1.0).to_array(),
        back: back.extend(if ortho { 1.0 } else { 0.0 }).to_array(),
        light_count,
        ..GpuCamera::default()
    }
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

        let timestamps = device.features().contains(wgpu::Features::TIMESTAMP_QUERY);
        // Queries 0, 1: the forward pass; 2 + 2l, 3 + 2l: shadow layer l.
        let query_count = 2 + 2 * layers;
        let query_bytes = 8 * query_count as u64;
        let query = timestamps.then(|| {
            let set = device.create_query_set(&wgpu::QuerySetDescriptor {
                label: Some("forward and shadow passes"),
                ty: wgpu::QueryType::Timestamp,
                count: query_count,
            });
            let resolve = device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("timestamps"),
                size: query_bytes,
                usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
                mapped_at_creation: false,
            });
            let read = device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("timestamps read"),
                size: query_bytes,
                usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            });
            (set, resolve, read)
        });

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
                timestamp_writes: query.as_ref().map(|(set, _, _)| {
                    wgpu::RenderPassTimestampWrites {
                        query_set: set,
                        beginning_of_pass_write_index: Some(2 + 2 * layer),
                        end_of_pass_write_index: Some(3 + 2 * layer),
                    }
                }),
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
                timestamp_writes: query.as_ref().map(|(set, _, _)| {
                    wgpu::RenderPassTimestampWrites {
                        query_set: set,
                        beginning_of_pass_write_index: Some(0),
                        end_of_pass_write_index: Some(1),
                    }
                }),
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
        if let Some((set, resolve, read)) = &query {
            encoder.resolve_query_set(set, 0..query_count, resolve, 0);
            encoder.copy_buffer_to_buffer(resolve, 0, read, 0, query_bytes);
        }
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
        let (gpu_pass_ms, shadow_pass_ms) = match &query {
            Some((_, _, read)) => {
                let ts = map_read(ctx, read)?;
                let t: &[u64] = bytemuck::cast_slice(&ts);
                let period = ctx.queue.get_timestamp_period() as f64;
                let ms = |a: usize| t[a + 1].saturating_sub(t[a]) as f64 * period * 1e-6;
                (
                    Some(ms(0)),
                    (0..layers as usize).map(|l| ms(2 + 2 * l)).collect(),
                )
            }
            None => (None, Vec::new()),
        };
        let image =
            Image::from_pixels(width, height, pixels).map_err(|e| GpuError::Wgpu(e.to_string()))?;
        Ok(RasterOutput {
            image,
            total_ms: start.elapsed().as_secs_f64() * 1e3,
            frame_ms,
            gpu_pass_ms,
            shadow_pass_ms,
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

#[cfg(test)]
mod tests {
    use super::*;
    use penumbra_scene::{Material, SceneAreaLight, primitives};
    use penumbra_shading::bsdf::{Bsdf, Mirror};
    use penumbra_shading::light::{AreaLight, Shape};

    fn project(v: &GpuShadowView, p: Vec3) -> Vec3 {
        let c = Mat4::from_cols_array_2d(&v.view_proj) * p.extend(1.0);
        c.truncate() / c.w
    }

    #[test]
    fn shadow_views_cover_the_scene_and_the_cones() {
        use penumbra_scene::SceneLight;
        use penumbra_shading::light::{DirectionalLight, Light, PointLight, SpotLight};
        let bounds = (Vec3::new(-3.0, 0.0, -2.0), Vec3::new(4.0, 2.0, 5.0));
        let spot = SpotLight {
            position: Vec3::new(0.0, 5.0, 0.0),
            direction: Vec3::new(0.3, -1.0, 0.1).normalize(),
            intensity: Vec3::ONE,
            cos_inner: 0.95,
            cos_outer: 0.8,
        };
        let lights = [
            Light::Directional(DirectionalLight {
                direction: Vec3::new(0.5, -1.0, 0.2).normalize(),
                irradiance: Vec3::ONE,
            }),
            Light::Spot(spot),
            Light::Point(PointLight {
                position: Vec3::new(1.0, 3.0, 1.0),
                intensity: Vec3::ONE,
            }),
        ]
        .map(|light| SceneLight {
            name: String::new(),
            light,
        });
        let (sh, views) = shadow_views(&lights, bounds, 1024, 3, 1.0);
        assert_eq!(views.len(), 8);
        let layers: Vec<_> = sh.iter().map(|s| (s.first_layer, s.layer_count)).collect();
        assert_eq!(layers, [(0, 1), (1, 1), (2, 6)]);
        // Directional: every corner of the bounds inside the map, depth in
        // [0, 1], nearer the light = larger (reversed) depth.
        let (lo, hi) = bounds;
        for i in 0..8 {
            let c = Vec3::new(
                if i & 1 == 0 { lo.x } else { hi.x },
                if i & 2 == 0 { lo.y } else { hi.y },
                if i & 4 == 0 { lo.z } else { hi.z },
            );
            let n = project(&views[0], c);
            assert!(n.x.abs() < 1.0 && n.y.abs() < 1.0, "{n}");
            assert!(n.z > 0.0 && n.z < 1.0, "{n}");
        }
        let d = Vec3::new(0.5, -1.0, 0.2).normalize();
        let centre = 0.5 * (lo + hi);
        assert!(project(&views[0], centre - d).z > project(&views[0], centre + d).z);
        // Spot: directions on the outer cone project inside the map.
        let frame = frame_of(spot.direction);
        let sin = (1.0 - spot.cos_outer * spot.cos_outer).sqrt();
        for k in 0..16 {
            let a = k as f32 * std::f32::consts::TAU / 16.0;
            let w = spot.cos_outer * spot.direction + sin * (a.cos() * frame.0 + a.sin() * frame.1);
            let n = project(&views[1], spot.position + 2.0 * w);
            assert!(n.x.abs() < 1.0 && n.y.abs() < 1.0, "{n}");
        }
        // Point: every direction lands inside the face of its major axis.
        let pos = Vec3::new(1.0, 3.0, 1.0);
        for w in [
            Vec3::new(0.9, 0.89, -0.5),
            Vec3::new(-1.0, 0.2, 0.99),
            Vec3::new(0.1, 1.0, 0.3),
            Vec3::new(0.5, -1.0, -0.9),
            Vec3::new(0.2, 0.3, 1.0),
            Vec3::new(-0.99, 0.1, -1.0),
        ] {
            let a = w.abs();
            let face = if a.x >= a.y && a.x >= a.z {
                if w.x >= 0.0 { 0 } else { 1 }
            } else if a.y >= a.z {
                if w.y >= 0.0 { 2 } else { 3 }
            } else if w.z >= 0.0 {
                4
            } else {
                5
            };
            let n = project(&views[2 + face], pos + w);
            assert!(n.x.abs() < 1.0 && n.y.abs() < 1.0, "{w}: {n}");
            assert!(n.z > 0.0 && n.z < 1.0, "{w}: {n}");
        }
    }

    fn frame_of(n: Vec3) -> (Vec3, Vec3) {
        let t = n
            .cross(if n.x.abs() < 0.9 { Vec3::X } else { Vec3::Y })
            .normalize();
        (t, n.cross(t))
    }

    #[test]
    fn scene_data_warns_about_what_it_approximates() {
        let mut scene = Scene::default();
        let lambert = scene.add_material(Material::lambert("white", Vec3::ONE));
        let mut mesh = primitives::sphere(Vec3::ZERO, 1.0, 4);
        mesh.material = lambert;
        scene.add_mesh(mesh, Mat4::IDENTITY);
        let data = SceneData::from_scene(&scene);
        assert!(data.warnings.is_empty(), "{:?}", data.warnings);
        assert_eq!((data.instances.len(), data.materials.len()), (1, 1));

        scene.add_material(Material {
            bsdf: Bsdf::Mirror(Mirror::new(Vec3::ONE)),
            ..Material::lambert("chrome", Vec3::ONE)
        });
        scene.add_material(Material::emitter("lamp", Vec3::splat(5.0)));
        scene.area_lights.push(SceneAreaLight {
            name: "ball".into(),
            light: AreaLight {
                shape: Shape::Sphere {
                    center: Vec3::Y,
                    radius: 0.1,
                },
                radiance: Vec3::ONE,
                two_sided: false,
            },
        });
        let w = SceneData::from_scene(&scene).warnings.join("\n");
        assert!(w.contains("'chrome' (mirror)"), "{w}");
        assert!(w.contains("area light"), "{w}");
        assert!(w.contains("emissive"), "{w}");
    }
}
