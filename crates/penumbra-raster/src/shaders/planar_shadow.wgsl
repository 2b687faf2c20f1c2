// Planar projected shadows for one light (params.light) on one receiver
// (params.receiver, stencil value receiver + 1).
//
// The notes' projection onto the plane π = (n, d), n·x + d = 0, from the
// light's homogeneous position L = (y, w) (w = 1 point or spot, w = 0
// directional): M = (π·L) I − L πᵀ, so M p lies on π and on the line
// through the light and p. The receiver is first marked in the stencil
// where it is the visible surface (vs_mark: the depth prepass's own clip
// position, depth test GreaterEqual); then every other object is drawn
// through M with no depth test, and each fragment whose original point is
// strictly between the light and the plane inverts the receiver's stencil
// value once (stencil test "equal to the receiver's value", so overlapping
// occluders darken a pixel once, and the shadow never spills off the
// receiver). The lighting pass then adds the light where the stencil's top
// bit is clear: the receiver is shaded without that light, never painted.
// No polygon is drawn on top of the receiver, so nothing z-fights.
// Appended to shading.wgsl + scene.wgsl.

@group(0) @binding(0) var<uniform> camera: GpuCamera;
@group(0) @binding(1) var<storage, read> instances: array<GpuInstance>;
@group(0) @binding(3) var<storage, read> lights: array<GpuLight>;
@group(0) @binding(18) var<storage, read> receivers: array<GpuReceiver>;
@group(1) @binding(0) var<uniform> params: GpuPassParams;

// The receiver's plane turned so that the light is on its positive side.
fn oriented_plane() -> vec4<f32> {
    let plane = receivers[params.receiver].plane;
    let l = lights[params.light].position;
    if dot(plane, l) < 0.0 {
        return -plane;
    }
    return plane;
}

@vertex
fn vs_mark(
    @location(0) position: vec3<f32>,
    @builtin(instance_index) instance: u32,
) -> @invariant @builtin(position) vec4<f32> {
    let world = world_point(instances[instance].model, position);
    return camera.view_proj * vec4<f32>(world, 1.0);
}

struct ProjectedOut {
    @builtin(position) clip: vec4<f32>,
    // The occluder's own world point (the projection is projective, so
    // perspective-correct interpolation recovers it exactly per fragment).
    @location(0) world: vec3<f32>,
}

@vertex
fn vs_project(
    @location(0) position: vec3<f32>,
    @builtin(instance_index) instance: u32,
) -> ProjectedOut {
    let p = world_point(instances[instance].model, position);
    let plane = oriented_plane();
    let l = lights[params.light].position;
    // M p = (π·L) p − L (π·p), p homogeneous with w = 1.
    let pl = dot(plane, l);
    let pp = dot(plane, vec4<f32>(p, 1.0));
    let shadow = pl * vec4<f32>(p, 1.0) - l * pp;
    var out: ProjectedOut;
    out.clip = camera.view_proj * shadow;
    out.world = p;
    return out;
}

// Keeps only points strictly between the plane and the light: on the
// light's side (above a scene-scale epsilon, so objects resting on the
// receiver do not shadow it through their bottom), and for a point light
// nearer the plane than the light.
@fragment
fn fs_project(in: ProjectedOut) {
    let plane = oriented_plane();
    let l = lights[params.light].position;
    let pp = dot(plane, vec4<f32>(in.world, 1.0));
    let pl = dot(plane, l);
    if pp <= receivers[params.receiver].plane_eps || (l.w != 0.0 && pp >= pl) {
        discard;
    }
}
