//! `#[repr(C)]` structs shared with the WGSL shaders, their conversion from
//! the scene model, and a description of their layouts ([`GPU_STRUCTS`]) that
//! the tests compare with the WGSL structs as naga lays them out.

use bytemuck::{Pod, Zeroable};
use glam::{Mat3, Mat4, Vec3};
use penumbra_shading::bsdf::{Bsdf, PhongVariant};
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

/// A material as the raster path shades it (WGSL `GpuMaterial`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GpuMaterial {
    pub model: u32,
    pub variant: u32,
    pub shininess: f32,
    pub double_sided: u32,
    /// Diffuse coefficient kd = ρ/π [1/sr].
    pub kd: [f32; 3],
    pub _pad0: f32,
    pub ks: [f32; 3],
    pub _pad1: f32,
    pub emission: [f32; 3],
    pub _pad2: f32,
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
    /// The BRDF the raster path evaluates for `bsdf`, and whether it is exact.
    /// Lambert and Phong–Blinn have WGSL twins; every other model is shaded
    /// as Lambert with the model's directional albedo `albedo()` (an
    /// approximation: no specular highlight, no delta lobes).
    pub fn from_bsdf(bsdf: &Bsdf, emission: Vec3, double_sided: bool) -> (Self, bool) {
        let mut m = Self {
            emission: emission.to_array(),
            double_sided: double_sided as u32,
            ..Self::default()
        };
        let exact = match bsdf {
            Bsdf::Lambert(l) => {
                m.model = MODEL_LAMBERT;
                m.kd = l.kd().to_array();
                true
            }
            Bsdf::PhongBlinn(p) => {
                m.model = MODEL_PHONG_BLINN;
                m.variant = phong_variant_index(p.variant);
                m.kd = p.kd.to_array();
                m.ks = p.ks.to_array();
                m.shininess = p.shininess;
                true
            }
            other => {
                m.model = MODEL_LAMBERT;
                m.kd = (other.albedo() * std::f32::consts::FRAC_1_PI).to_array();
                false
            }
        };
        (m, exact)
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
    pub _pad0: u32,
}

impl GpuInstance {
    pub fn new(transform: Mat4, normal_matrix: Mat3, material: u32, has_normals: bool) -> Self {
        Self {
            model: transform.to_cols_array_2d(),
            normal: Mat4::from_mat3(normal_matrix).to_cols_array_2d(),
            material,
            has_normals: has_normals as u32,
            flip_winding: (Mat3::from_mat4(transform).determinant() < 0.0) as u32,
            _pad0: 0,
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

/// Every struct the host uploads, as the shaders name them.
pub fn gpu_structs() -> Vec<HostLayout> {
    vec![
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
                _pad0,
                ks,
                _pad1,
                emission,
                _pad2
            ]
        ),
        host_layout!(
            GpuCamera,
            "GpuCamera",
            [view_proj, eye, back, light_count, _pad0, _pad1, _pad2]
        ),
        host_layout!(
            GpuInstance,
            "GpuInstance",
            [model, normal, material, has_normals, flip_winding, _pad0]
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
    ]
}

#[cfg(test)]
mod tests {
    use super::*;
    use penumbra_shading::bsdf::{Lambert, MetallicRoughness, PhongBlinn};
    use penumbra_shading::light::{DirectionalLight, SpotLight};

    #[test]
    fn materials_keep_the_rust_coefficients() {
        let rho = Vec3::new(0.8, 0.4, 0.2);
        let (m, exact) =
            GpuMaterial::from_bsdf(&Bsdf::Lambert(Lambert::new(rho)), Vec3::ZERO, true);
        assert!(exact && m.model == MODEL_LAMBERT && m.double_sided == 1);
        assert_eq!(Vec3::from(m.kd), Lambert::new(rho).kd());

        let p = PhongBlinn::from_albedo(rho, Vec3::splat(0.3), 17.0, PhongVariant::HalfwaySquared);
        let (m, exact) = GpuMaterial::from_bsdf(&Bsdf::PhongBlinn(p), Vec3::X, false);
        assert!(exact && m.model == MODEL_PHONG_BLINN && m.double_sided == 0);
        assert_eq!((m.variant, m.shininess), (2, 17.0));
        assert_eq!((Vec3::from(m.kd), Vec3::from(m.ks)), (p.kd, p.ks));
        assert_eq!(Vec3::from(m.emission), Vec3::X);

        // No twin yet: Lambert with the model's albedo, reported as inexact.
        let mr = Bsdf::MetallicRoughness(MetallicRoughness::new(rho, 0.0, 0.5));
        let (m, exact) = GpuMaterial::from_bsdf(&mr, Vec3::ZERO, true);
        assert!(!exact && m.model == MODEL_LAMBERT);
        let expect = mr.albedo() * std::f32::consts::FRAC_1_PI;
        assert!((Vec3::from(m.kd) - expect).abs().max_element() < 1e-7);
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
