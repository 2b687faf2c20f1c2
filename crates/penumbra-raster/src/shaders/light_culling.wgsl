// Tiled light culling (Forward+): one workgroup of 8 x 8 invocations per
// 16 x 16-pixel screen tile (each invocation reads 2 x 2 pixels).
// The tile's depth bounds come from the depth prepass (every sample of
// every pixel that holds geometry; reversed depth, 0 = nothing); a light
// whose range sphere (view space) lies outside one of the tile's four side
// planes or beyond its depth bounds is dropped. The survivors are written
// as [count, indices in increasing order], or count = TILE_OVERFLOW if more
// than max_per_tile meet the tile (its pixels then loop over every light).
// Lights without a range always survive. Appended to scene.wgsl;
// DEPTH_TEXTURE is replaced by the host (single- or multisampled).

@group(0) @binding(0) var<uniform> culling: GpuCulling;
// View-space centre and range of each light (range < 0: unbounded).
@group(0) @binding(1) var<storage, read> spheres: array<vec4<f32>>;
@group(0) @binding(2) var depth: DEPTH_TEXTURE;
@group(0) @binding(3) var<storage, read_write> tile_lights: array<u32>;

// Bit masks of surviving lights: up to 32 * MASK_WORDS lights are culled
// (the host disables culling beyond).
const MASK_WORDS: u32 = 256u;

var<workgroup> depth_lo: atomic<u32>;
var<workgroup> depth_hi: atomic<u32>;
var<workgroup> bounds: vec2<u32>;
var<workgroup> mask: array<atomic<u32>, MASK_WORDS>;
var<workgroup> word_start: array<u32, MASK_WORDS>;
var<workgroup> total: u32;

fn unproject(ndc: vec3<f32>) -> vec3<f32> {
    let v = culling.inv_proj * vec4<f32>(ndc, 1.0);
    return v.xyz / v.w;
}

// Inward unit normal and offset of the plane through a, b, c, oriented so
// that `inside` is on its positive side.
fn plane_through(a: vec3<f32>, b: vec3<f32>, c: vec3<f32>, inside: vec3<f32>) -> vec4<f32> {
    var n = normalize(cross(b - a, c - a));
    if dot(n, inside - a) < 0.0 {
        n = -n;
    }
    return vec4<f32>(n, -dot(n, a));
}

// Invocations per workgroup.
const GROUP: u32 = 64u;

@compute @workgroup_size(8, 8)
fn cull(
    @builtin(workgroup_id) tile: vec3<u32>,
    @builtin(local_invocation_id) local: vec3<u32>,
    @builtin(local_invocation_index) li: u32,
) {
    if li == 0u {
        atomicStore(&depth_lo, 0x7f800000u);
        atomicStore(&depth_hi, 0u);
    }
    for (var w = li; w < MASK_WORDS; w += GROUP) {
        atomicStore(&mask[w], 0u);
    }
    workgroupBarrier();
    // Positive floats order like their bit patterns.
    var lo = 0x7f800000u;
    var hi = 0u;
    for (var k = 0u; k < 4u; k++) {
        let px = tile.xy * TILE + 2u * local.xy + vec2<u32>(k & 1u, k >> 1u);
        if px.x < culling.width && px.y < culling.height {
            for (var s = 0u; s < culling.samples; s++) {
                let d = LOAD_DEPTH;
                if d > 0.0 {
                    lo = min(lo, bitcast<u32>(d));
                    hi = max(hi, bitcast<u32>(d));
                }
            }
        }
    }
    atomicMin(&depth_lo, lo);
    atomicMax(&depth_hi, hi);
    workgroupBarrier();
    if li == 0u {
        bounds = vec2<u32>(atomicLoad(&depth_lo), atomicLoad(&depth_hi));
    }
    let b = workgroupUniformLoad(&bounds);
    let list = (tile.y * culling.tiles_x + tile.x) * (culling.max_per_tile + 1u);
    if b.y == 0u {
        // Background only: no pixel of the tile is shaded.
        if li == 0u {
            tile_lights[list] = 0u;
        }
        return;
    }
    // The tile's side planes from its corners at two depths (1 = the near
    // plane, 0.5), in view space.
    let size = vec2<f32>(f32(culling.width), f32(culling.height));
    let p0 = vec2<f32>(tile.xy * TILE);
    let p1 = min(vec2<f32>((tile.xy + 1u) * TILE), size);
    let x0 = 2.0 * p0.x / size.x - 1.0;
    let x1 = 2.0 * p1.x / size.x - 1.0;
    let y0 = 1.0 - 2.0 * p0.y / size.y;
    let y1 = 1.0 - 2.0 * p1.y / size.y;
    let cx = 0.5 * (x0 + x1);
    let cy = 0.5 * (y0 + y1);
    let inside = unproject(vec3<f32>(cx, cy, 1.0));
    var planes: array<vec4<f32>, 4>;
    planes[0] = plane_through(unproject(vec3<f32>(x0, y0, 1.0)), unproject(vec3<f32>(x0, y1, 1.0)), unproject(vec3<f32>(x0, y0, 0.5)), inside);
    planes[1] = plane_through(unproject(vec3<f32>(x1, y0, 1.0)), unproject(vec3<f32>(x1, y1, 1.0)), unproject(vec3<f32>(x1, y0, 0.5)), inside);
    planes[2] = plane_through(unproject(vec3<f32>(x0, y0, 1.0)), unproject(vec3<f32>(x1, y0, 1.0)), unproject(vec3<f32>(x0, y0, 0.5)), inside);
    planes[3] = plane_through(unproject(vec3<f32>(x0, y1, 1.0)), unproject(vec3<f32>(x1, y1, 1.0)), unproject(vec3<f32>(x0, y1, 0.5)), inside);
    // View z of the nearest and farthest geometry (view looks along -z).
    let z_near = unproject(vec3<f32>(cx, cy, bitcast<f32>(b.y))).z;
    let z_far = unproject(vec3<f32>(cx, cy, bitcast<f32>(b.x))).z;
    let z_pad = 1e-4 * max(abs(z_near), abs(z_far));
    for (var i = li; i < culling.light_count; i += GROUP) {
        let sphere = spheres[i];
        var keep = sphere.w < 0.0;
        if !keep {
            // A small margin: never drop a light that reaches a pixel.
            let r = sphere.w * 1.001 + 1e-6 * length(sphere.xyz);
            let c = sphere.xyz;
            keep = c.z - r <= z_near + z_pad && c.z + r >= z_far - z_pad;
            for (var k = 0u; k < 4u; k++) {
                keep = keep && dot(planes[k].xyz, c) + planes[k].w >= -r;
            }
        }
        if keep {
            atomicOr(&mask[i / 32u], 1u << (i % 32u));
        }
    }
    workgroupBarrier();
    let words = (culling.light_count + 31u) / 32u;
    if li == 0u {
        var sum = 0u;
        for (var w = 0u; w < words; w++) {
            word_start[w] = sum;
            sum += countOneBits(atomicLoad(&mask[w]));
        }
        total = sum;
    }
    let n = workgroupUniformLoad(&total);
    if n > culling.max_per_tile {
        if li == 0u {
            tile_lights[list] = TILE_OVERFLOW;
        }
        return;
    }
    if li == 0u {
        tile_lights[list] = n;
    }
    for (var w = li; w < words; w += GROUP) {
        var bits = atomicLoad(&mask[w]);
        var at = list + 1u + word_start[w];
        while bits != 0u {
            let bit = firstTrailingBit(bits);
            tile_lights[at] = w * 32u + bit;
            at += 1u;
            bits &= bits - 1u;
        }
    }
}
