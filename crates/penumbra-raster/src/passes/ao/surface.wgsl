// What the hemisphere, GTAO and denoise passes read of the AO inputs: the
// view-distance chain and the view-space normals, and the surface seen at
// a pixel. Appended to common.wgsl.

@group(0) @binding(1) var view_depth: texture_2d<f32>;
@group(0) @binding(2) var view_normals: texture_2d<f32>;

// The surface seen through one pixel (valid = false: the background).
struct AoSurface {
    valid: bool,
    // View distance.
    z: f32,
    // View-space point at the pixel centre, and its unit normal.
    p: vec3<f32>,
    n: vec3<f32>,
}

fn ao_surface_at(px: vec2<i32>) -> AoSurface {
    var s: AoSurface;
    s.z = textureLoad(view_depth, px, 0).x;
    s.valid = s.z < AO_BACKGROUND;
    if s.valid {
        s.p = ao_view_position(vec2<f32>(px) + 0.5, s.z);
        s.n = textureLoad(view_normals, px, 0).xyz;
    }
    return s;
}

// The surface whose kA a pass estimates at pixel `px`: valid = false for
// the background and for analytic area lights (a zero normal), which are
// not surfaces (the `ao` integrator gives them kA = 0); the raw passes
// skip them and the denoise writes 0.
fn ao_target_at(px: vec2<i32>) -> AoSurface {
    var s = ao_surface_at(px);
    s.valid = s.valid && any(s.n != vec3<f32>(0.0));
    return s;
}
