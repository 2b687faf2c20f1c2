//! The scene uploaded for one frame: camera, instances, materials, lights
//! and one vertex/index buffer set per mesh; and the small wgpu helpers the
//! passes share (buffer creation, bind-group entries, per-pass parameter
//! slots).

use crate::camera::gpu_camera;
use crate::gpu::{GpuInstance, GpuLight, GpuPassParams, NO_VERTEX_DATA, PASS_PARAMS_STRIDE};
use crate::scene_data::SceneData;
use crate::textures::{TextureFeatures, TextureTable};
use glam::Vec3;
use penumbra_scene::Scene;
use penumbra_scene::camera::Camera;
use wgpu::util::DeviceExt;

/// A buffer initialised with `contents`.
pub(crate) fn buffer_init(
    device: &wgpu::Device,
    label: &str,
    contents: &[u8],
    usage: wgpu::BufferUsages,
) -> wgpu::Buffer {
    device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some(label),
        contents,
        usage,
    })
}

/// A storage-buffer binding (read-only or read-write).
pub(crate) fn storage_entry(
    binding: u32,
    visibility: wgpu::ShaderStages,
    read_only: bool,
) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Storage { read_only },
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    }
}

/// A uniform-buffer binding.
pub(crate) fn uniform_entry(
    binding: u32,
    visibility: wgpu::ShaderStages,
) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Uniform,
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    }
}

/// A bind-group entry for a whole buffer.
pub(crate) fn whole(binding: u32, buffer: &wgpu::Buffer) -> wgpu::BindGroupEntry<'_> {
    wgpu::BindGroupEntry {
        binding,
        resource: buffer.as_entire_binding(),
    }
}

/// A render pass over the depth-stencil target alone that keeps the depth
/// (read by the depth test) and starts from a cleared stencil: the stencil
/// pass of one light's planar shadows or shadow volumes.
pub(crate) fn begin_stencil_pass<'e>(
    encoder: &'e mut wgpu::CommandEncoder,
    label: &str,
    depth_stencil: &wgpu::TextureView,
    timestamp_writes: Option<wgpu::RenderPassTimestampWrites<'_>>,
) -> wgpu::RenderPass<'e> {
    encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some(label),
        color_attachments: &[],
        depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
            view: depth_stencil,
            depth_ops: Some(wgpu::Operations {
                load: wgpu::LoadOp::Load,
                store: wgpu::StoreOp::Store,
            }),
            stencil_ops: Some(wgpu::Operations {
                load: wgpu::LoadOp::Clear(0),
                store: wgpu::StoreOp::Store,
            }),
        }),
        timestamp_writes,
        occlusion_query_set: None,
        multiview_mask: None,
    })
}

/// Layout of group 1 of every pass pipeline: one [`GpuPassParams`] slot,
/// chosen per pass with a dynamic offset.
pub(crate) fn params_layout(device: &wgpu::Device) -> wgpu::BindGroupLayout {
    device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("pass params"),
        entries: &[wgpu::BindGroupLayoutEntry {
            binding: 0,
            visibility: wgpu::ShaderStages::VERTEX_FRAGMENT | wgpu::ShaderStages::COMPUTE,
            ty: wgpu::BindingType::Buffer {
                ty: wgpu::BufferBindingType::Uniform,
                has_dynamic_offset: true,
                min_binding_size: wgpu::BufferSize::new(size_of::<GpuPassParams>() as u64),
            },
            count: None,
        }],
    })
}

/// Per-pass parameter slots, [`PASS_PARAMS_STRIDE`] bytes apart, and the
/// group-1 bind group over them (offset of slot i: `i * stride`).
pub(crate) struct PassParams {
    _buffer: wgpu::Buffer,
    pub bind_group: wgpu::BindGroup,
}

impl PassParams {
    pub fn new(
        device: &wgpu::Device,
        layout: &wgpu::BindGroupLayout,
        slots: &[GpuPassParams],
    ) -> Self {
        let stride = PASS_PARAMS_STRIDE as usize;
        let mut bytes = vec![0u8; stride * slots.len().max(1)];
        for (i, s) in slots.iter().enumerate() {
            bytes[i * stride..][..size_of::<GpuPassParams>()]
                .copy_from_slice(bytemuck::bytes_of(s));
        }
        let buffer = buffer_init(device, "pass params", &bytes, wgpu::BufferUsages::UNIFORM);
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("pass params"),
            layout,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                    buffer: &buffer,
                    offset: 0,
                    size: wgpu::BufferSize::new(size_of::<GpuPassParams>() as u64),
                }),
            }],
        });
        Self {
            _buffer: buffer,
            bind_group,
        }
    }

    /// Dynamic offset of slot `i`.
    pub fn offset(i: usize) -> u32 {
        (i as u64 * PASS_PARAMS_STRIDE) as u32
    }
}

/// One mesh's vertex and index buffers.
pub(crate) struct GpuMesh {
    pub positions: wgpu::Buffer,
    pub normals: Option<wgpu::Buffer>,
    pub indices: wgpu::Buffer,
    pub index_count: u32,
}

/// The scene's frame data on the GPU.
pub(crate) struct SceneGpu {
    pub data: SceneData,
    pub bounds: (Vec3, Vec3),
    pub camera: wgpu::Buffer,
    pub instances: wgpu::Buffer,
    pub materials: wgpu::Buffer,
    pub lights: wgpu::Buffer,
    /// Per material: what the environment light needs of it (see
    /// `SceneData::env_materials`).
    pub env_materials: wgpu::Buffer,
    /// Texture coordinates (UV set 0) and colours (rgb, 1) of every mesh
    /// that has them, at `GpuInstance::first_uv` / `first_color`.
    pub vertex_uvs: wgpu::Buffer,
    pub vertex_colors: wgpu::Buffer,
    /// Tangents (xyz, w = handedness) of meshes that have them, at
    /// `GpuInstance::first_tangent`.
    pub vertex_tangents: wgpu::Buffer,
    /// The texture table, its texels and each material's textures
    /// ([`crate::textures::TextureTable`]).
    pub textures: wgpu::Buffer,
    pub texels: wgpu::Buffer,
    pub material_textures: wgpu::Buffer,
    /// What the textures use ([`TextureTable::features`]).
    pub texture_features: TextureFeatures,
    /// Per mesh (the scene's, then the area lights' emitters); `None` for
    /// meshes without triangles.
    pub meshes: Vec<Option<GpuMesh>>,
    /// Instances with triangles: (instance index, mesh index); the scene's
    /// first, then the emitters.
    pub draws: Vec<(u32, usize)>,
    /// The first `casters` draws are the scene's instances, which cast
    /// shadows; the emitters after them do not.
    pub casters: usize,
    /// Instances of BLEND materials (glTF alphaMode), not in `draws`:
    /// drawn last, blended over the frame, farthest first.
    pub blended: Vec<(u32, usize)>,
    /// Instances uploaded (at least 1).
    pub instance_count: u32,
}

impl SceneGpu {
    /// Lights of the frame (the buffer holds at least one, zeroed, entry).
    pub fn light_count(&self) -> u32 {
        self.data.lights.len() as u32
    }

    /// Uploads the frame's scene. With `unwelded`, every mesh is drawn as
    /// separate triangles (vertex 3t + k is corner k of triangle t, the
    /// index buffer 0, 1, 2, …), so `vertex_index` names the corner: the
    /// layout of per-corner data such as the bakes' atlas coordinates.
    pub fn upload(
        device: &wgpu::Device,
        scene: &Scene,
        camera: &Camera,
        width: u32,
        height: u32,
        unwelded: bool,
    ) -> Self {
        let mut data = SceneData::from_scene(scene);
        let table = TextureTable::new(scene, device.limits().max_storage_buffer_binding_size);
        data.warnings.extend(table.warnings.iter().cloned());
        let mut material_textures = table.materials.clone();
        material_textures.resize(data.materials.len().max(1), Default::default());
        let bounds = scene
            .bounds()
            .unwrap_or((Vec3::splat(-1.0), Vec3::splat(1.0)));
        let light_count = data.lights.len() as u32;
        let cam = gpu_camera(camera, width, height, bounds, light_count);
        let storage = wgpu::BufferUsages::STORAGE;
        let mut instances = data.instances.clone();
        if instances.is_empty() {
            instances.push(GpuInstance::default());
        }
        let mut lights = data.lights.clone();
        if lights.is_empty() {
            lights.push(GpuLight::default());
        }
        // Per mesh: first vertex in the UV (sets 0 and 1) and colour buffers.
        let mut uvs: Vec<[f32; 2]> = Vec::new();
        let mut colors: Vec<[f32; 4]> = Vec::new();
        let mut tangents: Vec<[f32; 4]> = Vec::new();
        let mut first_uv = Vec::new();
        let mut first_uv1 = Vec::new();
        let mut first_color = Vec::new();
        let mut first_tangent = Vec::new();
        let meshes = scene
            .meshes
            .iter()
            .chain(&data.emitters)
            .map(|m| {
                first_uv.push(NO_VERTEX_DATA);
                first_uv1.push(NO_VERTEX_DATA);
                first_color.push(NO_VERTEX_DATA);
                first_tangent.push(NO_VERTEX_DATA);
                if m.indices.is_empty() || m.positions.is_empty() {
                    return None;
                }
                let unwelded_mesh;
                let m = if unwelded {
                    unwelded_mesh = unweld(m);
                    &unwelded_mesh
                } else {
                    m
                };
                let n = m.positions.len();
                *first_uv.last_mut().unwrap() = append(&m.uv0, n, &mut uvs, |t| t.to_array());
                *first_uv1.last_mut().unwrap() = append(&m.uv1, n, &mut uvs, |t| t.to_array());
                *first_tangent.last_mut().unwrap() =
                    append(&m.tangents, n, &mut tangents, |t| t.to_array());
                *first_color.last_mut().unwrap() =
                    append(&m.colors, n, &mut colors, |c| c.extend(1.0).to_array());
                let vertex = wgpu::BufferUsages::VERTEX;
                let flat = |v: &[Vec3]| v.iter().map(|p| p.to_array()).collect::<Vec<[f32; 3]>>();
                Some(GpuMesh {
                    positions: buffer_init(
                        device,
                        "positions",
                        bytemuck::cast_slice(&flat(&m.positions)),
                        vertex,
                    ),
                    normals: m.normals.as_ref().map(|n| {
                        buffer_init(device, "normals", bytemuck::cast_slice(&flat(n)), vertex)
                    }),
                    indices: buffer_init(
                        device,
                        "indices",
                        bytemuck::cast_slice(&m.indices),
                        wgpu::BufferUsages::INDEX,
                    ),
                    index_count: (m.indices.len() * 3) as u32,
                })
            })
            .collect::<Vec<_>>();
        let (mut draws, blended): (Vec<Draw>, Vec<Draw>) = scene
            .instances
            .iter()
            .enumerate()
            .filter(|(_, inst)| meshes[inst.mesh].is_some())
            .map(|(i, inst)| (i as u32, inst.mesh))
            .partition(|&(i, _)| !blends(scene, i as usize));
        let blended = back_to_front(scene, camera, blended);
        // The scene's instances, then one per emitter (mesh first_mesh + k).
        let instance_meshes = scene
            .instances
            .iter()
            .map(|inst| inst.mesh)
            .chain(scene.meshes.len()..scene.meshes.len() + data.emitters.len());
        for (inst, mesh) in instances.iter_mut().zip(instance_meshes) {
            inst.first_uv = first_uv[mesh];
            inst.first_uv1 = first_uv1[mesh];
            inst.first_color = first_color[mesh];
            inst.first_tangent = first_tangent[mesh];
        }
        // Storage bindings cannot be empty.
        if uvs.is_empty() {
            uvs.push([0.0; 2]);
        }
        if colors.is_empty() {
            colors.push([1.0; 4]);
        }
        if tangents.is_empty() {
            tangents.push([0.0; 4]);
        }
        let casters = draws.len();
        let (first_instance, first_mesh) = (scene.instances.len(), scene.meshes.len());
        draws.extend(
            (0..data.emitters.len())
                .filter(|k| meshes[first_mesh + k].is_some())
                .map(|k| ((first_instance + k) as u32, first_mesh + k)),
        );
        Self {
            bounds,
            camera: buffer_init(
                device,
                "camera",
                bytemuck::bytes_of(&cam),
                wgpu::BufferUsages::UNIFORM,
            ),
            instances: buffer_init(
                device,
                "instances",
                bytemuck::cast_slice(&instances),
                storage,
            ),
            materials: buffer_init(
                device,
                "materials",
                bytemuck::cast_slice(&data.materials),
                storage,
            ),
            lights: buffer_init(device, "lights", bytemuck::cast_slice(&lights), storage),
            env_materials: buffer_init(
                device,
                "environment materials",
                bytemuck::cast_slice(&data.env_materials),
                storage,
            ),
            vertex_uvs: buffer_init(device, "vertex uvs", bytemuck::cast_slice(&uvs), storage),
            vertex_colors: buffer_init(
                device,
                "vertex colours",
                bytemuck::cast_slice(&colors),
                storage,
            ),
            vertex_tangents: buffer_init(
                device,
                "vertex tangents",
                bytemuck::cast_slice(&tangents),
                storage,
            ),
            textures: buffer_init(
                device,
                "textures",
                bytemuck::cast_slice(&table.textures),
                storage,
            ),
            texels: buffer_init(
                device,
                "texels",
                bytemuck::cast_slice(&table.texels),
                storage,
            ),
            material_textures: buffer_init(
                device,
                "material textures",
                bytemuck::cast_slice(&material_textures),
                storage,
            ),
            texture_features: table.features(),
            meshes,
            draws,
            blended,
            casters,
            instance_count: instances.len() as u32,
            data,
        }
    }

    /// Draws every instance with positions in slot 0 (and normals in slot 1
    /// when `with_normals`), instance index = `instance_base + instance`.
    pub fn draw_all(
        &self,
        pass: &mut wgpu::RenderPass<'_>,
        with_normals: bool,
        instance_base: u32,
    ) {
        for &(i, mesh) in &self.draws {
            self.draw_instance(pass, i, mesh, with_normals, instance_base);
        }
    }

    /// Draws the BLEND instances, farthest first (see [`Self::draw_all`]).
    pub fn draw_blended(&self, pass: &mut wgpu::RenderPass<'_>) {
        for &(i, mesh) in &self.blended {
            self.draw_instance(pass, i, mesh, true, 0);
        }
    }

    /// Draws the instances that cast shadows (see [`Self::draw_all`]).
    pub fn draw_casters(
        &self,
        pass: &mut wgpu::RenderPass<'_>,
        with_normals: bool,
        instance_base: u32,
    ) {
        for &(i, mesh) in &self.draws[..self.casters] {
            self.draw_instance(pass, i, mesh, with_normals, instance_base);
        }
    }

    /// Draws one instance (see [`Self::draw_all`]).
    pub fn draw_instance(
        &self,
        pass: &mut wgpu::RenderPass<'_>,
        instance: u32,
        mesh: usize,
        with_normals: bool,
        instance_base: u32,
    ) {
        let Some(m) = &self.meshes[mesh] else {
            return;
        };
        pass.set_vertex_buffer(0, m.positions.slice(..));
        if with_normals {
            pass.set_vertex_buffer(1, m.normals.as_ref().unwrap_or(&m.positions).slice(..));
        }
        pass.set_index_buffer(m.indices.slice(..), wgpu::IndexFormat::Uint32);
        let i = instance_base + instance;
        pass.draw_indexed(0..m.index_count, 0, i..i + 1);
    }
}

/// `mesh` as separate triangles: corner k of triangle t is vertex 3t + k.
fn unweld(mesh: &penumbra_scene::Mesh) -> penumbra_scene::Mesh {
    penumbra_scene::Mesh {
        name: mesh.name.clone(),
        positions: corners(mesh, &mesh.positions),
        normals: mesh.normals.as_deref().map(|v| corners(mesh, v)),
        uv0: mesh.uv0.as_deref().map(|v| corners(mesh, v)),
        uv1: mesh.uv1.as_deref().map(|v| corners(mesh, v)),
        tangents: mesh.tangents.as_deref().map(|v| corners(mesh, v)),
        colors: mesh.colors.as_deref().map(|v| corners(mesh, v)),
        indices: (0..mesh.indices.len() as u32)
            .map(|t| [3 * t, 3 * t + 1, 3 * t + 2])
            .collect(),
        material: mesh.material,
    }
}

/// A per-vertex attribute per triangle corner (corner k of triangle t at
/// 3t + k).
fn corners<T: Copy>(mesh: &penumbra_scene::Mesh, v: &[T]) -> Vec<T> {
    mesh.indices
        .iter()
        .flat_map(|t| t.map(|i| v[i as usize]))
        .collect()
}

/// Appends a per-vertex attribute of `n` vertices (as `f` packs it) to
/// `out`; its first index, or [`NO_VERTEX_DATA`] when the mesh has none.
fn append<T, U>(
    attribute: &Option<Vec<T>>,
    n: usize,
    out: &mut Vec<U>,
    f: impl Fn(&T) -> U,
) -> u32 {
    match attribute.as_ref().filter(|a| a.len() == n) {
        Some(a) => {
            let first = out.len() as u32;
            out.extend(a.iter().map(f));
            first
        }
        None => NO_VERTEX_DATA,
    }
}

/// One draw: (instance index, mesh index).
type Draw = (u32, usize);

/// Whether scene instance `i` has a BLEND material.
fn blends(scene: &Scene, i: usize) -> bool {
    scene.instance_material(&scene.instances[i]).is_blended()
}

/// `draws` sorted farthest first by the depth along the view direction of
/// their world bounds' centres (per-object sorting, as real-time engines
/// sort transparent objects: exact for separate convex objects, an
/// approximation where objects interpenetrate or a mesh overlaps itself).
fn back_to_front(scene: &Scene, camera: &Camera, mut draws: Vec<Draw>) -> Vec<Draw> {
    let eye = camera.position();
    let forward = -camera.camera_to_world.z_axis.truncate().normalize_or_zero();
    let depth = |&(i, mesh): &Draw| {
        let (lo, hi) = scene.meshes[mesh].bounds();
        let centre = scene.instances[i as usize]
            .transform
            .transform_point3(0.5 * (lo + hi));
        (centre - eye).dot(forward)
    };
    draws.sort_by(|a, b| depth(b).total_cmp(&depth(a)));
    draws
}

#[cfg(test)]
mod blend_order_tests {
    use super::*;
    use glam::Mat4;
    use penumbra_scene::{Projection, primitives};

    /// Three quads at depths 1, 3 and 2 in front of a camera looking down
    /// −z: drawn farthest first, whatever their order in the scene, and
    /// the other way round when the camera turns to look up +z from behind.
    #[test]
    fn blended_draws_go_farthest_first() {
        let mut scene = Scene::default();
        for z in [-1.0, -3.0, -2.0] {
            let quad = primitives::quad(Vec3::new(-1.0, -1.0, z), Vec3::X, Vec3::Y);
            scene.add_mesh(quad, Mat4::IDENTITY);
        }
        let draws: Vec<Draw> = (0..3).map(|i| (i as u32, i)).collect();
        let look = |eye: Vec3, target: Vec3| {
            Camera::look_at(eye, target, Vec3::Y, Projection::Perspective { fov_y: 0.8 })
        };
        let front = look(Vec3::ZERO, -Vec3::Z);
        let order: Vec<u32> = back_to_front(&scene, &front, draws.clone())
            .iter()
            .map(|d| d.0)
            .collect();
        assert_eq!(order, [1, 2, 0]);
        let behind = look(Vec3::new(0.0, 0.0, -10.0), Vec3::ZERO);
        let order: Vec<u32> = back_to_front(&scene, &behind, draws)
            .iter()
            .map(|d| d.0)
            .collect();
        assert_eq!(order, [0, 2, 1]);
    }
}
