// AO inputs: the prepass's normal target (world normal, view distance at
// the pixel centre; sample 0 of a multisampled target) becomes view-space
// normals (zero on analytic lights) and level 0 of the view-distance MIP chain; `ao_depth_mip` builds
// each further level from the one below it. Appended to common.wgsl;
// PREPASS_TEXTURE is replaced by the host.

@group(0) @binding(1) var prepass: PREPASS_TEXTURE;
@group(0) @binding(2) var depth_out: texture_storage_2d<r32float, write>;
@group(0) @binding(3) var normals_out: texture_storage_2d<rgba16float, write>;

@compute @workgroup_size(8, 8)
fn ao_inputs(@builtin(global_invocation_id) id: vec3<u32>) {
    if any(id.xy >= vec2<u32>(ao.size)) {
        return;
    }
    // Level 0 of a texture, or sample 0 of a multisampled one.
    let t = textureLoad(prepass, vec2<i32>(id.xy), 0);
    var z = AO_BACKGROUND;
    var n = vec3<f32>(0.0);
    if t.w > 0.0 {
        z = t.w;
        n = normalize((ao.view * vec4<f32>(t.xyz, 0.0)).xyz);
    } else if t.w < 0.0 {
        // An analytic light: its depth occludes, its zero normal says kA = 0.
        z = -t.w;
    }
    textureStore(depth_out, id.xy, vec4<f32>(z, 0.0, 0.0, 0.0));
    textureStore(normals_out, id.xy, vec4<f32>(n, 0.0));
}

@group(0) @binding(4) var finer: texture_2d<f32>;
@group(0) @binding(5) var coarser: texture_storage_2d<r32float, write>;

// One level of the view-distance MIP chain: each texel is the mean of its
// 2×2 children that show a surface, averaged as 1/z under perspective (1/z
// is affine in screen space on a plane, so a plane's coarse texels hold the
// plane's distance at their centres exactly) and as z under an
// orthographic camera (z is affine there). A depth edge becomes a point
// between the two surfaces, nearer the near one.
@compute @workgroup_size(8, 8)
fn ao_depth_mip(@builtin(global_invocation_id) id: vec3<u32>) {
    let dst = textureDimensions(coarser);
    if any(id.xy >= dst) {
        return;
    }
    let last = vec2<i32>(textureDimensions(finer)) - 1;
    let base = vec2<i32>(id.xy) * 2;
    let perspective = ao.ortho == 0u;
    var sum = 0.0;
    var count = 0.0;
    for (var k = 0; k < 4; k++) {
        let d = textureLoad(finer, min(base + vec2<i32>(k & 1, k >> 1u), last), 0).x;
        if d < AO_BACKGROUND {
            sum += select(d, 1.0 / d, perspective);
            count += 1.0;
        }
    }
    var z = AO_BACKGROUND;
    if count > 0.0 {
        z = sum / count;
        if perspective {
            z = 1.0 / z;
        }
    }
    textureStore(coarser, id.xy, vec4<f32>(z, 0.0, 0.0, 0.0));
}
