// Stencil shadow volumes (z-fail, "Carmack's reverse") for one light
// (params.light), over the merged geometry of every instance.
//
// 1. `facing` (compute): for every triangle t with world vertices A, B, C
//    and n = (B − A) × (C − A), s = sign(n · (y − A w)) for the light's
//    homogeneous position (y, w). Each triangle that casts gets a prism:
//    the triangle turned to face the light, pushed EPS away from it (so no
//    visible surface lies on a cap), its edges extruded away from the light
//    to infinity. On a closed mesh only the back-facing triangles cast
//    (f = −1 for s < 0, else 0): every light ray into the mesh leaves
//    through one. On an open or non-manifold mesh every triangle casts,
//    turned to face the light (f = s): the union of their prisms is exactly
//    the region the triangles hide from the light, whichever side faces it.
// 2. `vs_cap`: per triangle, near cap (the turned triangle) and far cap
//    (the same at infinity, reversed); degenerate where f = 0.
// 3. `vs_edge`: per edge [a, b, t1, t2] (see topology.rs), f(t1) − f(t2)
//    side quads a → b (negative: b → a), 1 or 2 copies; degenerate at 0.
//    Inside a region where the triangles cast alike the quads cancel, so
//    only silhouette (and open-boundary) edges produce geometry.
// The stencil pass counts, per pixel, the volume faces behind the visible
// surface (depth test fails): +1 for back faces, −1 for front faces (wrap
// around). A pixel is lit iff its count is 0, which holds whether the camera
// is inside a volume or not because no face is missing: the far caps are
// drawn at infinity, which the reversed infinite perspective keeps in the
// view (depth 0). Orthographic cameras have no infinity: there the prisms
// end `geometry.extrude` away, inside the camera's far plane.
// Appended to shading.wgsl + scene.wgsl, followed by
// shadow_volume_facing.wgsl (the compute pass, which writes `facing`) or
// shadow_volume_draw.wgsl (the stencil draws, which read it).

@group(0) @binding(0) var<uniform> camera: GpuCamera;
@group(0) @binding(1) var<storage, read> instances: array<GpuInstance>;
@group(0) @binding(3) var<storage, read> lights: array<GpuLight>;
@group(0) @binding(12) var<storage, read> positions: array<vec4<f32>>;
@group(0) @binding(13) var<storage, read> indices: array<u32>;
@group(0) @binding(14) var<storage, read> edges: array<vec4<u32>>;
@group(0) @binding(15) var<storage, read> volumes: array<GpuVolumeInstance>;
@group(0) @binding(17) var<uniform> geometry: GpuVolumeGeometry;
@group(1) @binding(0) var<uniform> params: GpuPassParams;

const NO_TRIANGLE: u32 = 0xffffffffu;

fn vertex_world(v: GpuVolumeInstance, index: u32) -> vec3<f32> {
    let p = positions[v.first_vertex + index].xyz;
    return world_point(instances[v.instance].model, p);
}

fn triangle_world(v: GpuVolumeInstance, t: u32) -> array<vec3<f32>, 3> {
    let i = v.first_index + 3u * t;
    return array<vec3<f32>, 3>(
        vertex_world(v, indices[i]),
        vertex_world(v, indices[i + 1u]),
        vertex_world(v, indices[i + 2u]),
    );
}

