// Structs every raster pass shares with the host (mirrors of the
// `#[repr(C)]` structs in gpu.rs; a test compares their layouts with naga),
// and the one clip-space transform all geometry passes use. Appended to
// shading.wgsl; the passes declare their own bindings.

struct GpuCamera {
    view_proj: mat4x4<f32>,
    // World position of the pinhole (perspective).
    eye: vec4<f32>,
    // World +z axis of the camera (towards the viewer); w = 1 orthographic.
    back: vec4<f32>,
    light_count: u32,
    _pad0: u32,
    _pad1: u32,
    _pad2: u32,
}

struct GpuInstance {
    model: mat4x4<f32>,
    // Inverse transpose of the linear part (columns 0..2).
    normal: mat4x4<f32>,
    material: u32,
    has_normals: u32,
    flip_winding: u32,
    // 1: the emitter of an analytic area light (a light, not a surface).
    light_shape: u32,
    // First vertex of the mesh in vertex_uvs / vertex_colors /
    // vertex_tangents (textures.wgsl); 0xffffffff: the mesh has none.
    first_uv: u32,
    first_color: u32,
    first_tangent: u32,
    // First vertex of the mesh's UV set 1 in vertex_uvs.
    first_uv1: u32,
}

// How each light is shadowed by a shadow map, indexed like the lights;
// layer_count = 0: not shadowed.
struct GpuShadow {
    first_layer: u32,
    // 1: one view (directional, spot); 6: cube faces +x, -x, +y, -y, +z, -z.
    layer_count: u32,
    // PCF kernel edge N: N x N taps one texel apart.
    pcf: u32,
    perspective: u32,
    // World size of a texel (orthographic) or per unit distance (perspective).
    texel: f32,
    // Normal offset of the lookup point, in texels.
    normal_offset: f32,
    map_size: f32,
    _pad0: f32,
}

// One depth-only view of a light: world to clip with reversed depth.
struct GpuShadowView {
    view_proj: mat4x4<f32>,
    axis: vec4<f32>,
}

// Tiled light culling: TILE x TILE pixel tiles, each a list of
// max_per_tile + 1 words (count, then light indices in increasing order).
struct GpuCulling {
    inv_proj: mat4x4<f32>,
    tiles_x: u32,
    tiles_y: u32,
    light_count: u32,
    max_per_tile: u32,
    width: u32,
    height: u32,
    enabled: u32,
    samples: u32,
}

const TILE: u32 = 16u;
const TILE_OVERFLOW: u32 = 0xffffffffu;

// Parameters of a one-light pass (dynamic uniform offset).
struct GpuPassParams {
    light: u32,
    receiver: u32,
    _pad0: u32,
    _pad1: u32,
}

// An instance in the merged geometry of the shadow-volume passes.
struct GpuVolumeInstance {
    first_index: u32,
    first_vertex: u32,
    first_edge: u32,
    edge_count: u32,
    first_facing: u32,
    triangle_count: u32,
    closed: u32,
    instance: u32,
}

// Scene-scale constants of the shadow-volume extrusion.
struct GpuVolumeGeometry {
    // Distance the prisms start behind their triangle.
    eps: f32,
    // Orthographic cameras: length of the finite extrusion.
    extrude: f32,
    _pad0: f32,
    _pad1: f32,
}

// A planar shadow receiver: n·x + d = 0; occluder points within plane_eps
// of the plane do not cast onto it.
struct GpuReceiver {
    plane: vec4<f32>,
    plane_eps: f32,
    _pad0: f32,
    _pad1: f32,
    _pad2: f32,
}

// Where one instance's light-map texels lie in one bake: the atlas
// coordinate of mesh corner c is uv_min + corner_uvs[first_corner + c] *
// (uv_max - uv_min), on array layer `page`; valid = 0: no texels.
struct GpuBakeInstance {
    uv_min: vec2<f32>,
    uv_max: vec2<f32>,
    first_corner: u32,
    page: u32,
    valid: u32,
    _pad0: u32,
}

// Which bakes the frame shows (1 = present).
struct GpuBakeParams {
    ao: u32,
    irradiance: u32,
    indirect_only: u32,
    _pad0: u32,
}

// World position of an object-space point. Every pass that must agree on
// depth with another (prepass, shading, stencil marking) computes clip
// positions as view_proj * vec4(world_point(..), 1) with @invariant.
fn world_point(model: mat4x4<f32>, p: vec3<f32>) -> vec3<f32> {
    return (model * vec4<f32>(p, 1.0)).xyz;
}
