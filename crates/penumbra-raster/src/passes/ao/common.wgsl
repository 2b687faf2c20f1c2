// Screen-space ambient occlusion: what every AO pass shares. kA(p) =
// (1/π) ∫Ω v(p, l) (n·l) dl with v = 0 where an occluder lies within the
// radius R of p (the `ao` integrator's definition at --ao-distance R),
// estimated from the view distance and normal of each pixel. Positions and
// normals are in view space (right-handed, the camera looks along −z);
// "view distance" z is −z_view, the distance from the camera plane.

struct GpuAoParams {
    // World to view.
    view: mat4x4<f32>,
    // The 4×4 jitter tile, indexed by (y & 3) * 4 + (x & 3): x = rotation
    // of the hemisphere kernel / offset of the GTAO slices, y = offset of
    // the GTAO steps, both in [0, 1).
    tile: array<vec4<f32>, 16>,
    // (P[0][0], P[1][1]) of the projection.
    proj_scale: vec2<f32>,
    // Width and height in pixels.
    size: vec2<f32>,
    // R in world units.
    radius: f32,
    // GTAO: width of the falloff band, as a fraction of R, centred on R.
    falloff: f32,
    ortho: u32,
    // Hemisphere kernel size.
    samples: u32,
    // GTAO slices and steps per side of each slice.
    slices: u32,
    steps: u32,
    // Levels of the view-distance MIP chain.
    mip_levels: u32,
    // GTAO's thin-occluder compensation c (AoSettings::thin_occluders).
    thin_occluders: f32,
}

// View distance of pixels that show no surface.
const AO_BACKGROUND: f32 = 1e30;
const AO_PI: f32 = 3.14159265358979;

@group(0) @binding(0) var<uniform> ao: GpuAoParams;

// View-space point seen through pixel coordinate `px` (pixel centres at
// +0.5) at view distance z: x = ndc_x z / P00 (perspective) or ndc_x / P00
// (orthographic), likewise y, z_view = −z.
fn ao_view_position(px: vec2<f32>, z: f32) -> vec3<f32> {
    let ndc = vec2<f32>(2.0 * px.x / ao.size.x - 1.0, 1.0 - 2.0 * px.y / ao.size.y);
    let xy = ndc / ao.proj_scale;
    if ao.ortho != 0u {
        return vec3<f32>(xy, -z);
    }
    return vec3<f32>(xy * z, -z);
}

// Pixel coordinate of a view-space point (inverse of ao_view_position).
fn ao_project(v: vec3<f32>) -> vec2<f32> {
    var ndc = v.xy * ao.proj_scale;
    if ao.ortho == 0u {
        ndc = ndc / max(-v.z, 1e-20);
    }
    return vec2<f32>((ndc.x + 1.0) * 0.5 * ao.size.x, (1.0 - ndc.y) * 0.5 * ao.size.y);
}

// Unit vector from p towards the viewer.
fn ao_view_vector(p: vec3<f32>) -> vec3<f32> {
    if ao.ortho != 0u {
        return vec3<f32>(0.0, 0.0, 1.0);
    }
    return normalize(-p);
}

// Pixels per world unit at view distance z.
fn ao_pixels_per_unit(z: f32) -> f32 {
    let f = 0.5 * ao.proj_scale.y * ao.size.y;
    if ao.ortho != 0u {
        return f;
    }
    return f / z;
}

fn ao_tile(px: vec2<u32>) -> vec4<f32> {
    return ao.tile[(px.y & 3u) * 4u + (px.x & 3u)];
}

fn ao_on_screen(px: vec2<f32>) -> bool {
    return all(px >= vec2<f32>(0.0)) && all(px < ao.size);
}
