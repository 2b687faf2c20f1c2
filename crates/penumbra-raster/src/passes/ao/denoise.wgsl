// Depth-aware spatial denoise of the raw AO: the mean over the 4×4 pixels
// [x − 2, x + 1] × [y − 2, y + 1] (one period of the jitter tile, so its
// 16 rotations or offsets average out), neighbour i weighted by
//   w_i = saturate(1 − |n·(q_i − p)| / τ) · saturate((n·n_i − 0.8) / 0.2),
// τ = 2 pixel footprints at p: neighbours off p's tangent plane (another
// object, a depth discontinuity) or with another orientation get no
// weight, so the blur never crosses an edge; the mean is clamped to
// [0, 1] (GTAO's raw slices may exceed 1). Background pixels and analytic
// area lights (zero normal) get 0, as the `ao` integrator gives where a
// camera ray escapes or meets such a light (emissive meshes are surfaces
// and keep their kA); zero normals get no weight as neighbours. Appended to
// common.wgsl + surface.wgsl.

@group(0) @binding(3) var raw_ao: texture_2d<f32>;
@group(0) @binding(4) var ao_out: texture_storage_2d<r32float, write>;

@compute @workgroup_size(8, 8)
fn ao_denoise(@builtin(global_invocation_id) id: vec3<u32>) {
    if any(id.xy >= vec2<u32>(ao.size)) {
        return;
    }
    let px = vec2<i32>(id.xy);
    let here = ao_target_at(px);
    if !here.valid {
        textureStore(ao_out, id.xy, vec4<f32>(0.0));
        return;
    }
    let p = here.p;
    let n = here.n;
    let tau = 2.0 / ao_pixels_per_unit(here.z);
    let last = vec2<i32>(ao.size) - 1;
    var sum = 0.0;
    var weight = 0.0;
    for (var dy = -2; dy <= 1; dy++) {
        for (var dx = -2; dx <= 1; dx++) {
            let q_px = px + vec2<i32>(dx, dy);
            if any(q_px < vec2<i32>(0)) || any(q_px > last) {
                continue;
            }
            let q = ao_surface_at(q_px);
            if !q.valid {
                continue;
            }
            let w = saturate(1.0 - abs(dot(n, q.p - p)) / tau) * saturate((dot(n, q.n) - 0.8) / 0.2);
            sum += w * textureLoad(raw_ao, q_px, 0).x;
            weight += w;
        }
    }
    // The centre always has weight 1.
    textureStore(ao_out, id.xy, vec4<f32>(saturate(sum / max(weight, 1e-6)), 0.0, 0.0, 0.0));
}
