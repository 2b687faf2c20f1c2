// Shadow volumes, pass 1: the casting value f of every triangle for the
// light (see shadow_volume.wgsl).

@group(0) @binding(16) var<storage, read_write> facing: array<i32>;

// 2-D dispatch: x = triangles in groups of 64, y = volume instance.
@compute @workgroup_size(64)
fn facing_main(@builtin(global_invocation_id) id: vec3<u32>) {
    let v = volumes[id.y];
    let t = id.x;
    if t >= v.triangle_count {
        return;
    }
    let tri = triangle_world(v, t);
    let light = lights[params.light].position;
    let n = cross(tri[1] - tri[0], tri[2] - tri[0]);
    let side = dot(n, light.xyz - tri[0] * light.w);
    var f = 0;
    if side < 0.0 {
        f = -1;
    } else if side > 0.0 && v.closed == 0u {
        f = 1;
    }
    facing[v.first_facing + t] = f;
}

