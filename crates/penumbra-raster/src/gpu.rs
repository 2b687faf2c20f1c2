//! `#[repr(C)]` structs shared with the WGSL shaders, their conversion from
//! the scene model, and a description of their layouts ([`GPU_STRUCTS`]) that
//! the tests compare with the WGSL structs as naga lays them out.

use bytemuck::{Pod, Zeroable};
use glam::{Mat3, Mat4, Vec3};
use penumbra_shading::bsdf::{Bsdf, FresnelModel, PhongVariant};
use penumbra_shading::light::{FarField, Light};
use std::mem::{offset_of, size_of};

/// Light kinds (`GpuLight::kind`), as the WGSL constants `LIGHT_*`.
pub const LIGHT_POINT: u32 = 0;
pub const LIGHT_DIRECTIONAL: u32 = 1;
pub const LIGHT_SPOT: u32 = 2;
/// The far-field point light of an analytic area light
/// ([`penumbra_shading::light::FarField`]).
pub const LIGHT_AREA: u32 = 3;

/// `GpuLight::flags`: an area light's far field emits on both sides.
pub const LIGHT_TWO_SIDED: u32 = 1;

/// Material models (`GpuMaterial::model`), as the WGSL constants `MODEL_*`.
pub const MODEL_LAMBERT: u32 = 0;
pub const MODEL_PHONG_BLINN: u32 = 1;
pub const MODEL_ROUGH_CONDUCTOR: u32 = 2;
pub const MODEL_ROUGH_DIELECTRIC: u32 = 3;
pub const MODEL_METALLIC_ROUGHNESS: u32 = 4;
/// Mirror, Conductor, Dielectric: delta lobes only, `eval` ≡ 0.
pub const MODEL_DELTA: u32 = 5;

/// Fresnel of a rough conductor (`GpuMaterial::variant`), as WGSL `FRESNEL_*`.
pub const FRESNEL_EXACT: u32 = 0;
pub const FRESNEL_SCHLICK: u32 = 1;

/// An abstract light in the notes' homogeneous form (WGSL `GpuLight`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GpuLight {
    /// (y, w): w = 1 position of a point or spot light, w = 0 unit direction
    /// towards a directional light.
    pub position: [f32; 4],
    /// M: intensity [W/sr] (w = 1) or irradiance [W/m²] (w = 0).
    pub m: [f32; 3],
    pub kind: u32,
    /// Spot lights: unit direction of travel on the axis. Area lights: the
    /// emitter's front normal (zero: isotropic, a sphere).
    pub spot_direction: [f32; 3],
    pub cos_inner: f32,
    pub cos_outer: f32,
    /// Range cut-off distance of point and spot lights (window
    /// `clamp(1 − (d/range)⁴, 0, 1)²`); 0 = no cut-off (shaders need not
    /// handle infinities).
    pub range: f32,
    /// [`LIGHT_TWO_SIDED`] for two-sided area lights.
    pub flags: u32,
    pub _pad2: f32,
}

impl GpuLight {
    /// The GPU form of a scene light, through the Rust light's own
    /// homogeneous form (so the directional normalisation is the same).
    pub fn from_light(light: &Light) -> Self {
        let h = light.homogeneous();
        let range = light.range();
        let mut out = Self {
            position: h.position.to_array(),
            m: h.m.to_array(),
            range: if range.is_finite() { range } else { 0.0 },
            ..Self::default()
        };
        match light {
            Light::Point(_) => out.kind = LIGHT_POINT,
            Light::Directional(_) => out.kind = LIGHT_DIRECTIONAL,
            Light::Spot(s) => {
                out.kind = LIGHT_SPOT;
                out.spot_direction = s.direction.to_array();
                out.cos_inner = s.cos_inner;
                out.cos_outer = s.cos_outer;
            }
        }
        out
    }

    /// `position.xyz`: the light's position (w = 1), or the direction
    /// towards it (w = 0).
    pub fn xyz(&self) -> Vec3 {
        Vec3::new(self.position[0], self.position[1], self.position[2])
    }

    /// The GPU form of an area light's far field: a point light (w = 1)
    /// whose intensity follows the emitter's lobe.
    pub fn from_far_field(f: &FarField) -> Self {
        Self {
            position: f.position.extend(1.0).to_array(),
            m: f.intensity.to_array(),
            kind: LIGHT_AREA,
            spot_direction: f.axis.to_array(),
            flags: if f.two_sided { LIGHT_TWO_SIDED } else { 0 },
            ..Self::default()
        }
    }
}

/// A material as the raster path shades it (WGSL `GpuMaterial`): the
/// parameters of every model's `eval` twin (a field is 0 where the model
/// does not use it), plus emission.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GpuMaterial {
    pub model: u32,
    /// Phong–Blinn: `PHONG_*` ([`phong_variant_index`]); rough conductor:
    /// [`FRESNEL_EXACT`] or [`FRESNEL_SCHLICK`].
    pub variant: u32,
    /// Phong–Blinn exponent.
    pub shininess: f32,
    pub double_sided: u32,
    /// Lambert and Phong–Blinn diffuse coefficient kd = ρ/π [1/sr].
    pub kd: [f32; 3],
    /// GGX α of the rough conductor and dielectric (clamped as `Ggx::new`
    /// clamps it) and of metallic–roughness (`roughness²`).
    pub alpha: f32,
    /// Phong–Blinn specular coefficient.
    pub ks: [f32; 3],
    /// Rough dielectric η = n_inside / n_outside; metallic–roughness ior.
    pub ior: f32,
    pub emission: [f32; 3],
    /// Metallic–roughness perceptual roughness, clamped to [0, 1].
    pub roughness: f32,
    /// Metallic–roughness base colour; rough dielectric transmission tint.
    pub base_color: [f32; 3],
    /// Metallic–roughness metallic, clamped to [0, 1].
    pub metallic: f32,
    /// KHR_materials_specular `specularColorFactor`.
    pub specular_color: [f32; 3],
    /// KHR_materials_transmission factor, clamped to [0, 1].
    pub transmission: f32,
    /// Rough conductor n per band (the real part of the complex index).
    pub conductor_eta: [f32; 3],
    /// KHR_materials_specular `specularFactor`, clamped to [0, 1].
    pub specular: f32,
    /// Rough conductor κ per band.
    pub conductor_k: [f32; 3],
    /// 1: camera rays (the shading passes) do not see the back faces
    /// (glTF `doubleSided: false`).
    pub cull_back_faces: u32,
}

/// WGSL index of a Phong–Blinn variant (`PHONG_*`).
pub fn phong_variant_index(v: PhongVariant) -> u32 {
    match v {
        PhongVariant::Notes => 0,
        PhongVariant::MaxBlinn => 1,
        PhongVariant::HalfwaySquared => 2,
        PhongVariant::Normalized => 3,
    }
}

impl GpuMaterial {
    /// The BSDF the raster path evaluates for `bsdf`: its WGSL
    /// `material_eval` twin equals `Bsdf::eval`. Every model has a twin: Lambert, Phong–Blinn, the GGX rough conductor, rough
    /// dielectric and metallic–roughness, and the delta models (Mirror,
    /// Conductor, Dielectric), whose `eval` is 0. A surface seen from its back
    /// goes through WGSL `material_seen_from_back` (Rust `seen_from_back`).
    pub fn from_bsdf(bsdf: &Bsdf, emission: Vec3, double_sided: bool) -> Self {
        let mut m = Self {
            emission: emission.to_array(),
            double_sided: double_sided as u32,
            ..Self::default()
        };
        match bsdf {
            Bsdf::Lambert(l) => {
                m.model = MODEL_LAMBERT;
                m.kd = l.kd().to_array();
            }
            Bsdf::PhongBlinn(p) => {
                m.model = MODEL_PHONG_BLINN;
                m.variant = phong_variant_index(p.variant);
                m.kd = p.kd.to_array();
                m.ks = p.ks.to_array();
                m.shininess = p.shininess;
            }
            Bsdf::RoughConductor(c) => {
                m.model = MODEL_ROUGH_CONDUCTOR;
                m.variant = match c.fresnel {
                    FresnelModel::Exact => FRESNEL_EXACT,
                    FresnelModel::Schlick => FRESNEL_SCHLICK,
                };
                m.conductor_eta = c.eta.to_array();
                m.conductor_k = c.k.to_array();
                m.alpha = c.ggx().alpha();
            }
            Bsdf::RoughDielectric(d) => {
                m.model = MODEL_ROUGH_DIELECTRIC;
                m.ior = d.eta;
                m.alpha = d.ggx().alpha();
                m.base_color = d.tint.to_array();
            }
            Bsdf::MetallicRoughness(mr) => {
                m.model = MODEL_METALLIC_ROUGHNESS;
                m.base_color = mr.base_color.to_array();
                m.metallic = mr.metallic.clamp(0.0, 1.0);
                m.roughness = mr.roughness.clamp(0.0, 1.0);
                m.alpha = mr.alpha();
                m.ior = mr.ior;
                m.transmission = mr.transmission.clamp(0.0, 1.0);
                m.specular = mr.specular.clamp(0.0, 1.0);
                m.specular_color = mr.specular_color.to_array();
            }
            Bsdf::Mirror(_) | Bsdf::Conductor(_) | Bsdf::Dielectric(_) => {
                m.model = MODEL_DELTA;
            }
        }
        m
    }
}

/// Camera and frame constants (WGSL `GpuCamera`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GpuCamera {
    pub view_proj: [[f32; 4]; 4],
    pub eye: [f32; 4],
    /// Camera +z in world space; w = 1 for orthographic cameras.
    pub back: [f32; 4],
    pub light_count: u32,
    pub _pad0: u32,
    pub _pad1: u32,
    pub _pad2: u32,
}

/// Per-instance data (WGSL `GpuInstance`), indexed by `instance_index`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GpuInstance {
    pub model: [[f32; 4]; 4],
    pub normal: [[f32; 4]; 4],
    pub material: u32,
    pub has_normals: u32,
    pub flip_winding: u32,
    /// 1: the emitter of an analytic area light, which is a light and not
    /// a surface (the `ao` integrator gives it kA = 0).
    pub light_shape: u32,
    /// Index of the mesh's first vertex in the texture-coordinate (UV set
    /// 0), vertex-colour and tangent buffers, and of its UV set 1 in the
    /// texture-coordinate buffer; [`NO_VERTEX_DATA`]: the mesh has none.
    pub first_uv: u32,
    pub first_color: u32,
    pub first_tangent: u32,
    pub first_uv1: u32,
}

/// [`GpuInstance::first_uv`] / [`GpuInstance::first_color`] of a mesh
/// without that attribute; [`GpuMaterialTextures`] without that texture.
pub const NO_VERTEX_DATA: u32 = u32::MAX;
/// A texture slot of [`GpuMaterialTextures`] that holds none.
pub const NO_TEXTURE: u32 = u32::MAX;

/// One texture in the texel buffer (WGSL `GpuTexture`): its mip chain,
/// level 0 first, each level row-major from the top row (glTF's v = 0).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GpuTexture {
    /// KHR_texture_transform: u' = u_row · (u, v, 1), v' = v_row · (u, v, 1).
    pub u_row: [f32; 4],
    pub v_row: [f32; 4],
    /// Size of level 0 (level l: max(1, size >> l)).
    pub width: u32,
    pub height: u32,
    pub levels: u32,
    /// Index in the texel buffer (of words) of level 0's first texel.
    pub first: u32,
    /// Wrap modes along u and v: [`WRAP_REPEAT`], [`WRAP_CLAMP`], [`WRAP_MIRROR`].
    pub wrap_u: u32,
    pub wrap_v: u32,
    /// [`crate::textures::TexelFormat`] of every level.
    pub format: u32,
    /// The UV set the texture reads (0 or 1, [`penumbra_scene::Texture::uv_set`]).
    pub uv_set: u32,
}

pub const WRAP_REPEAT: u32 = 0;
pub const WRAP_CLAMP: u32 = 1;
pub const WRAP_MIRROR: u32 = 2;

/// The textures of one material (WGSL `GpuMaterialTextures`), indices into
/// the texture table or [`NO_TEXTURE`].
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct GpuMaterialTextures {
    pub albedo: u32,
    pub metallic_roughness: u32,
    pub emission: u32,
    /// Tangent-space normal map, and its `scale` (x and y of the mapped
    /// normal).
    pub normal: u32,
    pub normal_scale: f32,
    /// Baked ambient occlusion (R) and its strength: the environment term
    /// times `1 + strength · (R − 1)`.
    pub occlusion: u32,
    pub occlusion_strength: f32,
    /// Coverage (glTF alphaMode): [`ALPHA_OPAQUE`], [`ALPHA_MASK`] or
    /// [`ALPHA_BLEND`]; α = `alpha_factor` × the R channel of
    /// `alpha_texture` (the base colour's alpha).
    pub alpha_mode: u32,
    pub alpha_texture: u32,
    pub alpha_factor: f32,
    /// MASK: fragments with α < cutoff are discarded.
    pub alpha_cutoff: f32,
    pub _pad0: u32,
}

pub const ALPHA_OPAQUE: u32 = 0;
pub const ALPHA_MASK: u32 = 1;
pub const ALPHA_BLEND: u32 = 2;

/// Bits of the forward shaders' `TEXTURE_SLOTS` constant, one per slot of
/// [`GpuMaterialTextures`]: a pipeline reads only the slots its scene's
/// materials fill (a software rasteriser runs both sides of a branch, so
/// lookups no material needs would still cost every fragment).
pub const SLOT_ALBEDO: u32 = 1 << 0;
pub const SLOT_METALLIC_ROUGHNESS: u32 = 1 << 1;
pub const SLOT_EMISSION: u32 = 1 << 2;
pub const SLOT_NORMAL: u32 = 1 << 3;
pub const SLOT_OCCLUSION: u32 = 1 << 4;
pub const SLOT_ALPHA: u32 = 1 << 5;

impl GpuMaterialTextures {
    /// The `SLOT_*` bits of the slots that hold a texture.
    pub fn slot_mask(&self) -> u32 {
        [
            (self.albedo, SLOT_ALBEDO),
            (self.metallic_roughness, SLOT_METALLIC_ROUGHNESS),
            (self.emission, SLOT_EMISSION),
            (self.normal, SLOT_NORMAL),
            (self.occlusion, SLOT_OCCLUSION),
            (self.alpha_texture, SLOT_ALPHA),
        ]
        .into_iter()
        .filter(|&(t, _)| t != NO_TEXTURE)
        .fold(0, |m, (_, bit)| m | bit)
    }
}

impl Default for GpuMaterialTextures {
    fn default() -> Self {
        Self {
            albedo: NO_TEXTURE,
            metallic_roughness: NO_TEXTURE,
            emission: NO_TEXTURE,
            normal: NO_TEXTURE,
            normal_scale: 1.0,
            occlusion: NO_TEXTURE,
            occlusion_strength: 1.0,
            alpha_mode: ALPHA_OPAQUE,
            alpha_texture: NO_TEXTURE,
            alpha_factor: 1.0,
            alpha_cutoff: 0.0,
            _pad0: 0,
        }
    }
}

impl GpuInstance {
    pub fn new(transform: Mat4, normal_matrix: Mat3, material: u32, has_normals: bool) -> Self {
        Self {
            model: transform.to_cols_array_2d(),
            normal: Mat4::from_mat3(normal_matrix).to_cols_array_2d(),
            material,
            has_normals: has_normals as u32,
            flip_winding: (Mat3::from_mat4(transform).determinant() < 0.0) as u32,
            light_shape: 0,
            first_uv: NO_VERTEX_DATA,
            first_color: NO_VERTEX_DATA,
            first_tangent: NO_VERTEX_DATA,
            first_uv1: NO_VERTEX_DATA,
        }
    }
}

/// How one light is shadowed (WGSL `GpuShadow`), indexed like the lights.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GpuShadow {
    /// First layer of the light's views in the shadow-map array.
    pub first_layer: u32,
    /// 0: not shadowed; 1: one view (directional, spot); 6: the six cube
    /// faces of a point light (+x, −x, +y, −y, +z, −z).
    pub layer_count: u32,
    /// PCF kernel edge N (N×N taps, 1 = one hard tap).
    pub pcf: u32,
    /// 1 for perspective views (spot, point), 0 orthographic (directional).
    pub perspective: u32,
    /// World size of one texel: orthographic views its size, perspective
    /// views its size per unit of distance along the view axis.
    pub texel: f32,
    /// Normal offset of the lookup point in texels (scaled by `texel`).
    pub normal_offset: f32,
    /// Edge of the shadow map in texels.
    pub map_size: f32,
    pub _pad0: f32,
}

/// One depth-only view of a light (WGSL `GpuShadowView`), one per layer.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GpuShadowView {
    /// World to clip, reversed depth (1 near the light, 0 far from it).
    pub view_proj: [[f32; 4]; 4],
    /// Unit view axis (direction the view looks along), w unused.
    pub axis: [f32; 4],
}

/// Tiled light culling (WGSL `GpuCulling`): the screen is cut into
/// `TILE`×`TILE`-pixel tiles, each with a list of the lights whose range
/// sphere meets the tile's slice of the view frustum (see
/// `light_culling.rs`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GpuCulling {
    /// Clip (NDC with reversed depth) to view space.
    pub inv_proj: [[f32; 4]; 4],
    pub tiles_x: u32,
    pub tiles_y: u32,
    pub light_count: u32,
    /// Most lights one tile list holds; a tile with more is marked
    /// [`TILE_OVERFLOW`] and its pixels loop over every light.
    pub max_per_tile: u32,
    pub width: u32,
    pub height: u32,
    /// 0: no lists, every pixel loops over every light.
    pub enabled: u32,
    /// Samples per pixel of the depth buffer.
    pub samples: u32,
}

/// Count of a tile list that overflowed (its pixels shade every light).
pub const TILE_OVERFLOW: u32 = u32::MAX;

/// Per-pass parameters of the one-light passes (WGSL `GpuPassParams`), one
/// 256-byte slot each, bound with a dynamic offset.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GpuPassParams {
    /// Index of the light the pass is about.
    pub light: u32,
    /// Planar shadows: index of the receiver (stencil value `receiver + 1`).
    pub receiver: u32,
    pub _pad0: u32,
    pub _pad1: u32,
}

/// Stride of [`GpuPassParams`] slots (the largest
/// `min_uniform_buffer_offset_alignment` wgpu allows).
pub const PASS_PARAMS_STRIDE: u64 = 256;

/// One instance as the shadow-volume passes see it (WGSL
/// `GpuVolumeInstance`): where its mesh lies in the merged geometry
/// buffers and where its triangles' facing values go.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GpuVolumeInstance {
    /// First index (of 3 per triangle) of the mesh in the merged index buffer.
    pub first_index: u32,
    /// Added to the mesh's indices: its first vertex in the merged positions.
    pub first_vertex: u32,
    pub first_edge: u32,
    pub edge_count: u32,
    /// First entry of this instance's triangles in the facing buffer.
    pub first_facing: u32,
    pub triangle_count: u32,
    /// 1: every edge has two opposite triangles (only back-facing triangles
    /// cast); 0: open or non-manifold (every triangle casts, two-sided).
    pub closed: u32,
    /// Index into the scene instances (model matrix).
    pub instance: u32,
}

/// Scene-scale constants of the shadow-volume extrusion (WGSL
/// `GpuVolumeGeometry`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GpuVolumeGeometry {
    /// Distance each prism starts behind its triangle, away from the light.
    pub eps: f32,
    /// Orthographic cameras: length of the finite extrusion.
    pub extrude: f32,
    pub _pad0: f32,
    pub _pad1: f32,
}

/// A planar shadow receiver (WGSL `GpuReceiver`): its world plane.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GpuReceiver {
    /// (n, d) with n·x + d = 0, n unit.
    pub plane: [f32; 4],
    /// Occluder points within this distance of the plane cast nothing on it.
    pub plane_eps: f32,
    pub _pad0: f32,
    pub _pad1: f32,
    pub _pad2: f32,
}

/// Where one instance's light-map texels lie (WGSL `GpuBakeInstance`), per
/// bake and instance: the atlas coordinate of corner `c` of the instance's
/// mesh is `uv_min + corner_uvs[first_corner + c] (uv_max − uv_min)`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GpuBakeInstance {
    pub uv_min: [f32; 2],
    pub uv_max: [f32; 2],
    /// The mesh's first corner in the bake's corner-coordinate buffer.
    pub first_corner: u32,
    /// Atlas page (array layer).
    pub page: u32,
    /// 0: the instance has no texels in this bake (nothing to look up).
    pub valid: u32,
    pub _pad0: u32,
}

/// Which bakes a frame shows (WGSL `GpuBakeParams`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GpuBakeParams {
    /// 1: an ambient-occlusion bake multiplies the ambient light.
    pub ao: u32,
    /// 1: an irradiance bake (light map or radiosity) gives diffuse light.
    pub irradiance: u32,
    /// 1: the irradiance bake holds indirect light only, so the real-time
    /// lights add the direct part.
    pub indirect_only: u32,
    pub _pad0: u32,
}

/// Constants of the screen-space AO passes (WGSL `GpuAoParams`,
/// passes/ao/common.wgsl).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GpuAoParams {
    /// World to view.
    pub view: [[f32; 4]; 4],
    /// The 4×4 jitter tile (x: rotation / slice offset, y: step offset).
    pub tile: [[f32; 4]; 16],
    /// (P[0][0], P[1][1]) of the projection.
    pub proj_scale: [f32; 2],
    /// Width and height in pixels.
    pub size: [f32; 2],
    /// R [world units].
    pub radius: f32,
    /// GTAO's falloff band as a fraction of R.
    pub falloff: f32,
    pub ortho: u32,
    pub samples: u32,
    pub slices: u32,
    pub steps: u32,
    pub mip_levels: u32,
    /// GTAO's thin-occluder compensation (`AoSettings::thin_occluders`).
    pub thin_occluders: f32,
}

/// Environment `GpuEnvMaterial::kind`s, as the WGSL constants `ENV_SPEC_*`
/// (passes/environment/environment.wgsl says what each reflects).
pub const ENV_SPEC_NONE: u32 = 0;
pub const ENV_SPEC_SPLIT_SUM: u32 = 1;
pub const ENV_SPEC_DELTA_CONSTANT: u32 = 2;
pub const ENV_SPEC_DELTA_CONDUCTOR: u32 = 3;
pub const ENV_SPEC_DELTA_DIELECTRIC: u32 = 4;

/// The environment of a frame (WGSL `GpuEnvironment`): its SH9 projection
/// and how its prefiltered map is looked up.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GpuEnvironment {
    /// L_lm (rgb, w unused), order of `penumbra_shading::light::sh9_basis`.
    pub sh: [[f32; 4]; 9],
    /// cos α, sin α of the map's rotation about +y.
    pub rotation_cos: f32,
    pub rotation_sin: f32,
    /// Levels of the prefiltered map (perceptual roughness r reads level
    /// r · (mip_count − 1)).
    pub mip_count: f32,
    /// 1: the map is drawn where no geometry is (the background pass).
    pub background: u32,
    /// Clip → world of the frame's camera (the background's view rays).
    pub inv_view_proj: [[f32; 4]; 4],
}

/// What the environment light needs of one material (WGSL
/// `GpuEnvMaterial`), made from the Rust `Bsdf` by
/// [`crate::passes::environment::env_material`].
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GpuEnvMaterial {
    /// c_diff (`Bsdf::diffuse_albedo`).
    pub diffuse: [f32; 3],
    /// `ENV_SPEC_*`.
    pub kind: u32,
    pub f0: [f32; 3],
    /// Perceptual roughness √α of the specular lobe (0 for delta lobes).
    pub roughness: f32,
    pub f90: [f32; 3],
    /// Smooth dielectric η = n_inside / n_outside.
    pub ior: f32,
    /// Smooth conductor: n per band.
    pub eta: [f32; 3],
    /// Smooth conductor: [`FRESNEL_EXACT`] or [`FRESNEL_SCHLICK`].
    pub fresnel: u32,
    /// Smooth conductor: κ per band.
    pub k: [f32; 3],
    /// 1: the diffuse light is scaled by 1 − E_d(μo) (metallic–roughness).
    pub diffuse_kc: u32,
    /// Metallic–roughness dielectric (f0, f90), for E_d.
    pub d_f0: [f32; 3],
    pub d_f90: f32,
    /// Weight of the environment seen straight through (transmission).
    pub transmit: [f32; 3],
    pub _pad0: f32,
}

/// One level of the environment prefilter (WGSL `GpuPrefilterParams`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GpuPrefilterParams {
    /// GGX α of the level.
    pub alpha: f32,
    /// GGX samples per texel.
    pub samples: u32,
    /// Size of the level written.
    pub width: u32,
    pub height: u32,
    /// Size of the source map's level 0 and its mip count.
    pub source_width: f32,
    pub source_height: f32,
    pub source_levels: f32,
    pub _pad0: f32,
}

/// Host layout of one `#[repr(C)]` GPU struct: its WGSL name, size and
/// (field name, offset) pairs, from `size_of` and `offset_of!`.
#[derive(Clone, Debug, PartialEq)]
pub struct HostLayout {
    pub wgsl_name: &'static str,
    pub size: usize,
    pub fields: Vec<(&'static str, usize)>,
}

macro_rules! host_layout {
    ($ty:ty, $name:literal, [$($field:ident),* $(,)?]) => {
        HostLayout {
            wgsl_name: $name,
            size: size_of::<$ty>(),
            fields: vec![$((stringify!($field), offset_of!($ty, $field))),*],
        }
    };
}

/// Constants the host and the shaders share, as the shaders name them.
pub fn gpu_constants() -> Vec<(&'static str, u32)> {
    use crate::textures::TexelFormat;
    vec![
        ("NO_TEXTURE", NO_TEXTURE),
        ("NO_VERTEX_DATA", NO_VERTEX_DATA),
        ("WRAP_REPEAT", WRAP_REPEAT),
        ("WRAP_CLAMP", WRAP_CLAMP),
        ("WRAP_MIRROR", WRAP_MIRROR),
        ("TEXEL_HALF", TexelFormat::Half as u32),
        ("TEXEL_SRGB8", TexelFormat::Srgb8 as u32),
        ("TEXEL_UNORM8", TexelFormat::Unorm8 as u32),
        ("ALPHA_OPAQUE", ALPHA_OPAQUE),
        ("ALPHA_MASK", ALPHA_MASK),
        ("ALPHA_BLEND", ALPHA_BLEND),
        ("SLOT_ALBEDO", SLOT_ALBEDO),
        ("SLOT_METALLIC_ROUGHNESS", SLOT_METALLIC_ROUGHNESS),
        ("SLOT_EMISSION", SLOT_EMISSION),
        ("SLOT_NORMAL", SLOT_NORMAL),
        ("SLOT_OCCLUSION", SLOT_OCCLUSION),
        ("SLOT_ALPHA", SLOT_ALPHA),
    ]
}

/// Every struct the host uploads, as the shaders name them.
pub fn gpu_structs() -> Vec<HostLayout> {
    vec![
        host_layout!(
            GpuAoParams,
            "GpuAoParams",
            [
                view,
                tile,
                proj_scale,
                size,
                radius,
                falloff,
                ortho,
                samples,
                slices,
                steps,
                mip_levels,
                thin_occluders
            ]
        ),
        host_layout!(
            GpuLight,
            "GpuLight",
            [
                position,
                m,
                kind,
                spot_direction,
                cos_inner,
                cos_outer,
                range,
                flags,
                _pad2
            ]
        ),
        host_layout!(
            GpuMaterial,
            "GpuMaterial",
            [
                model,
                variant,
                shininess,
                double_sided,
                kd,
                alpha,
                ks,
                ior,
                emission,
                roughness,
                base_color,
                metallic,
                specular_color,
                transmission,
                conductor_eta,
                specular,
                conductor_k,
                cull_back_faces
            ]
        ),
        host_layout!(
            GpuBakeInstance,
            "GpuBakeInstance",
            [uv_min, uv_max, first_corner, page, valid, _pad0]
        ),
        host_layout!(
            GpuBakeParams,
            "GpuBakeParams",
            [ao, irradiance, indirect_only, _pad0]
        ),
        host_layout!(
            GpuCamera,
            "GpuCamera",
            [view_proj, eye, back, light_count, _pad0, _pad1, _pad2]
        ),
        host_layout!(
            GpuInstance,
            "GpuInstance",
            [
                model,
                normal,
                material,
                has_normals,
                flip_winding,
                light_shape,
                first_uv,
                first_color,
                first_tangent,
                first_uv1
            ]
        ),
        host_layout!(
            GpuTexture,
            "GpuTexture",
            [
                u_row, v_row, width, height, levels, first, wrap_u, wrap_v, format, uv_set
            ]
        ),
        host_layout!(
            GpuMaterialTextures,
            "GpuMaterialTextures",
            [
                albedo,
                metallic_roughness,
                emission,
                normal,
                normal_scale,
                occlusion,
                occlusion_strength,
                alpha_mode,
                alpha_texture,
                alpha_factor,
                alpha_cutoff,
                _pad0
            ]
        ),
        host_layout!(
            GpuShadow,
            "GpuShadow",
            [
                first_layer,
                layer_count,
                pcf,
                perspective,
                texel,
                normal_offset,
                map_size,
                _pad0
            ]
        ),
        host_layout!(GpuShadowView, "GpuShadowView", [view_proj, axis]),
        host_layout!(
            GpuCulling,
            "GpuCulling",
            [
                inv_proj,
                tiles_x,
                tiles_y,
                light_count,
                max_per_tile,
                width,
                height,
                enabled,
                samples
            ]
        ),
        host_layout!(
            GpuPassParams,
            "GpuPassParams",
            [light, receiver, _pad0, _pad1]
        ),
        host_layout!(
            GpuVolumeInstance,
            "GpuVolumeInstance",
            [
                first_index,
                first_vertex,
                first_edge,
                edge_count,
                first_facing,
                triangle_count,
                closed,
                instance
            ]
        ),
        host_layout!(
            GpuVolumeGeometry,
            "GpuVolumeGeometry",
            [eps, extrude, _pad0, _pad1]
        ),
        host_layout!(
            GpuReceiver,
            "GpuReceiver",
            [plane, plane_eps, _pad0, _pad1, _pad2]
        ),
        host_layout!(
            GpuEnvironment,
            "GpuEnvironment",
            [
                sh,
                rotation_cos,
                rotation_sin,
                mip_count,
                background,
                inv_view_proj
            ]
        ),
        host_layout!(
            GpuEnvMaterial,
            "GpuEnvMaterial",
            [
                diffuse, kind, f0, roughness, f90, ior, eta, fresnel, k, diffuse_kc, d_f0, d_f90,
                transmit, _pad0
            ]
        ),
        host_layout!(
            GpuPrefilterParams,
            "GpuPrefilterParams",
            [
                alpha,
                samples,
                width,
                height,
                source_width,
                source_height,
                source_levels,
                _pad0
            ]
        ),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;
    use penumbra_shading::bsdf::{
        Conductor, Dielectric, Lambert, MIN_ALPHA, MetallicRoughness, Mirror, PhongBlinn,
        RoughConductor, RoughDielectric,
    };
    use penumbra_shading::light::{DirectionalLight, SpotLight};

    #[test]
    fn materials_keep_the_rust_coefficients() {
        let rho = Vec3::new(0.8, 0.4, 0.2);
        let m = GpuMaterial::from_bsdf(&Bsdf::Lambert(Lambert::new(rho)), Vec3::ZERO, true);
        assert!(m.model == MODEL_LAMBERT && m.double_sided == 1);
        assert_eq!(Vec3::from(m.kd), Lambert::new(rho).kd());

        let p = PhongBlinn::from_albedo(rho, Vec3::splat(0.3), 17.0, PhongVariant::HalfwaySquared);
        let m = GpuMaterial::from_bsdf(&Bsdf::PhongBlinn(p), Vec3::X, false);
        assert!(m.model == MODEL_PHONG_BLINN && m.double_sided == 0);
        assert_eq!((m.variant, m.shininess), (2, 17.0));
        assert_eq!((Vec3::from(m.kd), Vec3::from(m.ks)), (p.kd, p.ks));
        assert_eq!(Vec3::from(m.emission), Vec3::X);

        // Metallic–roughness: the clamped glTF factors, α = roughness².
        let mut mr = MetallicRoughness::new(rho, 1.5, 0.5);
        mr.transmission = 0.25;
        mr.specular = -1.0;
        mr.specular_color = Vec3::splat(2.0);
        let m = GpuMaterial::from_bsdf(&Bsdf::MetallicRoughness(mr), Vec3::ZERO, true);
        assert!(m.model == MODEL_METALLIC_ROUGHNESS);
        assert_eq!(Vec3::from(m.base_color), rho);
        assert_eq!((m.metallic, m.roughness, m.alpha), (1.0, 0.5, 0.25));
        assert_eq!((m.ior, m.transmission, m.specular), (1.5, 0.25, 0.0));
        assert_eq!(Vec3::from(m.specular_color), Vec3::splat(2.0));

        // Rough conductor and dielectric: α clamped like Ggx::new.
        let mut rc = RoughConductor::new(Vec3::new(0.2, 0.9, 1.1), Vec3::new(3.9, 2.4, 1.8), 0.0);
        rc.fresnel = FresnelModel::Schlick;
        let m = GpuMaterial::from_bsdf(&Bsdf::RoughConductor(rc), Vec3::ZERO, true);
        assert!(m.model == MODEL_ROUGH_CONDUCTOR && m.variant == FRESNEL_SCHLICK);
        assert_eq!(
            (Vec3::from(m.conductor_eta), Vec3::from(m.conductor_k)),
            (rc.eta, rc.k)
        );
        assert_eq!(m.alpha, MIN_ALPHA);
        let rd = RoughDielectric {
            tint: rho,
            ..RoughDielectric::new(1.33, 0.2)
        };
        let m = GpuMaterial::from_bsdf(&Bsdf::RoughDielectric(rd), Vec3::ZERO, true);
        assert!(m.model == MODEL_ROUGH_DIELECTRIC);
        assert_eq!((m.ior, m.alpha, Vec3::from(m.base_color)), (1.33, 0.2, rho));

        // Delta models: eval ≡ 0.
        for b in [
            Bsdf::Mirror(Mirror::new(rho)),
            Bsdf::Conductor(Conductor::new(rc.eta, rc.k, FresnelModel::Exact)),
            Bsdf::Dielectric(Dielectric::new(1.5, rho, FresnelModel::Exact)),
        ] {
            let m = GpuMaterial::from_bsdf(&b, Vec3::ZERO, true);
            assert!(m.model == MODEL_DELTA, "{b:?}");
        }
    }

    #[test]
    fn lights_use_the_homogeneous_form() {
        let d = DirectionalLight {
            direction: Vec3::new(0.0, -2.0, 0.0),
            irradiance: Vec3::splat(3.0),
        };
        let g = GpuLight::from_light(&Light::Directional(d));
        assert_eq!(g.kind, LIGHT_DIRECTIONAL);
        assert_eq!(g.position, [0.0, 1.0, 0.0, 0.0]);
        let s = SpotLight {
            position: Vec3::new(1.0, 2.0, 3.0),
            direction: Vec3::NEG_Y,
            intensity: Vec3::ONE,
            cos_inner: 0.9,
            cos_outer: 0.8,
            range: f32::INFINITY,
        };
        let g = GpuLight::from_light(&Light::Spot(s));
        assert_eq!(g.kind, LIGHT_SPOT);
        assert_eq!(g.position, [1.0, 2.0, 3.0, 1.0]);
        assert_eq!(
            (g.spot_direction, g.cos_inner, g.cos_outer),
            ([0.0, -1.0, 0.0], 0.9, 0.8)
        );
    }

    #[test]
    fn mirroring_instances_flip_the_winding() {
        let m = Mat4::from_scale(Vec3::new(-1.0, 1.0, 1.0));
        let i = GpuInstance::new(m, Mat3::from_mat4(m).inverse().transpose(), 3, true);
        assert_eq!((i.flip_winding, i.material, i.has_normals), (1, 3, 1));
        let i = GpuInstance::new(Mat4::IDENTITY, Mat3::IDENTITY, 0, false);
        assert_eq!((i.flip_winding, i.has_normals), (0, 0));
    }
}
