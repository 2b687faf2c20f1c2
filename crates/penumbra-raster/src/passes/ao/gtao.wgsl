// Ground-truth ambient occlusion (GTAO, Jimenez et al. 2016; Intel's
// XeGTAO is the reference implementation): per pixel, `slices` planes
// through the view vector, turned by the pixel's entry of the 4×4 jitter
// tile; in each, a horizon search of `steps` samples per side out to the
// radius R projected on screen (offsets in equal steps, the far ones read
// from coarser levels of the view-distance MIP chain), each horizon
// sample faded out around R (a band of `falloff`·R centred on R, so on
// average it counts what a hard cut at R counts; optionally sooner for
// points towards the viewer, the thin-occluder compensation); then the cosine-weighted
// slice integral with the projected normal (slice.wgsl). For a height
// field this integrates exactly the visibility kA. Appended to
// common.wgsl + surface.wgsl + slice.wgsl.

@group(0) @binding(4) var raw_ao: texture_storage_2d<r32float, write>;

// Sample offsets below 2^MIP_OFFSET pixels read level 0, each doubling one
// level further (XeGTAO's depth MIP sampling offset is 3.3: one level
// sooner, which blurs thin occluders into false ones; measured in
// docs/raster.md).
const GTAO_MIP_OFFSET: f32 = 4.3;

// The view-space point seen at pixel coordinate px (exactly, not snapped
// to a texel, so that it lies in the slice plane): the texel of `level`
// holding px gives a point q (at the texel centre) and the level-0 normal
// at px a plane through q, which the view ray through px meets. Exact for
// planes at level 0 and for planes facing the camera at every level;
// where the ray grazes that plane or meets it far from q, q itself.
fn gtao_point(px: vec2<f32>, level: u32) -> vec3<f32> {
    let scale = f32(1u << level);
    let last = vec2<i32>(textureDimensions(view_depth, level)) - 1;
    let t = clamp(vec2<i32>(floor(px / scale)), vec2<i32>(0), last);
    let z = textureLoad(view_depth, t, level).x;
    let q = ao_view_position((vec2<f32>(t) + 0.5) * scale, z);
    if z >= AO_BACKGROUND {
        return q;
    }
    let full = vec2<i32>(ao.size) - 1;
    let nq = textureLoad(view_normals, clamp(vec2<i32>(floor(px)), vec2<i32>(0), full), 0).xyz;
    // The ray through px: base + z' dir, z' the view distance.
    let base = ao_view_position(px, 0.0);
    let dir = ao_view_position(px, 1.0) - base;
    let denom = dot(dir, nq);
    if abs(denom) < 0.1 * length(dir) {
        return q;
    }
    let zp = dot(q - base, nq) / denom;
    // The correction spans at most half a texel of a plane up to ~75°
    // from facing the camera; more means px shows another surface than
    // the texel (a depth edge), and then q stands.
    if zp <= 0.0 || abs(zp - z) > 4.0 * scale / ao_pixels_per_unit(z) {
        return q;
    }
    return base + zp * dir;
}

// Cosine of the elevation of sample point q above the slice's horizon
// start, faded towards `low` (no occlusion) around R. With thin-occluder
// compensation c the fade sees q − p with its component t > 0 towards the
// viewer stretched by 1 + c: √(|q − p|² + ((1 + c)² − 1) t²).
fn gtao_horizon_cos(p: vec3<f32>, v: vec3<f32>, q: vec3<f32>, low: f32) -> f32 {
    let h = q - p;
    let d = length(h);
    if d <= 1e-20 * ao.radius || q.z <= -AO_BACKGROUND {
        return low;
    }
    let c = ao.thin_occluders;
    let t = max(dot(h, v), 0.0);
    let d_fade = sqrt(d * d + c * (2.0 + c) * t * t);
    let band = max(ao.falloff, 1e-6) * ao.radius;
    let w = saturate((ao.radius + 0.5 * band - d_fade) / band);
    return mix(low, dot(h, v) / d, w);
}

@compute @workgroup_size(8, 8)
fn gtao(@builtin(global_invocation_id) id: vec3<u32>) {
    if any(id.xy >= vec2<u32>(ao.size)) {
        return;
    }
    let here = ao_target_at(vec2<i32>(id.xy));
    if !here.valid {
        textureStore(raw_ao, id.xy, vec4<f32>(1.0));
        return;
    }
    let centre = vec2<f32>(id.xy) + 0.5;
    let z = here.z;
    let p = here.p;
    let v = ao_view_vector(p);
    let nrm = here.n;
    // R on screen; below about a pixel nothing can be resolved.
    let r_px = ao.radius * ao_pixels_per_unit(z);
    if r_px < 1.5 {
        textureStore(raw_ao, id.xy, vec4<f32>(1.0));
        return;
    }
    let jitter = ao_tile(id.xy);
    let half_pi = 0.5 * AO_PI;
    let slices = max(ao.slices, 1u);
    let steps = max(ao.steps, 1u);
    var visibility = 0.0;
    // Slice directions uniform about v (the estimator's assumption; equal
    // steps of the screen angle are not, away from the image centre under
    // perspective): t = cos φ b1 + sin φ b2 with b1, b2 ⟂ v.
    let b1 = normalize(vec3<f32>(1.0, 0.0, 0.0) - v.x * v);
    let b2 = cross(v, b1);
    for (var i = 0u; i < slices; i++) {
        let phi = AO_PI * (f32(i) + jitter.x) / f32(slices);
        let ortho_dir = cos(phi) * b1 + sin(phi) * b2;
        // The slice plane span(v, t) holds the eye, so it projects to the
        // screen line through the pixel along the image of t.
        let dir_px = normalize(ao_project(p + ortho_dir * (1e-3 * max(z, ao.radius))) - centre);
        let axis = normalize(cross(ortho_dir, v));
        let pn = nrm - axis * dot(nrm, axis);
        let pn_len = length(pn);
        if pn_len < 1e-6 {
            continue;
        }
        let cos_n = clamp(dot(pn, v) / pn_len, -1.0, 1.0);
        let n = sign(dot(ortho_dir, pn)) * acos(cos_n);
        // Horizons start at the tangent plane: cos(n ± π/2).
        let low1 = cos(n + half_pi);
        let low0 = cos(n - half_pi);
        var c1 = low1;
        var c0 = low0;
        for (var j = 0u; j < steps; j++) {
            let s = (f32(j) + jitter.y) / f32(steps);
            // Equal steps out to R: XeGTAO's s² crowds the steps near p and
            // finds the far rim of a crease late (under-occluded creases).
            let offset = max(s * r_px, 1.0 + f32(j));
            if offset > r_px {
                break;
            }
            let level = u32(clamp(floor(log2(offset) - GTAO_MIP_OFFSET), 0.0, f32(ao.mip_levels - 1u)));
            let a = centre + dir_px * offset;
            let b = centre - dir_px * offset;
            if ao_on_screen(a) {
                c1 = max(c1, gtao_horizon_cos(p, v, gtao_point(a, level), low1));
            }
            if ao_on_screen(b) {
                c0 = max(c0, gtao_horizon_cos(p, v, gtao_point(b, level), low0));
            }
        }
        let h1 = n + min(acos(clamp(c1, -1.0, 1.0)) - n, half_pi);
        let h0 = n + max(-acos(clamp(c0, -1.0, 1.0)) - n, -half_pi);
        visibility += pn_len * gtao_slice_visibility(n, h0, h1);
    }
    // Not clamped: a slice of a tilted normal may give more than 1 (only
    // the average over slice directions is kA), so clamping here would
    // bias the mean low; the denoise averages 16 slice offsets and clamps.
    textureStore(raw_ao, id.xy, vec4<f32>(max(visibility / f32(slices), 0.0), 0.0, 0.0, 0.0));
}
