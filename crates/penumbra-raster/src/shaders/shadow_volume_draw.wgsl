// Shadow volumes, pass 2: caps and side quads into the stencil (see
// shadow_volume.wgsl).

@group(0) @binding(16) var<storage, read> facing: array<i32>;

// Direction away from the light at world point p.
fn away_from_light(p: vec3<f32>) -> vec3<f32> {
    let l = lights[params.light].position;
    return p * l.w - l.xyz;
}

// Start of the prism under p: EPS further from the light.
fn near_point(p: vec3<f32>) -> vec4<f32> {
    let d = away_from_light(p);
    let len2 = dot(d, d);
    var q = p;
    if len2 > 0.0 {
        q = p + d * (geometry.eps * inverseSqrt(len2));
    }
    return camera.view_proj * vec4<f32>(q, 1.0);
}

// p pushed to infinity away from the light (finite for orthographic views).
fn far_point(p: vec3<f32>) -> vec4<f32> {
    let d = away_from_light(p);
    if camera.back.w > 0.5 {
        let len2 = dot(d, d);
        var q = p;
        if len2 > 0.0 {
            q = p + d * (geometry.extrude * inverseSqrt(len2));
        }
        return camera.view_proj * vec4<f32>(q, 1.0);
    }
    return camera.view_proj * vec4<f32>(d, 0.0);
}

// A vertex that produces no primitive (all three corners equal).
const DEGENERATE: vec4<f32> = vec4<f32>(0.0, 0.0, 0.0, 1.0);

// 6 vertices per triangle: 0..2 near cap, 3..5 far cap.
@vertex
fn vs_cap(
    @builtin(vertex_index) vi: u32,
    @builtin(instance_index) volume: u32,
) -> @builtin(position) vec4<f32> {
    let v = volumes[volume];
    let t = vi / 6u;
    let k = vi % 6u;
    let f = facing[v.first_facing + t];
    if f == 0 {
        return DEGENERATE;
    }
    var tri = triangle_world(v, t);
    // Corner order facing the light: (A, B, C) for f = +1, (A, C, B) for −1;
    // the far cap runs the other way round.
    var order = array<u32, 3>(0u, 1u, 2u);
    if f < 0 {
        order = array<u32, 3>(0u, 2u, 1u);
    }
    if k < 3u {
        return near_point(tri[order[k]]);
    }
    var far_order = array<u32, 3>(order[0], order[2], order[1]);
    return far_point(tri[far_order[k - 3u]]);
}

// 6 vertices per side quad, `copies` (1 closed, 2 open) quads per edge.
// Quad for P → Q (the cap's edge seen from the light): (Q, P, P∞),
// (Q, P∞, Q∞), its outside facing out of the prism.
@vertex
fn vs_edge(
    @builtin(vertex_index) vi: u32,
    @builtin(instance_index) volume: u32,
) -> @builtin(position) vec4<f32> {
    let v = volumes[volume];
    let copies = select(2u, 1u, v.closed != 0u);
    let e = edges[v.first_edge + vi / (6u * copies)];
    let copy = (vi / 6u) % copies;
    let k = vi % 6u;
    var m = facing[v.first_facing + e.z];
    if e.w != NO_TRIANGLE {
        m -= facing[v.first_facing + e.w];
    }
    if m == 0 || (copy == 1u && abs(m) < 2) {
        return DEGENERATE;
    }
    var p = vertex_world(v, e.x);
    var q = vertex_world(v, e.y);
    if m < 0 {
        let t = p;
        p = q;
        q = t;
    }
    switch k {
        case 0u, 3u: {
            return near_point(q);
        }
        case 1u: {
            return near_point(p);
        }
        case 2u, 4u: {
            return far_point(p);
        }
        default: {
            return far_point(q);
        }
    }
}
